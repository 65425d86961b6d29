//! Synthetic assets of procedural boxes: a cabinet body, a drawer in its front (slides), a lid
//! on top (turns) and small blocks resting on the body, all touching it.

use uniphys_geometry::{DVec3, SplitMix64, TriMesh};

/// One synthetic asset.
pub(crate) struct SyntheticAsset {
    pub name: String,
    pub meshes: Vec<TriMesh>,
    pub colours: Vec<[f32; 4]>,
    pub names: Vec<String>,
}

/// Whether asset `index` has a drawer besides its lid (every other one does).
pub(crate) fn has_drawer(index: usize) -> bool {
    index.is_multiple_of(2)
}

/// Asset `index` with `parts` parts (at least 3): body (label 1), lid (label 2), then a drawer
/// (label 3) for even indices, then blocks on the body. Sizes vary with the index.
pub(crate) fn synthetic_asset(index: usize, parts: usize) -> SyntheticAsset {
    let mut rng = SplitMix64::new(0xB0C5 ^ index as u64);
    let w = 0.6 + 0.4 * rng.next_f64();
    let d = 0.4 + 0.2 * rng.next_f64();
    let h = 0.5 + 0.3 * rng.next_f64();
    let gap = 0.001;
    let mut meshes = vec![TriMesh::cuboid(DVec3::ZERO, DVec3::new(w, d, h))];
    let mut names = vec!["body".to_owned()];
    meshes.push(TriMesh::cuboid(
        DVec3::new(0.0, 0.0, h + gap),
        DVec3::new(w, d, h + gap + 0.02),
    ));
    names.push("lid".to_owned());
    if has_drawer(index) {
        meshes.push(TriMesh::cuboid(
            DVec3::new(0.2 * w, -0.02 - gap, 0.2 * h),
            DVec3::new(0.8 * w, -gap, 0.4 * h),
        ));
        names.push("drawer".to_owned());
    }
    let mut k = 0usize;
    while meshes.len() < parts {
        // Blocks against the back face, in a row.
        let x0 = 0.05 + 0.09 * (k % 10) as f64 * w / 1.0;
        let z0 = 0.05 + 0.1 * (k / 10) as f64;
        meshes.push(TriMesh::cuboid(
            DVec3::new(x0.min(w - 0.06), d + gap, z0),
            DVec3::new(x0.min(w - 0.06) + 0.05, d + gap + 0.05, z0 + 0.05),
        ));
        names.push(format!("block {k}"));
        k += 1;
    }
    let colours = (0..meshes.len())
        .map(|i| {
            let t = i as f32 / meshes.len() as f32;
            [0.2 + 0.6 * t, 0.5, 0.8 - 0.6 * t, 1.0]
        })
        .collect();
    SyntheticAsset {
        name: format!("bench_{index:03}"),
        meshes,
        colours,
        names,
    }
}
