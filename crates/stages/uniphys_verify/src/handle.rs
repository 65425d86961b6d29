//! A panel's handle: what stands out of its outer face, judged against the face around it.
//!
//! The outer face of a real door is rarely a plane: it bulges, curves or carries a raised
//! frame. A handle is what stands out of the face *locally*: the outer surface is mapped as a
//! height field over the panel's plane, and a handle sample rises well above the median height
//! of the cells around it. A bulge or a curve rises with its neighbours and is not a handle; a
//! bar across the whole width still is, since it fills only a row of the neighbourhood.
//!
//! A hinge along a panel's edge lies across the panel from its handle, and a bar handle runs
//! along the hinge: the verifier's sweep measures both ([`handle_on_hinge`]), and the grounder
//! places hinges with [`panel_handle`].

use uniphys_geometry::{Aabb, DVec3, KdTree, principal_axes, projection_range};

use crate::held::{farthest_from_line_m, mean};
use crate::part_box::{Boxed, PartBox};

/// A part is a panel (a slab with an outer face that can carry a handle) when its thinnest box
/// extent is below this share of its middle one.
pub const PANEL_SLAB_RATIO: f64 = 0.5;

/// Cells of the height field along each of the panel's two long axes: about this many samples
/// per cell on average ...
const SAMPLES_PER_CELL: usize = 2;
/// ... and between these many cells each way.
const GRID_RANGE: (usize, usize) = (4, 16);
/// A cell is compared with the cells within this share of the grid each way (at least one); the
/// window keeps its size at the panel's edges (a bar along an edge is still a minority of it).
const NEIGHBOURHOOD_FRACTION: f64 = 0.15;
/// A handle stands out of the face around it by at least this share of the panel's own
/// thickness (a refrigerator door's bar stands a sixth of the thick door proud: a hand needs
/// the same clearance behind a bar on a thick door as on a thin one) ...
const STAND_OUT_OF_THICKNESS: f64 = 0.1;
/// ... and at least this share of the panel's diagonal (a groove or a moulding does not).
const STAND_OUT_OF_DIAGONAL: f64 = 0.01;
/// A handle is between these shares of the panel's surface samples.
const SHARE_RANGE: (f64, f64) = (0.002, 0.3);

/// Whether a part's box is a panel: thinner than [`PANEL_SLAB_RATIO`] of its middle extent.
pub(crate) fn is_panel(part: &PartBox) -> bool {
    let [thinnest, middle, _] = part.sorted_extents();
    thinnest < PANEL_SLAB_RATIO * middle
}

/// The centre of the handle standing out of the outer face of a panel (sampled at `points`):
/// the face of its thinnest box axis turned along `away` (away from its parent). `None` when
/// the part is no panel (see [`PANEL_SLAB_RATIO`]) or nothing stands out of its face.
#[must_use]
pub fn panel_handle(points: &[DVec3], away: DVec3) -> Option<DVec3> {
    if points.is_empty() {
        return None;
    }
    standing_out(points, &PartBox::of(points), away).map(|s| mean(&s))
}

/// The samples of a handle standing out of a panel's outer face (see [`panel_handle`]); `part`
/// is the box of `points`.
fn standing_out(points: &[DVec3], part: &PartBox, away: DVec3) -> Option<Vec<DVec3>> {
    if points.is_empty() {
        return None;
    }
    let thin = part.thinnest_axis();
    // Only a slab has an outer face (not a cap, a knob).
    if !is_panel(part) {
        return None;
    }
    let normal = outer_normal(part, away);
    let (a, b) = ((thin + 1) % 3, (thin + 2) % 3);
    let grid = ((points.len() / SAMPLES_PER_CELL) as f64)
        .sqrt()
        .clamp(GRID_RANGE.0 as f64, GRID_RANGE.1 as f64) as usize;
    let reach = ((NEIGHBOURHOOD_FRACTION * grid as f64).round() as usize).max(1);
    let cell_of = |p: &DVec3| {
        let index = |k: usize| {
            let (lo, hi) = part.ranges[k];
            let t = (p.dot(part.axes[k]) - lo) / (hi - lo).max(1e-12);
            ((t * grid as f64) as usize).min(grid - 1)
        };
        index(a) * grid + index(b)
    };
    // Per cell, the outermost level of the surface along the normal; per block of 2 x 2 cells
    // (enough samples to hold both faces), the outermost and innermost.
    let blocks = grid.div_ceil(2);
    let mut top = vec![f64::NEG_INFINITY; grid * grid];
    let mut block_top = vec![f64::NEG_INFINITY; blocks * blocks];
    let mut block_bottom = vec![f64::INFINITY; blocks * blocks];
    let cells: Vec<usize> = points.iter().map(cell_of).collect();
    for (p, &c) in points.iter().zip(&cells) {
        let level = p.dot(normal);
        let block = (c / grid / 2) * blocks + (c % grid) / 2;
        top[c] = top[c].max(level);
        block_top[block] = block_top[block].max(level);
        block_bottom[block] = block_bottom[block].min(level);
    }
    if top.iter().filter(|t| t.is_finite()).count() < grid {
        return None;
    }
    // The panel's own thickness: the median over the blocks.
    let mut thicknesses: Vec<f64> = block_top
        .iter()
        .zip(&block_bottom)
        .filter(|(t, _)| t.is_finite())
        .map(|(t, b)| t - b)
        .collect();
    let thickness = median(&mut thicknesses);
    let rise = (STAND_OUT_OF_THICKNESS * thickness).max(STAND_OUT_OF_DIAGONAL * part.diagonal);
    // The face level around each cell: the median outermost level of its neighbourhood.
    let around: Vec<Option<f64>> = (0..grid * grid)
        .map(|c| {
            let (i, j) = (c / grid, c % grid);
            let window = |k: usize| {
                let start = k
                    .saturating_sub(reach)
                    .min(grid.saturating_sub(2 * reach + 1));
                start..=(start + 2 * reach).min(grid - 1)
            };
            let mut levels: Vec<f64> = window(i)
                .flat_map(|ii| window(j).map(move |jj| ii * grid + jj))
                .map(|n| top[n])
                .filter(|t| t.is_finite())
                .collect();
            (levels.len() >= 3).then(|| median(&mut levels))
        })
        .collect();
    let standing: Vec<DVec3> = points
        .iter()
        .zip(&cells)
        .filter(|(p, c)| around[**c].is_some_and(|face| p.dot(normal) > face + rise))
        .map(|(p, _)| *p)
        .collect();
    let share = standing.len() as f64 / points.len().max(1) as f64;
    (SHARE_RANGE.0..=SHARE_RANGE.1)
        .contains(&share)
        .then_some(standing)
}

/// The unit normal of the outer face of a panel of box `part`: its thinnest box axis turned
/// along `away`.
fn outer_normal(part: &PartBox, away: DVec3) -> DVec3 {
    let thin = part.axes[part.thinnest_axis()];
    if thin.dot(away) < 0.0 { -thin } else { thin }
}

/// A hinge runs along a panel's edge when its axis is this far at most from the panel's plane
/// (|cosine| to the panel's normal): a door's or a lid's, not a knob's or a blade's, which turn
/// about their normal.
const IN_PLANE_COS_MAX: f64 = 0.5;

/// Whether `axis` crosses the plane of a panel (of box `part`) rather than running along it:
/// its |cosine| to the panel's normal is above [`IN_PLANE_COS_MAX`], as for the axis a knob, a
/// blade or a panel spun like a clock hand turns about.
pub(crate) fn axis_across_panel(part: &PartBox, axis: DVec3) -> bool {
    part.axes[part.thinnest_axis()]
        .dot(axis.normalize_or_zero())
        .abs()
        > IN_PLANE_COS_MAX
}

/// A panel is broad when its middle box extent is at least this share of its longest (a door,
/// a lid, a screen; not a lever or a blade) ...
const BROAD_RATIO: f64 = 0.3;
/// ... and a sheet when its surface covers at least this share of its box's two broad faces (not
/// a wire such as a bucket's handle).
const SHEET_FILL_MIN: f64 = 0.3;

/// Whether a part (its box `part`, its surface `area_m2`) is a broad sheet: a panel
/// ([`is_panel`]) that is broad and whose surface fills its broad faces (a door, a lid, a
/// laptop's screen).
pub(crate) fn is_broad_sheet(part: &PartBox, area_m2: f64) -> bool {
    let [_, middle, longest] = part.sorted_extents();
    is_panel(part)
        && middle >= BROAD_RATIO * longest
        && area_m2 >= SHEET_FILL_MIN * 2.0 * middle * longest
}

/// What stands out of a panel's face within this share of the moving parts' diagonal of its
/// parent touches it: a hinge or a fitting, not a handle (a laptop's hinge cover: 0.2 %; door
/// handles of real objects: at least 3 %).
const HANDLE_TOUCH_FRACTION: f64 = 0.01;

/// A handle whose length is at least this many times its width is a bar (a door's or an oven's
/// pull; the bars on the doors of real objects: 3 to 52 times); shorter ones are knobs or pads,
/// which have no direction.
const BAR_ELONGATION_MIN: f64 = 3.0;

/// A panel's handle seen from a hinge line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HandleOnHinge {
    /// How far the handle's middle lies from the line, a share of the moving parts' reach from
    /// it (1: at the far edge).
    pub reach_fraction: f64,
    /// For a bar ([`BAR_ELONGATION_MIN`]): the |cosine| between its length and the line (1: it
    /// runs along the hinge, as the bars of real doors do); `None` for a knob or a pad.
    pub bar_axis_cos: Option<f64>,
    /// The middle of the handle.
    pub centre: DVec3,
    /// The unit normal of the panel's outer face, which the handle stands out of.
    pub outward: DVec3,
}

impl HandleOnHinge {
    /// The cosine between the way the handle first moves when its panel turns about `axis`
    /// through `pivot` toward positive angles (`way` 1) or negative ones (`way` -1) and the
    /// panel's outer normal: 1 when the handle is pulled straight out of the face, -1 when it is
    /// pushed into it. `None` when the handle lies on the line.
    pub(crate) fn opening_cos(&self, axis: DVec3, pivot: DVec3, way: f64) -> Option<f64> {
        let first_move = (axis.cross(self.centre - pivot) * way).try_normalize()?;
        Some(first_move.dot(self.outward))
    }
}

/// Where a panel's handle lies from a hinge line through `pivot` along `axis`: its share of the
/// moving parts' reach from that line, and how a bar runs against the line. The handle of the
/// part itself (`child`: its samples) comes first, then that of the whole moving group
/// (`group`: the part and what it carries, such as a handle fixed to a door). `None` when the
/// part is no panel, the axis does not run along the panel's plane, nothing stands out of its
/// outer face (turned along `away`), or what stands out touches the parent (`parent`: its
/// samples; within [`HANDLE_TOUCH_FRACTION`] of the moving parts' diagonal): a handle is free to
/// grip, what touches the parent is a hinge or a fitting (a laptop's hinge cover).
#[must_use]
pub(crate) fn handle_on_hinge(
    child: &Boxed<'_>,
    group: &Boxed<'_>,
    parent: &[DVec3],
    axis: DVec3,
    pivot: DVec3,
    away: DVec3,
) -> Option<HandleOnHinge> {
    if child.points.is_empty() {
        return None;
    }
    let axis = axis.normalize_or_zero();
    if axis_across_panel(child.part_box(), axis) {
        return None;
    }
    let with_normal = |b: &Boxed<'_>| {
        standing_out(b.points, b.part_box(), away).map(|s| (s, outer_normal(b.part_box(), away)))
    };
    let (standing, outward) = with_normal(child)
        .or_else(|| (group.points.len() > child.points.len()).then(|| with_normal(group))?)?;
    let touch_m = HANDLE_TOUCH_FRACTION * Aabb::from_points(group.points).diagonal();
    let parent = KdTree::new(parent.to_vec());
    if standing
        .iter()
        .any(|p| parent.nearest_distance_within(*p, touch_m).is_some())
    {
        return None;
    }
    let centre = mean(&standing);
    let reach = farthest_from_line_m(group.points, pivot, axis);
    (reach > 0.0).then(|| HandleOnHinge {
        reach_fraction: (centre - pivot).reject_from_normalized(axis).length() / reach,
        bar_axis_cos: bar_direction(&standing).map(|d| d.dot(axis).abs()),
        centre,
        outward,
    })
}

/// The unit direction a handle's samples run along when they form a bar (their longest extent
/// at least [`BAR_ELONGATION_MIN`] times the next); `None` otherwise.
fn bar_direction(handle: &[DVec3]) -> Option<DVec3> {
    let [length, width, _] = principal_axes(handle);
    let extent = |d: DVec3| {
        let (lo, hi) = projection_range(handle, d);
        hi - lo
    };
    (extent(length) >= BAR_ELONGATION_MIN * extent(width)).then_some(length)
}

/// Whether a panel with a handle (the part itself sampled at `child`, or with what it carries,
/// `group`; the outer face turned along `away`) would turn about an `axis` across its plane,
/// spinning in place like a clock hand rather than swinging on an edge.
#[must_use]
pub(crate) fn handled_panel_spun(
    child: &[DVec3],
    group: &[DVec3],
    axis: DVec3,
    away: DVec3,
) -> bool {
    if child.is_empty() {
        return false;
    }
    let child_box = PartBox::of(child);
    axis_across_panel(&child_box, axis)
        && (standing_out(child, &child_box, away).is_some()
            || (group.len() > child.len()
                && standing_out(group, &PartBox::of(group), away).is_some()))
}

/// The median of `values` (reordered); 0 when empty.
fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mid = values.len() / 2;
    *values.select_nth_unstable_by(mid, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a door 0.6 wide (x), 0.8 tall (z) and 0.02 thick (y, outer face toward -y)
    /// whose outer face bulges out by `bulge_m` in its middle, with a bar 0.05 proud of the face
    /// across its top when `bar` is set.
    fn door(bulge_m: f64, bar: bool) -> Vec<DVec3> {
        let mut points = Vec::new();
        let n = 60;
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let (x, z) = (-0.3 + 0.6 * u, 0.8 * v);
                let rise =
                    bulge_m * (std::f64::consts::PI * u).sin() * (std::f64::consts::PI * v).sin();
                points.push(DVec3::new(x, -0.02 - rise, z));
                points.push(DVec3::new(x, 0.0, z));
            }
        }
        if bar {
            for i in 0..=40 {
                for k in 0..=4 {
                    let x = -0.2 + 0.4 * i as f64 / 40.0;
                    points.push(DVec3::new(x, -0.07, 0.72 + 0.03 * k as f64 / 4.0));
                }
            }
        }
        points
    }

    #[test]
    fn a_bar_on_a_bulging_face_is_the_handle_and_the_bulge_is_not() {
        let points = door(0.03, true);
        let handle = panel_handle(&points, -DVec3::Y).expect("the bar is a handle");
        assert!(
            handle.z > 0.7 && handle.x.abs() < 0.05,
            "at the bar: {handle:?}"
        );
        let bare = door(0.03, false);
        assert!(
            panel_handle(&bare, -DVec3::Y).is_none(),
            "a bulge alone is no handle"
        );
    }

    #[test]
    fn the_bar_of_a_thick_refrigerator_door_is_its_handle() {
        // A door 0.6 wide, 0.8 tall and 0.2 thick whose vertical bar near its right edge stands
        // 0.03 proud of its outer face (-y): less than a quarter of the door's thickness.
        let n = 60;
        let mut points: Vec<DVec3> = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (i as f64 / n as f64, j as f64 / n as f64)))
            .flat_map(|(u, v)| {
                let (x, z) = (-0.3 + 0.6 * u, 0.8 * v);
                [DVec3::new(x, -0.2, z), DVec3::new(x, 0.0, z)]
            })
            .collect();
        for i in 0..=40 {
            for k in 0..=4 {
                let z = 0.2 + 0.4 * f64::from(i) / 40.0;
                points.push(DVec3::new(0.24 + 0.02 * f64::from(k) / 4.0, -0.23, z));
            }
        }
        let handle = panel_handle(&points, -DVec3::Y).expect("the bar is a handle");
        assert!((handle.x - 0.25).abs() < 0.02, "at the bar: {handle:?}");
    }

    #[test]
    fn a_thick_part_has_no_handle() {
        // A cube with a stub on one face is not a panel.
        let mut points: Vec<DVec3> = (0..=20)
            .flat_map(|i| (0..=20).flat_map(move |j| (0..=20).map(move |k| (i, j, k))))
            .filter(|(i, j, k)| [i, j, k].iter().any(|c| **c == 0 || **c == 20))
            .map(|(i, j, k)| DVec3::new(i as f64, j as f64, k as f64) * 0.01)
            .collect();
        points.extend((0..20).map(|k| DVec3::new(0.1, -0.03, 0.1 + 0.001 * k as f64)));
        assert!(panel_handle(&points, -DVec3::Y).is_none());
    }

    /// The flat door of `door` with a vertical bar 0.05 proud of its outer face at x = 0.25,
    /// near its right edge (x = 0.3).
    fn door_with_side_bar() -> Vec<DVec3> {
        let mut points = door(0.0, false);
        for i in 0..=40 {
            for k in 0..=4 {
                let z = 0.2 + 0.4 * i as f64 / 40.0;
                points.push(DVec3::new(0.24 + 0.02 * k as f64 / 4.0, -0.07, z));
            }
        }
        points
    }

    /// A wall 0.05 behind the door's inner face, plus `extra` points.
    fn wall(extra: &[DVec3]) -> Vec<DVec3> {
        let mut points: Vec<DVec3> = (0..=30)
            .flat_map(|i| {
                (0..=30)
                    .map(move |j| DVec3::new(-0.3 + 0.02 * i as f64, 0.05, 0.8 * j as f64 / 30.0))
            })
            .collect();
        points.extend_from_slice(extra);
        points
    }

    /// The handle of [`door_with_side_bar`] seen from the hinge through `pivot` along `axis`,
    /// the wall behind the door its parent.
    fn side_bar_on_hinge(axis: DVec3, pivot: DVec3) -> Option<HandleOnHinge> {
        let points = door_with_side_bar();
        handle_on_hinge(
            &Boxed::new(&points),
            &Boxed::new(&points),
            &wall(&[]),
            axis,
            pivot,
            -DVec3::Y,
        )
    }

    #[test]
    fn a_hinge_lies_across_the_door_from_its_handle() {
        let fraction =
            |x: f64| side_bar_on_hinge(DVec3::Z, DVec3::new(x, 0.0, 0.0)).map(|h| h.reach_fraction);
        // Hinged on the left edge, the handle is at 0.55 of the 0.6 reach.
        let far = fraction(-0.3).expect("a handle");
        assert!((far - 0.55 / 0.6).abs() < 0.05, "{far}");
        // Hinged on the right edge, beside the handle.
        let near = fraction(0.3).expect("a handle");
        assert!(near < 0.2, "{near}");
        // A spin about the door's normal is no hinge along its edge.
        assert!(side_bar_on_hinge(DVec3::Y, DVec3::ZERO).is_none());
    }

    #[test]
    fn a_bar_handle_runs_along_its_hinge() {
        let bar_cos = |axis: DVec3, pivot: DVec3| {
            side_bar_on_hinge(axis, pivot)
                .and_then(|h| h.bar_axis_cos)
                .expect("a bar")
        };
        // The vertical bar along the door's vertical hinge on its left edge ...
        assert!(bar_cos(DVec3::Z, DVec3::new(-0.3, 0.0, 0.0)) > 0.99);
        // ... and across a hinge along its bottom edge.
        assert!(bar_cos(DVec3::X, DVec3::ZERO) < 0.05);
    }

    #[test]
    fn a_door_opening_outward_pulls_its_handle_out_of_its_face() {
        // Hinged on its left edge, its outer face toward -y, with the wall behind it at +y.
        let (axis, pivot) = (DVec3::Z, DVec3::new(-0.3, 0.0, 0.0));
        let handle = side_bar_on_hinge(axis, pivot).expect("a handle");
        assert!(handle.outward.dot(-DVec3::Y) > 0.99, "{handle:?}");
        // Turned toward negative angles about +z, the right edge comes out toward -y.
        let out = handle.opening_cos(axis, pivot, -1.0).expect("off the line");
        assert!(out > 0.99, "{out}");
        let into = handle.opening_cos(axis, pivot, 1.0).expect("off the line");
        assert!(into < -0.99, "{into}");
    }

    #[test]
    fn what_stands_out_against_the_parent_is_no_handle() {
        let points = door_with_side_bar();
        // The parent reaches round to touch the bar (a hinge cover seated in its base).
        let parent = wall(&[DVec3::new(0.25, -0.072, 0.4)]);
        let fraction = handle_on_hinge(
            &Boxed::new(&points),
            &Boxed::new(&points),
            &parent,
            DVec3::Z,
            DVec3::new(0.3, 0.0, 0.0),
            -DVec3::Y,
        );
        assert!(fraction.is_none(), "{fraction:?}");
    }
}
