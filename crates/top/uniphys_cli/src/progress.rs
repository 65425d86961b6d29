use std::io::{IsTerminal, Write};
use std::time::Duration;

use uniphys_pipeline::{Progress, Stage};

/// Prints one line per stage to stderr, with a live part counter on terminals.
pub(crate) struct StderrProgress {
    live: bool,
}

impl StderrProgress {
    pub(crate) fn new() -> Self {
        Self {
            live: std::io::stderr().is_terminal(),
        }
    }
}

fn position(stage: Stage) -> usize {
    Stage::ALL
        .iter()
        .position(|s| *s == stage)
        .map_or(0, |i| i + 1)
}

impl Progress for StderrProgress {
    fn stage_started(&self, stage: Stage) {
        if self.live {
            eprint!(
                "[{}/{}] {} ...",
                position(stage),
                Stage::ALL.len(),
                stage.name()
            );
            let _ = std::io::stderr().flush();
        }
    }

    fn stage_advanced(&self, stage: Stage, done: usize, total: usize) {
        if self.live {
            eprint!(
                "\r[{}/{}] {} ... {done}/{total}",
                position(stage),
                Stage::ALL.len(),
                stage.name()
            );
            let _ = std::io::stderr().flush();
        }
    }

    fn stage_finished(&self, stage: Stage, elapsed: Duration, summary: &str) {
        if self.live {
            eprint!("\r\x1b[2K");
        }
        eprintln!(
            "[{}/{}] {:<9} {:>9.1} ms  {summary}",
            position(stage),
            Stage::ALL.len(),
            stage.name(),
            elapsed.as_secs_f64() * 1e3
        );
    }
}
