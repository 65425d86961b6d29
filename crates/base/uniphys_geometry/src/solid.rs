use crate::{GeometryError, GeometryResult, MassProperties, TriMesh, voxelize};

/// How the volume behind a [`MassProperties`] was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VolumeMethod {
    /// Exact, from a closed mesh by the divergence theorem.
    ClosedMesh,
    /// Approximate, from a filled voxel grid of this resolution along the longest side.
    Voxels {
        /// Voxels across the longest side of the mesh bounds.
        resolution: usize,
    },
}

impl VolumeMethod {
    /// Stable name for reports: `"closed_mesh"` or `"voxels_<resolution>"` (e.g. `"voxels_128"`).
    #[must_use]
    pub fn as_str(&self) -> String {
        match self {
            Self::ClosedMesh => "closed_mesh".to_owned(),
            Self::Voxels { resolution } => format!("voxels_{resolution}"),
        }
    }
}

impl std::fmt::Display for VolumeMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.as_str())
    }
}

/// Mass properties of the solid a mesh bounds: exact if the mesh is closed (after welding),
/// otherwise from its filled voxel grid at `voxel_resolution` (see [`crate::VoxelGrid`]).
///
/// Errors: those of [`voxelize`] (degenerate mesh, bad resolution) when the mesh is not closed.
pub fn solid_mass_properties(
    mesh: &TriMesh,
    voxel_resolution: usize,
) -> GeometryResult<(MassProperties, VolumeMethod)> {
    if let Some(exact) = MassProperties::from_closed_mesh(mesh) {
        return Ok((exact, VolumeMethod::ClosedMesh));
    }
    let properties = voxelize(mesh, voxel_resolution)?.mass_properties();
    if properties.volume_m3 > 0.0 {
        Ok((
            properties,
            VolumeMethod::Voxels {
                resolution: voxel_resolution,
            },
        ))
    } else {
        Err(GeometryError::Degenerate)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::test_shapes::{open_box, unit_box};

    #[test]
    fn closed_box_is_exact() {
        let (m, method) =
            solid_mass_properties(&unit_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0)), 64).unwrap();
        assert_eq!(method, VolumeMethod::ClosedMesh);
        assert_eq!(method.as_str(), "closed_mesh");
        assert!((m.volume_m3 - 6.0).abs() < 1e-12);
    }

    #[test]
    fn open_box_falls_back_to_voxels() {
        let (m, method) = solid_mass_properties(&open_box(), 128).unwrap();
        assert_eq!(method, VolumeMethod::Voxels { resolution: 128 });
        assert_eq!(method.to_string(), "voxels_128");
        // The open box leaks, so only its shell counts: five unit faces times about one
        // voxel (1/128 m) of thickness, far below the closed box's 1 m^3.
        assert!(m.volume_m3 > 5.0 / 128.0 * 0.8 && m.volume_m3 < 5.0 / 128.0 * 1.3);
    }

    #[test]
    fn degenerate_open_mesh_is_an_error() {
        let line =
            TriMesh::new(vec![DVec3::ZERO, DVec3::X, 2.0 * DVec3::X], vec![[0, 1, 2]]).unwrap();
        assert_eq!(
            solid_mass_properties(&line, 32),
            Err(GeometryError::Degenerate)
        );
    }
}
