//! The SAM and PartField clients against `uniphys_replay` playing recorded answers and faults
//! (`tests/fixtures/`, written by `make_fixtures.py`).

#![allow(clippy::unwrap_used)] // helpers outside #[test] functions

use std::path::PathBuf;
use std::time::Duration;

use uniphys_replay::{Recording, ReplayServer};
use uniphys_vision::{
    ClientConfig, MaskOptions, MaskSet, PartFeatures, PartFieldClient, SamClient, VisionError,
    VisionResult,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

fn serve(name: &str) -> ReplayServer {
    ReplayServer::start(Recording::load(fixture(name)).unwrap()).unwrap()
}

fn config(server: &ReplayServer) -> ClientConfig {
    ClientConfig {
        request_timeout: Duration::from_secs(5),
        max_attempts: 3,
        initial_backoff: Duration::from_millis(5),
        max_backoff: Duration::from_millis(50),
        ..ClientConfig::for_url(server.url())
    }
}

fn ask_masks(config: ClientConfig) -> VisionResult<MaskSet> {
    let png = std::fs::read(fixture("image_32x32.png")).unwrap();
    SamClient::new(config)
        .unwrap()
        .masks(&png, 32, 32, &MaskOptions::default())
}

/// A closed 12-triangle cube, 0.1 m on a side.
fn cube() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let vertices = (0..8)
        .map(|i| {
            [
                0.1 * (i & 1) as f32,
                0.1 * ((i >> 1) & 1) as f32,
                0.1 * ((i >> 2) & 1) as f32,
            ]
        })
        .collect();
    let faces = vec![
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
    (vertices, faces)
}

fn ask_features(server: &ReplayServer) -> VisionResult<PartFeatures> {
    let (vertices, faces) = cube();
    PartFieldClient::new(config(server))
        .unwrap()
        .features(&vertices, &faces)
}

/// The three recorded masks decode to the rectangles they encode, in row-major order.
fn assert_recorded_masks(set: &MaskSet) {
    assert_eq!(set.model, "sam2_hiera_large");
    assert_eq!((set.width_px, set.height_px), (32, 32));
    assert_eq!(set.masks.len(), 3);
    let rects = [(4, 20, 8, 24), (10, 14, 2, 30), (24, 30, 0, 2)];
    for (mask, (x0, x1, y0, y1)) in set.masks.iter().zip(rects) {
        for y in 0..32 {
            for x in 0..32 {
                let inside = (x0..x1).contains(&x) && (y0..y1).contains(&y);
                assert_eq!(mask.pixels[y * 32 + x], inside, "pixel ({x}, {y})");
            }
        }
        assert_eq!(mask.area_px, ((x1 - x0) * (y1 - y0)) as u64);
    }
    assert!((set.masks[1].predicted_iou - 0.91).abs() < 1e-6);
    assert!((set.masks[2].stability_score - 0.87).abs() < 1e-6);
}

#[test]
fn masks_are_decoded_and_the_request_follows_the_contract() {
    let server = serve("sam_ok.json");
    let set = ask_masks(config(&server)).unwrap();
    assert_recorded_masks(&set);
    let requests = server.requests();
    assert_eq!(requests.len(), 1);
    let body: serde_json::Value = serde_json::from_slice(&requests[0].body).unwrap();
    for (key, expected) in [
        ("pred_iou_thresh", 0.7),
        ("stability_score_thresh", 0.85),
        ("box_nms_thresh", 0.7),
    ] {
        let sent = body[key].as_f64().unwrap();
        assert!((sent - expected).abs() < 1e-6, "{key} = {sent}");
    }
    let png = std::fs::read(fixture("image_32x32.png")).unwrap();
    assert_eq!(
        base64::decode(body["image_png_base64"].as_str().unwrap()).unwrap(),
        png
    );
    assert_eq!(
        requests[0].headers.get("content-type").map(String::as_str),
        Some("application/json")
    );
    SamClient::new(config(&server)).unwrap().health().unwrap();
}

#[test]
fn retryable_failures_are_retried_until_an_answer() {
    for name in [
        "sam_429_then_ok.json",
        "sam_500_then_ok.json",
        "sam_truncated_then_ok.json",
        "sam_closed_then_ok.json",
        "sam_malformed_then_ok.json",
    ] {
        let server = serve(name);
        let set = ask_masks(config(&server)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_recorded_masks(&set);
        assert_eq!(server.requests().len(), 2, "{name}");
    }
}

#[test]
fn retry_after_replaces_the_exponential_backoff() {
    // Backoff of an hour, but the server says `Retry-After: 0`: the retry comes at once. (The
    // 60 s guard only turns an ignored header into a failure instead of an hour-long test.)
    let server = serve("sam_429_then_ok.json");
    let config = ClientConfig {
        initial_backoff: Duration::from_secs(3600),
        max_backoff: Duration::from_secs(3600),
        ..config(&server)
    };
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || sender.send(ask_masks(config).map(|set| set.masks.len())));
    let answer = receiver
        .recv_timeout(Duration::from_secs(60))
        .expect("Retry-After: 0 was not honoured: the client waits out its 1 h backoff");
    assert_eq!(answer.unwrap(), 3);
    assert_eq!(server.requests().len(), 2);
}

#[test]
fn a_hung_request_times_out_and_is_retried() {
    let server = serve("sam_hang_then_ok.json");
    let config = ClientConfig {
        request_timeout: Duration::from_millis(300),
        ..config(&server)
    };
    let set = ask_masks(config).unwrap();
    assert_recorded_masks(&set);
    assert_eq!(server.requests().len(), 2);
}

#[test]
fn persistent_500_gives_up_after_max_attempts_with_the_server_message() {
    let server = serve("sam_500_always.json");
    let error = ask_masks(config(&server)).unwrap_err();
    match &error {
        VisionError::GaveUp {
            attempts, reason, ..
        } => {
            assert_eq!(*attempts, 3);
            assert!(reason.contains("CUDA out of memory"), "{reason}");
        }
        other => panic!("expected GaveUp, got {other:?}"),
    }
    assert_eq!(server.requests().len(), 3);
}

#[test]
fn a_400_is_not_retried_and_carries_the_server_message() {
    let server = serve("sam_400.json");
    let error = ask_masks(config(&server)).unwrap_err();
    match &error {
        VisionError::Refused {
            status, message, ..
        } => {
            assert_eq!(*status, 400);
            assert_eq!(message, "image_png_base64 is not a PNG");
        }
        other => panic!("expected Refused, got {other:?}"),
    }
    assert_eq!(server.requests().len(), 1);
}

#[test]
fn masks_breaking_the_contract_are_refused_without_retry() {
    for (name, expected) in [
        ("sam_rle_wrong_sum.json", "mask 1: RLE runs sum to 1000"),
        (
            "sam_rle_wrong_size.json",
            "mask 0: RLE size [h, w] = [16, 64]",
        ),
    ] {
        let server = serve(name);
        let error = ask_masks(config(&server)).unwrap_err();
        assert!(
            matches!(error, VisionError::InvalidAnswer { .. }),
            "{name}: {error:?}"
        );
        assert!(error.to_string().contains(expected), "{name}: {error}");
        assert_eq!(server.requests().len(), 1, "{name}");
    }
}

#[test]
fn features_are_decoded_per_face() {
    let server = serve("partfield_ok.json");
    let features = ask_features(&server).unwrap();
    assert_eq!(features.model, "partfield_objaverse");
    assert_eq!((features.face_count(), features.dims), (12, 4));
    for face in 0..12 {
        let row = features.row(face).unwrap();
        for (d, value) in row.iter().enumerate() {
            assert_eq!(*value, face as f32 * 0.25 - d as f32);
        }
    }
    // The mesh went out as little-endian arrays of the stated sizes.
    let body: serde_json::Value = serde_json::from_slice(&server.requests()[0].body).unwrap();
    let faces = base64::decode(body["faces_u32_base64"].as_str().unwrap()).unwrap();
    assert_eq!(faces.len(), 12 * 3 * 4);
    assert_eq!(faces[12..16], 1u32.to_le_bytes()); // face 1 starts with vertex 1
    let vertices = base64::decode(body["vertices_f32_base64"].as_str().unwrap()).unwrap();
    assert_eq!(vertices.len(), 8 * 3 * 4);
    PartFieldClient::new(config(&server))
        .unwrap()
        .health()
        .unwrap();
}

#[test]
fn features_503_with_retry_after_is_retried() {
    let server = serve("partfield_503_then_ok.json");
    assert_eq!(ask_features(&server).unwrap().face_count(), 12);
    assert_eq!(server.requests().len(), 2);
}

#[test]
fn nan_or_missing_features_are_refused_naming_the_problem() {
    let server = serve("partfield_nan.json");
    let error = ask_features(&server).unwrap_err().to_string();
    assert!(
        error.contains("face 5 dimension 2 is NaN"),
        "unexpected: {error}"
    );
    assert_eq!(server.requests().len(), 1);
    let server = serve("partfield_short.json");
    let error = ask_features(&server).unwrap_err().to_string();
    assert!(error.contains("44 feature values"), "unexpected: {error}");
}

#[test]
fn an_unreachable_service_gives_up_and_health_says_so() {
    // A port nobody listens on: bind, note the port, close.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let config = ClientConfig {
        max_attempts: 2,
        initial_backoff: Duration::from_millis(1),
        ..ClientConfig::for_url(format!("http://127.0.0.1:{port}"))
    };
    let client = PartFieldClient::new(config).unwrap();
    let (vertices, faces) = cube();
    let error = client.features(&vertices, &faces).unwrap_err();
    assert!(
        matches!(error, VisionError::GaveUp { attempts: 2, .. }),
        "{error:?}"
    );
    assert!(matches!(
        client.health().unwrap_err(),
        VisionError::Unhealthy { .. }
    ));
}

#[test]
fn the_openapi_document_names_every_wire_field() {
    let document = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../proto/vision.openapi.yaml"),
    )
    .unwrap();
    let mask_request = serde_json::to_value(uniphys_vision::MaskRequest {
        image_png_base64: String::new(),
        width: 1,
        height: 1,
        options: MaskOptions::default(),
    })
    .unwrap();
    let feature_request = serde_json::to_value(uniphys_vision::PartFeatureRequest {
        vertex_count: 0,
        face_count: 0,
        vertices_f32_base64: String::new(),
        faces_u32_base64: String::new(),
    })
    .unwrap();
    let feature_response = serde_json::to_value(uniphys_vision::PartFeatureResponse {
        model: String::new(),
        dims: 0,
        features_f32_base64: String::new(),
    })
    .unwrap();
    let mask_response: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("sam_ok.json")).unwrap()).unwrap();
    let mask = &mask_response["exchanges"][1]["replies"][0]["json"]["masks"][0];
    let mut keys = Vec::new();
    for value in [
        &mask_request,
        &feature_request,
        &feature_response,
        mask,
        &mask["rle"],
    ] {
        keys.extend(value.as_object().unwrap().keys().cloned());
    }
    assert!(keys.len() > 15);
    for key in keys {
        assert!(
            document.contains(&format!("{key}:")),
            "proto/vision.openapi.yaml does not describe {key}"
        );
    }
    for path in ["/v1/masks:", "/v1/part-features:", "/healthz:"] {
        assert!(document.contains(path), "{path}");
    }
}
