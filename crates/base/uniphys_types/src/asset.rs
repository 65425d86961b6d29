use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use crate::{Estimate, Joint, ObjectProperties, PartId, PartProperties, TypesError, TypesResult};

/// Version of the [`AssetRecord`] schema. Bump it on any incompatible change.
pub const SCHEMA_VERSION: u32 = 1;

/// File format of an input asset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SourceFormat {
    /// Binary glTF.
    Glb,
    /// JSON glTF with embedded or external buffers.
    Gltf,
    /// Wavefront OBJ (with optional MTL).
    Obj,
    /// Stanford PLY.
    Ply,
    /// STL, ASCII or binary.
    Stl,
    /// A URDF with meshes (PartNet-Mobility style): an already-articulated input.
    Urdf,
}

impl SourceFormat {
    /// Every format, in declaration order.
    pub const ALL: [Self; 6] = [
        Self::Glb,
        Self::Gltf,
        Self::Obj,
        Self::Ply,
        Self::Stl,
        Self::Urdf,
    ];

    /// The file extension that names the format: lowercase, without the dot.
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            Self::Glb => "glb",
            Self::Gltf => "gltf",
            Self::Obj => "obj",
            Self::Ply => "ply",
            Self::Stl => "stl",
            Self::Urdf => "urdf",
        }
    }

    /// Every format's extension with its dot, comma-separated (`.glb, .gltf, ...`), for
    /// messages that say what may be sent.
    #[must_use]
    pub fn listed_extensions() -> String {
        Self::ALL
            .iter()
            .map(|f| format!(".{}", f.extension()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The format a file extension (without the dot, any case) names, if any.
    #[must_use]
    pub fn from_extension(extension: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(extension))
    }
}

/// Up axis of an input's coordinates; the service always works Z-up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UpAxis {
    /// +Y is up (glTF's convention).
    Y,
    /// +Z is up (URDF's and the service's convention).
    Z,
}

/// Where an asset came from and how its coordinates were interpreted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SourceInfo {
    /// File name of the input (no directories).
    pub file_name: String,
    /// Input format.
    pub format: SourceFormat,
    /// SHA-256 of the input bytes (main file, then referenced files in order), lowercase hex.
    pub content_sha256: String,
    /// Metres per input unit (1.0 for metres, 0.01 for centimetres).
    pub metres_per_unit: f64,
    /// The input's up axis.
    pub up_axis: UpAxis,
}

/// Mass properties of a part, in the object frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartMass {
    /// Volume of the part's material, m^3: its solid, or its walls and what fills them.
    pub volume_m3: f64,
    /// How the volume was computed: `closed_mesh` (exact), `voxels_128` (an open mesh's filled
    /// voxels), `shell_<t>mm` (walls at most t thick) or `shell_<t>mm_fill_<f>` (walls and that
    /// share of what they enclose).
    pub volume_method: String,
    /// Mass, kg.
    pub mass_kg: Estimate<f64>,
    /// Centre of mass in the object frame, metres.
    pub com_in_object_m: [f64; 3],
    /// Inertia tensor about the centre of mass, axes of the object frame, kg m^2 (row-major).
    pub inertia_about_com_kg_m2: [[f64; 3]; 3],
}

/// One part of an asset and everything known about it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartRecord {
    /// Part id.
    pub id: PartId,
    /// Part name (from the input, or assigned).
    pub name: String,
    /// Number of triangles of the part's mesh.
    pub triangle_count: usize,
    /// Axis-aligned bounds in the object frame: `[min, max]`, metres.
    pub bounds_in_object_m: [[f64; 3]; 2],
    /// Physical properties.
    pub properties: PartProperties,
    /// Mass properties.
    pub mass: PartMass,
}

impl PartRecord {
    /// Replaces the part's properties with another grounder's. The part's volume and centre of
    /// mass stay, and so does the rule its mass came from; its mass and inertia follow the new
    /// density.
    pub fn replace_properties(&mut self, properties: PartProperties) {
        let ratio = properties.density_kg_per_m3.value / self.properties.density_kg_per_m3.value;
        self.properties = properties;
        self.mass.mass_kg.value *= ratio;
        for row in &mut self.mass.inertia_about_com_kg_m2 {
            for value in row {
                *value *= ratio;
            }
        }
    }
}

/// An annotated asset: parts, properties, joints. The record every stage reads and extends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AssetRecord {
    /// Schema version, [`SCHEMA_VERSION`] when written by this build.
    pub schema_version: u32,
    /// Asset name (input file stem, sanitised).
    pub name: String,
    /// Input provenance.
    pub source: SourceInfo,
    /// Object-level properties.
    pub object: ObjectProperties,
    /// Parts, sorted by id.
    pub parts: Vec<PartRecord>,
    /// The part fixed to the world (the base of the articulation tree).
    pub root: PartId,
    /// Joints; every part but the root is the child of exactly one joint.
    pub joints: Vec<Joint>,
}

impl AssetRecord {
    /// Returns the part with the given id.
    #[must_use]
    pub fn part(&self, id: PartId) -> Option<&PartRecord> {
        self.parts.iter().find(|p| p.id == id)
    }

    /// Checks the structural invariants: unique ids and joint names, joints reference existing
    /// parts, every non-root part has exactly one parent joint, no cycles, finite unit axes and
    /// ordered limits on revolute/prismatic joints.
    pub fn validate(&self) -> TypesResult<()> {
        let ids: BTreeSet<PartId> = self.parts.iter().map(|p| p.id).collect();
        if ids.len() != self.parts.len() {
            return Err(TypesError::InvalidJointStructure(
                "duplicate part ids".into(),
            ));
        }
        if !ids.contains(&self.root) {
            return Err(TypesError::InvalidJointStructure(format!(
                "root {} is not a part",
                self.root
            )));
        }
        let mut names = BTreeSet::new();
        let mut parent_of: BTreeMap<PartId, PartId> = BTreeMap::new();
        for joint in &self.joints {
            if !names.insert(joint.name.as_str()) {
                return Err(TypesError::InvalidJointStructure(format!(
                    "duplicate joint name {:?}",
                    joint.name
                )));
            }
            for part in [joint.parent, joint.child] {
                if !ids.contains(&part) {
                    return Err(TypesError::UnknownPart {
                        joint: joint.name.clone(),
                        part,
                    });
                }
            }
            if joint.child == self.root {
                return Err(TypesError::InvalidJointStructure(format!(
                    "joint {:?} moves the root",
                    joint.name
                )));
            }
            if parent_of.insert(joint.child, joint.parent).is_some() {
                return Err(TypesError::InvalidJointStructure(format!(
                    "{} has two parent joints",
                    joint.child
                )));
            }
            validate_joint_geometry(joint)?;
        }
        for id in &ids {
            if *id != self.root && !parent_of.contains_key(id) {
                return Err(TypesError::InvalidJointStructure(format!(
                    "{id} is not connected to the root"
                )));
            }
            // Walk to the root; more steps than parts means a cycle.
            let mut cursor = *id;
            for _ in 0..=ids.len() {
                match parent_of.get(&cursor) {
                    Some(p) => cursor = *p,
                    None => break,
                }
            }
            if cursor != self.root {
                return Err(TypesError::InvalidJointStructure(format!(
                    "{id} is in a cycle"
                )));
            }
        }
        Ok(())
    }
}

fn validate_joint_geometry(joint: &Joint) -> TypesResult<()> {
    for value in joint.axis_in_object.iter().chain(&joint.pivot_in_object_m) {
        if !value.is_finite() {
            return Err(TypesError::NotFinite {
                field: "joint axis/pivot",
                value: *value,
            });
        }
    }
    let norm = joint
        .axis_in_object
        .iter()
        .map(|v| v * v)
        .sum::<f64>()
        .sqrt();
    if joint.kind.is_movable() && (norm - 1.0).abs() > 1e-6 {
        return Err(TypesError::OutOfRange {
            field: "joint axis length",
            expected: "1 (unit vector)",
            value: norm,
        });
    }
    if joint.kind.needs_limits() {
        let Some(limits) = joint.limits else {
            return Err(TypesError::InvalidJointStructure(format!(
                "joint {:?} needs limits",
                joint.name
            )));
        };
        if !(limits.lower.is_finite() && limits.upper.is_finite() && limits.lower < limits.upper) {
            return Err(TypesError::OutOfRange {
                field: "joint limits",
                expected: "finite lower < upper",
                value: limits.upper - limits.lower,
            });
        }
    }
    for (field, value) in [
        ("joint damping", joint.damping),
        ("joint friction", joint.friction),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(TypesError::OutOfRange {
                field,
                expected: "[0, inf)",
                value,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::SourceFormat;

    #[test]
    fn every_format_is_named_by_its_extension_in_any_case_and_nothing_else_is() {
        for format in SourceFormat::ALL {
            assert_eq!(
                SourceFormat::from_extension(format.extension()),
                Some(format)
            );
            let upper = format.extension().to_ascii_uppercase();
            assert_eq!(SourceFormat::from_extension(&upper), Some(format));
        }
        for other in ["exe", "zip", "", "gl", "objx"] {
            assert_eq!(SourceFormat::from_extension(other), None, "{other}");
        }
    }
}
