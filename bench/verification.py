"""Verification benchmark (issue 6): the verification time per joint, and our volume and contact
computations against trimesh's and scipy's on the same meshes and points, timed in the same run.

Runs `cargo bench -p uniphys_verify --bench verification -- --emit DIR` (prints the per-joint sweep
table and writes the part meshes, the contact point sets and our own times to DIR), then times on
exactly those inputs:
- the reference's part volume (section 11.2): `mesh.voxelized(pitch=max(extents)/128).fill().volume`;
- the reference's contact search (sections 7.2 and 12) with a scipy cKDTree over the moving points,
  the threshold starting at and growing by the sweep's step until >= min_points parent points lie
  within it (`<=`), the same start, step, increments and minimum as ours; and, for information,
  the same search with dense pairwise distances (scipy cdist), which is what the reference computes
  (torch, on a GPU when it has one).

Usage: scripts/bench   (or: .venv/bin/python bench/verification.py)
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
from scipy.spatial import cKDTree
from scipy.spatial.distance import cdist

REPO = Path(__file__).resolve().parents[1]
VOLUME_TOLERANCE = 0.05  # relative difference accepted between the two whole-voxel volumes
# trimesh takes seconds per part (subdivision of large faces down to the pitch): one run by default.
TRIMESH_RUNS = int(os.environ.get("UNIPHYS_BENCH_TRIMESH_RUNS", "1"))


def median_ms(runs, f):
    """Median wall-clock time of `runs` calls of f (ms) and the last result."""
    times, result = [], None
    for _ in range(runs):
        start = time.perf_counter()
        result = f()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times), result


def geomean(xs):
    return float(np.exp(np.mean(np.log(xs))))


def grow_patch(distances, parent, j):
    """The threshold growth of uniphys_verify's grow_patch on precomputed nearest distances."""
    for k in range(j["increments"] + 1):
        threshold = j["start_m"] + j["step_m"] * k
        inside = distances <= threshold
        if np.count_nonzero(inside) >= j["min_points"]:
            return parent[inside], threshold
    return None, None


def contact_kdtree(moving, parent, j):
    tree = cKDTree(moving)
    distances, _ = tree.query(parent, k=1)
    return grow_patch(distances, parent, j)


def contact_dense(moving, parent, j):
    return grow_patch(cdist(parent, moving).min(axis=1), parent, j)


def run_ours(out):
    cmd = ["cargo", "bench", "--locked", "-q", "-p", "uniphys_verify", "--bench", "verification",
           "--", "--emit", str(out)]
    done = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{done.stderr}")
    print(done.stdout.strip().split("\n\nwrote")[0])
    return json.loads((out / "ours.json").read_text())


def volume_table(out, ours):
    runs = ours["volume_runs"]
    print()
    print(f"# part volume at pitch = longest side / {ours['resolution']} (ms; ours median of {runs}, "
          f"trimesh median of {TRIMESH_RUNS}); ratio = trimesh / ours")
    print("| part | triangles | ours voxelize ms | trimesh ms | ratio | ours solid ms (method) | ratio | "
          "filled voxels ours / trimesh | whole-voxel m^3 ours / trimesh (diff) | ours half-surface m^3 | exact m^3 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    voxel_ratios, solid_ratios, checks = [], [], []
    for p in ours["parts"]:
        mesh = trimesh.load(str(out / p["obj"]), force="mesh")
        pitch = float(np.max(mesh.extents)) / ours["resolution"]
        tm_ms, grid = median_ms(TRIMESH_RUNS, lambda: mesh.voxelized(pitch=pitch).fill())
        tm_m3, tm_count = float(grid.volume), int(grid.filled_count)
        diff = tm_m3 / p["voxel_whole_m3"] - 1.0
        exact = float(mesh.volume) if mesh.is_watertight else float("nan")
        voxel_ratios.append(tm_ms / p["voxelize_ms"])
        solid_ratios.append(tm_ms / p["solid_ms"])
        checks.append((p, diff, exact, mesh.extents / pitch))
        print(f"| {p['obj'][:-4]} ({p['name']}) | {p['triangles']} | {p['voxelize_ms']:.2f} | {tm_ms:.2f} | "
              f"{voxel_ratios[-1]:.1f}x | {p['solid_ms']:.4f} ({p['solid_method']}) | {solid_ratios[-1]:.0f}x | "
              f"{p['filled_count']} / {tm_count} | {p['voxel_whole_m3']:.4g} / {tm_m3:.4g} ({diff:+.1%}) | "
              f"{p['voxel_m3']:.4g} | {exact:.4g} |")
    print()
    print(f"geometric mean speed-up over trimesh: voxelize {geomean(voxel_ratios):.1f}x, "
          f"solid_mass_properties {geomean(solid_ratios):.0f}x over {len(voxel_ratios)} parts")
    return checks


def contact_table(out, ours):
    runs = ours["contact_runs"]
    print()
    print(f"# contact search at rest (kd-tree over the moving group's samples + threshold growth), "
          f"median of {runs} (ms); ratio = scipy / ours")
    print("| joint | moving pts | parent pts | ours ms | cKDTree ms | ratio | dense cdist ms | "
          "points ours / scipy | threshold m ours / scipy |")
    print("|---|---|---|---|---|---|---|---|---|")
    ratios, checks = [], []
    for j in ours["joints"]:
        moving, parent = np.load(out / j["moving"]), np.load(out / j["parent"])
        kd_ms, (points, threshold) = median_ms(runs, lambda: contact_kdtree(moving, parent, j))
        dense_ms, (dense_points, _) = median_ms(max(3, runs // 4), lambda: contact_dense(moving, parent, j))
        count = 0 if points is None else len(points)
        dense_count = 0 if dense_points is None else len(dense_points)
        ratios.append(kd_ms / j["ours_ms"])
        checks.append((j, count, dense_count, threshold))
        print(f"| {j['asset']}/{j['joint']} | {len(moving)} | {len(parent)} | {j['ours_ms']:.2f} | {kd_ms:.2f} | "
              f"{ratios[-1]:.2f}x | {dense_ms:.2f} | {j['points']} / {count} | "
              f"{j['threshold_m']:.5g} / {threshold if threshold is None else f'{threshold:.5g}'} |")
    print()
    print(f"geometric mean speed-up over scipy cKDTree: {geomean(ratios):.2f}x over {len(ratios)} joints")
    return checks


def print_checks(volumes, contacts):
    print()
    print("# agreement")
    for p, diff, exact, voxels in volumes:
        ok = abs(diff) <= VOLUME_TOLERANCE
        size = " x ".join(f"{v:.2f}" for v in voxels)
        verdict = "ok" if ok else f"beyond {VOLUME_TOLERANCE:.0%}, the part spans {size} voxels"
        print(f"- volume {p['obj'][:-4]}: whole-voxel volumes differ by {diff:+.1%} ({verdict}); "
              f"from the exact volume: ours (surface voxels half) {p['voxel_m3'] / exact - 1.0:+.1%}, "
              f"trimesh (all whole) {p['voxel_whole_m3'] * (1 + diff) / exact - 1.0:+.1%}")
    print("  (surface voxels are chosen differently: ours are the voxels a triangle touches, so a face "
          "lying on a voxel boundary marks both neighbours; trimesh's are the voxels, centred on "
          "multiples of the pitch, holding points of the surface subdivided below the pitch)")
    for j, count, dense_count, threshold in contacts:
        same = j["points"] == count == dense_count and threshold is not None and threshold == j["threshold_m"]
        print(f"- contact {j['asset']}/{j['joint']}: {j['points']} points (ours), {count} (cKDTree), "
              f"{dense_count} (dense): {'identical' if same else 'DIFFERENT'}")


def main():
    with tempfile.TemporaryDirectory(prefix="uniphys-verify-bench-") as tmp:
        out = Path(tmp)
        ours = run_ours(out)
        volumes = volume_table(out, ours)
        contacts = contact_table(out, ours)
        print_checks(volumes, contacts)


if __name__ == "__main__":
    main()
