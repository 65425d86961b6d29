"""`uniphys points` writes UniPhysGen's npz layout (reference 14.2) that numpy reads: shapes and
dtypes as documented, points on the object, unit normals, part names in numeric order, and the
coordinate frame of reference 14.3."""

import json
import subprocess

import numpy as np
import pytest
import trimesh

from conftest import REPO, uniphys_bin

CABINET = REPO / "test_data" / "examples" / "cabinet.glb"


@pytest.fixture(scope="module")
def points_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("points")
    proc = subprocess.run(
        [uniphys_bin(), "points", str(CABINET), "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    assert "timing_ms sample=" in proc.stderr
    return out, json.loads(proc.stdout)


def cabinet_vertices_z_up():
    # The ingest reads glTF as Y up and rotates +90 degrees about x: (x, y, z) -> (x, -z, y);
    # then, like `uniphys run`, the object rests on z = 0, centred in x and y.
    mesh = trimesh.load(CABINET, force="mesh")
    v = np.asarray(mesh.vertices)
    v = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)
    lo, hi = v.min(axis=0), v.max(axis=0)
    return v - np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2]])


def test_model_npz_has_the_documented_arrays(points_dir):
    out, summary = points_dir
    model = np.load(out / "npzs" / "model.npz")
    assert set(model.files) == {"point", "color", "normal", "part_names", "part_centers"}
    assert model["point"].shape == (100_000, 3) and model["point"].dtype == np.float32
    assert model["color"].shape == (100_000, 3) and model["color"].dtype == np.uint8
    assert model["normal"].shape == (100_000, 3) and model["normal"].dtype == np.float32
    names = model["part_names"]
    assert names.dtype.kind == "U"
    k = len(summary["parts"])
    assert names.shape == (k,)
    assert list(names) == sorted(names, key=int)
    assert model["part_centers"].shape == (k, 3) and model["part_centers"].dtype == np.float32


def test_part_npzs_exist_per_part_with_their_counts(points_dir):
    out, summary = points_dir
    model = np.load(out / "npzs" / "model.npz")
    for i, name in enumerate(model["part_names"]):
        part = np.load(out / "npzs" / f"{name}.npz")
        assert set(part.files) == {"point", "color", "normal"}
        n = part["point"].shape[0]
        assert n >= 10_000
        assert part["color"].shape == (n, 3) and part["color"].dtype == np.uint8
        assert part["normal"].shape == (n, 3) and part["normal"].dtype == np.float32
        # part_centers is the mean of the part's samples.
        np.testing.assert_allclose(model["part_centers"][i], part["point"].astype(np.float64).mean(axis=0), atol=1e-5)


def test_points_lie_within_the_object_bounds_and_normals_are_unit(points_dir):
    out, _ = points_dir
    v = cabinet_vertices_z_up()
    lo, hi = v.min(axis=0) - 1e-5, v.max(axis=0) + 1e-5
    for path in sorted((out / "npzs").glob("*.npz")):
        data = np.load(path)
        p = data["point"]
        assert (p >= lo).all() and (p <= hi).all(), path.name
        np.testing.assert_allclose(np.linalg.norm(data["normal"], axis=1), 1.0, atol=1e-5)
    # The object cloud reaches close to the object's box on every side.
    p = np.load(out / "npzs" / "model.npz")["point"]
    np.testing.assert_allclose(p.min(axis=0), v.min(axis=0), atol=0.02)
    np.testing.assert_allclose(p.max(axis=0), v.max(axis=0), atol=0.02)


def test_coordinate_frame_maps_the_object_into_0_2(points_dir):
    out, _ = points_dir
    frame = json.loads((out / "coordinate_frame.json").read_text())
    assert frame["name"] == "source_to_aabb_0_2"
    assert frame["model_frame"] == "aabb_normalized_shifted"
    p = np.load(out / "npzs" / "model.npz")["point"].astype(np.float64)
    center, scale, min_bound = np.array(frame["center"]), frame["scale"], np.array(frame["min_bound"])
    model = (p - center) / scale - min_bound
    assert model.min() >= -1e-6 and model.max() <= 2 + 1e-6
    # Longest axis spans [0, 2].
    assert abs((model.max(axis=0) - model.min(axis=0)).max() - 2.0) < 1e-6
    np.testing.assert_allclose(np.array(frame["shift"]), -min_bound)


def test_same_seed_gives_identical_files(points_dir, tmp_path):
    out, _ = points_dir
    proc = subprocess.run(
        [uniphys_bin(), "points", str(CABINET), "--out", str(tmp_path)], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "npzs" / "model.npz").read_bytes() == (out / "npzs" / "model.npz").read_bytes()
