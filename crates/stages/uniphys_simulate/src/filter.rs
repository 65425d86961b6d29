//! Collision-filter policy: which part pairs never generate contacts in the simulation.
//!
//! The policy mirrors what the exported MJCF does in MuJoCo, so the check simulates what a user
//! will simulate:
//! - parent and child of every joint (MuJoCo's `filterparent`; the exporter's colliders of a
//!   hinge and its door touch by construction);
//! - parts welded together by chains of fixed joints (one rigid body in MuJoCo's eyes; contacts
//!   inside it could only produce internal forces);
//! - the caller's excluded pairs (the pipeline passes the touching pairs it writes as MJCF
//!   `<contact><exclude>`).
//!
//! Every other pair collides, so a door swinging into a sibling drawer is stopped, as in MuJoCo.

use std::collections::BTreeSet;

use rapier3d::prelude::{PairFilterContext, PhysicsHooks, SolverFlags};
use uniphys_types::{AssetRecord, JointKind, PartId};

/// Unordered pairs of part positions (in `record.parts`) whose contacts are ignored.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairFilter {
    excluded: BTreeSet<(usize, usize)>,
}

impl PairFilter {
    /// The policy of the module documentation for `record`.
    pub fn new(record: &AssetRecord, excluded_pairs: &[(PartId, PartId)]) -> Self {
        let position = |id: PartId| record.parts.iter().position(|p| p.id == id);
        let mut filter = Self::default();
        for joint in &record.joints {
            if let (Some(a), Some(b)) = (position(joint.parent), position(joint.child)) {
                filter.exclude(a, b);
            }
        }
        for &(a, b) in excluded_pairs {
            if let (Some(a), Some(b)) = (position(a), position(b)) {
                filter.exclude(a, b);
            }
        }
        // Welded groups: union-find over fixed joints.
        let n = record.parts.len();
        let mut group: Vec<usize> = (0..n).collect();
        fn find(group: &mut [usize], mut i: usize) -> usize {
            while group[i] != i {
                group[i] = group[group[i]];
                i = group[i];
            }
            i
        }
        for joint in record.joints.iter().filter(|j| j.kind == JointKind::Fixed) {
            if let (Some(a), Some(b)) = (position(joint.parent), position(joint.child)) {
                let (ra, rb) = (find(&mut group, a), find(&mut group, b));
                group[ra] = rb;
            }
        }
        for a in 0..n {
            for b in (a + 1)..n {
                if find(&mut group, a) == find(&mut group, b) {
                    filter.exclude(a, b);
                }
            }
        }
        filter
    }

    fn exclude(&mut self, a: usize, b: usize) {
        if a != b {
            self.excluded.insert((a.min(b), a.max(b)));
        }
    }

    /// Whether contacts between the parts at positions `a` and `b` are ignored.
    pub fn is_excluded(&self, a: usize, b: usize) -> bool {
        a == b || self.excluded.contains(&(a.min(b), a.max(b)))
    }
}

impl PhysicsHooks for PairFilter {
    fn filter_contact_pair(&self, context: &PairFilterContext<'_>) -> Option<SolverFlags> {
        // Every collider carries the position of its part in `user_data`.
        let part = |h| {
            context
                .colliders
                .get(h)
                .and_then(|c| usize::try_from(c.user_data).ok())
        };
        match (part(context.collider1), part(context.collider2)) {
            (Some(a), Some(b)) if self.is_excluded(a, b) => None,
            _ => Some(SolverFlags::default()),
        }
    }
}
