//! `model.usda`: the articulation as an ASCII USD stage with the UsdPhysics schemas, for Isaac
//! Sim and Isaac Lab.
//!
//! Every link is an `Xform` under the stage's default prim, placed at its link frame (the
//! object's axes, origin at its anchor), with `PhysicsRigidBodyAPI` and `PhysicsMassAPI` (mass,
//! centre of mass, principal moments and axes; masses and moments are never rounded to 0, a
//! sensor link of a robot weighs a milligram); its visual mesh is a `Mesh` child with the
//! link's display colour, and each convex hull a `Mesh` child with `PhysicsCollisionAPI` and a
//! convex-hull approximation (purpose `guide`, so renderers skip it). Joints are
//! `PhysicsRevoluteJoint`, `PhysicsPrismaticJoint` or `PhysicsFixedJoint` prims: UsdPhysics joints
//! turn about their frame's X axis, so both joint frames are rotated from X onto the joint's
//! axis; revolute limits are in degrees, prismatic ones in metres, a continuous joint has none.
//! Drives are off; a joint's damping is a drive with no stiffness and no target speed, which is
//! a viscous damper (angular damping per degree, as UsdPhysics measures angles). The root is
//! fixed to the world by a joint with no `body0`. Metres, kilograms and Z up are stated in the
//! stage's metadata. A visual carries the link's display colour; the faces of a textured
//! material are a `GeomSubset` bound to a `UsdPreviewSurface` material under `Looks` whose
//! diffuse colour is the texture (`meshes/texture_<t>.png`, read at the mesh's `st`). Links that
//! touch at rest without a joint between them have their contacts filtered
//! (`PhysicsFilteredPairsAPI`), as the MJCF excludes them; jointed bodies collide with each other
//! only if the joint enables it, which UsdPhysics leaves off.

use std::fmt::Write as _;

use uniphys_geometry::{DMat3, DQuat, DVec3, TriMesh, symmetric_eigen};
use uniphys_types::{Joint, JointKind};

use crate::MESH_DIR;
use crate::model::{ExcludeReason, Link, Model, sanitize};
use crate::visuals::{Visual, texture_file};
use crate::xml::{coord, num, short_f32};

/// Scope of the materials under the default prim.
const LOOKS: &str = "Looks";

/// Writes the stage for `model`, with the visual mesh and the hulls of each link (object frame,
/// in the order of `model.links`).
pub(crate) fn write_usda(model: &Model<'_>, visuals: &[TriMesh], hulls: &[Vec<TriMesh>]) -> String {
    let root = &identifier(&model.name);
    let mut s = String::new();
    let _ = write!(
        s,
        "#usda 1.0\n(\n    defaultPrim = \"{root}\"\n    doc = \"written by uniphys\"\n    kilogramsPerUnit = 1\n    metersPerUnit = 1\n    upAxis = \"Z\"\n)\n\n"
    );
    let _ = writeln!(
        s,
        "def Xform \"{root}\" (\n    prepend apiSchemas = [\"PhysicsArticulationRootAPI\"]\n)\n{{"
    );
    for (i, link) in model.links.iter().enumerate() {
        let filtered: Vec<&str> = model
            .exclude_pairs
            .iter()
            .filter(|&&(a, _, why)| a == i && why == ExcludeReason::TouchAtRest)
            .map(|&(_, b, _)| model.links[b].name.as_str())
            .collect();
        write_link(&mut s, root, link, &visuals[i], &hulls[i], &filtered);
    }
    write_looks(&mut s, root, model);
    let root_link = &model.links[model.root];
    let _ = writeln!(
        s,
        "    def PhysicsFixedJoint \"world_fixed\"\n    {{\n        rel physics:body1 = </{root}/{}>\n        point3f physics:localPos0 = {}\n    }}",
        root_link.name,
        point(root_link.anchor)
    );
    let mut taken: Vec<String> = model.links.iter().map(|l| l.name.clone()).collect();
    taken.push("world_fixed".to_owned());
    for joint in &model.joints {
        let prim = unique(identifier(&joint.name), &mut taken);
        write_joint(&mut s, root, &prim, model, joint);
    }
    s.push_str("}\n");
    s
}

/// One link: its rigid body, mass, visual and hulls, in its own frame, and the links it touches at
/// rest (`filtered`, by name), whose contacts with it are off.
fn write_link(
    s: &mut String,
    root: &str,
    link: &Link,
    visual: &TriMesh,
    hulls: &[TriMesh],
    filtered: &[&str],
) {
    let (moments, axes) = principal_inertia(link.inertia_kg_m2);
    let filter_api = if filtered.is_empty() {
        ""
    } else {
        ", \"PhysicsFilteredPairsAPI\""
    };
    let _ = writeln!(
        s,
        "    def Xform \"{}\" (\n        prepend apiSchemas = [\"PhysicsRigidBodyAPI\", \"PhysicsMassAPI\"{filter_api}]\n    )\n    {{",
        link.name
    );
    if !filtered.is_empty() {
        let targets: Vec<String> = filtered.iter().map(|n| format!("</{root}/{n}>")).collect();
        let _ = writeln!(
            s,
            "        rel physics:filteredPairs = [{}]",
            targets.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "        double3 xformOp:translate = {}\n        uniform token[] xformOpOrder = [\"xformOp:translate\"]",
        point(link.anchor)
    );
    let _ = writeln!(
        s,
        "        float physics:mass = {}\n        point3f physics:centerOfMass = {}\n        float3 physics:diagonalInertia = ({}, {}, {})\n        quatf physics:principalAxes = {}",
        num(link.mass_kg),
        point(link.com_in_link),
        num(moments.x.max(0.0)),
        num(moments.y.max(0.0)),
        num(moments.z.max(0.0)),
        quat(axes)
    );
    let [r, g, b, _] = link.rgba;
    let mut attributes = vec![format!(
        "color3f[] primvars:displayColor = [({r}, {g}, {b})]"
    )];
    let textured: Vec<&Visual> = link
        .visuals
        .iter()
        .filter(|v| v.texture.is_some())
        .collect();
    let mut subsets = String::new();
    if let (Some(uvs), false) = (&visual.uvs, textured.is_empty()) {
        // USD's t runs up the image, glTF's v down.
        let st: Vec<String> = uvs
            .iter()
            .map(|[u, v]| format!("({}, {})", short_f32(*u), short_f32(1.0 - *v)))
            .collect();
        attributes.push(format!(
            "texCoord2f[] primvars:st = [{}] (\n                interpolation = \"vertex\"\n            )",
            st.join(", ")
        ));
        attributes.push(
            "uniform token subsetFamily:materialBind:familyType = \"nonOverlapping\"".to_owned(),
        );
        for piece in textured {
            let indices: Vec<String> = piece.faces.iter().map(ToString::to_string).collect();
            let lines = [
                format!("            def GeomSubset \"{}\" (", piece.stem),
                "                prepend apiSchemas = [\"MaterialBindingAPI\"]".to_owned(),
                "            )".to_owned(),
                "            {".to_owned(),
                "                uniform token elementType = \"face\"".to_owned(),
                "                uniform token familyName = \"materialBind\"".to_owned(),
                format!("                int[] indices = [{}]", indices.join(", ")),
                format!(
                    "                rel material:binding = </{root}/{LOOKS}/{}>",
                    piece.material
                ),
                "            }".to_owned(),
            ];
            for line in lines {
                let _ = writeln!(subsets, "{line}");
            }
        }
    }
    write_mesh(
        s,
        "visual",
        visual,
        link.anchor,
        &attributes,
        (!subsets.is_empty()).then_some("[\"MaterialBindingAPI\"]"),
        &subsets,
    );
    for (k, hull) in hulls.iter().enumerate() {
        write_mesh(
            s,
            &format!("collision_{k}"),
            hull,
            link.anchor,
            &[
                "uniform token physics:approximation = \"convexHull\"".to_owned(),
                "uniform token purpose = \"guide\"".to_owned(),
            ],
            Some("[\"PhysicsCollisionAPI\", \"PhysicsMeshCollisionAPI\"]"),
            "",
        );
    }
    s.push_str("    }\n");
}

/// A triangle mesh prim named `name`, its points moved into the frame at `origin`.
fn write_mesh(
    s: &mut String,
    name: &str,
    mesh: &TriMesh,
    origin: DVec3,
    attributes: &[String],
    schemas: Option<&str>,
    children: &str,
) {
    let _ = write!(s, "        def Mesh \"{name}\"");
    if let Some(schemas) = schemas {
        let _ = write!(
            s,
            " (\n            prepend apiSchemas = {schemas}\n        )"
        );
    }
    s.push_str("\n        {\n");
    for attribute in attributes {
        let _ = writeln!(s, "            {attribute}");
    }
    s.push_str("            uniform token subdivisionScheme = \"none\"\n");
    let _ = writeln!(
        s,
        "            int[] faceVertexCounts = [{}]",
        vec!["3"; mesh.triangles.len()].join(", ")
    );
    s.push_str("            int[] faceVertexIndices = [");
    for (n, t) in mesh.triangles.iter().enumerate() {
        let sep = if n == 0 { "" } else { ", " };
        let _ = write!(s, "{sep}{}, {}, {}", t[0], t[1], t[2]);
    }
    s.push_str("]\n            point3f[] points = [");
    for (n, p) in mesh.positions.iter().enumerate() {
        let sep = if n == 0 { "" } else { ", " };
        let _ = write!(s, "{sep}{}", point(*p - origin));
    }
    s.push_str("]\n");
    s.push_str(children);
    s.push_str("        }\n");
}

/// The materials of the textured visuals, under `/root/Looks`: a `UsdPreviewSurface` whose
/// diffuse colour is the texture (read at the mesh's `st`) times the material's base colour.
fn write_looks(s: &mut String, root: &str, model: &Model<'_>) {
    let textured: Vec<(&Visual, usize)> = model
        .links
        .iter()
        .flat_map(|l| l.visuals.iter())
        .filter_map(|v| v.texture.map(|t| (v, t)))
        .collect();
    if textured.is_empty() {
        return;
    }
    let _ = writeln!(s, "    def Scope \"{LOOKS}\"\n    {{");
    for (visual, texture) in textured {
        let path = format!("/{root}/{LOOKS}/{}", visual.material);
        let [r, g, b, a] = visual.rgba.map(short_f32);
        let lines = [
            format!("        def Material \"{}\"", visual.material),
            "        {".to_owned(),
            format!("            token outputs:surface.connect = <{path}/surface.outputs:surface>"),
            "            def Shader \"surface\"".to_owned(),
            "            {".to_owned(),
            "                uniform token info:id = \"UsdPreviewSurface\"".to_owned(),
            format!(
                "                color3f inputs:diffuseColor.connect = <{path}/texture.outputs:rgb>"
            ),
            "                token outputs:surface".to_owned(),
            "            }".to_owned(),
            "            def Shader \"texture\"".to_owned(),
            "            {".to_owned(),
            "                uniform token info:id = \"UsdUVTexture\"".to_owned(),
            format!(
                "                asset inputs:file = @{MESH_DIR}/{}@",
                texture_file(texture)
            ),
            format!("                float2 inputs:st.connect = <{path}/st.outputs:result>"),
            format!("                float4 inputs:scale = ({r}, {g}, {b}, {a})"),
            "                float3 outputs:rgb".to_owned(),
            "            }".to_owned(),
            "            def Shader \"st\"".to_owned(),
            "            {".to_owned(),
            "                uniform token info:id = \"UsdPrimvarReader_float2\"".to_owned(),
            "                string inputs:varname = \"st\"".to_owned(),
            "                float2 outputs:result".to_owned(),
            "            }".to_owned(),
            "        }".to_owned(),
        ];
        for line in lines {
            let _ = writeln!(s, "{line}");
        }
    }
    s.push_str("    }\n");
}

/// One joint between two links, as the prim `prim` under `/root`; both joint frames sit at the
/// child's anchor.
fn write_joint(s: &mut String, root: &str, prim_name: &str, model: &Model<'_>, joint: &Joint) {
    let (parent, child) = (model.link(joint.parent), model.link(joint.child));
    let (prim, drive) = match joint.kind {
        JointKind::Revolute | JointKind::Continuous => ("PhysicsRevoluteJoint", Some("angular")),
        JointKind::Prismatic => ("PhysicsPrismaticJoint", Some("linear")),
        JointKind::Fixed => ("PhysicsFixedJoint", None),
    };
    let _ = write!(s, "    def {prim} \"{prim_name}\"");
    if let Some(drive) = drive {
        let _ = write!(
            s,
            " (\n        prepend apiSchemas = [\"PhysicsDriveAPI:{drive}\"]\n    )"
        );
    }
    let _ = writeln!(
        s,
        "\n    {{\n        custom string uniphys:name = \"{}\"\n        rel physics:body0 = </{root}/{}>\n        rel physics:body1 = </{root}/{}>\n        point3f physics:localPos0 = {}\n        point3f physics:localPos1 = (0, 0, 0)",
        escaped(&joint.name),
        parent.name,
        child.name,
        point(model.joint_origin(joint))
    );
    if let Some(drive) = drive {
        let rotation = DQuat::from_rotation_arc(
            DVec3::X,
            DVec3::from_array(joint.axis_in_object).normalize(),
        );
        let _ = writeln!(
            s,
            "        quatf physics:localRot0 = {}\n        quatf physics:localRot1 = {}\n        uniform token physics:axis = \"X\"",
            quat(rotation),
            quat(rotation)
        );
        // Angular quantities in UsdPhysics are per degree.
        let (limit_scale, damping) = if drive == "angular" {
            (180.0 / std::f64::consts::PI, joint.damping.to_radians())
        } else {
            (1.0, joint.damping)
        };
        if let Some(l) = joint.limits.filter(|_| joint.kind.needs_limits()) {
            let _ = writeln!(
                s,
                "        float physics:lowerLimit = {}\n        float physics:upperLimit = {}",
                coord(l.lower * limit_scale),
                coord(l.upper * limit_scale)
            );
        }
        let _ = writeln!(
            s,
            "        uniform token drive:{drive}:physics:type = \"force\"\n        float drive:{drive}:physics:stiffness = 0\n        float drive:{drive}:physics:damping = {}\n        float drive:{drive}:physics:targetVelocity = 0",
            coord(damping)
        );
    }
    s.push_str("    }\n");
}

/// Principal moments and the rotation whose columns are their axes (a proper
/// rotation: the third axis is the cross product of the first two).
fn principal_inertia(inertia: DMat3) -> (DVec3, DQuat) {
    let (moments, vectors) = symmetric_eigen(inertia);
    let (x, y) = (vectors.x_axis.normalize(), vectors.y_axis.normalize());
    let z = x.cross(y).normalize();
    let y = z.cross(x);
    (
        moments,
        DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize(),
    )
}

/// A valid prim name: ASCII letters, digits and `_`, not starting with a digit.
fn identifier(name: &str) -> String {
    let s = sanitize(name);
    if s.starts_with(|c: char| c.is_ascii_digit()) {
        format!("_{s}")
    } else {
        s
    }
}

/// `name`, or `name_2`, `name_3`, ... when `taken` holds it already; the result is taken.
fn unique(name: String, taken: &mut Vec<String>) -> String {
    let mut candidate = name.clone();
    let mut n = 1;
    while taken.contains(&candidate) {
        n += 1;
        candidate = format!("{name}_{n}");
    }
    taken.push(candidate.clone());
    candidate
}

/// `text` inside a USD string literal.
fn escaped(text: &str) -> String {
    text.replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n")
}

fn point(p: DVec3) -> String {
    format!("({}, {}, {})", coord(p.x), coord(p.y), coord(p.z))
}

/// A quaternion in USD's order: real part first.
fn quat(q: DQuat) -> String {
    format!(
        "({}, {}, {}, {})",
        coord(q.w),
        coord(q.x),
        coord(q.y),
        coord(q.z)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prim_names_are_identifiers_and_unique() {
        let mut taken = vec!["part_0_body".to_owned()];
        assert_eq!(unique(identifier("8"), &mut taken), "_8");
        assert_eq!(
            unique(identifier("part 0 body"), &mut taken),
            "part_0_body_2"
        );
        assert_eq!(unique(identifier("8"), &mut taken), "_8_2");
        assert_eq!(escaped("a \"b\"\\"), "a \\\"b\\\"\\\\");
    }

    #[test]
    fn principal_axes_turn_the_diagonal_back_into_the_tensor() {
        let turn = DMat3::from_quat(DQuat::from_rotation_z(0.4) * DQuat::from_rotation_x(0.3));
        let tensor = turn * DMat3::from_diagonal(DVec3::new(1.0, 2.0, 3.0)) * turn.transpose();
        let (moments, axes) = principal_inertia(tensor);
        let r = DMat3::from_quat(axes);
        let back = r * DMat3::from_diagonal(moments) * r.transpose();
        assert!((back - tensor).abs_diff_eq(DMat3::ZERO, 1e-9), "{back:?}");
    }
}
