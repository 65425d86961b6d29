//! Worker processes of the chaos tests: `uniphys worker` with stand-in stages, killed with
//! SIGKILL at random.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// Settings every worker process of a scenario shares.
#[derive(Clone, Debug)]
pub struct WorkerEnv {
    pub database_url: String,
    pub storage_dir: std::path::PathBuf,
    pub redis_url: Option<String>,
    pub stages: Vec<&'static str>,
    pub work_ms: u64,
    pub lease_secs: u64,
    pub slots_per_stage: usize,
}

/// One running `uniphys worker`.
pub struct WorkerProcess {
    child: Child,
    pub id: String,
}

impl WorkerProcess {
    /// Starts a worker and waits for the line that names its fresh id.
    pub fn start(env: &WorkerEnv) -> Self {
        let slots: Vec<String> = env
            .stages
            .iter()
            .map(|s| format!("{s}={}", env.slots_per_stage))
            .collect();
        let mut command = Command::new(env!("CARGO_BIN_EXE_uniphys"));
        command
            .arg("worker")
            .args(["--stand-ins", &env.stages.join(",")])
            .args(["--stand-in-work-ms", &env.work_ms.to_string()])
            .args(["--stages", &slots.join(",")])
            .args(["--lease-secs", &env.lease_secs.to_string()])
            .args(["--poll-ms", "250"])
            .args(["--reap-ms", "500"])
            .env_clear()
            .env("PATH", std::env::var("PATH").unwrap_or_default())
            .env("UNIPHYS_DATABASE_URL", &env.database_url)
            .env("UNIPHYS_STORAGE_URL", &env.storage_dir)
            .env("UNIPHYS_RETRY_BASE_MS", "200")
            .env("UNIPHYS_LOG", "warn")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null());
        if let Some(url) = &env.redis_url {
            command.env("UNIPHYS_REDIS_URL", url);
        }
        let mut child = command.spawn().expect("uniphys worker starts");
        let stdout = child.stdout.take().expect("piped stdout");
        let mut reader = BufReader::new(stdout);
        let mut line = String::new();
        reader
            .read_line(&mut line)
            .expect("the worker prints its id");
        // Keep draining, so later output never meets a closed pipe.
        std::thread::spawn(move || std::io::copy(&mut reader, &mut std::io::sink()));
        let id = line
            .trim()
            .strip_prefix("worker ")
            .unwrap_or_else(|| panic!("unexpected first line {line:?}"))
            .to_owned();
        Self { child, id }
    }

    /// SIGKILL: no shutdown, no release; its leases must expire and be recovered.
    pub fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// SIGTERM, then wait for the graceful exit.
    pub fn terminate(mut self) -> std::process::ExitStatus {
        let _ = Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status();
        self.child.wait().expect("worker exits")
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
