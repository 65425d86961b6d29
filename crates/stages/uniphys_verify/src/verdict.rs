//! The verdict on a sweep: which physical rules its metrics break ([`SweepMetrics::failures`]),
//! how badly, comparably across variants of one joint ([`SweepMetrics::severity`]), where it
//! first failed, and its metrics by name.

use std::collections::BTreeMap;

use uniphys_types::JointKind;

use crate::fit::ROUND_RESIDUAL_MAX;
use crate::in_plane::InPlaneTurn;
use crate::off_round::OffRoundSpin;
use crate::slide_side::SlideSide;
use crate::slide_trap::SlideTrap;
use crate::sweep::SweepMetrics;
use crate::sweep_params::SweepParams;

impl SweepMetrics {
    /// Why the joint fails, empty when it passes:
    /// - the child does not touch its parent at rest;
    /// - rotational joints: the axis line passes clear of the moving parts (nothing holds it), or
    ///   a hinge along a panel's edge lies at the panel's handle rather than across from it;
    /// - hinges (revolute): a panel turns in its own plane though it is neither round about the
    ///   axis nor held across both faces (a door spun about its corner over the cabinet's front);
    /// - continuous joints: a part round about one line spins about another (a wheel flipped
    ///   about its diameter);
    /// - hinges (revolute) limited to less than a half turn: the part is round about the axis
    ///   (`part_way_round_residual_max`), so turned it lands on itself and moves nothing (a
    ///   round button or cap given a quarter turn);
    /// - hinges (revolute) turning a panel with a handle one way from rest: the handle's first
    ///   move pushes it into the panel's face (`handle_opening_cos_min`: a door swung into its
    ///   oven);
    /// - rotational joints: contact lost at some step while the axis runs away from the parent,
    ///   or severe overlap change (more than `bad_overlap_fraction_max` of steps below
    ///   `overlap_min` and the 10th percentile too; not for a spin of a part round about its
    ///   line, which turns in place);
    /// - short slides: the part moves away from a face of its parent that surrounds it or
    ///   reaches far around it (a button or a knob pulled out), into a parent whose end it caps
    ///   (a lid pushed in), or across the face it sits on (neither pressing into it nor guided
    ///   by walls);
    /// - slides: the parent holds the part from both ends along the axis (`slide_trap_share_min`
    ///   and `slide_trap_separation_min`: a lid seated in a rim slid sideways);
    /// - hinges (revolute): the part sits in a slot along the axis (walled in on
    ///   `hinge_slot_walled_sides_min` sides across it: a drawer turned about its depth);
    /// - long slides: the part runs in no slot of its parent (walled in on too few sides across
    ///   the axis) and does not lift off the face it sits on (a door or lid pushed along its
    ///   own face), or, on an object standing on the ground, lifts off it without rising (a
    ///   door pulled straight off a cabinet's front);
    /// - hinges (revolute): the moving colliders sink into the still ones by more than
    ///   `hinge_sink_mean_max` penetration tolerances on average over the sweep (a door swung
    ///   into its own hollow cabinet, which no surface crossing shows when the door is inset);
    /// - rotational joints but a spin in place: the 95th percentile thickness ratio above
    ///   `thickness_ratio_max` (a door turned into a hollow cabinet crosses nothing: its rim, in
    ///   contact with the frame at rest, sinks past it and the contact thickens; a slide's points
    ///   move along straight lines, so anything it passes through is a crossing measured across
    ///   the crossed plane, while its contact, spread over rails and frame in several planes,
    ///   thickens and thins as it slides);
    /// - any joint: more than `crossing_fraction_max` of the moving surface clear of other parts
    ///   at rest passes through another part's surface (where it crosses inside the space the
    ///   moving parts filled at rest, only deeper than a short slide's travel counts: what
    ///   overlapped at rest, or a symmetric part turning in place, is not new; what is crossed
    ///   only in a limited joint's end stops, the last `end_stop_travel_fraction` of its travel
    ///   on each side, is a stop met a little before the written limit and does not count);
    /// - any joint: a moving part goes below the ground the object stands on by more than
    ///   `below_ground_fraction_max` of the diagonal (a laptop's screen opened backwards).
    #[must_use]
    pub fn failures(&self, params: &SweepParams) -> Vec<String> {
        let mut reasons = Vec::new();
        if self.initial_contact_points == 0 {
            reasons.push("the moving part does not touch its parent at rest".to_owned());
        }
        if self.hinge_off_part() {
            reasons.push(format!(
                "the axis passes {:.4} m from the moving part (at most {:.4} m): nothing holds it",
                self.hinge_to_part_m, self.hinge_to_part_max_m
            ));
        }
        if let Some(turn) = self.spun_in_plane(params) {
            reasons.push(format!(
                "turns a flat panel in its own plane like a clock hand: it is not round about the axis (residual {:.3} of its diagonal, at most {:.3}) and not held across both faces ({:.0} % of its samples with a still surface close over or under them have one on both sides, at least {:.0} %)",
                turn.residual,
                params.in_plane_round_max,
                100.0 * turn.sandwiched_share,
                100.0 * params.in_plane_sandwiched_share_min
            ));
        }
        if let Some(spin) = self.spun_off_round(params) {
            let (a, p) = (spin.round_axis, spin.round_point);
            reasons.push(format!(
                "spins a round part about a line it is not round about: turned, it lands {:.3} of its diagonal from itself (at most {:.3}), and {:.3} about the line along ({:.3}, {:.3}, {:.3}) through ({:.4}, {:.4}, {:.4}); a knob, a wheel or a cap spins about its own axis",
                spin.residual,
                params.off_round_residual_min,
                spin.round_residual,
                a.x,
                a.y,
                a.z,
                p.x,
                p.y,
                p.z
            ));
        }
        if let Some(residual) = self.turned_round_part_way(params) {
            reasons.push(format!(
                "turns a part round about its axis less than a half turn: turned, it lands {residual:.3} of its diagonal from itself (at most {:.3} counts as round), so it moves nothing; a knob spins, a round button or cap is pushed or lifted along the axis",
                params.part_way_round_residual_max
            ));
        }
        if let Some(f) = self.hinge_at_handle(params) {
            reasons.push(format!(
                "hinged at its handle: the handle lies {f:.2} of the part's reach from the axis (at least {:.2}); a handle sits near the free edge",
                params.hinge_handle_fraction_min
            ));
        }
        if let Some(off) = self.sheet_hinged_off_parent(params) {
            reasons.push(format!(
                "a panel hinged away from its parent: the axis runs {:.2} of the moving parts' diagonal from the parent on average (at most {:.2}); a door, a lid or a screen hangs on the line where it meets its parent",
                off, params.sheet_hinge_off_parent_max
            ));
        }
        if let Some(cos) = self.hinge_across_bar(params) {
            reasons.push(format!(
                "hinged across its handle's bar: the bar runs {:.0} degrees from the axis (at most {:.0}); a door's pull runs along its hinge",
                cos.clamp(0.0, 1.0).acos().to_degrees(),
                params.hinge_bar_cos_min.clamp(0.0, 1.0).acos().to_degrees()
            ));
        }
        if let Some(cos) = self.opened_away_from_handle(params) {
            reasons.push(format!(
                "opens away from its handle: the handle first moves {:.0} degrees from the way its face looks (at most {:.0}); a handle is pulled, so a door or a lid opens toward it",
                cos.clamp(-1.0, 1.0).acos().to_degrees(),
                params.handle_opening_cos_min.clamp(-1.0, 1.0).acos().to_degrees()
            ));
        }
        if self.hinge_lost_contact() {
            reasons.push(format!(
                "hinge lost contact with its parent in {} of {} steps",
                self.lost_contact_steps, self.steps
            ));
        }
        if self.severe_overlap_change(params) {
            reasons.push(format!(
                "severe contact overlap change: p10 = {:.3}, bad fraction = {:.3}",
                self.overlap_ratio_p10, self.bad_overlap_fraction
            ));
        }
        if self.contact_change_judged() && self.thickness_ratio_p95 > params.thickness_ratio_max {
            reasons.push(format!(
                "severe contact thickness change: p95 ratio = {:.2}",
                self.thickness_ratio_p95
            ));
        }
        if let Some(sink) = self.hinge_sunk(params) {
            reasons.push(format!(
                "the hinge sinks its part into the others: {sink:.2} penetration tolerances on average over the sweep (at most {:.2})",
                params.hinge_sink_mean_max
            ));
        }
        if self.short_slide_unheld(params) {
            reasons.push(format!(
                "a short slide moves across the face it sits on: it presses into it {:.2} (at least {:.2}) and is guided by walls {:.2} (at least {:.2})",
                self.short_slide_press,
                params.short_slide_press_min,
                self.short_slide_guidance,
                params.short_slide_guidance_min
            ));
        }
        if let Some(side) = self.short_slide_wrong_way(params) {
            reasons.push(if side.away > 0.0 && Self::on_broad_face(&side, params) {
                format!(
                    "a short slide pulls its part off the broad face it stands on (its parent reaches {:.1} times the part's radius from its axis there, a part capping its parent's end at most {:.1}): a knob or a button is pressed in, toward its parent",
                    side.parent_reach_ratio, params.short_slide_cap_reach_max
                )
            } else if side.away > 0.0 {
                format!(
                    "a short slide pulls its part out of the face around it (surrounded in {:.0} % of the directions, at least {:.0} %): a button is pressed in, toward its parent",
                    100.0 * side.surround_share,
                    100.0 * params.short_slide_surround_min
                )
            } else {
                format!(
                    "a short slide pushes its part into the parent it caps (surrounded in {:.0} % of the directions, at most {:.0} %): a lid lifts off, away from its parent",
                    100.0 * side.surround_share,
                    100.0 * params.short_slide_capping_max
                )
            });
        }
        if let Some(trap) = self.slide_trapped(params) {
            reasons.push(format!(
                "a slide pushes its part into its parent whichever way it goes: faces of its parent hold it from both ends along the axis ({:.0} % of its contact each way, at least {:.0} %, {:.2} of its length apart, at least {:.2}); a lid seated in a rim lifts out of it, a drawer slides along its slot",
                100.0 * trap.two_way_share,
                100.0 * params.slide_trap_share_min,
                trap.separation,
                params.slide_trap_separation_min
            ));
        }
        if self.hinge_in_slot(params) {
            reasons.push(format!(
                "turns its part about the axis of a slot: its parent walls it in on {} of the 4 sides across the axis (at most {}); what sits in a slot slides along it",
                self.hinge_slot_walled_sides,
                params.hinge_slot_walled_sides_min.saturating_sub(1)
            ));
        }
        if self.long_slide_unheld(params) {
            let held = match self.long_slide_sideways(params) {
                _ if self.long_slide_along_sheet
                    && self.short_slide_press >= params.short_slide_press_min =>
                {
                    "it is a broad sheet (a door, a lid) moved along its own plane: only a slot \
                     holds a sheet sliding along itself; one lifted off a face moves across it"
                        .to_owned()
                }
                Some(rise) if self.short_slide_press >= params.short_slide_press_min => format!(
                    "it lifts off the face it sits on rising {rise:.2} of its travel (at least {:.2}): only a part lifted up off a face is held by it",
                    params.long_slide_lift_rise_min
                ),
                _ => format!(
                    "it presses into the face it sits on {:.2} (at least {:.2})",
                    self.short_slide_press, params.short_slide_press_min
                ),
            };
            let slot = if self.long_slide_walled_sides >= params.long_slide_walled_sides_min {
                format!(
                    "a long slide runs out of its slot: it travels {:.2} of its own length along the slide (at most {:.2})",
                    self.long_slide_travel_share, params.long_slide_travel_share_max
                )
            } else {
                format!(
                    "a long slide runs in no slot: its parent walls it in on {} of 4 sides (at least {})",
                    self.long_slide_walled_sides, params.long_slide_walled_sides_min
                )
            };
            reasons.push(format!("{slot} and {held}"));
        }
        if self.short_slide_left_parent() {
            reasons.push(format!(
                "a short slide leaves its parent: {:.4} m further away than at rest (at most {:.4} m)",
                self.short_slide_gap_growth_m, self.short_slide_gap_max_m
            ));
        }
        if self.crossed_before_end_stops() > params.crossing_fraction_max {
            let part = self
                .crossed_part
                .map_or_else(|| "?".to_owned(), |p| p.to_string());
            reasons.push(format!(
                "passes through part {part}: {:.1} % of its clear surface from coordinate {:.4} (at most {:.1} %)",
                100.0 * self.crossed_before_end_stops(),
                self.crossing_coordinate.unwrap_or(f64::NAN),
                100.0 * params.crossing_fraction_max
            ));
        }
        if self.below_ground() {
            reasons.push(format!(
                "goes through the ground the object stands on: {:.4} m below its lowest point at rest from coordinate {:.4} (at most {:.4} m)",
                self.below_ground_m,
                self.below_ground_coordinate.unwrap_or(f64::NAN),
                self.below_ground_max_m
            ));
        }
        reasons
    }

    /// How badly the joint fails, comparable across variants of one joint: the largest of each
    /// rule's measure over its limit. Crossed fraction, a turning joint's thickness ratio and a
    /// hinge's mean penetration count as they are; when they fail, lost contact of a turning
    /// joint counts 1 plus ten times its share of steps, a severe overlap change 1 plus five
    /// times its excess of bad steps, a short slide leaving its parent 1 plus its gap over the
    /// allowed one, a panel opened away from its handle 1 plus its cosine's shortfall. Failures
    /// no change of range can mend count 2 plus their excess: an axis clear of the part, a hinge
    /// at its handle or across its bar, a panel hinged away from its parent, a panel spun in its
    /// own plane, a round part spun off its round line, a short slide across its face; a long
    /// slide in no slot, a hinge about a slot's axis, a short slide the wrong way or a slide held
    /// from both ends counts 2.5. 10 without contact at rest. At most 1 when the sweep passes:
    /// then the margin to each rule (a short slide's gap growth over the allowed one, the axis's
    /// distance from the part over the allowed one, the least handle distance over the
    /// handle's), so a press is preferred to a pull and a hinge across the part from its handle
    /// to one beside it.
    #[must_use]
    pub fn severity(&self, params: &SweepParams) -> f64 {
        if self.initial_contact_points == 0 {
            return 10.0;
        }
        let steps = self.steps.max(1) as f64;
        let mut s = self.crossed_before_end_stops() / params.crossing_fraction_max;
        if self.crossed_fraction > params.crossing_fraction_max {
            // Crossing at an end stop passes with no margin left.
            s = s.max(1.0);
        }
        if self.contact_change_judged() {
            s = s.max(self.thickness_ratio_p95 / params.thickness_ratio_max);
        }
        if self.short_slide_gap_max_m > 0.0 {
            s = s.max(self.short_slide_gap_growth_m / self.short_slide_gap_max_m);
        }
        if self.hinge_to_part_max_m > 0.0 {
            s = s.max(self.hinge_to_part_m / self.hinge_to_part_max_m);
        }
        if self.below_ground_max_m > 0.0 {
            s = s.max(self.below_ground_m / self.below_ground_max_m);
        }
        if let Some(f) = self.handle_reach_fraction {
            s = s.max(params.hinge_handle_fraction_min / f.max(1e-9));
        }
        if self.hinge_lost_contact() {
            s = s.max(1.0 + 10.0 * self.lost_contact_steps as f64 / steps);
        }
        if let Some(cos) = self.opened_away_from_handle(params) {
            s = s.max(1.0 + params.handle_opening_cos_min - cos);
        }
        if self.severe_overlap_change(params) {
            s = s.max(1.0 + 5.0 * (self.bad_overlap_fraction - params.bad_overlap_fraction_max));
        }
        if self.short_slide_left_parent() {
            s = s.max(1.0 + self.short_slide_gap_growth_m / self.short_slide_gap_max_m);
        }
        if self.hinge_off_part() {
            s = s.max(2.0 + self.hinge_to_part_m / self.hinge_to_part_max_m);
        }
        if let Some(f) = self.hinge_at_handle(params) {
            s = s.max(3.0 - f / params.hinge_handle_fraction_min);
        }
        if let Some(cos) = self.hinge_across_bar(params) {
            s = s.max(3.0 - cos / params.hinge_bar_cos_min.max(1e-12));
        }
        if let Some(off) = self.sheet_hinged_off_parent(params) {
            s = s.max(2.0 + off / params.sheet_hinge_off_parent_max.max(1e-12));
        }
        if let Some(turn) = self.spun_in_plane(params) {
            s = s.max(2.0 + turn.residual / params.in_plane_round_max.max(1e-12));
        }
        if let Some(spin) = self.spun_off_round(params) {
            s = s.max(2.0 + spin.residual / params.off_round_residual_min.max(1e-12));
        }
        if let Some(residual) = self.turned_round_part_way(params) {
            s = s.max(3.0 - residual / params.part_way_round_residual_max.max(1e-12));
        }
        if self.long_slide_unheld(params)
            || self.short_slide_wrong_way(params).is_some()
            || self.slide_trapped(params).is_some()
            || self.hinge_in_slot(params)
        {
            s = s.max(2.5);
        }
        if self.kind == JointKind::Revolute {
            s = s.max(self.hinge_sink() / params.hinge_sink_mean_max);
        }
        if self.short_slide_unheld(params) {
            let held = (self.short_slide_press / params.short_slide_press_min)
                .max(self.short_slide_guidance / params.short_slide_guidance_min);
            s = s.max(3.0 - held);
        }
        s
    }

    /// The joint turns (revolute or continuous).
    fn rotational(&self) -> bool {
        matches!(self.kind, JointKind::Revolute | JointKind::Continuous)
    }

    /// A turning joint whose contact with its parent is judged for change (thickening,
    /// overlap lost): every one but a spin of a disc or a drum round about its line, which turns
    /// in place and lands on itself, so its contact can change only where its outline is not
    /// round (a wheel's spokes passing the fork that holds its axle). A sliver spun about its
    /// length seems round by its diagonal whatever its section, and is judged.
    fn contact_change_judged(&self) -> bool {
        self.rotational()
            && !self
                .spin_round_residual
                .is_some_and(|r| r <= ROUND_RESIDUAL_MAX)
    }

    /// A turning joint's contact changed severely: more than `bad_overlap_fraction_max` of its
    /// contact steps overlap the rest contact less than `overlap_min`, and its 10th percentile
    /// does too.
    fn severe_overlap_change(&self, params: &SweepParams) -> bool {
        self.contact_change_judged()
            && self.contact_steps > 0
            && self.bad_overlap_fraction > params.bad_overlap_fraction_max
            && self.overlap_ratio_p10 < params.overlap_min
    }

    /// A hinge's mean penetration growth in tolerances, when it sinks its part too deep into the
    /// others.
    fn hinge_sunk(&self, params: &SweepParams) -> Option<f64> {
        let sink = self.hinge_sink();
        (self.kind == JointKind::Revolute && sink > params.hinge_sink_mean_max).then_some(sink)
    }

    /// Mean penetration growth over the sweep, in penetration tolerances.
    fn hinge_sink(&self) -> f64 {
        self.mean_penetration_growth_m / self.penetration_tolerance_m.max(1e-12)
    }

    /// The handle's share of the reach from the axis when it is too near the hinge.
    fn hinge_at_handle(&self, params: &SweepParams) -> Option<f64> {
        self.handle_reach_fraction
            .filter(|&f| f < params.hinge_handle_fraction_min)
    }

    /// The cosine between a handle's first move and its panel's outer normal, when the hinge
    /// pushes the handle into the face.
    fn opened_away_from_handle(&self, params: &SweepParams) -> Option<f64> {
        self.handle_opening_cos
            .filter(|&cos| self.kind == JointKind::Revolute && cos < params.handle_opening_cos_min)
    }

    /// A broad sheet's hinge line's mean distance from its parent, when too far.
    fn sheet_hinged_off_parent(&self, params: &SweepParams) -> Option<f64> {
        self.sheet_hinge_off_parent
            .filter(|&off| off > params.sheet_hinge_off_parent_max)
    }

    /// The |cosine| between a hinge and its panel's bar handle when the bar runs across it.
    fn hinge_across_bar(&self, params: &SweepParams) -> Option<f64> {
        self.handle_bar_axis_cos
            .filter(|&cos| self.kind == JointKind::Revolute && cos < params.hinge_bar_cos_min)
    }

    /// A hinge spins a panel in its own plane that is neither round about the axis nor held
    /// across both faces.
    fn spun_in_plane(&self, params: &SweepParams) -> Option<InPlaneTurn> {
        self.in_plane_turn.filter(|t| {
            t.residual > params.in_plane_round_max
                && t.sandwiched_share < params.in_plane_sandwiched_share_min
        })
    }

    /// A continuous joint spins a part round about another line about one it is not round
    /// about.
    fn spun_off_round(&self, params: &SweepParams) -> Option<OffRoundSpin> {
        self.off_round_spin.filter(|s| {
            self.kind == JointKind::Continuous && s.residual > params.off_round_residual_min
        })
    }

    /// A revolute joint turns a part round about its line less than a half turn: the residual.
    pub(crate) fn turned_round_part_way(&self, params: &SweepParams) -> Option<f64> {
        self.part_way_round_residual
            .filter(|&r| r <= params.part_way_round_residual_max)
    }

    /// The moving parts went deeper below the ground than allowed.
    fn below_ground(&self) -> bool {
        self.below_ground_m > self.below_ground_max_m
    }

    /// A turning joint's axis runs clear of the parts it turns.
    fn hinge_off_part(&self) -> bool {
        self.hinge_to_part_max_m > 0.0 && self.hinge_to_part_m > self.hinge_to_part_max_m
    }

    /// A short slide neither presses into the face it touches nor slides along guiding walls.
    fn short_slide_unheld(&self, params: &SweepParams) -> bool {
        self.short_slide_gap_max_m > 0.0
            && self.short_slide_press < params.short_slide_press_min
            && self.short_slide_guidance < params.short_slide_guidance_min
    }

    /// A short slide goes the wrong way: out of a face that surrounds its part or off a broad
    /// face it stands on, or into the parent its part caps.
    fn short_slide_wrong_way(&self, params: &SweepParams) -> Option<SlideSide> {
        self.short_slide_side.filter(|side| {
            let held_on_face = side.surround_share >= params.short_slide_surround_min
                || Self::on_broad_face(side, params);
            (held_on_face && side.away > 0.0)
                || (Self::caps_parent(side, params) && side.away < 0.0)
        })
    }

    /// A short slide pulls its part off a broad face of its parent it stands on, though little
    /// of the face shows just outside its outline ([`Self::on_broad_face`]).
    pub(crate) fn pulled_off_broad_face(&self, params: &SweepParams) -> bool {
        self.short_slide_wrong_way(params)
            .is_some_and(|side| side.away > 0.0 && Self::on_broad_face(&side, params))
    }

    /// A short slide's part caps its parent's end: no face of the parent just outside its
    /// outline, and the parent no wider than a few times the part there.
    fn caps_parent(side: &SlideSide, params: &SweepParams) -> bool {
        side.surround_share <= params.short_slide_capping_max
            && side.parent_reach_ratio <= params.short_slide_cap_reach_max
    }

    /// A short slide's part stands on a face of its parent reaching far around it, though
    /// little of the face shows just outside its outline (a knob in a ring-shaped recess).
    fn on_broad_face(side: &SlideSide, params: &SweepParams) -> bool {
        side.surround_share < params.short_slide_surround_min
            && side.parent_reach_ratio > params.short_slide_cap_reach_max
    }

    /// A slide whose parent holds its part from both ends along the axis.
    fn slide_trapped(&self, params: &SweepParams) -> Option<SlideTrap> {
        self.slide_trap.filter(|t| {
            self.kind == JointKind::Prismatic
                && t.two_way_share >= params.slide_trap_share_min
                && t.separation >= params.slide_trap_separation_min
        })
    }

    /// A hinge turns its part about the axis of a slot its parent holds it in.
    fn hinge_in_slot(&self, params: &SweepParams) -> bool {
        self.kind == JointKind::Revolute
            && self.hinge_slot_walled_sides >= params.hinge_slot_walled_sides_min
    }

    /// A long slide runs in no slot it stays in, and does not lift up off the face it sits on
    /// (across its own plane, when it is a broad sheet).
    fn long_slide_unheld(&self, params: &SweepParams) -> bool {
        !self.long_slide_in_slot(params)
            && (self.short_slide_press < params.short_slide_press_min
                || self.long_slide_along_sheet
                || self.long_slide_sideways(params).is_some())
    }

    /// A long slide runs in a slot its parent walls in and stays in it over its travel.
    fn long_slide_in_slot(&self, params: &SweepParams) -> bool {
        self.long_slide_walled_sides >= params.long_slide_walled_sides_min
            && self.long_slide_travel_share <= params.long_slide_travel_share_max
    }

    /// How much a long slide on the ground rises, when it rises less than a lift must.
    fn long_slide_sideways(&self, params: &SweepParams) -> Option<f64> {
        self.long_slide_rise
            .filter(|&rise| rise < params.long_slide_lift_rise_min)
    }

    /// A short slide moved its part away from its parent by more than it may.
    fn short_slide_left_parent(&self) -> bool {
        self.short_slide_gap_max_m > 0.0
            && self.short_slide_gap_growth_m > self.short_slide_gap_max_m
    }

    /// A turning joint lost contact with its parent: some step found no contact patch, and the
    /// axis itself runs away from the parent (a hinge on its parent keeps the part attached
    /// even where a thick door or a handle swings clear of the parent's surface).
    fn hinge_lost_contact(&self) -> bool {
        self.rotational()
            && self.initial_contact_points > 0
            && self.lost_contact_steps > 0
            && self.hinge_to_parent_m > self.contact_reach_m
    }

    /// Share of the clear moving surface that crossed another part before the end stops.
    fn crossed_before_end_stops(&self) -> f64 {
        (self.crossed_fraction - self.end_stop_crossed_fraction).max(0.0)
    }

    /// The coordinate where the sweep first failed (passed through a part, lost contact or went
    /// below the ground), if it did at a known step.
    #[must_use]
    pub fn failure_coordinate(&self) -> Option<f64> {
        let lost = self
            .lost_contact_coordinate
            .filter(|_| self.hinge_lost_contact());
        [self.crossing_coordinate, lost, self.below_ground_coordinate]
            .into_iter()
            .flatten()
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
    }

    /// The metrics by name, units in the names.
    #[must_use]
    pub fn as_map(&self) -> BTreeMap<String, f64> {
        let entries = [
            ("steps", self.steps as f64),
            ("initial_contact_points", self.initial_contact_points as f64),
            ("contact_threshold_m", self.contact_threshold_m),
            ("contact_steps", self.contact_steps as f64),
            ("lost_contact_steps", self.lost_contact_steps as f64),
            ("thickness_ratio_p95", self.thickness_ratio_p95),
            ("overlap_ratio_p10", self.overlap_ratio_p10),
            ("bad_overlap_fraction", self.bad_overlap_fraction),
            ("max_penetration_growth_m", self.max_penetration_growth_m),
            ("mean_penetration_growth_m", self.mean_penetration_growth_m),
            ("penetrating_steps", self.penetrating_steps as f64),
            ("penetration_tolerance_m", self.penetration_tolerance_m),
            ("worst_coordinate", self.worst_coordinate),
            ("clear_points", self.clear_points as f64),
            ("crossed_points", self.crossed_points as f64),
            ("crossed_fraction", self.crossed_fraction),
            ("end_stop_crossed_fraction", self.end_stop_crossed_fraction),
            ("hinge_to_parent_m", self.hinge_to_parent_m),
            ("hinge_mean_to_parent_m", self.hinge_mean_to_parent_m),
            ("hinge_pin_to_parent_m", self.hinge_pin_to_parent_m),
            ("hinge_to_part_m", self.hinge_to_part_m),
            ("hinge_to_part_max_m", self.hinge_to_part_max_m),
            ("below_ground_m", self.below_ground_m),
            ("short_slide_gap_growth_m", self.short_slide_gap_growth_m),
            ("short_slide_press", self.short_slide_press),
            ("short_slide_guidance", self.short_slide_guidance),
            (
                "long_slide_walled_sides",
                self.long_slide_walled_sides as f64,
            ),
            (
                "long_slide_along_sheet",
                f64::from(u8::from(self.long_slide_along_sheet)),
            ),
            ("long_slide_travel_share", self.long_slide_travel_share),
            (
                "hinge_slot_walled_sides",
                self.hinge_slot_walled_sides as f64,
            ),
        ];
        // Measured only for some joints: present when measured.
        let measured = [
            ("handle_reach_fraction", self.handle_reach_fraction),
            ("handle_bar_axis_cos", self.handle_bar_axis_cos),
            ("handle_opening_cos", self.handle_opening_cos),
            ("sheet_hinge_off_parent", self.sheet_hinge_off_parent),
            ("long_slide_rise", self.long_slide_rise),
            ("part_way_round_residual", self.part_way_round_residual),
            ("spin_round_residual", self.spin_round_residual),
        ];
        entries
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .chain(
                measured
                    .into_iter()
                    .filter_map(|(k, v)| v.map(|v| (k.to_owned(), v))),
            )
            .chain(self.in_plane_turn.into_iter().flat_map(|t| {
                [
                    ("in_plane_residual".to_owned(), t.residual),
                    ("in_plane_sandwiched_share".to_owned(), t.sandwiched_share),
                ]
            }))
            .chain(self.off_round_spin.into_iter().flat_map(|s| {
                [
                    ("off_round_residual".to_owned(), s.residual),
                    ("off_round_round_residual".to_owned(), s.round_residual),
                ]
            }))
            .chain(self.short_slide_side.into_iter().flat_map(|s| {
                [
                    ("short_slide_surround_share".to_owned(), s.surround_share),
                    ("short_slide_away".to_owned(), s.away),
                    (
                        "short_slide_parent_reach_ratio".to_owned(),
                        s.parent_reach_ratio,
                    ),
                ]
            }))
            .chain(self.slide_trap.into_iter().flat_map(|t| {
                [
                    ("slide_trap_two_way_share".to_owned(), t.two_way_share),
                    ("slide_trap_separation".to_owned(), t.separation),
                ]
            }))
            .collect()
    }
}
