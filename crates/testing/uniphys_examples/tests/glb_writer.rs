//! Reads GLB output back with the `gltf` crate (which validates it) and checks it against the
//! source asset.

use gltf::Gltf;
use uniphys_examples::glb_writer::DEFAULT_MATERIAL_NAME;
use uniphys_examples::shapes::cuboid;
use uniphys_examples::{ExamplesError, GlbFrame, catalogue, write_glb};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, SurfaceMaterial, TriMesh};

/// One primitive read back: material name, triangle corner positions, normals, UVs, colours.
struct Primitive {
    material: Option<String>,
    triangles: Vec<[[f32; 3]; 3]>,
    /// Three per triangle.
    normals: Vec<[f32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    colors: Option<Vec<[f32; 4]>>,
}

/// Per-vertex values in index order (three per triangle).
fn pick<T: Copy>(indices: &[u32], values: impl Iterator<Item = T>) -> Vec<T> {
    let values: Vec<T> = values.collect();
    indices.iter().map(|&i| values[i as usize]).collect()
}

/// Parts read back: node name and primitives, in node order.
fn read_back(bytes: &[u8]) -> Vec<(String, Vec<Primitive>)> {
    let gltf = Gltf::from_slice(bytes).expect("GLB must parse and validate");
    let blob = gltf.blob.as_deref();
    let scene = gltf.default_scene().expect("a default scene");
    scene
        .nodes()
        .map(|node| {
            let primitives = node
                .mesh()
                .map(|mesh| {
                    mesh.primitives()
                        .map(|p| {
                            let reader = p.reader(|_| blob);
                            let positions: Vec<[f32; 3]> =
                                reader.read_positions().expect("POSITION").collect();
                            let indices: Vec<u32> =
                                reader.read_indices().expect("indices").into_u32().collect();
                            let triangles = indices
                                .chunks(3)
                                .map(|t| {
                                    t.iter().map(|&i| positions[i as usize]).collect::<Vec<_>>()
                                })
                                .map(|t| [t[0], t[1], t[2]])
                                .collect();
                            let normals = pick(&indices, reader.read_normals().expect("NORMAL"));
                            Primitive {
                                material: p.material().name().map(str::to_owned),
                                triangles,
                                normals,
                                uvs: reader
                                    .read_tex_coords(0)
                                    .map(|t| pick(&indices, t.into_f32())),
                                colors: reader
                                    .read_colors(0)
                                    .map(|c| pick(&indices, c.into_rgba_f32())),
                            }
                        })
                        .collect()
                })
                .unwrap_or_default();
            (node.name().unwrap_or_default().to_owned(), primitives)
        })
        .collect()
}

fn assert_positions_round_trip(asset: &MeshAsset, up: GlbFrame) {
    let parts = read_back(&write_glb(asset, up).expect("writable asset"));
    assert_eq!(parts.len(), asset.parts.len());
    for (part, (name, primitives)) in asset.parts.iter().zip(&parts) {
        assert_eq!(&part.name, name);
        let mesh = &part.mesh;
        let mut expected_materials: Vec<u32> = mesh.face_materials.clone().unwrap_or_default();
        expected_materials.sort_unstable();
        expected_materials.dedup();
        let expected_primitives = if mesh.triangles.is_empty() {
            0
        } else {
            expected_materials.len().max(1)
        };
        assert_eq!(primitives.len(), expected_primitives);
        for (k, primitive) in primitives.iter().enumerate() {
            let faces: Vec<usize> = (0..mesh.triangle_count())
                .filter(|&f| {
                    mesh.face_materials
                        .as_ref()
                        .is_none_or(|m| m[f] == expected_materials[k])
                })
                .collect();
            if let Some(&material) = expected_materials.get(k) {
                let name = &asset.materials[material as usize].name;
                assert_eq!(primitive.material.as_deref(), Some(name.as_str()));
            }
            assert_eq!(primitive.triangles.len(), faces.len());
            for (read, &face) in primitive.triangles.iter().zip(&faces) {
                for (corner, source) in read.iter().zip(mesh.corners(face)) {
                    let source = up.map(source);
                    let error = (DVec3::from_array(corner.map(f64::from)) - source)
                        .abs()
                        .max_element();
                    assert!(error < 1e-6, "{name} face {face}: {corner:?} vs {source}");
                }
            }
        }
    }
}

#[test]
fn every_example_round_trips_positions_in_both_frames() {
    for e in catalogue() {
        assert_positions_round_trip(&e.asset, GlbFrame::YUp);
        assert_positions_round_trip(&e.asset, GlbFrame::ZUp);
    }
}

#[test]
fn y_up_frame_writes_z_up_points_as_x_z_minus_y() {
    assert_eq!(
        GlbFrame::YUp.map(DVec3::new(1.0, 2.0, 3.0)),
        DVec3::new(1.0, 3.0, -2.0)
    );
    assert_eq!(
        GlbFrame::ZUp.map(DVec3::new(1.0, 2.0, 3.0)),
        DVec3::new(1.0, 2.0, 3.0)
    );
    // The ingest rotation (x, y, z) -> (x, -z, y) undoes it.
    let p = GlbFrame::YUp.map(DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(DVec3::new(p.x, -p.z, p.y), DVec3::new(1.0, 2.0, 3.0));
}

#[test]
fn output_is_byte_identical_across_calls_and_4_byte_aligned() {
    for e in catalogue() {
        let first = write_glb(&e.asset, GlbFrame::YUp).unwrap();
        let second = write_glb(&e.clone().asset, GlbFrame::YUp).unwrap();
        assert_eq!(first, second, "{}", e.name);
        assert_eq!(first.len() % 4, 0);
        assert_eq!(
            u32::from_le_bytes(first[8..12].try_into().unwrap()) as usize,
            first.len()
        );
        let json_len = u32::from_le_bytes(first[12..16].try_into().unwrap()) as usize;
        assert_eq!(json_len % 4, 0);
        assert_eq!(&first[16..20], b"JSON");
        assert_eq!(&first[24 + json_len..28 + json_len], b"BIN\0");
    }
}

#[test]
fn normals_are_unit_and_point_out_of_the_face() {
    let e = uniphys_examples::example("mug").unwrap();
    for (_, primitives) in read_back(&write_glb(&e.asset, GlbFrame::YUp).unwrap()) {
        for p in primitives {
            assert_eq!(p.normals.len(), 3 * p.triangles.len());
            for (t, corners) in p.triangles.iter().enumerate() {
                let [a, b, c] = corners.map(|q| DVec3::from_array(q.map(f64::from)));
                let face = (b - a).cross(c - a).normalize();
                for n in &p.normals[3 * t..3 * t + 3] {
                    let n = DVec3::from_array(n.map(f64::from));
                    assert!((n.length() - 1.0).abs() < 1e-6);
                    assert!(n.dot(face) > 0.999, "normal {n} vs face {face}");
                }
            }
        }
    }
}

fn two_material_asset() -> MeshAsset {
    let mut mesh = cuboid(DVec3::ZERO, DVec3::ONE);
    let n = mesh.positions.len();
    mesh = mesh
        .with_face_materials((0..12).map(|f| u32::from(f >= 4)).collect())
        .expect("one material per face")
        .with_uvs((0..n).map(|i| [i as f32 / 8.0, 0.5]).collect())
        .expect("one UV per vertex")
        .with_vertex_colors(vec![[0.1, 0.2, 0.3, 1.0]; n])
        .expect("one colour per vertex");
    let material = |name: &str, rgba| SurfaceMaterial {
        name: name.to_owned(),
        base_color_rgba: rgba,
        base_color_texture: None,
    };
    MeshAsset {
        parts: vec![
            MeshPart {
                name: "striped".to_owned(),
                mesh,
            },
            MeshPart {
                name: "plain".to_owned(),
                mesh: cuboid(DVec3::splat(2.0), DVec3::splat(3.0)),
            },
            MeshPart {
                name: "empty".to_owned(),
                mesh: TriMesh::default(),
            },
        ],
        materials: vec![
            material("wood_oak", [0.5, 0.3, 0.1, 1.0]),
            material("glass_clear", [0.9, 0.9, 0.9, 0.2]),
        ],
        ..MeshAsset::default()
    }
}

#[test]
fn parts_split_into_one_primitive_per_material_with_uvs_colours_and_a_default_material() {
    let asset = two_material_asset();
    assert_positions_round_trip(&asset, GlbFrame::YUp);
    let bytes = write_glb(&asset, GlbFrame::YUp).unwrap();
    let parts = read_back(&bytes);
    let names: Vec<&str> = parts.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["striped", "plain", "empty"]);
    let striped = &parts[0].1;
    assert_eq!(striped.len(), 2);
    assert_eq!(striped[0].triangles.len(), 4);
    assert_eq!(striped[1].material.as_deref(), Some("glass_clear"));
    let mesh = &asset.parts[0].mesh;
    let uvs = mesh.uvs.as_ref().unwrap();
    let first_face_uvs: Vec<[f32; 2]> =
        mesh.triangles[0].iter().map(|&v| uvs[v as usize]).collect();
    assert_eq!(striped[0].uvs.as_ref().unwrap()[..3], first_face_uvs[..]);
    assert_eq!(striped[0].colors.as_ref().unwrap()[0], [0.1, 0.2, 0.3, 1.0]);
    assert_eq!(
        parts[1].1[0].material.as_deref(),
        Some(DEFAULT_MATERIAL_NAME)
    );
    assert!(parts[1].1[0].uvs.is_none() && parts[1].1[0].colors.is_none());
    assert!(parts[2].1.is_empty());

    let gltf = Gltf::from_slice(&bytes).unwrap();
    let glass = gltf
        .materials()
        .find(|m| m.name() == Some("glass_clear"))
        .unwrap();
    assert_eq!(
        glass.pbr_metallic_roughness().base_color_factor(),
        [0.9, 0.9, 0.9, 0.2]
    );
    assert_eq!(glass.alpha_mode(), gltf::material::AlphaMode::Blend);
    let accessor = gltf
        .meshes()
        .next()
        .unwrap()
        .primitives()
        .next()
        .unwrap()
        .get(&gltf::Semantic::Positions)
        .unwrap();
    assert_eq!(accessor.min().unwrap(), serde_json::json!([0.0, 0.0, -1.0]));
    assert_eq!(accessor.max().unwrap(), serde_json::json!([1.0, 1.0, -0.0]));
}

#[test]
fn a_face_material_without_material_is_an_error() {
    let mut asset = two_material_asset();
    asset.materials.pop();
    let error = write_glb(&asset, GlbFrame::ZUp).unwrap_err();
    assert!(
        matches!(
            error,
            ExamplesError::MaterialOutOfRange {
                material: 1,
                count: 1,
                ..
            }
        ),
        "{error}"
    );
}

#[test]
fn an_asset_without_triangles_is_still_a_valid_glb() {
    let asset = MeshAsset {
        parts: vec![MeshPart {
            name: "nothing".to_owned(),
            mesh: TriMesh::default(),
        }],
        ..MeshAsset::default()
    };
    let parts = read_back(&write_glb(&asset, GlbFrame::YUp).unwrap());
    assert_eq!(parts.len(), 1);
    assert!(parts[0].1.is_empty());
}
