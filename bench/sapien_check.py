"""Our URDFs in SAPIEN (issue 21; PartNet-Mobility's own simulator, sapien from PyPI, PhysX's CPU
system): the example assets and the shared PartNet-Mobility objects as shipped (true joints),
through `uniphys run` (bench/sim_objects.py), then, as tests/sim/test_sapien.py does for a few:
loaded with the root fixed (a copy without `<visual>` elements: SAPIEN builds render materials for
visuals, which needs a GPU this machine lacks; bodies, inertia, colliders and joints are the same;
`model.srdf` turns off the contacts of parts touching at rest without a joint),
its degrees of freedom against the record's movable joints, 2 s at rest, and each limited joint
driven from rest to each of its limits for 2 s (within 5 % of its range).

Usage: .venv/bin/python bench/sapien_check.py [--data ../shared/data/partnet-mobility] [--only NAME ...]
(UNIPHYS_BIN names the binary; default target/release/uniphys)
"""

import re
from pathlib import Path

import numpy as np
import sapien

from sim_objects import (MAX_SPEED, REACH_TOLERANCE, arguments, check_each, drive_stiffness,
                         limited_joints, movable_dofs, moving_mass_kg, print_table)

STEP_S = 1.0 / 240.0
REST_SECS = 2.0
DRIVE_SECS = 2.0
STIFFNESS_MIN = 1e4
DAMPING_MIN = 1e2


def check(out: Path, record):
    physics = out / "model_sapien.urdf"
    physics.write_text(re.sub(r"<visual\b.*?</visual>", "", (out / "model.urdf").read_text(), flags=re.S))
    scene = sapien.Scene([sapien.physx.PhysxCpuSystem()])
    scene.set_timestep(STEP_S)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    robot = loader.load(str(physics), srdf_file=str(out / "model.srdf"))
    want = movable_dofs(record)
    problems = []
    if robot.dof != want:
        problems.append(f"{robot.dof} dofs for {want} movable joints")
    for _ in range(int(REST_SECS / STEP_S)):
        scene.step()
    q, v = robot.get_qpos(), robot.get_qvel()
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v)) and np.all(np.abs(v) < MAX_SPEED)):
        problems.append("not at rest")
    rest = robot.get_qpos()
    by_name = {j.name: (k, j) for k, j in enumerate(robot.get_active_joints())}
    limited = limited_joints(record)
    reached = 0
    for joint in limited:
        if joint["name"] not in by_name:
            problems.append(f"joint {joint['name']} missing")
            continue
        k, active = by_name[joint["name"]]
        robot.set_qpos(rest)
        robot.set_qvel(np.zeros_like(rest))
        lower, upper = joint["limits"]["lower"], joint["limits"]["upper"]
        span = max(upper - lower, 1e-9)
        mass_kg = moving_mass_kg(record, joint["child"])
        stiffness = drive_stiffness(mass_kg, span, STIFFNESS_MIN)
        active.set_drive_properties(stiffness=stiffness,
                                    damping=max(DAMPING_MIN, 2.0 * np.sqrt(stiffness * mass_kg)))
        ok = True
        for target in (lower, upper):
            active.set_drive_target(target)
            for _ in range(int(DRIVE_SECS / STEP_S)):
                scene.step()
            at = float(robot.get_qpos()[k])
            if not np.isfinite(at) or abs(at - target) > REACH_TOLERANCE * span:
                ok = False
                problems.append(f"{joint['name']} at {at:.3g} driven to {target:.3g}")
        active.set_drive_properties(stiffness=0.0, damping=0.0)
        reached += ok
    return f"{robot.dof} / {want}", f"{reached} / {len(limited)}", problems


def main():
    parser = arguments()
    args = parser.parse_args()
    rows = check_each(args.data, args.only, check, "sapien_check")
    print_table("SAPIEN (URDF, PhysX CPU)", ("dofs / movable joints", "limited joints reaching both limits"),
                rows, "objects load, rest and reach their limits in SAPIEN")


if __name__ == "__main__":
    main()
