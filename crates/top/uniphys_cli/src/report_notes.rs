//! Notes of the ingest options that changed the asset (ignored joints, a rotation), added to
//! the `notes` of `report.json` so an output directory says how it was produced.

use anyhow::Context;

/// `report.json` bytes with `notes` put first in its `notes` list; unchanged without notes.
pub(crate) fn with_notes(report_json: &[u8], notes: &[String]) -> anyhow::Result<Vec<u8>> {
    if notes.is_empty() {
        return Ok(report_json.to_vec());
    }
    let mut value: serde_json::Value =
        serde_json::from_slice(report_json).context("failed to read back report.json")?;
    let existing = value
        .get("notes")
        .and_then(serde_json::Value::as_array)
        .cloned()
        .unwrap_or_default();
    let mut all: Vec<serde_json::Value> = notes.iter().cloned().map(Into::into).collect();
    all.extend(existing);
    value["notes"] = all.into();
    let mut bytes = serde_json::to_vec_pretty(&value).context("failed to write report.json")?;
    bytes.push(b'\n');
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ingest_notes_come_first_and_other_notes_stay() {
        let report = br#"{"asset": "a", "notes": ["moved to rest"]}"#;
        let out = with_notes(report, &["ingest: rotated".to_owned()]).expect("valid json");
        let value: serde_json::Value = serde_json::from_slice(&out).expect("json");
        assert_eq!(value["notes"][0], "ingest: rotated");
        assert_eq!(value["notes"][1], "moved to rest");
        assert_eq!(with_notes(report, &[]).expect("unchanged"), report.to_vec());
    }
}
