//! Runs third-party parsers so that a panic inside them becomes an [`IngestError::Parse`].

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use crate::{IngestError, IngestResult};

/// Runs `f`, turning a panic into a parse error naming `path` and `format`.
pub(crate) fn guarded<T>(
    path: &Path,
    format: &'static str,
    f: impl FnOnce() -> T,
) -> IngestResult<T> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        IngestError::parse(
            path,
            format,
            format!("parser panicked: {}", panic_message(payload.as_ref())),
        )
    })
}

fn panic_message(payload: &(dyn Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "unknown panic"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panic_in_parser_becomes_parse_error_naming_the_file() {
        let err = guarded(Path::new("x.ply"), "ply", || -> u32 { panic!("boom") })
            .expect_err("panic caught");
        let msg = err.to_string();
        assert!(
            msg.contains("x.ply") && msg.contains("parser panicked: boom"),
            "{msg}"
        );
        assert_eq!(
            guarded(Path::new("x.ply"), "ply", || 7).expect("no panic"),
            7
        );
    }
}
