//! Blocking clients of the external vision model services, over HTTP (`uniphys_http`):
//! a SAM-compatible automatic mask service ([`SamClient`]) and a PartField-compatible per-face
//! feature service ([`PartFieldClient`]). The contract is `proto/vision.openapi.yaml`; its wire
//! types are in [`contract`].
//!
//! Both clients follow the shared retry policy (`uniphys_http`): connection errors, timeouts,
//! 408/425/429/500/502/503/504 and truncated answers, and here also bodies that are not JSON,
//! are retried with jittered exponential backoff (a `Retry-After` on 429/503 is honoured,
//! capped); other statuses are not retried and the error carries the server's message. Answers are checked against
//! the request (mask sizes and RLE sums, feature count, finite values) before they are returned.

mod config;
pub mod contract;
mod error;
mod partfield;
mod rle;
mod sam;
mod transport;

pub use config::ClientConfig;
pub use contract::{
    MaskOptions, MaskRequest, MaskResponse, PartFeatureRequest, PartFeatureResponse,
};
pub use error::{VisionError, VisionResult};
pub use partfield::{PartFeatures, PartFieldClient};
pub use rle::Rle;
pub use sam::{MaskSet, SamClient, SamMask};
