//! Small hand-built assets for the dynamic check: cuboid parts with exact mass properties.
#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::f64::consts::FRAC_PI_2;

use uniphys_geometry::{DMat3, DMat4, DQuat, DVec3, MassProperties, TriMesh};
use uniphys_types::{
    AssetRecord, Descriptions, Estimate, Joint, JointKind, JointLimits, Material, ObjectProperties,
    PartId, PartMass, PartProperties, PartRecord, Provenance, SourceFormat, SourceInfo, UpAxis,
};

/// Wood, kg/m^3.
pub const DENSITY: f64 = 700.0;

/// A part under construction: its collision hulls (object frame) and density.
pub struct PartSpec {
    pub name: &'static str,
    pub hulls: Vec<TriMesh>,
    pub density: f64,
}

impl PartSpec {
    pub fn cuboid(name: &'static str, min: [f64; 3], max: [f64; 3]) -> Self {
        Self {
            name,
            hulls: vec![TriMesh::cuboid(DVec3::from(min), DVec3::from(max))],
            density: DENSITY,
        }
    }

    /// Several boxes making one (concave) part.
    pub fn boxes(name: &'static str, boxes: &[([f64; 3], [f64; 3])]) -> Self {
        Self {
            name,
            hulls: boxes
                .iter()
                .map(|(a, b)| TriMesh::cuboid(DVec3::from(*a), DVec3::from(*b)))
                .collect(),
            density: DENSITY,
        }
    }

    /// The same part rotated by `angle_rad` about the line through `pivot` along `axis`.
    pub fn rotated(mut self, axis: [f64; 3], pivot: [f64; 3], angle_rad: f64) -> Self {
        let p = DVec3::from(pivot);
        let m = DMat4::from_translation(p)
            * DMat4::from_quat(DQuat::from_axis_angle(DVec3::from(axis), angle_rad))
            * DMat4::from_translation(-p);
        self.hulls = self.hulls.iter().map(|h| h.transformed(&m)).collect();
        self
    }
}

fn props() -> PartProperties {
    let e = |v: f64| Estimate::new(v, Provenance::rule("test"));
    PartProperties {
        material: Estimate::new(
            Material::parse("wood/oak").expect("known material"),
            Provenance::rule("test"),
        ),
        density_kg_per_m3: e(DENSITY),
        youngs_modulus_pa: e(1e10),
        hardness_pa: e(1e8),
        poisson_ratio: e(0.3),
        friction_coefficient: e(0.5),
        affordance_rank: Estimate::new(2, Provenance::rule("test")),
        graspable: Estimate::new(true, Provenance::rule("test")),
        descriptions: Descriptions::default(),
    }
}

/// Mass properties of a part from its hulls (each a closed box), summed about the common
/// centre of mass.
fn part_record(id: u32, spec: &PartSpec) -> PartRecord {
    let pieces: Vec<MassProperties> = spec
        .hulls
        .iter()
        .map(|h| MassProperties::from_closed_mesh(h).expect("closed hull"))
        .collect();
    let volume: f64 = pieces.iter().map(|p| p.volume_m3).sum();
    let mass = volume * spec.density;
    let com = pieces.iter().map(|p| p.com * p.volume_m3).sum::<DVec3>() / volume;
    let mut inertia = DMat3::ZERO;
    for p in &pieces {
        let d = p.com - com;
        let shift = DMat3::from_diagonal(DVec3::splat(d.length_squared()))
            - DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        inertia += p.inertia_kg_m2(spec.density) + shift * (p.volume_m3 * spec.density);
    }
    let bounds = TriMesh::merge(&spec.hulls).bounds();
    PartRecord {
        id: PartId(id),
        name: spec.name.into(),
        triangle_count: 12 * spec.hulls.len(),
        bounds_in_object_m: [bounds.min.to_array(), bounds.max.to_array()],
        properties: props(),
        mass: PartMass {
            volume_m3: volume,
            volume_method: "closed_mesh".into(),
            mass_kg: Estimate::new(mass, Provenance::rule("density_times_volume")),
            com_in_object_m: com.to_array(),
            inertia_about_com_kg_m2: inertia.transpose().to_cols_array_2d(),
        },
    }
}

/// A joint between two parts (ids): `parts` is (parent, child); `dynamics` is (damping, friction).
pub fn joint(
    name: &str,
    kind: JointKind,
    parts: (u32, u32),
    axis: [f64; 3],
    pivot: [f64; 3],
    limits: Option<(f64, f64)>,
    dynamics: (f64, f64),
) -> Joint {
    let ((parent, child), (damping, friction)) = (parts, dynamics);
    Joint {
        name: name.into(),
        kind,
        parent: PartId(parent),
        child: PartId(child),
        axis_in_object: axis,
        pivot_in_object_m: pivot,
        limits: limits.map(|(lower, upper)| JointLimits { lower, upper }),
        damping,
        friction,
        coupled_parts: vec![],
        provenance: Provenance::rule("test"),
    }
}

/// An asset: the record (part 0 is the root) and the colliders by part position.
pub struct TestAsset {
    pub record: AssetRecord,
    pub colliders: Vec<Vec<TriMesh>>,
}

pub fn asset(name: &str, parts: Vec<PartSpec>, joints: Vec<Joint>) -> TestAsset {
    let records: Vec<PartRecord> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| part_record(i as u32, p))
        .collect();
    let total_mass = records.iter().map(|p| p.mass.mass_kg.value).sum();
    let bounds = TriMesh::merge(parts.iter().flat_map(|p| &p.hulls)).bounds();
    let record = AssetRecord {
        schema_version: 1,
        name: name.into(),
        source: SourceInfo {
            file_name: format!("{name}.glb"),
            format: SourceFormat::Glb,
            content_sha256: "00".into(),
            metres_per_unit: 1.0,
            up_axis: UpAxis::Z,
        },
        object: ObjectProperties {
            name: Estimate::new(name.into(), Provenance::rule("test")),
            category: Estimate::new("Test".into(), Provenance::rule("test")),
            dimensions_m: Estimate::new(bounds.extents().to_array(), Provenance::rule("test")),
            mass_kg: Estimate::new(total_mass, Provenance::rule("test")),
        },
        parts: records,
        root: PartId(0),
        joints,
    };
    record.validate().expect("valid test record");
    TestAsset {
        record,
        colliders: parts.into_iter().map(|p| p.hulls).collect(),
    }
}

/// A 0.4 x 0.3 x 0.2 m box with a 2 cm lid hinged on its back edge (axis -x so that positive
/// angles open it), closed at rest, range [0, 1.9] rad.
pub fn box_with_lid(damping: f64, friction: f64) -> TestAsset {
    asset(
        "box_with_lid",
        vec![
            PartSpec::cuboid("box", [-0.2, -0.15, 0.0], [0.2, 0.15, 0.2]),
            PartSpec::cuboid("lid", [-0.2, -0.15, 0.2], [0.2, 0.15, 0.22]),
        ],
        vec![joint(
            "lid_hinge",
            JointKind::Revolute,
            (0, 1),
            [-1.0, 0.0, 0.0],
            [0.0, 0.15, 0.2],
            Some((0.0, 1.9)),
            (damping, friction),
        )],
    )
}

/// The box with its lid exported open by `open_rad`: limits relative to that pose.
pub fn box_with_open_lid(open_rad: f64, damping: f64, friction: f64) -> TestAsset {
    let axis = [-1.0, 0.0, 0.0];
    let pivot = [0.0, 0.15, 0.2];
    asset(
        "box_with_open_lid",
        vec![
            PartSpec::cuboid("box", [-0.2, -0.15, 0.0], [0.2, 0.15, 0.2]),
            PartSpec::cuboid("lid", [-0.2, -0.15, 0.2], [0.2, 0.15, 0.22])
                .rotated(axis, pivot, open_rad),
        ],
        vec![joint(
            "lid_hinge",
            JointKind::Revolute,
            (0, 1),
            axis,
            pivot,
            Some((-open_rad, 1.9 - open_rad)),
            (damping, friction),
        )],
    )
}

/// A 0.3 x 0.3 x 0.15 m pot with a 1 cm thick lid on it that lifts straight up by `lift_m`
/// (a pot lid; 0.9 kg at the test density).
pub fn pot_with_lifting_lid(lift_m: f64) -> TestAsset {
    asset(
        "pot_with_lifting_lid",
        vec![
            PartSpec::cuboid("pot", [-0.15, -0.15, 0.0], [0.15, 0.15, 0.15]),
            PartSpec::cuboid("lid", [-0.15, -0.15, 0.15], [0.15, 0.15, 0.16]),
        ],
        vec![joint(
            "lid_lift",
            JointKind::Prismatic,
            (0, 1),
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 0.15],
            Some((0.0, lift_m)),
            (0.9, 0.01),
        )],
    )
}

/// A carcass (five boards, open at the front, -y) with a drawer sliding out along -y by up to
/// 0.3 m.
pub fn drawer_in_carcass(damping: f64, friction: f64) -> TestAsset {
    drawer_asset(damping, friction, None)
}

/// The drawer asset with a rail fixed to the carcass `gap_m` in front of the drawer: the rail
/// blocks it (a sibling contact, not excluded).
pub fn drawer_blocked_by_rail(gap_m: f64) -> TestAsset {
    drawer_asset(2.0, 0.5, Some(gap_m))
}

fn drawer_asset(damping: f64, friction: f64, rail_gap_m: Option<f64>) -> TestAsset {
    let t = 0.02;
    let carcass = PartSpec::boxes(
        "carcass",
        &[
            ([-0.3, -0.25, 0.0], [0.3, 0.25, t]),                // bottom
            ([-0.3, -0.25, 0.4 - t], [0.3, 0.25, 0.4]),          // top
            ([-0.3, -0.25, t], [-0.3 + t, 0.25, 0.4 - t]),       // left
            ([0.3 - t, -0.25, t], [0.3, 0.25, 0.4 - t]),         // right
            ([-0.3 + t, 0.25 - t, t], [0.3 - t, 0.25, 0.4 - t]), // back
        ],
    );
    let c = 0.002; // clearance
    let drawer = PartSpec::boxes(
        "drawer",
        &[
            ([-0.28 + c, -0.25, t + c], [0.28 - c, -0.23, 0.3]), // front panel
            ([-0.28 + c, -0.23, t + c], [0.28 - c, 0.2, t + c + 0.015]), // floor
        ],
    );
    let mut parts = vec![carcass, drawer];
    let mut joints = vec![joint(
        "drawer_slide",
        JointKind::Prismatic,
        (0, 1),
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 0.15],
        Some((0.0, 0.3)),
        (damping, friction),
    )];
    if let Some(gap) = rail_gap_m {
        parts.push(PartSpec::cuboid(
            "rail",
            [-0.3, -0.25 - gap - 0.02, 0.1],
            [0.3, -0.25 - gap, 0.14],
        ));
        joints.push(joint(
            "rail_weld",
            JointKind::Fixed,
            (0, 2),
            [0.0, 0.0, 1.0],
            [0.0, -0.3, 0.12],
            None,
            (0.0, 0.0),
        ));
    }
    asset("drawer", parts, joints)
}

/// A 0.6 x 0.4 x 0.6 m cabinet with a door on a vertical hinge at its left front edge (axis -z:
/// positive angles open it outward), closed at rest, range [0, 1.6] rad.
pub fn door_cabinet(damping: f64, friction: f64) -> TestAsset {
    asset(
        "door_cabinet",
        vec![
            PartSpec::cuboid("body", [-0.3, -0.2, 0.0], [0.3, 0.2, 0.6]),
            PartSpec::cuboid("door", [-0.3, -0.22, 0.0], [0.3, -0.2, 0.6]),
        ],
        vec![joint(
            "door_hinge",
            JointKind::Revolute,
            (0, 1),
            [0.0, 0.0, -1.0],
            [-0.3, -0.21, 0.3],
            Some((0.0, 1.6)),
            (damping, friction),
        )],
    )
}

/// A cabinet with two doors meeting in the middle (left hinge axis -z, right hinge axis +z),
/// a drawer below them, and a knob on the left door on its own revolute joint. The doors
/// overlap by `overlap_m` at the middle (0 = they just touch).
pub fn two_door_cabinet(overlap_m: f64) -> TestAsset {
    let o = overlap_m / 2.0;
    let t = 0.02;
    asset(
        "two_door_cabinet",
        vec![
            PartSpec::boxes(
                "body",
                &[
                    ([-0.4, -0.25, 0.0], [0.4, 0.25, t]),
                    ([-0.4, -0.25, 0.8 - t], [0.4, 0.25, 0.8]),
                    ([-0.4, -0.25, t], [-0.4 + t, 0.25, 0.8 - t]),
                    ([0.4 - t, -0.25, t], [0.4, 0.25, 0.8 - t]),
                    ([-0.4 + t, 0.25 - t, t], [0.4 - t, 0.25, 0.8 - t]),
                    ([-0.4 + t, -0.25, 0.25], [0.4 - t, 0.25 - t, 0.25 + t]),
                ],
            ),
            PartSpec::cuboid("left_door", [-0.4, -0.27, 0.27], [o, -0.25, 0.8]),
            PartSpec::cuboid("right_door", [-o, -0.27, 0.27], [0.4, -0.25, 0.8]),
            PartSpec::boxes(
                "drawer",
                &[
                    ([-0.37, -0.27, 0.03], [0.37, -0.25, 0.24]),
                    ([-0.37, -0.25, 0.03], [0.37, 0.2, 0.05]),
                ],
            ),
            PartSpec::cuboid("knob", [-0.1, -0.3, 0.5], [-0.06, -0.27, 0.54]),
        ],
        vec![
            joint(
                "left_hinge",
                JointKind::Revolute,
                (0, 1),
                [0.0, 0.0, -1.0],
                [-0.4, -0.26, 0.5],
                Some((0.0, 1.5)),
                (0.5, 0.2),
            ),
            joint(
                "right_hinge",
                JointKind::Revolute,
                (0, 2),
                [0.0, 0.0, 1.0],
                [0.4, -0.26, 0.5],
                Some((0.0, 1.5)),
                (0.5, 0.2),
            ),
            joint(
                "drawer_slide",
                JointKind::Prismatic,
                (0, 3),
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 0.1],
                Some((0.0, 0.35)),
                (5.0, 1.0),
            ),
            joint(
                "knob_turn",
                JointKind::Revolute,
                (1, 4),
                [0.0, -1.0, 0.0],
                [-0.08, -0.28, 0.52],
                Some((-FRAC_PI_2, FRAC_PI_2)),
                (0.01, 0.02),
            ),
        ],
    )
}

/// A heavy bar on a horizontal hinge, horizontal at rest, wide limits, no damping, no friction:
/// an undamped pendulum.
pub fn free_pendulum() -> TestAsset {
    let mut bar = PartSpec::cuboid("bar", [0.0, -0.02, 0.48], [0.5, 0.02, 0.52]);
    bar.density = 7800.0;
    asset(
        "pendulum",
        vec![
            PartSpec::cuboid("post", [-0.05, -0.05, 0.0], [0.0, 0.05, 0.6]),
            bar,
        ],
        vec![joint(
            "bar_hinge",
            JointKind::Revolute,
            (0, 1),
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.5],
            Some((-3.0, 3.0)),
            (0.0, 0.0),
        )],
    )
}

/// The door cabinet with a bumper welded to the body that reaches `overlap_m` into the closed
/// door from behind (a sibling of the door: it collides unless the pair is excluded).
pub fn door_cabinet_with_bumper(overlap_m: f64) -> TestAsset {
    asset(
        "door_cabinet_with_bumper",
        vec![
            PartSpec::cuboid("body", [-0.3, -0.2, 0.0], [0.3, 0.2, 0.6]),
            PartSpec::cuboid("door", [-0.3, -0.22, 0.0], [0.3, -0.2, 0.6]),
            PartSpec::cuboid("bumper", [0.1, -0.2 - overlap_m, 0.2], [0.25, -0.1, 0.4]),
        ],
        vec![
            joint(
                "door_hinge",
                JointKind::Revolute,
                (0, 1),
                [0.0, 0.0, -1.0],
                [-0.3, -0.21, 0.3],
                Some((0.0, 1.6)),
                (0.2, 0.05),
            ),
            joint(
                "bumper_weld",
                JointKind::Fixed,
                (0, 2),
                [0.0, 0.0, 1.0],
                [0.175, -0.15, 0.3],
                None,
                (0.0, 0.0),
            ),
        ],
    )
}

/// The drawer with a handle hanging from a pin on its front (axis x, centre of mass 4 cm below
/// the pin, so gravity has no load on it at rest), range [-1.2, 1.2] rad.
pub fn drawer_with_hanging_handle(handle_damping: f64, handle_friction: f64) -> TestAsset {
    let mut drawer = drawer_in_carcass(2.0, 0.5);
    let handle = PartSpec::cuboid("handle", [-0.05, -0.28, 0.12], [0.05, -0.26, 0.2]);
    let mut parts: Vec<PartSpec> = vec![
        PartSpec {
            name: "carcass",
            hulls: drawer.colliders[0].clone(),
            density: DENSITY,
        },
        PartSpec {
            name: "drawer",
            hulls: drawer.colliders[1].clone(),
            density: DENSITY,
        },
    ];
    parts.push(handle);
    drawer.record.joints.push(joint(
        "handle_pin",
        JointKind::Revolute,
        (1, 2),
        [1.0, 0.0, 0.0],
        [0.0, -0.27, 0.2],
        Some((-1.2, 1.2)),
        (handle_damping, handle_friction),
    ));
    asset("drawer_with_handle", parts, drawer.record.joints)
}
