//! `uniphys dataset export`: a batch written out as a UniPhys-40K dataset, over the API.
//!
//! Every succeeded asset of the batch becomes an entity folder `<out>/<batch>/<type>/<entity>/`
//! (the convert stage's files: `parts/`, `annotations/`, `meta_data.json`, the URDF and MJCF,
//! record and report) with the UniPhysGen model inputs (`npzs/`, `coordinate_frame.json`).
//! Beside them: `index.csv` (one row per exported asset), `failures.csv` (dead and cancelled
//! jobs with their last error) and `statistics.json` (the batch's statistics).
//!
//! Resumable and safe while the batch runs: an entity is downloaded into `.partial/` and moved
//! into place only when whole (every file's SHA-256 checked), so an entity folder that exists is
//! complete and is not fetched again; assets still running are counted and left for a later run.
//!
//! With `--in-store`, the service writes the same layout (without the npz inputs) into its own
//! object store (`POST /v1/batches/{batch}/export`) and this command follows its progress.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use serde_json::Value;
use uniphys_api::dataset_layout::{self as layout, FAILURE_COLUMNS, INDEX_COLUMNS};

use super::client::{Client, ClientArgs};

/// `uniphys dataset export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// The API and the key.
    #[command(flatten)]
    pub client: ClientArgs,
    /// The batch to export (its label, as given to `uniphys submit --batch`).
    #[arg(long)]
    pub batch: String,
    /// The dataset root: the batch is written to `<out>/<batch>/`.
    #[arg(
        long,
        required_unless_present = "in_store",
        conflicts_with = "in_store"
    )]
    pub out: Option<PathBuf>,
    /// Leave out the UniPhysGen model inputs (npz point clouds), which take a few seconds per
    /// asset.
    #[arg(long)]
    pub no_npz: bool,
    /// Have the service write the dataset into its object store (`datasets/t{tenant}/{batch}/`,
    /// without the npz inputs) and follow its progress, instead of downloading it here.
    #[arg(long)]
    pub in_store: bool,
}

/// `uniphys dataset` actions.
#[derive(Debug, clap::Subcommand)]
pub enum DatasetAction {
    /// Write a batch's succeeded assets as a UniPhys-40K dataset, with an index, the failures
    /// and the statistics; run it again to add what finished since.
    Export(ExportArgs),
}

/// Where the export stands.
#[derive(Debug, Default)]
struct Tally {
    exported_now: usize,
    already_there: usize,
    running: usize,
    failed: usize,
}

/// `uniphys dataset export`.
pub fn export(args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let client = Client::new(&args.client)?;
    let batch = &args.batch;
    let Some(out) = &args.out else {
        return export_in_store(&client, batch);
    };
    let statistics = client.get(&format!("/v1/batches/{batch}/stats"))?;
    let root = out.join(batch);
    std::fs::create_dir_all(&root).with_context(|| format!("cannot create {}", root.display()))?;
    let mut done = complete_entities(&root)?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut tally = Tally::default();
    let mut before: Option<String> = None;
    loop {
        let mut path = format!("/v1/assets?batch={batch}&limit=1000");
        if let Some(cursor) = &before {
            path.push_str(&format!("&before={cursor}"));
        }
        let page = client.get(&path)?;
        for item in page["items"].as_array().into_iter().flatten() {
            let text = |key: &str| item[key].as_str().unwrap_or_default().to_owned();
            let (asset, job, file) = (text("asset_id"), text("job_id"), text("file_name"));
            match item["state"].as_str().unwrap_or_default() {
                "succeeded" => {
                    let entity = layout::entity_name(&file, &asset);
                    let place = if let Some(place) = done.get(&entity) {
                        tally.already_there += 1;
                        place.clone()
                    } else {
                        let place = export_entity(&client, &root, &asset, &entity, !args.no_npz)
                            .with_context(|| format!("exporting {asset} ({file})"))?;
                        tally.exported_now += 1;
                        eprintln!("{asset} ({file}): {place}");
                        done.insert(entity, place.clone());
                        place
                    };
                    rows.push(index_row(&root, &place, &asset, &job, &file)?);
                }
                "running" => tally.running += 1,
                state => {
                    tally.failed += 1;
                    failures.push(failure_row(&client, &asset, &job, &file, state)?);
                }
            }
        }
        match page["next"].as_str() {
            Some(next) => before = Some(next.to_owned()),
            None => break,
        }
    }
    rows.sort();
    failures.sort();
    write_csv(&root.join("index.csv"), INDEX_COLUMNS, &rows)?;
    write_csv(&root.join("failures.csv"), FAILURE_COLUMNS, &failures)?;
    let stats_path = root.join("statistics.json");
    std::fs::write(&stats_path, serde_json::to_string_pretty(&statistics)?)
        .with_context(|| format!("cannot write {}", stats_path.display()))?;
    println!(
        "batch {batch}: {} assets in {} ({} new, {} already there); {} still running (run again to add them); {} failed (failures.csv)",
        rows.len(),
        root.display(),
        tally.exported_now,
        tally.already_there,
        tally.running,
        tally.failed
    );
    Ok(ExitCode::SUCCESS)
}

/// `uniphys dataset export --in-store`: starts the service's export and prints its progress
/// until it ends.
fn export_in_store(client: &Client, batch: &str) -> anyhow::Result<ExitCode> {
    let path = format!("/v1/batches/{batch}/export");
    let mut view = client.post(&path)?;
    let mut last = String::new();
    while view["state"] == "running" {
        let line = format!(
            "{}: {} jobs read, {} exported, {} already there",
            view["prefix"].as_str().unwrap_or_default(),
            view["jobs_read"],
            view["exported"],
            view["already_there"]
        );
        if line != last {
            eprintln!("{line}");
            last = line;
        }
        std::thread::sleep(std::time::Duration::from_secs(1));
        view = client.get(&path)?;
    }
    if view["state"] != "finished" {
        bail!(
            "the service's export of {batch} failed: {}",
            view["error"].as_str().unwrap_or("no reason given")
        );
    }
    println!(
        "batch {batch}: {} new and {} already there in the object store under {}; {} still running (run again to add them); {} failed (failures.csv)",
        view["exported"],
        view["already_there"],
        view["prefix"].as_str().unwrap_or_default(),
        view["still_running"],
        view["failed"]
    );
    Ok(ExitCode::SUCCESS)
}

/// The entities already exported under `root`: entity name to `<type>/<entity>`.
fn complete_entities(root: &Path) -> anyhow::Result<BTreeMap<String, String>> {
    let mut found = BTreeMap::new();
    for kind in read_dirs(root)? {
        let name = kind.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        for entity in read_dirs(&kind.path())? {
            let entity = entity.file_name().to_string_lossy().into_owned();
            found.insert(entity.clone(), format!("{name}/{entity}"));
        }
    }
    Ok(found)
}

fn read_dirs(dir: &Path) -> anyhow::Result<Vec<std::fs::DirEntry>> {
    let mut dirs = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        let entry = entry?;
        if entry.file_type()?.is_dir() {
            dirs.push(entry);
        }
    }
    Ok(dirs)
}

/// Downloads the convert stage's files of `asset` into `.partial/<entity>`, checks each against
/// its SHA-256, adds the model inputs, and moves the folder to `<type>/<entity>` (the type from
/// the object's category); returns that relative place.
fn export_entity(
    client: &Client,
    root: &Path,
    asset: &str,
    entity: &str,
    npz: bool,
) -> anyhow::Result<String> {
    let partial = root.join(".partial").join(entity);
    if partial.exists() {
        std::fs::remove_dir_all(&partial)
            .with_context(|| format!("cannot clear {}", partial.display()))?;
    }
    let listing = client.get(&format!("/v1/assets/{asset}/artifacts"))?;
    let mut files = 0usize;
    for item in listing["items"].as_array().into_iter().flatten() {
        if item["stage"] != layout::ENTITY_STAGE {
            continue;
        }
        let name = item["name"].as_str().unwrap_or_default();
        let components = uniphys_archive::entry_path::safe_components(name)
            .map_err(|why| anyhow::anyhow!("the API named a file {name:?}: {why}"))?;
        let dest = components.iter().fold(partial.clone(), |p, c| p.join(c));
        if let Some(parent) = dest.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create {}", parent.display()))?;
        }
        let href = item["href"].as_str().unwrap_or_default();
        let (sha256, _) = client.download(href, &dest)?;
        if item["sha256"].as_str() != Some(sha256.as_str()) {
            bail!("{name} arrived with another SHA-256 than the API lists; run the export again");
        }
        files += 1;
    }
    if files == 0 {
        bail!("the API lists no converted files for {asset}");
    }
    if npz {
        crate::points_cmd::write_model_inputs(&partial.join("model.urdf"), &partial)
            .context("writing the UniPhysGen model inputs")?;
    }
    let object: Value = read_json(&partial.join("annotations/object.json"))?;
    let kind = layout::type_name(object["category"].as_str().unwrap_or_default());
    let place = format!("{kind}/{entity}");
    let target = root.join(&kind);
    std::fs::create_dir_all(&target)
        .with_context(|| format!("cannot create {}", target.display()))?;
    std::fs::rename(&partial, target.join(entity))
        .with_context(|| format!("cannot move {} into place", partial.display()))?;
    Ok(place)
}

fn read_json(path: &Path) -> anyhow::Result<Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{} is not JSON", path.display()))
}

/// One row of `index.csv`, read from the exported entity.
fn index_row(
    root: &Path,
    place: &str,
    asset: &str,
    job: &str,
    file: &str,
) -> anyhow::Result<Vec<String>> {
    let dir = root.join(place);
    let record = read_json(&dir.join("record.json"))?;
    let report = read_json(&dir.join("report.json"))?;
    let npz_files = std::fs::read_dir(dir.join("npzs")).map_or(0, Iterator::count);
    Ok(layout::index_row(&layout::IndexEntry {
        place,
        asset,
        job,
        source_file: file,
        record: &record,
        report: &report,
        npz_files,
    }))
}

/// One row of `failures.csv`: the stage that failed and its last error.
fn failure_row(
    client: &Client,
    asset: &str,
    job: &str,
    file: &str,
    state: &str,
) -> anyhow::Result<Vec<String>> {
    let detail = client.get(&format!("/v1/jobs/{job}"))?;
    let failed = detail["stages"]
        .as_array()
        .into_iter()
        .flatten()
        .find(|s| s["state"] == "dead" || s["state"] == "cancelled");
    let stage = failed
        .and_then(|s| s["name"].as_str())
        .unwrap_or_default()
        .to_owned();
    let error = failed
        .and_then(|s| s["errors"].as_array())
        .and_then(|e| e.last())
        .and_then(|e| e["message"].as_str())
        .unwrap_or_default()
        .to_owned();
    Ok(vec![
        asset.to_owned(),
        job.to_owned(),
        file.to_owned(),
        state.to_owned(),
        stage,
        error,
    ])
}

/// Writes a CSV table with a header.
fn write_csv(path: &Path, columns: &[&str], rows: &[Vec<String>]) -> anyhow::Result<()> {
    std::fs::write(path, layout::csv_text(columns, rows))
        .with_context(|| format!("cannot write {}", path.display()))
}
