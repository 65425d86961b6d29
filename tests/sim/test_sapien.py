"""The URDF in SAPIEN (PartNet-Mobility's own simulator, from PyPI), on PhysX's CPU system, for the
example assets and the shared real objects (the assets whose joints the pipeline found): it loads
with the root fixed and the record's movable joints, stays finite and bounded for 2 s under gravity,
and each limited joint is driven from rest to both of its limits. SAPIEN's URDF loader builds render
materials for visual elements, which needs a GPU this machine lacks, so a copy without `<visual>`
elements is loaded: the bodies, inertia, colliders and joints are the same. The loader reads
`model.srdf`, which turns off the contacts of parts that touch at rest without a joint between them
(a handle by a hinge against the body, neighbouring knobs). PyBullet's robot URDFs
are left to the PyBullet and MuJoCo checks: driven from rest in SAPIEN, some legs are stopped by
their own bodies."""

import json
import re

import numpy as np
import pytest
import sapien

from conftest import INPUTS, PARTNET, _run, exported, uniphys_bin

NAMES = [name for name, _ in INPUTS if name.startswith(("example/", "partnet/"))]
SIM_SECONDS = 2.0
STEP_S = 1.0 / 240.0
MAX_SPEED = 50.0  # rad/s or m/s: anything above this in a passive asset is an explosion
DRIVE_SECONDS = 2.0


def _physics_only(urdf: str) -> str:
    return re.sub(r"<visual\b.*?</visual>", "", urdf, flags=re.S)


@pytest.mark.parametrize("name", NAMES)
def test_urdf_loads_in_sapien_settles_and_is_driven_to_its_limits(exports, name):
    e = exported(exports, name)
    urdf = e.out / "model.urdf"
    physics = urdf.with_name("model_sapien.urdf")
    physics.write_text(_physics_only(urdf.read_text()))
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(STEP_S)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    robot = loader.load(str(physics), srdf_file=str(e.out / "model.srdf"))
    assert robot is not None, f"SAPIEN did not load {name}"
    assert robot.dof == len(e.summary["movable_joints"]), "SAPIEN sees a different number of movable joints"
    for _ in range(int(SIM_SECONDS / STEP_S)):
        scene.step()
    q, v = robot.get_qpos(), robot.get_qvel()
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(v)), f"{name} not finite at rest"
    assert np.all(np.abs(v) < MAX_SPEED), f"{name} explodes at rest: {v}"
    limits = robot.get_qlimits()
    rest = robot.get_qpos()
    for k, joint in enumerate(robot.get_active_joints()):
        robot.set_qpos(rest)
        robot.set_qvel(np.zeros_like(rest))
        lo, hi = limits[k]
        if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
            continue
        joint.set_drive_properties(stiffness=1e4, damping=1e2)
        for target in (lo, hi):
            joint.set_drive_target(target)
            for _ in range(int(DRIVE_SECONDS / STEP_S)):
                scene.step()
            q = robot.get_qpos()[k]
            assert np.isfinite(q), f"{name} {joint.name} not finite at {target}"
            assert abs(q - target) <= 0.05 * (hi - lo) + 1e-3, f"{name} {joint.name}: {q:.4f} did not reach {target:.4f}"
        joint.set_drive_properties(stiffness=0.0, damping=0.0)


# A cabinet door with its true joint whose handle, welded to the door by the hinge, touches the
# cabinet at rest: a pair no joint connects, so only `model.srdf` turns its contacts off.
HANDLE_BY_THE_HINGE = "kitchen-12249"


def _drive_each_to_its_upper_limit(urdf, srdf):
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(STEP_S)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    robot = loader.load(str(urdf), srdf_file=str(srdf))
    reached = {}
    for k, joint in enumerate(robot.get_active_joints()):
        lo, hi = robot.get_qlimits()[k]
        joint.set_drive_properties(stiffness=1e4, damping=1e2)
        joint.set_drive_target(hi)
        for _ in range(int(DRIVE_SECONDS / STEP_S)):
            scene.step()
        reached[joint.name] = (float(robot.get_qpos()[k]), float(lo), float(hi))
    return reached


def test_the_srdf_frees_a_door_whose_welded_handle_touches_the_cabinet_at_rest(tmp_path):
    source = PARTNET / HANDLE_BY_THE_HINGE
    assert (source / "mobility.urdf").is_file(), f"these checks need {source} beside the repository"
    out = tmp_path / "out"
    code, stderr, _ = _run(uniphys_bin(), source, out, [])
    assert code in (0, 1), stderr
    report = json.loads((out / "report.json").read_text())
    assert any(x["why"] == "touch at rest" for x in report["contact_excludes"]), "the fixture lost its touching pair"
    physics = out / "model_sapien.urdf"
    physics.write_text(_physics_only((out / "model.urdf").read_text()))
    with_srdf = _drive_each_to_its_upper_limit(physics, out / "model.srdf")
    for name, (q, lo, hi) in with_srdf.items():
        assert abs(q - hi) <= 0.05 * (hi - lo), f"{name} stopped at {q:.3f} of {hi:.3f} with the SRDF"
    # Without it the handle holds the door: the SRDF is what frees it.
    without = _drive_each_to_its_upper_limit(physics, tmp_path / "none.srdf")
    assert any(abs(q - hi) > 0.05 * (hi - lo) for q, lo, hi in without.values()), f"{without}: the fixture no longer needs the SRDF"
