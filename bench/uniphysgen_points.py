"""UniPhysGen point preparation benchmark: `uniphys points` (its own sampling time, read from the
`timing_ms` line it prints on stderr) against trimesh's `sample_surface` on the same meshes, in
the same run.

Asset: a 10-part GLB made in this run from three shipped examples placed side by side (cabinet 5
parts, laptop 3, box with lid 2). Work on both sides: 100,000 object points plus each part's
max(10,000, area share of 100,000) points, with colours and face normals.

Usage: cargo build --release --bin uniphys && .venv/bin/python bench/uniphysgen_points.py
(UNIPHYS_BIN overrides the binary, default target/release/uniphys; UNIPHYS_BENCH_REPEATS, default 5)
"""

import os
import re
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
REPEATS = int(os.environ.get("UNIPHYS_BENCH_REPEATS", "5"))
EXAMPLES = ["cabinet", "laptop", "box_with_lid"]
OBJECT_POINTS = 100_000
TIMING = re.compile(r"timing_ms sample=([0-9.]+) frame=([0-9.]+) write=([0-9.]+) load=([0-9.]+)")


def ten_part_asset(directory: Path) -> Path:
    """The three examples side by side in one GLB, one node per part (10 parts)."""
    scene = trimesh.Scene()
    offset = 0.0
    for name in EXAMPLES:
        for i, mesh in enumerate(trimesh.load(REPO / "test_data" / "examples" / f"{name}.glb", force="scene").dump()):
            mesh = mesh.copy()
            mesh.apply_translation([offset, 0.0, 0.0])
            scene.add_geometry(mesh, node_name=f"{name}_{i}", geom_name=f"{name}_{i}")
        offset += 1.0
    path = directory / "ten_parts.glb"
    scene.export(str(path))
    return path


def ours(asset: Path):
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        proc = subprocess.run(
            [BIN, "points", str(asset), "--out", out, "--object-points", str(OBJECT_POINTS)],
            capture_output=True,
            text=True,
        )
        wall = (time.perf_counter() - t0) * 1e3
    if proc.returncode != 0:
        sys.exit(f"uniphys points failed: {proc.stderr}")
    match = TIMING.search(proc.stderr)
    if not match:
        sys.exit(f"no timing_ms line in uniphys points stderr: {proc.stderr}")
    sample, frame, write, load = map(float, match.groups())
    return sample, frame, write, load, wall


def trimesh_sampling(parts, full):
    """What the reference's generate_npzs.py does per entity: object + every part, with colours."""
    t0 = time.perf_counter()
    total_area = full.area
    for mesh, n in [(full, OBJECT_POINTS)] + [
        (p, max(10_000, int(p.area / total_area * OBJECT_POINTS))) for p in parts
    ]:
        try:
            points, faces, colors = trimesh.sample.sample_surface(mesh, n, seed=42, sample_color=True)
        except (AttributeError, TypeError):
            # An untextured PBR material: trimesh cannot sample its texture; use its face colours
            # (the material's base colour), as the reference falls back to the material colour.
            points, faces = trimesh.sample.sample_surface(mesh, n, seed=42)
            main_color = getattr(getattr(mesh.visual, "material", None), "main_color", None)
            rgb = np.asarray(main_color if main_color is not None else [255, 255, 255, 255], dtype=np.uint8)[:3]
            colors = np.broadcast_to(rgb, (len(faces), 3)).copy()
        normals = mesh.face_normals[faces]
        normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    return (time.perf_counter() - t0) * 1e3


def main():
    if not Path(BIN).is_file():
        sys.exit(f"binary not found at {BIN}; run `cargo build --release --bin uniphys` or set UNIPHYS_BIN")
    asset = ten_part_asset(Path(tempfile.mkdtemp(prefix="uniphys-points-")))
    scene = trimesh.load(asset, force="scene")
    parts = list(scene.dump())
    full = trimesh.util.concatenate(parts)
    runs = [ours(asset) for _ in range(REPEATS)]
    theirs = [trimesh_sampling(parts, full) for _ in range(REPEATS)]
    med = lambda xs: statistics.median(xs)
    sample = med([r[0] for r in runs])
    trimesh_ms = med(theirs)
    print(f"asset: {asset.name} ({len(parts)} parts, {len(full.faces)} triangles), {OBJECT_POINTS} object points, median of {REPEATS}")
    print("| what | ms |")
    print("|---|---|")
    print(f"| uniphys points: sample (object + parts, colours, normals) | {sample:.1f} |")
    print(f"| uniphys points: frame + voxel features (256 bins) | {med([r[1] for r in runs]):.1f} |")
    print(f"| uniphys points: write npzs + frame | {med([r[2] for r in runs]):.1f} |")
    print(f"| uniphys points: load asset | {med([r[3] for r in runs]):.1f} |")
    print(f"| uniphys points: whole process (wall) | {med([r[4] for r in runs]):.1f} |")
    print(f"| trimesh sample_surface (object + parts, colours, normals) | {trimesh_ms:.1f} |")
    print(f"ratio trimesh / uniphys sampling: {trimesh_ms / sample:.2f}x")


if __name__ == "__main__":
    main()
