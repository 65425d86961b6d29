//! Surface crossings: the real triangle surfaces of the parts, and whether a moving surface point
//! passes through one of them between two poses. Exact for open shells and zero-thickness panels,
//! which have no inside for a convex collider to stand for.

use parry3d::math::Vector;
use parry3d::query::{PointQuery, Ray, RayCast};
use uniphys_geometry::{Aabb, DVec3, KdTree, TriMesh};

use crate::motion::JointMotion;
use crate::penetration::to_f32;
use crate::scene::Scene;
use crate::sweep::SweepParams;

/// One part's surface with a bounding volume hierarchy (parry), relative to the scene origin.
struct PartSurface {
    mesh: parry3d::shape::TriMesh,
    /// Bounds in the object frame, metres.
    bounds: Aabb,
}

/// The surfaces of every part (`None` for a part without triangles).
pub(crate) struct Surfaces {
    origin: DVec3,
    parts: Vec<Option<PartSurface>>,
}

impl Surfaces {
    /// The surfaces of `meshes`, shifted by `origin` (f32 precision is kept near the object).
    pub(crate) fn new(meshes: &[TriMesh], origin: DVec3) -> Self {
        let parts = meshes
            .iter()
            .map(|m| {
                let vertices: Vec<Vector> =
                    m.positions.iter().map(|p| to_f32(*p - origin)).collect();
                parry3d::shape::TriMesh::new(vertices, m.triangles.clone())
                    .ok()
                    .map(|mesh| PartSurface {
                        mesh,
                        bounds: m.bounds(),
                    })
            })
            .collect();
        Self { origin, parts }
    }

    /// Bounds of `part` in the object frame, if it has a surface.
    pub(crate) fn bounds(&self, part: usize) -> Option<Aabb> {
        self.parts.get(part)?.as_ref().map(|s| s.bounds)
    }

    /// Distance from `point` (object frame) to the surface of `part`, metres (infinite without
    /// a surface).
    pub(crate) fn distance_m(&self, part: usize, point: DVec3) -> f64 {
        match self.parts.get(part).and_then(Option::as_ref) {
            Some(s) => f64::from(
                s.mesh
                    .distance_to_local_point(to_f32(point - self.origin), false),
            ),
            None => f64::INFINITY,
        }
    }

    /// Where the segment from `from` to `to` (object frame) first crosses the surface of
    /// `part`, if it does.
    pub(crate) fn crossing(&self, part: usize, from: DVec3, to: DVec3) -> Option<DVec3> {
        let s = self.parts.get(part)?.as_ref()?;
        let lo = from.min(to);
        let hi = from.max(to);
        if lo.cmpgt(s.bounds.max).any() || hi.cmplt(s.bounds.min).any() {
            return None;
        }
        let d = to - from;
        let length = d.length();
        if length <= 0.0 {
            return None;
        }
        let ray = Ray::new(to_f32(from - self.origin), to_f32(d / length));
        let t = s.mesh.cast_local_ray(&ray, length as f32, false)?;
        Some(from + d / length * f64::from(t))
    }
}

/// Surface points of a moving group followed through a sweep: which of those clear of every
/// other part at rest pass through another part's surface, outside the space the moving group
/// filled at rest.
pub(crate) struct Crossings {
    /// Indices (into the moving points) of the points clear of other parts at rest.
    pub(crate) clear: Vec<usize>,
    /// Last position of each clear point.
    previous: Vec<DVec3>,
    /// Whether each clear point has passed through a surface (crossed it and gone deeper than
    /// `through_depth_m` beyond it).
    crossed: Vec<bool>,
    /// The part each clear point has crossed the surface of but not yet gone deep beyond, and
    /// whether it crossed it inside the space the moving group filled at rest.
    touching: Vec<Option<(usize, bool)>>,
    /// How far beyond a crossed surface a point must go to count: less is a part closing onto
    /// another (a lid on its box, a screen on its keyboard), which real limits are.
    through_depth_m: f64,
    /// How many clear points have crossed.
    pub(crate) crossed_count: usize,
    /// Still parts the moving group can reach, and how many points crossed each.
    near: Vec<(usize, usize)>,
    /// The moving points at rest.
    occupancy: KdTree,
    /// A crossing this close to a moving point at rest is in space the group filled at rest.
    occupancy_radius_m: f64,
    /// How far beyond a surface crossed in the space the group filled at rest a point must go to
    /// count: a button pressed into the face it rests on (real meshes often lack its hole) goes
    /// a few millimetres, a door turned into its cabinet through that face goes far.
    rest_space_depth_m: f64,
}

impl Crossings {
    /// Starts following `moving_points` (the parts `moving`) moved by `motion` over `range`
    /// among the `still` parts.
    pub(crate) fn new(
        scene: &Scene,
        moving_points: &[DVec3],
        moving: &[usize],
        still: &[usize],
        motion: &JointMotion,
        range: (f64, f64),
        params: &SweepParams,
    ) -> Self {
        let bounds = Aabb::from_points(moving_points);
        let centre = bounds.center();
        let radius = bounds.diagonal() / 2.0;
        let near: Vec<(usize, usize)> = still
            .iter()
            .filter(|&&p| {
                scene.surfaces.bounds(p).is_some_and(|b| {
                    motion.may_reach(centre, radius, range, b.center(), b.diagonal() / 2.0)
                })
            })
            .map(|&p| (p, 0))
            .collect();
        let contact_m = (params.rest_contact_part_fraction * bounds.diagonal())
            .min(params.rest_contact_object_fraction * scene.diagonal_m);
        let clear: Vec<usize> = (0..moving_points.len())
            .filter(|&i| {
                near.iter()
                    .all(|&(p, _)| scene.surfaces.distance_m(p, moving_points[i]) > contact_m)
            })
            .collect();
        let area_m2: f64 = moving.iter().map(|&p| scene.areas_m2[p]).sum();
        let spacing_m = (area_m2 / moving_points.len().max(1) as f64).sqrt();
        Self {
            previous: clear.iter().map(|&i| moving_points[i]).collect(),
            crossed: vec![false; clear.len()],
            touching: vec![None; clear.len()],
            through_depth_m: contact_m,
            rest_space_depth_m: (params.short_slide_fraction * scene.diagonal_m).max(contact_m),
            clear,
            crossed_count: 0,
            near,
            occupancy: KdTree::new(moving_points.to_vec()),
            occupancy_radius_m: spacing_m,
        }
    }

    /// Moves the points to `moved` (all moving points, in their original order) and records the
    /// crossings on the way from their previous positions; a point that crossed a surface counts
    /// once it is deeper than the contact distance beyond it, or, where it crossed inside the
    /// space the group filled at rest (a button pressed into its face, a wheel in its fork),
    /// deeper than a short slide's travel (a door turned into its cabinet through the face it
    /// rested on).
    pub(crate) fn advance(&mut self, scene: &Scene, moved: &[DVec3]) {
        for (k, &i) in self.clear.iter().enumerate() {
            let to = moved[i];
            if !self.crossed[k] {
                if self.touching[k].is_none() {
                    for (part, _) in &self.near {
                        let Some(hit) = scene.surfaces.crossing(*part, self.previous[k], to) else {
                            continue;
                        };
                        let in_rest_space =
                            self.occupancy.nearest_distance(hit) <= self.occupancy_radius_m;
                        self.touching[k] = Some((*part, in_rest_space));
                        break;
                    }
                }
                if let Some((part, in_rest_space)) = self.touching[k]
                    && scene.surfaces.distance_m(part, to)
                        > if in_rest_space {
                            self.rest_space_depth_m
                        } else {
                            self.through_depth_m
                        }
                {
                    self.crossed[k] = true;
                    self.crossed_count += 1;
                    if let Some((_, hits)) = self.near.iter_mut().find(|(p, _)| *p == part) {
                        *hits += 1;
                    }
                }
            }
            self.previous[k] = to;
        }
    }

    /// Puts the points back at rest (`rest`: all moving points at rest) to follow them the
    /// other way; what crossed stays crossed.
    pub(crate) fn restart(&mut self, rest: &[DVec3]) {
        for (k, &i) in self.clear.iter().enumerate() {
            self.previous[k] = rest[i];
            self.touching[k] = None;
        }
    }

    /// Fraction of the clear points that have crossed (0 without clear points).
    pub(crate) fn fraction(&self) -> f64 {
        if self.clear.is_empty() {
            0.0
        } else {
            self.crossed_count as f64 / self.clear.len() as f64
        }
    }

    /// The part crossed by the most points, if any was.
    pub(crate) fn most_crossed(&self) -> Option<usize> {
        self.near
            .iter()
            .filter(|(_, hits)| *hits > 0)
            .max_by_key(|(p, hits)| (*hits, std::cmp::Reverse(*p)))
            .map(|(p, _)| *p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_through_a_single_sided_quad_crosses_it_once() {
        // A zero-thickness panel in the plane z = 0 (two triangles, no volume).
        let panel = TriMesh::new(
            vec![
                DVec3::new(-1.0, -1.0, 0.0),
                DVec3::new(1.0, -1.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(-1.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .expect("panel");
        let s = Surfaces::new(&[panel], DVec3::new(0.2, 0.1, 0.0));
        let hit = s
            .crossing(0, DVec3::new(0.3, 0.2, 0.5), DVec3::new(0.3, 0.2, -0.5))
            .expect("crosses");
        assert!((hit - DVec3::new(0.3, 0.2, 0.0)).length() < 1e-5, "{hit}");
        // Stopping short, passing beside, or moving along the panel: no crossing.
        assert!(
            s.crossing(0, DVec3::new(0.3, 0.2, 0.5), DVec3::new(0.3, 0.2, 0.1))
                .is_none()
        );
        assert!(
            s.crossing(0, DVec3::new(1.5, 0.2, 0.5), DVec3::new(1.5, 0.2, -0.5))
                .is_none()
        );
        assert!((s.distance_m(0, DVec3::new(0.0, 0.0, 0.25)) - 0.25).abs() < 1e-5);
    }
}
