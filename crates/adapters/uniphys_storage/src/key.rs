use crate::{StorageError, StorageResult};

/// The deterministic prefix of a stage's artifacts: `{asset}/{stage}/{stage_version}/{input_digest}`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArtifactKey {
    /// Asset id or name.
    pub asset: String,
    /// Stage name, e.g. `export`.
    pub stage: String,
    /// Version of the stage's code/contract; bump it when outputs change for the same input.
    pub stage_version: u32,
    /// Digest of the stage's inputs (hex).
    pub input_digest: String,
}

impl ArtifactKey {
    /// The full key of the file `name` (a relative `/`-separated path) under this prefix.
    pub fn file(&self, name: &str) -> StorageResult<String> {
        let key = format!("{self}/{name}");
        validate_key(&key)?;
        Ok(key)
    }
}

impl std::fmt::Display for ArtifactKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}/{}/v{}/{}",
            self.asset, self.stage, self.stage_version, self.input_digest
        )
    }
}

/// Rejects keys with empty, `.` or `..` components or control characters.
pub(crate) fn validate_key(key: &str) -> StorageResult<()> {
    let bad = key
        .split('/')
        .any(|c| c.is_empty() || c == "." || c == ".." || c.chars().any(char::is_control));
    if bad {
        Err(StorageError::InvalidKey(key.to_owned()))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_deterministic_and_reject_traversal() {
        let k = ArtifactKey {
            asset: "cabinet".into(),
            stage: "export".into(),
            stage_version: 1,
            input_digest: "ab12".into(),
        };
        assert_eq!(
            k.file("model.urdf").unwrap(),
            "cabinet/export/v1/ab12/model.urdf"
        );
        assert!(k.file("../x").is_err());
        assert!(k.file("a//b").is_err());
    }
}
