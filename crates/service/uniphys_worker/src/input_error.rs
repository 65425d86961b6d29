//! Why a submitted file cannot be read, told to its submitter: the file by its name (never the
//! worker's temporary path), what is wrong, and for a limit that the service's operator sets it
//! (the reader's own message tells a library user which option to raise).

use uniphys_mesh_io::IngestError;

use crate::source::SourceFile;
use crate::stage::StageError;

/// The permanent stage error for `source`, which the reader refused with `error`.
pub(crate) fn unreadable(source: &SourceFile, error: &IngestError) -> StageError {
    let name = source.file_name();
    let operator =
        "decimate the mesh and submit it again (the limit is set by the service's operator)";
    let text = match error {
        IngestError::TooManyTriangles { count, limit, .. } => format!(
            "{name} has {count} triangles, more than this service's limit of {limit}; {operator}"
        ),
        IngestError::TooManyVertices { count, limit, .. } => format!(
            "{name} declares {count} vertices, more than this service's limit of {limit}; {operator}"
        ),
        IngestError::FileTooLarge { path, size, limit } => format!(
            "{} is {size} bytes, more than this service's limit of {limit} bytes per file; reduce it and submit it again (the limit is set by the service's operator)",
            path.display()
        ),
        other => other.to_string(),
    };
    StageError::Permanent(format!(
        "the input cannot be read: {}",
        source.without_local_paths(&text)
    ))
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;

    #[test]
    fn limits_are_the_operators_and_no_local_path_is_shown() {
        let source = SourceFile::in_dir(tempfile::tempdir().expect("tempdir"), "oven.glb");
        let too_big = IngestError::TooManyTriangles {
            path: source.path().to_path_buf(),
            count: 3_000_000,
            limit: 2_000_000,
        };
        let message = unreadable(&source, &too_big).to_string();
        assert!(
            message.contains("oven.glb has 3000000 triangles")
                && message.contains("limit of 2000000")
                && message.contains("operator"),
            "{message}"
        );
        assert!(!message.contains("IngestOptions"), "{message}");
        let missing = IngestError::MissingReference {
            path: source.path().to_path_buf(),
            reference: "wood.png".into(),
            resolved: source.path().with_file_name("wood.png"),
        };
        let message = unreadable(&source, &missing).to_string();
        let local = source.path().parent().map(PathBuf::from).expect("a folder");
        assert!(!message.contains(&*local.to_string_lossy()), "{message}");
        assert!(
            message.contains("oven.glb") && message.contains("wood.png"),
            "{message}"
        );
    }
}
