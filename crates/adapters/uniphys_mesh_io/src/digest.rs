//! The content hash recorded in `SourceInfo::content_sha256`.

use sha2::{Digest, Sha256};

/// SHA-256 over the main file's bytes followed by each referenced file's bytes, in the order
/// they are first referenced.
#[derive(Debug, Clone, Default)]
pub(crate) struct ContentDigest {
    hasher: Sha256,
}

impl ContentDigest {
    /// Appends one file's bytes.
    pub(crate) fn update(&mut self, bytes: &[u8]) {
        self.hasher.update(bytes);
    }

    /// Lowercase hex of the hash of everything appended.
    pub(crate) fn finish(self) -> String {
        hex::encode(self.hasher.finalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digest_of_concatenated_files_matches_known_sha256() {
        let mut d = ContentDigest::default();
        d.update(b"ab");
        d.update(b"c");
        // sha256("abc")
        assert_eq!(
            d.finish(),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
