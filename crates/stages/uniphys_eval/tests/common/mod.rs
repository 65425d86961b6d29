//! Fixtures: a cabinet URDF (body, hinged door, sliding drawer with a handle) and a record of
//! the same cabinet in the frame the pipeline would give it.
#![allow(dead_code, reason = "each test binary uses a subset of the fixtures")]

use std::path::{Path, PathBuf};

use uniphys_types::{
    AssetRecord, Descriptions, Estimate, Joint, JointKind, JointLimits, Material, ObjectProperties,
    PartId, PartMass, PartProperties, PartRecord, Provenance, SourceFormat, SourceInfo, UpAxis,
};

/// The cabinet as URDF. Body [-0.5, 0.5]^2 x [0, 1]; door x in [0.5, 0.52], hinged about +z
/// through (0.5, -0.5, 0), 0..1.57 rad; drawer 0.4 x 0.4 x 0.1 centred at (0, 0, 0.5), sliding
/// along +x 0..0.3 m; a handle fixed to the drawer. The union spans x in [-0.5, 0.52], so
/// resting on the ground moves everything by -0.01 along x.
pub const CABINET_URDF: &str = r#"<?xml version="1.0"?>
<robot name="cabinet">
  <link name="body"><visual><origin xyz="0 0 0.5"/><geometry><box size="1 1 1"/></geometry></visual></link>
  <link name="door"><visual><origin xyz="0.01 0.5 0.5"/><geometry><box size="0.02 1 1"/></geometry></visual></link>
  <link name="drawer"><visual><geometry><box size="0.4 0.4 0.1"/></geometry></visual></link>
  <link name="handle"><visual><origin xyz="0.21 0 0"/><geometry><box size="0.02 0.1 0.02"/></geometry></visual></link>
  <joint name="door_hinge" type="revolute">
    <origin xyz="0.5 -0.5 0"/><parent link="body"/><child link="door"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="1.57" effort="10" velocity="1"/>
  </joint>
  <joint name="drawer_slide" type="prismatic">
    <origin xyz="0 0 0.5"/><parent link="body"/><child link="drawer"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="10" velocity="1"/>
  </joint>
  <joint name="handle_fix" type="fixed">
    <origin xyz="0 0 0"/><parent link="drawer"/><child link="handle"/>
  </joint>
</robot>
"#;

/// Largest half-extent of the rested cabinet: x spans [-0.51, 0.51].
pub const CABINET_SCALE_M: f64 = 0.51;

/// Writes the cabinet URDF into `dir/cabinet/` and returns the folder.
pub fn cabinet_urdf(dir: &Path) -> PathBuf {
    let folder = dir.join("cabinet");
    std::fs::create_dir_all(&folder).expect("create fixture folder");
    std::fs::write(folder.join("cabinet.urdf"), CABINET_URDF).expect("write urdf");
    folder
}

fn props(material: &str, density: f64) -> PartProperties {
    let e = |v: f64| Estimate::new(v, Provenance::rule("test"));
    PartProperties {
        material: Estimate::new(
            Material::parse(material).expect("valid material"),
            Provenance::rule("test"),
        ),
        density_kg_per_m3: e(density),
        youngs_modulus_pa: e(1e10),
        hardness_pa: e(1e8),
        poisson_ratio: e(0.3),
        friction_coefficient: e(0.5),
        affordance_rank: Estimate::new(2, Provenance::rule("test")),
        graspable: Estimate::new(true, Provenance::rule("test")),
        descriptions: Descriptions::default(),
    }
}

fn part(id: u32, name: &str, min: [f64; 3], max: [f64; 3]) -> PartRecord {
    PartRecord {
        id: PartId(id),
        name: name.into(),
        triangle_count: 12,
        bounds_in_object_m: [min, max],
        properties: props("wood/oak", 700.0),
        mass: PartMass {
            volume_m3: 1.0,
            volume_method: "closed_mesh".into(),
            mass_kg: Estimate::new(1.0, Provenance::rule("test")),
            com_in_object_m: [0.0; 3],
            inertia_about_com_kg_m2: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        },
    }
}

/// A joint of the record.
pub fn joint(
    name: &str,
    kind: JointKind,
    parent: u32,
    child: u32,
    axis: [f64; 3],
    pivot: [f64; 3],
    limits: Option<(f64, f64)>,
) -> Joint {
    Joint {
        name: name.into(),
        kind,
        parent: PartId(parent),
        child: PartId(child),
        axis_in_object: axis,
        pivot_in_object_m: pivot,
        limits: limits.map(|(lower, upper)| JointLimits { lower, upper }),
        damping: 0.0,
        friction: 0.0,
        coupled_parts: vec![],
        provenance: Provenance::rule("test"),
    }
}

/// The cabinet's record in the rested frame (the URDF moved by -0.01 along x), with the true
/// joints: door revolute, drawer prismatic carrying the handle.
pub fn cabinet_record() -> AssetRecord {
    let mut drawer = joint(
        "drawer_slide",
        JointKind::Prismatic,
        0,
        2,
        [1.0, 0.0, 0.0],
        [-0.01, 0.0, 0.5],
        Some((0.0, 0.3)),
    );
    drawer.coupled_parts = vec![PartId(3)];
    AssetRecord {
        schema_version: 1,
        name: "cabinet".into(),
        source: SourceInfo {
            file_name: "cabinet.urdf".into(),
            format: SourceFormat::Urdf,
            content_sha256: "00".into(),
            metres_per_unit: 1.0,
            up_axis: UpAxis::Z,
        },
        object: ObjectProperties {
            name: Estimate::new("cabinet".into(), Provenance::rule("t")),
            category: Estimate::new("Furniture/Cabinet".into(), Provenance::rule("t")),
            dimensions_m: Estimate::new([1.02, 1.0, 1.0], Provenance::rule("t")),
            mass_kg: Estimate::new(30.0, Provenance::rule("t")),
        },
        parts: vec![
            part(0, "body", [-0.51, -0.5, 0.0], [0.49, 0.5, 1.0]),
            part(1, "door", [0.49, -0.5, 0.0], [0.51, 0.5, 1.0]),
            part(2, "drawer", [-0.21, -0.2, 0.45], [0.19, 0.2, 0.55]),
            part(3, "handle", [0.19, -0.05, 0.49], [0.21, 0.05, 0.51]),
        ],
        root: PartId(0),
        joints: vec![
            joint(
                "door_hinge",
                JointKind::Revolute,
                0,
                1,
                [0.0, 0.0, 1.0],
                [0.49, -0.5, 0.0],
                Some((0.0, 1.57)),
            ),
            drawer,
            joint(
                "handle_fix",
                JointKind::Fixed,
                2,
                3,
                [0.0, 0.0, 1.0],
                [0.2, 0.0, 0.5],
                None,
            ),
        ],
    }
}

/// Writes `record` as `dir/<name>/record.json` and returns the output directory.
pub fn write_record(dir: &Path, name: &str, record: &AssetRecord) -> PathBuf {
    let out = dir.join(name);
    std::fs::create_dir_all(&out).expect("create output dir");
    std::fs::write(
        out.join("record.json"),
        serde_json::to_vec_pretty(record).expect("serialise record"),
    )
    .expect("write record");
    out
}

/// Whether a metric is present and within 1e-9 of `b`.
pub fn close(a: Option<f64>, b: f64) -> bool {
    a.is_some_and(|a| (a - b).abs() < 1e-9)
}
