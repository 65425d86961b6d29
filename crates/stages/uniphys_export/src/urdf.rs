//! URDF output (simulation-readiness checklist 2.1): metric units, real mass and full inertia at
//! the centre of mass, one visual mesh and convex collision meshes per link, limits and dynamics on
//! every movable joint, a `<mujoco>` compiler block for MuJoCo's importer, Bullet `<contact>`
//! friction, and a massless `world` link that fixes the root.
//!
//! MuJoCo's importer is told to discard the visual meshes: it gives every mesh the volume-based
//! inertia, which refuses an open or zero-thickness part (a flat button face, a lid that is one
//! sheet) with "mesh volume is too small", and the importer has no way to mark a mesh as a shell.
//! The collision hulls always have volume; `model.xml` carries both, visuals as shells.

use uniphys_types::Joint;

use crate::MESH_DIR;
use crate::model::{Link, Model};
use crate::visuals::texture_file;
use crate::xml::{Element, coords, num, rgba};

/// Effort and velocity limits written on every movable joint (URDF requires them; passive
/// assets have no actuators, so they are generous bounds, not actuator specs).
const EFFORT_LIMIT: f64 = 1000.0;
const VELOCITY_LIMIT: f64 = 10.0;

pub(crate) fn write_urdf(model: &Model<'_>) -> String {
    let mut robot = Element::new("robot").attr("name", model.name.clone());
    robot.push(
        Element::new("mujoco").child(
            Element::new("compiler")
                .attr("meshdir", MESH_DIR)
                .attr("balanceinertia", "true")
                .attr("discardvisual", "true")
                .attr("fusestatic", "false")
                .attr("strippath", "true"),
        ),
    );
    robot.push(Element::new("link").attr("name", "world"));
    for link in &model.links {
        robot.push(link_element(link));
    }
    let root = &model.links[model.root];
    robot.push(
        Element::new("joint")
            .attr("name", "world_fixed")
            .attr("type", "fixed")
            .child(Element::new("parent").attr("link", "world"))
            .child(Element::new("child").attr("link", root.name.clone()))
            .child(
                Element::new("origin")
                    .attr("xyz", coords(&root.anchor.to_array()))
                    .attr("rpy", "0 0 0"),
            ),
    );
    for joint in &model.joints {
        robot.push(joint_element(model, joint));
    }
    robot.to_document()
}

fn link_element(link: &Link) -> Element {
    let i = link.inertia_kg_m2;
    let inertial = Element::new("inertial")
        .child(
            Element::new("origin")
                .attr("xyz", coords(&link.com_in_link.to_array()))
                .attr("rpy", "0 0 0"),
        )
        .child(Element::new("mass").attr("value", num(link.mass_kg)))
        .child(
            Element::new("inertia")
                .attr("ixx", num(i.x_axis.x))
                .attr("ixy", num(i.y_axis.x))
                .attr("ixz", num(i.z_axis.x))
                .attr("iyy", num(i.y_axis.y))
                .attr("iyz", num(i.z_axis.y))
                .attr("izz", num(i.z_axis.z)),
        );
    let mut el = Element::new("link")
        .attr("name", link.name.clone())
        .child(inertial);
    for visual in &link.visuals {
        let mut material = Element::new("material")
            .attr("name", visual.material.clone())
            .child(Element::new("color").attr("rgba", rgba(visual.rgba)));
        if let Some(t) = visual.texture {
            material = material.child(
                Element::new("texture").attr("filename", format!("{MESH_DIR}/{}", texture_file(t))),
            );
        }
        el.push(
            Element::new("visual")
                .attr("name", visual.stem.clone())
                .child(mesh_geometry(&visual.stem))
                .child(material),
        );
    }
    for stem in &link.collision_stems {
        el.push(
            Element::new("collision")
                .attr("name", stem.clone())
                .child(mesh_geometry(stem)),
        );
    }
    el.push(
        Element::new("contact")
            .child(Element::new("lateral_friction").attr("value", num(link.friction)))
            .child(Element::new("rolling_friction").attr("value", "0"))
            .child(Element::new("spinning_friction").attr("value", "0")),
    );
    el
}

fn mesh_geometry(stem: &str) -> Element {
    Element::new("geometry").child(
        Element::new("mesh")
            .attr("filename", format!("{MESH_DIR}/{stem}.obj"))
            .attr("scale", "1 1 1"),
    )
}

fn joint_element(model: &Model<'_>, joint: &Joint) -> Element {
    // URDF names its joint types as the record does.
    let mut el = Element::new("joint")
        .attr("name", joint.name.clone())
        .attr("type", joint.kind.as_str())
        .child(Element::new("parent").attr("link", model.link(joint.parent).name.clone()))
        .child(Element::new("child").attr("link", model.link(joint.child).name.clone()))
        .child(
            Element::new("origin")
                .attr("xyz", coords(&model.joint_origin(joint).to_array()))
                .attr("rpy", "0 0 0"),
        );
    if joint.kind.is_movable() {
        el.push(Element::new("axis").attr("xyz", coords(&joint.axis_in_object)));
        let mut limit = Element::new("limit");
        if let Some(l) = joint.limits.filter(|_| joint.kind.needs_limits()) {
            limit = limit
                .attr("lower", num(l.lower))
                .attr("upper", num(l.upper));
        }
        el.push(
            limit
                .attr("effort", num(EFFORT_LIMIT))
                .attr("velocity", num(VELOCITY_LIMIT)),
        );
        el.push(
            Element::new("dynamics")
                .attr("damping", num(joint.damping))
                .attr("friction", num(joint.friction)),
        );
    }
    el
}
