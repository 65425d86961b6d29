//! Time of the dynamic check per joint on the test assets: `cargo bench -p uniphys_simulate`.
//!
//! Prints one row per movable joint with the median over a few runs of its drive test, and one
//! row per asset with the at-rest test (all joints at once) and the whole check.
#![expect(clippy::unwrap_used, reason = "a benchmark fails loudly")]

#[path = "../tests/assets/mod.rs"]
mod assets;

use uniphys_simulate::{DynamicParams, DynamicReport, check_dynamics};
use uniphys_types::PartId;

const RUNS: usize = 5;

/// A named asset and the contact pairs the exporter would exclude.
type Case = (&'static str, assets::TestAsset, Vec<(PartId, PartId)>);

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let cases: Vec<Case> = vec![
        ("box_with_lid", assets::box_with_lid(0.05, 0.02), vec![]),
        (
            "open_lid",
            assets::box_with_open_lid(0.8, 0.05, 0.01),
            vec![],
        ),
        ("drawer", assets::drawer_in_carcass(2.0, 0.5), vec![]),
        ("drawer_rail", assets::drawer_blocked_by_rail(0.1), vec![]),
        ("door_cabinet", assets::door_cabinet(0.2, 0.05), vec![]),
        (
            "two_door_cabinet",
            assets::two_door_cabinet(0.0),
            vec![(PartId(1), PartId(2))],
        ),
        (
            "drawer_handle",
            assets::drawer_with_hanging_handle(0.05, 0.05),
            vec![],
        ),
        ("pendulum", assets::free_pendulum(), vec![]),
    ];
    let params = DynamicParams::default();
    println!(
        "dynamic check, {} Hz, rest {} s; median of {RUNS} runs, wall-clock ms\n",
        params.rate_hz, params.rest_duration_s
    );
    println!(
        "| asset | parts | joint | kind | verdict | drive ms | rest ms (asset) | total ms (asset) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, asset, excluded) in &cases {
        let reports: Vec<DynamicReport> = (0..RUNS)
            .map(|_| check_dynamics(&asset.record, &asset.colliders, excluded, &params).unwrap())
            .collect();
        let rest = median(reports.iter().map(|r| r.rest_time_ms).collect());
        let total = median(reports.iter().map(|r| r.total_time_ms).collect());
        for (k, joint) in reports[0].joints.iter().enumerate() {
            let drive = median(reports.iter().map(|r| r.joints[k].drive_time_ms).collect());
            println!(
                "| {name} | {} | {} | {:?} | {:?} | {drive:.1} | {rest:.1} | {total:.1} |",
                asset.record.parts.len(),
                joint.joint,
                joint.kind,
                joint.verdict.outcome
            );
        }
    }
}
