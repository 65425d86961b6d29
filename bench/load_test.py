#!/usr/bin/env python3
"""Load test of the endpoints the dashboard polls, while workers run.

Starts `uniphys serve` (embedded: SQLite and local objects in a fresh temp dir, or the database
named by UNIPHYS_DATABASE_URL) with stand-in stages, so its worker keeps claiming and completing
runs through the test; seeds N assets through the real upload route (every one its own content,
half of them in one batch); then
runs `wrk` against each endpoint in turn and prints p50/p99 latency and requests per second.

`/v1/stats` computes the statistics on every request: it is the baseline that `/v1/overview`
(the dashboard's poll, shared statistics recomputed at most once a second) is compared with.

Only loopback is used; every loop is bounded in count and time. Python standard library only.
"""

from __future__ import annotations

import argparse
import http.client
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

# The queue's stages in pipeline order (`ServiceStage::ALL`): a worker needs slots for every one, or
# jobs wait at the first stage without one (the dashboard then says "no worker").
STAGES = ["ingest", "decompose", "infer", "ground", "verify", "convert"]


def stage_slots(n: int, **more: int) -> str:
    """`UNIPHYS_STAGES` with n slots of every stage, or as many as `more` names."""
    return ",".join(f"{stage}={more.get(stage, n)}" for stage in STAGES)


ENDPOINTS = [
    ("/v1/stats", "statistics computed per request (baseline)"),
    # The dashboard asks for the samples after its last one; `{recent}` is 10 s before wrk starts.
    ("/v1/overview?since_ms={recent}", "the dashboard's poll"),
    ("/v1/work?state=dead&limit=50", "dead letters, first page"),
    ("/v1/work?state=running&limit=50", "running work, first page"),
    ("/v1/assets?limit=50", "assets, first page"),
    ("/v1/batches/load/stats", "batch statistics"),
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(binary: str, data_dir: Path, port: int) -> subprocess.Popen:
    env = dict(os.environ)
    env.update(
        UNIPHYS_DATA_DIR=str(data_dir),
        UNIPHYS_LOG="warn",
        UNIPHYS_STAND_INS=",".join(STAGES),
        UNIPHYS_STAND_IN_WORK_MS=env.get("UNIPHYS_STAND_IN_WORK_MS", "20"),
        UNIPHYS_MAX_BACKLOG_PER_TENANT="100000000",
        UNIPHYS_STAGES=env.get("UNIPHYS_STAGES", stage_slots(1, ingest=2)),
    )
    server = subprocess.Popen(
        [binary, "serve", "--listen", f"127.0.0.1:{port}"],
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    listening = threading.Event()

    def read_stderr() -> None:
        assert server.stderr is not None
        for line in server.stderr:
            if line.startswith("API on http://"):
                listening.set()

    threading.Thread(target=read_stderr, daemon=True).start()
    if not listening.wait(timeout=60):
        server.kill()
        raise SystemExit(f"uniphys serve did not start within 60 s (exit {server.wait()})")
    return server


def seed(port: int, key: str, assets: int, threads: int = 4, first: int = 0,
         batch_of=lambda i: "load" if i % 2 == 0 else None) -> float:
    """Uploads `assets` distinct small files (numbered from `first`, upload i into the batch
    `batch_of(i)` names, if any); returns the uploads per second."""
    counter = iter(range(first, first + assets))
    lock = threading.Lock()
    failures: list[str] = []

    def upload_loop() -> None:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        while True:
            with lock:
                i = next(counter, None)
            if i is None or failures:
                break
            body = f"asset {i}\n".encode()
            label = batch_of(i)
            batch = f"&batch={label}" if label else ""
            conn.request(
                "POST",
                f"/v1/assets?filename=a{i}.obj{batch}",
                body=body,
                headers={"Authorization": f"Bearer {key}", "Content-Type": "application/octet-stream"},
            )
            response = conn.getresponse()
            answer = response.read()
            if response.status not in (200, 201):
                failures.append(f"upload {i}: {response.status} {answer[:200]!r}")
        conn.close()

    started = time.monotonic()
    workers = [threading.Thread(target=upload_loop) for _ in range(threads)]
    for w in workers:
        w.start()
    last_report = started
    while any(w.is_alive() for w in workers):
        time.sleep(0.5)
        if time.monotonic() - last_report > 10:
            last_report = time.monotonic()
            print(f"  seeding... {time.monotonic() - started:.0f} s", file=sys.stderr, flush=True)
    if failures:
        raise SystemExit(failures[0])
    return assets / (time.monotonic() - started)


def wrk(port: int, key: str, path: str, seconds: int, connections: int) -> dict[str, float]:
    out = subprocess.run(
        [
            "wrk", "-t2", f"-c{connections}", f"-d{seconds}s", "--latency", "--timeout", "10s",
            "-H", f"Authorization: Bearer {key}", f"http://127.0.0.1:{port}{path}",
        ],
        capture_output=True, text=True, timeout=seconds + 60, check=True,
    ).stdout
    def latency_ms(pct: str) -> float:
        match = re.search(rf"^\s*{pct}%\s+([\d.]+)(us|ms|s)\s*$", out, re.M)
        if not match:
            raise SystemExit(f"no {pct}% latency in wrk's output:\n{out}")
        value, unit = float(match[1]), match[2]
        return value / 1000 if unit == "us" else value * 1000 if unit == "s" else value
    rps = re.search(r"Requests/sec:\s+([\d.]+)", out)
    non2xx = re.search(r"Non-2xx or 3xx responses:\s+(\d+)", out)
    total = re.search(r"(\d+) requests in", out)
    return {
        "p50": latency_ms("50"), "p99": latency_ms("99"),
        "rps": float(rps[1]) if rps else 0.0,
        "errors": int(non2xx[1]) if non2xx else 0,
        "requests": int(total[1]) if total else 0,
    }


def get_json(port: int, key: str, path: str) -> str:
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    conn.request("GET", path, headers={"Authorization": f"Bearer {key}"})
    body = conn.getresponse().read().decode()
    conn.close()
    return body


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bin", default="target/release/uniphys", help="the uniphys binary")
    parser.add_argument("--assets", type=int, default=100_000, help="assets to seed")
    parser.add_argument("--duration", type=int, default=15, help="seconds of wrk per endpoint")
    parser.add_argument("--connections", type=int, default=32)
    args = parser.parse_args()
    if shutil.which("wrk") is None:
        raise SystemExit("wrk is not installed: apt-get install wrk")
    if not os.access(args.bin, os.X_OK):
        raise SystemExit(f"{args.bin} is not an executable; build it (cargo build --release --bin uniphys)")

    data_dir = Path(tempfile.mkdtemp(prefix="uniphys-load-"))
    port = free_port()
    server = start_server(args.bin, data_dir, port)
    try:
        key = (data_dir / "api-key").read_text().strip()
        print(f"seeding {args.assets} assets through POST /v1/assets ...", file=sys.stderr, flush=True)
        per_sec = seed(port, key, args.assets)
        print(f"seeded {args.assets} assets at {per_sec:.0f}/s; workers keep running", flush=True)
        rows = []
        for template, what in ENDPOINTS:
            path = template.format(recent=int(time.time() * 1000) - 10_000)
            result = wrk(port, key, path, args.duration, args.connections)
            rows.append((path, what, result))
            if result["errors"]:
                raise SystemExit(f"{path}: {result['errors']} answers were not 2xx")
        overview = get_json(port, key, "/v1/overview")
        done = re.search(r'"succeeded":(\d+)', overview)
        print(f"\nwrk -t2 -c{args.connections} -d{args.duration}s per endpoint, {args.assets} assets, "
              f"worker running stand-in stages throughout ({done[1] if done else '?'} jobs done by the end)")
        base_rps = rows[0][2]["rps"]
        print(f"| endpoint | what | p50 ms | p99 ms | requests/s | × /v1/stats |")
        print(f"|---|---|---:|---:|---:|---:|")
        for path, what, r in rows:
            ratio = r["rps"] / base_rps if base_rps else float("nan")
            print(f"| `{re.sub(r'since_ms=[0-9]+', 'since_ms=…', path)}` | {what} | {r['p50']:.2f} | {r['p99']:.2f} | {r['rps']:.0f} | {ratio:.1f}x |")
        return 0
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
        shutil.rmtree(data_dir, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
