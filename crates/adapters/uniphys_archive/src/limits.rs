//! How much an archive may hold: enough for a real asset folder (a PartNet-Mobility object is a
//! few hundred files and tens of megabytes), far too little for a decompression bomb.

/// Limits checked while an archive is read; the unpacked bytes are counted as they are read,
/// never taken from the archive's headers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArchiveLimits {
    /// Entries (files and folders) at most. Default 20 000.
    pub max_entries: usize,
    /// Bytes of all files together once unpacked, at most. Default 4 GiB.
    pub max_unpacked_bytes: u64,
    /// The unpacked bytes may be at most this many times the archive's own size (meshes and
    /// images compress a few times; a bomb a thousand). Default 100.
    pub max_expansion_ratio: u64,
}

impl Default for ArchiveLimits {
    fn default() -> Self {
        Self {
            max_entries: 20_000,
            max_unpacked_bytes: 4 << 30,
            max_expansion_ratio: 100,
        }
    }
}

impl ArchiveLimits {
    /// The unpacked bytes allowed for an archive of `archive_bytes`.
    #[must_use]
    pub fn byte_budget(&self, archive_bytes: u64) -> u64 {
        self.max_unpacked_bytes
            .min(archive_bytes.saturating_mul(self.max_expansion_ratio))
    }
}
