//! Building the articulation tree of an asset without declared joints: which part is the root
//! and which part each other part hangs from.

use uniphys_types::PartId;

use crate::roles::Role;

/// Picks parents for every part given roles and pairwise distances (metres).
///
/// - The root is the largest body part (by volume); if there is none, the largest part.
/// - Body parts join the tree one at a time, the closest to the tree first (Prim's algorithm),
///   fixed to their nearest body already in the tree.
/// - Sliding and hinged parts hang from their nearest body part.
/// - Attachments hang from their nearest non-attachment part; a body part whose nearest part is a
///   sliding or hinged one counts as an attachment of it.
///
/// Returns the root and `parent[i]` (`None` for the root). Ties go to the lower part index.
pub(crate) fn build_tree(
    roles: &[Role],
    volumes_m3: &[f64],
    distance_m: &dyn Fn(usize, usize) -> f64,
) -> (PartId, Vec<Option<usize>>) {
    let n = roles.len();
    let largest = |filter: &dyn Fn(usize) -> bool| {
        (0..n)
            .filter(|&i| filter(i))
            .fold(None, |best: Option<usize>, i| match best {
                Some(b) if volumes_m3[b] >= volumes_m3[i] => Some(b),
                _ => Some(i),
            })
    };
    let root = largest(&|i| roles[i] == Role::Body)
        .or_else(|| largest(&|_| true))
        .unwrap_or(0);
    // A body part whose nearest neighbour is a moving part is a piece of it (a screen on a lid,
    // a glass pane in a door): it moves with that part.
    let roles: Vec<Role> = (0..n)
        .map(|i| {
            let nearest = (0..n)
                .filter(|&j| j != i)
                .min_by(|&a, &b| distance_m(i, a).total_cmp(&distance_m(i, b)));
            match nearest {
                Some(j)
                    if i != root
                        && roles[i] == Role::Body
                        && matches!(roles[j], Role::Sliding | Role::Hinged) =>
                {
                    Role::Attachment
                }
                _ => roles[i],
            }
        })
        .collect();
    let roles = roles.as_slice();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    let is_body = |i: usize| roles[i] == Role::Body || i == root;

    // Body parts, Prim-style.
    let mut in_tree = vec![false; n];
    in_tree[root] = true;
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for candidate in (0..n).filter(|&i| is_body(i) && !in_tree[i]) {
            for anchor in (0..n).filter(|&j| in_tree[j] && is_body(j)) {
                let d = distance_m(candidate, anchor);
                if best.is_none_or(|(bd, ..)| d < bd) {
                    best = Some((d, candidate, anchor));
                }
            }
        }
        let Some((_, candidate, anchor)) = best else {
            break;
        };
        parent[candidate] = Some(anchor);
        in_tree[candidate] = true;
    }

    let nearest = |i: usize, filter: &dyn Fn(usize) -> bool| {
        (0..n)
            .filter(|&j| j != i && filter(j))
            .fold(None, |best: Option<(f64, usize)>, j| {
                let d = distance_m(i, j);
                match best {
                    Some((bd, _)) if bd <= d => best,
                    _ => Some((d, j)),
                }
            })
    };
    for i in 0..n {
        if i == root || is_body(i) {
            continue;
        }
        let anchor = match roles[i] {
            Role::Attachment => nearest(i, &|j| roles[j] != Role::Attachment || j == root),
            _ => nearest(i, &is_body),
        };
        parent[i] = Some(anchor.map_or(root, |(_, j)| j));
    }
    // An attachment fixed to another attachment could form a cycle only between attachments,
    // which `nearest` excludes; moving parts hang from bodies, which are all in the tree.
    (PartId(u32::try_from(root).unwrap_or(0)), parent)
}

/// Picks parents by size and contact alone, for parts whose names say nothing:
///
/// - the root is the largest part (`sizes`, any measure of bulk);
/// - every other part hangs from the bigger part it touches most (`contact(i, j)`: how much of
///   part `i` touches part `j`), or, touching none, from the nearest bigger part. A door hangs
///   from its cabinet and a handle screwed to a door from the door, even where it also grazes
///   the cabinet.
///
/// Parents are always bigger (ties broken by index), so the tree has no cycle.
pub(crate) fn build_tree_by_size(
    sizes: &[f64],
    contact: &dyn Fn(usize, usize) -> f64,
    distance_m: &dyn Fn(usize, usize) -> f64,
) -> (PartId, Vec<Option<usize>>) {
    let n = sizes.len();
    let bigger = |j: usize, i: usize| sizes[j] > sizes[i] || (sizes[j] == sizes[i] && j < i);
    let root = (0..n)
        .reduce(|a, b| if bigger(b, a) { b } else { a })
        .unwrap_or(0);
    let parent = (0..n)
        .map(|i| {
            if i == root {
                return None;
            }
            let larger = (0..n).filter(|&j| j != i && bigger(j, i));
            let touching = larger
                .clone()
                .filter(|&j| contact(i, j) > 0.0)
                .max_by(|&a, &b| contact(i, a).total_cmp(&contact(i, b)));
            touching
                .or_else(|| larger.min_by(|&a, &b| distance_m(i, a).total_cmp(&distance_m(i, b))))
        })
        .collect();
    (PartId(u32::try_from(root).unwrap_or(0)), parent)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unnamed_parts_hang_from_the_bigger_part_they_touch_most() {
        // 0 door, 1 cabinet, 2 handle (mostly on the door, grazing the cabinet), 3 loose part.
        let sizes = [0.2, 1.0, 0.01, 0.02];
        let contact = |i: usize, j: usize| match (i, j) {
            (0, 1) | (1, 0) => 50.0,
            (2, 0) => 30.0,
            (2, 1) => 2.0,
            _ => 0.0,
        };
        let gap = |i: usize, j: usize| match (i.min(j), i.max(j)) {
            (1, 3) => 0.1,
            _ => 0.3,
        };
        let (root, parent) = build_tree_by_size(&sizes, &contact, &gap);
        assert_eq!(root, PartId(1));
        assert_eq!(parent, vec![Some(1), None, Some(0), Some(1)]);
    }

    #[test]
    fn cabinet_like_layout_gets_the_expected_parents() {
        // 0 body, 1 drawer, 2 drawer handle, 3 door, 4 door handle; positions on a line.
        let roles = [
            Role::Body,
            Role::Sliding,
            Role::Attachment,
            Role::Hinged,
            Role::Attachment,
        ];
        let volumes = [1.0, 0.1, 0.001, 0.05, 0.001];
        let pos: [f64; 5] = [0.0, 0.3, 0.35, -0.3, -0.36];
        let d = |i: usize, j: usize| (pos[i] - pos[j]).abs();
        let (root, parent) = build_tree(&roles, &volumes, &d);
        assert_eq!(root, PartId(0));
        assert_eq!(parent, vec![None, Some(0), Some(1), Some(0), Some(3)]);
    }

    #[test]
    fn a_body_part_touching_only_a_lid_moves_with_the_lid() {
        // 0 base, 1 lid, 2 screen glued to the lid.
        let roles = [Role::Body, Role::Hinged, Role::Body];
        let pos: [f64; 3] = [0.0, 0.5, 0.52];
        let d = |i: usize, j: usize| (pos[i] - pos[j]).abs();
        let (_, parent) = build_tree(&roles, &[1.0, 0.5, 0.1], &d);
        assert_eq!(parent, vec![None, Some(0), Some(1)]);
    }

    #[test]
    fn without_a_body_the_largest_part_is_the_root() {
        let roles = [Role::Hinged, Role::Hinged];
        let (root, parent) = build_tree(&roles, &[0.1, 0.2], &|_, _| 0.0);
        assert_eq!(root, PartId(1));
        assert_eq!(parent, vec![Some(1), None]);
    }
}
