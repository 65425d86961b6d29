//! Safe resolution of files referenced by an asset (MTL libraries, textures, glTF buffers, URDF
//! meshes).
//!
//! Every reference must stay inside a confinement root: the asset's own directory for glTF, OBJ
//! and friends, and the URDF's directory's parent for URDF assets (ROS packages commonly keep
//! `urdf/` and `meshes/` side by side). Absolute references and references climbing out of the
//! root with `..` are refused with [`IngestError::PathTraversal`] before anything is opened; after
//! resolution the canonical path is checked again so symbolic links cannot escape either.

use std::path::{Component, Path, PathBuf};

use crate::{IngestError, IngestResult};

/// Resolves `reference`, written in `referencing` (a file in the canonical directory
/// `base_dir`), to the canonical path of an existing file inside the canonical `root`.
pub(crate) fn resolve_reference(
    referencing: &Path,
    base_dir: &Path,
    root: &Path,
    reference: &str,
) -> IngestResult<PathBuf> {
    let traversal = || IngestError::PathTraversal {
        path: referencing.to_path_buf(),
        reference: reference.to_owned(),
    };
    let cleaned = reference.trim().replace('\\', "/");
    if is_absolute_like(&cleaned) {
        return Err(traversal());
    }
    let mut out = base_dir.to_path_buf();
    for part in cleaned.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                if !out.pop() || !out.starts_with(root) {
                    return Err(traversal());
                }
            }
            name => out.push(name),
        }
    }
    if !out.starts_with(root) {
        return Err(traversal());
    }
    existing_inside(referencing, reference, out, root)
}

/// Resolves an absolute path taken from a `file://` URI: accepted only when it lies inside the
/// canonical `root`.
pub(crate) fn resolve_absolute(
    referencing: &Path,
    root: &Path,
    reference: &str,
    absolute: &str,
) -> IngestResult<PathBuf> {
    let traversal = || IngestError::PathTraversal {
        path: referencing.to_path_buf(),
        reference: reference.to_owned(),
    };
    let path = Path::new(absolute);
    if !path.is_absolute() {
        return Err(traversal());
    }
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::ParentDir => {
                if !out.pop() {
                    return Err(traversal());
                }
            }
            Component::CurDir => {}
            other => out.push(other.as_os_str()),
        }
    }
    if !out.starts_with(root) {
        return Err(traversal());
    }
    existing_inside(referencing, reference, out, root)
}

/// Resolves a URDF mesh `filename`: `package://<pkg>/rest` is looked up as `rest`, then as
/// `<pkg>/rest`, relative to the URDF's directory and then to its parent; `file://` URIs must point inside `root`; plain
/// names are relative to the URDF's directory.
pub(crate) fn resolve_urdf_reference(
    urdf: &Path,
    urdf_dir: &Path,
    root: &Path,
    filename: &str,
) -> IngestResult<PathBuf> {
    if let Some(full) = filename.strip_prefix("package://") {
        // `package://<pkg>/rest`: try `rest` and the whole `<pkg>/rest` (some exports name a
        // folder as the package), next to the URDF and then in its parent directory.
        let rest = full.split_once('/').map_or("", |(_, r)| r);
        let parent = urdf_dir.parent().filter(|p| p.starts_with(root));
        let mut first = None;
        for dir in std::iter::once(urdf_dir).chain(parent) {
            for candidate in [rest, full] {
                let attempt = resolve_reference(urdf, dir, root, candidate);
                if !matches!(attempt, Err(IngestError::MissingReference { .. })) {
                    return attempt;
                }
                first.get_or_insert(attempt);
            }
        }
        let first = first.unwrap_or_else(|| resolve_reference(urdf, urdf_dir, root, rest));
        return first.map_err(|e| rename_reference(e, filename));
    }
    if let Some(absolute) = filename.strip_prefix("file://") {
        return resolve_absolute(urdf, root, filename, absolute);
    }
    // Plain relative names: next to the URDF, then (as PyBullet's search path does for its data
    // folder) relative to the URDF's parent directory, which is still inside `root`.
    let first = resolve_reference(urdf, urdf_dir, root, filename);
    if let (Err(IngestError::MissingReference { .. }), Some(parent)) =
        (&first, urdf_dir.parent().filter(|p| p.starts_with(root)))
    {
        let second = resolve_reference(urdf, parent, root, filename);
        if !matches!(second, Err(IngestError::MissingReference { .. })) {
            return second;
        }
    }
    first
}

/// Whether a reference is an absolute path on any platform (`/x`, `C:/x`, `//server/x`).
fn is_absolute_like(reference: &str) -> bool {
    let bytes = reference.as_bytes();
    reference.starts_with('/')
        || (bytes.len() >= 2 && bytes[0].is_ascii_alphabetic() && bytes[1] == b':')
        || Path::new(reference).is_absolute()
}

fn existing_inside(
    referencing: &Path,
    reference: &str,
    candidate: PathBuf,
    root: &Path,
) -> IngestResult<PathBuf> {
    if !candidate.exists() {
        return Err(IngestError::MissingReference {
            path: referencing.to_path_buf(),
            reference: reference.to_owned(),
            resolved: candidate,
        });
    }
    let canonical = candidate.canonicalize().map_err(|source| IngestError::Io {
        path: candidate.clone(),
        source,
    })?;
    if !canonical.starts_with(root) {
        return Err(IngestError::PathTraversal {
            path: referencing.to_path_buf(),
            reference: reference.to_owned(),
        });
    }
    Ok(canonical)
}

fn rename_reference(error: IngestError, filename: &str) -> IngestError {
    match error {
        IngestError::MissingReference { path, resolved, .. } => IngestError::MissingReference {
            path,
            reference: filename.to_owned(),
            resolved,
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().expect("tempdir");
        let root = dir.path().canonicalize().expect("canonical");
        std::fs::create_dir_all(root.join("asset/sub")).expect("mkdir");
        std::fs::write(root.join("asset/sub/tex.png"), b"x").expect("write");
        std::fs::write(root.join("outside.txt"), b"x").expect("write");
        (dir, root)
    }

    #[test]
    fn relative_reference_inside_root_resolves_to_canonical_path() {
        let (_d, root) = setup();
        let asset = root.join("asset");
        let main = asset.join("a.obj");
        let got = resolve_reference(&main, &asset, &asset, "sub/./tex.png").expect("resolves");
        assert_eq!(got, asset.join("sub/tex.png"));
        let got = resolve_reference(&main, &asset.join("sub"), &asset, "../sub/tex.png")
            .expect("climbing within the root is fine");
        assert_eq!(got, asset.join("sub/tex.png"));
        let got = resolve_reference(&main, &asset, &asset, "sub\\tex.png").expect("backslashes");
        assert_eq!(got, asset.join("sub/tex.png"));
    }

    #[test]
    fn climbing_out_or_absolute_references_are_refused_before_reading() {
        let (_d, root) = setup();
        let asset = root.join("asset");
        let main = asset.join("a.obj");
        for bad in [
            "../outside.txt",
            "sub/../../outside.txt",
            "/etc/passwd",
            "C:/Windows/win.ini",
        ] {
            let err = resolve_reference(&main, &asset, &asset, bad).expect_err(bad);
            assert!(
                matches!(err, IngestError::PathTraversal { .. }),
                "{bad}: {err}"
            );
        }
    }

    #[cfg(unix)]
    #[test]
    fn symlink_pointing_out_of_the_root_is_refused() {
        let (_d, root) = setup();
        let asset = root.join("asset");
        std::os::unix::fs::symlink(root.join("outside.txt"), asset.join("link.mtl"))
            .expect("symlink");
        let err = resolve_reference(&asset.join("a.obj"), &asset, &asset, "link.mtl")
            .expect_err("escapes");
        assert!(matches!(err, IngestError::PathTraversal { .. }), "{err}");
    }

    #[test]
    fn missing_reference_names_referencing_file_and_missing_path() {
        let (_d, root) = setup();
        let asset = root.join("asset");
        let main = asset.join("a.obj");
        let err = resolve_reference(&main, &asset, &asset, "nope.mtl").expect_err("missing");
        let msg = err.to_string();
        assert!(matches!(err, IngestError::MissingReference { .. }));
        assert!(msg.contains("a.obj") && msg.contains("nope.mtl"), "{msg}");
    }

    #[test]
    fn plain_names_fall_back_to_the_parent_directory_but_not_beyond_the_root() {
        let (_d, root) = setup();
        let urdf_dir = root.join("asset/sub");
        let urdf = urdf_dir.join("r.urdf");
        // `sub/tex.png` written relative to the data folder, as PyBullet's search path allows.
        let got = resolve_urdf_reference(&urdf, &urdf_dir, &root.join("asset"), "sub/tex.png")
            .expect("found in parent");
        assert_eq!(got, root.join("asset/sub/tex.png"));
        let err = resolve_urdf_reference(&urdf, &urdf_dir, &root.join("asset/sub"), "sub/tex.png")
            .expect_err("the parent is outside this root");
        assert!(matches!(err, IngestError::MissingReference { .. }), "{err}");
    }

    #[test]
    fn package_uri_falls_back_to_the_parent_directory() {
        let (_d, root) = setup();
        let urdf_dir = root.join("asset/sub");
        let urdf = urdf_dir.join("r.urdf");
        // `package://pkg/sub/tex.png` is not in urdf_dir/sub/ but in urdf_dir/../sub/.
        let got = resolve_urdf_reference(
            &urdf,
            &urdf_dir,
            &root.join("asset"),
            "package://pkg/sub/tex.png",
        )
        .expect("found in parent");
        assert_eq!(got, root.join("asset/sub/tex.png"));
        let err = resolve_urdf_reference(
            &urdf,
            &urdf_dir,
            &root.join("asset"),
            "package://pkg/none.obj",
        )
        .expect_err("missing");
        assert!(err.to_string().contains("package://pkg/none.obj"), "{err}");
    }

    #[test]
    fn file_uri_is_accepted_only_inside_the_root() {
        let (_d, root) = setup();
        let asset = root.join("asset");
        let urdf = asset.join("r.urdf");
        let inside = format!("file://{}", asset.join("sub/tex.png").display());
        assert!(resolve_urdf_reference(&urdf, &asset, &asset, &inside).is_ok());
        let outside = format!("file://{}", root.join("outside.txt").display());
        let err = resolve_urdf_reference(&urdf, &asset, &asset, &outside).expect_err("outside");
        assert!(matches!(err, IngestError::PathTraversal { .. }), "{err}");
    }
}
