use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use uniphys_types::UpAxis;

use crate::lvlm_args::LvlmArgs;

/// Turn raw 3D assets into simulation-ready assets.
#[derive(Debug, Parser)]
#[command(name = "uniphys", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the whole pipeline on one asset in this process (no database, no network).
    Run(RunArgs),
    /// Export an earlier result again (its URDF, MJCF and USD and their meshes, or everything)
    /// from its own files, without running the pipeline: after an update of the exporter, or to
    /// write one simulator's files elsewhere.
    Export(ExportArgs),
    /// Print the mass properties of every part of a mesh file as JSON: exact (closed meshes) and
    /// voxelised, in the file's own coordinates (no up-axis change).
    Measure {
        /// The mesh file.
        mesh: PathBuf,
        /// Voxels along the longest side of each part.
        #[arg(long, default_value_t = 128)]
        voxel_resolution: usize,
    },
    /// Write the UniPhysGen point clouds of an asset (object and parts) as npz files in the
    /// reference layout, with the coordinate frame of the model's answers.
    Points(PointsArgs),
    /// Evaluate predictions (our record.json) against ground truth with the paper's metrics:
    /// joint type, axis, pivot and limit; motion-coupled groups; part physics; object values.
    Eval(EvalArgs),
    /// Run the service in one process: HTTP API and workers, on SQLite and a local directory
    /// unless configured otherwise (`UNIPHYS_DATABASE_URL`, `UNIPHYS_STORAGE_URL`, `UNIPHYS_REDIS_URL`).
    Serve(crate::service::server_args::ServeArgs),
    /// Run the HTTP API alone (workers run elsewhere).
    Api(crate::service::server_args::ApiOnlyArgs),
    /// Run workers alone: claim stage runs from the queue and run them.
    Worker(crate::service::server_args::WorkerOnlyArgs),
    /// Apply the queue database's migrations.
    Migrate(crate::service::config::ServiceArgs),
    /// Manage tenants and their API keys.
    Tenant {
        /// What to do.
        #[command(subcommand)]
        action: TenantAction,
    },
    /// Pause or resume claims of a stage across the fleet (running work finishes).
    Stage {
        /// What to do.
        #[command(subcommand)]
        action: StageAction,
    },
    /// Submit asset files (uploads) or a batch manifest to the API; `--watch` follows them.
    Submit(crate::service::client::SubmitArgs),
    /// Show the newest jobs, or one asset's stages.
    Status(crate::service::client::StatusArgs),
    /// Get a batch out of the service as a dataset (UniPhys-40K layout, model inputs, index).
    Dataset {
        /// What to do.
        #[command(subcommand)]
        action: crate::service::dataset::DatasetAction,
    },
    /// Write the example assets (cabinet, laptop, box with lid, mug) as GLB files.
    Examples {
        /// Output directory.
        #[arg(long, default_value = "test_data/examples")]
        out: PathBuf,
    },
}

/// Arguments of `uniphys export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// A folder `uniphys run` wrote (or a dataset entry of the same layout).
    pub result: PathBuf,
    /// The files to write.
    #[arg(long, value_enum, default_value_t = ExportFormat::All)]
    pub format: ExportFormat,
    /// Where to write them (created if missing); the result folder itself when not given. Files
    /// of the chosen format are replaced (each whole or not at all), others left as they are;
    /// `--format all` also removes files in `meshes/`, `parts/` and `annotations/` that it no
    /// longer writes.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// What `uniphys export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// `model.urdf` with its link meshes and textures, and `model.srdf` (the contacts that are off).
    Urdf,
    /// `model.xml` (MJCF) with its link meshes and textures.
    Mjcf,
    /// `model.usda` with the textures it reads (its meshes are inside the stage).
    Usd,
    /// Every file of the export: the three models and the SRDF, meshes, parts, record, annotations and report.
    All,
}

/// Tenant actions.
#[derive(Debug, Subcommand)]
pub enum TenantAction {
    /// Create a tenant and print a new API key for it (an existing tenant only with
    /// `--rotate-key`).
    Create {
        /// The tenant's name: letters, digits, '.', '_' and '-', at most 64.
        name: String,
        /// The tenant exists: revoke its keys and print a new one.
        #[arg(long)]
        rotate_key: bool,
        /// Where the queue state lives.
        #[command(flatten)]
        service: crate::service::config::ServiceArgs,
    },
}

/// Stage actions.
#[derive(Debug, Subcommand)]
pub enum StageAction {
    /// Stop claiming runs of a stage.
    Pause {
        /// The stage.
        stage: String,
        /// Where the queue state lives.
        #[command(flatten)]
        service: crate::service::config::ServiceArgs,
    },
    /// Claim runs of a stage again.
    Resume {
        /// The stage.
        stage: String,
        /// Where the queue state lives.
        #[command(flatten)]
        service: crate::service::config::ServiceArgs,
    },
    /// List paused stages.
    Paused {
        /// Where the queue state lives.
        #[command(flatten)]
        service: crate::service::config::ServiceArgs,
    },
    /// Run one stage alone on a local file, without servers (stages: decompose).
    Run {
        /// The stage.
        stage: String,
        /// Its input and options.
        #[command(flatten)]
        args: StageRunArgs,
    },
}

/// Arguments of `uniphys stage run`.
#[derive(Debug, clap::Args)]
pub struct StageRunArgs {
    /// The asset: .glb, .gltf, .obj, .ply, .stl, .urdf, or a folder with one URDF.
    pub asset: PathBuf,
    /// Output directory (created if missing); decompose writes parts/part_<i>.obj, parts.obj,
    /// face_parts.json and decompose.json.
    #[arg(long)]
    pub out: PathBuf,
    /// Up axis of the input coordinates.
    #[arg(long, value_enum, default_value_t = UpArg::Auto)]
    pub up: UpArg,
    /// Unit of the input coordinates: m, cm, mm, in, ft, or metres per unit as a number.
    #[arg(long, default_value = "m")]
    pub unit: String,
    /// Refuse inputs with more triangles than this.
    #[arg(long, default_value_t = 2_000_000)]
    pub max_triangles: usize,
    /// Views rendered around the object.
    #[arg(long, default_value_t = 8)]
    pub views: usize,
    /// Width and height of every view, pixels.
    #[arg(long, default_value_t = 512)]
    pub resolution_px: u32,
    /// Threads segmenting the views (the result does not depend on it).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Seed for anything random (same input and seed, same parts).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Segment the views with a SAM-compatible mask service at this URL (e.g. http://sam:8000)
    /// instead of the built-in render-space segmenter.
    #[arg(long)]
    pub sam_url: Option<String>,
    /// Take per-face features from a PartField-compatible service at this URL instead of the
    /// built-in geometric features.
    #[arg(long)]
    pub partfield_url: Option<String>,
}

/// Up axis of the input.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum UpArg {
    /// The format's convention (glTF and OBJ: Y; PLY, STL and URDF: Z).
    Auto,
    /// +Y is up.
    Y,
    /// +Z is up.
    Z,
}

/// Arguments of `uniphys run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The asset: .glb, .gltf, .obj, .ply, .stl, .urdf, or a folder with one URDF (PartNet-Mobility style).
    pub asset: PathBuf,
    /// Output directory (created if missing). A folder holding an earlier result of the same
    /// asset is cleared first; one holding anything else is refused unless `--force`.
    #[arg(long)]
    pub out: PathBuf,
    /// Clear the output folder first, whatever it holds.
    #[arg(long)]
    pub force: bool,
    /// Up axis of the input coordinates.
    #[arg(long, value_enum, default_value_t = UpArg::Auto)]
    pub up: UpArg,
    /// Unit of the input coordinates: m, cm, mm, in, ft, a number of metres per unit, or auto:
    /// a PartNet-Mobility folder (normalised coordinates) is scaled to the typical size of its
    /// kind, and an input whose size in metres is implausible for its kind is read in the
    /// common unit that fits; any other input is in metres.
    #[arg(long, default_value = "auto")]
    pub unit: String,
    /// Refuse inputs with more triangles than this.
    #[arg(long, default_value_t = 2_000_000)]
    pub max_triangles: usize,
    /// Voxels along the longest side of a part, for volumes of open meshes.
    #[arg(long, default_value_t = 128)]
    pub voxel_resolution: usize,
    /// Most convex hulls per part in the colliders.
    #[arg(long, default_value_t = 16)]
    pub max_hulls: usize,
    /// Ground with the UniPhysGen model server at this URL (e.g. http://gpu-node:8000) instead of
    /// the built-in grounder's estimates; the articulation tree still comes from the input or the
    /// geometric heuristic.
    #[arg(long, env = "UNIPHYSGEN_URL")]
    pub uniphysgen_url: Option<String>,
    /// GPU slots this process may hold on the model server at once.
    #[arg(long, default_value_t = 1)]
    pub uniphysgen_slots: usize,
    /// The LVLM, if any.
    #[command(flatten)]
    pub lvlm: LvlmArgs,
    /// Drop the joints an articulated input (URDF) declares, keeping its parts and their names,
    /// so that the grounder infers the articulation (noted in report.json).
    #[arg(long)]
    pub ignore_joints: bool,
    /// Decompose the input into parts right after ingest (built-in segmenter and generator, 8
    /// views at 512 px), for meshes given in one piece or in fragments; the decomposed parts
    /// replace the input's and its declared joints are dropped.
    #[arg(long)]
    pub decompose: bool,
    /// Rotate the whole asset by a uniformly random rotation drawn from this seed, after the
    /// unit and up-axis conversion (noted in report.json; give the same seed to `uniphys eval`).
    #[arg(long, value_name = "SEED")]
    pub rotate_seed: Option<u64>,
    /// Print the run summary as JSON on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `uniphys eval`. Predictions and ground truths are paired in order.
#[derive(Debug, clap::Args)]
pub struct EvalArgs {
    /// Predictions: record.json files or `uniphys run` output directories.
    #[arg(long, required = true, num_args = 1..)]
    pub pred: Vec<PathBuf>,
    /// Ground truths, one per prediction: URDF files or folders (PartNet-Mobility style),
    /// record.json files or output directories, or UniPhys-40K entity directories.
    #[arg(long, required = true, num_args = 1..)]
    pub gt: Vec<PathBuf>,
    /// Up axis of URDF ground truths, as given to `uniphys run`.
    #[arg(long, value_enum, default_value_t = UpArg::Auto)]
    pub up: UpArg,
    /// Unit of URDF ground truths, as given to `uniphys run`.
    #[arg(long, default_value = "m")]
    pub unit: String,
    /// Rotate URDF ground truths by the rotation of this seed, as given to `uniphys run`.
    #[arg(long, value_name = "SEED")]
    pub rotate_seed: Option<u64>,
    /// Print the report as JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Also list every ground-truth movable joint next to the predicted one (a table, or a
    /// `joints` array with `--json`).
    #[arg(long)]
    pub per_joint: bool,
    /// How predicted parts are paired with true parts.
    #[arg(long, value_enum, default_value_t = MatchParts::Name)]
    pub match_parts: MatchParts,
}

/// How `uniphys eval` pairs predicted parts with true parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MatchParts {
    /// By part name (a run that kept the input's parts).
    Name,
    /// By shared surface, one to one, at least half the union shared (a run that decomposed
    /// the mesh into parts of its own: `uniphys run --decompose`); reads each prediction's
    /// `parts/part_<id>.obj`, and needs a URDF or an output directory as ground truth.
    Overlap,
}

impl UpArg {
    /// The up axis, `None` for the format's convention.
    #[must_use]
    pub fn up_axis(self) -> Option<UpAxis> {
        match self {
            Self::Auto => None,
            Self::Y => Some(UpAxis::Y),
            Self::Z => Some(UpAxis::Z),
        }
    }
}

/// Arguments of `uniphys points`.
#[derive(Debug, clap::Args)]
pub struct PointsArgs {
    /// The asset (any format `uniphys run` reads), ingested with the default options.
    pub asset: PathBuf,
    /// Output directory: `npzs/model.npz`, `npzs/<part index>.npz`, `coordinate_frame.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of the surface sampling.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Points on the whole object.
    #[arg(long, default_value_t = 100_000)]
    pub object_points: usize,
    /// Fewest points on a part (parts get their area share of the object points, at least this).
    #[arg(long, default_value_t = 10_000)]
    pub min_part_points: usize,
    /// Voxels per axis of the model grid (the released checkpoints use 256).
    #[arg(long, default_value_t = 256)]
    pub num_bins: u32,
}

/// Whether a `--unit` value asks for `auto`.
pub fn unit_is_auto(unit: &str) -> bool {
    unit.trim().eq_ignore_ascii_case("auto")
}

/// Metres per unit for a `--unit` value (`auto` reads coordinates as metres; the pipeline then
/// rescales when it should).
pub fn metres_per_unit(unit: &str) -> anyhow::Result<f64> {
    if unit_is_auto(unit) {
        return Ok(1.0);
    }
    let value = match unit.trim().to_ascii_lowercase().as_str() {
        "m" | "meter" | "metre" | "meters" | "metres" => 1.0,
        "cm" => 0.01,
        "mm" => 0.001,
        "in" | "inch" | "inches" => 0.0254,
        "ft" | "foot" | "feet" => 0.3048,
        other => other.parse::<f64>().map_err(|_| {
            anyhow::anyhow!(
                "unknown unit {unit:?}: use auto, m, cm, mm, in, ft, or a number of metres per unit"
            )
        })?,
    };
    if !(value.is_finite() && value > 0.0) {
        anyhow::bail!("unit {unit:?} must give a positive number of metres per unit");
    }
    Ok(value)
}
