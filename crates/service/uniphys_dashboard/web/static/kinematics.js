/**
 * The kinematic tree of record.json: where every part is for given joint positions.
 *
 * All geometry and joint data are in the object frame at rest (q = 0). A joint's motion M(q) is
 * a rigid transform of that frame: a rotation by q (radians, right-handed about the axis) about
 * the axis through the pivot for revolute and continuous joints, a translation by q metres along
 * the axis for prismatic ones, none for fixed ones. Motions compose down the tree: a part that
 * is the child of joint J sits at pose(J.parent) · M_J(q_J), so a drawer's handle follows the
 * drawer, and a part listed in J's `coupled_parts` (and child of no joint) rides with J's child.
 * The root, and any part no joint attaches, stays put.
 */

import { Matrix4, Vector3 } from 'three';

const TAU = 2 * Math.PI;

export class KinematicTree {
  /** @param {object} record record.json: `parts[].id`, `root` and `joints`. */
  constructor(record) {
    this.partIds = record.parts.map((p) => p.id);
    this.joints = record.joints.map((j) => ({
      name: j.name,
      kind: j.kind,
      parent: j.parent,
      child: j.child,
      coupled: j.coupled_parts ?? [],
      axis: new Vector3(...j.axis_in_object).normalize(),
      pivot: new Vector3(...j.pivot_in_object_m),
      limits: j.limits ?? null,
    }));
    /** Part id → `{joint}` (it is that joint's child) or `{follows: part id}` (coupled). */
    this.attachment = new Map();
    for (const joint of this.joints) {
      if (joint.child !== record.root && !this.attachment.has(joint.child)) {
        this.attachment.set(joint.child, { joint });
      }
    }
    for (const joint of this.joints) {
      for (const part of joint.coupled) {
        if (part !== record.root && part !== joint.child && !this.attachment.has(part)) {
          this.attachment.set(part, { follows: joint.child });
        }
      }
    }
  }

  /** The joints with a degree of freedom. */
  get movable() {
    return this.joints.filter((j) => j.kind !== 'fixed');
  }

  /**
   * A joint's position `tS` seconds into an animation of period `periodS`: a smooth sweep from
   * the lower limit to the upper one and back, or full turns for a continuous joint.
   */
  positionAt(joint, tS, periodS) {
    const phase = (TAU * tS) / periodS;
    if (joint.kind === 'continuous') return phase % TAU;
    if (joint.kind === 'fixed' || !joint.limits) return 0;
    const { lower, upper } = joint.limits;
    return lower + (upper - lower) * (0.5 - 0.5 * Math.cos(phase));
  }

  /** M(q) of `joint`, written into `out`. */
  motion(joint, q, out = new Matrix4()) {
    const { axis, pivot } = joint;
    switch (joint.kind) {
      case 'prismatic':
        return out.makeTranslation(axis.x * q, axis.y * q, axis.z * q);
      case 'revolute':
      case 'continuous': {
        // Translate the pivot to the origin, rotate, translate back.
        const toPivot = new Matrix4().makeTranslation(pivot.x, pivot.y, pivot.z);
        const rotate = new Matrix4().makeRotationAxis(axis, q);
        const fromPivot = new Matrix4().makeTranslation(-pivot.x, -pivot.y, -pivot.z);
        return out.copy(toPivot).multiply(rotate).multiply(fromPivot);
      }
      default:
        return out.identity();
    }
  }

  /**
   * The pose of every part (a transform of the object frame) for joint positions `q`, a Map of
   * joint name → position (missing: 0, the rest pose). A cycle in a broken record leaves the
   * part where the cycle closes at rest instead of recursing forever.
   */
  poses(q) {
    const poses = new Map();
    const visiting = new Set();
    const poseOf = (id) => {
      if (poses.has(id)) return poses.get(id);
      if (visiting.has(id)) return new Matrix4();
      visiting.add(id);
      const attachment = this.attachment.get(id);
      let pose;
      if (attachment?.joint) {
        const { joint } = attachment;
        pose = poseOf(joint.parent).clone().multiply(this.motion(joint, q.get(joint.name) ?? 0));
      } else if (attachment) {
        pose = poseOf(attachment.follows).clone();
      } else {
        pose = new Matrix4();
      }
      visiting.delete(id);
      poses.set(id, pose);
      return pose;
    };
    for (const id of this.partIds) poseOf(id);
    return poses;
  }
}
