"""Our exports in Genesis (issue 21): the example assets and the shared PartNet-Mobility objects as
shipped (true joints), through `uniphys run` (bench/sim_objects.py); then Genesis (genesis-world
from PyPI, on its CPU backend: no GPU here) loads the MJCF, or the URDF with the root fixed, and
for each object:

- its degrees of freedom against the record's movable joints (one each);
- 1 s at rest: every joint speed under 50 rad/s or m/s and every position finite;
- each limited joint driven by Genesis's position control from rest (the others at rest and
  undriven) to each of its limits for 1 s: reached when within 5 % of its range.

Genesis compiles its kernels on first use (minutes; later scenes reuse them). Prints one row per
object and a summary. Usage, in a venv with genesis-world and torch (scripts/bench makes one):
  python bench/genesis_check.py [--format mjcf|urdf] [--data ../shared/data/partnet-mobility]
  [--only NAME ...] (UNIPHYS_BIN names the binary; default target/release/uniphys)
"""

from pathlib import Path

import numpy as np

from sim_objects import (MAX_SPEED, REACH_TOLERANCE, arguments, check_each, drive_stiffness,
                         limited_joints, movable_dofs, moving_mass_kg, print_table)

DT_SECS = 0.002
REST_SECS = 1.0
DRIVE_SECS = 1.0
KP_MIN = 2000.0
KV_MIN = 100.0
FORCE_MAX = 1000.0


def check(gs, out: Path, record, fmt: str):
    scene = gs.Scene(show_viewer=False, sim_options=gs.options.SimOptions(dt=DT_SECS))
    if fmt == "mjcf":
        entity = scene.add_entity(gs.morphs.MJCF(file=str(out / "model.xml")))
    else:
        entity = scene.add_entity(gs.morphs.URDF(file=str(out / "model.urdf"), fixed=True))
    scene.build()
    want = movable_dofs(record)
    problems = []
    if entity.n_dofs != want:
        problems.append(f"{entity.n_dofs} dofs for {want} movable joints")
    fastest = 0.0
    for _ in range(int(REST_SECS / DT_SECS)):
        scene.step()
        speed = np.abs(entity.get_dofs_velocity().cpu().numpy())
        fastest = max(fastest, float(speed.max()) if speed.size else 0.0)
    if not np.isfinite(entity.get_qpos().cpu().numpy()).all() or fastest > MAX_SPEED:
        problems.append(f"not at rest (fastest joint {fastest:.3g})")
    limited = limited_joints(record)
    reached = 0
    rest = entity.get_dofs_position()
    by_name = {j.name: j for j in entity.joints}
    for joint in limited:
        found = by_name.get(joint["name"])
        if found is None:
            problems.append(f"joint {joint['name']} missing")
            continue
        dof = found.dofs_idx_local[0]
        lower, upper = joint["limits"]["lower"], joint["limits"]["upper"]
        span = max(upper - lower, 1e-9)
        mass_kg = moving_mass_kg(record, joint["child"])
        kp = drive_stiffness(mass_kg, span, KP_MIN)
        entity.set_dofs_kp(np.array([kp]), [dof])
        entity.set_dofs_kv(np.array([max(KV_MIN, 2.0 * np.sqrt(kp * mass_kg))]), [dof])
        entity.set_dofs_force_range(np.array([-FORCE_MAX]), np.array([FORCE_MAX]), [dof])
        entity.set_dofs_position(rest)
        entity.zero_all_dofs_velocity()
        ok = True
        for target in (lower, upper):
            entity.control_dofs_position(np.array([target]), [dof])
            for _ in range(int(DRIVE_SECS / DT_SECS)):
                scene.step()
            at = float(entity.get_dofs_position([dof]).cpu().numpy()[0])
            if abs(at - target) > REACH_TOLERANCE * span:
                ok = False
                problems.append(f"{joint['name']} at {at:.3g} driven to {target:.3g}")
        entity.control_dofs_force(np.array([0.0]), [dof])
        reached += ok
    return f"{entity.n_dofs} / {want}", f"{reached} / {len(limited)}", problems


def main():
    parser = arguments()
    parser.add_argument("--format", choices=["mjcf", "urdf"], default="mjcf")
    args = parser.parse_args()
    import genesis as gs

    gs.init(backend=gs.cpu, logging_level="warning")
    rows = check_each(args.data, args.only,
                      lambda out, record: check(gs, out, record, args.format), "genesis_check")
    print_table(f"Genesis ({args.format.upper()}, CPU backend)",
                ("dofs / movable joints", "limited joints reaching both limits"), rows,
                "objects load, rest and reach their limits in Genesis")


if __name__ == "__main__":
    main()
