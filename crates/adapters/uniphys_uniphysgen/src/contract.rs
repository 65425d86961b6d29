//! Serde types of the model-server contract `proto/uniphysgen/v1` (see its README and
//! `openapi.yaml`). Units are the model's: degrees, the [0, 2] model frame, g/cm^3, GPa, HV,
//! cm, kg. Restoration to SI and the object frame is in [`crate::restore`].

use serde::{Deserialize, Serialize};

use crate::FeatureRow;

/// Path of the prediction endpoint, relative to the server's base URL.
pub const PREDICT_PATH: &str = "/v1/predict";

/// What to predict. Each task is one released checkpoint on the server.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Task {
    /// Per-part material and physical properties (`UniPhysGen-1.7B-Physics`).
    Physics,
    /// Per-part motion type, axis, pivot and range (`UniPhysGen-1.7B-Kinematics`).
    Kinematics,
    /// Per-part group of parts that move together (`UniPhysGen-1.7B-Structure`).
    Structure,
    /// Object name, category, dimensions and mass (`UniPhysGen-1.7B-Object`).
    ObjectLevel,
}

impl Task {
    /// The name on the wire: `physics`, `kinematics`, `structure`, `object_level`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Physics => "physics",
            Self::Kinematics => "kinematics",
            Self::Structure => "structure",
            Self::ObjectLevel => "object_level",
        }
    }

    /// Whether the task answers per part (every task but `object_level`).
    #[must_use]
    pub fn is_per_part(self) -> bool {
        !matches!(self, Self::ObjectLevel)
    }
}

impl std::fmt::Display for Task {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Feature rows of one point cloud, `[grid(3), coord(3), color(3), normal(3)]` each.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CloudInput {
    /// One row per voxel-sampled point.
    pub features: Vec<FeatureRow>,
}

/// One part of a request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartInput {
    /// Part id (decimal index in the asset).
    pub id: String,
    /// Feature rows of the part's cloud, in the same frame and grid as the object's.
    pub features: Vec<FeatureRow>,
    /// Part centre in the model frame, rounded to 4 decimals (the `structure` task's part list).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
}

/// `POST /v1/predict` body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PredictRequest {
    /// What to predict.
    pub task: Task,
    /// Caller's id of the asset, echoed back and used in errors.
    pub sample_id: String,
    /// Voxels per axis the features were sampled with.
    pub num_bins: u32,
    /// The object's cloud.
    pub object: CloudInput,
    /// The parts to answer for (empty for `object_level`).
    #[serde(default)]
    pub parts: Vec<PartInput>,
    /// Every part of the object with its position (the `structure` task's part list, which may
    /// name parts that are not in this request's batch); empty for other tasks.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub part_list: Vec<PartPosition>,
}

/// A part of the object and its centre, for the structure task's part list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartPosition {
    /// Part id.
    pub id: String,
    /// Centre in the model frame, rounded to 4 decimals.
    pub position: [f64; 3],
}

/// An axis as the model gives it: spherical angles in degrees or a 3-vector.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum AxisAnswer {
    /// Polar angle from +z and azimuth from +x, degrees.
    Spherical {
        /// Polar angle from +z, degrees in [0, 180].
        theta: f64,
        /// Azimuth from +x towards +y, degrees in [0, 360).
        phi: f64,
    },
    /// A direction vector (any length but zero).
    Vector([f64; 3]),
}

/// The physics checkpoint's `physical_properties`, in the model's units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhysicsAnswer {
    /// `category` or `category/subtype`, e.g. `wood/oak`.
    pub material: String,
    /// Density, g/cm^3.
    pub density: f64,
    /// Young's modulus, GPa.
    pub young: f64,
    /// Vickers hardness, HV.
    pub hardness: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Friction coefficient.
    pub friction: f64,
    /// Affordance rank 1..10, if given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub affordance: Option<u8>,
    /// Whether a hand would grasp the part, if given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub graspable: Option<bool>,
}

/// The answer for one part. Which fields are present depends on the task: `physical_properties`
/// (physics); `motion_type`, `axis`, `pivot`, `range` (kinematics); `members` (structure).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PartAnswer {
    /// The part id of the request.
    pub id: String,
    /// Physics answer.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub physical_properties: Option<PhysicsAnswer>,
    /// `"B"` (prismatic), `"C"` (revolute) or null (does not move).
    #[serde(default)]
    pub motion_type: Option<String>,
    /// Motion axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<AxisAnswer>,
    /// A point on the axis, model frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pivot: Option<[f64; 3]>,
    /// `[min, max]`: revolute as a fraction of 2*pi, prismatic in model units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f64; 2]>,
    /// Ids of the parts that move with this one (structure).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub members: Option<Vec<String>>,
}

/// The object-level checkpoint's answer, in the model's units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectAnswer {
    /// Object name, e.g. `cabinet`.
    pub object_name: String,
    /// Category, e.g. `Furniture/Cabinet`.
    pub category: String,
    /// Dimensions `[L, W, H]`, cm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dimension: Option<[f64; 3]>,
    /// Volume, cm^3 (servers may send it instead of `dimension`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<f64>,
    /// Mass, kg.
    pub mass: f64,
}

/// `POST /v1/predict` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PredictResponse {
    /// The request's sample id.
    pub sample_id: String,
    /// The request's task.
    pub task: Task,
    /// Checkpoint that answered, e.g. `breezexian/UniPhysGen-1.7B-Kinematics`.
    pub model: String,
    /// One answer per requested part (per-part tasks).
    #[serde(default)]
    pub parts: Vec<PartAnswer>,
    /// The object answer (`object_level`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<ObjectAnswer>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn request_serialises_with_the_contract_keys() {
        let request = PredictRequest {
            task: Task::ObjectLevel,
            sample_id: "s1".to_owned(),
            num_bins: 256,
            object: CloudInput {
                features: vec![[0.0; 12]],
            },
            parts: vec![PartInput {
                id: "3".to_owned(),
                features: Vec::new(),
                position: None,
            }],
            part_list: Vec::new(),
        };
        let json = serde_json::to_value(&request).unwrap();
        assert_eq!(json["task"], "object_level");
        assert_eq!(json["object"]["features"][0].as_array().unwrap().len(), 12);
        assert_eq!(json["parts"][0]["id"], "3");
        assert!(json["parts"][0].get("position").is_none());
    }

    #[test]
    fn kinematics_answer_reads_spherical_or_vector_axis_and_null_motion() {
        let text = r#"{"sample_id":"s","task":"kinematics","model":"m","parts":[
            {"id":"1","motion_type":"C","axis":{"theta":90,"phi":0},"pivot":[1,1,1],"range":[0,0.25]},
            {"id":"2","motion_type":null},
            {"id":"3","motion_type":"B","axis":[0,0,2],"range":[0,0.5]}]}"#;
        let response: PredictResponse = serde_json::from_str(text).unwrap();
        assert_eq!(
            response.parts[0].axis,
            Some(AxisAnswer::Spherical {
                theta: 90.0,
                phi: 0.0
            })
        );
        assert_eq!(response.parts[1].motion_type, None);
        assert_eq!(
            response.parts[2].axis,
            Some(AxisAnswer::Vector([0.0, 0.0, 2.0]))
        );
    }
}
