//! The surface things are set on: a broad flat board raised over the object (its underside in
//! the upper half of the object's height), covering most of its plan, with nothing else above
//! it (a table's top, a cooktop, a cart's top shelf). With no walled cavity under it, it closes
//! nothing, so it is no lid: it joins the largest part, when both are of one material (every part
//! of the stage is: a glass top stays apart from its wooden frame).
//!
//! Why: such a board is a piece of its own, resting on legs, an apron, a frame or drawers, and
//! the views show it apart from them. Left a part, it costs the body much of its area and gets
//! a joint downstream (measured on the shared PartNet-Mobility objects, `decompose-bench
//! --partnet`: table tops, an oven's cooktop, a cart's shelf). A lid is the top of a container:
//! under it lies the container's empty inside, deep and walled all round (a chest, a pot, a
//! bottle's neck under its cap), and the test keeps it. Up is +Z, the frame the stage reads the
//! mesh in.
//!
//! What the test cannot tell: a closed laptop's screen lies on its base with no cavity under it.
//! It joins the base when other parts remain; when that would leave one part, it stays. A
//! chest whose inside a drawer or a tray fills just under its lid reads as a table too.

use uniphys_geometry::{Aabb, DVec3, RayMesh, TriMesh};

use crate::part_faces::PartFaces;
use crate::sheet_shape::SheetShape;

/// Tuning of [`merge_tops`]. Shares are of the object's height, plan or diagonal as named.
#[derive(Debug, Clone, PartialEq)]
pub struct TopOptions {
    /// A board is thin: its thickness at most this share of its length. Default 0.15.
    pub thin_ratio_max: f64,
    /// ... flat, its normal at most this far from the vertical (cosine). Default 0.9.
    pub level_cos_min: f64,
    /// ... broad: its width at least this share of its length (not a bar, not a blade).
    /// Default 0.25.
    pub broad_ratio_min: f64,
    /// ... and a sheet: its area at least this many times its length times its width (a wire's
    /// is far less). Default 1.0.
    pub fill_min: f64,
    /// Its plan covers at least this share of the object's plan. Default 0.4.
    pub plan_cover_min: f64,
    /// It is raised: its underside lies at least this share of the object's height above the
    /// object's bottom (a laptop's base or a stapler's lies at the bottom). Default 0.5.
    pub raised_min: f64,
    /// At least this share of it sees the sky straight up past every other part. Default 0.5.
    pub sky_share_min: f64,
    /// Under it, a column is a container's inside when the first surface below lies at least
    /// this share of the object's height down ... Default 0.3.
    pub cavity_depth_min: f64,
    /// ... and surfaces stand all round it halfway down; a board over at least this share of
    /// such columns is a lid. Default 0.5.
    pub cavity_share_max: f64,
    /// Parts below this share of the total area are left alone. Default 0.005.
    pub area_fraction_min: f64,
}

impl Default for TopOptions {
    fn default() -> Self {
        Self {
            thin_ratio_max: 0.15,
            level_cos_min: 0.9,
            broad_ratio_min: 0.25,
            fill_min: 1.0,
            plan_cover_min: 0.4,
            raised_min: 0.5,
            sky_share_min: 0.5,
            cavity_depth_min: 0.3,
            cavity_share_max: 0.5,
            area_fraction_min: 0.005,
        }
    }
}

/// Samples of a board for its sky test.
const SAMPLES: usize = 400;
/// Columns under a board along each side of its plan for the cavity test.
const COLUMNS: usize = 10;
/// Horizontal directions a cavity's walls are looked for in.
const WALL_DIRECTIONS: usize = 8;
/// Rays start this share of the diagonal off the surface they leave.
const RAY_OFFSET_REL: f64 = 1e-3;

/// Joins every board topping the object with no cavity under it (see the module) to the largest
/// part when both are of one material (`face_material`: one id per face, or empty when
/// unknown), unless that would leave one part. Returns the new labels (numbered by smallest
/// face), their count and how many parts were joined.
#[must_use]
pub fn merge_tops(
    mesh: &TriMesh,
    face_part: &[u32],
    face_material: &[u32],
    options: &TopOptions,
) -> (Vec<u32>, usize, usize) {
    let parts = PartFaces::of(mesh, face_part);
    let unchanged = || (face_part.to_vec(), parts.count(), 0);
    let Some(largest) = parts.largest().filter(|_| parts.count() >= 3) else {
        return unchanged();
    };
    let object = Object::of(mesh);
    let material = parts.main_materials(mesh, face_material);
    let boards: Vec<(usize, Board)> = (0..parts.count())
        .filter(|&p| {
            p != largest
                && material[p] == material[largest]
                && parts.area_m2[p] >= options.area_fraction_min * parts.total_m2
        })
        .filter_map(|p| {
            Board::of(mesh, &parts.faces_of[p], parts.area_m2[p], &object, options)
                .map(|board| (p, board))
        })
        .collect();
    if boards.is_empty() {
        return unchanged();
    }
    let tops: Vec<usize> = boards
        .into_iter()
        .filter(|(p, board)| {
            let others: Vec<usize> = (0..mesh.triangle_count())
                .filter(|&f| face_part[f] as usize != *p)
                .collect();
            RayMesh::new(&mesh.submesh(&others)).is_some_and(|others| {
                board.sees_the_sky(&others, &object, options)
                    && board.cavity_share(&others, &object, options) < options.cavity_share_max
            })
        })
        .map(|(p, _)| p)
        .take(parts.count() - 2)
        .collect();
    if tops.is_empty() {
        return unchanged();
    }
    let (labels, count) = parts.joined_into(face_part, &tops, largest);
    (labels, count, tops.len())
}

/// The object's extent: bounds, height, plan area and diagonal.
struct Object {
    bounds: Aabb,
    height_m: f64,
    plan_m2: f64,
    diagonal_m: f64,
}

impl Object {
    fn of(mesh: &TriMesh) -> Self {
        let bounds = mesh.bounds();
        let size = bounds.max - bounds.min;
        Self {
            bounds,
            height_m: size.z,
            plan_m2: size.x * size.y,
            diagonal_m: bounds.diagonal(),
        }
    }
}

/// A part shaped and placed as the object's top: a broad flat sheet raised over the object and
/// covering most of its plan.
struct Board {
    samples: Vec<DVec3>,
    bounds: Aabb,
    rays: RayMesh,
}

impl Board {
    /// `None` unless the part made of `faces` (area `area_m2`) is one.
    fn of(
        mesh: &TriMesh,
        faces: &[usize],
        area_m2: f64,
        object: &Object,
        options: &TopOptions,
    ) -> Option<Self> {
        if object.height_m <= 0.0 || object.plan_m2 <= 0.0 {
            return None;
        }
        let corners: Vec<DVec3> = faces.iter().flat_map(|&f| mesh.corners(f)).collect();
        let bounds = Aabb::from_points(&corners);
        let plan = bounds.max - bounds.min;
        if plan.x * plan.y < options.plan_cover_min * object.plan_m2
            || bounds.min.z < object.bounds.min.z + options.raised_min * object.height_m
        {
            return None;
        }
        let sheet = mesh.submesh(faces);
        let shape = SheetShape::of(&sheet, corners, SAMPLES, faces.len() as u64)?;
        let [length, width, _] = shape.extents_m;
        let is_board = shape.is_broad_sheet(options.thin_ratio_max, options.broad_ratio_min)
            && shape.axes[2].z.abs() >= options.level_cos_min
            && area_m2 >= options.fill_min * length * width;
        if !is_board {
            return None;
        }
        Some(Self {
            samples: shape.samples,
            bounds,
            rays: RayMesh::new(&sheet)?,
        })
    }

    /// Whether enough of it sees the sky straight up past every other part (`others`).
    fn sees_the_sky(&self, others: &RayMesh, object: &Object, options: &TopOptions) -> bool {
        let open = self
            .samples
            .iter()
            .filter(|p| {
                others
                    .first_hit_m(**p, DVec3::Z, 2.0 * object.diagonal_m)
                    .is_none()
            })
            .count();
        open as f64 >= options.sky_share_min * self.samples.len() as f64
    }

    /// Share of the columns under the board that look down into a container's inside: the
    /// first surface of `below` (every other part) lies deep under the board, and surfaces of
    /// `below` stand all round the column halfway down.
    fn cavity_share(&self, below: &RayMesh, object: &Object, options: &TopOptions) -> f64 {
        let offset_m = RAY_OFFSET_REL * object.diagonal_m;
        let reach_m = 2.0 * object.diagonal_m;
        let walls: Vec<DVec3> = (0..WALL_DIRECTIONS)
            .map(|k| {
                let angle = std::f64::consts::TAU * k as f64 / WALL_DIRECTIONS as f64;
                DVec3::new(angle.cos(), angle.sin(), 0.0)
            })
            .collect();
        let size = self.bounds.max - self.bounds.min;
        let (mut columns, mut cavities) = (0usize, 0usize);
        for i in 0..COLUMNS {
            for j in 0..COLUMNS {
                let at = DVec3::new(
                    self.bounds.min.x + (i as f64 + 0.5) / COLUMNS as f64 * size.x,
                    self.bounds.min.y + (j as f64 + 0.5) / COLUMNS as f64 * size.y,
                    self.bounds.min.z - offset_m,
                );
                // Only the columns the board covers.
                if self
                    .rays
                    .first_hit_m(at - DVec3::Z * offset_m, DVec3::Z, reach_m)
                    .is_none()
                {
                    continue;
                }
                columns += 1;
                let Some(depth_m) = below.first_hit_m(at, -DVec3::Z, reach_m) else {
                    continue;
                };
                if depth_m < options.cavity_depth_min * object.height_m {
                    continue;
                }
                let halfway = at - DVec3::Z * (0.5 * depth_m);
                if walls
                    .iter()
                    .all(|&d| below.first_hit_m(halfway, d, reach_m).is_some())
                {
                    cavities += 1;
                }
            }
        }
        cavities as f64 / columns.max(1) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    /// One mesh of the parts, each a list of boxes, and the part of every face.
    fn object(parts: &[Vec<(DVec3, DVec3)>]) -> (TriMesh, Vec<u32>) {
        let mut meshes = Vec::new();
        let mut labels = Vec::new();
        for (i, boxes) in parts.iter().enumerate() {
            for &(min, max) in boxes {
                let m = TriMesh::cuboid(min, max);
                labels.extend(std::iter::repeat_n(i as u32, m.triangle_count()));
                meshes.push(m);
            }
        }
        (TriMesh::merge(&meshes), labels)
    }

    /// A frame of four legs and an apron (part 0), a board on it (part 1) and a drawer hung
    /// under the board (part 2); with `walls`, a closed chest instead: a floor and four walls up
    /// to the board, and a pull on the front wall for the third part.
    fn table(walls: bool) -> (TriMesh, Vec<u32>) {
        let frame = if walls {
            vec![
                (v(0.0, 0.0, 0.0), v(1.0, 0.6, 0.05)),
                (v(0.0, 0.0, 0.05), v(1.0, 0.03, 0.76)),
                (v(0.0, 0.57, 0.05), v(1.0, 0.6, 0.76)),
                (v(0.0, 0.03, 0.05), v(0.03, 0.57, 0.76)),
                (v(0.97, 0.03, 0.05), v(1.0, 0.57, 0.76)),
            ]
        } else {
            let leg = |x: f64, y: f64| (v(x, y, 0.0), v(x + 0.05, y + 0.05, 0.76));
            vec![
                leg(0.0, 0.0),
                leg(0.95, 0.0),
                leg(0.0, 0.55),
                leg(0.95, 0.55),
                (v(0.05, 0.0, 0.6), v(0.95, 0.02, 0.76)),
                (v(0.05, 0.58, 0.6), v(0.95, 0.6, 0.76)),
                (v(0.95, 0.05, 0.6), v(0.97, 0.55, 0.76)),
            ]
        };
        let board = vec![(v(-0.02, -0.02, 0.76), v(1.02, 0.62, 0.8))];
        let third = if walls {
            vec![(v(0.45, -0.04, 0.6), v(0.55, 0.0, 0.65))]
        } else {
            vec![
                (v(0.1, 0.05, 0.62), v(0.8, 0.55, 0.63)),
                (v(0.03, 0.05, 0.62), v(0.1, 0.55, 0.74)),
                (v(0.8, 0.05, 0.62), v(0.81, 0.55, 0.74)),
            ]
        };
        object(&[frame, board, third])
    }

    #[test]
    fn a_tables_top_joins_its_frame_and_its_drawer_stays() {
        let (mesh, labels) = table(false);
        let (joined, count, tops) = merge_tops(&mesh, &labels, &[], &TopOptions::default());
        assert_eq!((count, tops), (2, 1));
        let board = labels.iter().position(|&l| l == 1).expect("board");
        let drawer = labels.iter().position(|&l| l == 2).expect("drawer");
        assert_eq!(joined[board], joined[0]);
        assert_ne!(joined[drawer], joined[0]);
        // A glass top on a wooden frame stays apart: every part is of one material.
        let materials: Vec<u32> = labels.iter().map(|&l| u32::from(l == 1)).collect();
        assert_eq!(
            merge_tops(&mesh, &labels, &materials, &TopOptions::default()).2,
            0
        );
    }

    #[test]
    fn a_chests_closed_lid_stays_a_part() {
        // The same board on a box walled all round with a floor: under it lies the chest's
        // empty inside.
        let (mesh, labels) = table(true);
        let (joined, count, tops) = merge_tops(&mesh, &labels, &[], &TopOptions::default());
        assert_eq!((count, tops), (3, 0));
        assert_eq!(joined, labels);
    }

    #[test]
    fn a_board_low_down_or_covered_from_above_is_no_top() {
        // The table's board lowered under its apron is a shelf in the lower half ...
        let (mesh, labels) = table(false);
        let lowered = TriMesh {
            positions: mesh
                .positions
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let on_board = mesh
                        .triangles
                        .iter()
                        .zip(&labels)
                        .any(|(t, &l)| l == 1 && t.contains(&u32::try_from(i).expect("index")));
                    if on_board { *p - DVec3::Z * 0.6 } else { *p }
                })
                .collect(),
            ..mesh.clone()
        };
        assert_eq!(
            merge_tops(&lowered, &labels, &[], &TopOptions::default()).2,
            0
        );
        // ... and under a second board as wide, it does not see the sky.
        let cover = TriMesh::cuboid(v(-0.02, -0.02, 0.9), v(1.02, 0.62, 0.92));
        let covered = TriMesh::merge([&mesh, &cover]);
        let mut cover_labels = labels.clone();
        cover_labels.extend(std::iter::repeat_n(3, cover.triangle_count()));
        let (joined, _, _) = merge_tops(&covered, &cover_labels, &[], &TopOptions::default());
        let board = labels.iter().position(|&l| l == 1).expect("board");
        assert_ne!(joined[board], joined[0]);
    }
}
