//! The output folder of `uniphys run`, checked before any work: a folder that holds another
//! asset's result, or files that are not a result at all, is refused unless `--force`; an earlier
//! result of the same asset is replaced once the new one is ready, so no stale file of it stays.

use std::path::Path;

use anyhow::Context;

/// Checks, before any work, that `out` can take the result of the asset called `asset_name`:
/// not a file; empty, missing, or holding an earlier result of the same asset (or anything, with
/// `force`); and under a folder that is not read-only. Nothing is changed on disk.
pub(crate) fn check_out_dir(out: &Path, asset_name: &str, force: bool) -> anyhow::Result<()> {
    if out.exists() && !out.is_dir() {
        anyhow::bail!(
            "--out {} is a file, not a folder; give a folder to write the result into",
            out.display()
        );
    }
    if out.is_dir() && !is_empty(out)? && !force {
        let earlier = earlier_asset(out);
        if earlier.as_deref() != Some(asset_name) {
            let holds = match &earlier {
                Some(name) => format!("the result of another asset ({name:?})"),
                None => "files that are not a uniphys result".to_owned(),
            };
            anyhow::bail!(
                "--out {} already holds {holds}; choose an empty folder, or pass --force to clear it first",
                out.display()
            );
        }
    }
    let existing = out.ancestors().find(|a| a.exists());
    if let Some(folder) = existing
        && std::fs::metadata(folder).is_ok_and(|m| m.permissions().readonly())
    {
        anyhow::bail!("--out {}: {} is read-only", out.display(), folder.display());
    }
    Ok(())
}

/// Empties `out` (an earlier result, checked by [`check_out_dir`]) or creates it, so that no
/// stale file of an earlier run stays beside the new result.
pub(crate) fn clear_out_dir(out: &Path) -> anyhow::Result<()> {
    if out.is_dir() && !is_empty(out)? {
        std::fs::remove_dir_all(out)
            .with_context(|| format!("cannot clear the earlier result in {}", out.display()))?;
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create --out {}", out.display()))
}

fn is_empty(dir: &Path) -> anyhow::Result<bool> {
    Ok(std::fs::read_dir(dir)
        .with_context(|| format!("cannot read --out {}", dir.display()))?
        .next()
        .is_none())
}

/// The asset name of an earlier result in `dir` (its `record.json`), if it holds one.
fn earlier_asset(dir: &Path) -> Option<String> {
    let text = std::fs::read_to_string(dir.join("record.json")).ok()?;
    let record: serde_json::Value = serde_json::from_str(&text).ok()?;
    record.get("name")?.as_str().map(str::to_owned)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_or_missing_folder_is_accepted_and_a_file_is_refused() {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("new/out");
        check_out_dir(&out, "cabinet", false).expect("missing is fine");
        assert!(!out.exists(), "checking creates nothing");
        clear_out_dir(&out).expect("created");
        assert!(out.is_dir());
        let file = dir.path().join("file");
        std::fs::write(&file, b"x").expect("write");
        let err = check_out_dir(&file, "cabinet", false).expect_err("a file");
        assert!(err.to_string().contains("is a file"), "{err}");
    }

    #[test]
    fn another_assets_result_is_refused_unless_forced_and_the_same_assets_is_replaced() {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("out");
        std::fs::create_dir_all(out.join("meshes")).expect("mkdir");
        std::fs::write(out.join("record.json"), br#"{"name": "laptop"}"#).expect("write");
        std::fs::write(out.join("meshes/part_9_visual.obj"), b"stale").expect("write");
        let err = check_out_dir(&out, "cabinet", false).expect_err("another asset");
        assert!(
            err.to_string().contains("\"laptop\"") && err.to_string().contains("--force"),
            "{err}"
        );
        check_out_dir(&out, "cabinet", true).expect("forced");
        // The same asset again: accepted, and its earlier files go, so none is left stale.
        check_out_dir(&out, "laptop", false).expect("same asset");
        clear_out_dir(&out).expect("cleared");
        assert!(is_empty(&out).expect("readable"));
        std::fs::write(out.join("notes.txt"), b"mine").expect("write");
        let err = check_out_dir(&out, "laptop", false).expect_err("not a result");
        assert!(err.to_string().contains("not a uniphys result"), "{err}");
    }
}
