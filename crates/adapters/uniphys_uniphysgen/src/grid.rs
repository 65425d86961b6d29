use uniphys_geometry::DVec3;

use crate::{CoordinateFrame, PointCloud, PreparedAsset, UniPhysGenError, UniPhysGenResult};

/// Voxels along each axis of the [0, 2] model cube in the released checkpoints.
pub const DEFAULT_NUM_BINS: u32 = 256;

/// Largest accepted `num_bins` (keeps the voxel occupancy bitset at 128 MiB at most).
pub const MAX_NUM_BINS: u32 = 1024;

/// One point as the model reads it: `[grid(3), coord(3), color(3), normal(3)]` with the integer
/// voxel coordinates, the model-frame position, the colour in [-1, 1] and the unit normal.
pub type FeatureRow = [f32; 12];

/// The model's inputs for one asset: the frame and the voxel-sampled feature rows of the object
/// and of every part, all in that one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelInputs {
    /// Source (object frame, metres) to model frame.
    pub frame: CoordinateFrame,
    /// Voxels per axis.
    pub num_bins: u32,
    /// Feature rows of the object.
    pub object: Vec<FeatureRow>,
    /// `(part id, feature rows)` per part, in the order of [`PreparedAsset::parts`].
    pub parts: Vec<(String, Vec<FeatureRow>)>,
    /// Part centres in the model frame, in the order of `parts`.
    pub part_centers_in_model: Vec<DVec3>,
}

/// Normalises a prepared asset into the model frame and voxel-samples every cloud (reference
/// 14.3): one frame for the object and all its parts; one voxel grid of `2 / num_bins` whose
/// origin is the object's lowest voxel on each axis, shared by the parts; one point per voxel.
///
/// The point kept in a voxel is the first one in sampling order, and rows come out in the order
/// of their first point. The reference instead sorts points by the FNV hash of their voxel and
/// keeps the middle-ranked one of each voxel; both keep exactly one point per occupied voxel
/// (same voxels, a different representative inside each 2/num_bins cell).
///
/// # Errors
/// [`UniPhysGenError::InvalidOption`] if `num_bins` is 0 or above [`MAX_NUM_BINS`].
pub fn model_inputs(prepared: &PreparedAsset, num_bins: u32) -> UniPhysGenResult<ModelInputs> {
    if num_bins == 0 || num_bins > MAX_NUM_BINS {
        return Err(UniPhysGenError::InvalidOption {
            name: "num_bins",
            value: num_bins.to_string(),
            expected: "between 1 and 1024 (the released checkpoints use 256)",
        });
    }
    let part_refs: Vec<&PointCloud> = prepared.parts.iter().map(|(_, c)| c).collect();
    let frame = CoordinateFrame::from_clouds(&prepared.object, &part_refs);
    let grid = VoxelGrid::of_object(&frame, &prepared.object, num_bins);
    let object = grid.features(&frame, &prepared.object);
    let parts = prepared
        .parts
        .iter()
        .map(|(id, c)| (id.clone(), grid.features(&frame, c)))
        .collect();
    let part_centers_in_model = prepared
        .part_centers_in_object_m
        .iter()
        .map(|&c| frame.point_source_to_model(c))
        .collect();
    Ok(ModelInputs {
        frame,
        num_bins,
        object,
        parts,
        part_centers_in_model,
    })
}

/// The shared voxel grid: size `2 / num_bins`, origin at the object's lowest voxel per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoxelGrid {
    /// Voxels per axis.
    pub num_bins: u32,
    /// Voxel edge, model units (`2 / num_bins`).
    pub grid_size: f64,
    /// Per axis, the lowest `floor(coord / grid_size)` over the object's points.
    pub shared_min: [i64; 3],
}

impl VoxelGrid {
    /// The grid whose origin is the object's lowest voxel (`floor(object / grid_size).min(0)`).
    #[must_use]
    pub fn of_object(frame: &CoordinateFrame, object: &PointCloud, num_bins: u32) -> Self {
        let grid_size = 2.0 / f64::from(num_bins);
        let mut shared_min = [i64::MAX; 3];
        for p in &object.points {
            let cell = raw_cell(frame.point_source_to_model(*p), grid_size);
            for k in 0..3 {
                shared_min[k] = shared_min[k].min(cell[k]);
            }
        }
        if object.points.is_empty() {
            shared_min = [0; 3];
        }
        Self {
            num_bins,
            grid_size,
            shared_min,
        }
    }

    /// Voxel of a model-frame point: `floor(coord / grid_size) - shared_min`, clipped to
    /// `[0, num_bins - 1]`.
    #[must_use]
    pub fn cell(&self, point_in_model: DVec3) -> [u32; 3] {
        let raw = raw_cell(point_in_model, self.grid_size);
        let top = i64::from(self.num_bins) - 1;
        [0, 1, 2].map(|k| {
            let clipped = (raw[k] - self.shared_min[k]).clamp(0, top);
            u32::try_from(clipped).unwrap_or(0)
        })
    }

    /// Feature rows of a cloud, one per occupied voxel (the first point of each voxel).
    #[must_use]
    pub fn features(&self, frame: &CoordinateFrame, cloud: &PointCloud) -> Vec<FeatureRow> {
        let n = self.num_bins as usize;
        let mut occupied = vec![0u64; (n * n * n).div_ceil(64)];
        let mut rows = Vec::new();
        for ((p, c), normal) in cloud
            .points
            .iter()
            .zip(&cloud.colors_rgb8)
            .zip(&cloud.normals)
        {
            let coord = frame.point_source_to_model(*p);
            let cell = self.cell(coord);
            let index = (cell[0] as usize * n + cell[1] as usize) * n + cell[2] as usize;
            let (word, bit) = (index / 64, 1u64 << (index % 64));
            if occupied[word] & bit != 0 {
                continue;
            }
            occupied[word] |= bit;
            let color = c.map(|v| f32::from(v) / 127.5 - 1.0);
            rows.push([
                cell[0] as f32,
                cell[1] as f32,
                cell[2] as f32,
                coord.x as f32,
                coord.y as f32,
                coord.z as f32,
                color[0],
                color[1],
                color[2],
                normal.x as f32,
                normal.y as f32,
                normal.z as f32,
            ]);
        }
        rows
    }
}

fn raw_cell(point_in_model: DVec3, grid_size: f64) -> [i64; 3] {
    (point_in_model / grid_size)
        .floor()
        .to_array()
        .map(|v| v as i64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(points: &[[f64; 3]], colors: &[[u8; 3]]) -> PointCloud {
        PointCloud {
            points: points.iter().map(|&p| DVec3::from_array(p)).collect(),
            colors_rgb8: colors.to_vec(),
            normals: vec![DVec3::Z; points.len()],
        }
    }

    #[test]
    fn grid_of_a_unit_cube_object_has_hand_computed_cells_and_rows() {
        // Object corners (0,0,0) and (2,2,2): centre 1, scale 1, model frame = source frame
        // (min_bound -1 undoes the centring). With 4 bins the voxel is 0.5.
        let object = cloud(
            &[
                [0.0, 0.0, 0.0],
                [2.0, 2.0, 2.0],
                [0.1, 0.2, 0.3],
                [0.6, 1.2, 1.9],
            ],
            &[[0, 0, 0], [255, 255, 255], [10, 20, 30], [255, 0, 127]],
        );
        let prepared = PreparedAsset {
            object: object.clone(),
            parts: vec![("0".to_owned(), cloud(&[[0.6, 1.2, 1.9]], &[[0, 0, 0]]))],
            part_centers_in_object_m: vec![DVec3::new(0.6, 1.2, 1.9)],
        };
        let inputs = model_inputs(&prepared, 4).unwrap();
        assert_eq!(inputs.frame.scale_m, 1.0);
        // (0,0,0) -> cell 0; (2,2,2) -> floor(4) = 4 clipped to 3; (0.1,0.2,0.3) -> cell 0 again
        // (dropped: one point per voxel); (0.6,1.2,1.9) -> (1,2,3).
        let cells: Vec<[f32; 3]> = inputs.object.iter().map(|r| [r[0], r[1], r[2]]).collect();
        assert_eq!(cells, [[0.0; 3], [3.0; 3], [1.0, 2.0, 3.0]]);
        let last = inputs.object[2];
        assert!((last[3] - 0.6).abs() < 1e-6 && (last[5] - 1.9).abs() < 1e-6);
        // Colour 255 -> 1, 0 -> -1, 127 -> 127/127.5 - 1 = -0.0039216.
        assert_eq!(&last[6..8], &[1.0, -1.0]);
        assert!((last[8] + 0.003_921_6).abs() < 1e-6);
        assert_eq!(&last[9..], &[0.0, 0.0, 1.0]);
        assert_eq!(inputs.parts[0].1.len(), 1);
        assert_eq!(&inputs.parts[0].1[0][..3], &[1.0, 2.0, 3.0]);
        assert!((inputs.part_centers_in_model[0] - DVec3::new(0.6, 1.2, 1.9)).length() < 1e-9);
    }

    #[test]
    fn the_object_grid_origin_is_shared_by_a_part_below_it() {
        // Object from (0,0,0) to (2,2,2); the part reaches x = -0.6 in source. The shared shift
        // then makes model x = source x + 0.6, the object's lowest voxel is floor(0.6/0.5) = 1,
        // and the part point at model x = 0 lands at raw cell 0 - 1 = -1, clipped to 0. Source
        // x = 1 is model 1.6: floor(3.2) - 1 = 2.
        let object = cloud(&[[0.0, 0.0, 0.0], [2.0, 2.0, 2.0]], &[[0; 3]; 2]);
        let part = cloud(&[[-0.6, 0.0, 0.0]], &[[0; 3]]);
        let frame = CoordinateFrame::from_clouds(&object, &[&part]);
        let grid = VoxelGrid::of_object(&frame, &object, 4);
        assert_eq!(grid.shared_min, [1, 0, 0]);
        let cell = |x: f64| grid.cell(frame.point_source_to_model(DVec3::new(x, 0.0, 0.0)));
        assert_eq!(cell(-0.6), [0, 0, 0]);
        assert_eq!(cell(1.0), [2, 0, 0]);
    }

    #[test]
    fn voxel_sampling_keeps_one_point_per_occupied_voxel_in_first_seen_order() {
        let object = cloud(
            &[
                [0.0, 0.0, 0.0],
                [2.0, 2.0, 2.0],
                [1.9, 1.9, 1.9],
                [0.01, 0.0, 0.0],
            ],
            &[[1, 1, 1], [2, 2, 2], [3, 3, 3], [4, 4, 4]],
        );
        let frame = CoordinateFrame::from_clouds(&object, &[]);
        let rows = VoxelGrid::of_object(&frame, &object, 2).features(&frame, &object);
        // 2 bins: voxel 1.0; (2,2,2) and (1.9,1.9,1.9) share cell (1,1,1); the first is kept.
        assert_eq!(rows.len(), 2);
        assert!((rows[1][6] - (2.0 / 127.5 - 1.0)).abs() < 1e-6);
    }

    #[test]
    fn num_bins_out_of_range_is_refused() {
        let prepared = PreparedAsset {
            object: PointCloud::default(),
            parts: Vec::new(),
            part_centers_in_object_m: Vec::new(),
        };
        let error = model_inputs(&prepared, 0).unwrap_err();
        assert!(error.to_string().contains("num_bins"), "{error}");
    }
}
