//! Best-effort fleet hints for the UniPhys service, over Redis or in process.
//!
//! Redis is never the only copy of a job (see `shared/reference/queue-contract.md` §5): Postgres
//! owns the queue and workers poll it. This crate only makes things sooner or fairer:
//! - **doorbells** ([`Hints::ring`], [`Hints::doorbell`]): a PUBLISH per stage, so idle workers
//!   claim within milliseconds instead of at their next poll;
//! - **fleet-wide limits**: token-bucket rate limits ([`Hints::try_acquire`]) and slot pools with
//!   expiry for GPU semaphores ([`Hints::acquire_slot`]), atomic in Lua on the Redis clock;
//! - **live progress** for the dashboard ([`Hints::set_progress`]), expiring after an hour, and
//!   events for server-sent streams ([`Hints::publish_event`]).
//!
//! With Redis down or flushed, every call fails fast (connect and answer bounded by
//! [`HintsOptions`], 250 ms each by default), a doorbell's `wait` just runs out its time, and
//! the client reconnects in the background. [`Hints::local`] gives the same behaviour in one
//! process for embedded mode.
//!
//! Keys: `{prefix}:ring:{stage}` and `{prefix}:events:{channel}` (channels),
//! `{prefix}:rate:{name}` (hash), `{prefix}:slots:{pool}` (sorted set),
//! `{prefix}:progress:{job_id}` (hash).

mod doorbell;
mod error;
mod hints;
mod keys;
mod local;
mod progress;
mod rate_limit;
mod redis_backend;
mod scripts;

pub use doorbell::{Doorbell, EventStream, Wake};
pub use error::{HintsError, HintsResult};
pub use hints::{Hints, HintsOptions};
pub use progress::Progress;
pub use rate_limit::{RateDecision, RateLimit};
