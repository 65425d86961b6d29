//! A run on the asset the queue's `ingest` stage stores ([`IngestedAsset`]) exports the same
//! files, byte for byte, as a run on the file it was read from: on an example written as GLB and
//! on a real PartNet-Mobility folder (whose missing texture images the reader warns about).

use std::path::Path;

use uniphys_examples::{GlbFrame, catalogue, write_glb};
use uniphys_mesh_io::load_asset;
use uniphys_pipeline::{IngestedAsset, NoProgress, RunOptions, asset_name, run};

/// Exported files: path and bytes.
type Files = Vec<(String, Vec<u8>)>;

/// The exported files of a run on `path` and of a run on what `ingest` would store of it.
fn both_runs(path: &Path) -> (Files, Files) {
    let options = RunOptions::default();
    let files = |artifacts: Vec<uniphys_export::Artifact>| -> Files {
        artifacts.into_iter().map(|a| (a.path, a.bytes)).collect()
    };
    let from_file = run(path, &options, &NoProgress).expect("a run on the file");
    let ingested = IngestedAsset {
        name: asset_name(path),
        loaded: load_asset(path, &options.ingest).expect("readable"),
    };
    let stored =
        IngestedAsset::from_bytes(&ingested.to_bytes().expect("storable")).expect("read back");
    let from_stored = run(&stored, &options, &NoProgress).expect("a run on the stored asset");
    (files(from_file.artifacts), files(from_stored.artifacts))
}

#[test]
fn a_stored_example_exports_what_its_file_does() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cabinet = catalogue()
        .into_iter()
        .find(|e| e.name == "cabinet")
        .expect("the cabinet example");
    let path = dir.path().join("cabinet.glb");
    std::fs::write(
        &path,
        write_glb(&cabinet.asset, GlbFrame::YUp).expect("glb"),
    )
    .expect("write");
    let (from_file, from_stored) = both_runs(&path);
    assert!(from_file.len() > 5, "{} files", from_file.len());
    assert_eq!(from_file, from_stored);
}

#[test]
fn a_stored_real_object_exports_what_its_folder_does() {
    let folder = uniphys_examples::shared_partnet_object("kitchen-11622");
    let (from_file, from_stored) = both_runs(&folder);
    assert!(from_file.len() > 5, "{} files", from_file.len());
    assert_eq!(from_file, from_stored);
}
