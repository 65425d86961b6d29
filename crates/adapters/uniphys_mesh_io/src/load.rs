//! The entry points: format detection and [`load_asset`], which dispatches to the format readers
//! and brings the result into the service frame (Z up, metres).

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use uniphys_geometry::{DMat4, DVec3, MeshAsset};
use uniphys_types::{SourceFormat, SourceInfo, UpAxis};

use crate::checks::sanitize;
use crate::facts::{InputFacts, input_facts};
use crate::source::Session;
use crate::{IngestError, IngestOptions, IngestResult, gltf, obj, ply, stl, urdf};

/// An ingested asset: parts in the service frame (Z up, metres), and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedAsset {
    /// Parts, materials, textures and (for URDF) joints, in the object frame.
    pub asset: MeshAsset,
    /// Input file name, format, content hash, and the unit and up axis used.
    pub source: SourceInfo,
    /// Zero-area triangles removed from the input (parts made only of them are errors).
    pub dropped_degenerate_triangles: usize,
    /// What was tolerated rather than refused (a missing MTL file: the geometry loads without its
    /// materials), one sentence each.
    pub warnings: Vec<String>,
    /// Whether the coordinates have a known unit, and the object's kind if the input names it.
    pub facts: InputFacts,
}

/// The format of `path` by its extension (`.glb .gltf .obj .ply .stl .urdf`, any case). A
/// directory is a URDF asset (PartNet-Mobility folder) if it holds exactly one `.urdf` file.
pub fn detect_format(path: &Path) -> IngestResult<SourceFormat> {
    if path.is_dir() {
        find_urdf_in(path)?;
        return Ok(SourceFormat::Urdf);
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    SourceFormat::from_extension(&extension).ok_or_else(|| IngestError::UnsupportedFormat {
        path: path.to_path_buf(),
        extension,
    })
}

/// The up axis a format uses when [`IngestOptions::up_axis`] is `None`: Y for glTF/GLB (by the
/// specification) and OBJ (by convention), Z for PLY, STL and URDF.
#[must_use]
pub fn default_up_axis(format: SourceFormat) -> UpAxis {
    match format {
        SourceFormat::Glb | SourceFormat::Gltf | SourceFormat::Obj => UpAxis::Y,
        SourceFormat::Ply | SourceFormat::Stl | SourceFormat::Urdf => UpAxis::Z,
    }
}

/// Reads the asset at `path` (a mesh file, a URDF, or a folder holding one URDF) and returns it
/// in the service frame: scaled by `metres_per_unit`, then rotated from the input's up axis to
/// Z up ((x, y, z) -> (x, -z, y) for Y up), then, if asked, without its declared joints and
/// rotated by [`IngestOptions::rotation`]. Referenced files must lie inside the asset's
/// directory (for URDF: inside the URDF's directory's parent).
pub fn load_asset(path: &Path, options: &IngestOptions) -> IngestResult<LoadedAsset> {
    options.validate()?;
    let format = detect_format(path)?;
    let given = if path.is_dir() {
        find_urdf_in(path)?
    } else {
        path.to_path_buf()
    };
    let main = given.canonicalize().map_err(|source| IngestError::Io {
        path: given.clone(),
        source,
    })?;
    let dir = main.parent().unwrap_or(Path::new("/"));
    let root = match format {
        SourceFormat::Urdf => dir.parent().unwrap_or(dir),
        _ => dir,
    };
    let mut session = Session::new(options, root)?;
    let bytes = session.read(&main)?;
    let mut asset = match format {
        SourceFormat::Glb | SourceFormat::Gltf => gltf::read_gltf(&main, &bytes, &mut session)?,
        SourceFormat::Obj => obj::read_obj(&main, &bytes, &mut session)?,
        SourceFormat::Ply => ply::read_ply(&main, &bytes, &session)?,
        SourceFormat::Stl => stl::read_stl(&main, bytes, &session)?,
        SourceFormat::Urdf => urdf::read_urdf(&main, &bytes, &mut session)?,
    };
    sanitize(&mut asset, &main, &mut session)?;
    session.check_triangles(&main, asset.triangle_count())?;
    let up_axis = options.up_axis.unwrap_or(default_up_axis(format));
    asset.transform(&to_service_frame(up_axis, options.metres_per_unit));
    if options.ignore_joints {
        asset.joints.clear();
    }
    if let Some(rotation) = &options.rotation {
        asset.transform(&DMat4::from_quat(rotation.rotated_from_input));
    }
    let dropped_degenerate_triangles = session.dropped_degenerate;
    let mut warnings = std::mem::take(&mut session.warnings);
    let facts = input_facts(&main, format, &mut warnings);
    Ok(LoadedAsset {
        asset,
        source: SourceInfo {
            file_name: given
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            format,
            content_sha256: session.finish_digest(),
            metres_per_unit: options.metres_per_unit,
            up_axis,
        },
        dropped_degenerate_triangles,
        warnings,
        facts,
    })
}

/// Scale to metres, then rotate the up axis onto +Z.
fn to_service_frame(up: UpAxis, metres_per_unit: f64) -> DMat4 {
    let rotation = match up {
        UpAxis::Y => DMat4::from_rotation_x(FRAC_PI_2),
        UpAxis::Z => DMat4::IDENTITY,
    };
    rotation * DMat4::from_scale(DVec3::splat(metres_per_unit))
}

/// The single `.urdf` file in `dir`.
fn find_urdf_in(dir: &Path) -> IngestResult<PathBuf> {
    let entries = std::fs::read_dir(dir).map_err(|source| IngestError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
        })
        .collect();
    found.sort();
    match found.len() {
        0 => Err(IngestError::NoUrdfInDirectory {
            path: dir.to_path_buf(),
        }),
        1 => Ok(found.remove(0)),
        _ => Err(IngestError::SeveralUrdfsInDirectory {
            path: dir.to_path_buf(),
            found: found
                .iter()
                .filter_map(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_up_becomes_z_up_by_rotating_plus_90_about_x() {
        let m = to_service_frame(UpAxis::Y, 2.0);
        let p = m.transform_point3(DVec3::new(1.0, 2.0, 3.0));
        assert!((p - DVec3::new(2.0, -6.0, 4.0)).length() < 1e-12, "{p}");
        let q = to_service_frame(UpAxis::Z, 0.5).transform_point3(DVec3::new(1.0, 2.0, 3.0));
        assert!((q - DVec3::new(0.5, 1.0, 1.5)).length() < 1e-12);
    }

    #[test]
    fn extension_detection_is_case_insensitive_and_lists_supported_on_error() {
        assert_eq!(
            detect_format(Path::new("a/B.GLB")).ok(),
            Some(SourceFormat::Glb)
        );
        assert_eq!(
            detect_format(Path::new("x.Stl")).ok(),
            Some(SourceFormat::Stl)
        );
        let err = detect_format(Path::new("x.fbx")).expect_err("unsupported");
        let msg = err.to_string();
        assert!(
            msg.contains("x.fbx") && msg.contains(".glb, .gltf, .obj, .ply, .stl, .urdf"),
            "{msg}"
        );
    }

    #[test]
    fn default_up_axes_follow_the_format_conventions() {
        assert_eq!(default_up_axis(SourceFormat::Gltf), UpAxis::Y);
        assert_eq!(default_up_axis(SourceFormat::Glb), UpAxis::Y);
        assert_eq!(default_up_axis(SourceFormat::Obj), UpAxis::Y);
        assert_eq!(default_up_axis(SourceFormat::Ply), UpAxis::Z);
        assert_eq!(default_up_axis(SourceFormat::Stl), UpAxis::Z);
        assert_eq!(default_up_axis(SourceFormat::Urdf), UpAxis::Z);
    }
}
