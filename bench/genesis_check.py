"""Our exports in Genesis (issue 21): the example assets and the shared PartNet-Mobility objects as
shipped (true joints), through `uniphys run`; then Genesis (genesis-world from PyPI, on its CPU
backend: no GPU here) loads the MJCF, or the URDF with the root fixed, and for each object:

- its degrees of freedom against the record's movable joints (one each);
- 1 s at rest: every joint speed under 50 rad/s or m/s and every position finite;
- each limited joint driven by Genesis's position control to each of its limits for 1 s: reached
  when within 5 % of its range.

Genesis compiles its kernels on first use (minutes; later scenes reuse them). Prints one row per
object and a summary. Usage, in a venv with genesis-world and torch (scripts/bench makes one):
  python bench/genesis_check.py [--format mjcf|urdf] [--data ../shared/data/partnet-mobility]
  [--only NAME ...] (UNIPHYS_BIN names the binary; default target/release/uniphys)
"""

import argparse
import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
DT_SECS = 0.002
REST_SECS = 1.0
DRIVE_SECS = 1.0
REACH_TOLERANCE = 0.05  # share of a joint's range a driven joint may stop short by
MAX_SPEED = 50.0
# Position control of a driven joint: stiff enough to carry a part of a few kilograms against
# gravity to its limit within the drive time, and damped.
KP = 2000.0
KV = 100.0
FORCE_MAX = 1000.0


def inputs(data: Path, only):
    found = [(p.stem, p) for p in sorted((REPO / "test_data" / "examples").glob("*.glb"))]
    found += [(d.name, d) for d in sorted(data.iterdir()) if (d / "mobility.urdf").is_file()]
    return [(n, p) for n, p in found if not only or any(o in n for o in only)]


def movable_dofs(record) -> int:
    return sum(1 for j in record["joints"] if j["kind"] in ("revolute", "prismatic", "continuous"))


def moving_mass_kg(record, child) -> float:
    """Mass of part `child` and every part jointed below it."""
    mass = {p["id"]: p["mass"]["mass_kg"]["value"] for p in record["parts"]}
    below = [child]
    for part in below:
        below += [j["child"] for j in record["joints"] if j["parent"] == part]
    return sum(mass.get(p, 0.0) for p in below)


def check(gs, out: Path, fmt: str):
    record = json.loads((out / "record.json").read_text())
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
    limited = [j for j in record["joints"] if j["kind"] in ("revolute", "prismatic") and j.get("limits")]
    reached = 0
    names = {j.name: j for j in entity.joints}
    for joint in limited:
        gj = names.get(joint["name"])
        if gj is None:
            problems.append(f"joint {joint['name']} missing")
            continue
        dof = gj.dofs_idx_local[0]
        lower, upper = joint["limits"]["lower"], joint["limits"]["upper"]
        span = max(upper - lower, 1e-9)
        ok = True
        # Stiff enough that the moving parts' weight (at a lever of 1 m for a turn) sags the
        # joint by a twentieth of the tolerance, and critically damped for that mass.
        mass_kg = moving_mass_kg(record, joint["child"])
        kp = max(KP, 20.0 * mass_kg * 9.81 / (REACH_TOLERANCE * span))
        kv = max(KV, 2.0 * np.sqrt(kp * mass_kg))
        entity.set_dofs_kp(np.array([kp]), [dof])
        entity.set_dofs_kv(np.array([kv]), [dof])
        entity.set_dofs_force_range(np.array([-FORCE_MAX]), np.array([FORCE_MAX]), [dof])
        for target in (lower, upper):
            entity.control_dofs_position(np.array([target]), [dof])
            for _ in range(int(DRIVE_SECS / DT_SECS)):
                scene.step()
            at = float(entity.get_dofs_position([dof]).cpu().numpy()[0])
            ok &= abs(at - target) <= REACH_TOLERANCE * span
            if abs(at - target) > REACH_TOLERANCE * span:
                problems.append(f"{joint['name']} at {at:.3g} driven to {target:.3g}")
        reached += ok
    if reached < len(limited):
        problems.append(f"{len(limited) - reached} of {len(limited)} limited joints short of a limit")
    return entity.n_dofs, want, reached, len(limited), problems


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--format", choices=["mjcf", "urdf"], default="mjcf")
    parser.add_argument("--data", type=Path, default=REPO.parent / "shared" / "data" / "partnet-mobility")
    parser.add_argument("--only", nargs="*")
    args = parser.parse_args()
    binary = os.environ.get("UNIPHYS_BIN", str(REPO / "target" / "release" / "uniphys"))
    import genesis as gs

    gs.init(backend=gs.cpu, logging_level="warning")
    rows, failed = [], 0
    with tempfile.TemporaryDirectory() as scratch:
        for name, source in inputs(args.data, args.only):
            out = Path(scratch) / name
            run = subprocess.run([binary, "run", str(source), "--out", str(out), "--force"],
                                 capture_output=True, text=True, timeout=1200)
            if run.returncode not in (0, 1) or not (out / "record.json").is_file():
                rows.append((name, "-", "-", "-", 0.0, f"uniphys run failed: {run.stderr.strip()[-200:]}"))
                failed += 1
                continue
            started = time.time()
            try:
                dofs, want, reached, limited, problems = check(gs, out, args.format)
            except Exception as error:  # a loader error is a finding, not the end of the table
                dofs, want, reached, limited, problems = "-", "-", 0, "-", [f"{type(error).__name__}: {error}"[:200]]
            failed += bool(problems)
            rows.append((name, f"{dofs} / {want}", f"{reached} / {limited}", "", time.time() - started,
                         "; ".join(problems) or "ok"))
            print(f"genesis_check: {name}: {rows[-1][-1]}", flush=True)
    print(f"\n### Genesis ({args.format.upper()}, CPU backend)\n")
    print("| object | dofs / movable joints | limited joints reaching both limits | s | outcome |")
    print("|---|---:|---:|---:|---|")
    for name, dofs, reached, _, secs, outcome in rows:
        print(f"| {name} | {dofs} | {reached} | {secs:.1f} | {outcome} |")
    print(f"\n{len(rows) - failed} of {len(rows)} objects load, rest and reach their limits in Genesis.")


if __name__ == "__main__":
    main()
