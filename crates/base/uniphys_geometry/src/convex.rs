use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec3;

use crate::vhacd::{ComponentFrame, first_copies, tight_extent};
use crate::{
    Aabb, GeometryError, GeometryResult, MAX_VOXEL_RESOLUTION, TriMesh, connected_components,
    convex_hull, parallel_map, solid_mass_properties,
};

/// Parameters of [`convex_decomposition`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvexParams {
    /// Most hulls returned for the whole mesh.
    pub max_hulls: usize,
    /// Voxels across a component for its solid volume estimate, and across the whole mesh for
    /// V-HACD (a component is cut at the mesh's voxel size, with at least 16 voxels across it).
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

/// A closed convex hull with its volume.
pub(crate) struct Hull {
    pub(crate) mesh: TriMesh,
    pub(crate) volume_m3: f64,
}

impl Hull {
    pub(crate) fn new(mesh: TriMesh) -> Self {
        let volume_m3 = signed_volume(&mesh);
        Self { mesh, volume_m3 }
    }
}

/// Approximate convex decomposition of `mesh` into closed convex hulls of positive volume.
///
/// The mesh is split into connected components ([`connected_components`]). A component whose
/// convex hull exceeds its solid volume ([`solid_mass_properties`]) by at most
/// `concavity_tolerance` is replaced by that hull; any other is decomposed by parry3d's V-HACD
/// at the mesh's voxel size (hull of the mesh clipped to each part, or of the part's voxels
/// where that fails; the component's single hull if V-HACD fails altogether). A flat component
/// (a zero-thickness panel) gets a slab 1 % of its size thick; hulls below 1e-6 of their
/// component's hull volume are dropped. While there are more than `max_hulls` hulls,
/// the smallest is merged into the hull whose bounds are nearest its centre (the hull of both
/// point sets), so no region loses its collision shape. Components are worked on all cores, and
/// V-HACD runs once for a shape that repeats ([`convex_decompositions`]). Deterministic.
///
/// Errors: invalid parameters; [`GeometryError::Degenerate`] if no hull with volume remains.
pub fn convex_decomposition(mesh: &TriMesh, params: &ConvexParams) -> GeometryResult<Vec<TriMesh>> {
    convex_decompositions(&[mesh], params, &|_, _| {})?
        .pop()
        .expect("one result per mesh")
}

/// [`convex_decomposition`] of several meshes (the parts of one object) at once: the connected
/// components of all of them are worked on all cores, and a component that is a moved copy of
/// an earlier one (the same triangles, the same vertices in its own box frame to 1e-4 of its
/// size: another key of a keyboard, another knob of an oven) gets that component's V-HACD hulls
/// moved onto it instead of a V-HACD run of its own. The first of each shape is decomposed
/// exactly as it would be alone in its mesh. One result per mesh, in order. `progress` is told
/// how many V-HACD runs have finished of how many, as they finish (from any thread).
///
/// Errors: invalid parameters (for all); per mesh, [`GeometryError::Degenerate`] if no hull
/// with volume remains.
pub fn convex_decompositions(
    meshes: &[&TriMesh],
    params: &ConvexParams,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> GeometryResult<Vec<GeometryResult<Vec<TriMesh>>>> {
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
    // Every component of every mesh, in mesh order, judged on all cores.
    let components: Vec<(usize, Vec<usize>)> = parallel_map(meshes, |m| connected_components(m))
        .into_iter()
        .enumerate()
        .flat_map(|(mesh, faces)| faces.into_iter().map(move |f| (mesh, f)))
        .collect();
    let judged = parallel_map(&components, |(mesh, faces)| {
        judge(&meshes[*mesh].submesh(faces), params)
    });
    // V-HACD on the first component of each concave shape, on all cores; its hulls moved onto
    // the later copies.
    // Each is cut at its mesh's voxel size: the size of every mesh with a concave component.
    let mut concave = vec![false; meshes.len()];
    for ((mesh, _), j) in components.iter().zip(&judged) {
        concave[*mesh] |= matches!(j, Judged::Concave { .. });
    }
    let sized: Vec<(bool, &TriMesh)> = concave.into_iter().zip(meshes.iter().copied()).collect();
    let mesh_extents: Vec<Option<f64>> =
        parallel_map(&sized, |&(concave, m)| concave.then(|| tight_extent(m)));
    let (frames, resolutions): (Vec<&ComponentFrame>, Vec<u32>) = components
        .iter()
        .zip(&judged)
        .filter_map(|((mesh, _), j)| match j {
            Judged::Concave { frame, .. } => Some((
                frame.as_ref(),
                component_resolution(
                    params.voxel_resolution,
                    frame.extent(),
                    mesh_extents[*mesh].unwrap_or_default(),
                ),
            )),
            Judged::Done(_) => None,
        })
        .unzip();
    let first = first_copies(&frames);
    let (originals, copies): (Vec<usize>, Vec<usize>) =
        (0..frames.len()).partition(|&k| first[k] == k);
    let mut outcomes: Vec<Option<Vec<Hull>>> = frames.iter().map(|_| None).collect();
    let finished = AtomicUsize::new(0);
    let runs = parallel_map(&originals, |&k| {
        let hulls = frames[k].decompose(&ConvexParams {
            voxel_resolution: resolutions[k],
            ..*params
        });
        progress(
            finished.fetch_add(1, Ordering::Relaxed) + 1,
            originals.len(),
        );
        hulls
    });
    for (k, hulls) in originals.iter().zip(runs) {
        outcomes[*k] = hulls;
    }
    let moved = parallel_map(&copies, |&k| {
        outcomes[first[k]]
            .as_ref()
            .map(|hulls| frames[k].moved_hulls(frames[first[k]], hulls))
    });
    for (k, hulls) in copies.into_iter().zip(moved) {
        outcomes[k] = hulls;
    }
    let mut outcomes = outcomes.into_iter();
    // Each mesh's hulls in the order of its components.
    let mut per_mesh: Vec<Vec<Hull>> = meshes.iter().map(|_| Vec::new()).collect();
    for ((mesh, _), judged) in components.iter().zip(judged) {
        let hulls = match judged {
            Judged::Done(hulls) => hulls,
            Judged::Concave { hull, .. } => {
                let min_volume = 1e-6 * hull.volume_m3;
                let parts: Vec<Hull> = outcomes
                    .next()
                    .flatten()
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
        };
        per_mesh[*mesh].extend(hulls);
    }
    Ok(per_mesh
        .into_iter()
        .map(|mut hulls| {
            if hulls.is_empty() {
                return Err(GeometryError::Degenerate);
            }
            merge_down(&mut hulls, params.max_hulls);
            Ok(hulls.into_iter().map(|h| h.mesh).collect())
        })
        .collect())
}

/// The fewest voxels across a component V-HACD decomposes.
const MIN_COMPONENT_RESOLUTION: u32 = 16;

/// V-HACD's resolution for a component of largest extent `component_m` in a mesh of largest
/// extent `mesh_m` (both along their own tight boxes, so the same in any pose): `resolution`
/// voxels across the whole mesh, so a component gets the mesh's voxel size (a handle on a door
/// is cut as finely as the door, not 64 voxels across the handle alone), and at least
/// [`MIN_COMPONENT_RESOLUTION`] across itself.
fn component_resolution(resolution: u32, component_m: f64, mesh_m: f64) -> u32 {
    let share = if mesh_m > 0.0 {
        (component_m / mesh_m).min(1.0)
    } else {
        1.0
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "share is in [0, 1]"
    )]
    let scaled = (f64::from(resolution) * share).ceil() as u32;
    scaled.clamp(MIN_COMPONENT_RESOLUTION.min(resolution), resolution)
}

/// What a connected component needs.
enum Judged {
    /// Its hulls are known: none (no area), a slab (flat) or its own hull (nearly convex).
    Done(Vec<Hull>),
    /// Concave: V-HACD decomposes it in `frame`; `hull` is its single hull.
    Concave {
        hull: Hull,
        frame: Box<ComponentFrame>,
    },
}

/// Whether `component` needs V-HACD, and its hulls when it does not.
fn judge(component: &TriMesh, params: &ConvexParams) -> Judged {
    if component.area() <= 0.0 {
        return Judged::Done(Vec::new());
    }
    let extent = component.bounds().max_extent();
    let hull = convex_hull(&component.positions)
        .ok()
        .map(Hull::new)
        .filter(|h| h.volume_m3.abs() > 1e-9 * extent.powi(3));
    let Some(hull) = hull else {
        // Flat (a zero-thickness panel): a thin slab; a line or a point: nothing to collide.
        return Judged::Done(slab_hull(component).map(Hull::new).into_iter().collect());
    };
    let resolution = params.voxel_resolution as usize;
    let solid_volume =
        solid_mass_properties(component, resolution).map_or(0.0, |(m, _)| m.volume_m3);
    if hull.volume_m3 <= solid_volume * (1.0 + params.concavity_tolerance) {
        return Judged::Done(vec![hull]);
    }
    Judged::Concave {
        hull,
        frame: Box::new(ComponentFrame::of(component)),
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
        // Three concave components of different shapes (so none is a copy of another), each
        // further along x: the hulls of the whole are those of each component alone at the
        // whole's voxel size, in the order of the components.
        let params = ConvexParams {
            max_hulls: 64,
            ..ConvexParams::default()
        };
        let pieces: Vec<TriMesh> = [(0.0, 1.0), (2.5, 1.2), (5.0, 1.4)]
            .iter()
            .map(|(x, stretch)| {
                l_prism().transformed(&DMat4::from_scale_rotation_translation(
                    DVec3::new(1.0, *stretch, 1.0),
                    glam::DQuat::IDENTITY,
                    DVec3::new(*x, 0.0, 0.0),
                ))
            })
            .collect();
        let whole_mesh = TriMesh::merge(&pieces);
        let whole = convex_decomposition(&whole_mesh, &params).unwrap();
        let alone: Vec<TriMesh> = pieces
            .iter()
            .flat_map(|p| {
                let voxel_resolution = component_resolution(
                    params.voxel_resolution,
                    tight_extent(p),
                    tight_extent(&whole_mesh),
                );
                assert!(voxel_resolution < params.voxel_resolution);
                let at_whole_voxel = ConvexParams {
                    voxel_resolution,
                    ..params
                };
                convex_decomposition(p, &at_whole_voxel).unwrap()
            })
            .collect();
        assert!(alone.len() >= 6, "{}", alone.len());
        assert_eq!(whole, alone);
    }

    #[test]
    fn a_moved_copy_gets_the_hulls_of_its_original_and_v_hacd_runs_once_per_shape() {
        let params = ConvexParams {
            max_hulls: 64,
            ..ConvexParams::default()
        };
        let original = l_prism();
        let world_from_copy = DMat4::from_rotation_translation(
            glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            DVec3::new(10.0, -4.0, 2.0),
        );
        let copy = original.transformed(&world_from_copy);
        // Not a copy: the same triangles, stretched.
        let stretched = original.transformed(&DMat4::from_scale(DVec3::new(1.0, 1.3, 1.0)));
        let runs = std::sync::Mutex::new(Vec::new());
        let results =
            convex_decompositions(&[&original, &copy, &stretched], &params, &|done, total| {
                runs.lock().unwrap().push((done, total))
            })
            .unwrap();
        let [a, b, c] = [0, 1, 2].map(|i| results[i].as_ref().unwrap());
        // Two V-HACD runs: the original and the stretched one.
        let mut runs = runs.into_inner().unwrap();
        runs.sort_unstable();
        assert_eq!(runs, vec![(1, 2), (2, 2)]);
        // The first of a shape is decomposed as alone, and so is a different shape.
        assert_eq!(a, &convex_decomposition(&original, &params).unwrap());
        assert_eq!(c, &convex_decomposition(&stretched, &params).unwrap());
        // The copy's hulls are the original's, moved: the same volumes, and corners that are the
        // original's corners moved (a corner in the middle of a face may drop out).
        assert_eq!(a.len(), b.len());
        for (h, moved) in a.iter().zip(b) {
            let [v, w] = [h, moved].map(|m| volumes(std::slice::from_ref(m))[0]);
            assert!((v - w).abs() < 1e-6 * v, "{v} {w}");
            let corners: Vec<DVec3> = h
                .positions
                .iter()
                .map(|p| world_from_copy.transform_point3(*p))
                .collect();
            for p in &moved.positions {
                let nearest = corners
                    .iter()
                    .map(|c| (*c - *p).length())
                    .fold(f64::MAX, f64::min);
                assert!(nearest < 1e-6, "{p} is {nearest} from the moved corners");
            }
        }
    }

    #[test]
    fn a_component_is_cut_at_its_mesh_voxel_size_and_never_coarser_than_16_across() {
        assert_eq!(component_resolution(64, 2.0, 2.0), 64);
        assert_eq!(component_resolution(64, 0.5, 1.0), 32);
        assert_eq!(component_resolution(64, 0.01, 1.0), 16);
        assert_eq!(component_resolution(8, 0.01, 1.0), 8);
        assert_eq!(component_resolution(64, 1.0, 0.0), 64);
        // A small concave piece beside a large one (a handle on a door) is decomposed as it would
        // be alone at 16 voxels across; the large one as alone.
        let params = ConvexParams {
            max_hulls: 64,
            ..ConvexParams::default()
        };
        // The L spans 2 m; the small one, a tenth of it, stands clear above it.
        let large = l_prism();
        let small = l_prism().transformed(
            &(DMat4::from_translation(DVec3::new(0.0, 0.0, 1.5))
                * DMat4::from_scale(DVec3::splat(0.1))),
        );
        let both = TriMesh::merge(&[large.clone(), small.clone()]);
        let hulls = convex_decomposition(&both, &params).unwrap();
        let alone = |mesh: &TriMesh, voxel_resolution| {
            convex_decomposition(
                mesh,
                &ConvexParams {
                    voxel_resolution,
                    ..params
                },
            )
            .unwrap()
        };
        let (large_alone, small_at_16) = (alone(&large, 64), alone(&small, 16));
        assert_ne!(
            small_at_16,
            alone(&small, 64),
            "the L is cut differently at 16 and 64"
        );
        assert_eq!(hulls.len(), large_alone.len() + small_at_16.len());
        for hull in large_alone.iter().chain(&small_at_16) {
            assert!(hulls.contains(hull));
        }
        // Turned, the pair is cut the same way: the same hull volumes (a size taken on the
        // axis-aligned bounds would grow by the turn and cut both more coarsely).
        let turned = both.transformed(&DMat4::from_rotation_z(std::f64::consts::FRAC_PI_4));
        let mut upright_volumes = volumes(&hulls);
        let mut turned_volumes = volumes(&convex_decomposition(&turned, &params).unwrap());
        upright_volumes.sort_by(f64::total_cmp);
        turned_volumes.sort_by(f64::total_cmp);
        assert_eq!(upright_volumes.len(), turned_volumes.len());
        for (u, t) in upright_volumes.iter().zip(&turned_volumes) {
            assert!((u - t).abs() <= 1e-6 * u.abs().max(1e-9), "{u} {t}");
        }
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
