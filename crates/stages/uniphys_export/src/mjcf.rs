//! MJCF output (simulation-readiness checklist 2.2): radians, `meshdir`, default classes that
//! separate visual geoms (no contacts, group 2) from convex collision geoms (group 3), explicit
//! `fullinertia` per body, joint damping, friction loss and armature, stiff joint limits, contact
//! excludes for jointed and touching bodies, and a root body fixed to the world.

use uniphys_types::{Joint, JointKind};

use crate::MESH_DIR;
use crate::model::{Link, Model};
use crate::visuals::texture_file;
use crate::xml::{Element, coords, num, nums, rgba};

/// Armature as seconds times damping: reflected inertia of 10 % of the damping time constant,
/// which stabilises light joints at the 2 ms time step.
const ARMATURE_SECS: f64 = 0.1;
/// Simulation time step, seconds.
const TIMESTEP_SECS: f64 = 0.002;
/// Time constant of a joint limit's soft constraint: two steps, the stiffest MuJoCo integrates
/// stably. MuJoCo's default (20 ms) lets gravity press a part into its limit by about 0.2 mm,
/// most of a 0.4 mm button's travel; two steps leave a twenty-fifth of that.
const LIMIT_TIMECONST_SECS: f64 = 2.0 * TIMESTEP_SECS;

pub(crate) fn write_mjcf(model: &Model<'_>) -> String {
    let mut root = Element::new("mujoco").attr("model", model.name.clone());
    root.push(
        Element::new("compiler")
            .attr("angle", "radian")
            .attr("meshdir", MESH_DIR)
            .attr("texturedir", MESH_DIR)
            .attr("autolimits", "true"),
    );
    root.push(
        Element::new("option")
            .attr("timestep", num(TIMESTEP_SECS))
            .attr("gravity", "0 0 -9.81")
            .attr("integrator", "implicitfast"),
    );
    // Class names carry the model name so several assets can share one scene.
    root.push(
        Element::new("default")
            .child(
                Element::new("default")
                    .attr("class", format!("{}_visual", model.name))
                    .child(
                        Element::new("geom")
                            .attr("type", "mesh")
                            .attr("contype", "0")
                            .attr("conaffinity", "0")
                            .attr("group", "2")
                            .attr("density", "0"),
                    ),
            )
            .child(
                Element::new("default")
                    .attr("class", format!("{}_collision", model.name))
                    .child(
                        Element::new("geom")
                            .attr("type", "mesh")
                            .attr("group", "3")
                            .attr("condim", "3")
                            .attr("density", "0")
                            .attr("rgba", "0.5 0.5 0.5 0.3"),
                    ),
            ),
    );
    let mut asset = Element::new("asset");
    let mut textures = std::collections::BTreeSet::new();
    for link in &model.links {
        for visual in &link.visuals {
            let mut material = Element::new("material")
                .attr("name", visual.material.clone())
                .attr("rgba", rgba(visual.rgba));
            if let Some(t) = visual.texture {
                if textures.insert(t) {
                    asset.push(
                        Element::new("texture")
                            .attr("name", texture_name(&model.name, t))
                            .attr("type", "2d")
                            .attr("file", texture_file(t)),
                    );
                }
                material = material.attr("texture", texture_name(&model.name, t));
            }
            asset.push(material);
            asset.push(
                Element::new("mesh")
                    .attr("name", visual.stem.clone())
                    .attr("file", format!("{}.obj", visual.stem))
                    .attr("inertia", "shell"),
            );
        }
        for stem in &link.collision_stems {
            asset.push(
                Element::new("mesh")
                    .attr("name", stem.clone())
                    .attr("file", format!("{stem}.obj"))
                    .attr("inertia", "convex"),
            );
        }
    }
    root.push(asset);
    let mut world = Element::new("worldbody");
    world.push(body(model, model.root, None));
    root.push(world);
    if !model.exclude_pairs.is_empty() {
        let mut contact = Element::new("contact");
        for &(a, b, _) in &model.exclude_pairs {
            contact.push(
                Element::new("exclude")
                    .attr("body1", model.links[a].name.clone())
                    .attr("body2", model.links[b].name.clone()),
            );
        }
        root.push(contact);
    }
    root.to_document()
}

/// Name of texture `index` in the MJCF; it carries the model name, as the classes do.
fn texture_name(model: &str, index: usize) -> String {
    format!("{model}_texture_{index}")
}

/// The body of link `index`, with its joint (if movable) and its child bodies, recursively.
fn body(model: &Model<'_>, index: usize, joint: Option<&Joint>) -> Element {
    let link: &Link = &model.links[index];
    let pos = joint.map_or(link.anchor, |j| model.joint_origin(j));
    let mut el = Element::new("body")
        .attr("name", link.name.clone())
        .attr("pos", coords(&pos.to_array()));
    let i = link.inertia_kg_m2;
    el.push(
        Element::new("inertial")
            .attr("pos", coords(&link.com_in_link.to_array()))
            .attr("mass", num(link.mass_kg))
            .attr(
                "fullinertia",
                nums(&[
                    i.x_axis.x, i.y_axis.y, i.z_axis.z, i.y_axis.x, i.z_axis.x, i.z_axis.y,
                ]),
            ),
    );
    if let Some(j) = joint.filter(|j| j.kind.is_movable()) {
        let kind = if j.kind == JointKind::Prismatic {
            "slide"
        } else {
            "hinge"
        };
        let mut je = Element::new("joint")
            .attr("name", j.name.clone())
            .attr("type", kind)
            .attr("pos", "0 0 0")
            .attr("axis", coords(&j.axis_in_object));
        if let Some(l) = j.limits.filter(|_| j.kind.needs_limits()) {
            je = je
                .attr("range", nums(&[l.lower, l.upper]))
                .attr("solreflimit", nums(&[LIMIT_TIMECONST_SECS, 1.0]));
        }
        el.push(
            je.attr("damping", num(j.damping))
                .attr("frictionloss", num(j.friction))
                .attr("armature", num(ARMATURE_SECS * j.damping)),
        );
    }
    for visual in &link.visuals {
        el.push(
            Element::new("geom")
                .attr("name", visual.stem.clone())
                .attr("class", format!("{}_visual", model.name))
                .attr("mesh", visual.stem.clone())
                .attr("material", visual.material.clone()),
        );
    }
    for stem in &link.collision_stems {
        el.push(
            Element::new("geom")
                .attr("name", stem.clone())
                .attr("class", format!("{}_collision", model.name))
                .attr("mesh", stem.clone())
                .attr("friction", format!("{} 0.005 0.0001", num(link.friction))),
        );
    }
    for child_joint in model.joints.iter().filter(|j| j.parent == link.id) {
        let child_index = model
            .links
            .iter()
            .position(|l| l.id == child_joint.child)
            .expect("joint children are links");
        el.push(body(model, child_index, Some(child_joint)));
    }
    el
}
