"""Real objects in the simulators (issue 17): every shared PartNet-Mobility object, as shipped with
its true joints, through `uniphys run`; then, in MuJoCo, the MJCF at rest for 2 s, each limited
joint set to each of its limits and held there for 0.5 s (it must stay within 5 % of its range),
the colliders of different bodies that overlap at rest (contacts deeper than 1 mm that the export
does not exclude), and for each joint the share of its child's colliders that its parent's also
fill (a carcass collider that fills its drawer's cavity leaves a gripper no room); the URDF
through MuJoCo's importer, at rest for 2 s; in PyBullet, the URDF at rest for 2 s and each joint
set to each limit, motor off, for 0.5 s.

Prints one row per object and a summary. Usage:
  .venv/bin/python bench/real_simulators.py [--data ../shared/data/partnet-mobility] [--only NAME ...]
  [--ignore-joints] (UNIPHYS_BIN names the binary; default target/release/uniphys)
"""

import argparse
import json
import os
import subprocess
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import mujoco
import numpy as np
import pybullet as p

REPO = Path(__file__).resolve().parents[1]
REST_SECS = 2.0
HOLD_SECS = 0.5
HOLD_TOLERANCE = 0.05  # share of the joint's range a held joint may leave it by
OVERLAP_DEPTH_M = 1e-3  # contacts at rest deeper than this are colliders that fight
MAX_SPEED = 50.0  # rad/s or m/s: faster in a passive asset is an explosion
FILLED_SHARE = 0.5  # a parent's colliders filling more of its child than this leave no room for it
# MuJoCo's joint types as plain ints: numpy's int32 does not compare equal to the enum.
MOVABLE_TYPES = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


def run(binary, source, out, extra):
    started = time.time()
    proc = subprocess.run(
        [binary, "run", str(source), "--out", str(out), "--json", "--force", *extra],
        capture_output=True, text=True, timeout=1200,
    )
    return proc.returncode, proc.stderr.strip(), time.time() - started


def mujoco_checks(model_xml):
    model = mujoco.MjModel.from_xml_path(str(model_xml))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    overlaps = set()
    for c in data.contact[: data.ncon]:
        if -c.dist > OVERLAP_DEPTH_M:
            a, b = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
            overlaps.add(tuple(sorted((mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, a) or str(a),
                                       mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or str(b)))))
    filled = cavity_filled(model, data)
    for _ in range(int(round(REST_SECS / model.opt.timestep))):
        mujoco.mj_step(model, data)
    rest_ok = bool(np.all(np.isfinite(data.qvel)) and (len(data.qvel) == 0 or np.max(np.abs(data.qvel)) < MAX_SPEED))
    held, failed = 0, []
    for j in range(model.njnt):
        if int(model.jnt_type[j]) not in MOVABLE_TYPES or not model.jnt_limited[j]:
            continue
        lo, hi = model.jnt_range[j]
        for target in (lo, hi):
            d = mujoco.MjData(model)
            adr = model.jnt_qposadr[j]
            d.qpos[adr] = target
            mujoco.mj_forward(model, d)
            for _ in range(int(round(HOLD_SECS / model.opt.timestep))):
                mujoco.mj_step(model, d)
            q = d.qpos[adr]
            margin = HOLD_TOLERANCE * (hi - lo)
            held += 1
            if not (np.isfinite(q) and lo - margin <= q <= hi + margin):
                name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or str(j)
                failed.append(f"{name}@{target:.3g}->{q:.3g}")
    return rest_ok, held, failed, sorted(overlaps), filled


def _body_hulls(model, data, body):
    """World-frame vertices of each collision mesh geom of `body` (MuJoCo meshes are convex)."""
    hulls = []
    for g in range(model.ngeom):
        if model.geom_bodyid[g] != body or model.geom_contype[g] == 0 or model.geom_dataid[g] < 0:
            continue
        if int(model.geom_type[g]) != int(mujoco.mjtGeom.mjGEOM_MESH):
            continue
        m = model.geom_dataid[g]
        start, count = model.mesh_vertadr[m], model.mesh_vertnum[m]
        local = model.mesh_vert[start:start + count]
        hulls.append(local @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g])
    return hulls


def cavity_filled(model, data):
    """For each movable joint: the share of its child's collider volume that its parent's
    colliders also fill at rest (a carcass drawn as one block where the drawer sits)."""
    from scipy.spatial import Delaunay

    # Each object its own generator: one shared by the two worker threads made the samples,
    # and so the shares, depend on the order the objects finished in.
    rng = np.random.default_rng(0)

    shares = {}
    for j in range(model.njnt):
        if int(model.jnt_type[j]) not in MOVABLE_TYPES:
            continue
        child = model.jnt_bodyid[j]
        parent = model.body_parentid[child]
        child_hulls = [Delaunay(h) for h in _body_hulls(model, data, child) if len(h) >= 4]
        parent_hulls = [Delaunay(h) for h in _body_hulls(model, data, parent) if len(h) >= 4]
        if not child_hulls or not parent_hulls:
            continue
        pts = np.concatenate([h.points for h in child_hulls])
        lo, hi = pts.min(0), pts.max(0)
        samples = lo + rng.random((4000, 3)) * (hi - lo)
        inside = np.zeros(len(samples), bool)
        for h in child_hulls:
            inside |= h.find_simplex(samples) >= 0
        samples = samples[inside]
        if len(samples) < 20:
            continue
        covered = np.zeros(len(samples), bool)
        for h in parent_hulls:
            covered |= h.find_simplex(samples) >= 0
        shares[mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or str(j)] = float(covered.mean())
    return shares


def mujoco_urdf_rests(urdf):
    """MuJoCo's URDF importer: the model loads and rests 2 s without an explosion."""
    model = mujoco.MjModel.from_xml_path(str(urdf))
    data = mujoco.MjData(model)
    for _ in range(int(REST_SECS / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return bool(np.all(np.isfinite(data.qvel)) and (model.nv == 0 or np.abs(data.qvel).max() < MAX_SPEED))


def pybullet_checks(urdf):
    """PyBullet: the URDF at rest for 2 s, then each joint set to each limit with its motor off
    and held 0.5 s; returns (rest ok, joint-limits held, failures)."""
    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        body = p.loadURDF(str(urdf), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        joints = [j for j in range(p.getNumJoints(body, physicsClientId=client))
                  if p.getJointInfo(body, j, physicsClientId=client)[2] in (p.JOINT_REVOLUTE, p.JOINT_PRISMATIC)]
        for j in joints:
            p.setJointMotorControl2(body, j, p.VELOCITY_CONTROL, force=0, physicsClientId=client)
        start = p.saveState(physicsClientId=client)
        for _ in range(int(REST_SECS * 240)):
            p.stepSimulation(physicsClientId=client)
        speeds = [abs(s[1]) for s in p.getJointStates(body, joints, physicsClientId=client)] if joints else [0.0]
        rest_ok = bool(np.all(np.isfinite(speeds)) and max(speeds) < MAX_SPEED)
        held, failed = 0, []
        for j in joints:
            info = p.getJointInfo(body, j, physicsClientId=client)
            lo, hi = info[8], info[9]
            if hi <= lo:
                continue
            for target in (lo, hi):
                p.restoreState(start, physicsClientId=client)
                p.resetJointState(body, j, target, physicsClientId=client)
                for _ in range(int(HOLD_SECS * 240)):
                    p.stepSimulation(physicsClientId=client)
                q = p.getJointState(body, j, physicsClientId=client)[0]
                margin = HOLD_TOLERANCE * (hi - lo)
                held += 1
                if not (np.isfinite(q) and lo - margin <= q <= hi + margin):
                    failed.append(f"{info[1].decode()}@{target:.3g}->{q:.3g}")
        return rest_ok, held, failed
    finally:
        p.disconnect(client)


def one(binary, source, work, extra):
    out = work / source.name
    code, stderr, secs = run(binary, source, out, extra)
    row = {"object": source.name, "exit": code, "secs": secs}
    if code not in (0, 1):
        row["error"] = stderr.splitlines()[-1] if stderr else "no message"
        return row
    try:
        row["mj_rest"], row["held"], row["failed"], row["overlaps"], row["filled"] = mujoco_checks(out / "model.xml")
    except Exception as error:  # a load failure is a result, reported in the row
        row["mj_error"] = str(error).splitlines()[0]
    try:
        row["mj_urdf_rest"] = mujoco_urdf_rests(out / "model.urdf")
    except Exception as error:
        row["mj_urdf_error"] = str(error).splitlines()[0]
    try:
        row["pb_rest"], row["pb_held"], row["pb_failed"] = pybullet_checks(out / "model.urdf")
    except Exception as error:
        row["pb_error"] = str(error).splitlines()[0]
    return row


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=str(REPO.parent / "shared" / "data" / "partnet-mobility"))
    parser.add_argument("--only", nargs="*", default=[])
    parser.add_argument("--ignore-joints", action="store_true", help="articulate with the built-in grounder")
    parser.add_argument("--json", help="also write the rows to this file")
    args = parser.parse_args()
    binary = os.environ.get("UNIPHYS_BIN", str(REPO / "target" / "release" / "uniphys"))
    if not Path(binary).is_file():
        raise SystemExit(f"uniphys binary not found at {binary}; run `cargo build --release --bin uniphys` or set UNIPHYS_BIN")
    data = Path(args.data)
    sources = sorted(d for d in data.iterdir() if (d / "mobility.urdf").is_file()
                     and (not args.only or any(o in d.name for o in args.only)))
    if not sources:
        raise SystemExit(f"no PartNet-Mobility objects under {data}")
    extra = ["--ignore-joints"] if args.ignore_joints else []
    work = Path(tempfile.mkdtemp(prefix="uniphys-realsim-"))
    rows = []
    print(f"{len(sources)} objects, outputs in {work}", flush=True)
    print("| object | exit | s | MuJoCo rest | MuJoCo joints held at limits | overlapping at rest | joints whose parent's colliders fill over half their child | MuJoCo URDF import rest | PyBullet rest | PyBullet joints held at limits |")
    print("|---|---:|---:|---|---|---|---|---|---|---|")
    with ThreadPoolExecutor(max_workers=2) as pool:
        for row in pool.map(lambda s: one(binary, s, work, extra), sources):
            rows.append(row)
            held, failed = row.get("held", 0), row.get("failed", [])
            pb_held, pb_failed = row.get("pb_held", 0), row.get("pb_failed", [])
            filled = sorted(j for j, share in row.get("filled", {}).items() if share > FILLED_SHARE)
            print(f"| {row['object']} | {row['exit']} | {row['secs']:.0f} | "
                  f"{row.get('mj_rest', row.get('mj_error', row.get('error', '-')))} | "
                  f"{held - len(failed)}/{held} {' '.join(failed)} | "
                  f"{len(row.get('overlaps', []))} {' '.join('+'.join(o) for o in row.get('overlaps', [])[:4])} | "
                  f"{len(filled)} {' '.join(filled[:6])} | "
                  f"{row.get('mj_urdf_rest', row.get('mj_urdf_error', '-'))} | "
                  f"{row.get('pb_rest', row.get('pb_error', '-'))} | "
                  f"{pb_held - len(pb_failed)}/{pb_held} {' '.join(pb_failed)} |", flush=True)
    exported = [r for r in rows if r["exit"] in (0, 1)]
    limit_fail = [r for r in exported if r.get("failed")]
    overlap = [r for r in exported if r.get("overlaps")]
    print()
    print("| what | objects |")
    print("|---|---:|")
    print(f"| run | {len(rows)} |")
    print(f"| exported (exit 0 or 1) | {len(exported)} |")
    print(f"| MuJoCo loads and rests 2 s | {sum(1 for r in exported if r.get('mj_rest'))} |")
    print(f"| MuJoCo loads the URDF and it rests 2 s | {sum(1 for r in exported if r.get('mj_urdf_rest'))} |")
    print(f"| PyBullet loads and rests 2 s | {sum(1 for r in exported if r.get('pb_rest'))} |")
    print(f"| a joint leaves its range by over 5 % when held at a limit | {len(limit_fail)} ({100 * len(limit_fail) / max(len(exported), 1):.1f} %) |")
    print(f"| joints x limits held | {sum(r.get('held', 0) - len(r.get('failed', [])) for r in exported)} of {sum(r.get('held', 0) for r in exported)} |")
    print(f"| colliders of two bodies overlap at rest (> 1 mm) | {len(overlap)} |")
    pb_fail = [r for r in exported if r.get("pb_failed")]
    print(f"| PyBullet: a joint leaves its range by over 5 % when set at a limit | {len(pb_fail)} |")
    print(f"| PyBullet: joints x limits held | {sum(r.get('pb_held', 0) - len(r.get('pb_failed', [])) for r in exported)} of {sum(r.get('pb_held', 0) for r in exported)} |")
    filled = [(r["object"], j) for r in exported for j, share in r.get("filled", {}).items() if share > FILLED_SHARE]
    judged = sum(len(r.get("filled", {})) for r in exported)
    print(f"| joints whose parent's colliders fill over half of their child at rest | {len(filled)} of {judged} |")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
