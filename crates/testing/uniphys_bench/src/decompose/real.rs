//! `decompose-bench --partnet`: the stage on real objects merged into one mesh, scored against
//! their true parts (area IoU after one-to-one matching, movable parts recovered by joint kind,
//! count error), next to two baselines (the whole object as one part; each connected piece a
//! part) and the best a merge of connected pieces could reach, or of finer pieces split where
//! three or more faces share an edge (how far cutting welded seams could go); per category, time
//! per object, and the five worst objects with what went wrong.

use std::collections::BTreeMap;
use std::time::Instant;

use uniphys_decompose::pieces::manifold_pieces;
use uniphys_decompose::{Decomposition, PartMatching, match_parts};
use uniphys_geometry::{TriMesh, connected_components};
use uniphys_types::JointKind;

use crate::partnet::RealCase;
use crate::steps::{StepScores, lost_at, match_steps, print_steps, score_steps};

/// A true part counts as recovered when its matched part has at least this IoU.
pub(crate) const RECOVERED_IOU: f64 = 0.5;

/// The scores of one labelling of one object.
struct Scored {
    area_iou: f64,
    found_parts: usize,
    matching: PartMatching,
}

/// Per movable true part, its joint kind and whether it was recovered.
type Recovered = Vec<(JointKind, bool)>;

/// One object's results.
struct Row {
    name: String,
    category: String,
    faces: usize,
    true_parts: usize,
    stage: Scored,
    whole: f64,
    pieces: Scored,
    /// The best merge of connected pieces, and of manifold pieces: area IoU and movable parts
    /// recovered.
    bounds: [(f64, Recovered); 2],
    secs: f64,
    diagnosis: String,
}

/// Runs the stage with `decompose` on every case and prints the tables.
pub(crate) fn bench_real(
    cases: &[RealCase],
    decompose: &dyn Fn(&RealCase) -> anyhow::Result<Decomposition>,
) -> anyhow::Result<()> {
    println!(
        "# Decomposition of real objects: {} PartNet-Mobility objects merged into one mesh at rest, no names, colours or materials\n",
        cases.len()
    );
    println!(
        "| object | category | faces | true parts | found | area IoU | whole | pieces | best merge | movable recovered | s |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    let mut steps: Vec<StepScores> = Vec::new();
    for case in cases {
        let clock = Instant::now();
        let decomposition = match decompose(case) {
            Ok(d) => d,
            Err(error) => {
                println!("| {} | {} | FAILED: {error:#} |", case.name, case.category);
                continue;
            }
        };
        let secs = clock.elapsed().as_secs_f64();
        let mut row = score_case(case, &decomposition.face_part, secs)?;
        if let Some(reason) = &decomposition.summary.one_part_reason {
            row.diagnosis = format!("one part: {reason}; {}", row.diagnosis);
        }
        let matched = match_steps(case, &decomposition.steps);
        steps.push(score_steps(case, &matched));
        let lost = lost_at(case, &matched);
        if !lost.is_empty() {
            let by_step = format!("by step: {}", lost.join(", "));
            row.diagnosis = if row.diagnosis.is_empty() {
                by_step
            } else {
                format!("{}; {by_step}", row.diagnosis)
            };
        }
        let movable = movable_recovered(case, &row.stage.matching);
        println!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {}/{} | {:.2} |",
            row.name,
            row.category,
            row.faces,
            row.true_parts,
            row.stage.found_parts,
            row.stage.area_iou,
            row.whole,
            row.pieces.area_iou,
            row.bounds[0].0,
            movable.iter().filter(|(_, ok)| *ok).count(),
            movable.len(),
            row.secs
        );
        rows.push((row, movable));
    }
    if rows.is_empty() {
        return Ok(());
    }
    summary(&rows);
    print_steps(&steps);
    per_category(&rows);
    worst(&rows);
    missed(&rows);
    Ok(())
}

fn score_case(case: &RealCase, found: &[u32], secs: f64) -> anyhow::Result<Row> {
    let mesh = &case.asset.parts[0].mesh;
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    let scored = |labels: &[u32]| -> anyhow::Result<Scored> {
        let matching = match_parts(labels, &case.truth, &areas)?;
        Ok(Scored {
            area_iou: matching.area_iou(),
            found_parts: matching.found_parts,
            matching,
        })
    };
    let pieces = piece_labels(mesh);
    let bound = |labels: &[u32]| -> anyhow::Result<(f64, Recovered)> {
        let scored = scored(&best_merge(labels, &case.truth, &areas))?;
        Ok((scored.area_iou, movable_recovered(case, &scored.matching)))
    };
    let bounds = [bound(&pieces)?, bound(&manifold_pieces(mesh).0)?];
    Ok(Row {
        name: case.name.clone(),
        category: case.category.clone(),
        faces: mesh.triangle_count(),
        true_parts: case.motion.len(),
        stage: scored(found)?,
        whole: scored(&vec![0; found.len()])?.area_iou,
        pieces: scored(&pieces)?,
        bounds,
        secs,
        diagnosis: diagnose(case, found, &areas),
    })
}

/// Each connected piece of the mesh (vertices welded by position) as a part.
fn piece_labels(mesh: &TriMesh) -> Vec<u32> {
    let mut labels = vec![0u32; mesh.triangle_count()];
    for (i, faces) in connected_components(mesh).iter().enumerate() {
        for &f in faces {
            labels[f] = u32::try_from(i).unwrap_or(u32::MAX);
        }
    }
    labels
}

/// The best labelling that only merges pieces: each piece goes to the true part holding most of
/// its area.
fn best_merge(pieces: &[u32], truth: &[u32], areas: &[f64]) -> Vec<u32> {
    let mut area_by: BTreeMap<(u32, u32), f64> = BTreeMap::new();
    for f in 0..pieces.len() {
        *area_by.entry((pieces[f], truth[f])).or_default() += areas[f];
    }
    let mut best: BTreeMap<u32, (u32, f64)> = BTreeMap::new();
    for (&(piece, label), &area) in &area_by {
        let entry = best.entry(piece).or_insert((label, area));
        if area > entry.1 {
            *entry = (label, area);
        }
    }
    pieces.iter().map(|p| best[p].0).collect()
}

/// The movable true parts with their joint kind and whether they were recovered.
pub(crate) fn movable_recovered(case: &RealCase, matching: &PartMatching) -> Recovered {
    case.motion
        .iter()
        .zip(&matching.iou)
        .filter_map(|(kind, &iou)| kind.map(|k| (k, iou >= RECOVERED_IOU)))
        .collect()
}

/// What went wrong, in words: movable parts merged into another part, parts shattered.
fn diagnose(case: &RealCase, found: &[u32], areas: &[f64]) -> String {
    let true_parts = case.motion.len();
    let found_parts = found.iter().max().map_or(0, |&m| m as usize + 1);
    let mut inter = vec![0.0f64; true_parts * found_parts];
    let mut true_area = vec![0.0f64; true_parts];
    for f in 0..found.len() {
        inter[case.truth[f] as usize * found_parts + found[f] as usize] += areas[f];
        true_area[case.truth[f] as usize] += areas[f];
    }
    // Per found part, the true part holding most of it.
    let owner: Vec<usize> = (0..found_parts)
        .map(|j| {
            (0..true_parts)
                .max_by(|&a, &b| inter[a * found_parts + j].total_cmp(&inter[b * found_parts + j]))
                .unwrap_or(0)
        })
        .collect();
    let mut notes = Vec::new();
    for t in 0..true_parts {
        let row = &inter[t * found_parts..(t + 1) * found_parts];
        let Some(main) = (0..found_parts).max_by(|&a, &b| row[a].total_cmp(&row[b])) else {
            continue;
        };
        let label = || {
            let kind =
                case.motion[t].map_or("rigid".to_owned(), |k| format!("{k:?}").to_lowercase());
            format!("{} ({kind})", case.part_names[t])
        };
        if case.motion[t].is_some() && owner[main] != t {
            notes.push(format!(
                "{} merged into {}",
                label(),
                case.part_names[owner[main]]
            ));
        }
        let pieces = row.iter().filter(|&&a| a >= 0.05 * true_area[t]).count();
        if pieces >= 3 {
            notes.push(format!("{} cut into {pieces}", label()));
        }
    }
    notes.join("; ")
}

fn mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

fn summary(rows: &[(Row, Recovered)]) {
    let recall = |kind: Option<JointKind>| {
        let all: Vec<bool> = rows
            .iter()
            .flat_map(|(_, m)| m.iter())
            .filter(|(k, _)| kind.is_none_or(|want| *k == want))
            .map(|(_, ok)| *ok)
            .collect();
        let hit = all.iter().filter(|ok| **ok).count();
        if all.is_empty() {
            "n/a".to_owned()
        } else {
            format!(
                "{:.0} % ({hit} of {})",
                100.0 * hit as f64 / all.len() as f64,
                all.len()
            )
        }
    };
    let mut times: Vec<f64> = rows.iter().map(|(r, _)| r.secs).collect();
    times.sort_by(f64::total_cmp);
    let exact = rows
        .iter()
        .filter(|(r, _)| r.stage.found_parts == r.true_parts)
        .count();
    println!("\n## Summary over {} objects\n", rows.len());
    println!(
        "| what | area IoU | movable recovered (IoU >= 0.5) | prismatic | revolute | continuous | mean count error | exact count | median s | max s |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    println!(
        "| built-in decomposition | {:.3} | {} | {} | {} | {} | {:.2} | {:.0} % | {:.2} | {:.2} |",
        mean(rows.iter().map(|(r, _)| r.stage.area_iou)),
        recall(None),
        recall(Some(JointKind::Prismatic)),
        recall(Some(JointKind::Revolute)),
        recall(Some(JointKind::Continuous)),
        mean(
            rows.iter()
                .map(|(r, _)| r.stage.found_parts.abs_diff(r.true_parts) as f64)
        ),
        100.0 * exact as f64 / rows.len() as f64,
        times[times.len() / 2],
        times[times.len() - 1],
    );
    println!(
        "| baseline: the whole object as one part | {:.3} | | | | | | | | |",
        mean(rows.iter().map(|(r, _)| r.whole))
    );
    println!(
        "| baseline: each connected piece a part | {:.3} | | | | | {:.2} | | | |",
        mean(rows.iter().map(|(r, _)| r.pieces.area_iou)),
        mean(
            rows.iter()
                .map(|(r, _)| r.pieces.found_parts.abs_diff(r.true_parts) as f64)
        ),
    );
    for (i, what) in [
        "connected pieces",
        "pieces split where three or more faces share an edge",
    ]
    .iter()
    .enumerate()
    {
        let recovered: Vec<&(JointKind, bool)> =
            rows.iter().flat_map(|(r, _)| &r.bounds[i].1).collect();
        let ok = recovered.iter().filter(|(_, ok)| *ok).count();
        println!(
            "| best achievable by merging {what} | {:.3} | {:.0} % ({ok} of {}) | | | | | | | |",
            mean(rows.iter().map(|(r, _)| r.bounds[i].0)),
            100.0 * ok as f64 / recovered.len().max(1) as f64,
            recovered.len()
        );
    }
}

fn per_category(rows: &[(Row, Recovered)]) {
    let mut by: BTreeMap<&str, Vec<&(Row, Recovered)>> = BTreeMap::new();
    for row in rows {
        by.entry(row.0.category.as_str()).or_default().push(row);
    }
    println!("\n## Per category\n");
    println!(
        "| category | objects | area IoU | whole | pieces | best merge | movable recovered | above both baselines |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---|");
    for (category, members) in by {
        let iou = mean(members.iter().map(|(r, _)| r.stage.area_iou));
        let whole = mean(members.iter().map(|(r, _)| r.whole));
        let pieces = mean(members.iter().map(|(r, _)| r.pieces.area_iou));
        let movable: Vec<bool> = members
            .iter()
            .flat_map(|(_, m)| m.iter().map(|(_, ok)| *ok))
            .collect();
        println!(
            "| {category} | {} | {iou:.3} | {whole:.3} | {pieces:.3} | {:.3} | {}/{} | {} |",
            members.len(),
            mean(members.iter().map(|(r, _)| r.bounds[0].0)),
            movable.iter().filter(|ok| **ok).count(),
            movable.len(),
            if iou > whole.max(pieces) {
                "yes"
            } else {
                "**no**"
            }
        );
    }
}

fn worst(rows: &[(Row, Recovered)]) {
    let mut order: Vec<&Row> = rows.iter().map(|(r, _)| r).collect();
    order.sort_by(|a, b| a.stage.area_iou.total_cmp(&b.stage.area_iou));
    println!("\n## The five worst objects\n");
    for row in order.iter().take(5) {
        println!(
            "- {} ({}), area IoU {:.3}, {} true parts, {} found: {}",
            row.name,
            row.category,
            row.stage.area_iou,
            row.true_parts,
            row.stage.found_parts,
            if row.diagnosis.is_empty() {
                "parts found but their outlines are off"
            } else {
                &row.diagnosis
            }
        );
    }
}

/// Every object that missed a movable part, with what went wrong and at which step.
fn missed(rows: &[(Row, Recovered)]) {
    let missing: Vec<&Row> = rows
        .iter()
        .filter(|(_, m)| m.iter().any(|(_, ok)| !ok))
        .map(|(r, _)| r)
        .collect();
    if missing.is_empty() {
        return;
    }
    println!("\n## Objects that missed a movable part\n");
    for row in missing {
        println!("- {} ({}): {}", row.name, row.category, row.diagnosis);
    }
}
