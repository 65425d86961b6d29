//! Geometry checks shared by the integration tests: surface samples, point-in-solid by winding
//! number, and point-to-mesh distance.

use uniphys_geometry::{DVec3, TriMesh};

/// Points strictly inside each triangle on a grid of spacing about `spacing`, each moved `depth`
/// against the face normal (into the solid); `depth = 0` keeps them on the surface.
pub fn surface_samples(mesh: &TriMesh, spacing: f64, depth: f64) -> Vec<DVec3> {
    let mut points = Vec::new();
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.corners(t);
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let n = ((longest / spacing).ceil() as usize).clamp(1, 200);
        let inward = -mesh.face_normal(t) * depth;
        for i in 0..n {
            for j in 0..(n - i) {
                let u = (i as f64 + 1.0 / 3.0) / n as f64;
                let v = (j as f64 + 1.0 / 3.0) / n as f64;
                points.push(a + (b - a) * u + (c - a) * v + inward);
            }
        }
    }
    points
}

/// Generalised winding number of `p` with respect to a closed mesh: about 1 inside, 0 outside.
pub fn winding_number(mesh: &TriMesh, p: DVec3) -> f64 {
    let mut total = 0.0;
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.corners(t).map(|q| q - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let numerator = a.dot(b.cross(c));
        let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * numerator.atan2(denominator);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// Distance from `p` to the closest point of triangle `abc` (Ericson, Real-Time Collision
/// Detection, 5.1.5).
pub fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

/// Smallest distance from any of `points` to `mesh`.
pub fn distance_to_mesh(points: &[DVec3], mesh: &TriMesh) -> f64 {
    let mut best = f64::INFINITY;
    for &p in points {
        for t in 0..mesh.triangle_count() {
            let [a, b, c] = mesh.corners(t);
            best = best.min(point_triangle_distance(p, a, b, c));
        }
    }
    best
}

/// An upper bound of the distance between two meshes, from their vertices and surface samples.
pub fn mesh_distance(a: &TriMesh, b: &TriMesh) -> f64 {
    let probe = |m: &TriMesh| {
        let mut points = m.positions.clone();
        points.extend(surface_samples(m, 0.02, 0.0));
        points
    };
    distance_to_mesh(&probe(a), b).min(distance_to_mesh(&probe(b), a))
}
