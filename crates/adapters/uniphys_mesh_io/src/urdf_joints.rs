//! URDF joints as `uniphys_types::Joint`s between parts, in the object frame at the zero
//! configuration.
//!
//! Links without geometry are not parts, but their frames still count. A part's joint connects
//! it to its nearest ancestor link that is a part; the joints on the way (through links without
//! geometry) are collapsed into one, named after the joint whose child is the part. Its motion
//! is the movable joint on the way closest to the part (fixed if there is none); further movable
//! joints on the way are ignored and listed in the provenance detail. If the root link has no
//! geometry, the first part hanging off it by fixed joints only (else the first one) becomes the
//! root part and the other parts hanging off it are attached to it. Floating, planar and
//! spherical joints are treated as fixed, which the provenance detail says.

use std::path::Path;

use uniphys_geometry::DVec3;
use uniphys_types::{Joint, JointKind, JointLimits, PartId, Provenance};
use urdf_rs::JointType;

use crate::urdf_tree::Tree;
use crate::{IngestError, IngestResult};

/// The joints between parts. `part_of_link[l]` is the part index of link `l`, if it has one.
pub(crate) fn part_joints(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    part_of_link: &[Option<usize>],
    path: &Path,
) -> IngestResult<Vec<Joint>> {
    let mut out = Vec::new();
    let mut orphans: Vec<(usize, Vec<usize>)> = Vec::new();
    for (link, part) in part_of_link.iter().enumerate() {
        let Some(part) = *part else { continue };
        if link == tree.root {
            continue;
        }
        // Joints from the part up to the nearest ancestor part, child first.
        let mut chain = Vec::new();
        let mut cursor = link;
        let mut ancestor = None;
        while let Some(j) = tree.parent_joint[cursor] {
            chain.push(j);
            cursor = tree.joint_links[j].0;
            if let Some(p) = part_of_link[cursor] {
                ancestor = Some(p);
                break;
            }
        }
        match ancestor {
            Some(parent) => out.push(collapse(robot, tree, parent, part, &chain, path)?),
            None => orphans.push((part, chain)),
        }
    }
    if !orphans.is_empty() {
        let rigid = orphans
            .iter()
            .position(|(_, chain)| {
                chain
                    .iter()
                    .all(|&j| !is_movable(&robot.joints[j].joint_type))
            })
            .unwrap_or(0);
        let (root_part, _) = orphans.remove(rigid);
        for (part, chain) in &orphans {
            out.push(collapse(robot, tree, root_part, *part, chain, path)?);
        }
    }
    out.sort_by_key(|j| j.child);
    Ok(out)
}

fn is_movable(t: &JointType) -> bool {
    matches!(
        t,
        JointType::Revolute | JointType::Continuous | JointType::Prismatic
    )
}

/// One joint from `parent` to `child` standing for the URDF joints in `chain` (child first).
fn collapse(
    robot: &urdf_rs::Robot,
    tree: &Tree,
    parent: usize,
    child: usize,
    chain: &[usize],
    path: &Path,
) -> IngestResult<Joint> {
    let err = |m: String| IngestError::urdf(path, m);
    let Some(&named) = chain.first() else {
        return Err(err(
            "internal: a non-root part without a parent joint".into()
        ));
    };
    let movable: Vec<usize> = chain
        .iter()
        .copied()
        .filter(|&j| is_movable(&robot.joints[j].joint_type))
        .collect();
    let motion = movable.first().copied().unwrap_or(named);
    let joint = &robot.joints[motion];
    let mut notes = Vec::new();
    for &j in chain {
        let kind = match robot.joints[j].joint_type {
            JointType::Floating => "floating",
            JointType::Planar => "planar",
            JointType::Spherical => "spherical",
            _ => continue,
        };
        notes.push(format!(
            "urdf joint {} is {kind}, treated as fixed",
            robot.joints[j].name
        ));
    }
    if motion != named {
        notes.push(format!(
            "motion from urdf joint {} across links without geometry",
            joint.name
        ));
    }
    if movable.len() > 1 {
        let ignored: Vec<&str> = movable[1..]
            .iter()
            .map(|&j| robot.joints[j].name.as_str())
            .collect();
        notes.push(format!(
            "motion of urdf joints {} ignored",
            ignored.join(", ")
        ));
    }
    let kind = match joint.joint_type {
        JointType::Revolute => JointKind::Revolute,
        JointType::Continuous => JointKind::Continuous,
        JointType::Prismatic => JointKind::Prismatic,
        JointType::Fixed | JointType::Floating | JointType::Planar | JointType::Spherical => {
            JointKind::Fixed
        }
    };
    let frame = tree.link_world[tree.joint_links[motion].1];
    let local_axis = DVec3::from_array(joint.axis.xyz.0);
    let axis = frame.transform_vector3(local_axis);
    let axis = if axis.is_finite() && axis.length() > 1e-12 {
        axis.normalize()
    } else if kind.is_movable() {
        return Err(err(format!(
            "joint {:?} has the axis {:?}; give a non-zero, finite <axis xyz>",
            joint.name, joint.axis.xyz.0
        )));
    } else {
        frame.transform_vector3(DVec3::X).normalize_or(DVec3::X)
    };
    let limits = kind
        .needs_limits()
        .then_some(&joint.limit)
        .filter(|l| l.lower.is_finite() && l.upper.is_finite() && l.lower < l.upper)
        .map(|l| JointLimits {
            lower: l.lower,
            upper: l.upper,
        });
    let (damping, friction) = joint
        .dynamics
        .as_ref()
        .map_or((0.0, 0.0), |d| (d.damping, d.friction));
    for (what, v) in [("damping", damping), ("friction", friction)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(err(format!(
                "joint {:?} has {what} {v}; it must be finite and >= 0",
                joint.name
            )));
        }
    }
    let mut detail = format!("urdf joint {}", robot.joints[named].name);
    for note in notes {
        detail.push_str("; ");
        detail.push_str(&note);
    }
    Ok(Joint {
        name: robot.joints[named].name.clone(),
        kind,
        parent: part_id(parent),
        child: part_id(child),
        axis_in_object: axis.to_array(),
        pivot_in_object_m: frame.transform_point3(DVec3::ZERO).to_array(),
        limits,
        damping,
        friction,
        coupled_parts: Vec::new(),
        provenance: Provenance::input(detail),
    })
}

fn part_id(index: usize) -> PartId {
    PartId(u32::try_from(index).unwrap_or(u32::MAX))
}
