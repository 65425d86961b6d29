//! The handlers, one file per resource.

pub(crate) mod artifacts;
pub(crate) mod assets;
pub(crate) mod import;
pub(crate) mod jobs;
pub(crate) mod ops;
pub(crate) mod submit;
