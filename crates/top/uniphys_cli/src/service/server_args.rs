//! Arguments of `serve`, `api` and `worker`.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context;
use uniphys_decompose::DecomposeMode;
use uniphys_hints::Hints;
use uniphys_lvlm::RateLimiter;
use uniphys_pipeline::LearnedOptions;
use uniphys_storage::ArtifactStore;
use uniphys_uniphysgen::ClientConfig as ModelClientConfig;
use uniphys_vision::ClientConfig;
use uniphys_worker::stages::{ConvertStage, DecomposeStage};
use uniphys_worker::{FleetRateLimiter, StageRegistry, StageSlots, StoreAnswerCache, WorkerConfig};

use crate::lvlm_args::LvlmArgs;

use super::config::{ServiceArgs, parse_stage_slots, secs};

/// API settings.
#[derive(Debug, Clone, clap::Args)]
pub struct ApiArgs {
    /// Address the API listens on.
    #[arg(long, env = "UNIPHYS_LISTEN", default_value = "127.0.0.1:8080")]
    pub listen: SocketAddr,
    /// Largest accepted upload, in bytes.
    #[arg(long, env = "UNIPHYS_MAX_UPLOAD_BYTES", default_value_t = uniphys_api::DEFAULT_MAX_UPLOAD_BYTES)]
    pub max_upload_bytes: u64,
    /// Unfinished stage runs a tenant may have before submissions get 429.
    #[arg(long, env = "UNIPHYS_MAX_BACKLOG_PER_TENANT", default_value_t = 10_000)]
    pub max_backlog_per_tenant: u64,
    /// Seconds a client has to send a request's headers (and an idle keep-alive connection
    /// stays open); slower clients are disconnected.
    #[arg(long, env = "UNIPHYS_HEADER_READ_TIMEOUT_SECS", default_value_t = 10)]
    pub header_read_timeout_secs: u64,
    /// Seconds an upload may pause between its bytes before it is answered 408.
    #[arg(long, env = "UNIPHYS_BODY_READ_TIMEOUT_SECS", default_value_t = 30)]
    pub body_read_timeout_secs: u64,
    /// Connections one client address may hold open at once; more are closed on accept.
    #[arg(
        long,
        env = "UNIPHYS_MAX_CONNECTIONS_PER_ADDRESS",
        default_value_t = 64
    )]
    pub max_connections_per_address: usize,
    /// Hours a succeeded or cancelled job (its runs, manifests and events) is kept; the API
    /// process deletes older ones every hour. Artifacts and assets stay.
    #[arg(long, env = "UNIPHYS_RETENTION_FINISHED_HOURS", default_value_t = 720)]
    pub retention_finished_hours: u64,
    /// Hours a dead-lettered job is kept.
    #[arg(long, env = "UNIPHYS_RETENTION_DEAD_HOURS", default_value_t = 2160)]
    pub retention_dead_hours: u64,
}

impl ApiArgs {
    /// The retention policy.
    #[must_use]
    pub fn retention(&self) -> uniphys_queue::RetentionPolicy {
        uniphys_queue::RetentionPolicy {
            finished: Duration::from_secs(self.retention_finished_hours.saturating_mul(3600)),
            dead: Duration::from_secs(self.retention_dead_hours.saturating_mul(3600)),
            ..uniphys_queue::RetentionPolicy::default()
        }
    }
}

/// Worker settings.
#[derive(Debug, Clone, clap::Args)]
pub struct WorkerArgs {
    /// Stages to claim and their concurrency, e.g. `ingest=2,convert=1`
    /// (default: every stage this binary knows, one at a time).
    #[arg(long, env = "UNIPHYS_STAGES")]
    pub stages: Option<String>,
    /// Lease per claimed run, renewed every third of it.
    #[arg(long, env = "UNIPHYS_LEASE_SECS", default_value_t = 60)]
    pub lease_secs: u64,
    /// Longest wait between claims when no doorbell rings, in milliseconds.
    #[arg(long, env = "UNIPHYS_POLL_MS", default_value_t = 1000)]
    pub poll_ms: u64,
    /// How often expired leases of dead workers are recovered, in milliseconds.
    #[arg(long, env = "UNIPHYS_REAP_MS", default_value_t = 15_000)]
    pub reap_ms: u64,
    /// Hard limit on one stage run, in seconds.
    #[arg(long, env = "UNIPHYS_STAGE_DEADLINE_SECS", default_value_t = 3600)]
    pub stage_deadline_secs: u64,
    /// On SIGTERM, how long running stages may finish before their runs are released.
    #[arg(long, env = "UNIPHYS_SHUTDOWN_GRACE_SECS", default_value_t = 20)]
    pub shutdown_grace_secs: u64,
    /// Testing: run deterministic stand-in stages with these names instead of the pipeline.
    #[arg(long, env = "UNIPHYS_STAND_INS", value_delimiter = ',')]
    pub stand_ins: Vec<String>,
    /// Testing: how long each stand-in stage works, in milliseconds.
    #[arg(long, env = "UNIPHYS_STAND_IN_WORK_MS", default_value_t = 10)]
    pub stand_in_work_ms: u64,
    /// Which assets `decompose` splits into parts: `auto` (inputs in one piece or in more than
    /// 20 fragments, without joints), `always` or `off`.
    #[arg(long, env = "UNIPHYS_DECOMPOSE_MODE", default_value = "auto", value_parser = parse_mode)]
    pub decompose_mode: DecomposeMode,
    /// `decompose` segments its views with a SAM-compatible mask service at this URL instead of
    /// the built-in render-space segmenter.
    #[arg(long, env = "UNIPHYS_SAM_URL")]
    pub sam_url: Option<String>,
    /// `decompose` takes per-face features from a PartField-compatible service at this URL
    /// instead of the built-in geometric features.
    #[arg(long, env = "UNIPHYS_PARTFIELD_URL")]
    pub partfield_url: Option<String>,
    /// `infer` asks the UniPhysGen model server at this URL (e.g. http://gpu-node:8000) about
    /// every asset's parts and object, and `ground` applies its answers; without it `infer`
    /// stores nothing.
    #[arg(long, env = "UNIPHYS_UNIPHYSGEN_URL")]
    pub uniphysgen_url: Option<String>,
    /// GPU slots this process may hold on the model server at once.
    #[arg(long, env = "UNIPHYS_UNIPHYSGEN_SLOTS", default_value_t = 1)]
    pub uniphysgen_slots: usize,
    /// The LVLM `ground` grounds with, if any.
    #[command(flatten)]
    pub lvlm: LvlmArgs,
}

fn parse_mode(text: &str) -> Result<DecomposeMode, String> {
    DecomposeMode::parse(text).ok_or_else(|| format!("{text:?}: expected auto, always or off"))
}

/// Name of the fleet's LVLM request bucket in Redis.
const LVLM_BUCKET: &str = "lvlm";

/// Where the fleet's LVLM answers are cached in the object store.
const LVLM_ANSWERS_PREFIX: &str = "cache/lvlm-answers";

impl WorkerArgs {
    /// The stages this process can run. The LVLM's request rate is shared with the fleet
    /// through `hints` (Redis; the in-process twin keeps it per process), and its answers are
    /// cached in `artifacts` unless a cache directory is set; must be called inside the
    /// service's runtime.
    ///
    /// # Errors
    /// An LVLM request rate of 0.
    pub fn registry(
        &self,
        hints: &Hints,
        artifacts: &ArtifactStore,
    ) -> anyhow::Result<StageRegistry> {
        if !self.stand_ins.is_empty() {
            let names: Vec<&str> = self.stand_ins.iter().map(String::as_str).collect();
            return Ok(StageRegistry::stand_ins(
                &names,
                Duration::from_millis(self.stand_in_work_ms),
            ));
        }
        let fleet_limit = match self.lvlm.lvlm_requests_per_minute {
            Some(per_minute) if self.lvlm.lvlm_base_url.is_some() => Some(Arc::new(
                FleetRateLimiter::new(
                    hints.clone(),
                    LVLM_BUCKET,
                    per_minute,
                    tokio::runtime::Handle::current(),
                )
                .context("UNIPHYS_LVLM_REQUESTS_PER_MINUTE")?,
            )
                as Arc<dyn RateLimiter>),
            _ => None,
        };
        let mut convert = ConvertStage::default();
        convert.options.learned = self.uniphysgen_url.as_ref().map(|url| LearnedOptions {
            client: ModelClientConfig {
                base_url: url.clone(),
                ..ModelClientConfig::default()
            },
            slots: self.uniphysgen_slots,
            ..LearnedOptions::default()
        });
        convert.options.lvlm = self.lvlm.options(fleet_limit)?;
        if let Some(lvlm) = &mut convert.options.lvlm
            && lvlm.cache_dir.is_none()
        {
            // A retry on another worker finds the answers the first attempt paid for.
            lvlm.cache = Some(Arc::new(StoreAnswerCache::new(
                artifacts.clone(),
                LVLM_ANSWERS_PREFIX,
                tokio::runtime::Handle::current(),
            )));
        }
        let decompose = DecomposeStage {
            mode: self.decompose_mode,
            sam: self.sam_url.clone().map(ClientConfig::for_url),
            partfield: self.partfield_url.clone().map(ClientConfig::for_url),
            ..DecomposeStage::default()
        };
        Ok(StageRegistry::pipeline_with(decompose, convert))
    }

    /// The worker configuration.
    pub fn config(&self, registry: &StageRegistry) -> anyhow::Result<WorkerConfig> {
        let slots = match &self.stages {
            Some(text) => parse_stage_slots(text)?,
            None => registry.names().into_iter().map(|n| (n, 1)).collect(),
        };
        let deadline = secs(self.stage_deadline_secs, "the stage deadline")?;
        Ok(WorkerConfig {
            stages: slots
                .into_iter()
                .map(|(name, n)| StageSlots {
                    deadline,
                    ..StageSlots::new(name, n)
                })
                .collect(),
            lease: secs(self.lease_secs, "the lease")?,
            poll_interval: Duration::from_millis(self.poll_ms.max(1)),
            reap_interval: Duration::from_millis(self.reap_ms.max(1)),
            shutdown_grace: Duration::from_secs(self.shutdown_grace_secs),
        })
    }
}

/// `uniphys serve`: API and workers in one process.
#[derive(Debug, Clone, clap::Args)]
pub struct ServeArgs {
    /// Where state, objects and hints live.
    #[command(flatten)]
    pub service: ServiceArgs,
    /// API settings.
    #[command(flatten)]
    pub api: ApiArgs,
    /// Worker settings.
    #[command(flatten)]
    pub worker: WorkerArgs,
}

/// `uniphys api`: the API alone.
#[derive(Debug, Clone, clap::Args)]
pub struct ApiOnlyArgs {
    /// Where state, objects and hints live.
    #[command(flatten)]
    pub service: ServiceArgs,
    /// API settings.
    #[command(flatten)]
    pub api: ApiArgs,
    /// Stages submissions get (testing with stand-ins; default: the pipeline's graph).
    #[arg(long, env = "UNIPHYS_STAND_INS", value_delimiter = ',')]
    pub stand_ins: Vec<String>,
}

/// `uniphys worker`: workers alone.
#[derive(Debug, Clone, clap::Args)]
pub struct WorkerOnlyArgs {
    /// Serve Prometheus `/metrics` of this worker on this address (default: not served).
    #[arg(long, env = "UNIPHYS_METRICS_LISTEN")]
    pub metrics_listen: Option<SocketAddr>,
    /// Where state, objects and hints live.
    #[command(flatten)]
    pub service: ServiceArgs,
    /// Worker settings.
    #[command(flatten)]
    pub worker: WorkerArgs,
}
