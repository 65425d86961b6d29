//! Surface crossings: the real triangle surfaces of the parts, and whether a moving surface point
//! passes through one of them between two poses. Exact for open shells and zero-thickness panels,
//! which have no inside for a convex collider to stand for.

use parry3d::math::Vector;
use parry3d::query::{PointQuery, PointQueryWithLocation, Ray, RayCast};
use uniphys_geometry::{Aabb, DVec3, KdTree, TriMesh};
use uniphys_types::JointKind;

use crate::held::rest_contact_m;
use crate::motion::JointMotion;
use crate::penetration::to_f32;
use crate::scene::Scene;
use crate::sweep_params::SweepParams;

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

    /// The smallest distance from `points` (object frame) to the surface of `part`, metres
    /// (infinite without a surface or points); the same as the least [`Self::distance_m`], found
    /// with each query bounded by the nearest so far, so most stop near the top of the hierarchy.
    pub(crate) fn nearest_distance_m(
        &self,
        part: usize,
        points: impl IntoIterator<Item = DVec3>,
    ) -> f64 {
        // parry's own bound for an unbounded query, so the first point's is one.
        let unbounded_m = f64::from(f32::MAX);
        let nearest_m = points.into_iter().fold(unbounded_m, |nearest_m, point| {
            self.distance_within_m(part, point, nearest_m)
                .map_or(nearest_m, |d| d.min(nearest_m))
        });
        if nearest_m == unbounded_m {
            f64::INFINITY
        } else {
            nearest_m
        }
    }

    /// Distance from `point` (object frame) to the surface of `part`, metres, if it is at most
    /// `max_m` (a bounded query: a far point costs a few box tests).
    pub(crate) fn distance_within_m(&self, part: usize, point: DVec3, max_m: f64) -> Option<f64> {
        let s = self.parts.get(part)?.as_ref()?;
        let local = to_f32(point - self.origin);
        let projection = s
            .mesh
            .project_local_point_with_max_dist(local, false, max_m as f32)?;
        Some(f64::from((local - projection.point).length()))
    }

    /// The point of `part`'s surface nearest to `point` (object frame) and its triangle's unit
    /// normal (as the triangle is wound), if one lies within `max_distance_m`.
    pub(crate) fn nearest_with_normal(
        &self,
        part: usize,
        point: DVec3,
        max_distance_m: f64,
    ) -> Option<(DVec3, DVec3)> {
        let s = self.parts.get(part)?.as_ref()?;
        let (projection, (triangle, _)) =
            s.mesh.project_local_point_and_get_location_with_max_dist(
                to_f32(point - self.origin),
                false,
                max_distance_m as f32,
            )?;
        let n = s.mesh.triangle(triangle).normal()?;
        let p = projection.point;
        Some((
            DVec3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z)) + self.origin,
            DVec3::new(f64::from(n.x), f64::from(n.y), f64::from(n.z)),
        ))
    }

    /// Where the segment from `from` to `to` (object frame) first crosses the surface of
    /// `part`, if it does, with the crossed triangle's normal turned along the segment.
    pub(crate) fn crossing(&self, part: usize, from: DVec3, to: DVec3) -> Option<Entry> {
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
        let direction = d / length;
        let ray = Ray::new(to_f32(from - self.origin), to_f32(direction));
        let hit = s
            .mesh
            .cast_local_ray_and_get_normal(&ray, length as f32, false)?;
        let normal = DVec3::new(
            f64::from(hit.normal.x),
            f64::from(hit.normal.y),
            f64::from(hit.normal.z),
        )
        .normalize_or_zero();
        let along = if normal.dot(direction) < 0.0 {
            -normal
        } else {
            normal
        };
        Some(Entry {
            part,
            point: from + direction * f64::from(hit.time_of_impact),
            normal: along,
            in_rest_space: false,
        })
    }
}

/// Where a moving point went through a part's surface.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry {
    /// The part whose surface was crossed.
    part: usize,
    /// The crossing, object frame.
    point: DVec3,
    /// The crossed triangle's unit normal, turned the way the point went through.
    normal: DVec3,
    /// Whether the crossing lies in the space the moving group filled at rest.
    in_rest_space: bool,
}

impl Entry {
    /// How far `point` lies beyond the crossed triangle's plane, metres (negative: back on the
    /// side it came from).
    fn depth_beyond_m(&self, point: DVec3) -> f64 {
        (point - self.point).dot(self.normal)
    }
}

/// Whether the segment from `from` to `to`, which crosses the surface of `entry.part`, still
/// crosses it when shifted by `margin_m` to either side along the crossed triangle's plane: a
/// crossing at least that far inside the surface's outline. A point on a face flush with the
/// crossed part's own face (a drawer's side sliding along a leg) meets the edge of the face
/// across its path and is only grazing it.
fn inside_outline(scene: &Scene, entry: &Entry, from: DVec3, to: DVec3, margin_m: f64) -> bool {
    let across = entry.normal.any_orthonormal_vector();
    let other = entry.normal.cross(across);
    [across, -across, other, -other].iter().all(|&side| {
        let shift = side * margin_m;
        scene
            .surfaces
            .crossing(entry.part, from + shift, to + shift)
            .is_some()
    })
}

/// How far a moving point's distance to a still part is measured, as a share of the moving
/// group's diagonal (at least twice the contact distance): beyond it, a point is that far.
const SLACK_REACH_FRACTION: f64 = 0.1;
/// A step skips its ray when it is shorter than the point's slack by this share of the scene's
/// diagonal.
const SLACK_MARGIN_FRACTION: f64 = 1e-5;

/// Most steps a point near a surface is followed without measuring its distance.
const MAX_UNMEASURED_STEPS: u8 = 31;

/// Surfaces a point may be inside at once before the oldest is forgotten.
const MAX_ENTRIES: usize = 4;

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
    /// The surfaces each clear point has gone through but not yet deep beyond (at most
    /// `MAX_ENTRIES`, the latest kept).
    entries: Vec<Vec<Entry>>,
    /// How far beyond a crossed surface a point must go to count: less is a part closing onto
    /// another (a lid on its box, a screen on its keyboard), which real limits are. A fraction
    /// of the moving group's own size, as a limit set a degree or two long sinks a part's far
    /// end by its length times that angle, whatever the object around it.
    through_depth_m: f64,
    /// How near another part a moving point at rest is in contact with it, metres; a crossing
    /// must lie this far inside the crossed surface's outline.
    contact_m: f64,
    /// The points move along straight lines (a slide), so the crossed plane measures how far
    /// one went past a surface; a turning point curves away from it, and its depth is also at
    /// most its distance to the crossed part (a knob's edge following the collar it overlaps).
    straight: bool,
    /// How many clear points have crossed.
    pub(crate) crossed_count: usize,
    /// Still parts the moving group can reach, and how many points crossed each.
    near: Vec<(usize, usize)>,
    /// For each clear point and near part (by point, then part): how far the point may still
    /// travel before it could reach that part's surface, metres (its distance there when last
    /// measured, less the path travelled since). A step shorter than that crosses nothing, so
    /// no ray is cast for it.
    slack_m: Vec<f64>,
    /// The same with every point at rest.
    rest_slack_m: Vec<f64>,
    /// For each clear point and near part: steps left to cast without measuring the distance,
    /// and how many to wait after the next measurement that finds the point within two steps of
    /// the surface (a point sliding along or through a surface would be measured every step for
    /// no slack; the wait doubles while that lasts).
    unmeasured: Vec<(u8, u8)>,
    /// Distances are measured this far; a point farther away has this much slack.
    slack_reach_m: f64,
    /// A step must be this much shorter than the slack to skip its ray (f32 rounding of the
    /// surfaces and rays).
    slack_margin_m: f64,
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
        let through_depth_m = params.rest_contact_part_fraction * bounds.diagonal();
        let contact_m = rest_contact_m(params, bounds.diagonal(), scene.diagonal_m);
        let slack_reach_m = (SLACK_REACH_FRACTION * bounds.diagonal()).max(2.0 * contact_m);
        let mut rest_slack_m = Vec::new();
        let mut clear = Vec::new();
        for (i, point) in moving_points.iter().enumerate() {
            let distances = near.iter().map(|&(p, _)| {
                scene
                    .surfaces
                    .distance_within_m(p, *point, slack_reach_m)
                    .unwrap_or(slack_reach_m)
            });
            let start = rest_slack_m.len();
            rest_slack_m.extend(distances);
            if rest_slack_m[start..].iter().all(|&d| d > contact_m) {
                clear.push(i);
            } else {
                rest_slack_m.truncate(start);
            }
        }
        let area_m2: f64 = moving.iter().map(|&p| scene.areas_m2[p]).sum();
        let spacing_m = (area_m2 / moving_points.len().max(1) as f64).sqrt();
        Self {
            previous: clear.iter().map(|&i| moving_points[i]).collect(),
            crossed: vec![false; clear.len()],
            entries: vec![Vec::new(); clear.len()],
            through_depth_m,
            contact_m,
            straight: motion.kind == JointKind::Prismatic,
            rest_space_depth_m: (params.short_slide_fraction * scene.diagonal_m)
                .max(through_depth_m),
            clear,
            crossed_count: 0,
            near,
            slack_m: rest_slack_m.clone(),
            unmeasured: vec![(0, 0); rest_slack_m.len()],
            rest_slack_m,
            slack_reach_m,
            slack_margin_m: SLACK_MARGIN_FRACTION * scene.diagonal_m,
            occupancy: KdTree::new(moving_points.to_vec()),
            occupancy_radius_m: spacing_m,
        }
    }

    /// Moves the points to `moved` (all moving points, in their original order) and records the
    /// crossings on the way from their previous positions. A point that went through a surface,
    /// at least the contact distance inside its outline, counts once it is deeper than
    /// `through_depth_m` beyond the crossed triangle's plane, or, where it went through inside
    /// the space the group filled at rest (a button pressed into its face, a wheel in its fork),
    /// deeper than a short slide's travel (a door turned into its cabinet through the face it
    /// rested on). Depth is measured across the crossed plane: a point sliding along a surface
    /// it touches (a drawer's side along a leg flush with it) and then past that surface's edge
    /// has gone through nothing. A slide's depth is not bounded by the distance to the nearest
    /// surface (a drawer pushed sideways into the edge of a thin rail travels inside the rail,
    /// never far from its faces); a turning point's is. A point that comes back through a plane
    /// it entered is out again. A step's ray is cast only where the step is at least the point's
    /// slack to that part: a shorter one cannot reach its surface.
    pub(crate) fn advance(&mut self, scene: &Scene, moved: &[DVec3]) {
        for (k, &i) in self.clear.iter().enumerate() {
            let to = moved[i];
            if !self.crossed[k] {
                let from = self.previous[k];
                let travel_m = (to - from).length();
                let entries = &mut self.entries[k];
                let row = k * self.near.len()..(k + 1) * self.near.len();
                let slacks = self.slack_m[row.clone()]
                    .iter_mut()
                    .zip(&mut self.unmeasured[row]);
                for (&(part, _), (slack_m, (left, wait))) in self.near.iter().zip(slacks) {
                    if *slack_m - travel_m > self.slack_margin_m {
                        *slack_m -= travel_m;
                        continue;
                    }
                    if *left > 0 {
                        *left -= 1;
                        *slack_m = 0.0;
                    } else {
                        *slack_m = scene
                            .surfaces
                            .distance_within_m(part, to, self.slack_reach_m)
                            .unwrap_or(self.slack_reach_m);
                        *wait = if *slack_m > 2.0 * travel_m {
                            0
                        } else {
                            wait.saturating_mul(2)
                                .saturating_add(1)
                                .min(MAX_UNMEASURED_STEPS)
                        };
                        *left = *wait;
                    }
                    let Some(mut entry) = scene.surfaces.crossing(part, from, to) else {
                        continue;
                    };
                    if !inside_outline(scene, &entry, from, to, self.contact_m) {
                        continue;
                    }
                    if let Some(back) = entries.iter().position(|e| {
                        e.part == part
                            && e.depth_beyond_m(from) > 0.0
                            && e.depth_beyond_m(to) <= 0.0
                    }) {
                        entries.remove(back);
                        continue;
                    }
                    entry.in_rest_space = self
                        .occupancy
                        .nearest_distance_within(entry.point, self.occupancy_radius_m)
                        .is_some();
                    if entries.len() == MAX_ENTRIES {
                        entries.remove(0);
                    }
                    entries.push(entry);
                }
                let through = entries.iter().find(|e| {
                    let depth_m = if e.in_rest_space {
                        self.rest_space_depth_m
                    } else {
                        self.through_depth_m
                    };
                    e.depth_beyond_m(to) > depth_m
                        && (self.straight || scene.surfaces.distance_m(e.part, to) > depth_m)
                });
                if let Some(part) = through.map(|e| e.part) {
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
            self.entries[k].clear();
        }
        self.slack_m.copy_from_slice(&self.rest_slack_m);
        self.unmeasured.fill((0, 0));
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
    fn the_nearest_distance_of_many_points_is_the_least_of_their_distances() {
        // A folded sheet (two quads at a right angle) and points around it on a spiral.
        let sheet = TriMesh::new(
            vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(1.0, 0.0, 1.0),
                DVec3::new(1.0, 1.0, 1.0),
            ],
            vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]],
        )
        .expect("sheet");
        let s = Surfaces::new(&[sheet], DVec3::new(0.5, 0.5, 0.0));
        let points: Vec<DVec3> = (0..200)
            .map(|i| {
                let t = f64::from(i) * 0.1;
                DVec3::new(0.5 + 0.8 * t.cos(), 0.5 + 0.8 * t.sin(), 0.3 + 0.02 * t)
            })
            .collect();
        let least = points
            .iter()
            .map(|p| s.distance_m(0, *p))
            .fold(f64::INFINITY, f64::min);
        assert!(least > 0.0 && least < 0.5, "{least}");
        assert_eq!(s.nearest_distance_m(0, points.iter().copied()), least);
        assert_eq!(s.nearest_distance_m(0, points.iter().rev().copied()), least);
        assert_eq!(s.nearest_distance_m(0, []), f64::INFINITY);
        assert_eq!(
            s.nearest_distance_m(1, points.iter().copied()),
            f64::INFINITY
        );
    }

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
        assert!(
            (hit.point - DVec3::new(0.3, 0.2, 0.0)).length() < 1e-5,
            "{hit:?}"
        );
        // The normal is turned the way the point went: it is 0.4 beyond the plane at z = -0.4.
        assert!((hit.depth_beyond_m(DVec3::new(0.0, 0.0, -0.4)) - 0.4).abs() < 1e-5);
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
