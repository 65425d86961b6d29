//! The settings of an articulation sweep ([`crate::sweep`]): its steps and every rule's bound,
//! distances as fractions of the object's diagonal or of the parts involved.

use crate::patch::PatchParams;

/// Parameters of a sweep. Distances are fractions of the object diagonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepParams {
    /// Joint coordinates visited, both limits included (reference: 200).
    pub steps: usize,
    /// Contact threshold search.
    pub patch: PatchParams,
    /// Turning joints fail when the 95th percentile of the contact thickness ratio exceeds this
    /// (reference: 3, for every joint).
    pub thickness_ratio_max: f64,
    /// A step's contact overlap below this is bad (reference: 0.4).
    pub overlap_min: f64,
    /// Rotational joints fail when more than this fraction of steps has bad overlap and the
    /// 10th percentile is bad too (reference: 0.1).
    pub bad_overlap_fraction_max: f64,
    /// Interpenetration of colliders beyond their overlap at rest (a fraction of the object
    /// diagonal) counted as a penetrating step; reported, and a penalty of the grounder's
    /// hypotheses, but no failure: convex hulls fill the cavities of real parts.
    pub penetration_tolerance_fraction: f64,
    /// The joint fails when more than this fraction of the moving surface that is clear of other
    /// parts at rest passes through another part's surface where the moving parts were not at
    /// rest.
    pub crossing_fraction_max: f64,
    /// A limited joint's last this fraction of travel on each side is its end stop: what the
    /// moving surface crosses only there is the part meeting its stop a little past where a
    /// real limit was written (a button pressed to the bottom of its socket), reported in
    /// `end_stop_crossed_fraction` and no failure.
    pub end_stop_travel_fraction: f64,
    /// Moving surface points this close to another part at rest (a fraction of the moving
    /// group's diagonal, at most `rest_contact_object_fraction` of the object's) are in contact
    /// at rest: they may slide along or out of it. A point crossing another part's surface
    /// counts once it goes this fraction of the group's diagonal beyond it (no object bound: a
    /// limit a degree long sinks a part's far end by a share of the part's own length).
    pub rest_contact_part_fraction: f64,
    /// Upper bound of that contact distance, a fraction of the object diagonal.
    pub rest_contact_object_fraction: f64,
    /// A slide whose travel is at most this fraction of its parent's diagonal is short (a button,
    /// a key, a cap's lift): it must stay at its parent all the way.
    pub short_slide_fraction: f64,
    /// How far a short slide's moving group may move away from its parent beyond its gap at
    /// rest, as a fraction of the group's diagonal.
    pub short_slide_gap_fraction: f64,
    /// A short slide of a part that its parent's face surrounds in at least this share of the
    /// directions around its axis (a button set into a face) must go toward its parent: it is
    /// at its outer stop at rest (true buttons of real objects: 0.81 to 1) ...
    pub short_slide_surround_min: f64,
    /// ... and one surrounded in at most this share (a lid capping its parent's end) must go
    /// away from it: it lifts off (true lids of real objects: 0 to 0.13) ...
    pub short_slide_capping_max: f64,
    /// ... when its parent reaches at most this many times the part's radius from its axis
    /// around the level where they touch ([`crate::SlideSide::parent_reach_ratio`]: true lids
    /// and caps of real objects 1.0 to 1.5); a part on a broader face (knobs and buttons on
    /// appliances' fronts: 28 to 52) must go toward its parent, however little of the face
    /// shows just outside its outline.
    pub short_slide_cap_reach_max: f64,
    /// A short slide presses into (or lifts off) the face it sits on, or slides along walls
    /// that guide it. Where its moving samples touch the parent at rest (within
    /// `rest_contact_part_fraction` of the group's diagonal), the parent's surface normals give
    /// a tensor `T` (mean of `n n^T`): the slide presses when `a^T T a` is at least this share
    /// of `T`'s largest eigenvalue (true buttons and lids of real objects: 0.97 to 1; slid
    /// across the face: 0) ...
    pub short_slide_press_min: f64,
    /// ... or is guided when `T` restricted to the plane across the axis has both eigenvalues at
    /// least this (the neck a cap slides along: 0.37 to 0.5; a flat face: 0).
    pub short_slide_guidance_min: f64,
    /// A slide fails when its parent holds its part from both ends along the axis
    /// ([`crate::SlideTrap`]): faces facing both ways weigh at least this share of the touching
    /// samples (true slides of real objects whose faces lie apart: at most 0.035; their lids
    /// and drawers slid a quarter turn off their axis: 0.1 to 0.45) ...
    pub slide_trap_share_min: f64,
    /// ... and lie at least this share of the part's length along the axis apart (a part drawn
    /// slightly into its parent at rest has faces facing both ways at one place).
    pub slide_trap_separation_min: f64,
    /// A hinge along a panel's edge fails when the panel's handle lies nearer its axis than this
    /// share of the panel's reach from the axis: the handle is near the free edge (true hinges
    /// of real objects: at least 0.47; moved to the opposite edge: at most 0.35).
    pub hinge_handle_fraction_min: f64,
    /// A hinge (revolute) along a panel's edge fails when the panel's bar handle runs across it:
    /// the |cosine| between the bar and the axis below this (the bars on true hinges of real
    /// objects: 0.7 to 1; hinges turned a quarter: at most 0.04). A door's pull runs along its
    /// hinge, a side-hinged door's upright and an oven door's level.
    pub hinge_bar_cos_min: f64,
    /// A hinge (revolute) that turns a panel with a handle one way from rest fails when the
    /// handle's first move, against the panel's outer normal, has a cosine below this: it
    /// pushes the handle into the face, so the panel opens away from its handle (a door swung
    /// into its oven); a handle is pulled (true hinges of real objects: 0.98 to 1; reversed:
    /// about -1).
    pub handle_opening_cos_min: f64,
    /// A hinge (revolute) along the plane of a broad sheet (a door, a lid, a screen) fails when
    /// its line runs away from the parent: its mean distance to the parent's surface over the
    /// sheet's stretch above this share of the moving parts' diagonal (true hinges of real
    /// objects: at most 0.09; a laptop's screen or a lid hinged across its hinge line: 0.19 to
    /// 0.29). A panel hangs on the line where it meets its parent.
    pub sheet_hinge_off_parent_max: f64,
    /// ... when it is held along an edge: its contact with the parent at rest runs along at
    /// least this share of its box diagonal (a door's, a lid's or a screen's hinge line; a
    /// spout held on its collar by a small patch is not judged so).
    pub sheet_contact_fraction_min: f64,
    /// A long slide (a drawer) runs in a slot: its parent walls it in on at least this many of
    /// the four sides across its axis, or it presses into (lifts off) the face it sits on (at
    /// least `short_slide_press_min`) and, when it is a broad sheet, moves across its own plane
    /// (a lid lifted off its pot; a door lifted along its cabinet's face off the ledge it rests
    /// on is not). A door or lid pushed along its own face is in no slot.
    pub long_slide_walled_sides_min: usize,
    /// ... and stays in it: its travel is at most this many times its own length along the
    /// slide (the drawers of real objects: 0.59 to 0.93 of their depth). A door pulled straight
    /// out of its frame leaves the slot after its thickness; then only a lift holds it.
    pub long_slide_travel_share_max: f64,
    /// ... and one held only by lifting off that face lifts: on an object standing on the
    /// ground, the direction it travels rises by at least this share (a lid lifted off its
    /// pot). Pulled straight off a cabinet's front (a door made a slide) or dropped from under a
    /// table's top (a drawer slid down out of its frame), nothing but the face held it.
    pub long_slide_lift_rise_min: f64,
    /// ... walled in by any part that stays still, not only its parent. For parts a
    /// decomposition cut: the still body may be several parts, and the one a part hangs from is
    /// a guess (a drawer's parent may be one board of its carcass, its other walls other
    /// boards). Off for authored parts, whose parent is the body that holds the slot (a door
    /// slid along its face between two other doors is not in a slot).
    pub slot_walled_by_any_still_part: bool,
    /// A hinge (revolute) fails when its parent walls its moving parts in on at least this many
    /// of the four sides across its axis: they sit in a slot along the axis, which they slide
    /// along and do not turn about (the drawers of real objects: 2 to 4, mostly 3; true hinges:
    /// at most 2). A panel turned about its own normal between its parent's faces (a folding
    /// knife's blade between its scales: 3) is judged by the in-plane rule instead.
    pub hinge_slot_walled_sides_min: usize,
    /// A hinge (a revolute joint) fails when its moving colliders sink into the still ones, beyond
    /// their overlap at rest, by more than this many penetration tolerances on average over its
    /// sweep: a door swung into its own hollow cabinet, whose convex pieces fill the cavity (true
    /// hinges of real objects: at most 1.1; doors reversed into their cabinets: 2.1 to 5.7).
    /// Continuous joints and slides are exempt: a wheel turns and a drawer slides inside hulls
    /// that fill their housing.
    pub hinge_sink_mean_max: f64,
    /// A turning joint fails when its axis line passes farther than this fraction of the moving
    /// group's diagonal from the group's surface: a hinge pin or spin axis is held by the part it
    /// turns (true joints of real objects: at most 3.3 %).
    pub hinge_off_part_fraction: f64,
    /// A hinge (revolute) fails when it turns a flat panel about the panel's own normal (like a
    /// clock hand) and the panel is neither round about the axis (its roundness residual, a
    /// share of its diagonal, above this: knobs of real objects on true hinges 0.01, and on
    /// continuous joints, which are not judged so, at most 0.04; doors, screens and legs spun
    /// about a corner 0.18 to 0.42) ...
    pub in_plane_round_max: f64,
    /// ... nor held across both faces (below this share of the samples with a still surface
    /// close over or under them have one on both sides: the folding knife blades of real
    /// objects between their handle's scales 1.0; a laptop's screen whose foot sits between its
    /// base's hinge blocks 0.52; doors and lids lying on one face of their parent 0). A panel
    /// in a slot is held on both faces nearly wherever it is held at all.
    pub in_plane_sandwiched_share_min: f64,
    /// A continuous joint fails when it spins a part that is round about another line about a
    /// line it is not round about: its roundness residual about the joint's line above this
    /// share of its diagonal (true continuous joints of real objects: at most 0.04, spouts that
    /// are round about no line aside; wheels and knobs flipped about a diameter: 0.07 to 0.19).
    pub off_round_residual_min: f64,
    /// A revolute joint limited to less than a half turn fails when its moving parts are a disc
    /// or a drum round about its line (no longer along it than across it): their roundness
    /// residual there at most this share of their diagonal. A
    /// round part turned part-way lands on itself and moves nothing; a knob spins (continuous,
    /// or nearly a full turn: an oven's knobs turn 330 degrees), a round button or cap is
    /// pushed or lifted along the line (true revolute joints of the shared real objects limited
    /// to less than a half turn: 0.05 for a faucet's switch, 0.07 and more for doors; each of
    /// their 31 round buttons and lids turned a quarter about its own line: at most 0.03).
    pub part_way_round_residual_max: f64,
    /// A joint fails when it takes a moving part below the ground the object stands on (its
    /// lowest point at rest in the service frame, Z up) by more than this fraction of the object
    /// diagonal (true joints of real objects: at most 1.5 %, a stapler's pressed arm aside;
    /// laptop screens opened backwards: at least 12 %).
    pub below_ground_fraction_max: f64,
    /// Seed of the candidate search of corrections.
    pub seed: u64,
}

impl Default for SweepParams {
    /// 200 steps, the reference's ratios, penetration tolerance 1.5 % of the diagonal, at most
    /// 2 % of the clear moving surface through other parts, contact at rest within 3 % of the
    /// moving group's diagonal (at most 1 % of the object's), a turning axis within 10 % of the
    /// moving group's diagonal from its surface.
    fn default() -> Self {
        Self {
            steps: 200,
            patch: PatchParams::default(),
            thickness_ratio_max: 3.0,
            overlap_min: 0.4,
            bad_overlap_fraction_max: 0.1,
            penetration_tolerance_fraction: 0.015,
            crossing_fraction_max: 0.02,
            end_stop_travel_fraction: 0.1,
            rest_contact_part_fraction: 0.03,
            rest_contact_object_fraction: 0.01,
            short_slide_fraction: 0.05,
            short_slide_gap_fraction: 0.1,
            hinge_off_part_fraction: 0.1,
            short_slide_press_min: 0.5,
            short_slide_surround_min: 0.75,
            short_slide_capping_max: 0.25,
            short_slide_cap_reach_max: 3.0,
            short_slide_guidance_min: 0.15,
            slide_trap_share_min: 0.08,
            slide_trap_separation_min: 0.2,
            hinge_handle_fraction_min: 0.4,
            hinge_bar_cos_min: 0.5,
            handle_opening_cos_min: -0.5,
            sheet_hinge_off_parent_max: 0.15,
            sheet_contact_fraction_min: 0.45,
            long_slide_walled_sides_min: 2,
            long_slide_travel_share_max: 1.5,
            long_slide_lift_rise_min: 0.5,
            slot_walled_by_any_still_part: false,
            hinge_slot_walled_sides_min: 3,
            hinge_sink_mean_max: 2.0,
            in_plane_round_max: 0.1,
            in_plane_sandwiched_share_min: 0.75,
            off_round_residual_min: 0.06,
            part_way_round_residual_max: 0.03,
            below_ground_fraction_max: 0.05,
            seed: 7,
        }
    }
}
