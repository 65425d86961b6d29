//! The articulation of an asset whose part names do not say what slides or turns (`link_0`,
//! `Mesh.002`, `handle`): the tree from size, contact and the ground (its root stands on it),
//! each part's joint from its shape and sweeps of candidate motions
//! ([`crate::motion_search`]).

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_types::{Joint, JointKind, PartId, Provenance};
use uniphys_verify::Scene;

use crate::BUILTIN_PROVIDER;
use crate::articulate::{PartInput, carried_by, fixed_joint, kind_word, pairwise_distances, pid};
use crate::hypotheses::SCREEN_SAMPLES;
use crate::motion_search::{Mover, PartBox, TOUCH_FRACTION, find_motion, touching};
use crate::roles::{Role, role_of};
use crate::tree::build_tree_by_size;

/// Names that keep a part fixed to what it is on (names are a prior: a part called `handle` on
/// a mug or a door is not swept for a motion of its own). Knobs and buttons move, so their names
/// leave the choice to geometry.
const FIXED_ATTACHMENTS: [&str; 4] = ["handle", "grip", "pull", "hinge"];
/// Parts at least this fraction of the largest part's size are candidates for the root.
const BIG_FRACTION: f64 = 0.5;
/// A root candidate whose box is this many times every other's is the root whatever its solid
/// volume.
const BULKIER_RATIO: f64 = 2.0;
/// A big part that does not stand on the ground is a root candidate only when its box is this
/// many times that of every big part that does (a microwave whose door hangs open below it); a
/// spout, a screen or a lens held above the ground by a base is not.
const HANGING_BULK_RATIO: f64 = 4.0;

/// Root, one joint per other part, and notes on every choice; the scene's error when the parts
/// cannot be swept (an object without extent).
pub(crate) fn unnamed_joints(
    parts: &[PartInput<'_>],
) -> Result<(PartId, Vec<Joint>, Vec<String>), String> {
    let n = parts.len();
    let meshes: Vec<TriMesh> = parts.iter().map(|p| p.mesh.clone()).collect();
    let colliders: Vec<Vec<TriMesh>> = parts.iter().map(|p| p.colliders.to_vec()).collect();
    let scene = Scene::new(&meshes, &colliders, SCREEN_SAMPLES).map_err(|e| e.to_string())?;
    let distance = pairwise_distances(parts);
    // The root carries the others: among the big parts (at least half the size of the largest),
    // the one touching the most big parts, then the bulkiest ([`root_among`]): a cabinet's or a
    // fridge's body, a laptop's base rather than its screen, a bottle rather than its cap; a
    // handle on a door does not make the door the root.
    let touch_m = TOUCH_FRACTION * scene.diagonal_m;
    let diagonals: Vec<f64> = parts.iter().map(|p| p.mesh.bounds().diagonal()).collect();
    let largest = diagonals.iter().copied().fold(0.0, f64::max);
    let big = |i: usize| diagonals[i] >= BIG_FRACTION * largest;
    let touches: Vec<usize> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| j != i && big(j) && distance[i][j] <= touch_m)
                .count()
        })
        .collect();
    let points: Vec<Vec<DVec3>> = (0..n).map(|i| scene.points_of(&[i])).collect();
    let boxes: Vec<PartBox> = points.iter().map(|p| PartBox::of(p)).collect();
    let mut sizes: Vec<f64> = (0..n)
        .map(|i| box_volume(&points[i], &boxes[i], scene.diagonal_m))
        .collect();
    let pool = root_pool(
        &(0..n).filter(|&i| big(i)).collect::<Vec<_>>(),
        &sizes,
        &scene,
    );
    let most = pool.iter().map(|&i| touches[i]).max().unwrap_or(0);
    let candidates: Vec<usize> = pool.into_iter().filter(|&i| touches[i] == most).collect();
    let root_part = root_among(&candidates, &sizes, parts);
    sizes[root_part] = f64::INFINITY;
    // How many of part i's samples touch part j.
    let mut contact = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in (0..n).filter(|&j| j != i && distance[i][j] <= touch_m) {
            contact[i][j] = touching(&scene, j, &points[i], touch_m).len() as f64;
        }
    }
    let (root, parents) = build_tree_by_size(&sizes, &|i, j| contact[i][j], &|i, j| distance[i][j]);
    let mut joints = Vec::new();
    let mut notes = vec![format!(
        "no part is named: {:?}, among the big parts (those standing on the ground, when any does) the one touching the most big parts and then the bulkiest, is the root; every other part hangs from the bigger part it touches most, and its joint comes from its shape and sweeps of its motions",
        parts[root.0 as usize].name
    )];
    for (i, parent) in parents.iter().enumerate() {
        let Some(p) = *parent else { continue };
        if let (Role::Attachment, Some(word)) = role_of(parts[i].name)
            && FIXED_ATTACHMENTS.contains(&word)
        {
            notes.push(format!(
                "part {:?} on {:?}: fixed (named as a {word}, which is fixed to what it is on)",
                parts[i].name, parts[p].name
            ));
            joints.push(fixed_joint(
                pid(p),
                pid(i),
                parts[i].mass.com,
                Provenance::provider(BUILTIN_PROVIDER, format!("named as a {word}: fixed")),
            ));
            continue;
        }
        let mut moving = vec![i];
        moving.extend((0..n).filter(|&k| carried_by(k, i, &parents)));
        let motion = find_motion(
            &scene,
            &Mover {
                child: i,
                parent: p,
                moving: &moving,
                boxes: &boxes,
            },
        );
        let kind = motion.joint.as_ref().map_or(JointKind::Fixed, |j| j.kind);
        notes.push(format!(
            "part {:?} on {:?}: {} ({})",
            parts[i].name,
            parts[p].name,
            kind_word(kind),
            motion.summary
        ));
        joints.push(motion.joint.unwrap_or_else(|| {
            fixed_joint(
                pid(p),
                pid(i),
                parts[i].mass.com,
                Provenance::provider(BUILTIN_PROVIDER, "no free motion found: fixed"),
            )
        }));
    }
    Ok((root, joints, notes))
}

/// The big parts the root is chosen among: the object stands on its root, so those standing on
/// the ground (a faucet's base, not its spout; a laptop's base, not its open screen), and any
/// that does not but whose box is `HANGING_BULK_RATIO` times every standing one's (a body its
/// open door hangs below); all of them when none stands.
fn root_pool(big: &[usize], box_volumes: &[f64], scene: &Scene) -> Vec<usize> {
    let standing = |i: usize| scene.stands_on_ground(i);
    let Some(standing_bulk) = big
        .iter()
        .filter(|&&i| standing(i))
        .map(|&i| box_volumes[i])
        .reduce(f64::max)
    else {
        return big.to_vec();
    };
    big.iter()
        .copied()
        .filter(|&i| standing(i) || box_volumes[i] >= HANGING_BULK_RATIO * standing_bulk)
        .collect()
}

/// Among root candidates, the one whose box is at least `BULKIER_RATIO` times every other's (a
/// fridge's hollow body against its door: a shell's solid volume says little), else the one with
/// the most solid volume (a laptop's base against its screen, boxes alike).
fn root_among(candidates: &[usize], box_volumes: &[f64], parts: &[PartInput<'_>]) -> usize {
    let by = |key: &dyn Fn(usize) -> f64| {
        candidates
            .iter()
            .copied()
            .max_by(|&a, &b| key(a).total_cmp(&key(b)))
    };
    let Some(bulkiest) = by(&|i| box_volumes[i]) else {
        return 0;
    };
    let clear = candidates
        .iter()
        .all(|&i| i == bulkiest || box_volumes[bulkiest] >= BULKIER_RATIO * box_volumes[i]);
    if clear {
        bulkiest
    } else {
        by(&|i| parts[i].volume_m3).unwrap_or(bulkiest)
    }
}

/// Volume of the points' box (`part_box`, on their own box axes), each side at least 1 % of the
/// object's diagonal (a flat panel still has a size); 0 without points.
fn box_volume(points: &[DVec3], part_box: &PartBox, object_diagonal_m: f64) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let floor = 0.01 * object_diagonal_m;
    (0..3).map(|k| part_box.extent(k).max(floor)).product()
}
