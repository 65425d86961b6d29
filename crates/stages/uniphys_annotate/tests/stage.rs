//! The stage against a local replay server: answers, repairs, fault paths, cost, cache, budget.

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use common::*;
use serde_json::{Value, json};
use uniphys_annotate::articulation::candidates_for;
use uniphys_annotate::{
    AnnotateError, AnnotateInput, AnnotateOptions, Annotation, MovablePart, annotate,
};
use uniphys_geometry::Aabb;
use uniphys_lvlm::{CostLedger, LvlmError, MemoryCache, NoCache};
use uniphys_replay::{Fault, RecordedRequest, ReplayServer, Reply};
use uniphys_types::{JointKind, JointLimits, Provenance};

type Script = dyn Fn(&RecordedRequest, usize) -> Reply + Send + Sync;

/// A server answering by `script(request, index of the request)`.
fn serve(script: Box<Script>) -> ReplayServer {
    let count = Arc::new(AtomicUsize::new(0));
    ReplayServer::start_with(Arc::new(move |request: &RecordedRequest| {
        let index = count.fetch_add(1, Ordering::SeqCst);
        script(request, index)
    }))
    .expect("server")
}

fn good(request: &RecordedRequest) -> Reply {
    let body = request.body_text();
    let answer = if is_properties(&body) {
        fixture("box_with_lid_properties.json")
    } else {
        fixture("box_with_lid_articulation.json")
    };
    Reply::json(200, completion(&marked(&answer)))
}

fn run(server: &ReplayServer, ledger: &CostLedger) -> Result<Annotation, AnnotateError> {
    run_with(server, ledger, &options())
}

fn run_with(
    server: &ReplayServer,
    ledger: &CostLedger,
    options: &AnnotateOptions,
) -> Result<Annotation, AnnotateError> {
    let asset = box_with_lid();
    let client = client(config(&server.url()), Arc::new(NoCache));
    annotate(
        &AnnotateInput {
            object_name: "box_with_lid",
            part_meshes: &asset.meshes,
            part_colours: &asset.colours,
            part_names: &asset.names,
        },
        &client,
        ledger,
        options,
    )
}

fn lid(limits_deg: f64) -> MovablePart {
    MovablePart {
        label: 2,
        parent: 1,
        kind: JointKind::Revolute,
        limits: JointLimits {
            lower: 0.0,
            upper: limits_deg.to_radians(),
        },
        damping: 0.05,
        group: vec![2],
    }
}

#[test]
fn properties_and_the_chosen_joint_come_from_the_answers() {
    let server = serve(Box::new(|r, _| good(r)));
    let ledger = CostLedger::new(None);
    let a = run(&server, &ledger).expect("annotated");
    assert_eq!(a.provider, "lvlm:test-model");
    assert_eq!(a.parts.len(), 2);
    assert!((a.parts[1].density_kg_per_m3.value - 500.0).abs() < 1e-9);
    assert_eq!(
        a.parts[1].density_kg_per_m3.provenance,
        Provenance::provider("lvlm:test-model", "v1")
    );
    assert_eq!(a.object.name.value, "wooden box with lid");
    assert!((a.object.mass_kg.value - 1.6).abs() < 1e-12);
    assert!(a.motion_issues.is_empty() && a.repairs.is_empty());

    // The axis is the "Red" (object X) candidate, negated; the pivot the "Green" one (index 1).
    let asset = box_with_lid();
    let diagonal = asset
        .meshes
        .iter()
        .fold(Aabb::EMPTY, |b, m| b.union(m.bounds()))
        .diagonal();
    let c = candidates_for(&lid(100.0), &asset.meshes, diagonal, 400, 42).expect("candidates");
    assert_eq!(a.joints.len(), 1);
    let j = &a.joints[0];
    assert_eq!((j.kind, j.parent.0, j.child.0), (JointKind::Revolute, 0, 1));
    let expected_axis = -c.axes[7];
    assert!(
        (uniphys_geometry::DVec3::from_array(j.axis_in_object) - expected_axis).length() < 1e-12
    );
    assert!((expected_axis - uniphys_geometry::DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
    assert!(
        (uniphys_geometry::DVec3::from_array(j.pivot_in_object_m) - c.pivots[1]).length() < 1e-12
    );
    assert!(
        c.pivots[1].y > 0.08,
        "the green pivot is on the back edge: {:?}",
        c.pivots[1]
    );
    let limits = j.limits.expect("limits");
    assert!(limits.lower == 0.0 && (limits.upper - 100f64.to_radians()).abs() < 1e-12);
    assert!((j.damping - 0.05).abs() < 1e-12);

    // Two calls, each charged from the server's usage at the default prices.
    assert_eq!(a.cost.total.calls, 2);
    assert_eq!(a.cost.total.prompt_tokens, 2 * PROMPT_TOKENS);
    assert!(
        (a.cost.total.cost_usd - 2.0 * call_cost_usd()).abs() < 1e-12,
        "{:?}",
        a.cost
    );
    assert_eq!(a.cost.by_purpose["properties"].calls, 1);
    assert_eq!(a.cost.by_purpose["articulation"].calls, 1);

    // The requests carry the images: two composites, then composite + axes + pivots.
    let requests = server.requests();
    assert_eq!(requests.len(), 2);
    let images = |r: &RecordedRequest| r.body_text().matches("data:image/png;base64,").count();
    assert_eq!(images(&requests[0]), 2);
    assert_eq!(images(&requests[1]), 3);
    assert!(a.timings.images == 4 && a.timings.render_secs > 0.0);
}

#[test]
fn json_outside_the_markers_is_repaired_by_asking_again() {
    let server = serve(Box::new(|r, i| {
        if i == 0 {
            let raw = fixture("box_with_lid_properties.json").to_string();
            Reply::json(200, completion(&format!("Sure! {raw}")))
        } else {
            good(r)
        }
    }));
    let ledger = CostLedger::new(None);
    let a = run(&server, &ledger).expect("annotated");
    assert_eq!(a.repairs.len(), 1);
    assert_eq!(a.repairs[0].subject, "properties");
    assert!(
        a.repairs[0].violations[0].contains("no ===BEGIN_JSON=== marker"),
        "{:?}",
        a.repairs
    );
    assert_eq!(a.cost.by_purpose["properties repair"].calls, 1);
    assert!((a.cost.total.cost_usd - 3.0 * call_cost_usd()).abs() < 1e-12);
}

#[test]
fn a_schema_violation_is_listed_in_the_repair_turn_and_then_fixed() {
    let server = serve(Box::new(|r, _| {
        let body = r.body_text();
        if is_properties(&body) && !is_repair(&body) {
            let mut answer = fixture("box_with_lid_properties.json");
            answer["parts"][1]["density"] = json!("0.5 kg");
            answer["parts"][0]["poisson_ratio"] = json!(0.9);
            return Reply::json(200, completion(&marked(&answer)));
        }
        good(r)
    }));
    let ledger = CostLedger::new(None);
    let a = run(&server, &ledger).expect("annotated");
    assert_eq!(a.repairs[0].violations.len(), 2, "{:?}", a.repairs);
    let repair = server
        .requests()
        .into_iter()
        .find(|r| is_repair(&r.body_text()))
        .expect("a repair turn was sent");
    let body = repair.body_text();
    assert!(
        body.contains("parts[1].density"),
        "the repair turn lists the violation"
    );
    assert!(body.contains("parts[0].poisson_ratio"));
    assert!((a.parts[1].density_kg_per_m3.value - 500.0).abs() < 1e-9);
}

#[test]
fn an_answer_still_invalid_after_the_repair_is_reported_and_not_cached() {
    let server = serve(Box::new(|r, _| {
        let body = r.body_text();
        if is_properties(&body) {
            let mut answer = fixture("box_with_lid_properties.json");
            answer["parts"][0]["material"] = json!("unobtainium");
            return Reply::json(200, completion(&marked(&answer)));
        }
        good(r)
    }));
    let asset = box_with_lid();
    let cache = Arc::new(MemoryCache::new());
    let client = client(config(&server.url()), cache.clone());
    let err = annotate(
        &AnnotateInput {
            object_name: "box",
            part_meshes: &asset.meshes,
            part_colours: &asset.colours,
            part_names: &asset.names,
        },
        &client,
        &CostLedger::new(None),
        &options(),
    )
    .expect_err("invalid");
    match &err {
        AnnotateError::InvalidAnswer {
            purpose,
            violations,
        } => {
            assert_eq!(purpose, "properties");
            assert_eq!(violations[0].path, "parts[0].material");
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(err.to_string().contains("parts[0].material"));
    assert_eq!(
        server.requests().len(),
        2,
        "one request and one repair turn"
    );
    assert!(
        cache.is_empty(),
        "invalid answers are dropped from the cache"
    );
}

#[test]
fn an_articulation_answer_still_invalid_fails_the_stage_or_fixes_the_part_when_asked() {
    let server = serve(Box::new(|r, _| {
        if is_properties(&r.body_text()) {
            return good(r);
        }
        let answer = json!({"axis_colour": "Teal", "motion_direction": "up", "pivot": "Green"});
        Reply::json(200, completion(&marked(&answer)))
    }));
    let error = run(&server, &CostLedger::new(None)).expect_err("fails by default");
    match &error {
        AnnotateError::ArticulationFailed { label, reason } => {
            assert_eq!(*label, 2);
            assert!(reason.contains("axis_colour"), "{reason}");
        }
        other => panic!("{other}"),
    }
    let fix = AnnotateOptions {
        fix_unanswered_parts: true,
        ..options()
    };
    let a = run_with(&server, &CostLedger::new(None), &fix).expect("annotated");
    assert_eq!(a.articulation_failures.len(), 1);
    assert_eq!(a.articulation_failures[0].label, 2);
    assert!(a.articulation_failures[0].reason.contains("axis_colour"));
    assert_eq!(a.joints[0].kind, JointKind::Fixed);
    assert_eq!(a.cost.by_purpose["articulation repair"].calls, 1);
}

#[test]
fn rate_limits_server_errors_truncated_bodies_and_timeouts_are_retried() {
    let server = serve(Box::new(|r, i| match i {
        0 => Reply::text(429, "slow down").with_header("Retry-After", "0"),
        1 => Reply::text(500, "boom"),
        2 => {
            let mut reply = good(r);
            reply.fault = Some(Fault::Truncate { keep_bytes: 20 });
            reply
        }
        3 => Reply::fault(Fault::Hang),
        _ => good(r),
    }));
    let asset = box_with_lid();
    let mut config = config(&server.url());
    config.request_timeout_secs = 0.5;
    config.max_attempts = 5;
    let client = client(config, Arc::new(NoCache));
    let a = annotate(
        &AnnotateInput {
            object_name: "box",
            part_meshes: &asset.meshes,
            part_colours: &asset.colours,
            part_names: &asset.names,
        },
        &client,
        &CostLedger::new(None),
        &options(),
    )
    .expect("annotated after retries");
    assert_eq!(a.cost.by_purpose["properties"].retries, 4, "{:?}", a.cost);
    assert_eq!(a.joints.len(), 1);
    assert_eq!(server.requests().len(), 6);
}

#[test]
fn an_exhausted_budget_stops_the_stage_with_a_clear_error() {
    let server = serve(Box::new(|r, _| good(r)));
    // Room for the properties request (estimated before it is sent) but not for more.
    let ledger = CostLedger::new(Some(1e-6));
    let err = run(&server, &ledger).expect_err("over budget");
    assert!(
        matches!(err, AnnotateError::Lvlm(LvlmError::BudgetExceeded { .. })),
        "{err:?}"
    );
    assert!(err.to_string().contains("budget"), "{err}");
    assert!(server.requests().is_empty(), "nothing is sent over budget");
}

#[test]
fn a_retried_stage_is_answered_from_the_cache_and_pays_nothing() {
    let server = serve(Box::new(|r, _| good(r)));
    let asset = box_with_lid();
    let cache = Arc::new(MemoryCache::new());
    let input = AnnotateInput {
        object_name: "box",
        part_meshes: &asset.meshes,
        part_colours: &asset.colours,
        part_names: &asset.names,
    };
    let first = annotate(
        &input,
        &client(config(&server.url()), cache.clone()),
        &CostLedger::new(None),
        &options(),
    )
    .expect("first");
    let second = annotate(
        &input,
        &client(config(&server.url()), cache.clone()),
        &CostLedger::new(None),
        &options(),
    )
    .expect("second");
    assert_eq!(server.requests().len(), 2, "the second run sent nothing");
    assert_eq!(second.cost.total.cache_hits, 2);
    assert_eq!(second.cost.total.cost_usd, 0.0);
    assert!(first.cost.total.cost_usd > 0.0);
    assert_eq!(
        first.joints, second.joints,
        "same renders, same requests, same joints"
    );
}

#[test]
fn more_parts_than_a_request_carries_are_refused_before_anything_is_sent() {
    let server = serve(Box::new(|r, _| good(r)));
    let asset = box_with_lid();
    let meshes: Vec<_> = (0..51).map(|i| asset.meshes[i % 2].clone()).collect();
    let colours = vec![[0.5, 0.5, 0.5, 1.0]; 51];
    let names: Vec<String> = (0..51).map(|i| format!("p{i}")).collect();
    let err = annotate(
        &AnnotateInput {
            object_name: "big",
            part_meshes: &meshes,
            part_colours: &colours,
            part_names: &names,
        },
        &client(config(&server.url()), Arc::new(NoCache)),
        &CostLedger::new(None),
        &AnnotateOptions::default(),
    )
    .expect_err("too many parts");
    assert!(matches!(
        err,
        AnnotateError::TooManyParts { parts: 51, max: 50 }
    ));
    assert!(server.requests().is_empty());
    let _: Option<Value> = None;
}
