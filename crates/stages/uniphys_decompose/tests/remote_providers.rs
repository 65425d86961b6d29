//! The remote providers (SAM-compatible segmenter, PartField-compatible candidate generator)
//! against `uniphys_replay` playing recorded answers for a 12-triangle cube.

#![allow(clippy::unwrap_used)] // helpers outside #[test] functions

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use uniphys_decompose::candidates::{CandidateGenerator, CandidateRequest, PartFieldGenerator};
use uniphys_decompose::decompose::{DecomposeOptions, decompose};
use uniphys_decompose::segment::{NO_LABEL, SamSegmenter, Segmenter, ViewImage};
use uniphys_decompose::{DecomposeError, PerceptionOptions, ViewOptions, render_views};
use uniphys_geometry::{DVec3, TriMesh};
use uniphys_replay::{RecordedRequest, Recording, ReplayServer, Reply};
use uniphys_vision::{ClientConfig, PartFieldClient, SamClient, VisionError};

fn serve(name: &str) -> ReplayServer {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    ReplayServer::start(Recording::load(path).unwrap()).unwrap()
}

fn config(server: &ReplayServer) -> ClientConfig {
    ClientConfig {
        request_timeout: Duration::from_secs(5),
        max_attempts: 2,
        initial_backoff: Duration::from_millis(5),
        ..ClientConfig::for_url(server.url())
    }
}

/// A closed cube of 0.1 m: faces 0-1 bottom, 2-3 top, 4-5 y = 0, 6-7 y = 0.1, 8-9 x = 0,
/// 10-11 x = 0.1.
fn cube() -> TriMesh {
    let positions = (0..8)
        .map(|i| {
            DVec3::new(
                0.1 * f64::from(i & 1),
                0.1 * f64::from((i >> 1) & 1),
                0.1 * f64::from((i >> 2) & 1),
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    TriMesh::new(positions, triangles).unwrap()
}

#[test]
fn sam_segmenter_turns_the_recorded_masks_into_a_label_map_of_the_view() {
    let server = serve("sam_halves_32.json");
    let mesh = cube();
    let views = render_views(
        &mesh,
        &[[180, 180, 180, 255]; 12],
        &ViewOptions {
            count: 1,
            resolution_px: 32,
        },
    )
    .unwrap();
    let view = ViewImage {
        index: 0,
        camera: &views.cameras[0],
        face_ids: &views.face_ids[0],
        colour: &views.colour[0],
        face_material: &[],
    };
    let segmenter = SamSegmenter::new(SamClient::new(config(&server)).unwrap());
    assert_eq!(segmenter.provider(), "sam:unknown");
    let map = segmenter.segment(&view).unwrap();
    assert_eq!(segmenter.provider(), "sam:sam2_hiera_large");
    assert_eq!((map.width_px, map.height_px), (32, 32));

    // Background stays unlabelled; foreground takes the label of the half it lies in.
    let mut half_labels = [Vec::new(), Vec::new()];
    for (i, &label) in map.labels.iter().enumerate() {
        let foreground = views.face_ids[0].face[i] != 0;
        assert_eq!(label == NO_LABEL, !foreground, "pixel {i}");
        if foreground {
            half_labels[usize::from(i % 32 >= 16)].push(label);
        }
    }
    for labels in &mut half_labels {
        assert!(!labels.is_empty(), "the cube covers both halves");
        labels.sort_unstable();
        labels.dedup();
        assert_eq!(labels.len(), 1, "one label per half: {labels:?}");
    }
    assert_ne!(half_labels[0], half_labels[1]);

    // The view went out as the PNG of the colour image.
    let body: serde_json::Value = serde_json::from_slice(&server.requests()[0].body).unwrap();
    let png = uniphys_render::encode_png(&views.colour[0]).unwrap();
    assert_eq!(
        body["image_png_base64"].as_str().unwrap().len(),
        png.len().div_ceil(3) * 4
    );
}

#[test]
fn partfield_generator_clusters_the_normalised_recorded_features() {
    let server = serve("partfield_cube.json");
    let generator = PartFieldGenerator::new(PartFieldClient::new(config(&server)).unwrap());
    let mesh = cube();
    let request = CandidateRequest {
        mesh: &mesh,
        face_rgba: &[[180, 180, 180, 255]; 12],
        face_material: &[0; 12],
        k_values: 1..=3,
        seed: 7,
    };
    let candidates = generator.candidates(&request).unwrap();
    assert_eq!(generator.provider(), "partfield:partfield_objaverse");
    let ks: Vec<usize> = candidates.iter().map(|c| c.k).collect();
    assert_eq!(ks, [1, 2, 3]);
    let two = &candidates[1];
    assert_eq!(two.face_labels.len(), 12);
    // Two parts by feature direction (faces 0-5 against 6-11), whatever the magnitudes.
    for face in 0..12 {
        assert_eq!(
            two.face_labels[face] == two.face_labels[0],
            face < 6,
            "face {face}: {:?}",
            two.face_labels
        );
    }
}

#[test]
fn service_refusals_surface_as_vision_errors() {
    let server = ReplayServer::start_with(Arc::new(|_: &RecordedRequest| {
        Reply::json(400, serde_json::json!({"error": "mesh too large"}))
    }))
    .unwrap();
    let generator = PartFieldGenerator::new(PartFieldClient::new(config(&server)).unwrap());
    let mesh = cube();
    let request = CandidateRequest {
        mesh: &mesh,
        face_rgba: &[[0, 0, 0, 255]; 12],
        face_material: &[0; 12],
        k_values: 1..=2,
        seed: 0,
    };
    let error = generator.candidates(&request).unwrap_err();
    assert!(
        matches!(
            error,
            DecomposeError::Vision(VisionError::Refused { status: 400, .. })
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("mesh too large"), "{error}");
    assert_eq!(generator.provider(), "partfield:unknown");
}

#[test]
fn the_stage_runs_on_both_remote_providers_and_names_them() {
    let sam = serve("sam_halves_32.json");
    let partfield = serve("partfield_cube.json");
    let segmenter = SamSegmenter::new(SamClient::new(config(&sam)).unwrap());
    let generator = PartFieldGenerator::new(PartFieldClient::new(config(&partfield)).unwrap());
    let mesh = cube();
    let options = DecomposeOptions {
        perception: PerceptionOptions {
            views: ViewOptions {
                count: 8,
                resolution_px: 32,
            },
            ..PerceptionOptions::default()
        },
        ..DecomposeOptions::default()
    };
    let decomposition = decompose(
        &mesh,
        &[[180, 180, 180, 255]; 12],
        &[],
        &segmenter,
        &generator,
        &options,
    )
    .unwrap();
    assert_eq!(decomposition.summary.segmenter, "sam:sam2_hiera_large");
    assert_eq!(
        decomposition.summary.generator,
        "partfield:partfield_objaverse"
    );
    assert_eq!(sam.requests().len(), 8, "one mask request per view");
    assert_eq!(
        partfield.requests().len(),
        1,
        "one feature request per mesh"
    );
    assert_eq!(decomposition.face_part.len(), 12);
    // The recorded masks are image halves, the same in every view, so they cut the cube
    // differently from each viewpoint; whatever K wins, the two triangles of a side stay
    // together and the cube is split (the features alone give 2 groups, the sides 6).
    let sides = &decomposition.face_part;
    assert!(
        (2..=6).contains(&decomposition.part_count),
        "{} parts: {sides:?}",
        decomposition.part_count
    );
    assert!(
        sides.chunks(2).all(|side| side[0] == side[1]),
        "a side's triangles in different parts: {sides:?}"
    );
    assert!(
        decomposition
            .face_part
            .iter()
            .all(|&p| (p as usize) < decomposition.part_count)
    );
}
