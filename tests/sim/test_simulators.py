"""Independent checks of our exports: the MJCF and the URDF load and simulate in MuJoCo and PyBullet
(and MuJoCo's URDF importer), stay finite and bounded for 2 s under gravity with the base fixed, and
every joint can be driven to both of its limits."""

import numpy as np
import pytest
import mujoco
import pybullet as p

from conftest import INPUTS, exported

NAMES = [name for name, _ in INPUTS]
SIM_SECONDS = 2.0
MAX_SPEED = 50.0  # rad/s or m/s: anything above this in a passive asset is an explosion
# MuJoCo's joint types as plain ints: numpy's int32 does not compare equal to the enum.
MOVABLE_TYPES = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
FREE = int(mujoco.mjtJoint.mjJNT_FREE)


def joint_types(model: mujoco.MjModel) -> list[int]:
    return [int(t) for t in model.jnt_type]


def _mujoco_rollout(model: mujoco.MjModel, seconds: float) -> mujoco.MjData:
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for _ in range(int(round(seconds / model.opt.timestep))):
        mujoco.mj_step(model, data)
        if not (np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))):
            break
    return data


def _assert_sane(qpos, qvel, what: str):
    assert np.all(np.isfinite(qpos)), f"{what}: non-finite positions {qpos}"
    assert np.all(np.isfinite(qvel)), f"{what}: non-finite velocities {qvel}"
    if len(qvel):
        assert np.max(np.abs(qvel)) < MAX_SPEED, f"{what}: velocity {np.max(np.abs(qvel)):.1f} exceeds {MAX_SPEED}"


def _limited_joints(model: mujoco.MjModel):
    for j in range(model.njnt):
        if int(model.jnt_type[j]) in MOVABLE_TYPES and model.jnt_limited[j]:
            yield j, model.jnt_range[j]


@pytest.mark.parametrize("name", NAMES)
def test_mjcf_loads_settles_and_reaches_limits(exports, name):
    e = exported(exports, name)
    model = mujoco.MjModel.from_xml_path(str(e.out / "model.xml"))
    assert model.nbody >= 2, "no bodies in the MJCF"
    # The root is fixed: no free joint anywhere.
    assert FREE not in joint_types(model)
    data = _mujoco_rollout(model, SIM_SECONDS)
    _assert_sane(data.qpos, data.qvel, f"{name} MJCF after {SIM_SECONDS} s")
    for j, (lo, hi) in _limited_joints(model):
        for target in (lo, hi):
            data = mujoco.MjData(model)
            data.qpos[model.jnt_qposadr[j]] = target
            mujoco.mj_forward(model, data)
            for _ in range(250):
                mujoco.mj_step(model, data)
            q = data.qpos[model.jnt_qposadr[j]]
            _assert_sane(data.qpos, data.qvel, f"{name} joint {j} at {target:.3f}")
            margin = 0.05 * (hi - lo) + 1e-3
            assert lo - margin <= q <= hi + margin, f"{name} joint {j} left its range: {q:.4f} not in [{lo:.4f}, {hi:.4f}]"


@pytest.mark.parametrize("name", NAMES)
def test_urdf_imports_into_mujoco_fixed_and_stable(exports, name):
    e = exported(exports, name)
    model = mujoco.MjModel.from_xml_path(str(e.out / "model.urdf"))
    assert FREE not in joint_types(model), "the `world` link must fix the root"
    assert model.ngeom > 0, "MuJoCo's URDF import produced no geoms"
    data = _mujoco_rollout(model, SIM_SECONDS)
    _assert_sane(data.qpos, data.qvel, f"{name} URDF in MuJoCo")


@pytest.fixture()
def bullet():
    client = p.connect(p.DIRECT)
    yield client
    p.disconnect(client)


@pytest.mark.parametrize("name", NAMES)
def test_urdf_loads_in_pybullet_settles_and_reaches_limits(exports, name, bullet):
    e = exported(exports, name)
    p.setGravity(0, 0, -9.81, physicsClientId=bullet)
    body = p.loadURDF(str(e.out / "model.urdf"), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=bullet)
    n = p.getNumJoints(body, physicsClientId=bullet)
    movable = [j for j in range(n) if p.getJointInfo(body, j, physicsClientId=bullet)[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC)]
    assert len(movable) == len(e.summary["movable_joints"]), "PyBullet sees a different number of movable joints"
    # Passive: switch off PyBullet's default velocity motors.
    for j in movable:
        p.setJointMotorControl2(body, j, p.VELOCITY_CONTROL, force=0, physicsClientId=bullet)
    for _ in range(int(SIM_SECONDS * 240)):
        p.stepSimulation(physicsClientId=bullet)
    states = p.getJointStates(body, movable, physicsClientId=bullet) if movable else []
    _assert_sane(np.array([s[0] for s in states]), np.array([s[1] for s in states]), f"{name} in PyBullet")
    for j in movable:
        info = p.getJointInfo(body, j, physicsClientId=bullet)
        lo, hi = info[8], info[9]
        if hi <= lo:
            continue
        for target in (lo, hi):
            p.resetJointState(body, j, target, physicsClientId=bullet)
            p.setJointMotorControl2(body, j, p.POSITION_CONTROL, targetPosition=target, force=1e4, physicsClientId=bullet)
            for _ in range(120):
                p.stepSimulation(physicsClientId=bullet)
            q, v = p.getJointState(body, j, physicsClientId=bullet)[:2]
            assert np.isfinite(q) and np.isfinite(v), f"{name} joint {j} not finite at {target}"
            assert abs(q - target) <= 0.05 * (hi - lo) + 1e-3, f"{name} joint {j}: {q:.4f} did not reach {target:.4f}"
            p.setJointMotorControl2(body, j, p.VELOCITY_CONTROL, force=0, physicsClientId=bullet)
