"""`model.usda` opened with `usd-core` (Pixar's USD from PyPI): the UsdPhysics validators find no
error, and the stage holds the record's articulation: one rigid body per part with its mass, a
convex-hull collider on each, one joint per record joint of the matching type between existing
bodies, limits in degrees (revolute) or metres (prismatic), the joint axis, and both joint frames at
the same place at rest. usd-core has no physics engine: stepping the stage needs Isaac Sim."""

import json
import math

import numpy as np
import pytest
from pxr import Gf, Usd, UsdGeom, UsdPhysics, UsdValidation

from conftest import INPUTS, exported

NAMES = [name for name, _ in INPUTS]
VALIDATORS = ("usdPhysicsValidators:", "usdGeomValidators:StageMetadataChecker", "usdValidation:")
JOINT_TYPES = {
    "revolute": UsdPhysics.RevoluteJoint,
    "continuous": UsdPhysics.RevoluteJoint,
    "prismatic": UsdPhysics.PrismaticJoint,
    "fixed": UsdPhysics.FixedJoint,
}


def _validation_errors(stage: Usd.Stage) -> list[str]:
    registry = UsdValidation.ValidationRegistry()
    names = [v.GetMetadata().name for v in registry.GetOrLoadAllValidators()]
    chosen = [registry.GetOrLoadValidatorByName(n) for n in names if n.startswith(VALIDATORS)]
    assert any(v.GetMetadata().name.startswith("usdPhysicsValidators:") for v in chosen), names
    return [f"{e.GetName()}: {e.GetMessage()}" for e in UsdValidation.ValidationContext(chosen).Validate(stage)]


def _joint_frame_in_world(cache: UsdGeom.XformCache, stage: Usd.Stage, body_rel, local_pos, local_rot):
    targets = body_rel.GetTargets()
    to_world = cache.GetLocalToWorldTransform(stage.GetPrimAtPath(targets[0])) if targets else Gf.Matrix4d(1.0)
    position = to_world.Transform(Gf.Vec3d(local_pos))
    rotation = to_world.ExtractRotationQuat() * Gf.Quatd(local_rot)
    return np.array(position), rotation


@pytest.mark.parametrize("name", NAMES)
def test_usd_stage_validates_and_holds_the_records_articulation(exports, name):
    e = exported(exports, name)
    record = json.loads((e.out / "record.json").read_text())
    stage = Usd.Stage.Open(str(e.out / "model.usda"))
    assert stage is not None, f"usd-core cannot open the stage of {name}"
    errors = _validation_errors(stage)
    assert not errors, "\n".join(errors)
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0 and UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0

    bodies = {p.GetName(): p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)}
    assert len(bodies) == len(record["parts"])
    for part in record["parts"]:
        body = next(b for n, b in bodies.items() if n.startswith(f"part_{part['id']}_"))
        mass = UsdPhysics.MassAPI(body).GetMassAttr().Get()
        assert mass == pytest.approx(part["mass"]["mass_kg"]["value"], rel=1e-5)
        colliders = [c for c in body.GetChildren() if c.HasAPI(UsdPhysics.CollisionAPI)]
        assert colliders, f"{body.GetName()} has no collider"
        for c in colliders:
            assert UsdPhysics.MeshCollisionAPI(c).GetApproximationAttr().Get() == "convexHull"
            assert len(UsdGeom.Mesh(c).GetPointsAttr().Get()) >= 4

    # Prim names are identifiers ("8" becomes "_8"); the record's name is kept beside.
    joints = {(p.GetAttribute("uniphys:name").Get() or p.GetName()): p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint)}
    assert len(joints) == len(record["joints"]) + 1, sorted(joints)  # and the root's weld to the world
    cache = UsdGeom.XformCache()
    for j in record["joints"]:
        prim = joints[j["name"]]
        assert prim.IsA(JOINT_TYPES[j["kind"]]), f"{j['name']} is a {prim.GetTypeName()}"
        joint = UsdPhysics.Joint(prim)
        for rel in (joint.GetBody0Rel(), joint.GetBody1Rel()):
            (target,) = rel.GetTargets()
            assert stage.GetPrimAtPath(target).HasAPI(UsdPhysics.RigidBodyAPI), target
        p0, r0 = _joint_frame_in_world(cache, stage, joint.GetBody0Rel(), joint.GetLocalPos0Attr().Get(), joint.GetLocalRot0Attr().Get())
        p1, r1 = _joint_frame_in_world(cache, stage, joint.GetBody1Rel(), joint.GetLocalPos1Attr().Get(), joint.GetLocalRot1Attr().Get())
        assert np.allclose(p0, p1, atol=1e-5), f"{j['name']}: joint frames apart at rest: {p0} {p1}"
        if j["kind"] == "fixed":
            continue
        axis = np.array(r0.Transform(Gf.Vec3d(1.0, 0.0, 0.0)))
        assert np.allclose(axis, np.array(j["axis_in_object"]) / np.linalg.norm(j["axis_in_object"]), atol=1e-5)
        assert np.allclose(np.array(r1.Transform(Gf.Vec3d(1.0, 0.0, 0.0))), axis, atol=1e-5)
        typed = JOINT_TYPES[j["kind"]](prim)
        lower, upper = typed.GetLowerLimitAttr(), typed.GetUpperLimitAttr()
        if j["kind"] == "continuous":
            assert not lower.HasAuthoredValue() and not upper.HasAuthoredValue()
            continue
        scale = 180.0 / math.pi if j["kind"] == "revolute" else 1.0
        assert lower.Get() < upper.Get()
        assert lower.Get() == pytest.approx(j["limits"]["lower"] * scale, abs=1e-4)
        assert upper.Get() == pytest.approx(j["limits"]["upper"] * scale, abs=1e-4)
