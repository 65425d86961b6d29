"""The objects the simulator checks load (bench/genesis_check.py, bench/sapien_check.py): the
example assets and the shared PartNet-Mobility objects as shipped (true joints), each through
`uniphys run`, and what the checks share: the record's movable joints, the weight a drive lifts,
the table."""

import argparse
import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DEFAULT_DATA = REPO.parent / "shared" / "data" / "partnet-mobility"
REACH_TOLERANCE = 0.05  # share of a joint's range a driven joint may stop short by
MAX_SPEED = 50.0  # rad/s or m/s: faster in a passive asset is an explosion


def arguments() -> argparse.ArgumentParser:
    """The command line every check takes: `--data` (the shared objects' folder) and `--only`."""
    parser = argparse.ArgumentParser()
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA)
    parser.add_argument("--only", nargs="*")
    return parser


def inputs(data: Path, only):
    """(name, source) of the example assets and the shared objects, those naming `only` if given."""
    found = [(p.stem, p) for p in sorted((REPO / "test_data" / "examples").glob("*.glb"))]
    found += [(d.name, d) for d in sorted(data.iterdir()) if (d / "mobility.urdf").is_file()]
    return [(n, p) for n, p in found if not only or any(o in n for o in only)]


def run_uniphys(source: Path, out: Path):
    """The record of `uniphys run` on `source` into `out`, or the end of its error."""
    binary = os.environ.get("UNIPHYS_BIN", str(REPO / "target" / "release" / "uniphys"))
    run = subprocess.run([binary, "run", str(source), "--out", str(out), "--force"],
                         capture_output=True, text=True, timeout=1200)
    if run.returncode not in (0, 1) or not (out / "record.json").is_file():
        return None, f"uniphys run failed: {run.stderr.strip()[-200:]}"
    return json.loads((out / "record.json").read_text()), None


def movable_dofs(record) -> int:
    return sum(1 for j in record["joints"] if j["kind"] in ("revolute", "prismatic", "continuous"))


def limited_joints(record):
    return [j for j in record["joints"] if j["kind"] in ("revolute", "prismatic") and j.get("limits")]


def moving_mass_kg(record, child) -> float:
    """Mass of part `child` and every part jointed below it."""
    mass = {p["id"]: p["mass"]["mass_kg"]["value"] for p in record["parts"]}
    below = [child]
    for part in below:
        below += [j["child"] for j in record["joints"] if j["parent"] == part]
    return sum(mass.get(p, 0.0) for p in below)


def drive_stiffness(mass_kg: float, span: float, floor: float) -> float:
    """Stiff enough that the moving parts' weight (at a lever of 1 m for a turn) sags a driven joint
    by a twentieth of the tolerance, and at least `floor`."""
    return max(floor, 20.0 * mass_kg * 9.81 / (REACH_TOLERANCE * max(span, 1e-9)))


def check_each(data: Path, only, check, tag: str):
    """Rows of (name, two counts, seconds, outcome): `check(out, record)` on each object's export,
    returning its two counts and its problems; a failed run or a loader's error is a finding of its
    row, not the end of the table."""
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for name, source in inputs(data, only):
            out = Path(scratch) / name
            record, error = run_uniphys(source, out)
            started = time.time()
            if record is None:
                first, second, problems = "-", "-", [error]
            else:
                try:
                    first, second, problems = check(out, record)
                except Exception as failure:
                    first, second, problems = "-", "-", [f"{type(failure).__name__}: {failure}"[:200]]
            rows.append((name, first, second, time.time() - started, "; ".join(problems[:3]) or "ok"))
            print(f"{tag}: {name}: {rows[-1][-1]}", flush=True)
    return rows


def print_table(title: str, columns, rows, verdict: str):
    """Rows of (name, two counts, seconds, outcome) under `columns` (the counts' headings)."""
    print(f"\n### {title}\n")
    print(f"| object | {columns[0]} | {columns[1]} | s | outcome |")
    print("|---|---:|---:|---:|---|")
    for name, first, second, secs, outcome in rows:
        print(f"| {name} | {first} | {second} | {secs:.1f} | {outcome} |")
    good = sum(1 for r in rows if r[-1] == "ok")
    print(f"\n{good} of {len(rows)} {verdict}.")
