//! How an input is interpreted (units, up axis) and the resource limits applied while reading it.

use uniphys_types::UpAxis;

use crate::{AssetRotation, IngestError, IngestResult};

/// Options of [`crate::load_asset`].
#[derive(Debug, Clone, PartialEq)]
pub struct IngestOptions {
    /// Up axis of the input; `None` uses the format's convention (glTF and OBJ: Y, PLY, STL and
    /// URDF: Z).
    pub up_axis: Option<UpAxis>,
    /// Metres per input unit (1.0 for metres, 0.001 for millimetres). Must be finite and positive.
    pub metres_per_unit: f64,
    /// Largest number of triangles accepted; larger inputs are rejected before being read fully
    /// where the format declares its size.
    pub max_triangles: usize,
    /// Largest size of any single file read (the input and every file it references), in bytes.
    pub max_file_bytes: u64,
    /// Drop the joints an articulated input (URDF) declares, keeping its parts and their names,
    /// so that the grounder has to infer the articulation (benchmarks of the grounder).
    pub ignore_joints: bool,
    /// A rotation of the whole asset (meshes and joints), applied right after the unit and
    /// up-axis conversion (tests that grounding does not depend on an upright pose).
    pub rotation: Option<AssetRotation>,
}

impl Default for IngestOptions {
    fn default() -> Self {
        Self {
            up_axis: None,
            metres_per_unit: 1.0,
            max_triangles: 2_000_000,
            max_file_bytes: 1 << 30,
            ignore_joints: false,
            rotation: None,
        }
    }
}

impl IngestOptions {
    /// What these options change in the asset beyond units and up axis (ignored joints, a
    /// rotation), one sentence each, for the notes of a run; empty for plain ingest.
    #[must_use]
    pub fn transform_notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        if self.ignore_joints {
            notes.push(
                "ingest ignored the joints declared by the input (parts and names kept): the articulation is inferred"
                    .to_owned(),
            );
        }
        if let Some(rotation) = &self.rotation {
            notes.push(format!("ingest: {}", rotation.describe()));
        }
        notes
    }

    /// Checks that the options are usable.
    pub fn validate(&self) -> IngestResult<()> {
        if !(self.metres_per_unit.is_finite() && self.metres_per_unit > 0.0) {
            return Err(IngestError::InvalidOption {
                option: "metres_per_unit",
                value: self.metres_per_unit.to_string(),
                expected: "finite and greater than 0 (1.0 for metres, 0.001 for millimetres)",
            });
        }
        if self.max_triangles == 0 {
            return Err(IngestError::InvalidOption {
                option: "max_triangles",
                value: "0".to_owned(),
                expected: "at least 1",
            });
        }
        if let Some(rotation) = &self.rotation {
            let q = rotation.rotated_from_input;
            if !(q.is_finite() && (q.length() - 1.0).abs() < 1e-9) {
                return Err(IngestError::InvalidOption {
                    option: "rotation",
                    value: format!("{q}"),
                    expected: "a finite unit quaternion",
                });
            }
        }
        if self.max_file_bytes == 0 {
            return Err(IngestError::InvalidOption {
                option: "max_file_bytes",
                value: "0".to_owned(),
                expected: "at least 1",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_metres_with_format_up_axis_and_documented_limits() {
        let o = IngestOptions::default();
        assert_eq!(o.up_axis, None);
        assert!((o.metres_per_unit - 1.0).abs() < f64::EPSILON);
        assert_eq!(o.max_triangles, 2_000_000);
        assert_eq!(o.max_file_bytes, 1024 * 1024 * 1024);
        assert!(!o.ignore_joints && o.rotation.is_none());
        assert!(o.transform_notes().is_empty());
        assert!(o.validate().is_ok());
    }

    #[test]
    fn non_positive_or_nan_unit_scale_is_rejected() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let o = IngestOptions {
                metres_per_unit: bad,
                ..IngestOptions::default()
            };
            let err = o.validate().expect_err("bad scale accepted");
            assert!(err.to_string().contains("metres_per_unit"), "{err}");
        }
    }

    #[test]
    fn transform_notes_name_ignored_joints_and_the_rotation_seed() {
        let o = IngestOptions {
            ignore_joints: true,
            rotation: Some(AssetRotation::from_seed(3)),
            ..IngestOptions::default()
        };
        let notes = o.transform_notes();
        assert_eq!(notes.len(), 2);
        assert!(notes[0].contains("ignored the joints"), "{notes:?}");
        assert!(notes[1].contains("seed 3"), "{notes:?}");
    }
}
