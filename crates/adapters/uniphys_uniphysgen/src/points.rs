use uniphys_geometry::{DVec3, MeshAsset, sample_surface};

use crate::{UniPhysGenError, UniPhysGenResult};

/// Surface samples of an object or a part, in the frame of the mesh they were sampled from
/// (the object frame, metres, for an ingested asset).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointCloud {
    /// Sample positions.
    pub points: Vec<DVec3>,
    /// Surface colour at each sample, 8-bit sRGB.
    pub colors_rgb8: Vec<[u8; 3]>,
    /// Unit normal of the face each sample lies on.
    pub normals: Vec<DVec3>,
}

impl PointCloud {
    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the cloud has no points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Mean of the points (the reference's `part_centers` entry); zero for an empty cloud.
    #[must_use]
    pub fn centroid(&self) -> DVec3 {
        if self.points.is_empty() {
            return DVec3::ZERO;
        }
        self.points.iter().copied().sum::<DVec3>() / self.points.len() as f64
    }
}

/// How many points to sample, and the seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PointOptions {
    /// Points on the whole object (reference: 100,000).
    pub object_points: usize,
    /// Fewest points on a part (reference: 10,000); a part gets
    /// `max(min_part_points, floor(area share * object_points))`.
    pub min_part_points: usize,
    /// Seed of every cloud (reference: 42, the same for the object and each part).
    pub seed: u64,
}

impl Default for PointOptions {
    fn default() -> Self {
        Self {
            object_points: 100_000,
            min_part_points: 10_000,
            seed: 42,
        }
    }
}

/// The point clouds UniPhysGen reads for one asset: the object and each part, in the object
/// frame, with the part centres.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedAsset {
    /// Samples of the merged mesh of all parts.
    pub object: PointCloud,
    /// `(part id, samples)` per part; the id is the part's index in the asset as a decimal
    /// string (`PartId(i)` is `"i"`), in ascending numeric order.
    pub parts: Vec<(String, PointCloud)>,
    /// Mean of each part's samples, in the order of `parts`, object frame.
    pub part_centers_in_object_m: Vec<DVec3>,
}

/// Points of a part: `max(min_part_points, floor(part_area / object_area * object_points))`.
#[must_use]
pub fn part_point_count(part_area: f64, object_area: f64, options: &PointOptions) -> usize {
    let share = if object_area > 0.0 {
        part_area / object_area
    } else {
        0.0
    };
    // Truncation as the reference's `int(...)`.
    let by_area = (share * options.object_points as f64).floor() as usize;
    by_area.max(options.min_part_points)
}

/// Samples the object (merged mesh) and every part, area-weighted, with colours from the
/// texture, material or vertex colours (else white) and face normals. Deterministic for a given
/// seed.
///
/// # Errors
/// [`UniPhysGenError::NoSurface`] if the object or a part has no area.
pub fn prepare_points(
    asset: &MeshAsset,
    options: &PointOptions,
) -> UniPhysGenResult<PreparedAsset> {
    let merged = asset.merged();
    let object = cloud(
        asset,
        &merged,
        options.object_points,
        options.seed,
        "object",
    )?;
    let object_area = merged.area();
    let mut parts = Vec::with_capacity(asset.parts.len());
    for (index, part) in asset.parts.iter().enumerate() {
        let count = part_point_count(part.mesh.area(), object_area, options);
        let samples = cloud(asset, &part.mesh, count, options.seed, &part.name)?;
        parts.push((index.to_string(), samples));
    }
    let part_centers_in_object_m = parts.iter().map(|(_, c)| c.centroid()).collect();
    Ok(PreparedAsset {
        object,
        parts,
        part_centers_in_object_m,
    })
}

fn cloud(
    asset: &MeshAsset,
    mesh: &uniphys_geometry::TriMesh,
    count: usize,
    seed: u64,
    name: &str,
) -> UniPhysGenResult<PointCloud> {
    let samples = sample_surface(mesh, &asset.materials, &asset.textures, count, seed);
    if samples.points.is_empty() && count > 0 {
        return Err(UniPhysGenError::NoSurface {
            part: name.to_owned(),
        });
    }
    Ok(PointCloud {
        points: samples.points,
        colors_rgb8: samples.colors_rgb8,
        normals: samples.normals,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use uniphys_geometry::{MeshPart, TriMesh};

    fn two_box_asset() -> MeshAsset {
        // A 1 x 1 x 1 box (area 6) and a 1 x 1 x 2 box (area 10) beside it.
        let a = TriMesh::cuboid(DVec3::ZERO, DVec3::ONE);
        let b = TriMesh::cuboid(DVec3::new(2.0, 0.0, 0.0), DVec3::new(3.0, 1.0, 2.0));
        MeshAsset {
            parts: vec![
                MeshPart {
                    name: "a".to_owned(),
                    mesh: a,
                },
                MeshPart {
                    name: "b".to_owned(),
                    mesh: b,
                },
            ],
            ..MeshAsset::default()
        }
    }

    #[test]
    fn part_counts_follow_area_share_with_a_floor() {
        let options = PointOptions::default();
        // 6 / 16 of 100,000 = 37,500; 10 / 16 = 62,500; 0.05 share = 5,000 < 10,000.
        assert_eq!(part_point_count(6.0, 16.0, &options), 37_500);
        assert_eq!(part_point_count(10.0, 16.0, &options), 62_500);
        assert_eq!(part_point_count(0.05, 1.0, &options), 10_000);
    }

    #[test]
    fn prepared_asset_has_counts_ids_centres_and_white_unit_normal_points() {
        let options = PointOptions {
            object_points: 1600,
            min_part_points: 100,
            seed: 42,
        };
        let prepared = prepare_points(&two_box_asset(), &options).unwrap();
        assert_eq!(prepared.object.len(), 1600);
        let ids: Vec<_> = prepared.parts.iter().map(|(id, _)| id.as_str()).collect();
        assert_eq!(ids, ["0", "1"]);
        assert_eq!(prepared.parts[0].1.len(), 600);
        assert_eq!(prepared.parts[1].1.len(), 1000);
        // Centres of box surfaces are near the box centres (0.5,0.5,0.5) and (2.5,0.5,1).
        let c0 = prepared.part_centers_in_object_m[0];
        let c1 = prepared.part_centers_in_object_m[1];
        assert!((c0 - DVec3::splat(0.5)).length() < 0.05, "{c0}");
        assert!((c1 - DVec3::new(2.5, 0.5, 1.0)).length() < 0.05, "{c1}");
        for (_, c) in &prepared.parts {
            assert!(c.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-12));
            assert!(c.colors_rgb8.iter().all(|&rgb| rgb == [255, 255, 255]));
        }
    }

    #[test]
    fn same_seed_repeats_and_another_seed_differs() {
        let options = PointOptions {
            object_points: 200,
            min_part_points: 50,
            seed: 7,
        };
        let a = prepare_points(&two_box_asset(), &options).unwrap();
        assert_eq!(a, prepare_points(&two_box_asset(), &options).unwrap());
        let other = PointOptions { seed: 8, ..options };
        let b = prepare_points(&two_box_asset(), &other).unwrap();
        assert_ne!(a.object.points, b.object.points);
    }

    #[test]
    fn an_asset_without_area_is_refused() {
        let error = prepare_points(&MeshAsset::default(), &PointOptions::default()).unwrap_err();
        assert!(error.to_string().contains("no surface area"), "{error}");
    }
}
