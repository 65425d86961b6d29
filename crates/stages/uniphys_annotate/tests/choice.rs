//! Colour → candidate index → vector: every colour of the legend selects its own candidate
//! ("Dark Gray" included, which the reference could never select), a negative direction flips
//! the axis, the pivot colour selects its pivot, "average" the mean, a slide the centroid.

use uniphys_annotate::articulation::{CENTROID_PIVOT, resolve_choice};
use uniphys_annotate::schema::{ArticulationAnswer, MotionDirection};
use uniphys_annotate::{AXIS_LEGEND, PIVOT_LEGEND};
use uniphys_geometry::DVec3;
use uniphys_verify::ArticulationCandidates;

fn candidates() -> ArticulationCandidates {
    // Ten distinct unit axes and six distinct pivots.
    let axes = (0..10)
        .map(|k| {
            let t = f64::from(k) * 0.6;
            DVec3::new(t.cos(), t.sin(), 0.1 * f64::from(k)).normalize()
        })
        .collect();
    let pivots = (0..6)
        .map(|k| DVec3::new(f64::from(k), 1.0, -2.0))
        .collect();
    ArticulationCandidates {
        contact_points: Vec::new(),
        contact_normal: DVec3::Z,
        axes,
        pivots,
    }
}

fn answer(axis: &str, direction: MotionDirection, pivot: Option<&str>) -> ArticulationAnswer {
    ArticulationAnswer {
        part_description: String::new(),
        axis_description: String::new(),
        axis_colour: axis.to_owned(),
        motion_direction: direction,
        pivot: pivot.map(str::to_owned),
        justification: String::new(),
    }
}

fn legends() -> (Vec<&'static str>, Vec<&'static str>) {
    (
        AXIS_LEGEND.iter().map(|(n, _)| *n).collect(),
        PIVOT_LEGEND.iter().map(|(n, _)| *n).collect(),
    )
}

#[test]
fn every_axis_colour_selects_its_own_candidate_and_negative_flips_it() {
    let c = candidates();
    let (axes, pivots) = legends();
    for (k, name) in axes.iter().enumerate() {
        let pos = resolve_choice(
            &c,
            &answer(name, MotionDirection::Positive, Some("Red")),
            true,
            &axes,
            &pivots,
        )
        .expect("chosen");
        assert_eq!(pos.axis_index, k, "{name}");
        assert!((pos.axis - c.axes[k]).length() < 1e-12);
        let neg = resolve_choice(
            &c,
            &answer(name, MotionDirection::Negative, Some("Red")),
            true,
            &axes,
            &pivots,
        )
        .expect("chosen");
        assert!((neg.axis + c.axes[k]).length() < 1e-12);
    }
    let grey = resolve_choice(
        &c,
        &answer("dark grey", MotionDirection::Negative, Some("average")),
        true,
        &axes,
        &pivots,
    )
    .expect("Dark Gray is selectable");
    assert_eq!(grey.axis_index, 5);
    assert!((grey.axis + c.axes[5]).length() < 1e-12);
}

#[test]
fn pivot_colours_average_and_slides_pick_their_points() {
    let c = candidates();
    let (axes, pivots) = legends();
    for (k, name) in pivots.iter().enumerate() {
        let choice = resolve_choice(
            &c,
            &answer("Blue", MotionDirection::Positive, Some(name)),
            true,
            &axes,
            &pivots,
        )
        .expect("chosen");
        assert_eq!(choice.pivot_index, Some(k));
        assert_eq!(choice.pivot_m, c.pivots[k]);
    }
    let avg = resolve_choice(
        &c,
        &answer("Blue", MotionDirection::Positive, Some("Average")),
        true,
        &axes,
        &pivots,
    )
    .expect("chosen");
    assert_eq!(avg.pivot_index, None);
    assert!((avg.pivot_m - DVec3::new(2.5, 1.0, -2.0)).length() < 1e-12);
    let slide = resolve_choice(
        &c,
        &answer("Blue", MotionDirection::Positive, None),
        false,
        &axes,
        &pivots,
    )
    .expect("chosen");
    assert_eq!(slide.pivot_m, c.pivots[CENTROID_PIVOT]);
    assert!(
        resolve_choice(
            &c,
            &answer("Teal", MotionDirection::Positive, None),
            false,
            &axes,
            &pivots
        )
        .is_none()
    );
}
