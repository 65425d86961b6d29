//! Where the stage loses movable parts: area IoU and movable parts recovered after each of its
//! steps, over every object (from [`uniphys_decompose::Decomposition::steps`]).

use std::collections::BTreeMap;

use uniphys_decompose::{StepLabels, match_parts};

use crate::partnet::RealCase;

/// A true part counts as recovered when its matched part has at least this IoU.
const RECOVERED_IOU: f64 = 0.5;

/// One object's scores after each step: `(step, area IoU, movable recovered, movable)`.
pub(crate) type StepScores = Vec<(String, f64, usize, usize)>;

/// Scores `steps` of the stage on `case`; steps whose labels cannot be scored are left out.
pub(crate) fn score_steps(case: &RealCase, steps: &[StepLabels]) -> StepScores {
    let mesh = &case.asset.parts[0].mesh;
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    steps
        .iter()
        .filter_map(|s| {
            let matching = match_parts(&compact(&s.face_part), &case.truth, &areas).ok()?;
            let movable: Vec<bool> = case
                .motion
                .iter()
                .zip(&matching.iou)
                .filter_map(|(kind, &iou)| kind.map(|_| iou >= RECOVERED_IOU))
                .collect();
            Some((
                s.step.clone(),
                matching.area_iou(),
                movable.iter().filter(|ok| **ok).count(),
                movable.len(),
            ))
        })
        .collect()
}

/// Where each movable true part the stage missed in the end was lost: `"link_3 lost at merge"`
/// (recovered after the step before), or `"link_4 never separated"`. Empty when every movable
/// part was recovered or the steps were not kept.
pub(crate) fn lost_at(case: &RealCase, steps: &[StepLabels]) -> Vec<String> {
    let mesh = &case.asset.parts[0].mesh;
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    let history: Vec<(String, Vec<f64>)> = steps
        .iter()
        .filter_map(|s| {
            let matching = match_parts(&compact(&s.face_part), &case.truth, &areas).ok()?;
            Some((s.step.clone(), matching.iou))
        })
        .collect();
    let Some((_, last)) = history.last() else {
        return Vec::new();
    };
    (0..case.motion.len())
        .filter(|&t| case.motion[t].is_some() && last[t] < RECOVERED_IOU)
        .map(|t| {
            let name = &case.part_names[t];
            match history.iter().rposition(|(_, iou)| iou[t] >= RECOVERED_IOU) {
                Some(i) => format!("{name} lost at {}", history[i + 1].0),
                None => format!("{name} never separated"),
            }
        })
        .collect()
}

/// Prints the table of the steps, summed over `objects`.
pub(crate) fn print_steps(objects: &[StepScores]) {
    let mut order: Vec<String> = Vec::new();
    let mut sums: BTreeMap<String, (f64, usize, usize, usize)> = BTreeMap::new();
    for scores in objects {
        for (step, iou, hit, all) in scores {
            if !order.contains(step) {
                order.push(step.clone());
            }
            let e = sums.entry(step.clone()).or_default();
            *e = (e.0 + iou, e.1 + hit, e.2 + all, e.3 + 1);
        }
    }
    if order.is_empty() {
        return;
    }
    println!("\n## After each step\n");
    println!("| step | area IoU | movable recovered |");
    println!("|---|---:|---:|");
    for step in order {
        let (iou, hit, all, n) = sums[&step];
        println!(
            "| {step} | {:.3} | {:.0} % ({hit} of {all}) |",
            iou / n.max(1) as f64,
            100.0 * hit as f64 / all.max(1) as f64
        );
    }
}

/// Labels renumbered `0..n` in order of first appearance.
fn compact(labels: &[u32]) -> Vec<u32> {
    let mut ids: BTreeMap<u32, u32> = BTreeMap::new();
    labels
        .iter()
        .map(|l| {
            let next = u32::try_from(ids.len()).unwrap_or(u32::MAX);
            *ids.entry(*l).or_insert(next)
        })
        .collect()
}
