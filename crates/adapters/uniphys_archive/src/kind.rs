//! Which archive a file name names.

/// The archive formats an asset may come in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArchiveKind {
    /// A zip file (stored or deflated entries).
    Zip,
    /// A plain tar file.
    Tar,
    /// A gzip-compressed tar file.
    TarGz,
}

impl ArchiveKind {
    /// The file name endings of archives, as the API's messages list them.
    pub const ENDINGS: [&'static str; 4] = [".zip", ".tar", ".tar.gz", ".tgz"];

    /// The kind a file name ends with (any case), if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        let name = name.to_ascii_lowercase();
        if name.ends_with(".zip") {
            Some(Self::Zip)
        } else if name.ends_with(".tar.gz") || name.ends_with(".tgz") {
            Some(Self::TarGz)
        } else if name.ends_with(".tar") {
            Some(Self::Tar)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::ArchiveKind;

    #[test]
    fn archives_are_named_by_their_endings() {
        assert_eq!(ArchiveKind::from_name("oven.zip"), Some(ArchiveKind::Zip));
        assert_eq!(
            ArchiveKind::from_name("45213.TAR.GZ"),
            Some(ArchiveKind::TarGz)
        );
        assert_eq!(ArchiveKind::from_name("a.tgz"), Some(ArchiveKind::TarGz));
        assert_eq!(ArchiveKind::from_name("a.tar"), Some(ArchiveKind::Tar));
        for other in ["a.glb", "a.gz", "zip", "a.tar.bz2", "a.zipx"] {
            assert_eq!(ArchiveKind::from_name(other), None, "{other}");
        }
    }
}
