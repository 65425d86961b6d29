//! The built-in render-space segmenter: regions of a face-ID render that correspond to physical
//! parts, found without a model.
//!
//! Faces visible in the view are joined into regions (union-find) across every pair of
//! neighbouring pixels that lie on different faces, unless the two surfaces are separated there:
//!
//! - a gap or an occlusion: one surface lies in front of the other's tangent plane by more than
//!   a threshold relative to the pixel footprint and to the object's visible size, or one lies
//!   in front of the other's plane while the other lies behind the first's (a step or slot
//!   too shallow for the threshold; along an edge of one surface both lie on the same side);
//! - a concave crease: the surfaces' normals differ by more than the crease angle and each point
//!   lies in front of the other's tangent plane (where a handle meets a body, a drawer front sits
//!   in a frame, a lid sits on a box). Convex edges (each point behind the other's plane) never
//!   separate, so a box stays one region;
//! - a material change (face material ids);
//! - a colour change: the shaded colours differ by more than a threshold; where the normals
//!   differ, brightness is normalised first (Lambert shading only scales the colour).
//!
//! Each pixel pair votes. Faces first form surface patches where every pair between them is
//! smooth (near-parallel normals, nothing separating); then two patches are joined when a good
//! share of the pixel pairs between them is continuous. Voting between whole patches rather
//! than single triangles keeps a few ambiguous pixels (where an occlusion boundary runs into a
//! contact crease, say) from joining two finely tessellated parts. Regions smaller than a
//! fraction of the foreground are unlabelled.
//!
//! Known limits: parts flush with their neighbours and of the same material and colour are
//! separated only by a gap of at least about a pixel (a 2 mm gap on a 0.9 m cabinet at 512 px
//! is not); colour boundaries under strong per-face texture noise can leak.
//!
//! A concave crease inside one solid does not split it when the solid's other faces connect
//! both sides: an L-shaped block stays one region in views that see its L-shaped side (all
//! eight rig views do), and becomes two only in a view that sees nothing but the two faces
//! meeting at the inner corner. A part is cut out only when separations enclose it.

use uniphys_geometry::DVec3;

use super::masks::drop_small_regions;
use super::{LabelMap, Segmenter, ViewImage};
use crate::candidates::UnionFind;
use crate::views::PixelRays;
use crate::{DecomposeError, DecomposeResult};

/// Provider name of [`BuiltinSegmenter`].
pub const BUILTIN_PROVIDER: &str = "builtin-render-segmenter";

/// Heights above the other's tangent plane, in pixel footprints, that count as clearly in front
/// or behind in the mixed-sign test of [`classify`].
const MIXED_SIGN_PX: f64 = 0.5;

/// Continuous pixel pairs two surface patches need at least to be joined.
pub const MIN_CONTINUOUS_PAIRS: usize = 3;

/// Thresholds of the built-in segmenter; every distance is relative to the view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuiltinOptions {
    /// A surface more than this many pixel footprints (at its depth) in front of its neighbour's
    /// tangent plane is a gap or occlusion (default 2.0) ...
    pub gap_px: f64,
    /// ... unless that is less than this fraction of the object's visible size, the diagonal of
    /// the box around the view's visible points (default 0.005).
    pub gap_fraction: f64,
    /// Normals differing by more than this angle make a crease, which separates when concave
    /// (default 30 degrees, in radians).
    pub crease_angle_rad: f64,
    /// Faces whose normals differ by less than this angle, with nothing separating them, form
    /// one surface patch before patches vote on joining (default 15 degrees, in radians).
    pub smooth_angle_rad: f64,
    /// Neighbouring colours further apart than this (Euclidean, sRGB in [0, 1]) separate
    /// (default 0.15).
    pub colour_distance: f64,
    /// Normals closer than this angle compare colours as they are; other pairs compare colours
    /// brought to the same brightness (default 5 degrees, in radians).
    pub same_shading_angle_rad: f64,
    /// Two surface patches join when at least this share of the pixel pairs between them (and
    /// at least [`MIN_CONTINUOUS_PAIRS`]) is continuous (default 0.25).
    pub join_fraction: f64,
    /// Whether different face materials separate (default true).
    pub split_materials: bool,
    /// Regions smaller than this fraction of the foreground pixels are unlabelled (default
    /// 0.002).
    pub min_region_fraction: f64,
}

impl Default for BuiltinOptions {
    fn default() -> Self {
        Self {
            gap_px: 2.0,
            gap_fraction: 0.005,
            crease_angle_rad: 30f64.to_radians(),
            smooth_angle_rad: 15f64.to_radians(),
            colour_distance: 0.15,
            same_shading_angle_rad: 5f64.to_radians(),
            join_fraction: 0.25,
            split_materials: true,
            min_region_fraction: 0.002,
        }
    }
}

/// The built-in render-space segmenter (provider "builtin-render-segmenter"). Deterministic.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BuiltinSegmenter {
    /// Its thresholds.
    pub options: BuiltinOptions,
}

impl BuiltinSegmenter {
    /// A segmenter with the given thresholds.
    #[must_use]
    pub fn new(options: BuiltinOptions) -> Self {
        Self { options }
    }
}

impl Segmenter for BuiltinSegmenter {
    fn provider(&self) -> String {
        BUILTIN_PROVIDER.to_owned()
    }

    fn segment(&self, view: &ViewImage<'_>) -> DecomposeResult<LabelMap> {
        segment_view(view, &self.options)
    }
}

/// How a pixel pair on two different faces voted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Vote {
    /// One smooth surface: continuous and normals within the smooth angle.
    Smooth,
    /// Continuous across an edge (convex, or a crease too shallow to separate).
    Continuous,
    /// A gap, occlusion, concave crease or colour change.
    Separated,
}

/// Key of an unordered pair of face ids (or patch roots), sorting by the smaller one.
fn pair_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

fn split_key(key: u64) -> (u32, u32) {
    ((key >> 32) as u32, (key & 0xFFFF_FFFF) as u32)
}

fn segment_view(view: &ViewImage<'_>, options: &BuiltinOptions) -> DecomposeResult<LabelMap> {
    let ids = view.face_ids;
    let (w, h) = (ids.width_px as usize, ids.height_px as usize);
    let n = w * h;
    if ids.face.len() != n || ids.depth_m.len() != n || ids.normal_world.len() != n {
        return Err(DecomposeError::Segmentation {
            view: view.index,
            message: format!(
                "face-ID image of {w} x {h} px has {} faces, {} depths, {} normals",
                ids.face.len(),
                ids.depth_m.len(),
                ids.normal_world.len()
            ),
        });
    }
    let colour = (view.colour.pixels.len() == n).then_some(&view.colour.pixels);
    let rays = PixelRays::new(view.camera);

    // Object size: diagonal of the visible points' bounding box.
    let mut low = DVec3::splat(f64::INFINITY);
    let mut high = DVec3::splat(f64::NEG_INFINITY);
    let mut foreground_px = 0usize;
    let mut max_face = 0u32;
    for (k, &face) in ids.face.iter().enumerate() {
        if face == 0 || !ids.depth_m[k].is_finite() {
            continue;
        }
        foreground_px += 1;
        max_face = max_face.max(face);
        let p = rays.point(k % w, k / w, ids.depth_m[k]);
        low = low.min(p);
        high = high.max(p);
    }
    let mut map = LabelMap::unlabelled(ids.width_px, ids.height_px);
    if foreground_px == 0 {
        return Ok(map);
    }
    let size_m = (high - low).length();

    let thresholds = Thresholds {
        gap_floor_m: options.gap_fraction * size_m,
        gap_px: options.gap_px,
        crease_cos: options.crease_angle_rad.cos(),
        same_shading_cos: options.same_shading_angle_rad.cos(),
        smooth_cos: options.smooth_angle_rad.cos(),
        colour_distance: options.colour_distance,
    };
    let is_on = |k: usize| ids.face[k] != 0 && ids.depth_m[k].is_finite();
    let mut votes: Vec<(u64, Vote)> = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let p = y * w + x;
            if !is_on(p) {
                continue;
            }
            let neighbours = [
                (x + 1 < w).then_some((x + 1, y)),
                (y + 1 < h).then_some((x, y + 1)),
            ];
            for (qx, qy) in neighbours.into_iter().flatten() {
                let q = qy * w + qx;
                if !is_on(q) || ids.face[q] == ids.face[p] {
                    continue;
                }
                let sample = |k: usize, kx: usize, ky: usize| Sample {
                    point: rays.point(kx, ky, ids.depth_m[k]),
                    normal: DVec3::from_array(ids.normal_world[k].map(f64::from)),
                    colour: colour.map(|c| c[k]),
                    footprint_m: f64::from(ids.depth_m[k]) * rays.footprint_per_m,
                };
                let vote = classify(&sample(p, x, y), &sample(q, qx, qy), &thresholds);
                votes.push((pair_key(ids.face[p], ids.face[q]), vote));
            }
        }
    }
    votes.sort_unstable();

    // Stage 1, surface patches: faces joined where every pixel pair between them is smooth
    // (same material, near-parallel normals, no gap, same colour). Stage 2: patches joined
    // where a good share of the pixel pairs between them is continuous. Voting between whole
    // patches, not between single (possibly tiny) triangles, keeps a few ambiguous pixel pairs,
    // e.g. where an occlusion boundary meets a contact crease, from joining two parts. A share
    // rather than a majority, because two patches of one solid often border each other twice:
    // along their shared edge (continuous) and where one occludes the other (separated).
    let material = |face_id: u32| view.face_material.get(face_id as usize - 1).copied();
    let same_material = |a: u32, b: u32| !options.split_materials || material(a) == material(b);
    let mut regions = UnionFind::new(max_face as usize + 1);
    for pair in votes.chunk_by(|a, b| a.0 == b.0) {
        let (a, b) = split_key(pair[0].0);
        if pair.iter().all(|v| v.1 == Vote::Smooth) && same_material(a, b) {
            regions.union(a, b);
        }
    }
    let mut patch_votes: Vec<(u64, Vote)> = votes
        .iter()
        .filter_map(|&(key, vote)| {
            let (a, b) = split_key(key);
            let (pa, pb) = (regions.find(a), regions.find(b));
            (pa != pb).then(|| (pair_key(pa, pb), vote))
        })
        .collect();
    patch_votes.sort_unstable();
    let joins: Vec<(u32, u32)> = patch_votes
        .chunk_by(|a, b| a.0 == b.0)
        .filter(|pair| {
            let continuous = pair.iter().filter(|v| v.1 != Vote::Separated).count();
            continuous >= MIN_CONTINUOUS_PAIRS
                && continuous as f64 >= options.join_fraction * pair.len() as f64
        })
        .map(|pair| split_key(pair[0].0))
        .filter(|&(a, b)| same_material(a, b))
        .collect();
    for (a, b) in joins {
        regions.union(a, b);
    }
    for (k, label) in map.labels.iter_mut().enumerate() {
        if is_on(k) {
            *label = i32::try_from(regions.find(ids.face[k])).unwrap_or(i32::MAX);
        }
    }
    drop_small_regions(&mut map, foreground_px, options.min_region_fraction);
    map.canonicalise();
    Ok(map)
}

/// One pixel's surface.
struct Sample {
    /// Relative to the eye, metres.
    point: DVec3,
    /// Unit normal facing the camera.
    normal: DVec3,
    colour: Option<[u8; 4]>,
    /// Pixel width at this depth, metres.
    footprint_m: f64,
}

struct Thresholds {
    gap_floor_m: f64,
    gap_px: f64,
    crease_cos: f64,
    same_shading_cos: f64,
    smooth_cos: f64,
    colour_distance: f64,
}

/// Whether two neighbouring pixels on different faces lie on one continuous surface.
fn classify(p: &Sample, q: &Sample, t: &Thresholds) -> Vote {
    let delta = q.point - p.point;
    // Height of each point above the other's tangent plane (towards the camera).
    let q_above_p = p.normal.dot(delta);
    let p_above_q = -q.normal.dot(delta);
    let footprint_m = p.footprint_m.min(q.footprint_m);
    let gap_m = (t.gap_px * footprint_m).max(t.gap_floor_m);
    if q_above_p.max(p_above_q) > gap_m {
        return Vote::Separated;
    }
    // Across an edge of one surface both heights have the sign of the edge (both <= 0 convex,
    // both >= 0 concave). One point in front of the other's plane while the other is behind
    // the first's means the surfaces pass each other: a step, slot or occluding edge, seen
    // even when the depth jump is below the gap threshold.
    let mixed_m = MIXED_SIGN_PX * footprint_m;
    if q_above_p.max(p_above_q) > mixed_m && q_above_p.min(p_above_q) < -mixed_m {
        return Vote::Separated;
    }
    let cos = p.normal.dot(q.normal);
    let tolerance_m = 0.05 * footprint_m;
    if cos < t.crease_cos
        && q_above_p.min(p_above_q) > -tolerance_m
        && q_above_p + p_above_q > 2.0 * tolerance_m
    {
        return Vote::Separated;
    }
    if let (Some(a), Some(b)) = (p.colour, q.colour)
        && colour_difference(a, b, cos >= t.same_shading_cos) > t.colour_distance
    {
        return Vote::Separated;
    }
    if cos >= t.smooth_cos {
        Vote::Smooth
    } else {
        Vote::Continuous
    }
}

/// Euclidean distance of two sRGB colours in [0, 1]; with `same_shading` false the darker colour
/// is first scaled to the brighter one's norm (Lambert shading scales all channels alike).
fn colour_difference(a: [u8; 4], b: [u8; 4], same_shading: bool) -> f64 {
    let v = |c: [u8; 4]| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])) / 255.0;
    let (a, b) = (v(a), v(b));
    if same_shading {
        return a.distance(b);
    }
    let (la, lb) = (a.length(), b.length());
    // Near black the hue is noise; nothing to compare.
    if la.max(lb) < 0.05 {
        return 0.0;
    }
    if la.min(lb) <= 1e-9 {
        return la.max(lb);
    }
    (a / la - b / lb).length() * la.max(lb)
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::TriMesh;

    use super::*;
    use crate::segment::test_meshes::{
        CUBOID_FACES, body_drawer_handle, box_with_flush_lid, box_with_inset_lid, fine_cuboid,
        l_shaped_solid,
    };
    use crate::views::{ViewOptions, ViewSet, render_views};

    fn views_of(mesh: &TriMesh, face_rgba: &[[u8; 4]], resolution_px: u32) -> ViewSet {
        let options = ViewOptions {
            count: 8,
            resolution_px,
        };
        match render_views(mesh, face_rgba, &options) {
            Ok(views) => views,
            Err(e) => panic!("render: {e}"),
        }
    }

    fn segment_all(
        views: &ViewSet,
        face_material: &[u32],
        segmenter: &BuiltinSegmenter,
    ) -> Vec<LabelMap> {
        (0..views.cameras.len())
            .map(|k| {
                let view = ViewImage {
                    index: k,
                    camera: &views.cameras[k],
                    face_ids: &views.face_ids[k],
                    colour: &views.colour[k],
                    face_material,
                };
                match segmenter.segment(&view) {
                    Ok(map) => map,
                    Err(e) => panic!("segment view {k}: {e}"),
                }
            })
            .collect()
    }

    /// Per region of a view: pixels on body faces (`< CUBOID_FACES`) and on lid faces.
    fn body_and_lid_pixels(map: &LabelMap, face_ids: &[u32]) -> Vec<(usize, usize)> {
        let mut counts = vec![(0, 0); map.region_count()];
        for (&label, &id) in map.labels.iter().zip(face_ids) {
            if label >= 0 && id > 0 {
                let entry = &mut counts[label as usize];
                if (id as usize - 1) < CUBOID_FACES {
                    entry.0 += 1;
                } else {
                    entry.1 += 1;
                }
            }
        }
        counts
    }

    #[test]
    fn a_single_box_is_one_region_in_every_view() {
        // Convex edges between the box's faces never separate.
        let mesh = TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.6));
        let views = views_of(&mesh, &[[180, 180, 180, 255]; 12], 128);
        for (k, map) in segment_all(&views, &[], &BuiltinSegmenter::default())
            .iter()
            .enumerate()
        {
            assert_eq!(map.region_count(), 1, "view {k}");
            let labelled = map.labels.iter().filter(|&&l| l >= 0).count();
            assert_eq!(labelled, views.face_ids[k].covered_pixels(), "view {k}");
        }
    }

    #[test]
    fn an_inset_lid_is_its_own_region_where_it_is_seen() {
        // The lid meets the box top at concave creases and occludes it behind: views from above
        // (eye above the centre) see two regions, one per part; views from below see the box.
        let mesh = box_with_inset_lid();
        let views = views_of(&mesh, &[[180, 180, 180, 255]; 24], 160);
        let maps = segment_all(&views, &[], &BuiltinSegmenter::default());
        let mut above = 0;
        for (k, map) in maps.iter().enumerate() {
            let from_above = views.cameras[k].eye_m.z > views.cameras[k].target_m.z;
            let counts = body_and_lid_pixels(map, &views.face_ids[k].face);
            if from_above {
                above += 1;
                assert_eq!(counts.len(), 2, "view {k}: {counts:?}");
                // Each region lies on one part (a few pixels of slack for rasterised edges).
                for &(body, lid) in &counts {
                    assert!(body.min(lid) * 100 <= body + lid, "view {k}: {counts:?}");
                }
                assert!(counts.iter().any(|&(b, l)| l > b) && counts.iter().any(|&(b, l)| b > l));
            } else {
                assert_eq!(counts.len(), 1, "view {k}: {counts:?}");
            }
        }
        assert_eq!(above, 4);
    }

    /// Per region: pixels on each part, parts being consecutive face ranges ending at `ends`.
    fn part_pixels(map: &LabelMap, face_ids: &[u32], ends: &[usize]) -> Vec<Vec<usize>> {
        let mut counts = vec![vec![0; ends.len()]; map.region_count()];
        for (&label, &id) in map.labels.iter().zip(face_ids) {
            if label >= 0 && id > 0 {
                let part = ends.partition_point(|&end| end < id as usize);
                counts[label as usize][part] += 1;
            }
        }
        counts
    }

    /// Asserts every region lies (99 %) on one part and returns the parts the regions cover.
    fn parts_of_regions(counts: &[Vec<usize>], what: &str) -> Vec<usize> {
        counts
            .iter()
            .map(|c| {
                let total: usize = c.iter().sum();
                let (part, &most) = c
                    .iter()
                    .enumerate()
                    .max_by_key(|&(_, n)| *n)
                    .unwrap_or((0, &0));
                assert!(most * 100 >= total * 99, "{what}: {counts:?}");
                part
            })
            .collect()
    }

    #[test]
    fn a_finely_tessellated_lid_is_still_its_own_region() {
        // Small triangles: only a few pixel pairs per face pair, some of them ambiguous where
        // the lid's occluding edge runs into its contact crease with the box top.
        let body = fine_cuboid(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.6), 20);
        let lid = fine_cuboid(DVec3::new(0.15, 0.15, 0.6), DVec3::new(0.85, 0.85, 0.7), 15);
        let ends = [
            body.triangle_count(),
            body.triangle_count() + lid.triangle_count(),
        ];
        let mesh = TriMesh::merge([&body, &lid]);
        let views = views_of(&mesh, &vec![[180, 180, 180, 255]; ends[1]], 192);
        let maps = segment_all(&views, &[], &BuiltinSegmenter::default());
        for (k, map) in maps.iter().enumerate() {
            let counts = part_pixels(map, &views.face_ids[k].face, &ends);
            let mut parts = parts_of_regions(&counts, &format!("view {k}"));
            parts.sort_unstable();
            let from_above = views.cameras[k].eye_m.z > views.cameras[k].target_m.z;
            let expected = if from_above { vec![0, 1] } else { vec![0] };
            assert_eq!(parts, expected, "view {k}: {counts:?}");
        }
    }

    #[test]
    fn a_drawer_front_and_its_handle_are_regions_of_their_own() {
        // Views from the front (-y) see body, drawer front and handle; the others the body.
        let mesh = body_drawer_handle();
        let ends = [12, 24, 36];
        let views = views_of(&mesh, &[[180, 180, 180, 255]; 36], 160);
        let maps = segment_all(&views, &[], &BuiltinSegmenter::default());
        for (k, map) in maps.iter().enumerate() {
            let counts = part_pixels(map, &views.face_ids[k].face, &ends);
            let mut parts = parts_of_regions(&counts, &format!("view {k}"));
            parts.sort_unstable();
            let from_front = views.cameras[k].eye_m.y < views.cameras[k].target_m.y;
            let expected = if from_front { vec![0, 1, 2] } else { vec![0] };
            assert_eq!(parts, expected, "view {k}: {counts:?}");
        }
    }

    #[test]
    fn a_flush_lid_is_split_by_material_or_colour_only() {
        // Flush sides are coplanar: geometry alone joins lid and box in every view.
        let mesh = box_with_flush_lid();
        let grey = [[180, 180, 180, 255]; 24];
        let views = views_of(&mesh, &grey, 128);
        let segmenter = BuiltinSegmenter::default();
        let one_material = vec![0u32; 24];
        for map in segment_all(&views, &one_material, &segmenter) {
            assert_eq!(map.region_count(), 1);
        }
        // A different material on the lid separates it in every view (all see its sides).
        let materials: Vec<u32> = (0..24).map(|f| u32::from(f >= CUBOID_FACES)).collect();
        for (k, map) in segment_all(&views, &materials, &segmenter)
            .iter()
            .enumerate()
        {
            let counts = body_and_lid_pixels(map, &views.face_ids[k].face);
            assert_eq!(counts.len(), 2, "view {k}: {counts:?}");
            for &(body, lid) in &counts {
                assert_eq!(body.min(lid), 0, "view {k}: {counts:?}");
            }
        }
        // ... unless materials are ignored.
        let no_materials = BuiltinSegmenter::new(BuiltinOptions {
            split_materials: false,
            ..BuiltinOptions::default()
        });
        for map in segment_all(&views, &materials, &no_materials) {
            assert_eq!(map.region_count(), 1);
        }
        // A different colour (one material) separates it too.
        let mut painted = grey;
        for c in &mut painted[CUBOID_FACES..] {
            *c = [200, 60, 40, 255];
        }
        let views = views_of(&mesh, &painted, 128);
        for map in segment_all(&views, &one_material, &segmenter) {
            assert_eq!(map.region_count(), 2);
        }
    }

    #[test]
    fn an_l_shaped_solid_stays_one_region() {
        // The concave crease at the inner corner separates the two inner faces, but the L-shaped
        // end faces, seen by every rig view, join both arms: one region per view.
        let mesh = l_shaped_solid();
        let faces = mesh.triangle_count();
        let views = views_of(&mesh, &vec![[180, 180, 180, 255]; faces], 128);
        for (k, map) in segment_all(&views, &[], &BuiltinSegmenter::default())
            .iter()
            .enumerate()
        {
            assert_eq!(map.region_count(), 1, "view {k}");
        }
    }

    #[test]
    fn segmentation_is_deterministic() {
        let mesh = box_with_inset_lid();
        let views = views_of(&mesh, &[[180, 180, 180, 255]; 24], 128);
        let segmenter = BuiltinSegmenter::default();
        assert_eq!(
            segment_all(&views, &[], &segmenter),
            segment_all(&views, &[], &segmenter)
        );
        assert_eq!(segmenter.provider(), BUILTIN_PROVIDER);
    }
}
