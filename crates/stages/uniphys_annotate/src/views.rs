//! The images of the requests, from the renderer's primitives: a context-preserving composite
//! per part, the candidate axes and the candidate pivots of a moving part, each from two
//! viewpoints, as deterministic PNG files.

use uniphys_geometry::{Aabb, DVec3, TriMesh};
use uniphys_render::{
    Camera, RgbaImage, camera_from_direction, draw, encode_png, hstack, render_face_ids, shade,
};

use crate::AnnotateResult;

/// Axis legend, in the order of the candidates: contact normal, six in-plane directions, then
/// the object frame X, Y, Z.
pub const AXIS_LEGEND: [(&str, [u8; 4]); 10] = [
    ("Yellow", [255, 230, 0, 255]),
    ("Orange", [255, 128, 0, 255]),
    ("Purple", [153, 51, 255, 255]),
    ("Cyan", [0, 220, 230, 255]),
    ("Magenta", [255, 0, 255, 255]),
    ("Dark Gray", [70, 70, 70, 255]),
    ("Brown", [110, 66, 26, 255]),
    ("Red", [230, 0, 0, 255]),
    ("Green", [0, 180, 0, 255]),
    ("Blue", [0, 60, 255, 255]),
];

/// Pivot legend, in the order of the candidates: five contact cluster centres, then their
/// centroid.
pub const PIVOT_LEGEND: [(&str, [u8; 4]); 6] = [
    ("Red", [230, 0, 0, 255]),
    ("Green", [0, 180, 0, 255]),
    ("Blue", [0, 60, 255, 255]),
    ("Yellow", [255, 230, 0, 255]),
    ("Purple", [153, 51, 255, 255]),
    ("Brown", [110, 66, 26, 255]),
];

/// Colour names of a legend.
pub fn names<const N: usize>(legend: &[(&'static str, [u8; 4]); N]) -> [&'static str; N] {
    legend.map(|(name, _)| name)
}

/// The two viewpoints (front-right-above and back-right-above, as the reference's cameras).
const VIEWS: [[f64; 3]; 2] = [[0.5, -1.0, 0.5], [0.5, 1.0, 0.5]];
const FADED: [u8; 4] = [190, 190, 190, 70];
const WHITE: [u8; 4] = [255, 255, 255, 255];
const INK: [u8; 4] = [0, 0, 0, 255];

/// All parts merged, with the part of each triangle.
pub struct Scene<'a> {
    meshes: &'a [TriMesh],
    colours: Vec<[u8; 4]>,
    merged: TriMesh,
    part_of_face: Vec<usize>,
    bounds: Aabb,
    size_px: u32,
}

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
    /// A scene of `meshes` with linear RGBA `colours`, rendered in panels of `size_px`.
    pub fn new(meshes: &'a [TriMesh], colours: &[[f32; 4]], size_px: u32) -> Self {
        let merged = TriMesh::merge(meshes);
        let part_of_face = meshes
            .iter()
            .enumerate()
            .flat_map(|(i, m)| std::iter::repeat_n(i, m.triangle_count()))
            .collect();
        let bounds = meshes.iter().fold(Aabb::EMPTY, |b, m| b.union(m.bounds()));
        Self {
            meshes,
            colours: colours
                .iter()
                .map(|c| [srgb8(c[0]), srgb8(c[1]), srgb8(c[2]), 255])
                .collect(),
            merged,
            part_of_face,
            bounds,
            size_px,
        }
    }

    fn camera(&self, bounds: &Aabb, view: usize) -> Camera {
        camera_from_direction(
            bounds,
            DVec3::from_array(VIEWS[view]),
            self.size_px,
            self.size_px,
        )
    }

    /// The whole object from `view`, the parts in `highlighted` in `colour(part)`, the others
    /// faded grey.
    fn object_panel(
        &self,
        view: usize,
        colour: &dyn Fn(usize) -> Option<[u8; 4]>,
    ) -> (RgbaImage, Camera) {
        let camera = self.camera(&self.bounds, view);
        let ids = render_face_ids(&self.merged, &camera);
        let panel = shade(&ids, &camera, &|face| {
            let part = self.part_of_face.get(face).copied().unwrap_or(usize::MAX);
            colour(part).unwrap_or(FADED)
        });
        (on_white(&panel), camera)
    }

    /// Composite of part `index`: the object from two viewpoints with the part in its colours
    /// and the rest faded, then the part alone; labelled `part <index + 1>`.
    pub fn part_composite(&self, index: usize) -> AnnotateResult<Vec<u8>> {
        let own =
            |part: usize| (part == index).then(|| self.colours.get(part).copied().unwrap_or(WHITE));
        let mut panels: Vec<RgbaImage> = (0..2).map(|v| self.object_panel(v, &own).0).collect();
        if let Some(mesh) = self.meshes.get(index) {
            let camera = self.camera(&mesh.bounds(), 0);
            let ids = render_face_ids(mesh, &camera);
            let colour = self.colours.get(index).copied().unwrap_or(WHITE);
            panels.push(on_white(&shade(&ids, &camera, &|_| colour)));
        }
        let mut image = hstack(&panels, 4, INK);
        draw::text(&mut image, 4, 4, &format!("part {}", index + 1), 2, INK);
        Ok(encode_png(&image)?)
    }

    /// The moving `group` with the candidate `axes` drawn as arrows from `anchor_m`, from two
    /// viewpoints, with the legend.
    pub fn axis_views(
        &self,
        group: &[usize],
        axes: &[DVec3],
        anchor_m: DVec3,
    ) -> AnnotateResult<Vec<u8>> {
        let length_m = 0.5 * self.group_bounds(group).diagonal().max(1e-3);
        let mut panels = Vec::new();
        for view in 0..2 {
            let (mut panel, camera) = self.object_panel(view, &|p| self.group_colour(group, p));
            for (axis, (_, rgba)) in axes.iter().zip(AXIS_LEGEND) {
                let (Some(a), Some(b)) = (
                    camera.project(anchor_m),
                    camera.project(anchor_m + *axis * length_m),
                ) else {
                    continue;
                };
                draw::arrow(
                    &mut panel,
                    [a.x_px, a.y_px],
                    [b.x_px, b.y_px],
                    2.0,
                    8.0,
                    rgba,
                );
            }
            panels.push(panel);
        }
        let mut image = hstack(&panels, 4, INK);
        legend(&mut image, &AXIS_LEGEND);
        Ok(encode_png(&image)?)
    }

    /// The moving `group` faded with the candidate `pivots` as coloured discs, from two
    /// viewpoints, with the legend.
    pub fn pivot_views(&self, group: &[usize], pivots: &[DVec3]) -> AnnotateResult<Vec<u8>> {
        let radius_px = (f64::from(self.size_px) / 40.0).max(3.0);
        let mut panels = Vec::new();
        for view in 0..2 {
            let (mut panel, camera) = self.object_panel(view, &|p| {
                self.group_colour(group, p).map(|c| [c[0], c[1], c[2], 110])
            });
            for (pivot, (_, rgba)) in pivots.iter().zip(PIVOT_LEGEND) {
                if let Some(p) = camera.project(*pivot) {
                    draw::disc(&mut panel, [p.x_px, p.y_px], radius_px, rgba);
                }
            }
            panels.push(panel);
        }
        let mut image = hstack(&panels, 4, INK);
        legend(&mut image, &PIVOT_LEGEND);
        Ok(encode_png(&image)?)
    }

    fn group_colour(&self, group: &[usize], part: usize) -> Option<[u8; 4]> {
        group
            .contains(&part)
            .then(|| self.colours.get(part).copied().unwrap_or(WHITE))
    }

    fn group_bounds(&self, group: &[usize]) -> Aabb {
        group
            .iter()
            .filter_map(|&i| self.meshes.get(i))
            .fold(Aabb::EMPTY, |b, m| b.union(m.bounds()))
    }
}

fn on_white(image: &RgbaImage) -> RgbaImage {
    image.flattened([255, 255, 255])
}

fn legend<const N: usize>(image: &mut RgbaImage, entries: &[(&str, [u8; 4]); N]) {
    for (row, (name, rgba)) in entries.iter().enumerate() {
        let y = 4 + 10 * i32::try_from(row).unwrap_or(0);
        draw::fill_rect(image, 4, y, 8, 7, *rgba);
        draw::text(image, 16, y, name, 1, INK);
    }
}
