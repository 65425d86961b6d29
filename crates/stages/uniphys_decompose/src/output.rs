//! The stage's result: the part of every face, a per-step summary (like the reference's
//! `record.txt`) and the files written for it.
//!
//! Files ([`Decomposition::files`]): `parts/part_<i>.obj` per part, `parts.obj` with an
//! `o part_<i>` group per part (so `uniphys run parts.obj` ingests the parts), `face_parts.json`
//! (a JSON array: face index -> part index) and `decompose.json` (the summary).

use std::fmt::Write as _;

use serde::Serialize;
use uniphys_geometry::TriMesh;

use crate::{DecomposeError, DecomposeResult};

/// Loss of one candidate decomposition.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateLoss {
    /// Part count.
    pub k: usize,
    /// Multi-view Hungarian loss (lower is better).
    pub loss: f64,
}

/// Wall time of one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepTiming {
    /// Step name: "perceive", "candidates", "select", "refine", "merge", "handles",
    /// "refine_again", "small_parts", "pieces", "hidden", "layers", "tops".
    pub step: String,
    /// Seconds.
    pub secs: f64,
}

/// What each step of the stage did.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct DecomposeSummary {
    /// Faces of the merged mesh.
    pub faces: usize,
    /// Views rendered.
    pub views: usize,
    /// Side of every view, pixels.
    pub resolution_px: u32,
    /// Masks after the cross-view merge (`sam_3d_masks` of the reference).
    pub masks: usize,
    /// Part-count prior K0.
    pub k_prior: usize,
    /// Connected components holding at least 1 % of the area: the smallest K tried.
    pub k_geometric: usize,
    /// Share of the seen surface covered by masks below the whole object.
    pub mask_coverage: f64,
    /// Smallest and largest K asked of the generator.
    pub k_range: [usize; 2],
    /// Loss of every candidate.
    pub candidates: Vec<CandidateLoss>,
    /// K of the chosen candidate (`partfield_match`).
    pub matched_k: usize,
    /// Views with a mask that is not the whole object.
    pub informative_views: usize,
    /// How the candidate was chosen: "masks", or by the geometry when no view has an informative
    /// mask.
    pub selected_by: String,
    /// Parts after the first connectivity split (`refined_parts`).
    pub refined_parts: usize,
    /// Parts after the merge (`merged_parts`).
    pub merged_parts: usize,
    /// Parts the merge had joined to others that carry a handle (doors, drawer fronts), split
    /// back out with their handles.
    #[serde(default)]
    pub panels_kept_apart: usize,
    /// Parts after the second connectivity split (`refined_again_parts`).
    pub refined_again_parts: usize,
    /// Small parts merged into a neighbour.
    pub small_parts_merged: usize,
    /// Connected pieces of the mesh (vertices welded by position).
    pub pieces: usize,
    /// Pieces the steps before had cut between parts, made whole again.
    pub pieces_made_whole: usize,
    /// Small compact pieces (knobs, buttons), also those drawn into a larger piece's surface, and
    /// caps drawn onto a neck (pockets behind one crease), split off the larger part they had
    /// been merged into.
    pub controls_kept: usize,
    /// Parts made of two big pieces side by side (a laptop's screen and base) split in two.
    #[serde(default)]
    pub parts_split_in_two: usize,
    /// Parts hidden inside the object when it is closed (unreachable, so not operable), merged
    /// into the largest part.
    #[serde(default)]
    pub hidden_parts_merged: usize,
    /// Thin parts stacked flat against another (a door's skin and liner), joined to it.
    #[serde(default)]
    pub layers_joined: usize,
    /// Boards topping the object with no cavity under them (a table's top, a cooktop), joined to
    /// the largest part.
    #[serde(default)]
    pub tops_joined: usize,
    /// When the stage found a single part, why (which step joined everything, or that the mesh
    /// is one piece).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub one_part_reason: Option<String>,
    /// Final part count (`final_parts`).
    pub final_parts: usize,
    /// How the merge was done (`merge_strategy`).
    pub merge_strategy: String,
    /// Who segmented the views.
    pub segmenter: String,
    /// Who generated the candidates.
    pub generator: String,
    /// Seed used.
    pub seed: u64,
    /// Wall time per step (the only part of the summary that varies between runs).
    pub timings: Vec<StepTiming>,
}

impl DecomposeSummary {
    /// Total seconds of all steps.
    #[must_use]
    pub fn total_secs(&self) -> f64 {
        self.timings.iter().map(|t| t.secs).sum()
    }
}

/// The decomposition of a mesh into parts.
#[derive(Debug, Clone, PartialEq)]
pub struct Decomposition {
    /// Part of every face, `0..part_count`, numbered by each part's smallest face.
    pub face_part: Vec<u32>,
    /// Number of parts.
    pub part_count: usize,
    /// What each step did.
    pub summary: DecomposeSummary,
    /// Every step's face labels, when asked for ([`crate::DecomposeOptions::keep_step_labels`]).
    pub steps: Vec<StepLabels>,
}

/// The face labels after one step of the stage (not renumbered).
#[derive(Debug, Clone, PartialEq)]
pub struct StepLabels {
    /// Step name, as in [`StepTiming::step`].
    pub step: String,
    /// Label of every face.
    pub face_part: Vec<u32>,
}

impl Decomposition {
    /// Face indices of every part, ascending.
    #[must_use]
    pub fn part_faces(&self) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); self.part_count];
        for (f, &p) in self.face_part.iter().enumerate() {
            if let Some(faces) = out.get_mut(p as usize) {
                faces.push(f);
            }
        }
        out
    }

    /// The mesh of every part (a submesh of `mesh`, the mesh that was decomposed).
    #[must_use]
    pub fn part_meshes(&self, mesh: &TriMesh) -> Vec<TriMesh> {
        self.part_faces()
            .iter()
            .map(|faces| mesh.submesh(faces))
            .collect()
    }

    /// The stage's files as `(relative path, bytes)`, deterministic except for the timings in
    /// `decompose.json`. `mesh` is the mesh that was decomposed.
    pub fn files(&self, mesh: &TriMesh) -> DecomposeResult<Vec<(String, Vec<u8>)>> {
        if self.face_part.len() != mesh.triangle_count() {
            return Err(DecomposeError::InvalidInput(format!(
                "{} face labels for a mesh of {} faces",
                self.face_part.len(),
                mesh.triangle_count()
            )));
        }
        let parts = self.part_meshes(mesh);
        let mut files = Vec::with_capacity(parts.len() + 3);
        let mut combined = String::from("# UniPhys decomposition: one object per part\n");
        let mut offset = 0usize;
        for (i, part) in parts.iter().enumerate() {
            let mut single = format!("# part {i}\no part_{i}\n");
            write_obj_body(&mut single, part, 0);
            files.push((format!("parts/part_{i}.obj"), single.into_bytes()));
            let _ = writeln!(combined, "o part_{i}");
            write_obj_body(&mut combined, part, offset);
            offset += part.positions.len();
        }
        files.push(("parts.obj".to_owned(), combined.into_bytes()));
        files.push(("face_parts.json".to_owned(), to_json(&self.face_part)?));
        files.push(("decompose.json".to_owned(), to_json(&self.summary)?));
        Ok(files)
    }
}

/// `mesh` as the text of an OBJ file: `v` lines then `f` lines, nothing else.
#[must_use]
pub fn obj_text(mesh: &TriMesh) -> String {
    let mut out = String::new();
    write_obj_body(&mut out, mesh, 0);
    out
}

/// `v` lines then `f` lines (1-based, shifted by `offset` vertices written before).
fn write_obj_body(out: &mut String, mesh: &TriMesh, offset: usize) {
    for p in &mesh.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| v as usize + offset + 1);
        let _ = writeln!(out, "f {a} {b} {c}");
    }
}

/// Pretty JSON with a final newline.
fn to_json<T: Serialize + ?Sized>(value: &T) -> DecomposeResult<Vec<u8>> {
    let mut bytes =
        serde_json::to_vec_pretty(value).map_err(|e| DecomposeError::Output(e.to_string()))?;
    bytes.push(b'\n');
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::DVec3;

    use super::*;

    #[test]
    fn files_hold_every_face_once_and_the_map() {
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::splat(2.0), DVec3::splat(3.0));
        let mesh = TriMesh::merge([&a, &b]);
        let decomposition = Decomposition {
            face_part: (0..24).map(|f| u32::from(f >= 12)).collect(),
            part_count: 2,
            summary: DecomposeSummary {
                final_parts: 2,
                ..DecomposeSummary::default()
            },
            steps: Vec::new(),
        };
        let files = decomposition.files(&mesh).unwrap();
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            vec![
                "parts/part_0.obj",
                "parts/part_1.obj",
                "parts.obj",
                "face_parts.json",
                "decompose.json"
            ]
        );
        let text = |i: usize| String::from_utf8(files[i].1.clone()).unwrap();
        let combined = text(2);
        assert_eq!(combined.matches("\no part_").count(), 2);
        assert_eq!(combined.lines().filter(|l| l.starts_with("f ")).count(), 24);
        assert_eq!(combined.lines().filter(|l| l.starts_with("v ")).count(), 16);
        // The second group's faces use vertices 9..=16.
        let last = combined.lines().rfind(|l| l.starts_with("f ")).unwrap();
        assert!(
            last.split(' ')
                .skip(1)
                .all(|v| (9..=16).contains(&v.parse::<usize>().unwrap()))
        );
        let map: Vec<u32> = serde_json::from_slice(&files[3].1).unwrap();
        assert_eq!(map, decomposition.face_part);
        let summary: serde_json::Value = serde_json::from_slice(&files[4].1).unwrap();
        assert_eq!(summary["final_parts"], 2);
        assert_eq!(text(0).lines().filter(|l| l.starts_with("f ")).count(), 12);
        // Wrong mesh.
        assert!(decomposition.files(&a).is_err());
    }
}
