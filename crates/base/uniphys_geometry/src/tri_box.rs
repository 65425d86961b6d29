use glam::DVec3;

/// Whether a triangle and an axis-aligned box overlap (touching counts), by the separating axis
/// theorem: the 3 box axes, the triangle normal and the 9 edge-axis cross products
/// (Akenine-Moeller 2001).
pub(crate) fn triangle_overlaps_box(tri: &[DVec3; 3], centre: DVec3, half: DVec3) -> bool {
    let v = [tri[0] - centre, tri[1] - centre, tri[2] - centre];
    // Box face normals: the triangle's bounds against the box.
    for axis in 0..3 {
        let lo = v[0][axis].min(v[1][axis]).min(v[2][axis]);
        let hi = v[0][axis].max(v[1][axis]).max(v[2][axis]);
        if lo > half[axis] || hi < -half[axis] {
            return false;
        }
    }
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    // Triangle plane against the box.
    let normal = edges[0].cross(edges[1]);
    if normal.dot(v[0]).abs() > half.dot(normal.abs()) {
        return false;
    }
    // Cross products of the edges with the box axes.
    for edge in edges {
        for unit in [DVec3::X, DVec3::Y, DVec3::Z] {
            let axis = unit.cross(edge);
            let (p0, p1, p2) = (axis.dot(v[0]), axis.dot(v[1]), axis.dot(v[2]));
            let radius = half.dot(axis.abs());
            if p0.min(p1).min(p2) > radius || p0.max(p1).max(p2) < -radius {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    const HALF: DVec3 = DVec3::splat(0.5);

    #[test]
    fn triangle_through_the_box_overlaps() {
        let tri = [
            DVec3::new(-2.0, -2.0, 0.1),
            DVec3::new(2.0, -2.0, 0.1),
            DVec3::new(0.0, 2.0, 0.1),
        ];
        assert!(triangle_overlaps_box(&tri, DVec3::ZERO, HALF));
    }

    #[test]
    fn triangle_beside_the_box_is_separated_by_a_face_axis() {
        let tri = [
            DVec3::new(0.6, -2.0, 0.0),
            DVec3::new(2.0, -2.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
        ];
        assert!(!triangle_overlaps_box(&tri, DVec3::ZERO, HALF));
    }

    #[test]
    fn tilted_plane_missing_the_corner_is_separated_by_the_normal() {
        // Plane x + y + z = 1.6 passes outside the corner (0.5, 0.5, 0.5) (sum 1.5), although
        // the triangle's bounds overlap the box.
        let tri = [
            DVec3::new(1.6, 0.0, 0.0),
            DVec3::new(0.0, 1.6, 0.0),
            DVec3::new(0.0, 0.0, 1.6),
        ];
        assert!(!triangle_overlaps_box(&tri, DVec3::ZERO, HALF));
        let closer = tri.map(|p| p * (1.4 / 1.6));
        assert!(triangle_overlaps_box(&closer, DVec3::ZERO, HALF));
    }

    #[test]
    fn triangle_near_an_edge_is_separated_by_an_edge_cross_axis() {
        // Bounds overlap; plane 6x + 6y - 3.36z = 7.2 cuts the box (max 7.68 at (.5, .5, -.5));
        // but x + y >= 1.2 on the whole triangle while the box reaches 1.0: only the axis
        // z x (p1 - p0) separates them.
        let tri = [
            DVec3::new(1.2, 0.0, 0.0),
            DVec3::new(0.0, 1.2, 0.0),
            DVec3::new(2.0, 2.0, 5.0),
        ];
        assert!(!triangle_overlaps_box(&tri, DVec3::ZERO, HALF));
        // Grown to half 0.61 the box contains (0.6, 0.6, 0), a point of the triangle.
        assert!(triangle_overlaps_box(&tri, DVec3::ZERO, DVec3::splat(0.61)));
    }

    #[test]
    fn touching_face_counts_as_overlap() {
        let tri = [
            DVec3::new(-1.0, -1.0, 0.5),
            DVec3::new(1.0, -1.0, 0.5),
            DVec3::new(0.0, 1.0, 0.5),
        ];
        assert!(triangle_overlaps_box(&tri, DVec3::ZERO, HALF));
    }
}
