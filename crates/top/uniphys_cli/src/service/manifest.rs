//! A batch manifest of any size submitted in chunks: `.json` (`{"items": [...], "batch": ...}`)
//! or `.jsonl` (one item per line, read as it is sent, so memory stays one chunk whatever the
//! manifest's length). Each chunk is one `POST /v1/batches` in which a bad item is refused on
//! its own and the others go on; a busy service is waited out. Known content answers with its
//! existing job, so sending a manifest again makes no new jobs and completes one cut short.

use std::io::BufRead;
use std::path::Path;

use anyhow::{Context, bail};
use serde_json::{Value, json};

use super::client::Client;

/// Items per request (the API takes up to 1,000).
const CHUNK_ITEMS: usize = 500;

/// What became of a manifest's items.
#[derive(Debug, Default, PartialEq, Eq)]
struct Outcome {
    accepted: usize,
    known: usize,
    refused: usize,
}

/// Submits the manifest at `path` (items join `batch`, or the manifest's own batch); prints each
/// refused item with why and a summary; returns the submitted items' names and asset ids.
pub(crate) fn submit_manifest(
    client: &Client,
    path: &Path,
    batch: Option<&str>,
) -> anyhow::Result<Vec<(String, String)>> {
    let mut submitted = Vec::new();
    let mut outcome = Outcome::default();
    let mut send = |chunk: &mut Vec<Value>, first: usize, batch: Option<&str>| {
        if chunk.is_empty() {
            return Ok::<(), anyhow::Error>(());
        }
        let mut body = json!({ "items": chunk, "all_or_nothing": false });
        if let Some(batch) = batch {
            body["batch"] = json!(batch);
        }
        let answer = client.post_batch(&body)?;
        for item in answer["items"].as_array().into_iter().flatten() {
            let index = first + usize::try_from(item["index"].as_u64().unwrap_or(0))?;
            match item["status"].as_u64() {
                Some(201) => outcome.accepted += 1,
                Some(200) => outcome.known += 1,
                _ => {
                    outcome.refused += 1;
                    println!(
                        "item {index}: refused: {}",
                        item["error"]["message"].as_str().unwrap_or("?")
                    );
                    continue;
                }
            }
            let asset = item["submission"]["asset_id"].as_str().unwrap_or_default();
            submitted.push((format!("item {index}"), asset.to_owned()));
        }
        let done = first + chunk.len();
        eprintln!(
            "{done} items sent: {} new, {} already submitted, {} refused",
            outcome.accepted, outcome.known, outcome.refused
        );
        chunk.clear();
        Ok(())
    };
    let mut chunk = Vec::with_capacity(CHUNK_ITEMS);
    let mut first = 0usize;
    let jsonl = path.extension().is_some_and(|e| e == "jsonl");
    if jsonl {
        let file =
            std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
        for (number, line) in std::io::BufReader::new(file).lines().enumerate() {
            let line = line.with_context(|| format!("cannot read {}", path.display()))?;
            if line.trim().is_empty() {
                continue;
            }
            let item: Value = serde_json::from_str(&line).with_context(|| {
                format!("{} line {}: not a JSON item", path.display(), number + 1)
            })?;
            chunk.push(item);
            if chunk.len() == CHUNK_ITEMS {
                send(&mut chunk, first, batch)?;
                first += CHUNK_ITEMS;
            }
        }
        send(&mut chunk, first, batch)?;
    } else {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let manifest: Value = serde_json::from_str(&text)
            .with_context(|| format!("{} is not JSON", path.display()))?;
        let Some(items) = manifest["items"].as_array() else {
            bail!(
                "{} has no \"items\" array: a manifest is {{\"items\": [{{\"url\": ...}}], \"batch\": ...}}",
                path.display()
            );
        };
        let batch = batch.or(manifest["batch"].as_str());
        for part in items.chunks(CHUNK_ITEMS) {
            chunk.extend(part.iter().cloned());
            send(&mut chunk, first, batch)?;
            first += part.len();
        }
    }
    println!(
        "{}: {} new, {} already submitted, {} refused",
        path.display(),
        outcome.accepted,
        outcome.known,
        outcome.refused
    );
    Ok(submitted)
}
