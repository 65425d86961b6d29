//! The UniPhys-40K layout a batch is exported in, shared by `POST /v1/batches/{batch}/export`
//! (into the object store) and `uniphys dataset export` (into a folder): one entity folder per
//! asset, `<type>/<entity>/`, holding the convert stage's files; `index.csv` with one row per
//! exported asset; `failures.csv` with the jobs that did not succeed; `statistics.json`.

use serde_json::Value;
use uniphys_types::ServiceStage;

/// The stage whose files make an asset's entity folder.
pub const ENTITY_STAGE: &str = ServiceStage::Convert.name();

/// The folder name of an asset's entity: its file's stem (letters, digits, `-`, `_`; other
/// characters become `_`) and its id, so it is unique in the batch.
#[must_use]
pub fn entity_name(file_name: &str, asset: &str) -> String {
    let stem = file_name
        .strip_suffix(".tar.gz")
        .or_else(|| file_name.rsplit_once('.').map(|(s, _)| s))
        .unwrap_or(file_name);
    let stem: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{stem}_{asset}")
}

/// The type folder of a category: its last level, letters, digits, `-` and `_` only
/// (`KitchenDining/KitchenAppliance` → `KitchenAppliance`); `Unknown` when nothing is left.
#[must_use]
pub fn type_name(category: &str) -> String {
    let last = category.rsplit('/').next().unwrap_or_default();
    let clean: String = last
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
        .collect();
    if clean.is_empty() {
        "Unknown".to_owned()
    } else {
        clean
    }
}

/// Columns of `index.csv`.
pub const INDEX_COLUMNS: &[&str] = &[
    "entity",
    "asset_id",
    "job_id",
    "source_file",
    "category",
    "mass_kg",
    "parts",
    "movable_joints",
    "revolute",
    "prismatic",
    "continuous",
    "verification_passed",
    "joint_providers",
    "npz_files",
];

/// What one row of `index.csv` is made of.
#[derive(Debug)]
pub struct IndexEntry<'a> {
    /// `<type>/<entity>`, relative to the batch's folder.
    pub place: &'a str,
    /// `asset_<n>`.
    pub asset: &'a str,
    /// `job_<n>`.
    pub job: &'a str,
    /// The submitted file's name.
    pub source_file: &'a str,
    /// The entity's `record.json`.
    pub record: &'a Value,
    /// The entity's `report.json`.
    pub report: &'a Value,
    /// UniPhysGen model inputs written beside it.
    pub npz_files: usize,
}

/// One row of `index.csv`, in [`INDEX_COLUMNS`] order: category and mass from the record, its
/// movable joints by kind and who chose them, and the verification verdict.
#[must_use]
pub fn index_row(entry: &IndexEntry<'_>) -> Vec<String> {
    let joints: Vec<&Value> = entry.record["joints"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|j| j["kind"] != "fixed")
        .collect();
    let count = |kind: &str| joints.iter().filter(|j| j["kind"] == kind).count();
    let mut providers: Vec<String> = joints
        .iter()
        .map(|j| {
            let p = &j["provenance"];
            p["name"]
                .as_str()
                .or_else(|| p["kind"].as_str())
                .unwrap_or("unknown")
                .to_owned()
        })
        .collect();
    providers.sort();
    providers.dedup();
    vec![
        entry.place.to_owned(),
        entry.asset.to_owned(),
        entry.job.to_owned(),
        entry.source_file.to_owned(),
        entry.record["object"]["category"]["value"]
            .as_str()
            .unwrap_or_default()
            .to_owned(),
        entry.record["object"]["mass_kg"]["value"]
            .as_f64()
            .map_or_else(String::new, |m| format!("{m:.4}")),
        entry.record["parts"]
            .as_array()
            .map_or(0, Vec::len)
            .to_string(),
        joints.len().to_string(),
        count("revolute").to_string(),
        count("prismatic").to_string(),
        count("continuous").to_string(),
        entry.report["passed"]
            .as_bool()
            .unwrap_or(false)
            .to_string(),
        providers.join(" "),
        entry.npz_files.to_string(),
    ]
}

/// Columns of `failures.csv`: the job, the stage that failed and its last error.
pub const FAILURE_COLUMNS: &[&str] = &[
    "asset_id",
    "job_id",
    "source_file",
    "state",
    "stage",
    "error",
];

/// A CSV table with a header line; fields with commas, quotes or line breaks are quoted.
#[must_use]
pub fn csv_text(columns: &[&str], rows: &[Vec<String>]) -> String {
    let field = |f: &str| {
        if f.contains([',', '"', '\n', '\r']) {
            format!("\"{}\"", f.replace('"', "\"\""))
        } else {
            f.to_owned()
        }
    };
    let mut text = columns.join(",");
    text.push('\n');
    for row in rows {
        let fields: Vec<String> = row.iter().map(|f| field(f)).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    #[test]
    fn entities_are_named_by_file_and_id_and_typed_by_category() {
        assert_eq!(
            entity_name("kitchen-7236.tar.gz", "asset_1"),
            "kitchen-7236_asset_1"
        );
        assert_eq!(entity_name("my chair.glb", "asset_12"), "my_chair_asset_12");
        assert_eq!(
            type_name("KitchenDining/KitchenAppliance"),
            "KitchenAppliance"
        );
        assert_eq!(type_name("../"), "Unknown");
    }

    #[test]
    fn csv_fields_with_commas_and_quotes_are_quoted() {
        let rows = vec![vec![
            "a,b".to_owned(),
            "say \"hi\"".to_owned(),
            "plain".to_owned(),
        ]];
        assert_eq!(
            csv_text(&["one", "two", "three"], &rows),
            "one,two,three\n\"a,b\",\"say \"\"hi\"\"\",plain\n"
        );
    }

    #[test]
    fn an_index_row_counts_movable_joints_by_kind_and_names_their_providers() {
        let record = json!({
            "object": {"category": {"value": "Furniture/Cabinet"}, "mass_kg": {"value": 12.5}},
            "parts": [{}, {}, {}],
            "joints": [
                {"kind": "fixed", "provenance": {"kind": "default"}},
                {"kind": "revolute", "provenance": {"kind": "estimated", "name": "builtin-grounder"}},
                {"kind": "prismatic", "provenance": {"kind": "read"}},
            ],
        });
        let report = json!({"passed": true});
        let row = index_row(&IndexEntry {
            place: "Cabinet/c_asset_1",
            asset: "asset_1",
            job: "job_1",
            source_file: "c.glb",
            record: &record,
            report: &report,
            npz_files: 2,
        });
        assert_eq!(
            row,
            [
                "Cabinet/c_asset_1",
                "asset_1",
                "job_1",
                "c.glb",
                "Furniture/Cabinet",
                "12.5000",
                "3",
                "2",
                "1",
                "1",
                "0",
                "true",
                "builtin-grounder read",
                "2"
            ]
        );
        assert_eq!(row.len(), INDEX_COLUMNS.len());
    }
}
