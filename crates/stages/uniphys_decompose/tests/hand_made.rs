//! Hand-made decomposition cases built in code: a box with a lid, a cabinet with two drawers, and
//! a box with a lid given as 40 fragments. Each runs the whole stage with the built-in providers
//! and is scored by part count and area-weighted IoU against the known parts.
#![expect(clippy::unwrap_used, reason = "test fixtures fail loudly on purpose")]

use uniphys_decompose::{
    BuiltinSegmenter, DecomposeOptions, GeometricGenerator, PartScore, PerceptionOptions,
    ViewOptions, decompose_asset, score_parts,
};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};

/// Small views keep each case fast in the dev profile.
fn options() -> DecomposeOptions {
    DecomposeOptions {
        perception: PerceptionOptions {
            views: ViewOptions {
                count: 8,
                resolution_px: 192,
            },
            ..PerceptionOptions::default()
        },
        ..DecomposeOptions::default()
    }
}

/// One grey material on every face.
fn with_material(mesh: TriMesh) -> TriMesh {
    let faces = mesh.triangle_count();
    mesh.with_face_materials(vec![0; faces]).unwrap()
}

fn asset(parts: Vec<TriMesh>) -> MeshAsset {
    MeshAsset {
        parts: parts
            .into_iter()
            .enumerate()
            .map(|(i, mesh)| MeshPart {
                name: format!("piece_{i}"),
                mesh: with_material(mesh),
            })
            .collect(),
        materials: vec![SurfaceMaterial {
            name: "grey".into(),
            base_color_rgba: [0.6, 0.6, 0.6, 1.0],
            base_color_texture: None,
        }],
        ..MeshAsset::default()
    }
}

fn cuboid(min: [f64; 3], max: [f64; 3]) -> TriMesh {
    TriMesh::cuboid(DVec3::from_array(min), DVec3::from_array(max))
}

/// Decomposes `asset` and scores it against `truth` (true part per face of the merged mesh).
fn run(asset: &MeshAsset, truth: &[u32]) -> PartScore {
    let segmenter = BuiltinSegmenter::default();
    let generator = GeometricGenerator::default();
    let (decomposed, decomposition) =
        decompose_asset(asset, &segmenter, &generator, &options()).unwrap();
    let mesh = asset.merged();
    assert_eq!(decomposition.face_part.len(), mesh.triangle_count());
    assert_eq!(decomposed.parts.len(), decomposition.part_count);
    assert!(decomposed.joints.is_empty());
    assert!(
        decomposed
            .parts
            .iter()
            .enumerate()
            .all(|(i, p)| p.name == format!("part_{i}"))
    );
    assert_eq!(decomposed.triangle_count(), mesh.triangle_count());
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    let score = score_parts(&decomposition.face_part, truth, &areas).unwrap();
    eprintln!("{score:?}\n{:#?}", decomposition.summary);
    score
}

#[test]
fn box_with_a_lid_given_as_one_mesh_comes_out_as_two_parts() {
    let body = cuboid([0.0, 0.0, 0.0], [1.0, 0.8, 0.6]);
    let lid = cuboid([-0.03, -0.03, 0.6], [1.03, 0.83, 0.7]);
    let one_piece = TriMesh::merge([&body, &lid]);
    let truth: Vec<u32> = (0..24).map(|f| u32::from(f >= 12)).collect();
    let score = run(&asset(vec![one_piece]), &truth);
    assert_eq!(score.found_parts, 2);
    assert!(score.area_iou > 0.99, "{score:?}");
}

#[test]
fn cabinet_with_two_drawers_comes_out_as_body_and_drawers() {
    let body = cuboid([0.0, 0.0, 0.0], [1.0, 0.6, 1.2]);
    let upper = cuboid([0.05, -0.04, 0.65], [0.95, 0.0, 1.15]);
    let upper_handle = cuboid([0.35, -0.08, 0.87], [0.65, -0.04, 0.93]);
    let lower = cuboid([0.05, -0.04, 0.05], [0.95, 0.0, 0.55]);
    let lower_handle = cuboid([0.35, -0.08, 0.27], [0.65, -0.04, 0.33]);
    let one_piece = TriMesh::merge([&body, &upper, &upper_handle, &lower, &lower_handle]);
    // Body, upper drawer with its handle, lower drawer with its handle.
    let truth: Vec<u32> = (0..60).map(|f| [0, 1, 1, 2, 2][f / 12]).collect();
    let score = run(&asset(vec![one_piece]), &truth);
    assert_eq!(score.count_error, 0, "{score:?}");
    assert!(score.area_iou > 0.95, "{score:?}");
}

/// The quads of one box side as `rows` strips (each strip a triangle list with its own vertices),
/// `origin + s u + t v` with `u x v` pointing out.
fn side_strips(origin: DVec3, u: DVec3, v: DVec3, rows: usize) -> Vec<TriMesh> {
    let cols = 3;
    (0..rows)
        .map(|r| {
            let mut positions = Vec::new();
            let mut triangles = Vec::new();
            for c in 0..cols {
                let at = |i: usize, j: usize| {
                    origin + u * (i as f64 / cols as f64) + v * (j as f64 / rows as f64)
                };
                let base = u32::try_from(positions.len()).unwrap();
                positions.extend([at(c, r), at(c + 1, r), at(c + 1, r + 1), at(c, r + 1)]);
                triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
            }
            TriMesh::new(positions, triangles).unwrap()
        })
        .collect()
}

/// The six sides of a box, each cut into `rows[side]` strips, sides in the order -z, +z, -y, +y,
/// -x, +x.
fn box_strips(min: DVec3, max: DVec3, rows: [usize; 6]) -> Vec<TriMesh> {
    let d = max - min;
    let (x, y, z) = (DVec3::X * d.x, DVec3::Y * d.y, DVec3::Z * d.z);
    let sides = [
        (min, y, x),
        (DVec3::new(min.x, min.y, max.z), x, y),
        (min, x, z),
        (DVec3::new(min.x, max.y, min.z), z, x),
        (min, z, y),
        (DVec3::new(max.x, min.y, min.z), y, z),
    ];
    sides
        .iter()
        .zip(rows)
        .flat_map(|(&(o, u, v), r)| side_strips(o, u, v, r))
        .collect()
}

#[test]
fn a_box_with_a_lid_in_forty_fragments_comes_out_as_the_two_real_parts() {
    // Body: 38 strips (5 on the bottom and top, 7 on each side); lid: its top and bottom as one
    // fragment, its four sides as another.
    let mut fragments = box_strips(DVec3::ZERO, DVec3::new(1.0, 0.8, 0.6), [5, 5, 7, 7, 7, 7]);
    let body_faces: usize = fragments.iter().map(TriMesh::triangle_count).sum();
    let (lid_min, lid_max) = (DVec3::new(-0.03, -0.03, 0.6), DVec3::new(1.03, 0.83, 0.7));
    fragments.push(TriMesh::merge(
        box_strips(lid_min, lid_max, [1, 1, 0, 0, 0, 0]).iter(),
    ));
    fragments.push(TriMesh::merge(
        box_strips(lid_min, lid_max, [0, 0, 1, 1, 1, 1]).iter(),
    ));
    let input = asset(fragments);
    assert_eq!(input.parts.len(), 40);
    let truth: Vec<u32> = (0..input.triangle_count())
        .map(|f| u32::from(f >= body_faces))
        .collect();
    let score = run(&input, &truth);
    assert_eq!(score.found_parts, 2, "{score:?}");
    assert!(score.area_iou > 0.99, "{score:?}");
}

#[test]
fn the_same_input_and_seed_give_the_same_parts() {
    let body = cuboid([0.0, 0.0, 0.0], [1.0, 0.8, 0.6]);
    let lid = cuboid([-0.03, -0.03, 0.6], [1.03, 0.83, 0.7]);
    let knob = cuboid([0.45, 0.35, 0.7], [0.55, 0.45, 0.75]);
    let input = asset(vec![body, lid, knob]);
    let segmenter = BuiltinSegmenter::default();
    let generator = GeometricGenerator::default();
    let first = decompose_asset(&input, &segmenter, &generator, &options())
        .unwrap()
        .1;
    let second = decompose_asset(&input, &segmenter, &generator, &options())
        .unwrap()
        .1;
    assert_eq!(first.face_part, second.face_part);
    let mut a = first.summary.clone();
    let mut b = second.summary.clone();
    a.timings.clear();
    b.timings.clear();
    assert_eq!(a, b);
}

#[test]
fn options_out_of_their_domain_and_empty_meshes_are_refused() {
    let segmenter = BuiltinSegmenter::default();
    let generator = GeometricGenerator::default();
    let bad = DecomposeOptions {
        whole_object_fraction: 1.5,
        ..options()
    };
    let input = asset(vec![cuboid([0.0; 3], [1.0; 3])]);
    let error = decompose_asset(&input, &segmenter, &generator, &bad).unwrap_err();
    assert!(
        error.to_string().contains("whole_object_fraction"),
        "{error}"
    );
    let empty = MeshAsset::default();
    assert!(decompose_asset(&empty, &segmenter, &generator, &options()).is_err());
}
