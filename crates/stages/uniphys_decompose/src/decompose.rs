//! The whole stage: perceive (views, segmentation, lifting, consensus, prior), candidate
//! decompositions for K around the prior, Hungarian selection, connectivity split, Apriori merge,
//! panels carrying a handle split back out of it, second split, small-part merge, the mesh's
//! pieces made whole and small controls kept, hidden parts merged into the largest, thin sheets
//! stacked flat against each other joined, boards topping the object joined to the largest part.

use std::time::Instant;

use uniphys_geometry::{MeshAsset, MeshPart, TriMesh};

use crate::apriori::{AprioriOptions, merge_parts};
use crate::candidates::{CandidateGenerator, CandidateRequest};
use crate::handles::{HandleOptions, keep_handled_panels};
use crate::hidden::{HiddenOptions, merge_hidden_parts};
use crate::layers::{LayerOptions, merge_layers};
use crate::output::{CandidateLoss, DecomposeSummary, Decomposition, StepLabels, StepTiming};
use crate::perception::{PerceptionOptions, perceive};
use crate::pieces::{PieceOptions, respect_pieces};
use crate::prior::k_range;
use crate::refine::split_disconnected;
use crate::segment::Segmenter;
use crate::select::{
    closest_k, select_candidate, substantial_components, visible_area_m2,
    without_whole_object_masks,
};
use crate::small_parts::{SmallPartOptions, merge_small_parts};
use crate::tops::{TopOptions, merge_tops};
use crate::views::{face_colours, face_material_ids};
use crate::{DecomposeError, DecomposeResult};

/// Options of [`decompose`]. Lengths are fractions of the bounds diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct DecomposeOptions {
    /// Views, lifting, consensus and prior (default: 8 views at 512 px).
    pub perception: PerceptionOptions,
    /// Candidates start this far below the prior K0 (default 3).
    pub k_below: usize,
    /// ... and end this far above it (default 14).
    pub k_above: usize,
    /// Vertices closer than this are connected in the first split (default 5e-3).
    pub refine_eps_rel: f64,
    /// ... and in the split after the merge (default 1e-2).
    pub refine_again_eps_rel: f64,
    /// In the split after the merge, a part that falls into more pieces than this stays whole
    /// (default 5).
    pub refine_again_keep_whole_above: usize,
    /// A mask holding at least this share of the area a view's masks cover is the whole object
    /// and is ignored (default 0.85).
    pub whole_object_fraction: f64,
    /// Connected components holding at least this share of the area are counted as parts: K
    /// starts at their count, and without any informative mask it is their count (default 0.01).
    pub component_area_fraction: f64,
    /// The merge of parts the views show together.
    pub apriori: AprioriOptions,
    /// Panels carrying a handle (doors, drawer fronts) kept out of the merge.
    pub handles: HandleOptions,
    /// The merge of small fragments.
    pub small_parts: SmallPartOptions,
    /// Connected pieces made whole, small compact pieces kept as parts.
    pub pieces: PieceOptions,
    /// Parts hidden inside the closed object merged into the largest part.
    pub hidden: HiddenOptions,
    /// Thin sheets stacked flat against each other joined into one panel.
    pub layers: LayerOptions,
    /// Boards topping the object with no cavity under them joined to the largest part.
    pub tops: TopOptions,
    /// Seed for anything random (default 0).
    pub seed: u64,
    /// Keep every step's face labels in [`Decomposition::steps`] (benchmarks; default false).
    pub keep_step_labels: bool,
}

impl Default for DecomposeOptions {
    fn default() -> Self {
        Self {
            perception: PerceptionOptions::default(),
            k_below: 3,
            k_above: 14,
            refine_eps_rel: 5e-3,
            refine_again_eps_rel: 1e-2,
            refine_again_keep_whole_above: 5,
            whole_object_fraction: 0.85,
            component_area_fraction: 0.01,
            apriori: AprioriOptions::default(),
            handles: HandleOptions::default(),
            small_parts: SmallPartOptions::default(),
            pieces: PieceOptions::default(),
            hidden: HiddenOptions::default(),
            layers: LayerOptions::default(),
            tops: TopOptions::default(),
            seed: 0,
            keep_step_labels: false,
        }
    }
}

impl DecomposeOptions {
    /// Checks that every fraction is in its domain.
    pub fn validate(&self) -> DecomposeResult<()> {
        let fractions = [
            ("refine_eps_rel", self.refine_eps_rel, 0.0, 1.0),
            ("refine_again_eps_rel", self.refine_again_eps_rel, 0.0, 1.0),
            (
                "whole_object_fraction",
                self.whole_object_fraction,
                0.0,
                1.0,
            ),
            (
                "component_area_fraction",
                self.component_area_fraction,
                0.0,
                1.0,
            ),
            ("apriori.coverage_min", self.apriori.coverage_min, 0.0, 1.0),
            (
                "pieces.control_area_fraction_max",
                self.pieces.control_area_fraction_max,
                0.0,
                1.0,
            ),
            (
                "pieces.control_area_fraction_min",
                self.pieces.control_area_fraction_min,
                0.0,
                1.0,
            ),
            (
                "pieces.control_compactness_min",
                self.pieces.control_compactness_min,
                0.0,
                1.0,
            ),
            (
                "pieces.control_thickness_min",
                self.pieces.control_thickness_min,
                0.0,
                1.0,
            ),
            ("hidden.skip_rel", self.hidden.skip_rel, 0.0, 1.0),
            (
                "handles.handle_area_fraction_max",
                self.handles.handle_area_fraction_max,
                0.0,
                1.0,
            ),
            ("handles.touch_rel", self.handles.touch_rel, 0.0, 1.0),
            ("handles.standoff_rel", self.handles.standoff_rel, 0.0, 1.0),
            (
                "hidden.exposed_share_max",
                self.hidden.exposed_share_max,
                0.0,
                1.0,
            ),
            (
                "hidden.area_fraction_min",
                self.hidden.area_fraction_min,
                0.0,
                1.0,
            ),
            (
                "layers.thin_ratio_max",
                self.layers.thin_ratio_max,
                0.0,
                1.0,
            ),
            (
                "layers.broad_ratio_min",
                self.layers.broad_ratio_min,
                0.0,
                1.0,
            ),
            (
                "layers.parallel_cos_min",
                self.layers.parallel_cos_min,
                0.0,
                1.0,
            ),
            ("layers.gap_rel_max", self.layers.gap_rel_max, 0.0, 1.0),
            (
                "layers.stack_ratio_max",
                self.layers.stack_ratio_max,
                0.0,
                1.0,
            ),
            ("layers.cover_min", self.layers.cover_min, 0.0, 1.0),
            (
                "layers.area_fraction_min",
                self.layers.area_fraction_min,
                0.0,
                1.0,
            ),
            (
                "layers.whole_fraction_max",
                self.layers.whole_fraction_max,
                0.0,
                1.0,
            ),
            ("tops.thin_ratio_max", self.tops.thin_ratio_max, 0.0, 1.0),
            ("tops.level_cos_min", self.tops.level_cos_min, 0.0, 1.0),
            ("tops.broad_ratio_min", self.tops.broad_ratio_min, 0.0, 1.0),
            ("tops.fill_min", self.tops.fill_min, 0.0, f64::MAX),
            ("tops.plan_cover_min", self.tops.plan_cover_min, 0.0, 1.0),
            ("tops.raised_min", self.tops.raised_min, 0.0, 1.0),
            ("tops.sky_share_min", self.tops.sky_share_min, 0.0, 1.0),
            (
                "tops.cavity_depth_min",
                self.tops.cavity_depth_min,
                0.0,
                1.0,
            ),
            (
                "tops.cavity_share_max",
                self.tops.cavity_share_max,
                0.0,
                1.0,
            ),
            (
                "tops.area_fraction_min",
                self.tops.area_fraction_min,
                0.0,
                1.0,
            ),
        ];
        for (name, value, low, high) in fractions {
            if !(value.is_finite() && value >= low && value <= high) {
                return Err(DecomposeError::InvalidOption(format!(
                    "{name} = {value} is outside [{low}, {high}]"
                )));
            }
        }
        if self.layers.grid_cells == 0 {
            return Err(DecomposeError::InvalidOption(
                "layers.grid_cells must be at least 1".into(),
            ));
        }
        if self.whole_object_fraction <= 0.0 {
            return Err(DecomposeError::InvalidOption(
                "whole_object_fraction must be positive".into(),
            ));
        }
        Ok(())
    }
}

/// Decomposes `mesh` into parts. `face_rgba` has one colour per face, `face_material` one
/// material per face or is empty. Deterministic for deterministic providers and the same seed
/// (only the timings of the summary vary).
pub fn decompose(
    mesh: &TriMesh,
    face_rgba: &[[u8; 4]],
    face_material: &[u32],
    segmenter: &dyn Segmenter,
    generator: &dyn CandidateGenerator,
    options: &DecomposeOptions,
) -> DecomposeResult<Decomposition> {
    options.validate()?;
    let faces = mesh.triangle_count();
    if faces == 0 {
        return Err(DecomposeError::InvalidInput("the mesh has no faces".into()));
    }
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |step: &str, timings: &mut Vec<StepTiming>| {
        timings.push(StepTiming {
            step: step.to_owned(),
            secs: clock.elapsed().as_secs_f64(),
        });
        clock = Instant::now();
    };

    let perception = perceive(
        mesh,
        face_rgba,
        face_material,
        segmenter,
        &options.perception,
    )?;
    lap("perceive", &mut timings);

    let materials: Vec<u32> = if face_material.len() == faces {
        face_material.to_vec()
    } else {
        vec![0; faces]
    };
    let face_area_m2: Vec<f64> = (0..faces).map(|f| mesh.face_area(f)).collect();
    let per_view = without_whole_object_masks(
        &perception.per_view,
        &face_area_m2,
        options.whole_object_fraction,
    );
    let merged_masks = without_whole_object_masks(
        std::slice::from_ref(&perception.merged),
        &face_area_m2,
        options.whole_object_fraction,
    )
    .pop()
    .unwrap_or_default();
    let informative_views = per_view.iter().filter(|v| !v.is_empty()).count();
    let seen_m2 = visible_area_m2(&perception.per_view, &face_area_m2);
    let mask_coverage = if seen_m2 > 0.0 {
        visible_area_m2(&per_view, &face_area_m2) / seen_m2
    } else {
        0.0
    };
    // Separate shells that each hold a share of the surface are parts unless the masks merge
    // them later: K starts at their count (the built-in segmenter often sees one region where
    // flush parts meet, which alone would make K = 1).
    let k_geometric = substantial_components(mesh, options.component_area_fraction);
    let k_values = {
        let range = k_range(
            perception.k_prior.max(k_geometric),
            options.k_below,
            options.k_above,
            faces,
        );
        (*range.start()).max(k_geometric.min(*range.end()))..=*range.end()
    };
    let request = CandidateRequest {
        mesh,
        face_rgba,
        face_material: &materials,
        k_values: k_values.clone(),
        seed: options.seed,
    };
    let candidates = generator.candidates(&request)?;
    lap("candidates", &mut timings);

    let (selection, selected_by) = if informative_views > 0 {
        (
            select_candidate(&candidates, &per_view, &face_area_m2)?,
            "masks",
        )
    } else {
        (
            closest_k(&candidates, k_geometric)?,
            "geometry (no view has a mask below the whole object)",
        )
    };
    let chosen = &candidates[selection.index];
    lap("select", &mut timings);
    let mut steps = Vec::new();
    let mut keep = |step: &str, face_part: &[u32]| {
        if options.keep_step_labels {
            steps.push(StepLabels {
                step: step.to_owned(),
                face_part: face_part.to_vec(),
            });
        }
    };
    keep("select", &chosen.face_labels);

    let (refined, refined_parts) =
        split_disconnected(mesh, &chosen.face_labels, options.refine_eps_rel, None);
    lap("refine", &mut timings);
    keep("refine", &refined);

    let merged = merge_parts(
        &refined,
        &per_view,
        &merged_masks,
        &face_area_m2,
        &options.apriori,
    );
    lap("merge", &mut timings);
    keep("merge", &merged.face_part);

    let (handled, _, panels_kept_apart) =
        keep_handled_panels(mesh, &refined, &merged.face_part, &options.handles);
    lap("handles", &mut timings);
    keep("handles", &handled);

    let (again, refined_again_parts) = split_disconnected(
        mesh,
        &handled,
        options.refine_again_eps_rel,
        Some(options.refine_again_keep_whole_above),
    );
    lap("refine_again", &mut timings);
    keep("refine_again", &again);

    let (small_merged, _, small_parts_merged) =
        merge_small_parts(mesh, &again, &materials, &options.small_parts);
    lap("small_parts", &mut timings);
    keep("small_parts", &small_merged);

    let piece_options = PieceOptions {
        make_whole: options.pieces.make_whole && !generator.learned(),
        ..options.pieces.clone()
    };
    let (whole, whole_parts, pieces) = respect_pieces(mesh, &small_merged, &piece_options);
    lap("pieces", &mut timings);
    keep("pieces", &whole);

    let (unhidden, _, hidden_parts_merged) = merge_hidden_parts(mesh, &whole, &options.hidden);
    lap("hidden", &mut timings);
    keep("hidden", &unhidden);

    let (layered, _, layers_joined) = merge_layers(mesh, &unhidden, &materials, &options.layers);
    lap("layers", &mut timings);
    keep("layers", &layered);

    let (face_part, part_count, tops_joined) =
        merge_tops(mesh, &layered, &materials, &options.tops);
    lap("tops", &mut timings);
    keep("tops", &face_part);
    let one_part_reason = (part_count == 1).then(|| {
        if whole_parts > 1 {
            format!(
                "every part other than the largest ({} of {whole_parts}) is hidden inside it (no \
                 ray from it leaves the closed object), so all were merged into it",
                whole_parts - 1
            )
        } else {
            one_part_reason(
                pieces.pieces,
                selection.k,
                merged.part_count,
                refined_again_parts,
                piece_options.make_whole,
            )
        }
    });

    let summary = DecomposeSummary {
        faces,
        views: perception.views.cameras.len(),
        resolution_px: options.perception.views.resolution_px,
        masks: perception.merged.len(),
        k_prior: perception.k_prior,
        k_geometric,
        mask_coverage,
        k_range: [*k_values.start(), *k_values.end()],
        candidates: selection
            .losses
            .iter()
            .map(|&(k, loss)| CandidateLoss { k, loss })
            .collect(),
        matched_k: selection.k,
        informative_views,
        selected_by: selected_by.to_owned(),
        refined_parts,
        merged_parts: merged.part_count,
        panels_kept_apart,
        refined_again_parts,
        small_parts_merged,
        pieces: pieces.pieces,
        pieces_made_whole: pieces.pieces_made_whole,
        controls_kept: pieces.controls_kept,
        parts_split_in_two: pieces.parts_split_in_two,
        hidden_parts_merged,
        layers_joined,
        tops_joined,
        one_part_reason,
        final_parts: part_count,
        merge_strategy: merged.strategy,
        segmenter: perception.provider,
        generator: generator.provider(),
        seed: options.seed,
        timings,
    };
    Ok(Decomposition {
        face_part,
        part_count,
        summary,
        steps,
    })
}

/// Why the stage found one part, from the part counts after each step.
fn one_part_reason(
    pieces: usize,
    matched_k: usize,
    merged: usize,
    refined_again: usize,
    make_whole: bool,
) -> String {
    if pieces == 1 && make_whole {
        return "the mesh is one connected piece, and cuts inside a piece from geometric \
                clustering are not kept (no seam separates its parts)"
            .to_owned();
    }
    if matched_k == 1 {
        return "the views' masks matched the one-part candidate best".to_owned();
    }
    if merged == 1 {
        return format!(
            "the views showed the {matched_k} candidate parts together, so the merge joined them"
        );
    }
    if refined_again > 1 {
        return format!(
            "the {refined_again} parts left were small fragments of one part and were merged into it"
        );
    }
    format!("the {pieces} connected pieces were all assigned to one part")
}

/// Decomposes the merged mesh of `asset` (colours and materials from its materials, textures
/// and vertex colours) and returns the asset with its parts replaced by the decomposed parts
/// (`part_<i>`, materials and textures kept, declared joints dropped: they name the old parts),
/// with the decomposition.
pub fn decompose_asset(
    asset: &MeshAsset,
    segmenter: &dyn Segmenter,
    generator: &dyn CandidateGenerator,
    options: &DecomposeOptions,
) -> DecomposeResult<(MeshAsset, Decomposition)> {
    let mesh = asset.merged();
    let colours = face_colours(asset);
    let materials = face_material_ids(asset);
    let decomposition = decompose(&mesh, &colours, &materials, segmenter, generator, options)?;
    let parts = decomposition
        .part_meshes(&mesh)
        .into_iter()
        .enumerate()
        .map(|(i, part)| MeshPart {
            name: format!("part_{i}"),
            mesh: part,
        })
        .collect();
    let decomposed = MeshAsset {
        parts,
        materials: asset.materials.clone(),
        textures: asset.textures.clone(),
        joints: Vec::new(),
    };
    Ok((decomposed, decomposition))
}
