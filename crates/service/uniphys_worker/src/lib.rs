//! The UniPhys worker: claims stage runs from the queue, runs them on blocking threads and
//! records their end, keeping the queue contract (`shared/reference/queue-contract.md` §5):
//!
//! - leases renewed every third of the lease while a stage runs; a lost lease or a cancelled job
//!   stops the stage and drops its result (fencing is in the store);
//! - stage outputs go to deterministic keys `{asset}/{stage}/v{version}/{input_digest}/…` with
//!   create-only writes ([`OutputWriter`]), so a re-run after a crash writes the same bytes and
//!   different bytes are refused;
//! - the Redis doorbell only shortens the wait; the poll interval is the guarantee;
//! - graceful shutdown stops claiming, lets running stages finish within a grace period and
//!   releases the rest; a fresh worker id per process start.
//!
//! Map: [`Stage`] (what a stage is) · [`StageRegistry`] and [`pipeline_job_spec`] (which stages
//! exist, the graph an asset gets) · [`stages`] (ingest, decompose, infer, ground, verify,
//! convert, stand-ins) · [`FleetRateLimiter`] (the LVLM client's rate limit over the fleet's
//! Redis bucket) · [`StoreAnswerCache`] (its answers in the object store) · [`Worker`] (claim
//! loops, reaper, shutdown) · [`WorkerConfig`].

mod config;
mod error;
mod execute;
mod fleet_rate_limit;
mod input_error;
mod outputs;
mod registry;
mod source;
mod stage;
pub mod stages;
mod store_answer_cache;
mod worker;

pub use config::{StageSlots, WorkerConfig};
pub use error::{WorkerError, WorkerResult};
pub use fleet_rate_limit::FleetRateLimiter;
pub use outputs::{OutputWriter, input_digest};
pub use registry::{StageRegistry, pipeline_job_spec};
pub use stage::{Stage, StageControl, StageError, StageInput, StageProgress};
pub use store_answer_cache::StoreAnswerCache;
pub use worker::{Worker, fresh_worker_id};
