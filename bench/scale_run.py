#!/usr/bin/env python3
"""Scale run: real objects through the service, and the queue at 40,000 jobs (issue 22, item 4).

Real objects: every object folder under --data is run with `uniphys run` (the baseline, one and
two at a time), then submitted as an archive (`uniphys submit --batch` packs each folder) to
  - `embedded`: `uniphys serve` (SQLite, local objects, workers in the API's process; W workers
    are W slots of each stage), and
  - `distributed`: `uniphys api` and W `uniphys worker` processes on PostgreSQL, Redis and an
    S3-compatible store (moto's server from the venv),
with W = 1 and 2; each run goes until every job has finished, then `uniphys dataset export`
writes the batch and every entity folder is checked (its files, and model.xml and model.urdf
loaded in MuJoCo). The table gives assets per hour, the service's wall time over the baseline's
with the same parallelism (the queue's overhead), and a projection to 40,000 assets.

No-op jobs: stand-in stages (no work) on PostgreSQL + Redis + a local object directory. A batch
of --noop-small jobs, then one of --noop-jobs, each submitted (uploads), drained by two worker
processes and exported; the dashboard's endpoints are timed after each. The large batch's rates
and latencies against the small one's show whether the service keeps its speed at that size.

Needs: the release binary (--bin), the venv's `mujoco` and `moto_server` (scripts/test installs
both into .venv), and for `distributed` and the no-op run PostgreSQL and Redis named by
UNIPHYS_TEST_DATABASE_URL and UNIPHYS_TEST_REDIS_URL (`. scripts/services` starts them). What is
missing is named and the run stops; nothing is skipped silently.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import http.client
import json
import os
import re
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.parse
from dataclasses import dataclass, field
from pathlib import Path

# bench/ is the script's folder, first on sys.path.
from load_test import STAGES, free_port, seed, stage_slots


ENTITY_FILES = [
    "model.urdf", "model.xml", "record.json", "report.json", "meta_data.json",
    "annotations/object.json",
]
ENTITY_FOLDERS = ["parts", "meshes", "npzs"]
FINISHED = {"succeeded", "dead", "cancelled"}
DASHBOARD = [
    "/v1/overview",
    "/v1/assets?limit=50",
    "/v1/work?state=dead&limit=50",
    "/v1/batches/{batch}/stats",
]


def log(message: str) -> None:
    print(f"[{time.strftime('%H:%M:%S')}] {message}", file=sys.stderr, flush=True)


def wait_port(port: int, what: str, process: subprocess.Popen | None = None, timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process is not None and process.poll() is not None:
            raise SystemExit(f"{what} exited with {process.returncode} before it listened")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.1)
    raise SystemExit(f"{what} did not listen on {port} within {timeout:.0f} s")


class Api:
    """A keep-alive JSON client of the service's API."""

    def __init__(self, port: int, key: str):
        self.port, self.key = port, key
        self.conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)

    def request(self, method: str, path: str, body: bytes | None = None) -> tuple[int, bytes]:
        headers = {"Authorization": f"Bearer {self.key}"}
        if body is not None:
            headers["Content-Type"] = "application/octet-stream"
        for attempt in range(2):
            try:
                self.conn.request(method, path, body=body, headers=headers)
                response = self.conn.getresponse()
                return response.status, response.read()
            except (http.client.HTTPException, ConnectionError):
                self.conn.close()
                self.conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=120)
                if attempt == 1:
                    raise
        raise AssertionError("unreachable")

    def get(self, path: str) -> dict:
        status, body = self.request("GET", path)
        if status != 200:
            raise SystemExit(f"GET {path}: {status} {body[:300]!r}")
        return json.loads(body)

    def batch_states(self, batch: str) -> dict[str, int]:
        counts: dict[str, int] = {}
        before = None
        while True:
            path = f"/v1/assets?batch={urllib.parse.quote(batch)}&limit=1000"
            if before:
                path += f"&before={urllib.parse.quote(before)}"
            page = self.get(path)
            for item in page["items"]:
                counts[item["state"]] = counts.get(item["state"], 0) + 1
            before = page.get("next")
            if not before:
                return counts


@dataclass
class Deployment:
    """The processes of one service deployment and how to reach it."""

    name: str
    port: int
    key: str
    env: dict[str, str]
    processes: list[subprocess.Popen] = field(default_factory=list)

    def stop(self) -> None:
        for p in self.processes:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in self.processes:
            try:
                p.wait(timeout=60)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def start_embedded(binary: str, scratch: Path, workers: int, extra: dict[str, str]) -> Deployment:
    data = scratch / "data"
    port = free_port()
    env = dict(os.environ, UNIPHYS_DATA_DIR=str(data), UNIPHYS_LOG="warn",
               UNIPHYS_STAGES=stage_slots(workers), **extra)
    for name in ("UNIPHYS_DATABASE_URL", "UNIPHYS_STORAGE_URL", "UNIPHYS_REDIS_URL"):
        env.pop(name, None)
    server = subprocess.Popen([binary, "serve", "--listen", f"127.0.0.1:{port}"], env=env,
                              stdout=subprocess.DEVNULL, stderr=open(scratch / "serve.log", "w"))
    wait_port(port, "uniphys serve", server)
    key_file = data / "api-key"
    deadline = time.monotonic() + 30
    while not key_file.exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    key = key_file.read_text().strip()
    client = dict(env, UNIPHYS_API_URL=f"http://127.0.0.1:{port}", UNIPHYS_API_KEY=key)
    return Deployment("embedded (SQLite, local objects)", port, key, client, [server])


@dataclass
class Servers:
    """PostgreSQL, Redis and (for S3) moto, shared by the distributed runs."""

    database_url: str
    redis_url: str
    s3_endpoint: str | None = None
    moto: subprocess.Popen | None = None

    def stop(self) -> None:
        if self.moto is not None:
            self.moto.terminate()
            self.moto.wait()


def start_servers(venv: Path, with_s3: bool) -> Servers:
    database_url = os.environ.get("UNIPHYS_TEST_DATABASE_URL")
    redis_url = os.environ.get("UNIPHYS_TEST_REDIS_URL")
    if not database_url or not redis_url:
        raise SystemExit("UNIPHYS_TEST_DATABASE_URL and UNIPHYS_TEST_REDIS_URL are not set: "
                         "run `. scripts/services` first (or --deployments embedded --no-noop)")
    servers = Servers(database_url, redis_url)
    if with_s3:
        moto = venv / "bin" / "moto_server"
        if not moto.exists():
            raise SystemExit(f"{moto} is missing: install the venv (scripts/test does)")
        port = free_port()
        servers.moto = subprocess.Popen([str(moto), "-H", "127.0.0.1", "-p", str(port)],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wait_port(port, "moto_server", servers.moto)
        servers.s3_endpoint = f"http://127.0.0.1:{port}"
    return servers


def start_distributed(binary: str, scratch: Path, workers: int, servers: Servers, run: str,
                      s3: bool, extra: dict[str, str], worker_stages: str) -> Deployment:
    schema = f"scale_{os.getpid()}_{run}"
    env = dict(os.environ, UNIPHYS_LOG="warn", UNIPHYS_DATABASE_URL=servers.database_url,
               UNIPHYS_DATABASE_SCHEMA=schema, UNIPHYS_REDIS_URL=servers.redis_url,
               UNIPHYS_REDIS_PREFIX=schema, UNIPHYS_DATA_DIR=str(scratch / "data"), **extra)
    if s3:
        assert servers.s3_endpoint is not None
        bucket = schema.replace("_", "-")
        conn = http.client.HTTPConnection(servers.s3_endpoint.removeprefix("http://"), timeout=30)
        conn.request("PUT", f"/{bucket}")
        if conn.getresponse().status != 200:
            raise SystemExit(f"moto refused to create bucket {bucket}")
        env.update(UNIPHYS_STORAGE_URL=f"s3://{bucket}", AWS_ENDPOINT_URL=servers.s3_endpoint,
                   AWS_REGION="us-east-1", AWS_ACCESS_KEY_ID="scale", AWS_SECRET_ACCESS_KEY="scale",
                   AWS_ALLOW_HTTP="true")
        store = "S3 (moto)"
    else:
        env["UNIPHYS_STORAGE_URL"] = str(scratch / "objects")
        store = "local objects"
    psql(servers.database_url, f"CREATE SCHEMA IF NOT EXISTS {schema}", check=True)
    subprocess.run([binary, "migrate"], env=env, check=True, stdout=subprocess.DEVNULL)
    created = subprocess.run([binary, "tenant", "create", "scale"], env=env, check=True,
                             capture_output=True, text=True)
    match = re.search(r"uk_[0-9a-f]+", created.stdout)
    if not match:
        raise SystemExit(f"`uniphys tenant create` printed no key: {created.stdout!r}")
    key = match[0]
    port = free_port()
    api = subprocess.Popen([binary, "api", "--listen", f"127.0.0.1:{port}"], env=env,
                           stdout=subprocess.DEVNULL, stderr=open(scratch / "api.log", "w"))
    deployment = Deployment(f"distributed (PostgreSQL, Redis, {store})", port, key,
                            dict(env, UNIPHYS_API_URL=f"http://127.0.0.1:{port}", UNIPHYS_API_KEY=key),
                            [api])
    wait_port(port, "uniphys api", api)
    deployment.env["UNIPHYS_STAGES"] = worker_stages
    for i in range(workers):
        deployment.processes.append(subprocess.Popen(
            [binary, "worker"], env=deployment.env, stdout=subprocess.DEVNULL,
            stderr=open(scratch / f"worker{i}.log", "w")))
    return deployment


def psql(database_url: str, sql: str, check: bool) -> None:
    binary = shutil.which("psql") or "/usr/lib/postgresql/15/bin/psql"
    subprocess.run([binary, "-X", "-q", "-v", "ON_ERROR_STOP=1", database_url, "-c", sql],
                   check=check, stdout=subprocess.DEVNULL,
                   env=dict(os.environ, PGOPTIONS="-c client_min_messages=warning"))


def drop_schema(database_url: str, schema: str) -> None:
    psql(database_url, f"DROP SCHEMA IF EXISTS {schema} CASCADE", check=False)


def wait_batch(api: Api, batch: str, total: int, timeout_secs: float) -> dict[str, int]:
    """Polls the batch until every job has finished; returns the counts by state."""
    started = time.monotonic()
    last = 0.0
    while True:
        counts = api.batch_states(batch)
        finished = sum(n for s, n in counts.items() if s in FINISHED)
        if finished >= total:
            return counts
        if time.monotonic() - last > 30:
            last = time.monotonic()
            log(f"  {batch}: {finished}/{total} finished {counts}")
        if time.monotonic() - started > timeout_secs:
            raise SystemExit(f"{batch}: only {finished} of {total} jobs finished in {timeout_secs:.0f} s")
        # Finer polls for small batches, whose drain takes seconds; a poll reads every page.
        time.sleep(0.2 if total <= 5_000 else 1.0)


def baseline(binary: str, folders: list[Path], scratch: Path, parallel: int) -> tuple[float, int]:
    """`uniphys run` on every folder, `parallel` at a time; returns the wall time and failures
    (exit code 2: the input was refused)."""
    def one(folder: Path) -> int:
        out = scratch / f"run{parallel}" / folder.name
        done = subprocess.run([binary, "run", str(folder), "--out", str(out), "--force"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              env=dict(os.environ, UNIPHYS_LOG="warn"))
        return done.returncode
    started = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(parallel) as pool:
        codes = list(pool.map(one, folders))
    return time.monotonic() - started, sum(1 for c in codes if c not in (0, 1))


def check_dataset(root: Path, expect_npz: bool) -> dict[str, int]:
    """Every entity folder's files, and its MJCF and URDF loaded in MuJoCo."""
    import mujoco  # the venv's; imported here so the no-op run does not need it

    with open(root / "index.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    result = {"rows": len(rows), "complete": 0, "mjcf_loads": 0, "urdf_loads": 0}
    problems = []
    for row in rows:
        entity = root / row["entity"]
        missing = [n for n in ENTITY_FILES if not (entity / n).is_file()]
        folders = ENTITY_FOLDERS if expect_npz else ENTITY_FOLDERS[:-1]
        missing += [f"{d}/" for d in folders if not any((entity / d).iterdir() if (entity / d).is_dir() else [])]
        if missing:
            problems.append(f"{row['entity']}: missing {missing}")
            continue
        result["complete"] += 1
        for name, key in (("model.xml", "mjcf_loads"), ("model.urdf", "urdf_loads")):
            try:
                mujoco.MjModel.from_xml_path(str(entity / name))
                result[key] += 1
            except Exception as e:  # noqa: BLE001 - every loader failure is reported
                problems.append(f"{row['entity']}/{name}: {str(e).splitlines()[0][:200]}")
    for p in problems[:10]:
        log(f"  check: {p}")
    return result


@dataclass
class RealRow:
    deployment: str
    workers: int
    submit_secs: float
    wall_secs: float
    counts: dict[str, int]
    export_secs: float
    check: dict[str, int]
    baseline_secs: float


def real_run(binary: str, folders: list[Path], deployment: Deployment, workers: int,
             scratch: Path, baseline_secs: float) -> RealRow:
    batch = "scale"
    api = Api(deployment.port, deployment.key)
    log(f"{deployment.name}, {workers} worker(s): submitting {len(folders)} folders")
    started = time.monotonic()
    with open(scratch / "submit.log", "w") as submit_log:
        subprocess.run([binary, "submit", "--batch", batch, *map(str, folders)], env=deployment.env,
                       check=True, stdout=submit_log, stderr=submit_log)
    submit_secs = time.monotonic() - started
    counts = wait_batch(api, batch, len(folders), timeout_secs=4 * 3600)
    wall_secs = time.monotonic() - started
    log(f"  all finished in {wall_secs:.0f} s: {counts}; exporting")
    out = scratch / "dataset"
    started = time.monotonic()
    subprocess.run([binary, "dataset", "export", "--batch", batch, "--out", str(out)],
                   env=deployment.env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    export_secs = time.monotonic() - started
    check = check_dataset(out / batch, expect_npz=True)
    log(f"  exported in {export_secs:.1f} s: {check}")
    return RealRow(deployment.name, workers, submit_secs, wall_secs, counts, export_secs, check,
                   baseline_secs)


def dashboard_p50_ms(api: Api, batch: str, repeats: int = 20) -> dict[str, float]:
    result = {}
    for template in DASHBOARD:
        path = template.format(batch=batch)
        times = []
        for _ in range(repeats):
            started = time.perf_counter()
            status, body = api.request("GET", path)
            times.append((time.perf_counter() - started) * 1000)
            if status != 200:
                raise SystemExit(f"GET {path}: {status} {body[:200]!r}")
        result[template] = statistics.median(times)
    return result


@dataclass
class NoopRow:
    jobs: int
    submit_secs: float
    drain_secs: float
    export_secs: float
    exported: int
    dashboard_ms: dict[str, float]


def noop_batch(binary: str, deployment: Deployment, batch: str, start: int, jobs: int,
               scratch: Path) -> NoopRow:
    api = Api(deployment.port, deployment.key)
    # Workers are held while the batch is submitted, so the drain is measured from a full queue.
    for stage in ("ingest", "decompose", "convert"):
        subprocess.run([binary, "stage", "pause", stage], env=deployment.env, check=True,
                       stdout=subprocess.DEVNULL)
    log(f"no-op: submitting {jobs} jobs into {batch}")
    submit_secs = jobs / seed(deployment.port, deployment.key, jobs, first=start,
                              batch_of=lambda _: batch)
    queued_ms = dashboard_p50_ms(api, batch)
    started = time.monotonic()
    for stage in ("ingest", "decompose", "convert"):
        subprocess.run([binary, "stage", "resume", stage], env=deployment.env, check=True,
                       stdout=subprocess.DEVNULL)
    counts = wait_batch(api, batch, jobs, timeout_secs=4 * 3600)
    drain_secs = time.monotonic() - started
    if counts.get("succeeded", 0) != jobs:
        raise SystemExit(f"no-op batch {batch}: {counts}")
    log(f"  drained in {drain_secs:.0f} s; exporting")
    out = scratch / "noop-dataset"
    started = time.monotonic()
    subprocess.run([binary, "dataset", "export", "--batch", batch, "--out", str(out), "--no-npz"],
                   env=deployment.env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    export_secs = time.monotonic() - started
    with open(out / batch / "index.csv", newline="") as f:
        exported = sum(1 for _ in csv.DictReader(f))
    done_ms = dashboard_p50_ms(api, batch)
    dashboard = {k: max(queued_ms[k], done_ms[k]) for k in queued_ms}
    return NoopRow(jobs, submit_secs, drain_secs, export_secs, exported, dashboard)


def print_real(rows: list[RealRow], objects: int, baselines: dict[int, float]) -> None:
    print(f"\n### Real objects through the service ({objects} shared PartNet-Mobility folders, "
          f"each submitted as a tar.gz)\n")
    for parallel, secs in sorted(baselines.items()):
        print(f"Baseline `uniphys run`, {parallel} at a time: {secs:.0f} s "
              f"({objects / secs * 3600:.0f} assets/h)")
    print()
    print("| deployment | workers | succeeded | dead | submit s | submit→all done s | assets/h | "
          "× baseline wall | export s | entities complete | MJCF loads | URDF loads | 40,000 assets in |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        per_hour = objects / r.wall_secs * 3600
        projection_h = 40_000 / per_hour
        print(f"| {r.deployment} | {r.workers} | {r.counts.get('succeeded', 0)} | "
              f"{r.counts.get('dead', 0)} | {r.submit_secs:.1f} | {r.wall_secs:.0f} | {per_hour:.0f} | "
              f"{r.wall_secs / r.baseline_secs:.2f} | {r.export_secs:.1f} | "
              f"{r.check['complete']}/{r.check['rows']} | {r.check['mjcf_loads']} | "
              f"{r.check['urdf_loads']} | {projection_h:.0f} h ({projection_h / 24:.1f} d) |")


def print_noop(small: NoopRow, large: NoopRow) -> None:
    print("\n### No-op jobs (stand-in stages, no work), PostgreSQL + Redis + local objects, "
          "two worker processes\n")
    print("| batch | jobs | uploads/s | drain jobs/s (3 stages each) | export assets/s | "
          "exported | " + " | ".join(f"`{d.split('?')[0].replace('{batch}', 'B')}` p50 ms" for d in DASHBOARD) + " |")
    print("|---|---:|---:|---:|---:|---:|" + "---:|" * len(DASHBOARD))
    for name, r in (("small", small), ("large", large)):
        print(f"| {name} | {r.jobs} | {r.jobs / r.submit_secs:.0f} | {r.jobs / r.drain_secs:.0f} | "
              f"{r.exported / r.export_secs:.0f} | {r.exported} | "
              + " | ".join(f"{r.dashboard_ms[d]:.1f}" for d in DASHBOARD) + " |")
    def ratio(f) -> str:
        return f"{f(large) / f(small):.2f}"
    print(f"| large / small | {large.jobs / small.jobs:.0f}x | "
          f"{ratio(lambda r: r.jobs / r.submit_secs)} | {ratio(lambda r: r.jobs / r.drain_secs)} | "
          f"{ratio(lambda r: r.exported / r.export_secs)} | | "
          + " | ".join(f"{large.dashboard_ms[d] / small.dashboard_ms[d]:.2f}" for d in DASHBOARD) + " |")
    print("\n(rates: higher is better, a ratio near 1 keeps its speed; dashboard: the slower of "
          "the p50s with the batch queued and done, lower is better)")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bin", default="target/release/uniphys")
    parser.add_argument("--data", default="../shared/data/partnet-mobility")
    parser.add_argument("--venv", default=os.environ.get("UNIPHYS_VENV", ".venv"))
    parser.add_argument("--objects", type=int, default=0, help="the first N folders (0: all)")
    parser.add_argument("--workers", default="1,2", help="worker counts to run")
    parser.add_argument("--deployments", default="embedded,distributed")
    parser.add_argument("--no-real", action="store_true", help="leave out the real objects")
    parser.add_argument("--no-noop", action="store_true", help="leave out the no-op jobs")
    parser.add_argument("--noop-small", type=int, default=1_000)
    parser.add_argument("--noop-jobs", type=int, default=40_000)
    parser.add_argument("--scratch", default=None, help="working folder (default: a temp dir, removed)")
    args = parser.parse_args()
    binary = str(Path(args.bin).resolve())
    if not os.access(binary, os.X_OK):
        raise SystemExit(f"{binary} is not an executable: cargo build --release --bin uniphys")
    venv = Path(args.venv)
    scratch = Path(args.scratch or tempfile.mkdtemp(prefix="uniphys-scale-"))
    scratch.mkdir(parents=True, exist_ok=True)
    workers = [int(w) for w in args.workers.split(",")]
    deployments = args.deployments.split(",")
    unknown = set(deployments) - {"embedded", "distributed"}
    if unknown:
        raise SystemExit(f"unknown deployments {sorted(unknown)}: embedded, distributed")
    need_servers = (not args.no_real and "distributed" in deployments) or not args.no_noop
    servers = start_servers(venv, with_s3=not args.no_real and "distributed" in deployments) \
        if need_servers else None
    try:
        real_rows: list[RealRow] = []
        baselines: dict[int, float] = {}
        folders = sorted(p.parent for p in Path(args.data).glob("*/mobility.urdf"))
        if args.objects:
            folders = folders[: args.objects]
        if not args.no_real:
            if not folders:
                raise SystemExit(f"no object folders (*/mobility.urdf) under {args.data}")
            for parallel in workers:
                log(f"baseline: uniphys run on {len(folders)} folders, {parallel} at a time")
                secs, refused = baseline(binary, folders, scratch / "baseline", parallel)
                baselines[parallel] = secs
                log(f"  {secs:.0f} s, {refused} refused")
            for name in deployments:
                for w in workers:
                    run_dir = scratch / f"{name}-{w}"
                    run_dir.mkdir(parents=True, exist_ok=True)
                    if name == "embedded":
                        deployment = start_embedded(binary, run_dir, w, {})
                    else:
                        assert servers is not None
                        deployment = start_distributed(binary, run_dir, w, servers, f"real{w}", True,
                                                       {}, stage_slots(1))
                    try:
                        real_rows.append(real_run(binary, folders, deployment, w, run_dir, baselines[w]))
                    finally:
                        deployment.stop()
                        if name == "distributed" and servers is not None:
                            drop_schema(servers.database_url, deployment.env["UNIPHYS_DATABASE_SCHEMA"])
        noop: tuple[NoopRow, NoopRow] | None = None
        if not args.no_noop:
            assert servers is not None
            run_dir = scratch / "noop"
            run_dir.mkdir(parents=True, exist_ok=True)
            extra = {"UNIPHYS_STAND_INS": ",".join(STAGES), "UNIPHYS_STAND_IN_WORK_MS": "0",
                     "UNIPHYS_MAX_BACKLOG_PER_TENANT": "1000000", "UNIPHYS_POLL_MS": "200"}
            deployment = start_distributed(binary, run_dir, 2, servers, "noop", False, extra,
                                           stage_slots(2))
            try:
                small = noop_batch(binary, deployment, "noop-small", 0, args.noop_small, run_dir)
                large = noop_batch(binary, deployment, "noop-large", args.noop_small, args.noop_jobs,
                                   run_dir)
                noop = (small, large)
            finally:
                deployment.stop()
                drop_schema(servers.database_url, deployment.env["UNIPHYS_DATABASE_SCHEMA"])
        if real_rows:
            print_real(real_rows, len(folders), baselines)
        if noop:
            print_noop(*noop)
        return 0
    finally:
        if servers is not None:
            servers.stop()
        if args.scratch is None:
            shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
