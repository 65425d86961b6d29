//! The real PartNet-Mobility objects of the shared development set, which live beside the
//! repository (`../shared/data/partnet-mobility/`) and are never copied into it.

use std::path::PathBuf;

/// The folder of the shared object `name` (e.g. `kitchen-46236`).
///
/// # Panics
/// When the folder has no `mobility.urdf`, naming the folder, so a test that needs the shared set
/// fails saying what is missing instead of passing without it.
#[must_use]
pub fn shared_partnet_object(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../../shared/data/partnet-mobility")
        .join(name);
    assert!(
        dir.join("mobility.urdf").is_file(),
        "the shared PartNet-Mobility object {} is missing: these tests need ../shared/data/partnet-mobility beside the repository",
        dir.display()
    );
    dir
}
