"""Speed on real assets (issue 18): `uniphys run --ignore-joints` on every shared PartNet-Mobility
object with its part labels hidden (the path that grounds joints from geometry), one object at a
time; per-stage time (median, p90, max) and peak memory (the process's peak RSS, an upper bound on
every stage's); then one object subdivided to about 10k, 100k and 1M triangles.

With `--baseline-bin` (a build of the commit before the change) each object is run by both binaries
back to back, so load on the machine falls on both, and every row carries the ratio new / baseline.

Usage:
  .venv/bin/python bench/real_speed.py --bin target/release/uniphys [--baseline-bin OLD]
      [--data ../shared/data/partnet-mobility] [--only NAME ...] [--no-scaling]
      [--scaling-object kitchen-101921] [--scaling-targets 10000,100000,1000000]
"""

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

REPO = Path(__file__).resolve().parents[1]
STAGES = ["ingest", "prepare", "colliders", "ground", "verify", "export"]
HIDDEN_FILES = {"semantics.txt", "mobility_v2.json", "meta.json"}
NAME_ATTR = re.compile(r'(<(?:visual|collision))\s+name="[^"]*"')


def hidden_copy(source, dest, meshes=None):
    """`source` without its part labels (the files that hold them and the `name` of visuals and
    collisions), as the articulation benchmark hides them; the meshes are copied (the pipeline
    reads no file outside the asset's folder, so links will not do), or `meshes`, a folder of
    replacements, is moved in."""
    dest.mkdir(parents=True)
    for entry in source.iterdir():
        if entry.name in HIDDEN_FILES:
            continue
        if entry.name == "mobility.urdf":
            (dest / entry.name).write_text(NAME_ATTR.sub(r"\1", entry.read_text()))
        elif entry.is_dir() and meshes is None:
            shutil.copytree(entry, dest / entry.name)
        elif entry.is_dir():
            shutil.move(meshes, dest / entry.name)
        else:
            shutil.copy2(entry, dest / entry.name)


def run_measured(binary, asset, out):
    """One `uniphys run --ignore-joints`: (per-stage ms, or None on failure; wall s; peak RSS MiB;
    error lines). The run is wrapped in `/usr/bin/time -f %M` when present (GNU time prints the
    child's peak in KiB), else the RSS is unknown (nan)."""
    time_bin = "/usr/bin/time"
    cmd = [binary, "run", str(asset), "--out", str(out), "--json", "--force", "--ignore-joints"]
    started = time.time()
    if os.path.exists(time_bin):
        proc = subprocess.run([time_bin, "-f", "PEAK_RSS_KIB %M", *cmd], capture_output=True, text=True, timeout=3600)
    else:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    wall = time.time() - started
    peak = re.search(r"PEAK_RSS_KIB (\d+)", proc.stderr)
    peak_mib = int(peak.group(1)) / 1024 if peak else float("nan")
    if proc.returncode not in (0, 1):
        lines = [line for line in proc.stderr.splitlines() if not line.startswith("PEAK_RSS_KIB")]
        return None, wall, peak_mib, lines[-1:] or [f"exit {proc.returncode}"]
    try:
        summary = json.loads(proc.stdout.strip().splitlines()[-1])
    except (json.JSONDecodeError, IndexError):
        return None, wall, peak_mib, ["no JSON summary"]
    return summary["timings_ms"], wall, peak_mib, []


def quantiles(values):
    values = sorted(values)
    if not values:
        return (float("nan"),) * 3
    p90 = values[min(len(values) - 1, int(round(0.9 * (len(values) - 1))))]
    return statistics.median(values), p90, values[-1]


def fmt_ratio(new, old):
    return f"{new / old:.2f}" if old and old == old and new == new and old > 0 else "-"


def triangle_count(folder):
    total = 0
    for obj in folder.rglob("*.obj"):
        with open(obj, errors="replace") as f:
            total += sum(1 for line in f if line.startswith("f "))
    return total


def subdivided(source, target, work):
    """A copy of `source` whose meshes are split (each chosen triangle into four at its edge
    midpoints) until the object has about `target` triangles: whole levels first, then the
    largest triangles of every mesh in proportion."""
    base = triangle_count(source / "textured_objs")
    folder = work / f"meshes-{target}"
    folder.mkdir(parents=True)
    for obj in sorted((source / "textured_objs").glob("*.obj")):
        mesh = trimesh.load(obj, force="mesh", process=False)
        factor = target / max(base, 1)
        while factor >= 4.0:
            mesh = mesh.subdivide()
            factor /= 4.0
        extra = int(round((factor - 1.0) / 3.0 * len(mesh.faces)))
        if extra > 0:
            largest = np.argsort(-mesh.area_faces)[:extra]
            mesh = mesh.subdivide(face_index=largest)
        mesh.export(folder / obj.name)
    return folder


def objects(data, only):
    folders = sorted(p for p in data.iterdir() if (p / "mobility.urdf").exists())
    if only:
        folders = [p for p in folders if any(o in p.name for o in only)]
    return folders


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bin", default=os.environ.get("UNIPHYS_BIN", str(REPO / "target/release/uniphys")))
    parser.add_argument("--baseline-bin", help="a build of the commit before the change")
    parser.add_argument("--data", default=str(REPO.parent / "shared/data/partnet-mobility"))
    parser.add_argument("--only", nargs="*")
    parser.add_argument("--no-scaling", action="store_true")
    parser.add_argument("--no-objects", action="store_true")
    parser.add_argument("--scaling-object", default="kitchen-101921")
    parser.add_argument("--scaling-targets", default="10000,100000,1000000")
    args = parser.parse_args()
    binaries = [("new", args.bin)] + ([("base", args.baseline_bin)] if args.baseline_bin else [])
    work = Path(tempfile.mkdtemp(prefix="uniphys-speed-"))
    data = Path(args.data)

    if not args.no_objects:
        rows = {name: [] for name, _ in binaries}
        print("| object | triangles | " + " | ".join(
            f"{name} s | {name} MiB" for name, _ in binaries) + (" | ratio |" if len(binaries) > 1 else " |"))
        print("|---|---:|" + "---:|---:|" * len(binaries) + ("---:|" if len(binaries) > 1 else ""))
        for folder in objects(data, args.only):
            asset = work / "assets" / folder.name
            hidden_copy(folder, asset)
            tris = triangle_count(folder / "textured_objs")
            cells = []
            walls = {}
            for name, binary in binaries:
                stages, wall, peak, error = run_measured(binary, asset, work / "out" / name / folder.name)
                rows[name].append((folder.name, tris, stages, wall, peak, error))
                walls[name] = wall
                cells.append(f"{wall:.2f}{'' if stages else ' (' + error[0][:60] + ')'} | {peak:.0f}")
            ratio = f" | {fmt_ratio(walls['new'], walls['base'])} |" if len(binaries) > 1 else " |"
            print(f"| {folder.name} | {tris} | " + " | ".join(cells) + ratio, flush=True)
            shutil.rmtree(work / "out", ignore_errors=True)

        print()
        n = len(rows["new"])
        print(f"## Per stage over {n} objects (s): median / p90 / max" + (", and new / baseline" if len(binaries) > 1 else ""))
        print()
        header = "| stage | " + " | ".join(f"{name} median | {name} p90 | {name} max" for name, _ in binaries)
        if len(binaries) > 1:
            header += " | ratio median | ratio p90 | ratio max"
        print(header + " |")
        print("|---|" + "---:|" * (3 * len(binaries) + (3 if len(binaries) > 1 else 0)))
        stats = {}
        for stage in STAGES + ["whole run (wall)", "peak RSS (MiB)"]:
            cells = []
            for name, _ in binaries:
                if stage == "whole run (wall)":
                    values = [r[3] for r in rows[name]]
                elif stage == "peak RSS (MiB)":
                    values = [r[4] for r in rows[name] if r[4] == r[4]]
                else:
                    values = [r[2][stage] / 1e3 for r in rows[name] if r[2] and stage in r[2]]
                stats[(stage, name)] = quantiles(values)
                cells += [f"{v:.3f}" if stage != "peak RSS (MiB)" else f"{v:.0f}" for v in stats[(stage, name)]]
            if len(binaries) > 1:
                cells += [fmt_ratio(a, b) for a, b in zip(stats[(stage, "new")], stats[(stage, "base")])]
            print(f"| {stage} | " + " | ".join(cells) + " |")
        for name, _ in binaries:
            failed = [r[0] for r in rows[name] if not r[2]]
            over = [f"{r[0]} ({r[3]:.1f} s)" for r in rows[name] if r[3] >= 10.0]
            print(f"\n{name}: {n - len(failed)} of {n} runs finished; failed: {', '.join(failed) or 'none'}; "
                  f"10 s or more: {', '.join(over) or 'none'}")

    if not args.no_scaling:
        source = data / args.scaling_object
        print()
        print(f"## Scaling: {source.name} subdivided (peak RSS is the whole process's)")
        print()
        print("| triangles | " + " | ".join(
            f"{name} s | {name} MiB | {name} slowest stage" for name, _ in binaries) + (" | ratio |" if len(binaries) > 1 else " |"))
        print("|---:|" + "---:|---:|---|" * len(binaries) + ("---:|" if len(binaries) > 1 else ""))
        for target in [int(t) for t in args.scaling_targets.split(",")]:
            meshes = subdivided(source, target, work / "scaling")
            asset = work / "scaling" / f"{source.name}-{target}"
            hidden_copy(source, asset, meshes=meshes)
            tris = triangle_count(asset / "textured_objs")
            cells, walls = [], {}
            for name, binary in binaries:
                stages, wall, peak, error = run_measured(binary, asset, work / "out" / name / asset.name)
                walls[name] = wall
                slowest = max(stages.items(), key=lambda kv: kv[1]) if stages else ("failed: " + error[0][:60], 0.0)
                cells.append(f"{wall:.2f} | {peak:.0f} | {slowest[0]} {slowest[1] / 1e3:.2f} s")
                shutil.rmtree(work / "out", ignore_errors=True)
            ratio = f" | {fmt_ratio(walls['new'], walls['base'])} |" if len(binaries) > 1 else " |"
            print(f"| {tris} | " + " | ".join(cells) + ratio, flush=True)
            shutil.rmtree(asset, ignore_errors=True)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
