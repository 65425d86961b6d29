"""Foundation benchmark: per-stage time of `uniphys run` on every example asset, and our voxel volume
against trimesh's `voxelized(pitch).fill()` on the same part files, timed in the same run.

Usage: scripts/bench   (builds the release binary, then runs this with the test venv)
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

REPO = Path(__file__).resolve().parents[1]
BIN = os.environ.get("UNIPHYS_BIN", str(REPO / "target" / "release" / "uniphys"))
REPEATS = int(os.environ.get("UNIPHYS_BENCH_REPEATS", "3"))
STAGES = ["ingest", "prepare", "ground", "colliders", "export"]


def run_json(*args):
    out = subprocess.run([BIN, *args], capture_output=True, text=True)
    if out.returncode not in (0, 1):
        sys.exit(f"uniphys {' '.join(args)} failed: {out.stderr}")
    return json.loads(out.stdout)


def main():
    examples = sorted((REPO / "test_data" / "examples").glob("*.glb"))
    work = Path(tempfile.mkdtemp(prefix="uniphys-bench-"))
    print(f"# uniphys run, median of {REPEATS} runs per asset (ms)")
    print(f"| asset | triangles | {' | '.join(STAGES)} | total |")
    print("|---" * (len(STAGES) + 3) + "|")
    parts = []
    for glb in examples:
        runs = [run_json("run", str(glb), "--out", str(work / glb.stem), "--json") for _ in range(REPEATS)]
        med = {s: statistics.median(r["timings_ms"][s] for r in runs) for s in STAGES}
        record = json.loads((work / glb.stem / "record.json").read_text())
        tris = sum(p["triangle_count"] for p in record["parts"])
        print(f"| {glb.stem} | {tris} | " + " | ".join(f"{med[s]:.1f}" for s in STAGES) + f" | {sum(med.values()):.1f} |")
        parts += sorted((work / glb.stem / "parts").glob("part_*.obj"))
    # A dense closed mesh, to see how both scale with triangles (the examples are small).
    sphere = work / "sphere" / "parts" / "icosphere_82k.obj"
    sphere.parent.mkdir(parents=True)
    trimesh.creation.icosphere(subdivisions=6, radius=0.2).export(str(sphere))
    parts.append(sphere)

    print()
    print(f"# voxel volume at pitch = longest side / 128, median of {REPEATS} (ms); ratio = trimesh / ours")
    print("| part | triangles | ours ms | trimesh ms | ratio | ours m^3 | trimesh m^3 | exact m^3 |")
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    for obj in parts:
        ours = [run_json("measure", str(obj))["parts"][0] for _ in range(REPEATS)]
        our_ms = statistics.median(o["voxel_ms"] for o in ours)
        mesh = trimesh.load(str(obj), force="mesh")
        pitch = float(np.max(mesh.extents)) / 128.0
        times = []
        for _ in range(REPEATS):
            start = time.perf_counter()
            volume = mesh.voxelized(pitch).fill().volume
            times.append((time.perf_counter() - start) * 1e3)
        tm_ms = statistics.median(times)
        ratios.append(tm_ms / our_ms)
        exact = ours[0]["exact"]["volume_m3"] if ours[0]["exact"] else float("nan")
        name = f"{obj.parent.parent.name}/{obj.stem}"
        print(f"| {name} | {len(mesh.faces)} | {our_ms:.1f} | {tm_ms:.1f} | {tm_ms / our_ms:.1f}x | {ours[0]['voxel']['volume_m3']:.6g} | {volume:.6g} | {exact:.6g} |")
    print()
    print(f"geometric mean speed-up over trimesh: {float(np.exp(np.mean(np.log(ratios)))):.1f}x over {len(ratios)} parts")


if __name__ == "__main__":
    main()
