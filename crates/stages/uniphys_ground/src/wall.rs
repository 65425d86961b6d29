//! How much material a part holds. Real parts are rarely solid through: an oven is sheet metal,
//! a cabinet is panels, a bottle is a thin plastic skin, and a part drawn as an open or
//! zero-thickness surface has no volume at all. A part is walls along its surface: where the
//! model draws both faces of a wall, the material between them; elsewhere a wall as thick as the
//! part's material is usually made (thicker for larger parts). A closed part keeps its solid
//! when that is less (a small solid knob).

use uniphys_geometry::{MassProperties, TriMesh, VolumeMethod, WallSamples};
use uniphys_types::MaterialCategory;

/// Parts smaller than this (largest side, m) get thinner walls than their material's usual:
/// the square root of their size ratio, down to [`MIN_WALL_SIZE_FACTOR`].
const WALL_REFERENCE_SIZE_M: f64 = 0.5;
/// The thinnest wall, as a fraction of the material's usual one.
const MIN_WALL_SIZE_FACTOR: f64 = 0.5;
/// Parts smaller than this (largest side, m) are solid: knobs, buttons, caps and small handles
/// are moulded or cast through, their walls would be most of them.
const SOLID_PART_SIZE_M: f64 = 0.05;

/// Brass parts are cast or forged (a faucet's body, a valve, a fitting), not pressed from sheet:
/// their walls are about 3 mm.
const CAST_BRASS_WALL_M: f64 = 0.003;

/// The usual wall thickness of parts made of `material` (`subtype` refines it), m: appliance
/// sheet steel 0.8 mm, cast brass 3 mm, moulded plastic 2.5 mm, furniture board 18 mm, glass
/// 4 mm.
fn usual_wall_m(material: MaterialCategory, subtype: &str) -> f64 {
    if material == MaterialCategory::Metal && subtype.to_ascii_lowercase().contains("brass") {
        return CAST_BRASS_WALL_M;
    }
    match material {
        MaterialCategory::Metal => 0.0008,
        MaterialCategory::Fabric => 0.001,
        MaterialCategory::Plastic => 0.0025,
        MaterialCategory::Leather => 0.002,
        MaterialCategory::Glass => 0.004,
        MaterialCategory::Rubber => 0.005,
        MaterialCategory::Ceramics => 0.006,
        MaterialCategory::Wood => 0.018,
        MaterialCategory::Stone => 0.02,
        MaterialCategory::Foam => 0.03,
        MaterialCategory::Concrete => 0.05,
        MaterialCategory::Other => 0.003,
    }
}

/// Wall thickness of a part of `material` (of `subtype`, possibly empty) whose largest side is
/// `largest_side_m`, m.
#[must_use]
pub fn wall_thickness_m(material: MaterialCategory, subtype: &str, largest_side_m: f64) -> f64 {
    let ratio = (largest_side_m.max(0.0) / WALL_REFERENCE_SIZE_M).sqrt();
    usual_wall_m(material, subtype) * ratio.clamp(MIN_WALL_SIZE_FACTOR, 1.0)
}

/// What a part's mass model is made from.
#[derive(Debug, Clone, Copy)]
pub struct PartMassInput<'a> {
    /// The solid the surface encloses: exact when closed, voxels when open.
    pub solid: &'a MassProperties,
    /// How `solid` was found.
    pub solid_method: VolumeMethod,
    /// The surface with the gaps between its walls (`None` without area).
    pub walls: Option<&'a WallSamples>,
    /// The part's convex hulls: together, what an open part encloses.
    pub hulls: &'a [TriMesh],
    /// The part's material.
    pub material: MaterialCategory,
    /// Its subtype (`steel`, `brass`), possibly empty.
    pub subtype: &'a str,
    /// Largest side of the part's box, m.
    pub largest_side_m: f64,
    /// How much of what the walls enclose is filled: the object kind's `interior_fill`, or
    /// `None` when the kind is unknown (a closed part is then taken as the solid it bounds).
    pub interior_fill: Option<f64>,
}

/// The mass properties a part's material fills, per unit density, and how they were found.
#[derive(Debug, Clone, PartialEq)]
pub struct PartMassModel {
    /// Volume, centre of mass and inertia per unit density.
    pub mass: MassProperties,
    /// `closed_mesh`, `voxels_<n>`, `shell_<thickness>mm` or `shell_<thickness>mm_fill_<f>`,
    /// for the report.
    pub method: String,
}

/// The part as walls along its surface (at most [`wall_thickness_m`] thick) plus the
/// `interior_fill` share of what they enclose (the closed solid, or the hulls of an open part;
/// all of it for parts under 5 cm across). A closed part keeps its solid when that is
/// less (a panel modelled with its real thickness) or when the object's kind is unknown (a
/// closed mesh is then taken at its word, as the solid it bounds). Without wall samples (no
/// area) the solid stands.
#[must_use]
pub fn part_mass_model(input: &PartMassInput<'_>) -> PartMassModel {
    let solid_model = || PartMassModel {
        mass: *input.solid,
        method: input.solid_method.to_string(),
    };
    let thickness_m = wall_thickness_m(input.material, input.subtype, input.largest_side_m);
    if !walls_matter(input.solid_method, input.interior_fill) {
        return solid_model();
    }
    let closed = input.solid_method == VolumeMethod::ClosedMesh;
    let Some(wall) = input.walls.and_then(|w| w.with_wall(thickness_m)) else {
        return solid_model();
    };
    if closed && input.solid.volume_m3 <= wall.volume_m3 {
        return solid_model();
    }
    let method = format!("shell_{:.1}mm", thickness_m * 1000.0);
    let interior_fill = if input.largest_side_m < SOLID_PART_SIZE_M {
        1.0
    } else {
        input.interior_fill.unwrap_or(0.0)
    };
    let interior = if interior_fill <= 0.0 {
        None
    } else if closed {
        Some(*input.solid)
    } else {
        hulls_together(input.hulls)
    };
    match interior {
        Some(inside) if inside.volume_m3 > wall.volume_m3 => {
            // The walls take their own share of the enclosed volume; the rest is filled.
            let fill = interior_fill * (1.0 - wall.volume_m3 / inside.volume_m3);
            let mass = MassProperties::combined(&[(wall, 1.0), (inside, fill)]).unwrap_or(wall);
            PartMassModel {
                mass,
                method: format!("{method}_fill_{interior_fill:.2}"),
            }
        }
        _ => PartMassModel { mass: wall, method },
    }
}

/// Whether a part's walls can change its mass model: not for a closed part of an object of
/// unknown kind (`interior_fill` `None`), which is the solid it bounds. Callers skip sampling
/// the walls when they cannot matter.
#[must_use]
pub fn walls_matter(solid_method: VolumeMethod, interior_fill: Option<f64>) -> bool {
    solid_method != VolumeMethod::ClosedMesh || interior_fill.is_some()
}

/// The solid the convex hulls make together (`None` without a closed hull).
fn hulls_together(hulls: &[TriMesh]) -> Option<MassProperties> {
    let bodies: Vec<(MassProperties, f64)> = hulls
        .iter()
        .filter_map(MassProperties::from_closed_mesh)
        .map(|hull| (hull, 1.0))
        .collect();
    MassProperties::combined(&bodies)
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::{DVec3, solid_mass_properties};

    use super::*;

    fn cuboid(size: DVec3) -> TriMesh {
        TriMesh::cuboid(DVec3::ZERO, size)
    }

    fn model_filled(
        mesh: &TriMesh,
        material: MaterialCategory,
        fill: Option<f64>,
    ) -> PartMassModel {
        let (solid, solid_method) = solid_mass_properties(mesh, 64).unwrap();
        let walls = WallSamples::of_mesh(mesh, 2000, 1);
        part_mass_model(&PartMassInput {
            solid: &solid,
            solid_method,
            walls: walls.as_ref(),
            hulls: &[],
            material,
            subtype: "",
            largest_side_m: mesh.bounds().extents().max_element(),
            interior_fill: fill,
        })
    }

    fn model(mesh: &TriMesh, material: MaterialCategory) -> PartMassModel {
        model_filled(mesh, material, Some(0.0))
    }

    #[test]
    fn a_closed_appliance_body_is_a_sheet_metal_wall_not_a_block_of_steel() {
        let body = cuboid(DVec3::new(0.7, 0.7, 1.8));
        let m = model(&body, MaterialCategory::Metal);
        assert!(m.method.starts_with("shell_"), "{}", m.method);
        let area = 2.0 * (0.7 * 0.7 + 2.0 * 0.7 * 1.8);
        let wall = wall_thickness_m(MaterialCategory::Metal, "", 1.8);
        assert!((m.mass.volume_m3 - area * wall).abs() < 1e-9 * area);
        // Steel at 7850 kg/m^3: tens of kilograms, where a solid body would weigh tonnes.
        let kg = m.mass.mass_kg(7850.0);
        assert!((30.0..150.0).contains(&kg), "{kg} kg");
    }

    #[test]
    fn a_board_with_its_real_thickness_keeps_its_solid_volume() {
        let board = cuboid(DVec3::new(0.6, 0.016, 0.8));
        let m = model(&board, MaterialCategory::Wood);
        assert_eq!(m.method, "closed_mesh");
        assert!((m.mass.volume_m3 - 0.6 * 0.016 * 0.8).abs() < 1e-12);
    }

    #[test]
    fn a_zero_thickness_lid_gets_a_wall_of_its_material() {
        let lid = TriMesh::new(
            vec![
                DVec3::ZERO,
                DVec3::new(0.4, 0.0, 0.0),
                DVec3::new(0.4, 0.3, 0.0),
                DVec3::new(0.0, 0.3, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]],
        )
        .unwrap();
        let m = model(&lid, MaterialCategory::Plastic);
        assert!(m.method.starts_with("shell_"), "{}", m.method);
        let wall = wall_thickness_m(MaterialCategory::Plastic, "", 0.4);
        assert!(
            (m.mass.volume_m3 - 0.12 * wall).abs() < 1e-12,
            "{}",
            m.mass.volume_m3
        );
    }

    #[test]
    fn a_knob_is_solid_even_on_a_hollow_object() {
        let knob = cuboid(DVec3::new(0.03, 0.03, 0.02));
        let m = model(&knob, MaterialCategory::Plastic);
        assert!(m.method.ends_with("_fill_1.00"), "{}", m.method);
        assert!((m.mass.volume_m3 - 0.03 * 0.03 * 0.02).abs() < 1e-12);
    }

    #[test]
    fn brass_is_cast_thicker_than_sheet_steel() {
        let brass = wall_thickness_m(MaterialCategory::Metal, "brass", 0.5);
        assert!((brass - CAST_BRASS_WALL_M).abs() < 1e-12);
        assert!(wall_thickness_m(MaterialCategory::Metal, "steel", 0.5) < 0.3 * brass);
    }

    #[test]
    fn small_parts_have_thinner_walls_down_to_half_the_usual() {
        let t = |size| wall_thickness_m(MaterialCategory::Plastic, "", size);
        assert!(t(0.1) < t(0.3) && t(0.3) < t(0.5));
        assert!((t(0.5) - 0.0025).abs() < 1e-12);
        assert!((t(100.0) - 0.0025).abs() < 1e-12);
        assert!((t(0.001) - 0.00125).abs() < 1e-12);
    }

    #[test]
    fn a_packed_device_fills_part_of_what_its_walls_enclose() {
        let base = cuboid(DVec3::new(0.33, 0.23, 0.02));
        let hollow = model(&base, MaterialCategory::Plastic);
        let packed = model_filled(&base, MaterialCategory::Plastic, Some(0.4));
        let solid = model_filled(&base, MaterialCategory::Plastic, Some(1.0));
        let unknown = model_filled(&base, MaterialCategory::Plastic, None);
        assert_eq!(
            unknown.method, "closed_mesh",
            "a closed mesh of no known kind is solid"
        );
        assert!(packed.method.ends_with("_fill_0.40"), "{}", packed.method);
        let enclosed = 0.33 * 0.23 * 0.02;
        let walls = hollow.mass.volume_m3;
        assert!((packed.mass.volume_m3 - (walls + 0.4 * (enclosed - walls))).abs() < 1e-12);
        // Filled through, the part is its solid again.
        assert!((solid.mass.volume_m3 - enclosed).abs() < 1e-12);
        assert!((packed.mass.com - DVec3::new(0.165, 0.115, 0.01)).length() < 0.01);
    }
}
