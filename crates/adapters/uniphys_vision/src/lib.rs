//! Blocking clients of the external vision model services, over HTTP (`ureq`):
//! a SAM-compatible automatic mask service ([`SamClient`]) and a PartField-compatible per-face
//! feature service ([`PartFieldClient`]). The contract is `proto/vision.openapi.yaml`; its wire
//! types are in [`contract`].
//!
//! Both clients retry connection errors, timeouts, 429, 5xx and truncated or malformed JSON
//! bodies with exponential backoff (a `Retry-After` on 429/503 is honoured, capped); other
//! 4xx are not retried and the error carries the server's message. Answers are checked against
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
