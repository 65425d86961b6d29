use std::io::{IsTerminal, Write};
use std::time::Duration;

use uniphys_pipeline::{Progress, Stage};

/// Prints one line per stage to stderr, numbered among the stages the run goes through, with a
/// live part counter on terminals.
pub(crate) struct StderrProgress {
    live: bool,
    stages: Vec<Stage>,
}

impl StderrProgress {
    /// Progress of a run going through the pipeline's stages; `infer` only `with_infer` (a
    /// UniPhysGen server is configured).
    pub(crate) fn new(with_infer: bool) -> Self {
        Self {
            live: std::io::stderr().is_terminal(),
            stages: Stage::ALL
                .into_iter()
                .filter(|s| with_infer || *s != Stage::Infer)
                .collect(),
        }
    }

    /// `[k/n]` of `stage` among the run's stages.
    fn position(&self, stage: Stage) -> String {
        let k = self
            .stages
            .iter()
            .position(|s| *s == stage)
            .map_or(0, |i| i + 1);
        format!("[{k}/{}]", self.stages.len())
    }
}

impl Progress for StderrProgress {
    fn stage_started(&self, stage: Stage) {
        if self.live {
            eprint!("{} {} ...", self.position(stage), stage.name());
            let _ = std::io::stderr().flush();
        }
    }

    fn stage_advanced(&self, stage: Stage, done: usize, total: usize) {
        if self.live {
            eprint!(
                "\r{} {} ... {done}/{total}",
                self.position(stage),
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
            "{} {:<9} {:>9.1} ms  {summary}",
            self.position(stage),
            stage.name(),
            elapsed.as_secs_f64() * 1e3
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_are_numbered_among_those_the_run_goes_through() {
        let builtin = StderrProgress::new(false);
        assert_eq!(builtin.position(Stage::Ingest), "[1/6]");
        assert_eq!(builtin.position(Stage::Prepare), "[2/6]");
        assert_eq!(builtin.position(Stage::Export), "[6/6]");
        let with_model = StderrProgress::new(true);
        assert_eq!(with_model.position(Stage::Infer), "[2/7]");
        assert_eq!(with_model.position(Stage::Prepare), "[3/7]");
    }
}
