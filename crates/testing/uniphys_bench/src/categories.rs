//! The category of every object of a PartNet-Mobility set, from its `INDEX.tsv`; shared by the
//! benchmarks that print per-category rows.

use std::collections::BTreeMap;
use std::path::Path;

/// Folder name -> category from `INDEX.tsv` (its `dir` and `category` columns).
pub(crate) fn read_categories(root: &Path) -> BTreeMap<String, String> {
    let Ok(text) = std::fs::read_to_string(root.join("INDEX.tsv")) else {
        return BTreeMap::new();
    };
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split('\t').collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let (Some(dir), Some(category)) = (column("dir"), column("category")) else {
        return BTreeMap::new();
    };
    lines
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('\t').collect();
            Some((
                (*cells.get(dir)?).to_owned(),
                (*cells.get(category)?).to_owned(),
            ))
        })
        .collect()
}
