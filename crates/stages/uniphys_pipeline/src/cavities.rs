//! Colliders that leave room where parts move: a parent's convex hulls are carved around the
//! tight box of each sizeable part jointed to it ([`uniphys_geometry::carve_out`]), so a
//! table's hull does not fill the slot its drawer slides out of. Only the exported colliders
//! change: every carved piece lies inside a hull the verification simulated, so no contact the
//! export keeps is new.

use uniphys_geometry::{TriMesh, carve_out, sample_points};
use uniphys_types::AssetRecord;
use uniphys_verify::PartBox;

/// A child whose box diagonal is under this share of its parent's is a control (a knob, a
/// button): a gripper does not reach into its place, and carving would multiply hulls.
const CHILD_SIZE_MIN_FRACTION: f64 = 0.2;
/// The child's box is shrunk to this share of each of its extents before carving, so the walls
/// flush with it stay whole.
const CAVITY_SCALE: f64 = 0.96;
/// Carved pieces thinner than this share of the child's diagonal are dropped.
const MIN_PIECE_FRACTION: f64 = 0.005;
/// Surface samples per part for its box.
const BOX_SAMPLES: usize = 2000;

/// Carves `colliders` (by part position in `record.parts`) around the children of `record`'s
/// movable joints; returns how many parents were carved.
pub(crate) fn carve_cavities(
    record: &AssetRecord,
    meshes: &[TriMesh],
    colliders: &mut [Vec<TriMesh>],
) -> usize {
    let index = |id| record.parts.iter().position(|p| p.id == id);
    let pairs: Vec<(usize, usize)> = record
        .joints
        .iter()
        .filter(|j| j.kind.is_movable())
        .filter_map(|j| Some((index(j.child)?, index(j.parent)?)))
        .collect();
    // The boxes of the parts those joints connect, and of no other.
    let boxes: Vec<Option<PartBox>> = (0..meshes.len())
        .map(|i| {
            pairs
                .iter()
                .any(|&(c, p)| c == i || p == i)
                .then(|| sample_points(&meshes[i], BOX_SAMPLES, 0x0ca7))
                .filter(|points| points.len() >= 4)
                .map(|points| PartBox::of(&points))
        })
        .collect();
    let mut carved = 0;
    for (child, parent) in pairs {
        let (Some(child_box), Some(parent_box)) = (&boxes[child], &boxes[parent]) else {
            continue;
        };
        let size = child_box.diagonal;
        if size < CHILD_SIZE_MIN_FRACTION * parent_box.diagonal {
            continue;
        }
        let cavity = child_box.oriented().scaled(CAVITY_SCALE);
        let before = colliders[parent].clone();
        let after: Vec<TriMesh> = before
            .iter()
            .flat_map(|h| carve_out(h, &cavity, MIN_PIECE_FRACTION * size))
            .collect();
        // A parent that would lose every hull keeps its own (it collides, if too much).
        if !after.is_empty() && after != before {
            colliders[parent] = after;
            carved += 1;
        }
    }
    carved
}
