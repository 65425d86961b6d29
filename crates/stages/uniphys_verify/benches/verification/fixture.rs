//! An example asset prepared for sweeps, as the verify stage prepares it: part meshes in the
//! object frame, convex colliders from `convex_decomposition`, a scene of surface samples.

use uniphys_geometry::{ConvexParams, TriMesh, convex_decomposition};
use uniphys_types::Joint;
use uniphys_verify::Scene;

/// Surface samples per part (the pipeline's default).
pub(crate) const SAMPLES_PER_PART: usize = 1500;

/// One example asset with its true joints.
pub(crate) struct Fixture {
    /// Example name (`cabinet`).
    pub(crate) name: &'static str,
    /// Part names, `PartId(i)` is `part_names[i]`.
    pub(crate) part_names: Vec<String>,
    /// Part meshes, object frame, metres.
    pub(crate) meshes: Vec<TriMesh>,
    /// The true joints.
    pub(crate) joints: Vec<Joint>,
    /// The scene the sweeps run in.
    pub(crate) scene: Scene,
    /// Convex colliders over all parts.
    pub(crate) hull_count: usize,
}

impl Fixture {
    /// Builds the fixture of the example `name` (panics if there is none: a benchmark fails
    /// loudly).
    pub(crate) fn new(name: &'static str) -> Self {
        let example = uniphys_examples::example(name).expect("example exists");
        let meshes: Vec<TriMesh> = example.asset.parts.iter().map(|p| p.mesh.clone()).collect();
        let colliders: Vec<Vec<TriMesh>> = meshes
            .iter()
            .map(|m| convex_decomposition(m, &ConvexParams::default()).expect("hulls"))
            .collect();
        Self {
            name,
            part_names: example.asset.parts.iter().map(|p| p.name.clone()).collect(),
            scene: Scene::new(&meshes, &colliders, SAMPLES_PER_PART).expect("scene"),
            hull_count: colliders.iter().map(Vec::len).sum(),
            meshes,
            joints: example.asset.joints.clone(),
        }
    }
}
