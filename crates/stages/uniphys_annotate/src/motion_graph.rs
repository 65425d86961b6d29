//! The motion dependency graph (reference section 6) from the neighbours of the properties
//! answer: which parts move, on which parent, how, and which parts move with them.
//!
//! Rules, with every departure reported as a [`MotionIssue`] instead of being resolved silently:
//! - a B (slide) or C (turn) relation makes its child a movable part with that parent; a movable
//!   part has one parent: a second one is a contradiction, the first is kept;
//! - a parent link that would close a cycle is refused and reported;
//! - a pair with B/C and also D is a contradiction (D ignored); a pair with A and also B/C/D
//!   breaks the prompt's rule (A ignored); the two sides of a pair that disagree on the range or
//!   damping keep the first;
//! - the co-moving group of a movable part is the part plus the parts rigidly (D) linked to it,
//!   transitively, never crossing into another movable part or into its own ancestors.
//!
//! The reference pulled every neighbour of a movable part into its group at the first hop,
//! touch-only (A) neighbours included, so a drawer dragged the shelf it rests on along with it;
//! here A neighbours never join a group.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use uniphys_types::{JointKind, JointLimits};

use crate::quantities::motion_range;
use crate::schema::{MovementType, PropertiesAnswer};

/// A part that moves relative to its parent.
#[derive(Debug, Clone, PartialEq)]
pub struct MovablePart {
    /// Its label.
    pub label: u32,
    /// The label of the part it moves on.
    pub parent: u32,
    /// [`JointKind::Prismatic`] (B) or [`JointKind::Revolute`] (C).
    pub kind: JointKind,
    /// Limits in SI (m or rad) from the answer's range.
    pub limits: JointLimits,
    /// The answer's damping coefficient (N s/m or N m s/rad).
    pub damping: f64,
    /// The labels that move rigidly with it, itself included, sorted.
    pub group: Vec<u32>,
}

/// A rigid attachment of a group member to the group (`child` fixed to `parent`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct FixedLink {
    /// The part it is fixed to.
    pub parent: u32,
    /// The attached part.
    pub child: u32,
}

/// What kind of inconsistency the answer had.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionIssueKind {
    /// A movable part was given a second parent (the first is kept).
    TwoParents,
    /// A parent link would close a cycle (refused).
    Cycle,
    /// A pair is both touching (A) and linked (B/C/D): A ignored.
    TouchAndLinked,
    /// Two relations of a pair exclude each other (e.g. D and C, or opposite directions).
    Contradiction,
    /// The two sides of a pair give different ranges or damping (the first is kept).
    Disagreement,
    /// A neighbour label that is not a part.
    UnknownLabel,
    /// A part rigidly linked to two moving groups (kept in the first).
    SharedRigidPart,
}

/// One reported inconsistency.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct MotionIssue {
    /// Kind.
    pub kind: MotionIssueKind,
    /// Labels involved.
    pub labels: Vec<u32>,
    /// What happened and what was kept.
    pub message: String,
}

/// The graph: movable parts, rigid attachments inside their groups, and the issues.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MotionGraph {
    /// Movable parts, by label.
    pub movable: Vec<MovablePart>,
    /// Rigid links from each group member to the part it was reached from.
    pub fixed: Vec<FixedLink>,
    /// Every inconsistency found.
    pub issues: Vec<MotionIssue>,
}

#[derive(Debug, Clone)]
struct Motion {
    parent: u32,
    child: u32,
    kind: MovementType,
    damping: f64,
    range: String,
}

#[derive(Default)]
struct Pair {
    first_seen: usize,
    motion: Option<Motion>,
    rigid: bool,
    touch: bool,
}

impl MotionGraph {
    fn issue(&mut self, kind: MotionIssueKind, labels: &[u32], message: String) {
        let mut labels = labels.to_vec();
        labels.sort_unstable();
        labels.dedup();
        self.issues.push(MotionIssue {
            kind,
            labels,
            message,
        });
    }

    /// The movable part with this label.
    #[must_use]
    pub fn movable_part(&self, label: u32) -> Option<&MovablePart> {
        self.movable.iter().find(|m| m.label == label)
    }
}

/// Builds the graph from a validated properties answer.
#[must_use]
pub fn motion_graph(answer: &PropertiesAnswer) -> MotionGraph {
    let mut graph = MotionGraph::default();
    let labels: BTreeSet<u32> = answer.parts.iter().map(|p| p.label).collect();
    let pairs = collect_pairs(answer, &labels, &mut graph);

    let mut order: Vec<(&(u32, u32), &Pair)> = pairs.iter().collect();
    order.sort_by_key(|(key, pair)| (pair.first_seen, **key));
    let mut parent_of: BTreeMap<u32, Motion> = BTreeMap::new();
    for (_, pair) in &order {
        let Some(motion) = &pair.motion else { continue };
        if let Some(existing) = parent_of.get(&motion.child) {
            graph.issue(
                MotionIssueKind::TwoParents,
                &[motion.child, existing.parent, motion.parent],
                format!(
                    "part {} moves on part {} and also on part {}; a moving part has one parent, the first ({}) is kept",
                    motion.child, existing.parent, motion.parent, existing.parent
                ),
            );
            continue;
        }
        if ancestors(&parent_of, motion.parent).contains(&motion.child) {
            graph.issue(
                MotionIssueKind::Cycle,
                &[motion.child, motion.parent],
                format!(
                    "part {} moving on part {} would close a cycle (part {} already hangs from part {}); refused",
                    motion.child, motion.parent, motion.parent, motion.child
                ),
            );
            continue;
        }
        parent_of.insert(motion.child, motion.clone());
    }

    let rigid: BTreeMap<u32, Vec<u32>> = {
        let mut adjacency: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for ((a, b), pair) in &pairs {
            if pair.rigid && pair.motion.is_none() {
                adjacency.entry(*a).or_default().push(*b);
                adjacency.entry(*b).or_default().push(*a);
            }
        }
        adjacency
    };
    let mut claimed: BTreeMap<u32, u32> = BTreeMap::new();
    for (&child, motion) in &parent_of {
        let ancestry = ancestors(&parent_of, motion.parent);
        let mut group = BTreeSet::from([child]);
        let mut queue = VecDeque::from([child]);
        while let Some(at) = queue.pop_front() {
            for &next in rigid.get(&at).map(Vec::as_slice).unwrap_or_default() {
                if group.contains(&next) {
                    continue;
                }
                if next == motion.parent || ancestry.contains(&next) {
                    graph.issue(
                        MotionIssueKind::Contradiction,
                        &[child, at, next],
                        format!(
                            "part {at} moves with part {child} but is rigidly linked to part {next}, which part {child} moves relative to; the link is ignored"
                        ),
                    );
                    continue;
                }
                if parent_of.contains_key(&next) {
                    graph.issue(
                        MotionIssueKind::Contradiction,
                        &[child, at, next],
                        format!(
                            "part {next} has its own joint but is rigidly linked to part {at} of the group of part {child}; the rigid link is ignored"
                        ),
                    );
                    continue;
                }
                if let Some(&owner) = claimed.get(&next) {
                    graph.issue(
                        MotionIssueKind::SharedRigidPart,
                        &[next, owner, child],
                        format!(
                            "part {next} is rigidly linked to the moving groups of part {owner} and part {child}; it stays with part {owner}"
                        ),
                    );
                    continue;
                }
                claimed.insert(next, child);
                group.insert(next);
                graph.fixed.push(FixedLink {
                    parent: at,
                    child: next,
                });
                queue.push_back(next);
            }
        }
        let range = motion_range(&motion.range).map(|r| r.bounds());
        let Some((lower, upper)) = range else {
            // Validated answers always parse; keep the part out rather than guess a range.
            graph.issue(
                MotionIssueKind::Contradiction,
                &[child],
                format!("part {child}: range {:?} does not parse", motion.range),
            );
            continue;
        };
        graph.movable.push(MovablePart {
            label: child,
            parent: motion.parent,
            kind: if motion.kind == MovementType::B {
                JointKind::Prismatic
            } else {
                JointKind::Revolute
            },
            limits: JointLimits { lower, upper },
            damping: motion.damping,
            group: group.into_iter().collect(),
        });
    }
    graph.fixed.sort_unstable();
    graph
}

/// The parent chain of `part` (itself included).
fn ancestors(parent_of: &BTreeMap<u32, Motion>, part: u32) -> BTreeSet<u32> {
    let mut out = BTreeSet::from([part]);
    let mut at = part;
    while let Some(m) = parent_of.get(&at) {
        if !out.insert(m.parent) {
            break;
        }
        at = m.parent;
    }
    out
}

fn collect_pairs(
    answer: &PropertiesAnswer,
    labels: &BTreeSet<u32>,
    graph: &mut MotionGraph,
) -> BTreeMap<(u32, u32), Pair> {
    let mut pairs: BTreeMap<(u32, u32), Pair> = BTreeMap::new();
    let mut index = 0usize;
    for part in &answer.parts {
        for n in &part.neighbours {
            index += 1;
            if !labels.contains(&n.label) || n.label == part.label {
                graph.issue(
                    MotionIssueKind::UnknownLabel,
                    &[part.label, n.label],
                    format!(
                        "part {} names neighbour {}, which is not another part; ignored",
                        part.label, n.label
                    ),
                );
                continue;
            }
            let key = (part.label.min(n.label), part.label.max(n.label));
            let pair = pairs.entry(key).or_insert_with(|| Pair {
                first_seen: index,
                ..Pair::default()
            });
            match n.movement_type {
                MovementType::A => {
                    if !pair.touch && (pair.rigid || pair.motion.is_some()) {
                        touch_and_linked(graph, key);
                    }
                    pair.touch = true;
                }
                MovementType::D => {
                    if pair.touch && !pair.rigid && pair.motion.is_none() {
                        touch_and_linked(graph, key);
                    }
                    if let Some(m) = &pair.motion {
                        graph.issue(
                            MotionIssueKind::Contradiction,
                            &[key.0, key.1],
                            format!(
                                "parts {} and {} are said to be rigidly joined (D) and to move ({:?}); the motion is kept",
                                key.0, key.1, m.kind
                            ),
                        );
                    }
                    pair.rigid = true;
                }
                MovementType::B | MovementType::C => {
                    let (Some(parent), Some(child), Some(damping), Some(range)) =
                        (n.parent, n.child, n.damping, n.range.clone())
                    else {
                        continue;
                    };
                    if pair.touch && !pair.rigid && pair.motion.is_none() {
                        touch_and_linked(graph, key);
                    }
                    let motion = Motion {
                        parent,
                        child,
                        kind: n.movement_type,
                        damping,
                        range,
                    };
                    match &pair.motion {
                        None => {
                            if pair.rigid {
                                graph.issue(
                                    MotionIssueKind::Contradiction,
                                    &[key.0, key.1],
                                    format!(
                                        "parts {} and {} are said to be rigidly joined (D) and to move ({:?}); the motion is kept",
                                        key.0, key.1, motion.kind
                                    ),
                                );
                            }
                            pair.motion = Some(motion);
                        }
                        Some(first)
                            if first.kind != motion.kind || first.parent != motion.parent =>
                        {
                            graph.issue(
                                MotionIssueKind::Contradiction,
                                &[key.0, key.1],
                                format!(
                                    "parts {} and {}: {:?} with parent {} contradicts {:?} with parent {} given first; the first is kept",
                                    key.0, key.1, motion.kind, motion.parent, first.kind, first.parent
                                ),
                            );
                        }
                        Some(first)
                            if first.range.trim() != motion.range.trim()
                                || (first.damping - motion.damping).abs() > 1e-12 =>
                        {
                            graph.issue(
                                MotionIssueKind::Disagreement,
                                &[key.0, key.1],
                                format!(
                                    "parts {} and {}: range {:?} damping {} disagrees with {:?} damping {} given first; the first is kept",
                                    key.0, key.1, motion.range, motion.damping, first.range, first.damping
                                ),
                            );
                        }
                        Some(_) => {}
                    }
                }
            }
        }
    }
    pairs
}

fn touch_and_linked(graph: &mut MotionGraph, key: (u32, u32)) {
    graph.issue(
        MotionIssueKind::TouchAndLinked,
        &[key.0, key.1],
        format!(
            "parts {} and {} are said to merely touch (A) and to be linked (B/C/D); the touch is ignored",
            key.0, key.1
        ),
    );
}
