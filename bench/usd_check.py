"""Our USD stages checked with usd-core (issue 21; Pixar's USD from PyPI, no physics engine: Isaac
Sim is not here): the example assets and the shared PartNet-Mobility objects as shipped (true
joints), through `uniphys run` (bench/sim_objects.py); then `model.usda` opened, its UsdPhysics,
shading, geometry and metadata validators run, and its rigid bodies, masses, colliders, joints and
limits held against the record: one body per part with the record's mass (positive), a convex-hull
collider on each, one joint per record joint between existing bodies, ordered limits, and the
pairs `report.json` says touch at rest filtered (`PhysicsFilteredPairsAPI`).

Usage: .venv/bin/python bench/usd_check.py [--data ../shared/data/partnet-mobility] [--only NAME ...]
(UNIPHYS_BIN names the binary; default target/release/uniphys)
"""

import json
import math
from pathlib import Path

from pxr import Usd, UsdPhysics, UsdValidation

from sim_objects import arguments, check_each, movable_dofs, print_table

VALIDATORS = ("usdPhysicsValidators:", "usdShadeValidators:", "usdGeomValidators:", "usdValidation:")


def validators():
    registry = UsdValidation.ValidationRegistry()
    names = [v.GetMetadata().name for v in registry.GetOrLoadAllValidators()]
    return [registry.GetOrLoadValidatorByName(n) for n in names if n.startswith(VALIDATORS)]


def check(out: Path, record, chosen):
    stage = Usd.Stage.Open(str(out / "model.usda"))
    errors = UsdValidation.ValidationContext(chosen).Validate(stage)
    problems = [f"{e.GetName()}: {e.GetMessage()}"[:160] for e in errors]
    bodies = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.RigidBodyAPI)]
    if len(bodies) != len(record["parts"]):
        problems.append(f"{len(bodies)} bodies for {len(record['parts'])} parts")
    for part in record["parts"]:
        body = next((b for b in bodies if b.GetName().startswith(f"part_{part['id']}_")), None)
        if body is None:
            problems.append(f"no body for part {part['id']}")
            continue
        mass = UsdPhysics.MassAPI(body).GetMassAttr().Get()
        if not mass > 0 or not math.isclose(mass, part["mass"]["mass_kg"]["value"], rel_tol=1e-5):
            problems.append(f"part {part['id']} mass {mass}")
        if not any(c.HasAPI(UsdPhysics.CollisionAPI) for c in body.GetChildren()):
            problems.append(f"part {part['id']} has no collider")
    joints = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint)]
    if len(joints) != len(record["joints"]) + 1:  # and the root's weld to the world
        problems.append(f"{len(joints)} joints for {len(record['joints'])} record joints and the weld")
    movable = 0
    for prim in joints:
        joint = UsdPhysics.Joint(prim)
        for rel in (joint.GetBody0Rel(), joint.GetBody1Rel()):
            for target in rel.GetTargets():
                if not stage.GetPrimAtPath(target).HasAPI(UsdPhysics.RigidBodyAPI):
                    problems.append(f"{prim.GetName()} names {target}, no body")
        for typed in (UsdPhysics.RevoluteJoint, UsdPhysics.PrismaticJoint):
            if prim.IsA(typed):
                movable += 1
                lower, upper = typed(prim).GetLowerLimitAttr(), typed(prim).GetUpperLimitAttr()
                if lower.HasAuthoredValue() and not lower.Get() < upper.Get():
                    problems.append(f"{prim.GetName()} limits out of order")
    if movable != movable_dofs(record):
        problems.append(f"{movable} movable joints for {movable_dofs(record)}")
    filtered = {frozenset((b.GetName(), stage.GetPrimAtPath(t).GetName()))
                for b in bodies if b.HasAPI(UsdPhysics.FilteredPairsAPI)
                for t in UsdPhysics.FilteredPairsAPI(b).GetFilteredPairsRel().GetTargets()}
    touching = {frozenset(x["links"]) for x in json.loads((out / "report.json").read_text())["contact_excludes"]
                if x["why"] == "touch at rest"}
    if filtered != touching:
        problems.append(f"{len(filtered)} filtered pairs for {len(touching)} touching at rest")
    return f"{len(bodies)} / {len(record['parts'])}", f"{movable} / {movable_dofs(record)}", problems


def main():
    parser = arguments()
    args = parser.parse_args()
    chosen = validators()
    rows = check_each(args.data, args.only, lambda out, record: check(out, record, chosen), "usd_check")
    print_table("USD (usd-core validators and the record)", ("bodies / parts", "movable joints / record's"),
                rows, "stages validate and hold the record's articulation")


if __name__ == "__main__":
    main()
