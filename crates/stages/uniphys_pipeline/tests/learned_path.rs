//! The learned path end to end against the rule-based UniPhysGen TEST server on loopback: the
//! model's answers land in the record with the model named in their provenance, and the export
//! still runs.

use uniphys_examples::{GlbFrame, example, write_glb};
use uniphys_pipeline::{
    LearnedOptions, NoProgress, PipelineError, RunOptions, Stage, ground_asset, infer_asset, run,
    verify_asset,
};
use uniphys_types::Provenance;
use uniphys_uniphysgen::test_server::TestServer;
use uniphys_uniphysgen::{ClientConfig, PointOptions};

fn cabinet() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    let cabinet = example("cabinet").expect("cabinet example");
    let path = dir.path().join("cabinet.glb");
    std::fs::write(
        &path,
        write_glb(&cabinet.asset, GlbFrame::YUp).expect("glb"),
    )
    .expect("write");
    (dir, path)
}

fn learned(url: String) -> RunOptions {
    RunOptions {
        learned: Some(LearnedOptions {
            client: ClientConfig {
                base_url: url,
                ..ClientConfig::default()
            },
            points: PointOptions {
                object_points: 20_000,
                min_part_points: 2_000,
                seed: 42,
            },
            ..LearnedOptions::default()
        }),
        ..RunOptions::default()
    }
}

#[test]
fn model_answers_replace_the_builtin_values_and_name_the_model() {
    let server = TestServer::start().expect("test server");
    let (_dir, path) = cabinet();
    let out = run(&path, &learned(server.url()), &NoProgress).expect("learned run");
    assert_eq!(
        out.timings[1].0,
        Stage::Infer,
        "the model is asked in its own stage"
    );
    let is_model = |p: &Provenance| matches!(p, Provenance::Provider { name, .. } if name.starts_with("uniphysgen"));
    for part in &out.record.parts {
        assert!(
            is_model(&part.properties.density_kg_per_m3.provenance),
            "{:?}",
            part.properties.density_kg_per_m3
        );
        assert!(is_model(&part.properties.material.provenance));
    }
    assert!(is_model(&out.record.object.category.provenance));
    for joint in out.record.joints.iter().filter(|j| j.kind.is_movable()) {
        assert!(is_model(&joint.provenance), "{joint:?}");
    }
    assert!(
        server.predict_requests() >= 3,
        "physics, kinematics and object requests"
    );
    assert!(out.artifacts.iter().any(|a| a.path == "model.urdf"));
}

// The queue's `infer` stage stores the model's answers; `ground` applies them without asking
// again, and decides what grounding with the server would.
#[test]
fn stored_model_answers_ground_as_asking_the_model_does() {
    let server = TestServer::start().expect("test server");
    let (_dir, path) = cabinet();
    let options = learned(server.url());
    let asking = ground_asset(&path, &options, &NoProgress).expect("grounding");
    let asked = server.predict_requests();
    let answers = infer_asset(&path, &options, &NoProgress)
        .expect("inference")
        .expect("a server is configured");
    assert_eq!(
        server.predict_requests(),
        2 * asked,
        "infer asks what grounding asked"
    );
    assert_eq!(answers.physics.parts.len(), asking.record.parts.len());
    let stored = serde_json::to_vec(&answers).expect("answers serialise");
    let applying = RunOptions {
        inferred: Some(serde_json::from_slice(&stored).expect("and read back")),
        ..options.clone()
    };
    let grounded = ground_asset(&path, &applying, &NoProgress).expect("grounding from answers");
    assert_eq!(
        server.predict_requests(),
        2 * asked,
        "no request after infer"
    );
    assert_eq!(grounded, asking);
    let none = infer_asset(&path, &RunOptions::default(), &NoProgress).expect("no server");
    assert!(none.is_none());
}

#[test]
fn stored_answers_for_other_parts_are_refused() {
    let server = TestServer::start().expect("test server");
    let (_dir, path) = cabinet();
    let options = learned(server.url());
    let mut answers = infer_asset(&path, &options, &NoProgress)
        .expect("inference")
        .expect("answers");
    answers.physics.parts.pop();
    let applying = RunOptions {
        inferred: Some(answers),
        ..options
    };
    let error = ground_asset(&path, &applying, &NoProgress).expect_err("a part without answers");
    assert!(error.to_string().contains("the asset has"), "{error}");
}

// The queue's `ground` stage stores what grounding decided; `convert` verifies and exports it
// without asking the model again, and gets what one run would.
#[test]
fn a_stored_grounding_is_verified_and_exported_without_asking_the_model_again() {
    let server = TestServer::start().expect("test server");
    let (_dir, path) = cabinet();
    let options = learned(server.url());
    let whole = run(&path, &options, &NoProgress).expect("learned run");
    let grounded = ground_asset(&path, &options, &NoProgress).expect("grounding");
    let asked = server.predict_requests();
    let stored = serde_json::to_vec(&grounded).expect("a grounding serialises");
    let again = RunOptions {
        grounded: Some(serde_json::from_slice(&stored).expect("and reads back")),
        ..options
    };
    let out = run(&path, &again, &NoProgress).expect("run from the stored grounding");
    assert_eq!(
        server.predict_requests(),
        asked,
        "no request after grounding"
    );
    assert_eq!(out.record, whole.record);
    let files = |artifacts: &[uniphys_export::Artifact]| {
        artifacts.iter().map(|a| a.path.clone()).collect::<Vec<_>>()
    };
    assert_eq!(files(&out.artifacts), files(&whole.artifacts));
}

// The queue's `verify` stage stores what verification decided; `convert` exports it without
// verifying again, and writes the same bytes one run would.
#[test]
fn a_stored_verification_is_exported_alone_and_gives_the_files_of_one_run() {
    let server = TestServer::start().expect("test server");
    let (_dir, path) = cabinet();
    let options = learned(server.url());
    let whole = run(&path, &options, &NoProgress).expect("learned run");
    let grounded = ground_asset(&path, &options, &NoProgress).expect("grounding");
    let grounded_options = RunOptions {
        grounded: Some(grounded),
        ..options
    };
    let verified = verify_asset(&path, &grounded_options, &NoProgress).expect("verification");
    let asked = server.predict_requests();
    let stored = serde_json::to_vec(&verified).expect("a verification serialises");
    let again = RunOptions {
        verified: Some(serde_json::from_slice(&stored).expect("and reads back")),
        ..grounded_options
    };
    let out = run(&path, &again, &NoProgress).expect("run from the stored verification");
    assert_eq!(
        server.predict_requests(),
        asked,
        "no request after grounding"
    );
    let stages: Vec<Stage> = out.timings.iter().map(|(stage, _)| *stage).collect();
    assert_eq!(stages, [Stage::Ingest, Stage::Export]);
    assert_eq!(out.record, whole.record);
    assert_eq!(out.artifacts.len(), whole.artifacts.len());
    for (a, b) in out.artifacts.iter().zip(&whole.artifacts) {
        assert_eq!(a.path, b.path);
        assert!(a.bytes == b.bytes, "{} differs from one run's", a.path);
    }
}

#[test]
fn a_stored_verification_of_other_parts_is_refused() {
    let (_dir, path) = cabinet();
    let grounded = ground_asset(&path, &RunOptions::default(), &NoProgress).expect("grounding");
    let options = RunOptions {
        grounded: Some(grounded),
        ..RunOptions::default()
    };
    let mut verified = verify_asset(&path, &options, &NoProgress).expect("verification");
    verified.record.parts[0].name = "not_a_part_of_the_cabinet".to_owned();
    let stored = RunOptions {
        verified: Some(verified.clone()),
        ..options.clone()
    };
    let error = run(&path, &stored, &NoProgress).expect_err("other parts");
    assert!(
        matches!(error, PipelineError::StoredVerification(_)),
        "{error}"
    );
    assert!(
        error.to_string().contains("not_a_part_of_the_cabinet"),
        "{error}"
    );

    verified.version += 1;
    let stored = RunOptions {
        verified: Some(verified),
        ..options
    };
    let error = run(&path, &stored, &NoProgress).expect_err("another version");
    assert!(error.to_string().contains("version"), "{error}");
}

#[test]
fn a_stored_grounding_of_other_parts_or_without_every_parts_colliders_is_refused() {
    let (_dir, path) = cabinet();
    let mut grounded = ground_asset(&path, &RunOptions::default(), &NoProgress).expect("grounding");
    grounded.record.parts[0].name = "not_a_part_of_the_cabinet".to_owned();
    let options = RunOptions {
        grounded: Some(grounded),
        ..RunOptions::default()
    };
    let error = run(&path, &options, &NoProgress).expect_err("other parts");
    assert!(
        matches!(error, PipelineError::StoredGrounding(_)),
        "{error}"
    );
    assert!(
        error.to_string().contains("not_a_part_of_the_cabinet"),
        "{error}"
    );

    let mut grounded = ground_asset(&path, &RunOptions::default(), &NoProgress).expect("grounding");
    grounded.colliders.pop();
    let options = RunOptions {
        grounded: Some(grounded),
        ..RunOptions::default()
    };
    let error = run(&path, &options, &NoProgress).expect_err("colliders missing");
    assert!(error.to_string().contains("colliders for"), "{error}");
}

#[test]
fn an_unreachable_model_server_is_a_model_error_naming_the_task() {
    let (_dir, path) = cabinet();
    // Port 9 (discard) on loopback: nothing listens.
    let mut options = learned("http://127.0.0.1:9".to_owned());
    if let Some(l) = &mut options.learned {
        l.client.max_attempts = 1;
    }
    let err = run(&path, &options, &NoProgress).expect_err("no server");
    assert!(matches!(err, PipelineError::Model(_)), "{err}");
    assert!(err.to_string().contains("physics"), "{err}");
}
