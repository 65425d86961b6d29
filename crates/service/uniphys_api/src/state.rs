//! What every handler shares: the queue store, the artifact store, the limits and the hooks.

use std::sync::Arc;

use uniphys_queue::QueueStore;
use uniphys_storage::ArtifactStore;

use crate::backlog_gauge::BacklogGauge;
use crate::board::Board;
use crate::dataset_export::ExportRegistry;
use crate::upload::{STALE_SPOOL, sweep_stale_spool};
use crate::{ApiConfig, NoHooks, ServiceHooks};

/// The API's dependencies. [`crate::router`] wraps it in an `Arc`, so it need not be cheap to
/// clone.
#[derive(Clone)]
pub struct ApiState {
    /// Jobs, stage runs, tenants and API keys.
    pub store: QueueStore,
    /// Uploaded sources and stage artifacts.
    pub artifacts: ArtifactStore,
    /// Limits and the stage graph of submissions.
    pub config: ApiConfig,
    /// Doorbell, progress, metrics, trace context, readiness.
    pub hooks: Arc<dyn ServiceHooks>,
    /// The dashboard's cached statistics and history.
    pub(crate) board: Arc<Board>,
    /// Each tenant's backlog as this process knows it (the cap's fast path).
    pub(crate) backlog: Arc<BacklogGauge>,
    /// The dataset exports this process runs or ran.
    pub(crate) exports: Arc<ExportRegistry>,
}

impl ApiState {
    /// A state with [`NoHooks`]. Spool files a crash left in the upload folder (untouched for
    /// an hour) are removed first.
    #[must_use]
    pub fn new(store: QueueStore, artifacts: ArtifactStore, config: ApiConfig) -> Self {
        let swept = sweep_stale_spool(config.upload_tmp_dir.as_deref(), STALE_SPOOL);
        if swept > 0 {
            tracing::info!(
                files = swept,
                "removed upload spool files left by an earlier crash"
            );
        }
        Self {
            store,
            artifacts,
            config,
            hooks: Arc::new(NoHooks),
            board: Arc::default(),
            backlog: Arc::default(),
            exports: Arc::default(),
        }
    }

    /// Replaces the hooks.
    #[must_use]
    pub fn with_hooks(mut self, hooks: Arc<dyn ServiceHooks>) -> Self {
        self.hooks = hooks;
        self
    }
}

impl std::fmt::Debug for ApiState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ApiState")
            .field("store", &self.store)
            .field("artifacts", &self.artifacts)
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

/// The state as handlers see it.
pub(crate) type Shared = Arc<ApiState>;
