//! The kinematic tree of a URDF: link and joint name checks, the root link, and every link's
//! world pose at the zero configuration.

use std::collections::HashMap;
use std::path::Path;

use uniphys_geometry::DMat3;
use uniphys_geometry::{DMat4, DVec3};

use crate::{IngestError, IngestResult};

/// Most links (and joints) accepted, which keeps the joint collapsing cheap; articulated
/// objects have tens of links.
const MAX_LINKS: usize = 10_000;

/// Structure of a URDF's links and joints.
#[derive(Debug, Clone)]
pub(crate) struct Tree {
    /// Index of the root link (the one that is never a joint's child).
    pub(crate) root: usize,
    /// For each link, the joint whose child it is.
    pub(crate) parent_joint: Vec<Option<usize>>,
    /// For each joint, its parent and child link.
    pub(crate) joint_links: Vec<(usize, usize)>,
    /// For each link, its pose in the object (root link) frame at the zero configuration.
    pub(crate) link_world: Vec<DMat4>,
}

impl Tree {
    /// Checks names and connectivity and computes link poses.
    pub(crate) fn new(robot: &urdf_rs::Robot, path: &Path) -> IngestResult<Self> {
        let err = |m: String| IngestError::urdf(path, m);
        if robot.links.len() > MAX_LINKS || robot.joints.len() > MAX_LINKS {
            return Err(err(format!(
                "it has {} links and {} joints; at most {MAX_LINKS} of each are accepted",
                robot.links.len(),
                robot.joints.len()
            )));
        }
        let mut link_index: HashMap<&str, usize> = HashMap::new();
        for (i, link) in robot.links.iter().enumerate() {
            if link_index.insert(link.name.as_str(), i).is_some() {
                return Err(err(format!(
                    "link name {:?} is used twice; link names must be unique",
                    link.name
                )));
            }
        }
        let mut joint_names: HashMap<&str, usize> = HashMap::new();
        let mut parent_joint = vec![None; robot.links.len()];
        let mut joint_links = Vec::with_capacity(robot.joints.len());
        for (j, joint) in robot.joints.iter().enumerate() {
            if joint_names.insert(joint.name.as_str(), j).is_some() {
                return Err(err(format!(
                    "joint name {:?} is used twice; joint names must be unique",
                    joint.name
                )));
            }
            let find = |name: &str| {
                link_index.get(name).copied().ok_or_else(|| {
                    err(format!(
                        "joint {:?} refers to link {name:?}, which is not defined",
                        joint.name
                    ))
                })
            };
            let (parent, child) = (find(&joint.parent.link)?, find(&joint.child.link)?);
            if parent == child {
                return Err(err(format!(
                    "joint {:?} connects link {:?} to itself",
                    joint.name, joint.child.link
                )));
            }
            if let Some(other) = parent_joint[child].replace(j) {
                return Err(err(format!(
                    "link {:?} is the child of two joints ({:?} and {:?}); a link has one parent joint",
                    joint.child.link, robot.joints[other].name, joint.name
                )));
            }
            joint_links.push((parent, child));
        }
        let roots: Vec<usize> = (0..robot.links.len())
            .filter(|&l| parent_joint[l].is_none())
            .collect();
        let root = match roots.as_slice() {
            [root] => *root,
            [] => {
                return Err(err(
                    "no root link: every link is a joint's child, so the joints form a cycle"
                        .into(),
                ));
            }
            several => {
                let names: Vec<&str> = several
                    .iter()
                    .map(|&l| robot.links[l].name.as_str())
                    .collect();
                return Err(err(format!(
                    "several root links ({}); connect them with joints so that one link is the root",
                    names.join(", ")
                )));
            }
        };
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
        for (j, &(parent, _)) in joint_links.iter().enumerate() {
            children[parent].push(j);
        }
        let mut link_world: Vec<Option<DMat4>> = vec![None; robot.links.len()];
        link_world[root] = Some(DMat4::IDENTITY);
        let mut stack = vec![root];
        while let Some(link) = stack.pop() {
            let world = link_world[link].unwrap_or(DMat4::IDENTITY);
            for &j in &children[link] {
                let joint = &robot.joints[j];
                let origin = pose_matrix(&joint.origin).ok_or_else(|| {
                    err(format!("joint {:?} has a non-finite origin", joint.name))
                })?;
                let child = joint_links[j].1;
                link_world[child] = Some(world * origin);
                stack.push(child);
            }
        }
        let link_world = link_world
            .into_iter()
            .enumerate()
            .map(|(l, w)| {
                w.ok_or_else(|| {
                    err(format!(
                        "link {:?} is not connected to the root link (the joints form a cycle)",
                        robot.links[l].name
                    ))
                })
            })
            .collect::<IngestResult<Vec<_>>>()?;
        Ok(Self {
            root,
            parent_joint,
            joint_links,
            link_world,
        })
    }
}

/// The transform of a URDF `<origin xyz rpy>`: translation times Rz(yaw) Ry(pitch) Rx(roll).
/// `None` if a value is not finite.
pub(crate) fn pose_matrix(pose: &urdf_rs::Pose) -> Option<DMat4> {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    if ![x, y, z, roll, pitch, yaw].iter().all(|v| v.is_finite()) {
        return None;
    }
    let rotation =
        DMat3::from_rotation_z(yaw) * DMat3::from_rotation_y(pitch) * DMat3::from_rotation_x(roll);
    Some(DMat4::from_translation(DVec3::new(x, y, z)) * DMat4::from_mat3(rotation))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rpy_is_fixed_axis_roll_then_pitch_then_yaw() {
        let pose = urdf_rs::Pose {
            xyz: urdf_rs::Vec3([1.0, 2.0, 3.0]),
            rpy: urdf_rs::Vec3([
                std::f64::consts::FRAC_PI_2,
                0.0,
                std::f64::consts::FRAC_PI_2,
            ]),
        };
        let m = pose_matrix(&pose).expect("finite");
        // roll 90 about X takes Y to Z; yaw 90 about Z then leaves Z alone and takes X to Y.
        assert!((m.transform_vector3(DVec3::Y) - DVec3::Z).length() < 1e-12);
        assert!((m.transform_vector3(DVec3::X) - DVec3::Y).length() < 1e-12);
        assert!((m.transform_point3(DVec3::ZERO) - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12);
    }

    fn robot(xml: &str) -> urdf_rs::Robot {
        urdf_rs::read_from_string(xml).expect("valid urdf")
    }

    #[test]
    fn several_roots_and_cycles_are_rejected_with_link_names() {
        let two_roots = robot(r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#);
        let err = Tree::new(&two_roots, Path::new("r.urdf")).expect_err("two roots");
        assert!(
            err.to_string().contains("several root links (a, b)"),
            "{err}"
        );

        let cycle = robot(
            r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
            <joint name="j1" type="fixed"><parent link="b"/><child link="c"/></joint>
            <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint></robot>"#,
        );
        let err = Tree::new(&cycle, Path::new("r.urdf")).expect_err("cycle");
        assert!(
            err.to_string().contains("not connected to the root"),
            "{err}"
        );
    }

    #[test]
    fn duplicate_joint_names_are_rejected() {
        let r = robot(
            r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
            <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
            <joint name="j" type="fixed"><parent link="a"/><child link="c"/></joint></robot>"#,
        );
        let err = Tree::new(&r, Path::new("r.urdf")).expect_err("duplicate");
        assert!(
            err.to_string().contains("joint name \"j\" is used twice"),
            "{err}"
        );
    }
}
