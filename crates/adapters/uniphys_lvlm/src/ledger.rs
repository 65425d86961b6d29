use std::collections::BTreeMap;
use std::sync::{Mutex, PoisonError};

use crate::{ChatRequest, LvlmConfig, LvlmError, LvlmResult, Usage};

/// Prompt tokens assumed for an image whose PNG header cannot be read: a 768 x 1536 image in
/// OpenAI's high-detail accounting (85 + 170 per 512 px tile, 6 tiles).
pub const IMAGE_TOKENS_FALLBACK: u64 = 85 + 170 * 6;

/// Completion tokens assumed for the budget check when `max_completion_tokens` is unset
/// (reasoning models at `medium` effort typically spend a few thousand).
pub const COMPLETION_TOKENS_ESTIMATE: u64 = 4096;

/// Prompt tokens of one PNG image in OpenAI's high-detail accounting: the image is scaled to
/// fit 2048 x 2048, then down so its shorter side is at most 768 px; it costs 85 tokens plus
/// 170 per 512 px tile. Other servers count differently; this is an estimate for the budget.
#[must_use]
pub fn image_tokens_estimate(png: &[u8]) -> u64 {
    let Some((width_px, height_px)) = png_size_px(png) else {
        return IMAGE_TOKENS_FALLBACK;
    };
    let (mut w, mut h) = (f64::from(width_px), f64::from(height_px));
    let fit = (2048.0 / w.max(h)).min(1.0);
    w *= fit;
    h *= fit;
    let short = (768.0 / w.min(h)).min(1.0);
    w *= short;
    h *= short;
    let tiles = (w / 512.0).ceil() * (h / 512.0).ceil();
    85 + 170 * tiles as u64
}

/// Width and height from a PNG's IHDR chunk.
fn png_size_px(png: &[u8]) -> Option<(u32, u32)> {
    if png.len() < 24 || &png[12..16] != b"IHDR" {
        return None;
    }
    let width = u32::from_be_bytes(png[16..20].try_into().ok()?);
    let height = u32::from_be_bytes(png[20..24].try_into().ok()?);
    (width > 0 && height > 0).then_some((width, height))
}

/// Estimated prompt tokens of a request: one token per 4 characters of text (system and user),
/// rounded up, plus [`image_tokens_estimate`] per image.
#[must_use]
pub fn estimate_prompt_tokens(request: &ChatRequest) -> u64 {
    let chars = request.system.chars().count() + request.user_text.chars().count();
    let text_tokens = (chars as u64).div_ceil(4);
    text_tokens
        + request
            .images_png
            .iter()
            .map(|png| image_tokens_estimate(png))
            .sum::<u64>()
}

/// Estimated cost of a request in USD under `config`: [`estimate_prompt_tokens`] in, and
/// `max_completion_tokens` (or [`COMPLETION_TOKENS_ESTIMATE`]) out.
#[must_use]
pub(crate) fn estimate_cost_usd(request: &ChatRequest, config: &LvlmConfig) -> f64 {
    let completion = config
        .max_completion_tokens
        .map_or(COMPLETION_TOKENS_ESTIMATE, u64::from);
    config
        .pricing
        .cost_usd(estimate_prompt_tokens(request), completion)
}

/// Totals of one purpose (or of the whole asset).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PurposeSummary {
    /// Answers received from the server (cached answers not included).
    pub calls: u64,
    /// Answers served from the cache (no cost).
    pub cache_hits: u64,
    /// Failed attempts that were retried.
    pub retries: u64,
    /// Requests that failed for good (attempts exhausted or a non-retryable error).
    pub failures: u64,
    /// Requests refused before sending because of the budget.
    pub refused_for_budget: u64,
    /// Prompt tokens paid for (failed attempts that reported usage included).
    pub prompt_tokens: u64,
    /// Completion tokens paid for.
    pub completion_tokens: u64,
    /// Reasoning tokens among them, where reported.
    pub reasoning_tokens: u64,
    /// Attempts whose usage was estimated because the server reported none.
    pub estimated_usages: u64,
    /// Cost in USD.
    pub cost_usd: f64,
}

impl PurposeSummary {
    fn add(&mut self, other: &Self) {
        self.calls += other.calls;
        self.cache_hits += other.cache_hits;
        self.retries += other.retries;
        self.failures += other.failures;
        self.refused_for_budget += other.refused_for_budget;
        self.prompt_tokens += other.prompt_tokens;
        self.completion_tokens += other.completion_tokens;
        self.reasoning_tokens += other.reasoning_tokens;
        self.estimated_usages += other.estimated_usages;
        self.cost_usd += other.cost_usd;
    }

    fn charge(&mut self, usage: &Usage, cost_usd: f64) {
        self.prompt_tokens += usage.prompt_tokens;
        self.completion_tokens += usage.completion_tokens;
        self.reasoning_tokens += usage.reasoning_tokens.unwrap_or(0);
        self.estimated_usages += u64::from(usage.estimated);
        self.cost_usd += cost_usd;
    }
}

/// What an asset's LVLM calls used and cost, for the report.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LedgerSummary {
    /// The budget, if any.
    pub budget_usd: Option<f64>,
    /// Totals over every purpose.
    pub total: PurposeSummary,
    /// Totals per purpose, by name.
    pub by_purpose: BTreeMap<String, PurposeSummary>,
}

/// Token and cost accounting of one asset, shared by the threads annotating it, with an
/// optional budget checked before every attempt.
#[derive(Debug, Default)]
pub struct CostLedger {
    budget_usd: Option<f64>,
    state: Mutex<LedgerState>,
}

#[derive(Debug, Default)]
struct LedgerState {
    /// Estimates of attempts in flight.
    reserved_usd: f64,
    by_purpose: BTreeMap<String, PurposeSummary>,
}

impl LedgerState {
    fn purpose(&mut self, purpose: &str) -> &mut PurposeSummary {
        self.by_purpose.entry(purpose.to_owned()).or_default()
    }

    fn spent_usd(&self) -> f64 {
        self.by_purpose.values().map(|p| p.cost_usd).sum()
    }
}

/// An attempt's share of the budget, held while it is in flight and given back on drop.
#[derive(Debug)]
pub(crate) struct Reservation<'a> {
    ledger: &'a CostLedger,
    estimated_usd: f64,
}

impl Drop for Reservation<'_> {
    fn drop(&mut self) {
        let mut state = self.ledger.lock();
        state.reserved_usd = (state.reserved_usd - self.estimated_usd).max(0.0);
    }
}

impl CostLedger {
    /// A ledger with an optional budget in USD. A budget that is not a finite number >= 0
    /// refuses every request.
    #[must_use]
    pub fn new(budget_usd: Option<f64>) -> Self {
        Self {
            budget_usd,
            state: Mutex::default(),
        }
    }

    /// A ledger without a budget.
    #[must_use]
    pub fn unlimited() -> Self {
        Self::new(None)
    }

    /// The budget, if any.
    #[must_use]
    pub fn budget_usd(&self) -> Option<f64> {
        self.budget_usd
    }

    /// USD spent so far.
    #[must_use]
    pub fn spent_usd(&self) -> f64 {
        self.lock().spent_usd()
    }

    /// Totals, overall and per purpose.
    #[must_use]
    pub fn summary(&self) -> LedgerSummary {
        let state = self.lock();
        let mut total = PurposeSummary::default();
        for purpose in state.by_purpose.values() {
            total.add(purpose);
        }
        LedgerSummary {
            budget_usd: self.budget_usd,
            total,
            by_purpose: state.by_purpose.clone(),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, LedgerState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Reserves `estimated_usd` for an attempt, or refuses when what is spent, what is in
    /// flight and the estimate together would exceed the budget.
    pub(crate) fn reserve(&self, purpose: &str, estimated_usd: f64) -> LvlmResult<Reservation<'_>> {
        let mut state = self.lock();
        if let Some(budget_usd) = self.budget_usd {
            let spent_usd = state.spent_usd() + state.reserved_usd;
            let within = spent_usd + estimated_usd <= budget_usd;
            if !within {
                state.purpose(purpose).refused_for_budget += 1;
                return Err(LvlmError::BudgetExceeded {
                    spent_usd,
                    budget_usd,
                    estimated_usd,
                });
            }
        }
        state.reserved_usd += estimated_usd;
        Ok(Reservation {
            ledger: self,
            estimated_usd,
        })
    }

    /// An answer received from the server.
    pub(crate) fn record_answer(&self, purpose: &str, usage: &Usage, cost_usd: f64) {
        let mut state = self.lock();
        let entry = state.purpose(purpose);
        entry.calls += 1;
        entry.charge(usage, cost_usd);
    }

    /// A failed attempt; `usage` when the server reported (and so charged) some.
    pub(crate) fn record_failed_attempt(
        &self,
        purpose: &str,
        usage: Option<(&Usage, f64)>,
        retried: bool,
    ) {
        let mut state = self.lock();
        let entry = state.purpose(purpose);
        if retried {
            entry.retries += 1;
        } else {
            entry.failures += 1;
        }
        if let Some((usage, cost_usd)) = usage {
            entry.charge(usage, cost_usd);
        }
    }

    /// An answer served from the cache.
    pub(crate) fn record_cache_hit(&self, purpose: &str) {
        self.lock().purpose(purpose).cache_hits += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png_header(width_px: u32, height_px: u32) -> Vec<u8> {
        let mut bytes = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
        bytes.extend_from_slice(b"IHDR");
        bytes.extend_from_slice(&width_px.to_be_bytes());
        bytes.extend_from_slice(&height_px.to_be_bytes());
        bytes
    }

    #[test]
    fn image_tokens_follow_the_tile_rule() {
        // 1024 x 1024 → 768 x 768 → 4 tiles.
        assert_eq!(image_tokens_estimate(&png_header(1024, 1024)), 85 + 170 * 4);
        // 1800 x 600 (the reference's composites): fits, short side below 768 → 4 x 2 tiles.
        assert_eq!(image_tokens_estimate(&png_header(1800, 600)), 85 + 170 * 8);
        // 4096 x 8192 → 1024 x 2048 → 768 x 1536 → 2 x 3 tiles.
        assert_eq!(image_tokens_estimate(&png_header(4096, 8192)), 85 + 170 * 6);
        // 100 x 100: one tile.
        assert_eq!(image_tokens_estimate(&png_header(100, 100)), 85 + 170);
        assert_eq!(image_tokens_estimate(b"not a png"), IMAGE_TOKENS_FALLBACK);
    }

    #[test]
    fn prompt_estimate_counts_text_and_images() {
        let request = ChatRequest::new("p", "abcd", "efghi").with_image(png_header(100, 100));
        assert_eq!(estimate_prompt_tokens(&request), 3 + 255);
    }

    #[test]
    fn the_budget_counts_spending_and_attempts_in_flight() {
        let ledger = CostLedger::new(Some(1.0));
        let first = ledger.reserve("a", 0.4).unwrap();
        let second = ledger.reserve("a", 0.4).unwrap();
        let error = ledger.reserve("a", 0.4).unwrap_err();
        let LvlmError::BudgetExceeded {
            spent_usd,
            budget_usd,
            estimated_usd,
        } = error
        else {
            panic!("{error}");
        };
        assert!((spent_usd - 0.8).abs() < 1e-12);
        assert_eq!((budget_usd, estimated_usd), (1.0, 0.4));
        drop(first);
        ledger.record_answer("a", &Usage::default(), 0.3);
        drop(second);
        // 0.3 spent, nothing in flight: 0.6 fits, 0.8 does not.
        assert!(ledger.reserve("a", 0.6).is_ok());
        assert!(ledger.reserve("a", 0.8).is_err());
        assert_eq!(ledger.summary().total.refused_for_budget, 2);
    }

    #[test]
    fn a_nonsense_budget_refuses_everything() {
        let ledger = CostLedger::new(Some(f64::NAN));
        assert!(ledger.reserve("a", 0.0).is_err());
    }

    #[test]
    fn summary_totals_are_sums_of_purposes() {
        let ledger = CostLedger::unlimited();
        let usage = Usage {
            prompt_tokens: 100,
            completion_tokens: 10,
            reasoning_tokens: Some(4),
            estimated: false,
        };
        ledger.record_answer("properties", &usage, 0.5);
        ledger.record_answer("axis", &usage, 0.25);
        ledger.record_failed_attempt("axis", Some((&usage, 0.125)), true);
        ledger.record_failed_attempt("axis", None, false);
        ledger.record_cache_hit("axis");
        let summary = ledger.summary();
        assert_eq!(summary.total.calls, 2);
        assert_eq!(summary.total.prompt_tokens, 300);
        assert_eq!(summary.total.reasoning_tokens, 12);
        assert!((summary.total.cost_usd - 0.875).abs() < 1e-12);
        let axis = &summary.by_purpose["axis"];
        assert_eq!((axis.retries, axis.failures, axis.cache_hits), (1, 1, 1));
        assert!((ledger.spent_usd() - 0.875).abs() < 1e-12);
        let json = serde_json::to_string(&summary).unwrap();
        let back: LedgerSummary = serde_json::from_str(&json).unwrap();
        assert_eq!(back, summary);
    }
}
