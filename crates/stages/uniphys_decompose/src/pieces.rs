//! The mesh's own pieces as evidence: a connected piece (vertices welded by position) was modelled
//! as one thing, so a decomposition should not cut it, and a small compact piece sitting on a
//! much larger part (a knob, a button, a dial) is a part of its own.
//!
//! Why: real meshes are assembled from pieces. A panel, a knob or a handle is one piece; a rigid
//! body is several. Clustering by views and creases cuts a body's panels apart along their
//! creases and lets small controls vanish into the panel they sit on; one welded piece is almost
//! never two parts (measured on the shared PartNet-Mobility objects: `decompose-bench --partnet`).
//! Welded seams between a door and its frame are the exception; they stay with whichever side
//! holds more of the piece, except a round part carved out of the piece whose rest is not
//! round about the same line (a wheel or a switch welded to its mount), which can spin.
//!
//! Two big pieces (each at least a quarter of its part) in one part, neither inside the other's
//! box, are two parts: a laptop's screen and base, each one piece, merged by the views.
//!
//! Controls are small pieces, and inside pieces too large to be one, finer pieces split where
//! three or more faces share an edge: a button modelled onto its panel shares the panel's
//! vertices, but its walls stand on the panel along edges the panel's own faces continue
//! across (on the shared objects this finds the welded buttons of a dishwasher and a camera).
//! A control drawn as a bump of the panel's own surface shares even its edges with the panel:
//! it is a pocket of the surface behind one crease ([`crate::pockets`]; an oven's knobs, a
//! camera's buttons). A control is solid (not a flat patch of a surface cut out by such edges)
//! and meets the rest along a seam in one plane (it stands on a face; a block filling the
//! corner of a frame meets several). Pieces repeated many times over (the keys of a keyboard,
//! the holes of a grille, screws), or dozens on one part, are surface detail, not controls: an
//! appliance has a handful of controls.

use uniphys_geometry::{DVec3, TriMesh, principal_axes, projection_range};

use crate::candidates::adjacency::WeldedEdges;
use crate::candidates::{UnionFind, relabel_by_first_face, welded_vertex_ids};
use crate::pockets::crease_pockets;
use crate::round::{round_about, round_axis};

/// Tuning of [`respect_pieces`]. Areas are shares of the total surface area.
#[derive(Debug, Clone, PartialEq)]
pub struct PieceOptions {
    /// Make every cut piece whole. Default true; the stage turns it off for learned candidates
    /// ([`crate::CandidateGenerator::learned`]).
    pub make_whole: bool,
    /// A piece below this share of the area is small enough to be a control. Default 0.005.
    pub control_area_fraction_max: f64,
    /// ... and above this share it is not dust. Default 1e-5.
    pub control_area_fraction_min: f64,
    /// ... compact: its second principal extent is at least this share of its first (a bar
    /// handle is not a control). Default 0.5.
    pub control_compactness_min: f64,
    /// ... and the part it was merged into holds at least this many times its area. Default 2.
    pub control_host_ratio: f64,
    /// ... solid: its third principal extent is at least this share of its first (a flat patch
    /// of a surface is not a control). Default 0.1.
    pub control_thickness_min: f64,
    /// ... unless more than this many pieces of the same shape are candidates (a keyboard's keys,
    /// a grille). Default 16.
    pub control_copies_max: usize,
    /// ... or more than this many candidates sit on the same part (studs, rivets, keys of many
    /// shapes: surface detail). Default 32.
    pub control_per_host_max: usize,
    /// Faces meeting at more than this angle meet at a crease, radians: a control drawn as a
    /// bump of its panel's surface is a pocket behind one ([`crate::pockets`]). Default 30
    /// degrees (an oven's knobs stand on their panel at 35).
    pub control_crease_rad: f64,
    /// A pocket may hold up to this share of the area (a cap drawn onto its bottle's neck is a
    /// part of its own, though too large to be a control). Default 0.3.
    pub pocket_area_fraction_max: f64,
}

/// A part with at least this share of its area inside one piece was carved out of it.
const WELDED_INSIDE_SHARE: f64 = 0.95;

impl Default for PieceOptions {
    fn default() -> Self {
        Self {
            make_whole: true,
            control_area_fraction_max: 0.005,
            control_area_fraction_min: 1e-5,
            control_compactness_min: 0.5,
            control_host_ratio: 2.0,
            control_thickness_min: 0.1,
            control_copies_max: 16,
            control_per_host_max: 32,
            control_crease_rad: 30f64.to_radians(),
            pocket_area_fraction_max: 0.3,
        }
    }
}

/// What [`respect_pieces`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PieceReport {
    /// Connected pieces of the mesh.
    pub pieces: usize,
    /// Pieces that were cut between parts and made whole again.
    pub pieces_made_whole: usize,
    /// Small compact pieces, and pockets of a larger piece's surface behind one crease, split
    /// off the part they had been merged into.
    pub controls_kept: usize,
    /// Parts of two big pieces side by side split in two (a laptop's screen and base).
    pub parts_split_in_two: usize,
}

/// Connected pieces of `mesh`: the piece of every face (numbered by smallest face) and the count.
#[must_use]
pub fn mesh_pieces(mesh: &TriMesh) -> (Vec<u32>, usize) {
    pieces_of(mesh, &welded_vertex_ids(mesh))
}

/// [`mesh_pieces`] with the welded vertex ids given.
fn pieces_of(mesh: &TriMesh, welded: &[u32]) -> (Vec<u32>, usize) {
    let mut uf = UnionFind::new(mesh.positions.len());
    for triangle in &mesh.triangles {
        let [a, b, c] = triangle.map(|v| welded[v as usize]);
        uf.union(a, b);
        uf.union(a, c);
    }
    let roots: Vec<u32> = mesh
        .triangles
        .iter()
        .map(|t| uf.find(welded[t[0] as usize]))
        .collect();
    relabel_by_first_face(&roots)
}

/// Pieces of `mesh` joined only across manifold edges: two faces are in one piece when a chain
/// of edges each shared by exactly two faces links them (faces over the same three welded
/// vertices, the two sides of a double-sided surface, count once). Where one surface meets
/// another along a line the other's faces also use (a button's wall standing on a panel, a door
/// welded to its frame along a seam the frame's faces continue across), the edge is shared by
/// three or more faces and the two are separate pieces.
#[must_use]
pub fn manifold_pieces(mesh: &TriMesh) -> (Vec<u32>, usize) {
    manifold_pieces_of(mesh, &WeldedEdges::new(mesh, &welded_vertex_ids(mesh)))
}

/// [`manifold_pieces`] with the mesh's welded edges given.
fn manifold_pieces_of(mesh: &TriMesh, edges: &WeldedEdges) -> (Vec<u32>, usize) {
    let faces = mesh.triangle_count();
    let mut uf = UnionFind::new(faces);
    for (f, &to) in edges.stands_for.iter().enumerate() {
        uf.union(u32::try_from(f).unwrap_or(u32::MAX), to);
    }
    for run in edges.runs() {
        if let [(_, _, f), (_, _, g)] = run {
            uf.union(*f, *g);
        }
    }
    let roots: Vec<u32> = (0..u32::try_from(faces).unwrap_or(u32::MAX))
        .map(|f| uf.find(f))
        .collect();
    relabel_by_first_face(&roots)
}

/// Makes every connected piece whole (it joins the part holding most of its area) and splits
/// small compact pieces off the larger parts they were merged into. Returns the new labels
/// (numbered by smallest face), their count and what was done.
#[must_use]
pub fn respect_pieces(
    mesh: &TriMesh,
    face_part: &[u32],
    options: &PieceOptions,
) -> (Vec<u32>, usize, PieceReport) {
    let welded = welded_vertex_ids(mesh);
    let (piece, pieces) = pieces_of(mesh, &welded);
    let parts = face_part.iter().max().map_or(0, |&m| m as usize + 1);
    let face_area_m2: Vec<f64> = (0..mesh.triangle_count())
        .map(|f| mesh.face_area(f))
        .collect();
    let total_m2: f64 = face_area_m2.iter().sum();
    let mut faces_of: Vec<Vec<usize>> = vec![Vec::new(); pieces];
    for (f, &p) in piece.iter().enumerate() {
        faces_of[p as usize].push(f);
    }
    let mut report = PieceReport {
        pieces,
        ..PieceReport::default()
    };
    let mut labels = face_part.to_vec();
    let mut part_total_m2 = vec![0.0f64; parts];
    for (f, &p) in face_part.iter().enumerate() {
        part_total_m2[p as usize] += face_area_m2[f];
    }
    let mut share = vec![0.0f64; parts];
    for faces in &faces_of {
        share.iter_mut().for_each(|s| *s = 0.0);
        for &f in faces {
            share[face_part[f] as usize] += face_area_m2[f];
        }
        let owner = majority(&share);
        if !options.make_whole || faces.iter().all(|&f| face_part[f] == owner) {
            continue;
        }
        // A round part carved whole out of the piece (a wheel or a knob welded to its mount)
        // can spin against the rest of it: it stays, unless the rest is round about the same
        // line (a band of a bucket's or a bottle's wall).
        let kept: Vec<u32> = (0..parts)
            .filter(|&p| {
                p != owner as usize
                    && share[p] >= WELDED_INSIDE_SHARE * part_total_m2[p]
                    && share[p] >= options.control_area_fraction_min * total_m2
                    && {
                        let (own, rest): (Vec<usize>, Vec<usize>) =
                            faces.iter().partition(|&&f| face_part[f] as usize == p);
                        round_axis(mesh, &own).is_some_and(|(c, a)| !round_about(mesh, &rest, c, a))
                    }
            })
            .map(|p| u32::try_from(p).unwrap_or(u32::MAX))
            .collect();
        report.pieces_made_whole += 1;
        for &f in faces {
            if !kept.contains(&face_part[f]) {
                labels[f] = owner;
            }
        }
    }
    let (parts, split) =
        split_two_big_pieces(mesh, &mut labels, parts, &piece, &faces_of, &face_area_m2);
    report.parts_split_in_two = split;
    let mut part_area_m2 = vec![0.0f64; parts];
    for (f, &p) in labels.iter().enumerate() {
        part_area_m2[p as usize] += face_area_m2[f];
    }
    // Candidates: small compact solid pieces inside a much larger part, with their shape. A
    // welded piece too large to be a control is looked into: split at edges three or more faces
    // share, a button modelled onto its panel is a piece of its own.
    let welded_edges = WeldedEdges::new(mesh, &welded);
    let (control_piece, control_pieces) = manifold_pieces_of(mesh, &welded_edges);
    let mut sub_pieces: Vec<Vec<usize>> = vec![Vec::new(); control_pieces];
    for (f, &p) in control_piece.iter().enumerate() {
        sub_pieces[p as usize].push(f);
    }
    let piece_area_m2: Vec<f64> = faces_of
        .iter()
        .map(|faces| faces.iter().map(|&f| face_area_m2[f]).sum())
        .collect();
    let too_large = |q: usize| piece_area_m2[q] >= options.control_area_fraction_max * total_m2;
    let whole_sets = (0..pieces)
        .filter(|&q| !too_large(q))
        .map(|q| (faces_of[q].as_slice(), Source::Piece));
    let welded_sets = sub_pieces
        .iter()
        .filter(|faces| too_large(piece[faces[0]] as usize))
        .map(|faces| (faces.as_slice(), Source::FinerPiece));
    // A control drawn as a bump of its panel's own surface, or a cap drawn onto its bottle's
    // neck: a pocket behind one crease.
    let pockets: Vec<Vec<usize>> = crease_pockets(
        mesh,
        &welded_edges,
        &face_area_m2,
        options.control_crease_rad,
        (
            options.control_area_fraction_min * total_m2,
            options.pocket_area_fraction_max * total_m2,
        ),
        options.control_host_ratio,
    )
    .into_iter()
    .filter(|faces| too_large(piece[faces[0]] as usize))
    .collect();
    let pocket_sets = pockets
        .iter()
        .map(|faces| (faces.as_slice(), Source::Pocket));
    let sets: Vec<(&[usize], Source)> = whole_sets.chain(welded_sets).chain(pocket_sets).collect();
    let seams = Seams::of(mesh, &welded, &control_piece);
    let mut candidates: Vec<(usize, usize, Shape)> = Vec::new();
    // A face goes to the first candidate holding it (a pocket that is also a finer piece once).
    let mut claimed = vec![false; mesh.triangle_count()];
    for (i, &(faces, source)) in sets.iter().enumerate() {
        if faces.iter().any(|&f| claimed[f]) {
            continue;
        }
        let area_m2: f64 = faces.iter().map(|&f| face_area_m2[f]).sum();
        let host = labels[faces[0]] as usize;
        let area_max = match source {
            Source::Pocket => options.pocket_area_fraction_max,
            Source::Piece | Source::FinerPiece => options.control_area_fraction_max,
        };
        let small =
            area_m2 < area_max * total_m2 && area_m2 > options.control_area_fraction_min * total_m2;
        if !small || part_area_m2[host] < options.control_host_ratio * area_m2 {
            continue;
        }
        let shape = Shape::of(mesh, faces);
        if shape.compactness() >= options.control_compactness_min
            && shape.thickness() >= options.control_thickness_min
            && (source != Source::FinerPiece || seams.stands_on_one_face(mesh, faces))
        {
            for &f in faces {
                claimed[f] = true;
            }
            candidates.push((i, host, shape));
        }
    }
    let mut per_host = vec![0usize; parts];
    for &(_, host, _) in &candidates {
        per_host[host] += 1;
    }
    let mut next = u32::try_from(parts).unwrap_or(u32::MAX);
    for (i, host, shape) in &candidates {
        let copies = candidates
            .iter()
            .filter(|(_, _, other)| other.same_as(shape))
            .count();
        if copies > options.control_copies_max || per_host[*host] > options.control_per_host_max {
            continue;
        }
        for &f in sets[*i].0 {
            labels[f] = next;
        }
        next += 1;
        report.controls_kept += 1;
    }
    let (labels, count) = relabel_by_first_face(&labels);
    (labels, count, report)
}

/// Where a control candidate comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// A whole connected piece.
    Piece,
    /// A piece split where three or more faces share an edge, inside a larger piece.
    FinerPiece,
    /// A pocket of a larger piece's surface behind one crease.
    Pocket,
}

/// Where pieces split at shared edges still share vertices with other pieces.
struct Seams<'a> {
    welded: &'a [u32],
    shared: Vec<bool>,
}

impl<'a> Seams<'a> {
    fn of(mesh: &TriMesh, welded: &'a [u32], piece: &[u32]) -> Self {
        let mut owner = vec![u32::MAX; mesh.positions.len()];
        let mut shared = vec![false; mesh.positions.len()];
        for (triangle, &p) in mesh.triangles.iter().zip(piece) {
            for v in triangle.map(|v| welded[v as usize] as usize) {
                if owner[v] == u32::MAX {
                    owner[v] = p;
                } else if owner[v] != p {
                    shared[v] = true;
                }
            }
        }
        Self { welded, shared }
    }

    /// Whether the piece made of `faces` meets the rest of its welded piece, if at all, along a
    /// seam in one plane (a button standing on its panel) rather than across several faces (a
    /// block filling the corner of a frame).
    fn stands_on_one_face(&self, mesh: &TriMesh, faces: &[usize]) -> bool {
        let mut seam: Vec<u32> = faces
            .iter()
            .flat_map(|&f| mesh.triangles[f])
            .map(|v| self.welded[v as usize])
            .filter(|&w| self.shared[w as usize])
            .collect();
        seam.sort_unstable();
        seam.dedup();
        let points: Vec<DVec3> = seam.iter().map(|&w| mesh.positions[w as usize]).collect();
        if points.len() < 3 {
            return true;
        }
        let extents = principal_axes(&points).map(|d| {
            let (lo, hi) = projection_range(&points, d);
            hi - lo
        });
        extents[2] <= SEAM_FLATNESS_MAX * extents[0]
    }
}

/// A seam is in one plane when its thickness is at most this share of its length.
const SEAM_FLATNESS_MAX: f64 = 0.1;

/// Index of the largest value (the first on ties).
fn majority(values: &[f64]) -> u32 {
    let mut best = 0;
    for (i, &v) in values.iter().enumerate() {
        if v > values[best] {
            best = i;
        }
    }
    u32::try_from(best).unwrap_or(u32::MAX)
}

/// A piece's shape for telling copies apart: its face count and principal extents.
struct Shape {
    faces: usize,
    extents_m: [f64; 3],
}

impl Shape {
    fn of(mesh: &TriMesh, faces: &[usize]) -> Self {
        let points = face_vertices(mesh, faces);
        let extents_m = principal_axes(&points).map(|d| {
            let (lo, hi) = projection_range(&points, d);
            hi - lo
        });
        Self {
            faces: faces.len(),
            extents_m,
        }
    }

    /// The second principal extent over the first (1 for a disc or a ball, near 0 for a bar).
    fn compactness(&self) -> f64 {
        if self.extents_m[0] > 0.0 {
            self.extents_m[1] / self.extents_m[0]
        } else {
            0.0
        }
    }

    /// The third principal extent over the first (0 for a flat patch of a surface).
    fn thickness(&self) -> f64 {
        if self.extents_m[0] > 0.0 {
            self.extents_m[2] / self.extents_m[0]
        } else {
            0.0
        }
    }

    /// The same face count and extents within 2 % of the largest.
    fn same_as(&self, other: &Self) -> bool {
        let tolerance_m = 0.02 * self.extents_m[0].max(other.extents_m[0]);
        self.faces == other.faces
            && self
                .extents_m
                .iter()
                .zip(&other.extents_m)
                .all(|(a, b)| (a - b).abs() <= tolerance_m)
    }
}

/// A piece holding at least this share of its part's area is big ...
const BIG_PIECE_SHARE: f64 = 0.25;

/// Splits a part holding exactly two big pieces (each [`BIG_PIECE_SHARE`] of its area or more),
/// neither inside the other's box, in two: the smaller big piece becomes a part of its own, the
/// rest stays (a laptop's screen and base, each modelled as one piece and merged by the views:
/// one piece is one thing, two big ones side by side likely two). Only the faces of the piece
/// in that part move. Returns the new part count and how many parts were split.
fn split_two_big_pieces(
    mesh: &TriMesh,
    labels: &mut [u32],
    parts: usize,
    piece: &[u32],
    faces_of: &[Vec<usize>],
    face_area_m2: &[f64],
) -> (usize, usize) {
    let mut area = vec![std::collections::BTreeMap::<u32, f64>::new(); parts];
    let mut part_m2 = vec![0.0f64; parts];
    for (f, (&l, &q)) in labels.iter().zip(piece).enumerate() {
        *area[l as usize].entry(q).or_default() += face_area_m2[f];
        part_m2[l as usize] += face_area_m2[f];
    }
    let mut next = u32::try_from(parts).unwrap_or(u32::MAX);
    // (part, piece, new part)
    let mut moved: Vec<(u32, u32, u32)> = Vec::new();
    for (p, by_piece) in area.iter().enumerate() {
        let mut big: Vec<(u32, f64)> = by_piece
            .iter()
            .filter(|&(_, &a)| a >= BIG_PIECE_SHARE * part_m2[p])
            .map(|(&q, &a)| (q, a))
            .collect();
        // Smaller first; of two equal pieces (a pair of mirror-image doors) the one numbered
        // first (a hash map's order made the choice differ run to run).
        big.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        if let [(smaller, _), (larger, _)] = big[..]
            && !nested(
                mesh,
                &faces_of[smaller as usize],
                &faces_of[larger as usize],
            )
        {
            moved.push((u32::try_from(p).unwrap_or(u32::MAX), smaller, next));
            next += 1;
        }
    }
    for (l, &q) in labels.iter_mut().zip(piece) {
        if let Some(&(_, _, to)) = moved
            .iter()
            .find(|(part, from, _)| *part == *l && *from == q)
        {
            *l = to;
        }
    }
    (next as usize, moved.len())
}

/// A piece is nested in another when at least this share of its area lies inside the other's
/// box (its principal axes): a liner inside a shell, a shelf inside a carcass.
const NESTED_SHARE: f64 = 0.5;

/// Whether the piece of faces `inner` lies inside the box of the piece of faces `outer` (see
/// [`NESTED_SHARE`]), judged by its faces' centres weighted by their areas.
fn nested(mesh: &TriMesh, inner: &[usize], outer: &[usize]) -> bool {
    let outside = face_vertices(mesh, outer);
    if outside.is_empty() {
        return false;
    }
    let axes = principal_axes(&outside);
    let ranges: Vec<(f64, f64)> = axes
        .iter()
        .map(|&a| projection_range(&outside, a))
        .collect();
    let (mut within_m2, mut total_m2) = (0.0, 0.0);
    for &f in inner {
        let centre = mesh.corners(f).iter().sum::<DVec3>() / 3.0;
        let area = mesh.face_area(f);
        total_m2 += area;
        if axes
            .iter()
            .zip(&ranges)
            .all(|(&a, &(lo, hi))| (lo..=hi).contains(&centre.dot(a)))
        {
            within_m2 += area;
        }
    }
    total_m2 > 0.0 && within_m2 >= NESTED_SHARE * total_m2
}

/// The corners of `faces`, one per face corner (shared vertices repeated).
fn face_vertices(mesh: &TriMesh, faces: &[usize]) -> Vec<DVec3> {
    faces
        .iter()
        .flat_map(|&f| mesh.triangles[f])
        .map(|v| mesh.positions[v as usize])
        .collect()
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::TriMesh;

    use super::*;
    use crate::segment::test_meshes::boxes;

    #[test]
    fn a_cut_piece_is_made_whole_and_a_knob_on_a_panel_is_kept() {
        // A panel (one piece, 12 faces) and a knob on it (one piece).
        let mesh = boxes(&[
            (DVec3::ZERO, DVec3::new(1.0, 1.0, 0.05)),
            (DVec3::new(0.46, 0.46, 0.05), DVec3::new(0.5, 0.5, 0.08)),
        ]);
        // The clustering cut a thin edge face off the panel (part 0) and merged the knob into
        // the rest (part 1).
        let edge = (0..12)
            .min_by(|&a, &b| mesh.face_area(a).total_cmp(&mesh.face_area(b)))
            .unwrap();
        let mut face_part = vec![1u32; 24];
        face_part[edge] = 0;
        let (labels, count, report) = respect_pieces(&mesh, &face_part, &PieceOptions::default());
        assert_eq!(count, 2, "{labels:?}");
        assert_eq!(report.pieces, 2);
        assert_eq!(report.pieces_made_whole, 1);
        assert_eq!(report.controls_kept, 1);
        assert!(labels[..12].iter().all(|&l| l == labels[0]));
        assert!(labels[12..].iter().all(|&l| l != labels[0]));
    }

    #[test]
    fn two_big_pieces_merged_into_one_part_are_two_parts_unless_one_is_inside_the_other() {
        // A laptop: a base slab and a screen slab standing on its back edge, two pieces that
        // the views merged into one part.
        let laptop = boxes(&[
            (DVec3::ZERO, DVec3::new(1.0, 0.7, 0.04)),
            (DVec3::new(0.02, 0.66, 0.04), DVec3::new(0.98, 0.7, 0.7)),
        ]);
        let (labels, count, report) = respect_pieces(&laptop, &[0; 24], &PieceOptions::default());
        assert_eq!(count, 2, "{labels:?}");
        assert_eq!(report.parts_split_in_two, 1);
        assert!(labels[..12].iter().all(|&l| l == labels[0]));
        assert!(labels[12..].iter().all(|&l| l != labels[0]));
        // A shell with a liner inside it: one rigid body of two pieces.
        let shell = boxes(&[
            (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.2)),
            (DVec3::splat(0.05), DVec3::new(0.95, 0.75, 1.15)),
        ]);
        let (labels, count, _) = respect_pieces(&shell, &[0; 24], &PieceOptions::default());
        assert_eq!(count, 1, "{labels:?}");
    }

    #[test]
    fn a_bar_handle_stays_with_its_door() {
        let mesh = boxes(&[
            (DVec3::ZERO, DVec3::new(1.0, 1.0, 0.05)),
            (DVec3::new(0.1, 0.45, 0.05), DVec3::new(0.3, 0.46, 0.06)),
        ]);
        let (_, count, report) = respect_pieces(&mesh, &[0u32; 24], &PieceOptions::default());
        assert_eq!((count, report.controls_kept), (1, 0));
    }

    /// A double-sided flat panel (a 24 x 24 grid of vertices 1 apart in z = 0, every triangle
    /// also given reversed) with a button (four walls 0.3 high and a top) standing on one cell:
    /// the walls' foot vertices are the panel's own, so the two are one welded piece. Returns
    /// the mesh and the panel's face count (the button's faces come after).
    fn panel_with_welded_button() -> (TriMesh, usize) {
        const N: u32 = 24;
        let mut positions: Vec<DVec3> = (0..N * N)
            .map(|i| DVec3::new(f64::from(i % N), f64::from(i / N), 0.0))
            .collect();
        let mut triangles = Vec::new();
        for y in 0..N - 1 {
            for x in 0..N - 1 {
                let (a, b) = (y * N + x, y * N + x + 1);
                let (c, d) = (b + N, a + N);
                for t in [[a, b, c], [a, c, d]] {
                    triangles.push(t);
                    triangles.push([t[0], t[2], t[1]]);
                }
            }
        }
        let panel_faces = triangles.len();
        let corner = 11 * N + 11;
        let foot = [corner, corner + 1, corner + N + 1, corner + N];
        let first_top = u32::try_from(positions.len()).unwrap();
        for &v in &foot {
            let p = positions[v as usize];
            positions.push(p + DVec3::Z * 0.3);
        }
        let top = [first_top, first_top + 1, first_top + 2, first_top + 3];
        for k in 0..4 {
            let (a, b) = (foot[k], foot[(k + 1) % 4]);
            triangles.push([a, b, top[(k + 1) % 4]]);
            triangles.push([a, top[(k + 1) % 4], top[k]]);
        }
        triangles.push([top[0], top[1], top[2]]);
        triangles.push([top[0], top[2], top[3]]);
        (TriMesh::new(positions, triangles).unwrap(), panel_faces)
    }

    #[test]
    fn a_button_welded_onto_a_panel_is_a_manifold_piece_of_its_own() {
        let (mesh, panel_faces) = panel_with_welded_button();
        assert_eq!(mesh_pieces(&mesh).1, 1);
        let (piece, count) = manifold_pieces(&mesh);
        // The panel, the patch under the button (its edges are shared with the walls too), the
        // button; both sides of the double-sided panel are one piece.
        assert_eq!(count, 3, "{piece:?}");
        let button = piece[panel_faces];
        assert!(piece[panel_faces..].iter().all(|&p| p == button));
        let under = piece[..panel_faces].iter().filter(|&&p| p != piece[0]);
        assert!(under.clone().all(|&p| p != button));
        assert_eq!(under.count(), 4);
    }

    #[test]
    fn a_welded_button_is_kept_as_a_control() {
        let (mesh, panel_faces) = panel_with_welded_button();
        let (labels, count, report) = respect_pieces(
            &mesh,
            &vec![0u32; mesh.triangle_count()],
            &PieceOptions::default(),
        );
        assert_eq!((count, report.controls_kept), (2, 1), "{labels:?}");
        assert!(labels[panel_faces..].iter().all(|&l| l != labels[0]));
    }
}
