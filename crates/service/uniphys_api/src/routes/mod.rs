//! The handlers, one file per resource.

pub(crate) mod artifacts;
pub(crate) mod assets;
pub(crate) mod batches;
pub(crate) mod exports;
pub(crate) mod import;
pub(crate) mod jobs;
pub(crate) mod ops;
pub(crate) mod overview;
pub(crate) mod submit;
pub(crate) mod work;
