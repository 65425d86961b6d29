use glam::{DMat3, DVec3, Vec3};
use parry3d::transformation::vhacd::{VHACD, VHACDParameters};
use parry3d::transformation::voxelization::VoxelSet;

use crate::{
    Aabb, GeometryError, GeometryResult, MAX_VOXEL_RESOLUTION, TriMesh, box_axes,
    connected_components, convex_hull, parallel_map, sample_points, solid_mass_properties,
};

/// Parameters of [`convex_decomposition`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvexParams {
    /// Most hulls returned for the whole mesh.
    pub max_hulls: usize,
    /// Voxel resolution of the solid volume estimate and of V-HACD.
    pub voxel_resolution: u32,
    /// How much a component's hull volume may exceed its solid volume (relative) before the
    /// component is decomposed; also V-HACD's concavity threshold.
    pub concavity_tolerance: f64,
}

impl Default for ConvexParams {
    /// At most 16 hulls, resolution 64, 5 % concavity tolerance.
    fn default() -> Self {
        Self {
            max_hulls: 16,
            voxel_resolution: 64,
            concavity_tolerance: 0.05,
        }
    }
}

/// A hull with its volume.
struct Hull {
    mesh: TriMesh,
    volume_m3: f64,
}

impl Hull {
    fn new(mesh: TriMesh) -> Self {
        let volume_m3 = signed_volume(&mesh);
        Self { mesh, volume_m3 }
    }
}

/// Approximate convex decomposition of `mesh` into closed convex hulls of positive volume.
///
/// The mesh is split into connected components ([`connected_components`]). A component whose
/// convex hull exceeds its solid volume ([`solid_mass_properties`]) by at most
/// `concavity_tolerance` is replaced by that hull; any other is decomposed by parry3d's V-HACD
/// (hull of the mesh clipped to each part, or of the part's voxels where that fails; the
/// component's single hull if V-HACD fails altogether). A flat component (a zero-thickness
/// panel) gets a slab 1 % of its size thick; hulls below 1e-6
/// of their component's hull volume are dropped. While there are more than `max_hulls` hulls,
/// the smallest is merged into the hull whose bounds are nearest its centre (the hull of both
/// point sets), so no region loses its collision shape. Components are worked on all cores;
/// deterministic.
///
/// Errors: invalid parameters; [`GeometryError::Degenerate`] if no hull with volume remains.
pub fn convex_decomposition(mesh: &TriMesh, params: &ConvexParams) -> GeometryResult<Vec<TriMesh>> {
    let resolution = params.voxel_resolution as usize;
    let tolerance = params.concavity_tolerance;
    if params.max_hulls == 0
        || !(1..=MAX_VOXEL_RESOLUTION).contains(&resolution)
        || !(tolerance.is_finite() && tolerance >= 0.0)
    {
        return Err(GeometryError::InvalidParameter(format!(
            "convex decomposition needs max_hulls > 0, a voxel resolution in \
             1..={MAX_VOXEL_RESOLUTION} and a non-negative tolerance, got {params:?}"
        )));
    }
    let components = connected_components(mesh);
    let per_component = parallel_map(&components, |faces| {
        component_hulls(&mesh.submesh(faces), params)
    });
    let mut hulls: Vec<Hull> = per_component.into_iter().flatten().collect();
    if hulls.is_empty() {
        return Err(GeometryError::Degenerate);
    }
    merge_down(&mut hulls, params.max_hulls);
    Ok(hulls.into_iter().map(|h| h.mesh).collect())
}

/// The hulls of one connected component: its own hull when it is nearly convex, a slab when it
/// is flat, else V-HACD's parts.
fn component_hulls(component: &TriMesh, params: &ConvexParams) -> Vec<Hull> {
    if component.area() <= 0.0 {
        return Vec::new();
    }
    let extent = component.bounds().max_extent();
    let hull = convex_hull(&component.positions)
        .ok()
        .map(Hull::new)
        .filter(|h| h.volume_m3.abs() > 1e-9 * extent.powi(3));
    let Some(hull) = hull else {
        // Flat (a zero-thickness panel): a thin slab; a line or a point: nothing to collide.
        return slab_hull(component).map(Hull::new).into_iter().collect();
    };
    let resolution = params.voxel_resolution as usize;
    let solid_volume =
        solid_mass_properties(component, resolution).map_or(0.0, |(m, _)| m.volume_m3);
    if hull.volume_m3 <= solid_volume * (1.0 + params.concavity_tolerance) {
        return vec![hull];
    }
    let min_volume = 1e-6 * hull.volume_m3;
    let parts: Vec<Hull> = decompose(component, params)
        .unwrap_or_default()
        .into_iter()
        .filter(|h| h.volume_m3 > min_volume)
        .collect();
    if parts.is_empty() {
        vec![hull] // V-HACD failed: the single hull still covers the component
    } else {
        parts
    }
}

/// Thickness of the collision slab of a flat component, as a fraction of its largest extent.
const SLAB_THICKNESS_FRACTION: f64 = 0.01;

/// The hull of a flat component (a zero-thickness panel: a door or lid modelled as one quad)
/// thickened along its plane's normal by 1 % of its largest extent, centred on the panel, so
/// the panel still collides; `None` for a component without a plane (a line).
fn slab_hull(component: &TriMesh) -> Option<TriMesh> {
    let plane = crate::fit_plane(&component.positions).ok()?;
    let half = 0.5 * SLAB_THICKNESS_FRACTION * component.bounds().max_extent();
    if !(half > 0.0 && half.is_finite()) {
        return None;
    }
    let points: Vec<DVec3> = component
        .positions
        .iter()
        .flat_map(|p| [*p + plane.normal * half, *p - plane.normal * half])
        .collect();
    convex_hull(&points).ok()
}

/// V-HACD on one component, in `f32` relative to its centroid and in the frame of its tight box
/// ([`box_axes`]), so that V-HACD's axis-aligned voxels follow the part's own edges whatever
/// its pose (a turned cabinet decomposes into the same panels as an upright one). Each part's
/// hull is the hull of the mesh clipped to the part's surface voxels, or of those voxels'
/// corners if that fails. `None` if V-HACD panicked (a third-party failure must not take the
/// service down).
fn decompose(component: &TriMesh, params: &ConvexParams) -> Option<Vec<Hull>> {
    let centroid =
        component.positions.iter().sum::<DVec3>() / component.positions.len().max(1) as f64;
    let [a, b, c] = box_axes(&sample_points(component, 2000, 0xb0c5));
    // Rows are the box axes: box_from_object.
    let box_from_object = DMat3::from_cols(a, b, c).transpose();
    let object_from_box = box_from_object.transpose();
    let points: Vec<Vec3> = component
        .positions
        .iter()
        .map(|p| (box_from_object * (*p - centroid)).as_vec3())
        .collect();
    let vhacd_params = VHACDParameters {
        resolution: params.voxel_resolution,
        concavity: params.concavity_tolerance as f32,
        max_convex_hulls: u32::try_from(params.max_hulls).unwrap_or(u32::MAX),
        ..VHACDParameters::default()
    };
    let to_world = |vertices: &[Vec3]| -> Vec<DVec3> {
        vertices
            .iter()
            .map(|v| centroid + object_from_box * v.as_dvec3())
            .collect()
    };
    let run = || {
        let decomposition = VHACD::decompose(&vhacd_params, &points, &component.triangles, true);
        decomposition
            .voxel_parts()
            .iter()
            .filter_map(|part| {
                let clipped = part.compute_primitive_intersections(&points, &component.triangles);
                convex_hull(&to_world(&clipped))
                    .or_else(|_| convex_hull(&to_world(&surface_voxel_corners(part))))
                    .ok()
                    .map(Hull::new)
            })
            .collect()
    };
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).ok()
}

/// Corners of the surface voxels of a V-HACD part.
fn surface_voxel_corners(part: &VoxelSet) -> Vec<Vec3> {
    let mut corners = Vec::new();
    for voxel in part.voxels().iter().filter(|v| v.is_on_surface) {
        let centre = voxel.coords.as_vec3();
        for dz in [-0.5, 0.5] {
            for dy in [-0.5, 0.5] {
                for dx in [-0.5, 0.5] {
                    corners.push(part.origin + (centre + Vec3::new(dx, dy, dz)) * part.scale);
                }
            }
        }
    }
    corners
}

/// Merges the smallest hull into its nearest neighbour until at most `max_hulls` remain.
fn merge_down(hulls: &mut Vec<Hull>, max_hulls: usize) {
    while hulls.len() > max_hulls.max(1) {
        let smallest = (0..hulls.len())
            .min_by(|&a, &b| hulls[a].volume_m3.total_cmp(&hulls[b].volume_m3))
            .expect("more than one hull");
        let centre = hulls[smallest].mesh.bounds().center();
        let nearest = (0..hulls.len())
            .filter(|&j| j != smallest)
            .min_by(|&a, &b| {
                distance_to_box(centre, hulls[a].mesh.bounds())
                    .total_cmp(&distance_to_box(centre, hulls[b].mesh.bounds()))
            })
            .expect("more than one hull");
        let removed = hulls.remove(smallest);
        let target = if nearest > smallest {
            nearest - 1
        } else {
            nearest
        };
        let mut points = hulls[target].mesh.positions.clone();
        points.extend_from_slice(&removed.mesh.positions);
        if let Ok(merged) = convex_hull(&points) {
            hulls[target] = Hull::new(merged);
        }
    }
}

fn distance_to_box(p: DVec3, b: Aabb) -> f64 {
    (p.clamp(b.min, b.max) - p).length()
}

fn signed_volume(mesh: &TriMesh) -> f64 {
    let reference = mesh.bounds().center();
    (0..mesh.triangle_count())
        .map(|i| {
            let [a, b, c] = mesh.corners(i).map(|p| p - reference);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {

    use super::*;
    use crate::MassProperties;
    use crate::test_shapes::{l_prism, two_boxes, unit_box};
    use glam::DMat4;

    fn volumes(hulls: &[TriMesh]) -> Vec<f64> {
        hulls
            .iter()
            .map(|h| {
                MassProperties::from_closed_mesh(h)
                    .expect("every hull is closed with positive volume")
                    .volume_m3
            })
            .collect()
    }

    #[test]
    fn a_box_is_its_own_single_hull() {
        let hulls = convex_decomposition(
            &unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)),
            &ConvexParams::default(),
        )
        .unwrap();
        assert_eq!(hulls.len(), 1);
        assert!((volumes(&hulls)[0] - 6.0).abs() < 1e-9);
    }

    #[test]
    fn two_disjoint_boxes_give_two_hulls() {
        let hulls = convex_decomposition(&two_boxes(), &ConvexParams::default()).unwrap();
        assert_eq!(hulls.len(), 2);
        for v in volumes(&hulls) {
            assert!((v - 1.0).abs() < 1e-9);
        }
        assert!(hulls[0].bounds().max.x <= 1.0 && hulls[1].bounds().min.x >= 3.0);
    }

    #[test]
    fn l_prism_splits_into_hulls_close_to_its_volume() {
        // Hull 3.5 m^3 vs solid 3 m^3 is 17 % over the 5 % tolerance, so V-HACD runs.
        let params = ConvexParams::default();
        let hulls = convex_decomposition(&l_prism(), &params).unwrap();
        assert!(
            hulls.len() >= 2 && hulls.len() <= params.max_hulls,
            "{}",
            hulls.len()
        );
        let total: f64 = volumes(&hulls).iter().sum();
        assert!((total - 3.0).abs() < 0.3, "total hull volume {total}");
        assert_eq!(hulls, convex_decomposition(&l_prism(), &params).unwrap());
    }

    #[test]
    fn components_decomposed_on_all_cores_come_back_in_mesh_order() {
        // Three concave components, each moved further along x: the hulls of the whole are
        // those of each component alone, in the order of the components.
        let params = ConvexParams {
            max_hulls: 64,
            ..ConvexParams::default()
        };
        let pieces: Vec<TriMesh> = [0.0, 5.0, 10.0]
            .iter()
            .map(|x| l_prism().transformed(&DMat4::from_translation(DVec3::new(*x, 0.0, 0.0))))
            .collect();
        let whole = convex_decomposition(&TriMesh::merge(&pieces), &params).unwrap();
        let alone: Vec<TriMesh> = pieces
            .iter()
            .flat_map(|p| convex_decomposition(p, &params).unwrap())
            .collect();
        assert!(alone.len() >= 6, "{}", alone.len());
        assert_eq!(whole, alone);
    }

    #[test]
    fn merging_down_to_one_hull_gives_the_full_hull() {
        let params = ConvexParams {
            max_hulls: 1,
            ..ConvexParams::default()
        };
        let hulls = convex_decomposition(&l_prism(), &params).unwrap();
        assert_eq!(hulls.len(), 1);
        assert!(
            (volumes(&hulls)[0] - 3.5).abs() < 0.05,
            "{:?}",
            volumes(&hulls)
        );
        let merged = convex_decomposition(&two_boxes(), &params).unwrap();
        // Hull of both cubes: a 4 x 1 x 1 box.
        assert!((volumes(&merged)[0] - 4.0).abs() < 1e-9);
    }

    #[test]
    fn a_flat_panel_gets_a_thin_slab_and_bad_parameters_are_errors() {
        // A zero-thickness lid: one double-sided quad.
        let square = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            vec![[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]],
        )
        .unwrap();
        let slab = convex_decomposition(&square, &ConvexParams::default()).unwrap();
        assert_eq!(slab.len(), 1);
        let b = slab[0].bounds();
        // 1 x 1 in the panel's plane, 1 % of its extent thick, centred on it.
        assert!(
            (b.extents() - DVec3::new(1.0, 1.0, 0.01)).length() < 1e-9,
            "{b:?}"
        );
        assert!((b.center().z).abs() < 1e-12);
        assert!((volumes(&slab)[0] - 0.01).abs() < 1e-9);
        let line = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)],
            vec![[0, 1, 2]],
        )
        .unwrap();
        assert_eq!(
            convex_decomposition(&line, &ConvexParams::default()),
            Err(GeometryError::Degenerate)
        );
        let zero = ConvexParams {
            max_hulls: 0,
            ..ConvexParams::default()
        };
        assert!(matches!(
            convex_decomposition(&two_boxes(), &zero),
            Err(GeometryError::InvalidParameter(_))
        ));
    }
}
