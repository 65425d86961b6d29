//! Where the stage loses movable parts: area IoU and movable parts recovered after each of its
//! steps, over every object (from [`uniphys_decompose::Decomposition::steps`]).

use std::collections::BTreeMap;

use uniphys_decompose::candidates::relabel_by_first_face;
use uniphys_decompose::{PartMatching, StepLabels, match_parts};

use crate::partnet::RealCase;
use crate::real::{RECOVERED_IOU, movable_recovered};

/// One object's scores after each step: `(step, area IoU, movable recovered, movable)`.
pub(crate) type StepScores = Vec<(String, f64, usize, usize)>;

/// Every kept step of the stage on `case` matched to its true parts; steps whose labels cannot
/// be matched are left out.
pub(crate) fn match_steps(case: &RealCase, steps: &[StepLabels]) -> Vec<(String, PartMatching)> {
    let mesh = &case.asset.parts[0].mesh;
    let areas: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    steps
        .iter()
        .filter_map(|s| {
            let (labels, _) = relabel_by_first_face(&s.face_part);
            let matching = match_parts(&labels, &case.truth, &areas).ok()?;
            Some((s.step.clone(), matching))
        })
        .collect()
}

/// The scores of the matched steps (`matched`, from [`match_steps`]) of `case`.
pub(crate) fn score_steps(case: &RealCase, matched: &[(String, PartMatching)]) -> StepScores {
    matched
        .iter()
        .map(|(step, matching)| {
            let movable = movable_recovered(case, matching);
            (
                step.clone(),
                matching.area_iou(),
                movable.iter().filter(|(_, ok)| *ok).count(),
                movable.len(),
            )
        })
        .collect()
}

/// Where each movable true part the stage missed in the end was lost: `"link_3 lost at merge"`
/// (recovered after the step before), or `"link_4 never separated"`. Empty when every movable
/// part was recovered or no step was matched (`matched`, from [`match_steps`]).
pub(crate) fn lost_at(case: &RealCase, matched: &[(String, PartMatching)]) -> Vec<String> {
    let Some((_, last)) = matched.last() else {
        return Vec::new();
    };
    (0..case.motion.len())
        .filter(|&t| case.motion[t].is_some() && last.iou[t] < RECOVERED_IOU)
        .map(|t| {
            let name = &case.part_names[t];
            match matched.iter().rposition(|(_, m)| m.iou[t] >= RECOVERED_IOU) {
                Some(i) => format!("{name} lost at {}", matched[i + 1].0),
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
