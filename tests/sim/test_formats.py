"""The URDF parses with yourdfpy and its meshes resolve; the UniPhys-40K record has the documented keys;
our mass properties agree with trimesh's on the example assets."""

import json
import subprocess

import numpy as np
import pytest
import trimesh
import yourdfpy

from conftest import EXAMPLES, INPUTS, exported, uniphys_bin

NAMES = [name for name, _ in INPUTS]
EXAMPLE_NAMES = [f"example/{p.stem}" for p in EXAMPLES]


@pytest.mark.parametrize("name", NAMES)
def test_urdf_parses_with_yourdfpy_and_meshes_resolve(exports, name):
    e = exported(exports, name)
    robot = yourdfpy.URDF.load(str(e.out / "model.urdf"), build_scene_graph=True, load_meshes=True)
    assert robot.validate(), f"yourdfpy rejects {name}"
    for link in robot.robot.links:
        if link.name == "world":
            continue
        assert link.inertial is not None and link.inertial.mass > 0, f"{link.name} has no mass"
        assert link.collisions, f"{link.name} has no collision geometry"
        for c in link.collisions:
            assert (e.out / c.geometry.mesh.filename).is_file()
    for joint in robot.robot.joints:
        if joint.type in ("revolute", "prismatic"):
            assert joint.limit is not None and joint.limit.lower < joint.limit.upper, f"{joint.name} lacks limits"
            assert joint.dynamics is not None and float(joint.dynamics.damping) > 0, f"{joint.name} lacks damping"


@pytest.mark.parametrize("name", EXAMPLE_NAMES)
def test_record_has_the_uniphys40k_layout(exports, name):
    e = exported(exports, name)
    record = json.loads((e.out / "record.json").read_text())
    obj = json.loads((e.out / "annotations" / "object.json").read_text())
    assert set(obj) >= {"object_name", "category", "dimension", "object_mass"}
    assert len(obj["dimension"]) == 3 and all(d > 0 for d in obj["dimension"])
    for part in record["parts"]:
        pid = part["id"]
        ann = json.loads((e.out / "annotations" / f"part_{pid}.json").read_text())
        assert set(ann) == {"index", "part_level", "basic_info", "kinematic_info"}
        assert set(ann["basic_info"]) >= {"material", "density", "young", "hardness", "poisson", "friction", "pass_check"}
        assert (e.out / "parts" / f"part_{pid}.obj").is_file()
        # Units at the edge: g/cm^3 in the record, kg/m^3 inside.
        rho = part["properties"]["density_kg_per_m3"]["value"]
        assert ann["basic_info"]["density"] == pytest.approx(rho / 1000.0, abs=1e-4)
    report = json.loads((e.out / "report.json").read_text())
    assert report["passed"], report["failures"]


@pytest.mark.parametrize("name", EXAMPLE_NAMES)
def test_mass_properties_agree_with_trimesh(exports, name):
    e = exported(exports, name)
    record = json.loads((e.out / "record.json").read_text())
    size = max(np.linalg.norm(np.array(p["bounds_in_object_m"][1]) - np.array(p["bounds_in_object_m"][0])) for p in record["parts"])
    for part in record["parts"]:
        obj = e.out / "parts" / f"part_{part['id']}.obj"
        ours = json.loads(subprocess.run([uniphys_bin(), "measure", str(obj)], capture_output=True, text=True, check=True).stdout)["parts"]
        mesh = trimesh.load(str(obj), force="mesh")
        assert mesh.is_watertight, f"{obj.name} is not watertight for trimesh"
        our_volume = sum(p["exact"]["volume_m3"] for p in ours)
        assert our_volume == pytest.approx(mesh.volume, rel=0.02), f"{obj.name}: volume {our_volume} vs trimesh {mesh.volume}"
        com = np.array(part["mass"]["com_in_object_m"])
        if part["mass"]["volume_method"] == "closed_mesh":
            assert part["mass"]["volume_m3"] == pytest.approx(mesh.volume, rel=0.02)
            assert np.linalg.norm(com - mesh.center_mass) <= 0.01 * size, f"{obj.name}: com {com} vs trimesh {mesh.center_mass}"
        else:
            # A hollow part of a known kind weighs as its walls: less material than the solid it
            # encloses, its centre of mass inside its box.
            assert part["mass"]["volume_method"].startswith("shell_"), part["mass"]["volume_method"]
            assert 0.0 < part["mass"]["volume_m3"] < mesh.volume, f"{obj.name}: walls {part['mass']['volume_m3']} vs solid {mesh.volume}"
            lo, hi = (np.array(b) for b in part["bounds_in_object_m"])
            assert np.all(com >= lo - 1e-9) and np.all(com <= hi + 1e-9), f"{obj.name}: com {com} outside {lo}..{hi}"
        # Voxels at the reference's pitch (longest side / 128) are the fallback for open meshes. On these
        # thin-walled parts no voxel count is within 2 % of the solid, so the claim checked is relative:
        # our grid (boundary voxels weighted by half) is at least as close to trimesh's exact volume as
        # trimesh's own filled grid, and its centre of mass is within 2 % of the object size (or no further off than trimesh's).
        pitch = float(np.max(mesh.extents)) / 128.0
        trimesh_grid = mesh.voxelized(pitch).fill()
        trimesh_voxel = trimesh_grid.volume
        our_voxel = sum(p["voxel"]["volume_m3"] for p in ours)
        assert abs(our_voxel - mesh.volume) <= abs(trimesh_voxel - mesh.volume), (
            f"{obj.name}: our voxel volume {our_voxel} is further from {mesh.volume} than trimesh's {trimesh_voxel}"
        )
        voxel_com_error = np.linalg.norm(np.array(ours[0]["voxel"]["com_m"]) - mesh.center_mass)
        trimesh_com_error = np.linalg.norm(trimesh_grid.points.mean(axis=0) - mesh.center_mass)
        # 2 %, not 1 %: the cabinet's 18 mm walls are under three voxels thick at this pitch, and
        # weighting boundary voxels by half shifts its centre of mass by 1.2 % of the object size.
        assert voxel_com_error <= max(0.02 * size, trimesh_com_error), (
            f"{obj.name}: voxel com off by {voxel_com_error:.4f} m, trimesh's grid by {trimesh_com_error:.4f} m"
        )
