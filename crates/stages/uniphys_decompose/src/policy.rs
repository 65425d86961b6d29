//! When to decompose: an asset that already comes in meaningful parts keeps them.

use uniphys_geometry::MeshAsset;

/// Inputs with more parts than this (and no declared joints) are taken as fragments to merge.
pub const FRAGMENTED_PART_COUNT: usize = 20;

/// Whether the decomposition stage runs on an asset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DecomposeMode {
    /// Never: the input's parts are kept.
    Off,
    /// Only where the input's parts cannot be used as they are: see [`needs_decomposition`].
    #[default]
    Auto,
    /// Always, replacing the input's parts and dropping its declared joints.
    Always,
}

impl DecomposeMode {
    /// Parses `off`, `auto` or `always`.
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "off" => Some(Self::Off),
            "auto" => Some(Self::Auto),
            "always" => Some(Self::Always),
            _ => None,
        }
    }

    /// Whether to decompose `asset` in this mode.
    #[must_use]
    pub fn applies_to(self, asset: &MeshAsset) -> bool {
        match self {
            Self::Off => false,
            Self::Auto => needs_decomposition(asset),
            Self::Always => true,
        }
    }
}

/// `Auto`'s rule: an asset without declared joints that comes in one piece (nothing says which
/// parts move) or in more than [`FRAGMENTED_PART_COUNT`] pieces (fragments of a scan or an
/// export, to be merged into parts). Assets with joints, or with a handful of parts (glTF
/// nodes, OBJ groups, URDF links), keep their own structure.
#[must_use]
pub fn needs_decomposition(asset: &MeshAsset) -> bool {
    asset.joints.is_empty() && (asset.parts.len() == 1 || asset.parts.len() > FRAGMENTED_PART_COUNT)
}

#[cfg(test)]
mod tests {
    use uniphys_geometry::{DVec3, MeshPart, TriMesh};

    use super::*;

    fn asset(parts: usize) -> MeshAsset {
        MeshAsset {
            parts: (0..parts)
                .map(|i| MeshPart {
                    name: format!("p{i}"),
                    mesh: TriMesh::cuboid(DVec3::splat(i as f64), DVec3::splat(i as f64 + 0.5)),
                })
                .collect(),
            materials: Vec::new(),
            textures: Vec::new(),
            joints: Vec::new(),
        }
    }

    #[test]
    fn auto_decomposes_one_piece_and_fragments_only() {
        assert!(needs_decomposition(&asset(1)));
        assert!(!needs_decomposition(&asset(3)));
        assert!(!needs_decomposition(&asset(FRAGMENTED_PART_COUNT)));
        assert!(needs_decomposition(&asset(FRAGMENTED_PART_COUNT + 1)));
        assert!(DecomposeMode::Always.applies_to(&asset(3)));
        assert!(!DecomposeMode::Off.applies_to(&asset(1)));
        assert_eq!(DecomposeMode::parse("auto"), Some(DecomposeMode::Auto));
        assert_eq!(DecomposeMode::parse("sometimes"), None);
    }
}
