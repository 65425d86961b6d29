//! End to end with an LVLM: the box with a lid through the pipeline, the properties and
//! articulation requests answered by a local replay server from the recorded answers in
//! `uniphys_annotate/tests/fixtures/`, then exported; the exported joint is the candidate the
//! answer chose, with the answer's limits, and the properties name the model.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_json::{Value, json};
use uniphys_annotate::articulation::candidates_for;
use uniphys_annotate::{AnnotateOptions, MovablePart};
use uniphys_examples::{GlbFrame, example, write_glb};
use uniphys_geometry::{Aabb, DVec3, TriMesh};
use uniphys_lvlm::LvlmConfig;
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_pipeline::{LvlmOptions, NoProgress, RunOptions, run};
use uniphys_replay::{RecordedRequest, ReplayServer, Reply};
use uniphys_types::{AssetRecord, JointKind, JointLimits, Provenance};

fn fixture(name: &str) -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../uniphys_annotate/tests/fixtures")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).expect("json")
}

fn completion(answer: &Value) -> Value {
    let text = format!("===BEGIN_JSON===\n{answer:#}\n===END_JSON===");
    json!({
        "id": "chatcmpl-e2e", "object": "chat.completion", "model": "recorded-model",
        "choices": [{"index": 0, "finish_reason": "stop",
                     "message": {"role": "assistant", "content": text}}],
        "usage": {"prompt_tokens": 2000, "completion_tokens": 300, "total_tokens": 2300}
    })
}

fn box_with_lid() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("box_with_lid.glb");
    let asset = example("box_with_lid").expect("example").asset;
    std::fs::write(&path, write_glb(&asset, GlbFrame::YUp).expect("glb")).expect("write");
    (dir, path)
}

const POINTS_PER_PART: usize = 400;

#[test]
fn the_box_lid_joint_is_the_chosen_candidate_with_the_answered_limits() {
    let server = ReplayServer::start_with(Arc::new(|request: &RecordedRequest| {
        let answer = if request.body_text().contains("UniPhys properties prompt") {
            fixture("box_with_lid_properties.json")
        } else {
            fixture("box_with_lid_articulation.json")
        };
        Reply::json(200, completion(&answer))
    }))
    .expect("server");
    let (dir, path) = box_with_lid();
    let options = RunOptions {
        lvlm: Some(LvlmOptions {
            client: LvlmConfig {
                base_url: format!("{}/v1", server.url()),
                model: "recorded-model".into(),
                max_concurrency: 2,
                ..LvlmConfig::default()
            },
            budget_usd: Some(1.0),
            cache_dir: Some(dir.path().join("lvlm-cache")),
            annotate: AnnotateOptions {
                panel_px: 96,
                points_per_part: POINTS_PER_PART,
                ..AnnotateOptions::default()
            },
            ..LvlmOptions::default()
        }),
        ..RunOptions::default()
    };
    let out = run(&path, &options, &NoProgress).expect("run with the LVLM");
    assert_eq!(
        server.requests().len(),
        2,
        "one properties and one articulation request"
    );

    // The exported record, read back from the artifact.
    let record_json = out
        .artifacts
        .iter()
        .find(|a| a.path == "record.json")
        .expect("record.json exported");
    let record: AssetRecord = serde_json::from_slice(&record_json.bytes).expect("record");
    let lid = record
        .joints
        .iter()
        .find(|j| j.child.0 == 1)
        .expect("lid joint");
    assert_eq!(lid.kind, JointKind::Revolute);
    assert_eq!(lid.parent.0, 0);
    assert_eq!(
        lid.provenance,
        Provenance::provider("lvlm:recorded-model", "v1")
    );

    // The candidates of the lid on the same ingested meshes: the answer chose "Red" (object X),
    // negative, and the "Green" pivot.
    let mut asset = load_asset(&path, &IngestOptions::default())
        .expect("ingest")
        .asset;
    asset.rest_on_ground();
    let meshes: Vec<TriMesh> = asset.parts.iter().map(|p| p.mesh.clone()).collect();
    let diagonal = meshes
        .iter()
        .fold(Aabb::EMPTY, |b, m| b.union(m.bounds()))
        .diagonal();
    let movable = MovablePart {
        label: 2,
        parent: 1,
        kind: JointKind::Revolute,
        limits: JointLimits {
            lower: 0.0,
            upper: 1.0,
        },
        damping: 0.05,
        group: vec![2],
    };
    let c = candidates_for(&movable, &meshes, diagonal, POINTS_PER_PART, 42).expect("candidates");
    let axis = DVec3::from_array(lid.axis_in_object);
    assert!((axis + c.axes[7]).length() < 1e-9, "axis {axis:?}");
    assert!((axis - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-9);
    let pivot = DVec3::from_array(lid.pivot_in_object_m);
    assert!(
        (pivot - c.pivots[1]).length() < 1e-9,
        "pivot {pivot:?} vs {:?}",
        c.pivots[1]
    );
    let limits = lid.limits.expect("limits");
    assert!(limits.lower.abs() < 1e-12 && (limits.upper - 100f64.to_radians()).abs() < 1e-12);
    assert!((lid.damping - 0.05).abs() < 1e-12);

    // Properties name the model; the URDF has the joint with the answered limit.
    for part in &record.parts {
        assert_eq!(
            part.properties.density_kg_per_m3.provenance.label(),
            "provider:lvlm:recorded-model"
        );
        assert!((part.properties.density_kg_per_m3.value - 500.0).abs() < 1e-9);
    }
    assert_eq!(record.object.name.value, "wooden box with lid");
    let urdf = out
        .artifacts
        .iter()
        .find(|a| a.path.ends_with(".urdf"))
        .expect("urdf");
    let urdf = String::from_utf8_lossy(&urdf.bytes);
    assert!(urdf.contains("type=\"revolute\""), "{urdf}");
    assert!(
        urdf.contains(&format!("{:.4}", 100f64.to_radians())) || urdf.contains("1.745329"),
        "{urdf}"
    );
    assert!(
        out.report.failures().count() == 0,
        "{:?}",
        out.report.failures().collect::<Vec<_>>()
    );

    // A second run is answered from the cache: nothing new reaches the server.
    run(&path, &options, &NoProgress).expect("cached run");
    assert_eq!(server.requests().len(), 2);
}
