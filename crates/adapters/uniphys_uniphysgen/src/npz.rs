use std::path::{Path, PathBuf};

use uniphys_geometry::DVec3;

use crate::npy::{npy_f32_rows, npy_u8_rows, npy_unicode};
use crate::zip::ZipWriter;
use crate::{PointCloud, PreparedAsset, UniPhysGenError, UniPhysGenResult};

fn f32_rows(points: &[DVec3]) -> Vec<[f32; 3]> {
    points.iter().map(|p| p.as_vec3().to_array()).collect()
}

fn archive(path: &Path, arrays: &[(&str, Vec<u8>)]) -> UniPhysGenResult<Vec<u8>> {
    let too_big = || UniPhysGenError::Write {
        path: path.to_owned(),
        source: std::io::Error::other("the arrays exceed the 4 GiB zip limit; sample fewer points"),
    };
    let mut zip = ZipWriter::default();
    for (name, npy) in arrays {
        zip.add(&format!("{name}.npy"), npy).ok_or_else(too_big)?;
    }
    zip.finish().ok_or_else(too_big)
}

fn cloud_arrays(cloud: &PointCloud) -> Vec<(&'static str, Vec<u8>)> {
    vec![
        ("point", npy_f32_rows(&f32_rows(&cloud.points))),
        ("color", npy_u8_rows(&cloud.colors_rgb8)),
        ("normal", npy_f32_rows(&f32_rows(&cloud.normals))),
    ]
}

/// Part ids in ascending numeric order (ids that are not numbers after them, by text), with
/// their index in [`PreparedAsset::parts`].
fn numeric_order(prepared: &PreparedAsset) -> Vec<usize> {
    let mut order: Vec<usize> = (0..prepared.parts.len()).collect();
    order.sort_by_key(|&i| {
        let id = &prepared.parts[i].0;
        (id.parse::<u64>().map_or(u64::MAX, |n| n), id.clone())
    });
    order
}

/// Writes the reference's npz layout (14.2) into `dir`: `model.npz` with `point` float32
/// [N,3], `color` uint8 [N,3], `normal` float32 [N,3], `part_names` (unicode, numeric ids in
/// numeric order) and `part_centers` float32 [K,3] (same order); and `<id>.npz` per part with
/// `point`, `color`, `normal`. Entries are stored uncompressed (the reference compresses; numpy
/// reads both). Returns the files written.
///
/// # Errors
/// [`UniPhysGenError::Write`] if the directory or a file cannot be written.
pub fn write_npzs(prepared: &PreparedAsset, dir: &Path) -> UniPhysGenResult<Vec<PathBuf>> {
    let write_error = |path: &Path| {
        let path = path.to_owned();
        move |source| UniPhysGenError::Write { path, source }
    };
    std::fs::create_dir_all(dir).map_err(write_error(dir))?;
    let order = numeric_order(prepared);
    let names: Vec<String> = order.iter().map(|&i| prepared.parts[i].0.clone()).collect();
    let centers: Vec<DVec3> = order
        .iter()
        .map(|&i| {
            prepared
                .part_centers_in_object_m
                .get(i)
                .copied()
                .unwrap_or_else(|| prepared.parts[i].1.centroid())
        })
        .collect();
    let mut written = Vec::with_capacity(prepared.parts.len() + 1);
    let model = dir.join("model.npz");
    let mut arrays = cloud_arrays(&prepared.object);
    arrays.push(("part_names", npy_unicode(&names)));
    arrays.push(("part_centers", npy_f32_rows(&f32_rows(&centers))));
    std::fs::write(&model, archive(&model, &arrays)?).map_err(write_error(&model))?;
    written.push(model);
    for &i in &order {
        let (id, cloud) = &prepared.parts[i];
        let path = dir.join(format!("{id}.npz"));
        std::fs::write(&path, archive(&path, &cloud_arrays(cloud))?).map_err(write_error(&path))?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(x: f64) -> PointCloud {
        PointCloud {
            points: vec![DVec3::new(x, 0.0, 0.0)],
            colors_rgb8: vec![[1, 2, 3]],
            normals: vec![DVec3::Z],
        }
    }

    #[test]
    fn parts_are_written_in_numeric_id_order() {
        let prepared = PreparedAsset {
            object: cloud(0.0),
            parts: vec![("10".to_owned(), cloud(10.0)), ("2".to_owned(), cloud(2.0))],
            part_centers_in_object_m: vec![DVec3::X * 10.0, DVec3::X * 2.0],
        };
        assert_eq!(numeric_order(&prepared), [1, 0]);
        let dir = tempfile::tempdir().unwrap();
        let written = write_npzs(&prepared, dir.path()).unwrap();
        let names: Vec<_> = written
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["model.npz", "2.npz", "10.npz"]);
        let model = std::fs::read(&written[0]).unwrap();
        assert_eq!(&model[..4], b"PK\x03\x04");
        // Entry names in order: point, color, normal, part_names, part_centers.
        let text = String::from_utf8_lossy(&model);
        let at = |s: &str| text.find(s).unwrap();
        assert!(at("point.npy") < at("color.npy") && at("part_names.npy") < at("part_centers.npy"));
    }
}
