//! The articulation of an asset: the declared joints of an articulated input, completed, or the
//! geometric heuristic's joints for an input without any.

use std::collections::BTreeSet;

use uniphys_geometry::{Aabb, ContactParams, DVec3, DistanceProbe, TriMesh, contact_region};
use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};

use uniphys_verify::Scene;

use crate::dynamics::{RigidMass, holding_friction, joint_dynamics, max_stable_damping};
use crate::hypotheses::{SCREEN_SAMPLES, Subject, best_joint};
use crate::joint_geometry::{hinge, slide};
use crate::roles::{Role, role_of};
use crate::unnamed::unnamed_joints;
use crate::{BUILTIN_PROVIDER, GroundError, GroundResult};

/// What the articulation step needs to know about a part.
#[derive(Debug, Clone, Copy)]
pub struct PartInput<'a> {
    /// Part name.
    pub name: &'a str,
    /// Mesh in the object frame.
    pub mesh: &'a TriMesh,
    /// Solid volume, m^3.
    pub volume_m3: f64,
    /// Mass properties in the object frame.
    pub mass: RigidMass,
    /// Convex colliders (closed hulls) in the object frame: the sweeps that choose joints
    /// measure interpenetration on them.
    pub colliders: &'a [TriMesh],
}

/// The articulation tree: a root fixed to the world and one joint per other part.
#[derive(Debug, Clone, PartialEq)]
pub struct Articulation {
    /// The part fixed to the world.
    pub root: PartId,
    /// One joint per non-root part, sorted by child id.
    pub joints: Vec<Joint>,
    /// What was completed or assumed, for the report.
    pub notes: Vec<String>,
}

/// The id of the part at index `i`.
pub(crate) fn pid(i: usize) -> PartId {
    PartId(u32::try_from(i).unwrap_or(u32::MAX))
}

/// Builds the articulation. With `declared` joints (an articulated input) they are kept and
/// completed. Without, when no part name says that it slides or turns (`link_0`, `Mesh.002`,
/// `handle`), the tree comes
/// from size and contact and each joint from the part's shape and sweeps of its candidate
/// motions (see `unnamed`); otherwise part names say which parts slide or turn, and for each of
/// them the joint is chosen among hypotheses from the contact geometry by sweeping them (see
/// `hypotheses`).
pub fn articulate(parts: &[PartInput<'_>], declared: &[Joint]) -> GroundResult<Articulation> {
    if parts.is_empty() {
        return Err(GroundError::NoParts);
    }
    // Without a name that says a part slides or turns, geometry alone decides.
    let unnamed = parts.len() > 1
        && parts
            .iter()
            .all(|p| !matches!(role_of(p.name).0, Role::Sliding | Role::Hinged));
    let (root, mut joints, mut notes) = if declared.is_empty() && unnamed {
        unnamed_joints(parts).unwrap_or_else(|e| {
            let (root, joints, mut notes) = heuristic_joints(parts);
            notes.push(format!("articulation sweeps unavailable: {e}"));
            (root, joints, notes)
        })
    } else if declared.is_empty() {
        heuristic_joints(parts)
    } else {
        complete_declared(parts, declared)?
    };
    finish_joints(parts, &mut joints, &mut notes);
    joints.sort_by_key(|j| j.child);
    Ok(Articulation {
        root,
        joints,
        notes,
    })
}

fn complete_declared(
    parts: &[PartInput<'_>],
    declared: &[Joint],
) -> GroundResult<(PartId, Vec<Joint>, Vec<String>)> {
    let n = parts.len();
    let mut notes = Vec::new();
    let mut joints: Vec<Joint> = Vec::new();
    let mut has_parent = vec![false; n];
    for joint in declared {
        for part in [joint.parent, joint.child] {
            if part.0 as usize >= n {
                return Err(GroundError::JointReferencesMissingPart {
                    joint: joint.name.clone(),
                    part,
                });
            }
        }
        let child = joint.child.0 as usize;
        if has_parent[child] {
            return Err(GroundError::TwoParents { part: joint.child });
        }
        has_parent[child] = true;
        let mut joint = joint.clone();
        if joint.kind.needs_limits() && joint.limits.is_none() {
            let limits = if joint.kind == JointKind::Revolute {
                JointLimits {
                    lower: -std::f64::consts::PI,
                    upper: std::f64::consts::PI,
                }
            } else {
                let extent = parts[child]
                    .mesh
                    .bounds()
                    .extents()
                    .dot(DVec3::from_array(joint.axis_in_object).abs());
                JointLimits {
                    lower: 0.0,
                    upper: extent.max(1e-3),
                }
            };
            notes.push(format!(
                "joint {:?} had no limits; defaulted to [{:.4}, {:.4}]",
                joint.name, limits.lower, limits.upper
            ));
            joint.limits = Some(limits);
        }
        joints.push(joint);
    }
    // Every part without a parent is a root; keep the one with the most descendants and fix the
    // others to it (an articulated input made of several disconnected trees).
    let roots: Vec<usize> = (0..n).filter(|&i| !has_parent[i]).collect();
    let subtree_size = |r: usize| descendants(&joints, pid(r)).len();
    let root = roots
        .iter()
        .copied()
        .max_by_key(|&r| (subtree_size(r), std::cmp::Reverse(r)))
        .ok_or(GroundError::NoRoot)?;
    for other in roots.into_iter().filter(|&r| r != root) {
        notes.push(format!(
            "part {:?} was not connected to the root; fixed to it",
            parts[other].name
        ));
        joints.push(fixed_joint(
            pid(root),
            pid(other),
            parts[other].mass.com,
            Provenance::rule("disconnected_part_fixed_to_root"),
        ));
    }
    Ok((pid(root), joints, notes))
}

fn heuristic_joints(parts: &[PartInput<'_>]) -> (PartId, Vec<Joint>, Vec<String>) {
    let n = parts.len();
    let roles: Vec<Role> = parts.iter().map(|p| role_of(p.name).0).collect();
    let volumes: Vec<f64> = parts.iter().map(|p| p.volume_m3).collect();
    let distance = pairwise_distances(parts);
    let (root, parents) = crate::tree::build_tree(&roles, &volumes, &|i, j| distance[i][j]);
    let bounds: Vec<Aabb> = parts.iter().map(|p| p.mesh.bounds()).collect();
    let object_diagonal_m = bounds
        .iter()
        .fold(Aabb::EMPTY, |a, b| a.union(*b))
        .diagonal();
    let mut notes = Vec::new();
    let meshes: Vec<TriMesh> = parts.iter().map(|p| p.mesh.clone()).collect();
    let colliders: Vec<Vec<TriMesh>> = parts.iter().map(|p| p.colliders.to_vec()).collect();
    let scene = Scene::new(&meshes, &colliders, SCREEN_SAMPLES)
        .map_err(|e| notes.push(format!("articulation sweeps unavailable: {e}")))
        .ok();
    let mut joints = Vec::new();
    for (i, parent) in parents.iter().enumerate() {
        let Some(p) = *parent else { continue };
        let provenance = |what: &str| {
            Provenance::provider(BUILTIN_PROVIDER, format!("geometric heuristic: {what}"))
        };
        let searched = match roles[i] {
            Role::Sliding | Role::Hinged => scene.as_ref().and_then(|scene| {
                let mut moving = vec![i];
                moving.extend((0..n).filter(|&k| carried_by(k, i, &parents)));
                let kind = if roles[i] == Role::Sliding {
                    JointKind::Prismatic
                } else {
                    JointKind::Revolute
                };
                let subject = Subject {
                    child: i,
                    parent: p,
                    moving: &moving,
                    kind,
                };
                best_joint(scene, &subject)
            }),
            _ => None,
        };
        if let Some(found) = searched {
            notes.push(format!(
                "part {:?}: {} chosen among {} swept hypotheses (score {:.3}, deepest penetration {:.4} m)",
                parts[i].name,
                kind_word(found.joint.kind),
                found.hypotheses,
                found.score,
                found.metrics.max_penetration_growth_m
            ));
            joints.push(found.joint);
            continue;
        }
        if matches!(roles[i], Role::Sliding | Role::Hinged) {
            notes.push(format!(
                "part {:?}: no contact with its parent to sweep from; joint from its bounding box",
                parts[i].name
            ));
        }
        let joint = match roles[i] {
            Role::Sliding => {
                let h = slide(&bounds[i], &bounds[p]);
                movable_joint(
                    JointKind::Prismatic,
                    pid(p),
                    pid(i),
                    h.axis,
                    h.pivot,
                    (h.lower, h.upper),
                    provenance("slides out of the open side of its parent"),
                )
            }
            Role::Hinged => {
                let contact = contact_region(
                    parts[i].mesh,
                    parts[p].mesh,
                    object_diagonal_m,
                    &ContactParams::default(),
                )
                .ok()
                .filter(|c| !c.points.is_empty())
                .map(|c| c.points.iter().sum::<DVec3>() / c.points.len() as f64);
                let attachments: Vec<DVec3> = (0..n)
                    .filter(|&k| parent_is(k, i, &roles, &parents))
                    .map(|k| bounds[k].center())
                    .collect();
                let away_from = (!attachments.is_empty())
                    .then(|| attachments.iter().sum::<DVec3>() / attachments.len() as f64);
                let h = hinge(&bounds[i], bounds[p].center(), contact, away_from);
                let why = if away_from.is_some() {
                    "hinge on the edge opposite the handle"
                } else {
                    "hinge on the edge nearest the contact with the parent"
                };
                movable_joint(
                    JointKind::Revolute,
                    pid(p),
                    pid(i),
                    h.axis,
                    h.pivot,
                    (h.lower, h.upper),
                    provenance(why),
                )
            }
            _ => fixed_joint(
                pid(p),
                pid(i),
                parts[i].mass.com,
                provenance("rigidly attached to the nearest part"),
            ),
        };
        joints.push(joint);
    }
    if joints.iter().all(|j| !j.kind.is_movable()) && n > 1 {
        notes.push(
            "no part name suggested motion (door, drawer, lid, ...); all parts fixed".to_owned(),
        );
    }
    (root, joints, notes)
}

/// The smallest distance between every two parts' meshes, metres (`distance[i][j]`).
pub(crate) fn pairwise_distances(parts: &[PartInput<'_>]) -> Vec<Vec<f64>> {
    let n = parts.len();
    let probes: Vec<DistanceProbe> = parts.iter().map(|p| DistanceProbe::new(p.mesh)).collect();
    let mut distance = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in (i + 1)..n {
            let d = probes[i].min_distance_m(&probes[j]);
            distance[i][j] = d;
            distance[j][i] = d;
        }
    }
    distance
}

/// A movable joint of the built-in grounder from `parent` to `child` (part indices), its range
/// `[0, upper]` (none for a continuous joint), with `why` in its provenance.
pub(crate) fn builtin_joint(
    kind: JointKind,
    (parent, child): (usize, usize),
    axis: DVec3,
    pivot: DVec3,
    upper: Option<f64>,
    why: String,
) -> Joint {
    Joint {
        name: String::new(),
        kind,
        parent: pid(parent),
        child: pid(child),
        axis_in_object: axis.normalize().to_array(),
        pivot_in_object_m: pivot.to_array(),
        limits: upper.map(|upper| JointLimits { lower: 0.0, upper }),
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance: Provenance::provider(BUILTIN_PROVIDER, why),
    }
}

fn parent_is(k: usize, i: usize, roles: &[Role], parent: &[Option<usize>]) -> bool {
    roles[k] == Role::Attachment && parent[k] == Some(i)
}

/// Whether part `k` hangs (directly or through other parts) from part `i`.
pub(crate) fn carried_by(k: usize, i: usize, parent: &[Option<usize>]) -> bool {
    let mut at = parent[k];
    let mut hops = 0;
    while let Some(p) = at {
        if p == i {
            return true;
        }
        hops += 1;
        if hops > parent.len() {
            return false;
        }
        at = parent[p];
    }
    false
}

fn movable_joint(
    kind: JointKind,
    parent: PartId,
    child: PartId,
    axis: DVec3,
    pivot: DVec3,
    range: (f64, f64),
    provenance: Provenance,
) -> Joint {
    Joint {
        name: String::new(),
        kind,
        parent,
        child,
        axis_in_object: axis.normalize().to_array(),
        pivot_in_object_m: pivot.to_array(),
        limits: Some(JointLimits {
            lower: range.0,
            upper: range.1,
        }),
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance,
    }
}

pub(crate) fn fixed_joint(
    parent: PartId,
    child: PartId,
    anchor: DVec3,
    provenance: Provenance,
) -> Joint {
    Joint {
        name: String::new(),
        kind: JointKind::Fixed,
        parent,
        child,
        axis_in_object: [1.0, 0.0, 0.0],
        pivot_in_object_m: anchor.to_array(),
        limits: None,
        damping: 0.0,
        friction: 0.0,
        coupled_parts: Vec::new(),
        provenance,
    }
}

/// All parts below `part` in the joint tree, sorted.
fn descendants(joints: &[Joint], part: PartId) -> BTreeSet<PartId> {
    reachable(joints, part, |_| true)
}

/// The parts fixed (transitively, through fixed joints only) to `part`, sorted.
fn fixed_group(joints: &[Joint], part: PartId) -> Vec<PartId> {
    reachable(joints, part, |j| j.kind == JointKind::Fixed)
        .into_iter()
        .collect()
}

/// Parts reached from `part` by going down joints that satisfy `through`.
fn reachable(joints: &[Joint], part: PartId, through: impl Fn(&Joint) -> bool) -> BTreeSet<PartId> {
    let mut out = BTreeSet::new();
    let mut stack = vec![part];
    while let Some(p) = stack.pop() {
        for j in joints.iter().filter(|j| j.parent == p && through(j)) {
            if out.insert(j.child) {
                stack.push(j.child);
            }
        }
    }
    out
}

/// Names every joint uniquely, fills motion-coupled groups and passive dynamics.
fn finish_joints(parts: &[PartInput<'_>], joints: &mut [Joint], notes: &mut Vec<String>) {
    let snapshot: Vec<Joint> = joints.to_vec();
    let mut used = BTreeSet::new();
    for joint in joints.iter_mut() {
        let base = if joint.name.is_empty() {
            format!(
                "{}_{}",
                kind_word(joint.kind),
                sanitize(parts[joint.child.0 as usize].name)
            )
        } else {
            sanitize(&joint.name)
        };
        let mut name = base.clone();
        let mut k = 1;
        while !used.insert(name.clone()) {
            k += 1;
            name = format!("{base}_{k}");
        }
        joint.name = name;
        if !joint.kind.is_movable() {
            continue;
        }
        joint.coupled_parts = fixed_group(&snapshot, joint.child);
        let mut moving: Vec<RigidMass> = vec![parts[joint.child.0 as usize].mass];
        moving.extend(
            descendants(&snapshot, joint.child)
                .iter()
                .map(|p| parts[p.0 as usize].mass),
        );
        let group = RigidMass::combine(&moving);
        let rotational = joint.kind != JointKind::Prismatic;
        let (damping, friction) = joint_dynamics(
            &group,
            DVec3::from_array(joint.axis_in_object),
            DVec3::from_array(joint.pivot_in_object_m),
            rotational,
        );
        if joint.damping <= 0.0 {
            joint.damping = damping;
            if matches!(joint.provenance, Provenance::Input { .. }) {
                notes.push(format!(
                    "joint {:?}: damping from rule joint_dynamics_from_inertia",
                    joint.name
                ));
            }
        }
        let stable = max_stable_damping(
            &group,
            DVec3::from_array(joint.axis_in_object),
            DVec3::from_array(joint.pivot_in_object_m),
            rotational,
        );
        if joint.damping > stable {
            notes.push(format!(
                "joint {:?}: damping {:.4} lowered to {:.4} so that inertia/damping stays above {:.4} s",
                joint.name, joint.damping, stable, crate::dynamics::MIN_DAMPING_TIME_CONSTANT_SECS
            ));
            joint.damping = stable;
        }
        if joint.friction <= 0.0 {
            joint.friction = if joint.kind == JointKind::Continuous {
                friction.max(holding_friction(
                    &group,
                    DVec3::from_array(joint.axis_in_object),
                    DVec3::from_array(joint.pivot_in_object_m),
                ))
            } else {
                friction
            };
        }
    }
}

pub(crate) fn kind_word(kind: JointKind) -> &'static str {
    match kind {
        JointKind::Revolute => "hinge",
        JointKind::Continuous => "spin",
        JointKind::Prismatic => "slide",
        JointKind::Fixed => "fixed",
    }
}

/// ASCII letters, digits and `_` only; other characters become `_`.
#[must_use]
pub fn sanitize(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() { "part".to_owned() } else { s }
}
