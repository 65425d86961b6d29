//! The client against the std-only test server over loopback.

use std::time::{Duration, Instant};

use uniphys_geometry::{DVec3, MeshAsset, MeshPart, TriMesh};
use uniphys_uniphysgen::restore::restore_motion;
use uniphys_uniphysgen::test_server::TestServer;
use uniphys_uniphysgen::{
    ClientConfig, ModelInputs, PointOptions, Task, UniPhysGenClient, UniPhysGenError, model_inputs,
    prepare_points,
};

/// A 1 x 0.5 x 1 m body and `doors` 0.02 m thin doors in front of it.
fn inputs(doors: usize) -> ModelInputs {
    let mut parts = vec![MeshPart {
        name: "body".to_owned(),
        mesh: TriMesh::cuboid(DVec3::ZERO, DVec3::new(1.0, 0.5, 1.0)),
    }];
    for k in 0..doors {
        let z = k as f64 * 0.1;
        parts.push(MeshPart {
            name: format!("door{k}"),
            mesh: TriMesh::cuboid(DVec3::new(0.0, -0.02, z), DVec3::new(1.0, 0.0, z + 0.05)),
        });
    }
    let asset = MeshAsset {
        parts,
        ..MeshAsset::default()
    };
    let options = PointOptions {
        object_points: 4000,
        min_part_points: 500,
        seed: 42,
    };
    let prepared = prepare_points(&asset, &options);
    match prepared.and_then(|p| model_inputs(&p, 64)) {
        Ok(inputs) => inputs,
        Err(e) => panic!("test asset does not prepare: {e}"),
    }
}

fn client(server: &TestServer, tweak: impl FnOnce(&mut ClientConfig)) -> UniPhysGenClient {
    let mut config = ClientConfig {
        base_url: server.url(),
        timeout: Duration::from_secs(10),
        max_attempts: 4,
        initial_backoff: Duration::from_millis(10),
        max_backoff: Duration::from_millis(100),
        max_parts_per_request: 8,
        slot_wait: Duration::from_secs(5),
    };
    tweak(&mut config);
    match UniPhysGenClient::new(config, 2) {
        Ok(client) => client,
        Err(e) => panic!("test client config is refused: {e}"),
    }
}

#[test]
fn every_task_answers_on_the_happy_path() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |_| {});
    let inputs = inputs(2);
    let ids = ["0", "1", "2"];

    let kinematics = client
        .predict_parts(Task::Kinematics, "cab", &inputs)
        .unwrap();
    assert_eq!(kinematics.model, "uniphysgen-test-server/kinematics");
    assert_eq!(
        kinematics
            .parts
            .iter()
            .map(|a| a.id.as_str())
            .collect::<Vec<_>>(),
        ids
    );
    // The doors are thin (0.02 / 1): revolute about their longest axis, x.
    let door = &kinematics.parts[1];
    assert_eq!(door.motion_type.as_deref(), Some("C"));
    let center = inputs
        .frame
        .point_model_to_source(inputs.part_centers_in_model[1]);
    let motion = restore_motion(door, &inputs.frame, center, &kinematics.model)
        .unwrap()
        .unwrap();
    assert!((DVec3::from_array(motion.axis_in_object) - DVec3::X).length() < 1e-12);
    // Pivot = the door's centroid, near (0.5, -0.01, 0.025) m (4-decimal model rounding).
    let pivot = DVec3::from_array(motion.pivot_in_object_m);
    assert!(
        (pivot - DVec3::new(0.5, -0.01, 0.025)).length() < 0.02,
        "{pivot}"
    );
    let limits = motion.limits.unwrap();
    assert!((limits.upper - std::f64::consts::FRAC_PI_2).abs() < 1e-12);

    let physics = client.predict_parts(Task::Physics, "cab", &inputs).unwrap();
    let properties = physics.parts[0].physical_properties.as_ref().unwrap();
    assert_eq!(properties.material, "wood");

    let structure = client
        .predict_parts(Task::Structure, "cab", &inputs)
        .unwrap();
    assert_eq!(
        structure.parts[2].members.as_deref(),
        Some(&["2".to_owned()][..])
    );

    let (model, object) = client.predict_object("cab", &inputs).unwrap();
    assert_eq!(model, "uniphysgen-test-server/object_level");
    assert_eq!(object.mass, 1.0);
    assert_eq!(server.predict_requests(), 4);
}

#[test]
fn batching_splits_seven_parts_into_ceil_seven_over_three_requests() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |c| c.max_parts_per_request = 3);
    let inputs = inputs(6);
    let answers = client
        .predict_parts(Task::Structure, "batch", &inputs)
        .unwrap();
    assert_eq!(server.predict_requests(), 3);
    let ids: Vec<_> = answers.parts.iter().map(|a| a.id.clone()).collect();
    assert_eq!(ids, ["0", "1", "2", "3", "4", "5", "6"]);
}

#[test]
fn a_429_then_a_500_are_retried_until_the_answer() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |_| {});
    let answers = client
        .predict_parts(Task::Physics, "s#429x1,500x1", &inputs(1))
        .unwrap();
    assert_eq!(answers.parts.len(), 2);
    assert_eq!(server.predict_requests(), 3);
}

#[test]
fn retry_after_replaces_the_exponential_backoff() {
    // A 30 s backoff would be used without the server's `Retry-After: 0`.
    let server = TestServer::start().unwrap();
    let client = client(&server, |c| {
        c.initial_backoff = Duration::from_secs(30);
        c.max_backoff = Duration::from_secs(60);
    });
    let start = Instant::now();
    client
        .predict_parts(Task::Physics, "s#429x2", &inputs(1))
        .unwrap();
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
    assert_eq!(server.predict_requests(), 3);
}

#[test]
fn persistent_500s_give_up_after_max_attempts_with_a_clear_error() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |c| c.max_attempts = 3);
    let error = client
        .predict_parts(Task::Kinematics, "s#500x99", &inputs(1))
        .unwrap_err();
    assert!(
        matches!(error, UniPhysGenError::GaveUp { attempts: 3, .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message.contains("kinematics") && message.contains("s#500x99"),
        "{message}"
    );
    assert!(message.contains("HTTP 500"), "{message}");
    assert_eq!(server.predict_requests(), 3);
}

#[test]
fn a_slow_answer_times_out_and_is_retried() {
    // The shared retry policy retries timeouts (this client used to fail at the first one).
    let server = TestServer::start().unwrap();
    let client = client(&server, |c| c.timeout = Duration::from_millis(300));
    let start = Instant::now();
    let answers = client
        .predict_parts(Task::Physics, "s#slow3000x1", &inputs(1))
        .unwrap();
    assert_eq!(answers.parts.len(), 2);
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "{:?}",
        start.elapsed()
    );
    assert_eq!(server.predict_requests(), 2);
}

#[test]
fn a_server_slow_on_every_attempt_times_out_after_max_attempts() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |c| {
        c.timeout = Duration::from_millis(300);
        c.max_attempts = 2;
    });
    let start = Instant::now();
    let error = client
        .predict_parts(Task::Physics, "s#slow3000x9", &inputs(1))
        .unwrap_err();
    assert!(
        matches!(error, UniPhysGenError::Timeout { .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("timed out"), "{error}");
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "{:?}",
        start.elapsed()
    );
    assert_eq!(server.predict_requests(), 2);
}

#[test]
fn malformed_json_is_rejected_with_the_reason() {
    let server = TestServer::start().unwrap();
    let client = client(&server, |_| {});
    let error = client
        .predict_object("s#malformedx1", &inputs(1))
        .unwrap_err();
    assert!(
        matches!(error, UniPhysGenError::MalformedResponse { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message.contains("object_level") && message.contains("not a valid response JSON"),
        "{message}"
    );
}

#[test]
fn an_unreachable_server_is_retried_then_reported() {
    // Bind then drop a listener: nothing listens on that port any more.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let config = ClientConfig {
        base_url: format!("http://127.0.0.1:{port}"),
        max_attempts: 2,
        initial_backoff: Duration::from_millis(1),
        ..ClientConfig::default()
    };
    let client = UniPhysGenClient::new(config, 1).unwrap();
    let error = client.predict_object("gone", &inputs(1)).unwrap_err();
    assert!(
        matches!(error, UniPhysGenError::GaveUp { attempts: 2, .. }),
        "{error:?}"
    );
    assert!(error.to_string().contains("cannot reach"), "{error}");
}
