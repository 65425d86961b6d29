//! A batch's dataset statistics (the paper's statistics figure) from its `convert` summaries:
//! counts by category, part material and joint type, and distributions of object mass, object
//! size (largest dimension) and parts per asset.
//!
//! Each summary is the `convert` stage's ([`ConvertSummary`], the type its worker writes); one
//! without `dataset` (an older stage version) counts as converted and by its parts, and one that
//! does not read as a summary at all counts as converted only.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use serde_json::Value;
use uniphys_types::ConvertSummary;
use utoipa::ToSchema;

/// Counts and distributions over a batch's converted assets.
#[derive(Clone, Debug, Default, PartialEq, Serialize, ToSchema)]
pub struct DatasetStats {
    /// Assets converted.
    pub converted: u64,
    /// Of those, assets whose every check passed.
    pub passed: u64,
    /// Assets by object category.
    pub categories: BTreeMap<String, u64>,
    /// Parts by material category.
    pub materials: BTreeMap<String, u64>,
    /// Joints by kind (`revolute`, `prismatic`, `continuous`, `fixed`).
    pub joint_types: BTreeMap<String, u64>,
    /// Object mass, kg (log-spaced bins, two per decade).
    pub mass_kg: Distribution,
    /// Largest dimension of the object, metres (log-spaced bins, four per decade).
    pub size_m: Distribution,
    /// Parts per asset (one bin per count).
    pub parts_per_asset: Distribution,
}

/// A distribution: its extent and a histogram.
#[derive(Clone, Debug, Default, PartialEq, Serialize, ToSchema)]
pub struct Distribution {
    /// Values counted.
    pub count: u64,
    /// Smallest value.
    pub min: Option<f64>,
    /// Median value.
    pub median: Option<f64>,
    /// Largest value.
    pub max: Option<f64>,
    /// Bin edges, ascending; one more than `counts`. Bin `i` holds `edges[i] <= v < edges[i+1]`
    /// (the last bin also holds its upper edge).
    pub edges: Vec<f64>,
    /// Values per bin.
    pub counts: Vec<u64>,
}

/// How a distribution's bins are laid out.
#[derive(Clone, Copy, Debug)]
enum Bins {
    /// Edges at `10^(k / per_decade)` covering the positive values.
    Log { per_decade: u32 },
    /// One bin per integer.
    Integer,
}

/// Aggregates `convert` summaries.
#[must_use]
pub fn dataset_stats(summaries: &[Value]) -> DatasetStats {
    let mut stats = DatasetStats::default();
    let mut masses = Vec::new();
    let mut sizes = Vec::new();
    let mut parts = Vec::new();
    for summary in summaries {
        stats.converted += 1;
        let Ok(summary) = ConvertSummary::deserialize(summary) else {
            continue;
        };
        if summary.passed {
            stats.passed += 1;
        }
        if summary.parts > 0 {
            #[expect(clippy::cast_precision_loss, reason = "part counts are small")]
            parts.push(summary.parts as f64);
        }
        let Some(dataset) = summary.dataset else {
            continue;
        };
        *stats.categories.entry(dataset.category).or_default() += 1;
        add_counts(&mut stats.materials, dataset.materials);
        add_counts(&mut stats.joint_types, dataset.joint_types);
        masses.push(dataset.mass_kg);
        sizes.push(dataset.size_m.into_iter().fold(f64::NEG_INFINITY, f64::max));
    }
    stats.mass_kg = distribution(masses, Bins::Log { per_decade: 2 });
    stats.size_m = distribution(sizes, Bins::Log { per_decade: 4 });
    stats.parts_per_asset = distribution(parts, Bins::Integer);
    stats
}

fn add_counts(into: &mut BTreeMap<String, u64>, counts: BTreeMap<String, u64>) {
    for (name, n) in counts {
        *into.entry(name).or_default() += n;
    }
}

fn distribution(mut values: Vec<f64>, bins: Bins) -> Distribution {
    values.retain(|v| v.is_finite() && (matches!(bins, Bins::Integer) || *v > 0.0));
    if values.is_empty() {
        return Distribution::default();
    }
    values.sort_by(f64::total_cmp);
    let (min, max) = (values[0], values[values.len() - 1]);
    let mid = values.len() / 2;
    let median = if values.len().is_multiple_of(2) {
        f64::midpoint(values[mid - 1], values[mid])
    } else {
        values[mid]
    };
    let edges: Vec<f64> = match bins {
        Bins::Log { per_decade } => {
            let step = f64::from(per_decade);
            let first = (min.log10() * step).floor();
            let last = ((max.log10() * step).floor() + 1.0).max(first + 1.0);
            let mut edges = Vec::new();
            let mut k = first;
            while k <= last {
                edges.push(10f64.powf(k / step));
                k += 1.0;
            }
            edges
        }
        Bins::Integer => {
            let mut edges = Vec::new();
            let mut v = min.floor();
            while v <= max.floor() + 1.0 {
                edges.push(v);
                v += 1.0;
            }
            edges
        }
    };
    let bins = edges.len() - 1;
    let mut counts = vec![0u64; bins];
    for v in &values {
        let bin = edges.partition_point(|edge| edge <= v).saturating_sub(1);
        counts[bin.min(bins - 1)] += 1;
    }
    Distribution {
        count: values.len() as u64,
        min: Some(min),
        median: Some(median),
        max: Some(max),
        edges,
        counts,
    }
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    fn summary(category: &str, mass_kg: f64, size_m: [f64; 3], parts: u64) -> Value {
        json!({
            "passed": mass_kg < 10.0,
            "parts": parts,
            "dataset": {
                "category": category,
                "mass_kg": mass_kg,
                "size_m": size_m,
                "materials": {"wood": parts - 1, "metal": 1},
                "joint_types": {"revolute": 1, "fixed": parts - 2},
            }
        })
    }

    #[test]
    fn counts_add_up_over_assets() {
        let stats = dataset_stats(&[
            summary("Furniture", 32.0, [0.6, 0.5, 0.8], 5),
            summary("Kitchenware", 0.3, [0.1, 0.1, 0.12], 2),
            summary("Furniture", 5.0, [0.4, 0.4, 0.4], 3),
            json!({"passed": true, "parts": 1}),
        ]);
        assert_eq!(stats.converted, 4);
        assert_eq!(stats.passed, 3);
        assert_eq!(stats.categories["Furniture"], 2);
        assert_eq!(stats.categories["Kitchenware"], 1);
        assert_eq!(stats.materials["wood"], 4 + 1 + 2);
        assert_eq!(stats.materials["metal"], 3);
        assert_eq!(stats.joint_types["revolute"], 3);
        assert_eq!(stats.joint_types["fixed"], 3 + 1);
        assert_eq!(
            stats.parts_per_asset.count, 4,
            "an older summary still has its part count"
        );
        assert_eq!(stats.mass_kg.count, 3);
        assert_eq!(stats.mass_kg.median, Some(5.0));
        assert_eq!(stats.size_m.max, Some(0.8));
    }

    #[test]
    fn what_the_worker_writes_is_what_is_counted() {
        let written = ConvertSummary {
            passed: true,
            name: "cabinet".into(),
            parts: 3,
            joints: 2,
            files: 40,
            stage_secs: BTreeMap::from([("ingest".to_owned(), 0.1)]),
            dataset: Some(uniphys_types::DatasetFacts {
                category: "Furniture".into(),
                mass_kg: 12.0,
                size_m: [0.5, 0.4, 0.9],
                materials: BTreeMap::from([("wood".to_owned(), 3)]),
                joint_types: BTreeMap::from([("revolute".to_owned(), 1), ("fixed".to_owned(), 1)]),
            }),
        };
        let value = serde_json::to_value(&written).expect("a summary serialises");
        let stats = dataset_stats(&[value, json!({"parts": "three"})]);
        assert_eq!(
            stats.converted, 2,
            "a summary that does not read still counts"
        );
        assert_eq!(stats.passed, 1);
        assert_eq!(stats.categories["Furniture"], 1);
        assert_eq!(stats.materials["wood"], 3);
        assert_eq!(stats.joint_types["revolute"], 1);
        assert_eq!(stats.mass_kg.median, Some(12.0));
        assert_eq!(stats.size_m.max, Some(0.9));
        assert_eq!(stats.parts_per_asset.count, 1);
    }

    #[test]
    fn histograms_cover_every_value_once_with_ascending_edges() {
        let masses = [0.012, 0.3, 0.31, 5.0, 32.0, 32.0, 950.0];
        let d = distribution(masses.to_vec(), Bins::Log { per_decade: 2 });
        assert_eq!(d.counts.iter().sum::<u64>(), masses.len() as u64);
        assert_eq!(d.edges.len(), d.counts.len() + 1);
        assert!(d.edges.windows(2).all(|w| w[0] < w[1]));
        assert!(d.edges[0] <= 0.012 && *d.edges.last().expect("edges") > 950.0);
        // 0.3 and 0.31 both lie in [10^-1, 10^-0.5) = [0.1, 0.316).
        let bin = |v: f64| d.edges.partition_point(|e| *e <= v) - 1;
        assert_eq!(bin(0.3), bin(0.31));
        assert_eq!(d.counts[bin(32.0)], 2);

        let parts = distribution(vec![1.0, 2.0, 2.0, 5.0], Bins::Integer);
        assert_eq!(parts.edges, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert_eq!(parts.counts, [1, 2, 0, 0, 1]);
        assert_eq!(parts.median, Some(2.0));
    }

    #[test]
    fn nothing_to_count_gives_empty_distributions() {
        let stats = dataset_stats(&[]);
        assert_eq!(stats, DatasetStats::default());
        let d = distribution(vec![f64::NAN, -1.0, 0.0], Bins::Log { per_decade: 2 });
        assert_eq!(d.count, 0);
        assert!(d.counts.is_empty());
    }
}
