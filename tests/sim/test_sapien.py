"""The URDF in SAPIEN (PartNet-Mobility's own simulator, from PyPI), on PhysX's CPU system, for the
example assets and the shared real objects (the assets whose joints the pipeline found): it loads
with the root fixed and the record's movable joints, stays finite and bounded for 2 s under gravity,
and each limited joint is driven from rest to both of its limits. SAPIEN's URDF loader builds render
materials for visual elements, which needs a GPU this machine lacks, so a copy without `<visual>`
elements is loaded: the bodies, inertia, colliders and joints are the same. PyBullet's robot URDFs
are left to the PyBullet and MuJoCo checks: driven from rest in SAPIEN, some legs are stopped by
their own bodies."""

import re

import numpy as np
import pytest
import sapien

from conftest import INPUTS, exported

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
    robot = loader.load(str(physics))
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
