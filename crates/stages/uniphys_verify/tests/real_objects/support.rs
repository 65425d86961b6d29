//! What the tests share: a shared object loaded with its true joints handed over as a
//! grounder's, the ways a joint is broken, and the checks that a correction put it back.

use uniphys_examples::shared_partnet_object;
use uniphys_geometry::{
    Aabb, ConvexParams, DVec3, TriMesh, convex_decomposition, parallel_map, projection_range,
};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::{CheckOutcome, Joint, JointKind, JointLimits, Provenance};
use uniphys_verify::{JointVerdict, Scene, SweepParams, verify_joint};

// A camera's shutter button is written to travel 5 mm; it meets the bottom of its socket in the
// body 0.3 mm before that. The written limit's overshoot lies in the end stop, so the joint passes
// as written (it was cut to 4.2 mm). Pressed half as far again, it goes through the body: caught,
// and the range this stage writes ends before the body.
pub(crate) const CAMERA: &str = "kitchen-101352";

pub(crate) struct Object {
    pub(crate) scene: Scene,
    /// The true joints, with a grounder's provenance (so they may be corrected).
    pub(crate) joints: Vec<Joint>,
}

pub(crate) fn object(name: &str) -> Object {
    let mut loaded =
        load_asset(&shared_partnet_object(name), &IngestOptions::default()).expect("ingest");
    loaded.asset.rest_on_ground();
    let meshes: Vec<TriMesh> = loaded.asset.parts.iter().map(|p| p.mesh.clone()).collect();
    let colliders: Vec<Vec<TriMesh>> = parallel_map(&meshes, |m| {
        convex_decomposition(m, &ConvexParams::default()).expect("hulls")
    });
    let joints = loaded
        .asset
        .joints
        .iter()
        .map(|j| Joint {
            provenance: Provenance::provider("test-truth", "partnet-mobility"),
            ..j.clone()
        })
        .collect();
    Object {
        scene: Scene::new(&meshes, &colliders, 1500).expect("scene"),
        joints,
    }
}

impl Object {
    pub(crate) fn movable(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&i| self.joints[i].kind.is_movable())
            .collect()
    }

    /// The movable joints of kind `kind`.
    pub(crate) fn movable_of(&self, kind: JointKind) -> Vec<usize> {
        self.movable()
            .into_iter()
            .filter(|&i| self.joints[i].kind == kind)
            .collect()
    }

    /// Joint `i` made a revolute joint a quarter turn about its own axis through `pivot` (a
    /// round part, turned part-way about the line it is round about) is caught as moving
    /// nothing; the correction keeps the line and is returned.
    fn part_way_round_turn_corrected(&self, i: usize, pivot: DVec3) -> (Joint, String) {
        let truth = &self.joints[i];
        let quarter = Joint {
            kind: JointKind::Revolute,
            pivot_in_object_m: pivot.to_array(),
            limits: Some(JointLimits {
                lower: 0.0,
                upper: std::f64::consts::FRAC_PI_2,
            }),
            ..truth.clone()
        };
        let (fixed, change) = self.corrected(i, quarter, "less than a half turn");
        assert_eq!(fixed.axis_in_object, truth.axis_in_object, "{change}");
        assert_eq!(fixed.pivot_in_object_m, pivot.to_array(), "{change}");
        (fixed, change)
    }

    /// [`Self::part_way_round_turn_corrected`], corrected to a spin about the same line.
    pub(crate) fn assert_part_way_round_turn_spun(&self, i: usize, pivot: DVec3) {
        let (fixed, change) = self.part_way_round_turn_corrected(i, pivot);
        assert_eq!(fixed.kind, JointKind::Continuous, "{change}");
    }

    /// [`Self::part_way_round_turn_corrected`], corrected to a press along the same line the
    /// way the true joint goes, by at most the part's depth along it.
    pub(crate) fn assert_part_way_round_turn_pressed(&self, i: usize, pivot: DVec3) {
        let truth = &self.joints[i];
        let (fixed, change) = self.part_way_round_turn_corrected(i, pivot);
        assert_eq!(fixed.kind, JointKind::Prismatic, "{change}");
        let (range, true_range) = (fixed.limits.expect("range"), truth.limits.expect("range"));
        let travel = |l: JointLimits| if l.upper > -l.lower { l.upper } else { l.lower };
        assert!(
            travel(range) * travel(true_range) > 0.0,
            "{change}: pressed the other way from the true {true_range:?}"
        );
        let part = self.scene.points_of(&[truth.child.0 as usize]);
        let (lo, hi) = projection_range(&part, DVec3::from_array(truth.axis_in_object));
        assert!(
            travel(range).abs() <= hi - lo,
            "{change}: deeper than the part"
        );
    }

    /// Verifies joint `i` of `joints` (correction on).
    pub(crate) fn verify(&self, joints: &[Joint], i: usize) -> JointVerdict {
        verify_joint(&self.scene, joints, i, &SweepParams::default(), true).expect("verify")
    }

    /// The joints with joint `i` replaced by `broken`.
    pub(crate) fn with(&self, i: usize, broken: Joint) -> Vec<Joint> {
        let mut joints = self.joints.clone();
        joints[i] = broken;
        joints
    }

    /// Joint `i` with its range reversed fails for `reason` and is corrected back to its true
    /// range by a reversal.
    pub(crate) fn assert_reversal_caught_and_undone(&self, i: usize, reason: &str) {
        let truth = &self.joints[i];
        let (fixed, change) = self.corrected(i, reversed(truth), reason);
        assert!(change.contains("reversed"), "{change}");
        assert_eq!(fixed.limits, truth.limits);
    }

    /// Joint `i` turned a quarter ([`sideways`]) fails for `reason` and is corrected back onto
    /// its true line ([`assert_restored_to_true_line`]).
    pub(crate) fn assert_sideways_caught_and_restored(&self, i: usize, reason: &str) {
        let truth = &self.joints[i];
        let verdict = self.caught(i, sideways(truth));
        assert!(verdict.message.contains(reason), "{}", verdict.message);
        assert_restored_to_true_line(&verdict, truth, part_diagonal(self, truth.child.0));
    }

    /// `truth` with its hinge line moved across its part's centre, to the opposite edge.
    pub(crate) fn hinged_on_opposite_edge(&self, truth: &Joint) -> Joint {
        let axis = DVec3::from_array(truth.axis_in_object).normalize();
        let pivot = DVec3::from_array(truth.pivot_in_object_m);
        let part = self.scene.points_of(&[truth.child.0 as usize]);
        let centre = part.iter().sum::<DVec3>() / part.len() as f64;
        Joint {
            pivot_in_object_m: (pivot - 2.0 * (pivot - centre).reject_from_normalized(axis))
                .to_array(),
            ..truth.clone()
        }
    }

    /// Joint `i` made a slide along its own line (half the part's length along it, as
    /// verify-bench's "revolute made prismatic" does) is caught and corrected back to a joint
    /// of its true kind on its true line ([`assert_restored_to_true_line`]); returns it.
    pub(crate) fn assert_slide_hinged_again(&self, i: usize) -> Joint {
        let truth = &self.joints[i];
        let axis = DVec3::from_array(truth.axis_in_object).normalize();
        let (lo, hi) = projection_range(&self.scene.points_of(&[truth.child.0 as usize]), axis);
        let slide = Joint {
            kind: JointKind::Prismatic,
            limits: Some(JointLimits {
                lower: 0.0,
                upper: 0.5 * (hi - lo),
            }),
            ..truth.clone()
        };
        let verdict = self.caught(i, slide);
        assert_restored_to_true_line(&verdict, truth, part_diagonal(self, truth.child.0));
        let (fixed, change) = verdict.correction.expect("corrected");
        assert_eq!(fixed.kind, truth.kind, "{change}");
        fixed
    }

    /// Verifies joint `i` with `broken` in its place, which the sweep must fail.
    pub(crate) fn caught(&self, i: usize, broken: Joint) -> JointVerdict {
        let verdict = self.verify(&self.with(i, broken), i);
        assert_ne!(verdict.outcome, CheckOutcome::Pass, "{}", verdict.message);
        verdict
    }

    /// [`Self::caught`] for a message naming `reason`; returns the correction and what it
    /// changed.
    pub(crate) fn corrected(&self, i: usize, broken: Joint, reason: &str) -> (Joint, String) {
        let verdict = self.caught(i, broken);
        assert!(verdict.message.contains(reason), "{}", verdict.message);
        verdict.correction.expect("corrected")
    }
}

/// `truth` with its axis turned a quarter ([`quarter_turned`]).
pub(crate) fn sideways(truth: &Joint) -> Joint {
    Joint {
        axis_in_object: quarter_turned(truth.axis_in_object),
        ..truth.clone()
    }
}

/// A correction, if the verdict made one, may only give back the true axis (within 2 degrees).
pub(crate) fn assert_correction_keeps_true_axis(verdict: &JointVerdict, truth: &Joint) {
    if let Some((fixed, _)) = &verdict.correction {
        assert!(
            line_angle_deg(fixed.axis_in_object, truth.axis_in_object) < 2.0,
            "{fixed:?}"
        );
    }
}

/// Angle between two lines, degrees.
pub(crate) fn line_angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (a, b) = (
        DVec3::from_array(a).normalize(),
        DVec3::from_array(b).normalize(),
    );
    a.dot(b).abs().clamp(0.0, 1.0).acos().to_degrees()
}

/// `axis` turned a quarter, towards the object axis least aligned with it.
pub(crate) fn quarter_turned(axis: [f64; 3]) -> [f64; 3] {
    let axis = DVec3::from_array(axis).normalize();
    let least = [DVec3::X, DVec3::Y, DVec3::Z]
        .into_iter()
        .min_by(|a, b| a.dot(axis).abs().total_cmp(&b.dot(axis).abs()))
        .unwrap_or(DVec3::X);
    least.reject_from_normalized(axis).normalize().to_array()
}

pub(crate) fn assert_true_joints_pass_unchanged(name: &str) {
    let o = object(name);
    let movable = o.movable();
    assert!(!movable.is_empty(), "{name} has movable joints");
    for i in movable {
        let verdict = o.verify(&o.joints, i);
        assert_eq!(
            verdict.outcome,
            CheckOutcome::Pass,
            "{name} {}: {}",
            o.joints[i].name,
            verdict.message
        );
        assert!(verdict.correction.is_none());
    }
}

/// The range of `joint` reversed: the part moves the other way.
pub(crate) fn reversed(joint: &Joint) -> Joint {
    let limits = joint.limits.expect("a limited joint");
    Joint {
        limits: Some(JointLimits {
            lower: -limits.upper,
            upper: -limits.lower,
        }),
        ..joint.clone()
    }
}

/// The correction of `verdict` turns about the true hinge line of `truth`: its axis within 2
/// degrees and its pivot within 5 % of the moving part's diagonal (`diagonal`) of the line.
pub(crate) fn assert_restored_to_true_line(verdict: &JointVerdict, truth: &Joint, diagonal: f64) {
    let (fixed, change) = verdict.correction.as_ref().expect("corrected");
    assert!(
        line_angle_deg(fixed.axis_in_object, truth.axis_in_object) < 2.0,
        "{change}: {fixed:?}"
    );
    let axis = DVec3::from_array(truth.axis_in_object).normalize();
    let off_line = (DVec3::from_array(fixed.pivot_in_object_m)
        - DVec3::from_array(truth.pivot_in_object_m))
    .reject_from_normalized(axis)
    .length();
    assert!(
        off_line < 0.05 * diagonal,
        "{change}: {off_line} m off the true line"
    );
}

/// The corrected joint's range, read along the true axis (reversed when its axis points the
/// other way), overlaps the true range by more than half of it.
pub(crate) fn assert_range_overlaps_truth(fixed: &Joint, truth: &Joint, context: &str) {
    let way = DVec3::from_array(fixed.axis_in_object).dot(DVec3::from_array(truth.axis_in_object));
    let (f, t) = (fixed.limits.expect("range"), truth.limits.expect("range"));
    let (lo, hi) = if way > 0.0 {
        (f.lower, f.upper)
    } else {
        (-f.upper, -f.lower)
    };
    let overlap = hi.min(t.upper) - lo.max(t.lower);
    assert!(
        overlap > 0.5 * (t.upper - t.lower),
        "{context}: {f:?} against {t:?}"
    );
}

/// Diagonal of the box of part `part`'s samples, metres.
pub(crate) fn part_diagonal(o: &Object, part: u32) -> f64 {
    Aabb::from_points(&o.scene.points_of(&[part as usize])).diagonal()
}
