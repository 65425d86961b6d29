//! The LVLM settings shared by `uniphys run` and the workers: flags, environment keys and the
//! pipeline's [`LvlmOptions`] made from them.

use std::path::PathBuf;
use std::sync::Arc;

use uniphys_lvlm::{LocalTokenBucket, Pricing, RateLimiter};
use uniphys_pipeline::LvlmOptions;

/// Where the LVLM is and how much of it one process may use.
#[derive(Debug, Clone, clap::Args)]
pub struct LvlmArgs {
    /// Ground with an OpenAI-compatible vision-language model at this base URL (with its API
    /// prefix, e.g. http://vllm:8000/v1) after the built-in grounder: properties, motion graph and
    /// joints chosen among geometric candidates replace the estimates. The key is read from
    /// UNIPHYS_LVLM_API_KEY (or OPENAI_API_KEY).
    #[arg(long, env = "UNIPHYS_LVLM_BASE_URL")]
    pub lvlm_base_url: Option<String>,
    /// Model name sent to the LVLM server.
    #[arg(long, env = "UNIPHYS_LVLM_MODEL", default_value = "gpt-5")]
    pub lvlm_model: String,
    /// `reasoning_effort` sent with each LVLM request (`minimal`, `low`, `medium`, `high`), or
    /// `none` to leave it out (servers that do not know it).
    #[arg(long, env = "UNIPHYS_LVLM_REASONING_EFFORT", default_value = "medium")]
    pub lvlm_reasoning_effort: String,
    /// Most LVLM requests of one asset in flight at once.
    #[arg(long, env = "UNIPHYS_LVLM_CONCURRENCY", default_value_t = 8)]
    pub lvlm_concurrency: usize,
    /// Most LVLM requests a minute (every attempt counts). Workers share this rate through
    /// Redis, so it is the fleet's; `uniphys run` and Redis-less services keep it per process.
    #[arg(long, env = "UNIPHYS_LVLM_REQUESTS_PER_MINUTE")]
    pub lvlm_requests_per_minute: Option<u32>,
    /// Most USD the LVLM requests of one asset may cost (requests that could exceed it are not
    /// sent and the run fails).
    #[arg(long, env = "UNIPHYS_LVLM_BUDGET_USD")]
    pub lvlm_budget_usd: Option<f64>,
    /// Prices of the model in USD per million tokens, `INPUT,OUTPUT` (images count as input,
    /// reasoning as output): the cost ledger and the budget use them. `0,0` for a self-hosted
    /// model.
    #[arg(long, env = "UNIPHYS_LVLM_PRICE_USD_PER_MTOK", default_value = "1.25,10", value_parser = parse_pricing)]
    pub lvlm_price_usd_per_mtok: Pricing,
    /// Limit on one LVLM attempt, connect to last byte, in seconds (then it is retried).
    #[arg(long, env = "UNIPHYS_LVLM_TIMEOUT_SECS", default_value_t = 120.0)]
    pub lvlm_timeout_secs: f64,
    /// Directory of the LVLM answer cache (keyed by request digest): a repeated run does not pay
    /// twice. Workers without one cache in the object store.
    #[arg(long, env = "UNIPHYS_LVLM_CACHE_DIR")]
    pub lvlm_cache_dir: Option<PathBuf>,
}

impl LvlmArgs {
    /// The pipeline's LVLM options, or `None` when no base URL is set. `rate_limiter` replaces
    /// the per-process bucket of `lvlm_requests_per_minute` (the workers pass the fleet's).
    ///
    /// # Errors
    /// A requests-per-minute of 0.
    pub fn options(
        &self,
        rate_limiter: Option<Arc<dyn RateLimiter>>,
    ) -> anyhow::Result<Option<LvlmOptions>> {
        let Some(base_url) = &self.lvlm_base_url else {
            return Ok(None);
        };
        let rate_limiter = match (rate_limiter, self.lvlm_requests_per_minute) {
            (Some(shared), _) => Some(shared),
            (None, Some(per_minute)) => Some(Arc::new(local_bucket(per_minute)?) as Arc<_>),
            (None, None) => None,
        };
        let api_key = [uniphys_lvlm::API_KEY_VARIABLE, "OPENAI_API_KEY"]
            .iter()
            .find_map(|name| std::env::var(name).ok().filter(|k| !k.trim().is_empty()));
        let reasoning_effort = Some(self.lvlm_reasoning_effort.trim().to_owned())
            .filter(|e| !e.is_empty() && !e.eq_ignore_ascii_case("none"));
        Ok(Some(LvlmOptions {
            client: uniphys_lvlm::LvlmConfig {
                base_url: base_url.trim_end_matches('/').to_owned(),
                model: self.lvlm_model.clone(),
                api_key,
                reasoning_effort,
                max_concurrency: self.lvlm_concurrency,
                request_timeout_secs: self.lvlm_timeout_secs,
                pricing: self.lvlm_price_usd_per_mtok,
                ..uniphys_lvlm::LvlmConfig::default()
            },
            budget_usd: self.lvlm_budget_usd,
            cache_dir: self.lvlm_cache_dir.clone(),
            rate_limiter,
            ..LvlmOptions::default()
        }))
    }
}

/// `INPUT,OUTPUT` USD per million tokens.
fn parse_pricing(text: &str) -> Result<Pricing, String> {
    let prices: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{text:?}: {e}; expected INPUT,OUTPUT USD per million tokens"))?;
    match prices[..] {
        [input, output] if [input, output].iter().all(|p| p.is_finite() && *p >= 0.0) => {
            Ok(Pricing {
                input_usd_per_million_tokens: input,
                output_usd_per_million_tokens: output,
            })
        }
        _ => Err(format!(
            "{text:?}: expected two prices >= 0, INPUT,OUTPUT USD per million tokens (e.g. 1.25,10)"
        )),
    }
}

/// A bucket of `per_minute` requests a minute with a burst of one minute's worth.
fn local_bucket(per_minute: u32) -> anyhow::Result<LocalTokenBucket> {
    anyhow::ensure!(
        per_minute > 0,
        "UNIPHYS_LVLM_REQUESTS_PER_MINUTE must be at least 1 (leave it unset for no limit)"
    );
    Ok(LocalTokenBucket::new(
        f64::from(per_minute) / 60.0,
        per_minute,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prices_parse_as_input_then_output() {
        let p = parse_pricing("0.5, 4").unwrap();
        assert_eq!(p.input_usd_per_million_tokens, 0.5);
        assert_eq!(p.output_usd_per_million_tokens, 4.0);
        for bad in ["1", "1,2,3", "a,1", "-1,2", "1,inf"] {
            assert!(parse_pricing(bad).is_err(), "{bad}");
        }
    }
}
