//! Command-line options of `articulation-bench`.

use std::path::PathBuf;

/// Strip the joints of the project's articulated assets, run the pipeline, and score the
/// recovered joints (joint type, axis, pivot, limit) upright and randomly rotated.
#[derive(Debug, clap::Parser)]
#[command(name = "articulation-bench", about)]
pub(crate) struct BenchArgs {
    /// PyBullet's data folder (`python -c "import pybullet_data; print(pybullet_data.getDataPath())"`);
    /// its URDFs with revolute, prismatic or continuous joints join the example assets.
    #[arg(long)]
    pub pybullet_data: Option<PathBuf>,
    /// A folder of PartNet-Mobility objects (`../shared/data/partnet-mobility`); each is copied
    /// without its part labels (see `partnet`) and joins the benchmark.
    #[arg(long)]
    pub partnet: Option<PathBuf>,
    /// Leave out the example assets (with `--partnet`, real objects only).
    #[arg(long)]
    pub no_examples: bool,
    /// Only the upright pose (no rotated pass).
    #[arg(long)]
    pub upright_only: bool,
    /// Skip assets with more triangles than this (30 000 keeps the run to about four minutes in
    /// release: it leaves out the full-resolution Laikago variants, their low-res one stays).
    #[arg(long, default_value_t = 30_000)]
    pub max_triangles: usize,
    /// Skip assets with more parts than this.
    #[arg(long, default_value_t = 40)]
    pub max_parts: usize,
    /// Seed of the random rotations; in rotated pass `k`, asset `i` is rotated by the rotation
    /// of seed `seed + 1000 k + i`.
    #[arg(long, default_value_t = 2026)]
    pub seed: u64,
    /// Rotated passes after the upright one, each with its own random rotation of every asset.
    #[arg(long, default_value_t = 3)]
    pub rotations: u64,
    /// Only assets whose name contains this text.
    #[arg(long)]
    pub only: Option<String>,
    /// The whole raw-mesh path: each URDF asset merged into one mesh at rest (no parts, names
    /// or joints), `run --decompose`, the built-in grounder, and the parts paired with the true
    /// ones by shared surface before scoring (upright only; examples keep their parts).
    #[arg(long)]
    pub decompose: bool,
}
