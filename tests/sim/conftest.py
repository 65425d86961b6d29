"""Shared fixtures: run `uniphys run` on every example asset, on every URDF with movable joints in
PyBullet's data folder, and on a few real PartNet-Mobility objects of the shared set with their
joints ignored (so the built-in grounder articulates them from geometry), once per session, two at
a time."""

import glob
import json
import os
import re
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pybullet_data
import pytest

# MuJoCo renders offscreen through EGL (Mesa's software driver on a machine without a GPU); it
# picks its GL backend when first imported, so this is set before any test imports it.
os.environ.setdefault("MUJOCO_GL", "egl")

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((REPO / "test_data" / "examples").glob("*.glb"))
# Real objects beside the repository (never copied into it); run with `--ignore-joints`, so what
# the simulators load are the joints the grounder found: a cabinet (door and drawer), an oven
# (drawer and eight knobs), a laptop, a bottle with its cap, a cart with four wheels, a table with
# three drawers.
PARTNET = REPO.parent / "shared" / "data" / "partnet-mobility"
# kitchen-100162: a box whose lid is one open sheet (MuJoCo's URDF importer refused its visual mesh).
PARTNET_OBJECTS = ["kitchen-46236", "kitchen-101921", "gensim2-11248", "kitchen-3614", "kitchen-100491", "kitchen-26387",
                   "kitchen-100162"]
MOVABLE = re.compile(r'<joint[^>]*type\s*=\s*"(revolute|prismatic|continuous)"')


def uniphys_bin() -> str:
    binary = os.environ.get("UNIPHYS_BIN", str(REPO / "target" / "debug" / "uniphys"))
    if not Path(binary).is_file():
        pytest.fail(f"uniphys binary not found at {binary}; build it with `cargo build --bin uniphys` or set UNIPHYS_BIN")
    return binary


def pybullet_urdfs():
    root = Path(pybullet_data.getDataPath())
    found = []
    for path in sorted(glob.glob(str(root / "**" / "*.urdf"), recursive=True)):
        text = Path(path).read_text(errors="replace")
        if MOVABLE.search(text):
            found.append(Path(path))
    return root, found


@dataclass
class Export:
    """The outcome of `uniphys run` on one input."""

    name: str
    source: Path
    out: Path
    returncode: int
    stderr: str
    summary: dict

    @property
    def exported(self) -> bool:
        # 0: exported and all checks passed; 1: exported, some checks failed; 2: rejected.
        return self.returncode in (0, 1)


def _run(binary: str, source: Path, out: Path, extra: list[str]) -> tuple[int, str, dict]:
    proc = subprocess.run(
        [binary, "run", str(source), "--out", str(out), "--json", *extra],
        capture_output=True,
        text=True,
        timeout=600,
    )
    summary = json.loads(proc.stdout) if proc.stdout.strip().startswith("{") else {}
    return proc.returncode, proc.stderr, summary


def _inputs():
    items = [(f"example/{p.stem}", p) for p in EXAMPLES]
    root, urdfs = pybullet_urdfs()
    items += [(f"pybullet/{p.relative_to(root).with_suffix('')}", p) for p in urdfs]
    items += [(f"partnet/{name}", PARTNET / name) for name in PARTNET_OBJECTS]
    return items


INPUTS = _inputs()


@pytest.fixture(scope="session")
def exports() -> dict[str, Export]:
    binary = uniphys_bin()
    work = Path(tempfile.mkdtemp(prefix="uniphys-sim-"))

    def one(item):
        name, source = item
        out = work / name.replace("/", "__")
        if name.startswith("partnet/") and not (source / "mobility.urdf").is_file():
            return name, Export(name, source, out, 2, f"the shared PartNet-Mobility object {source} is missing: these checks need ../shared/data/partnet-mobility beside the repository", {})
        extra = ["--ignore-joints"] if name.startswith("partnet/") else []
        code, stderr, summary = _run(binary, source, out, extra)
        return name, Export(name, source, out, code, stderr, summary)

    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(pool.map(one, INPUTS))


def exported(exports: dict[str, Export], name: str) -> Export:
    """The export of `name`; examples and real objects must be exported, PyBullet's URDFs are
    skipped if rejected."""
    e = exports[name]
    if not e.exported:
        if name.startswith(("example/", "partnet/")):
            pytest.fail(f"uniphys rejected the example {name}: {e.stderr.strip()}")
        pytest.skip(f"ingest does not accept {e.source.name}: {e.stderr.strip().splitlines()[-1] if e.stderr.strip() else e.returncode}")
    return e
