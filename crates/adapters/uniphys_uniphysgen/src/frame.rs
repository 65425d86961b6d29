use serde::{Deserialize, Serialize};
use uniphys_geometry::{Aabb, DVec3};

use crate::PointCloud;

/// Added to the scale before dividing, as the reference does (`scale + 1e-12`).
pub const SCALE_EPSILON: f64 = 1e-12;

/// The map between the source frame (the frame the clouds were sampled in: the object frame,
/// metres) and UniPhysGen's model frame ("AABB-normalised and shifted to [0, 2]").
///
/// `model = (source - center) / (scale + 1e-12) - min_bound` and
/// `source = (model + min_bound) * scale + center` (reference 14.3). Uniform scale plus
/// translation: directions are the same in both frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoordinateFrame {
    /// Centre of the object's AABB, source frame.
    pub center_in_source_m: DVec3,
    /// Largest half-extent of the object's AABB, metres per model unit (1.0 if below 1e-12).
    pub scale_m: f64,
    /// Joint minimum of the centred, scaled object and part points, model units.
    pub min_bound: DVec3,
}

impl CoordinateFrame {
    /// The frame of an object cloud and the part clouds sent with it: object AABB centre and
    /// half-extent scale, shifted by the minimum over the object and every part given.
    ///
    /// With one part this is exactly the reference; with several (a batched request, or the
    /// whole asset) the shift is the minimum over all of them, so every part in the batch shares
    /// one frame. With no part (the `object_level` task) the shift is the object's minimum.
    #[must_use]
    pub fn from_clouds(object: &PointCloud, parts: &[&PointCloud]) -> Self {
        let frame = Self::from_object_bounds(Aabb::from_points(&object.points));
        let min_bound = std::iter::once(object)
            .chain(parts.iter().copied())
            .flat_map(|c| c.points.iter())
            .map(|p| (*p - frame.center_in_source_m) / (frame.scale_m + SCALE_EPSILON))
            .reduce(DVec3::min)
            .unwrap_or(DVec3::ZERO);
        Self { min_bound, ..frame }
    }

    /// The frame of an object given by its AABB alone (the `object_level` task, or a part that
    /// lies inside the object): AABB centre, largest half-extent as scale (1.0 below 1e-12),
    /// shifted by the AABB's minimum corner so that the object spans `[0, 2]` along its longest
    /// side. An empty AABB gives the identity-like frame (centre 0, scale 1, no shift).
    #[must_use]
    pub fn from_object_bounds(bounds: Aabb) -> Self {
        if bounds.is_empty() {
            return Self {
                center_in_source_m: DVec3::ZERO,
                scale_m: 1.0,
                min_bound: DVec3::ZERO,
            };
        }
        let half = (bounds.max - bounds.min) / 2.0;
        let largest = half.max_element();
        let scale = if largest < 1e-12 { 1.0 } else { largest };
        let center = (bounds.max + bounds.min) / 2.0;
        Self {
            center_in_source_m: center,
            scale_m: scale,
            min_bound: (bounds.min - center) / (scale + SCALE_EPSILON),
        }
    }

    /// A source-frame point in the model frame: `(p - center) / (scale + 1e-12) - min_bound`.
    #[must_use]
    pub fn point_source_to_model(&self, point_in_source_m: DVec3) -> DVec3 {
        (point_in_source_m - self.center_in_source_m) / (self.scale_m + SCALE_EPSILON)
            - self.min_bound
    }

    /// A model-frame point in the source frame: `(p + min_bound) * scale + center`.
    #[must_use]
    pub fn point_model_to_source(&self, point_in_model: DVec3) -> DVec3 {
        (point_in_model + self.min_bound) * self.scale_m + self.center_in_source_m
    }

    /// A source-frame distance (metres) in model units: `distance / scale`.
    #[must_use]
    pub fn distance_source_to_model(&self, distance_m: f64) -> f64 {
        distance_m / self.scale_m
    }

    /// A model-frame distance in metres: `distance * scale`.
    #[must_use]
    pub fn distance_model_to_source(&self, distance_in_model: f64) -> f64 {
        distance_in_model * self.scale_m
    }

    /// The reference's `coordinate_frame` record.
    #[must_use]
    pub fn to_json(&self) -> CoordinateFrameJson {
        CoordinateFrameJson {
            name: "source_to_aabb_0_2".to_owned(),
            source_frame: "raw_annotation".to_owned(),
            model_frame: "aabb_normalized_shifted".to_owned(),
            center: self.center_in_source_m.to_array(),
            scale: self.scale_m,
            min_bound: self.min_bound.to_array(),
            shift: (-self.min_bound).to_array(),
            point_source_to_model: "(point - center) / scale - min_bound".to_owned(),
            point_model_to_source: "(point + min_bound) * scale + center".to_owned(),
            distance_source_to_model: "distance / scale".to_owned(),
            distance_model_to_source: "distance * scale".to_owned(),
        }
    }

    /// The frame of a `coordinate_frame` record (only `center`, `scale` and `min_bound` are
    /// read).
    #[must_use]
    pub fn from_json(json: &CoordinateFrameJson) -> Self {
        Self {
            center_in_source_m: DVec3::from_array(json.center),
            scale_m: json.scale,
            min_bound: DVec3::from_array(json.min_bound),
        }
    }
}

/// The reference's `coordinate_frame` JSON (reference 14.3 step 5), key for key. The source
/// frame here is the object frame in metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoordinateFrameJson {
    /// `"source_to_aabb_0_2"`.
    pub name: String,
    /// `"raw_annotation"`.
    pub source_frame: String,
    /// `"aabb_normalized_shifted"`.
    pub model_frame: String,
    /// AABB centre, source frame.
    pub center: [f64; 3],
    /// Largest AABB half-extent.
    pub scale: f64,
    /// Shift subtracted after scaling.
    pub min_bound: [f64; 3],
    /// `-min_bound`.
    pub shift: [f64; 3],
    /// The forward formula, as text.
    pub point_source_to_model: String,
    /// The inverse formula, as text.
    pub point_model_to_source: String,
    /// Distance forward, as text.
    pub distance_source_to_model: String,
    /// Distance inverse, as text.
    pub distance_model_to_source: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(points: &[[f64; 3]]) -> PointCloud {
        PointCloud {
            points: points.iter().map(|&p| DVec3::from_array(p)).collect(),
            colors_rgb8: vec![[0; 3]; points.len()],
            normals: vec![DVec3::Z; points.len()],
        }
    }

    #[test]
    fn frame_of_a_box_matches_hand_computed_center_scale_and_shift() {
        // Object AABB [0,4] x [0,2] x [0,1]: centre (2,1,0.5), half-extents (2,1,0.5), scale 2.
        // Centred and scaled: x in [-1,1], y in [-0.5,0.5], z in [-0.25,0.25].
        let object = cloud(&[[0.0, 0.0, 0.0], [4.0, 2.0, 1.0]]);
        let frame = CoordinateFrame::from_clouds(&object, &[]);
        assert_eq!(frame.center_in_source_m, DVec3::new(2.0, 1.0, 0.5));
        assert_eq!(frame.scale_m, 2.0);
        // (Dividing by scale + 1e-12 moves values by about 1e-12.)
        assert!((frame.min_bound - DVec3::new(-1.0, -0.5, -0.25)).length() < 1e-9);
        // The far corner maps to (2, 1, 0.5).
        let far = frame.point_source_to_model(DVec3::new(4.0, 2.0, 1.0));
        assert!((far - DVec3::new(2.0, 1.0, 0.5)).length() < 1e-9, "{far}");
    }

    #[test]
    fn a_part_below_the_object_lowers_the_shared_minimum() {
        // Part point at x = -2 (model x = (-2 - 2)/2 = -2) extends the minimum past the object's -1.
        let object = cloud(&[[0.0, 0.0, 0.0], [4.0, 2.0, 1.0]]);
        let part = cloud(&[[-2.0, 1.0, 0.5]]);
        let frame = CoordinateFrame::from_clouds(&object, &[&part]);
        assert!((frame.min_bound.x + 2.0).abs() < 1e-9);
        assert!((frame.point_source_to_model(DVec3::new(-2.0, 1.0, 0.5)).x).abs() < 1e-12);
    }

    #[test]
    fn frame_from_bounds_equals_frame_from_the_corner_cloud() {
        let object = cloud(&[[0.0, 0.0, 0.0], [4.0, 2.0, 1.0]]);
        let bounds = Aabb::from_points(&object.points);
        assert_eq!(
            CoordinateFrame::from_object_bounds(bounds),
            CoordinateFrame::from_clouds(&object, &[])
        );
        let empty = CoordinateFrame::from_object_bounds(Aabb::EMPTY);
        assert_eq!((empty.scale_m, empty.min_bound), (1.0, DVec3::ZERO));
    }

    #[test]
    fn a_point_object_uses_scale_one() {
        let object = cloud(&[[3.0, 3.0, 3.0]]);
        let frame = CoordinateFrame::from_clouds(&object, &[]);
        assert_eq!(frame.scale_m, 1.0);
        assert_eq!(frame.min_bound, DVec3::ZERO);
    }

    #[test]
    fn source_to_model_to_source_round_trips_points_and_distances() {
        let object = cloud(&[[-0.3, 0.1, 0.0], [0.5, 0.9, 1.7]]);
        let frame = CoordinateFrame::from_clouds(&object, &[]);
        for p in [[0.1, 0.2, 0.3], [-0.3, 0.1, 0.0], [12.0, -4.0, 7.5]] {
            let p = DVec3::from_array(p);
            let back = frame.point_model_to_source(frame.point_source_to_model(p));
            assert!(
                (back - p).length() <= 1e-6 * p.length().max(1.0),
                "{p} -> {back}"
            );
        }
        let d = frame.distance_model_to_source(frame.distance_source_to_model(0.37));
        assert!((d - 0.37).abs() < 1e-12);
        assert!((frame.distance_source_to_model(1.7) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn json_record_has_the_reference_shape_and_reads_back() {
        let object = cloud(&[[0.0, 0.0, 0.0], [4.0, 2.0, 1.0]]);
        let frame = CoordinateFrame::from_clouds(&object, &[]);
        let json = serde_json::to_value(frame.to_json()).unwrap();
        assert_eq!(json["name"], "source_to_aabb_0_2");
        assert_eq!(json["model_frame"], "aabb_normalized_shifted");
        assert_eq!(json["scale"], 2.0);
        assert!((json["shift"][0].as_f64().unwrap() - 1.0).abs() < 1e-9);
        assert_eq!(
            json["point_model_to_source"],
            "(point + min_bound) * scale + center"
        );
        let back: CoordinateFrameJson = serde_json::from_value(json).unwrap();
        assert_eq!(CoordinateFrame::from_json(&back), frame);
    }
}
