//! The images of the requests, drawn by `uniphys_render::lvlm_views` and encoded as PNG: the
//! context-preserving composite of each part, the ten candidate axes of a moving part (two
//! viewpoints, one per row) and its six candidate pivots (two viewpoints side by side).

use uniphys_geometry::{DVec3, TriMesh};
use uniphys_render::lvlm_views::{
    AXIS_COLOURS, PANEL_GAP_PX, PIVOT_COLOURS, PartScene, ViewOptions, axis_candidate_views,
    part_composite, pivot_candidate_views,
};
use uniphys_render::{encode_png, hstack, vstack};

use std::time::Instant;

use crate::{AnnotateError, AnnotateResult};

/// Axis legend in candidate order: contact normal, six in-plane directions, then object X, Y, Z
/// (Red, Green, Blue).
pub const AXIS_LEGEND: [(&str, [u8; 4]); 10] = AXIS_COLOURS;

/// Pivot legend in candidate order: five contact cluster centres, then their centroid.
pub const PIVOT_LEGEND: [(&str, [u8; 4]); 6] = PIVOT_COLOURS;

const WHITE: [u8; 4] = [255, 255, 255, 255];

/// Colour names of a legend.
pub fn names<const N: usize>(legend: &[(&'static str, [u8; 4]); N]) -> [&'static str; N] {
    legend.map(|(name, _)| name)
}

/// The parts with their display colours, rendered in panels of one size.
pub struct Scene<'a> {
    meshes: &'a [TriMesh],
    rgba: Vec<[u8; 4]>,
    options: ViewOptions,
}

/// Linear [0, 1] to 8-bit sRGB.
fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round().clamp(0.0, 255.0) as u8
}

impl<'a> Scene<'a> {
    /// A scene of `meshes` with linear RGBA `colours`, rendered in panels of `panel_px`.
    pub fn new(meshes: &'a [TriMesh], colours: &[[f32; 4]], panel_px: u32) -> Self {
        Self {
            meshes,
            rgba: colours
                .iter()
                .map(|c| [srgb8(c[0]), srgb8(c[1]), srgb8(c[2]), 255])
                .collect(),
            options: ViewOptions { panel_px },
        }
    }

    fn scene(&self) -> PartScene<'_> {
        PartScene {
            part_meshes: self.meshes,
            part_rgba: &self.rgba,
        }
    }

    /// Composite of part `index`: the object from two viewpoints with the part in its colours
    /// and the rest translucent grey, then the part alone.
    pub fn part_composite(&self, index: usize) -> AnnotateResult<Vec<u8>> {
        Ok(encode_png(&part_composite(
            &self.scene(),
            index,
            &self.options,
        ))?)
    }

    /// The ten candidate `axes` of `part` drawn through `anchor_m`, one viewpoint per row.
    pub fn axis_views(
        &self,
        part: usize,
        axes: &[DVec3; 10],
        anchor_m: DVec3,
    ) -> AnnotateResult<Vec<u8>> {
        let views = axis_candidate_views(&self.scene(), part, axes, anchor_m, &self.options);
        Ok(encode_png(&vstack(&views, PANEL_GAP_PX, WHITE))?)
    }

    /// The six candidate `pivots` of `part`, the two viewpoints side by side.
    pub fn pivot_views(&self, part: usize, pivots: &[DVec3; 6]) -> AnnotateResult<Vec<u8>> {
        let views = pivot_candidate_views(&self.scene(), part, pivots, &self.options);
        Ok(encode_png(&hstack(&views, PANEL_GAP_PX, WHITE))?)
    }
}

/// The composites of all `n` parts, rendered on the available cores (parts dealt round-robin
/// to threads); returns them in part order with the rendering time summed over threads.
pub fn render_composites(scene: &Scene<'_>, n: usize) -> AnnotateResult<(Vec<Vec<u8>>, f64)> {
    let threads = std::thread::available_parallelism()
        .map_or(1, std::num::NonZeroUsize::get)
        .min(n)
        .max(1);
    let rendered: Vec<(usize, AnnotateResult<Vec<u8>>, f64)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                s.spawn(move || {
                    (t..n)
                        .step_by(threads)
                        .map(|i| {
                            let started = Instant::now();
                            let png = scene.part_composite(i);
                            (i, png, started.elapsed().as_secs_f64())
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    });
    let mut slots: Vec<Option<Vec<u8>>> = vec![None; n];
    let mut secs = 0.0;
    for (i, png, elapsed) in rendered {
        secs += elapsed;
        if let Some(slot) = slots.get_mut(i) {
            *slot = Some(png?);
        }
    }
    let composites = slots
        .into_iter()
        .enumerate()
        .map(|(i, png)| {
            png.ok_or_else(|| {
                AnnotateError::RenderFailed(format!(
                    "the composite of part {} was not rendered (its thread panicked)",
                    i + 1
                ))
            })
        })
        .collect::<AnnotateResult<Vec<_>>>()?;
    Ok((composites, secs))
}
