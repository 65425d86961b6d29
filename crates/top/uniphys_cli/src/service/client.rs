//! `uniphys submit` and `uniphys status`: a small blocking client of the HTTP API.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, bail};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use serde_json::Value;

/// Where the API is and who we are.
#[derive(Debug, Clone, clap::Args)]
pub struct ClientArgs {
    /// Base URL of the API.
    #[arg(long, env = "UNIPHYS_API_URL", default_value = "http://127.0.0.1:8080")]
    pub api_url: String,
    /// API key (default: the local key `uniphys serve` wrote in the data directory).
    #[arg(long, env = "UNIPHYS_API_KEY", hide_env_values = true)]
    pub api_key: Option<String>,
    /// Data directory of a local `uniphys serve` (for its API key).
    #[arg(long, env = "UNIPHYS_DATA_DIR", default_value = "uniphys-data")]
    pub data_dir: PathBuf,
}

/// `uniphys submit`.
#[derive(Debug, clap::Args)]
pub struct SubmitArgs {
    /// The API and the key.
    #[command(flatten)]
    pub client: ClientArgs,
    /// Asset files to upload, asset folders (a URDF folder with its meshes, an OBJ with its MTL
    /// and textures: each packed into one .tar.gz, the same bytes every time, so a re-submission
    /// is the same asset), or one batch manifest of objects in the store (`.json`:
    /// `{"items": [{"url": ...}], "batch": ...}`, or `.jsonl`: one item per line, read as it is
    /// sent), submitted in chunks; each refused item is named with why, the others go on.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Priority of the jobs (higher runs first).
    #[arg(long, default_value_t = 0)]
    pub priority: i32,
    /// Add the jobs to this batch (its dataset statistics: `GET /v1/batches/{batch}/stats` and
    /// the dashboard); for a manifest, sets its `batch` unless it has one.
    #[arg(long)]
    pub batch: Option<String>,
    /// Follow the jobs with progress bars until they finish.
    #[arg(long)]
    pub watch: bool,
}

/// `uniphys status`.
#[derive(Debug, clap::Args)]
pub struct StatusArgs {
    /// The API and the key.
    #[command(flatten)]
    pub client: ClientArgs,
    /// An asset id (`asset_12`); without it, the newest jobs.
    pub asset: Option<String>,
    /// Print the API's JSON.
    #[arg(long)]
    pub json: bool,
}

/// A client of the service's HTTP API with its key.
pub(crate) struct Client {
    http: reqwest::blocking::Client,
    base: String,
    key: String,
}

impl Client {
    pub(crate) fn new(args: &ClientArgs) -> anyhow::Result<Self> {
        let key = match &args.api_key {
            Some(key) => key.clone(),
            None => {
                let file = args.data_dir.join("api-key");
                std::fs::read_to_string(&file)
                    .map(|k| k.trim().to_owned())
                    .with_context(|| {
                        format!(
                            "no API key: pass --api-key (or UNIPHYS_API_KEY), or start `uniphys serve` here so {} exists",
                            file.display()
                        )
                    })?
            }
        };
        let http = reqwest::blocking::Client::builder()
            .timeout(Duration::from_secs(600))
            .build()
            .context("cannot set up the HTTP client")?;
        Ok(Self {
            http,
            base: args.api_url.trim_end_matches('/').to_owned(),
            key,
        })
    }

    /// A request for `path` of the API, with the key.
    fn request(&self, method: reqwest::Method, path: &str) -> reqwest::blocking::RequestBuilder {
        self.http
            .request(method, format!("{}{path}", self.base))
            .header("authorization", format!("Bearer {}", self.key))
    }

    fn answer(
        &self,
        response: reqwest::Result<reqwest::blocking::Response>,
        what: &str,
    ) -> anyhow::Result<Value> {
        let response =
            response.with_context(|| format!("{what}: cannot reach the API at {}", self.base))?;
        let status = response.status();
        let body: Value = response
            .bytes()
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
            .unwrap_or(Value::Null);
        if status.is_success() {
            return Ok(body);
        }
        let message = body["error"]["message"]
            .as_str()
            .map_or_else(|| format!("HTTP {status}"), str::to_owned);
        bail!("{what}: {message} (HTTP {})", status.as_u16())
    }

    pub(crate) fn get(&self, path: &str) -> anyhow::Result<Value> {
        let response = self.request(reqwest::Method::GET, path).send();
        self.answer(response, &format!("GET {path}"))
    }

    /// `POST path` with no body.
    pub(crate) fn post(&self, path: &str) -> anyhow::Result<Value> {
        let response = self.request(reqwest::Method::POST, path).send();
        self.answer(response, &format!("POST {path}"))
    }

    /// Streams `GET path` into a new file at `dest`; returns its lowercase hex SHA-256 and size.
    pub(crate) fn download(&self, path: &str, dest: &Path) -> anyhow::Result<(String, u64)> {
        use sha2::Digest;
        let mut response = self
            .request(reqwest::Method::GET, path)
            .send()
            .with_context(|| format!("GET {path}: cannot reach the API at {}", self.base))?;
        if !response.status().is_success() {
            bail!("GET {path}: HTTP {}", response.status().as_u16());
        }
        let mut file = std::fs::File::create(dest)
            .with_context(|| format!("cannot create {}", dest.display()))?;
        let mut hasher = sha2::Sha256::new();
        let mut buffer = vec![0u8; 1 << 16];
        let mut size = 0u64;
        loop {
            let n = std::io::Read::read(&mut response, &mut buffer)
                .with_context(|| format!("GET {path}: the download broke off"))?;
            if n == 0 {
                break;
            }
            hasher.update(&buffer[..n]);
            std::io::Write::write_all(&mut file, &buffer[..n])
                .with_context(|| format!("cannot write {}", dest.display()))?;
            size += n as u64;
        }
        Ok((hex::encode(hasher.finalize()), size))
    }

    fn upload(&self, file: &Path, priority: i32, batch: Option<&str>) -> anyhow::Result<Value> {
        let name = file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .with_context(|| format!("{} has no file name", file.display()))?;
        let handle =
            std::fs::File::open(file).with_context(|| format!("cannot open {}", file.display()))?;
        let mut url = reqwest::Url::parse(&format!("{}/v1/assets", self.base))
            .with_context(|| format!("{} is not a URL", self.base))?;
        url.query_pairs_mut()
            .append_pair("filename", &name)
            .append_pair("priority", &priority.to_string());
        if let Some(batch) = batch {
            url.query_pairs_mut().append_pair("batch", batch);
        }
        let response = self
            .http
            .post(url)
            .header("authorization", format!("Bearer {}", self.key))
            .header("content-type", "application/octet-stream")
            .body(handle)
            .send();
        self.answer(response, &format!("upload {}", file.display()))
    }

    /// `POST /v1/batches` with `body`; a full backlog (429) or an unavailable service (503) is
    /// waited out as its `Retry-After` says and the same body sent again (known items answer
    /// 200 with their jobs, so a repeat makes nothing twice).
    pub(crate) fn post_batch(&self, body: &Value) -> anyhow::Result<Value> {
        let bytes = serde_json::to_vec(body).context("the batch as JSON")?;
        loop {
            let response = self
                .request(reqwest::Method::POST, "/v1/batches")
                .header("content-type", "application/json")
                .body(bytes.clone())
                .send();
            if let Ok(r) = &response {
                let status = r.status().as_u16();
                if status == 429 || status == 503 {
                    let wait_secs = r
                        .headers()
                        .get("retry-after")
                        .and_then(|v| v.to_str().ok())
                        .and_then(|v| v.parse::<u64>().ok())
                        .unwrap_or(5)
                        .clamp(1, 300);
                    eprintln!("the service is busy (HTTP {status}): waiting {wait_secs} s");
                    std::thread::sleep(Duration::from_secs(wait_secs));
                    continue;
                }
            }
            return self.answer(response, "POST /v1/batches");
        }
    }
}

/// `uniphys submit`.
pub fn submit(args: &SubmitArgs) -> anyhow::Result<ExitCode> {
    let client = Client::new(&args.client)?;
    let mut submitted: Vec<(String, String)> = Vec::new();
    let is_manifest = |p: &PathBuf| p.extension().is_some_and(|e| e == "json" || e == "jsonl");
    if args.inputs.len() == 1 && is_manifest(&args.inputs[0]) {
        submitted =
            super::manifest::submit_manifest(&client, &args.inputs[0], args.batch.as_deref())?;
    } else {
        for input in &args.inputs {
            let packed = packed_folder(input)?;
            let file = packed
                .as_ref()
                .map_or(input.as_path(), |(_, p)| p.as_path());
            let answer = client.upload(file, args.priority, args.batch.as_deref())?;
            let asset = answer["asset_id"].as_str().unwrap_or_default().to_owned();
            let created = if answer["created"] == Value::Bool(true) {
                "new"
            } else {
                "already submitted"
            };
            println!(
                "{}: {asset} job {} ({created})",
                input.display(),
                answer["job_id"].as_str().unwrap_or_default()
            );
            submitted.push((input.display().to_string(), asset));
        }
    }
    if !args.watch {
        return Ok(ExitCode::SUCCESS);
    }
    watch(&client, &submitted)
}

/// A folder packed into `<folder name>.tar.gz` in a temporary folder (removed on drop), or `None`
/// for a file.
fn packed_folder(input: &Path) -> anyhow::Result<Option<(tempfile::TempDir, PathBuf)>> {
    if !input.is_dir() {
        return Ok(None);
    }
    let name = input
        .canonicalize()
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .filter(|n| !n.is_empty())
        .unwrap_or_else(|| "asset".to_owned());
    let dir = tempfile::tempdir().context("a temporary folder to pack into")?;
    let archive = dir.path().join(format!("{name}.tar.gz"));
    let packed = uniphys_archive::pack_folder(input, &archive)
        .with_context(|| format!("cannot pack the folder {}", input.display()))?;
    eprintln!(
        "{}: packed {} files ({} bytes), read from {}",
        input.display(),
        packed.files,
        packed.bytes,
        packed.main_file
    );
    Ok(Some((dir, archive)))
}

/// Whether a job state is final.
fn finished(state: &str) -> bool {
    matches!(state, "succeeded" | "dead" | "cancelled")
}

fn watch(client: &Client, submitted: &[(String, String)]) -> anyhow::Result<ExitCode> {
    let bars = MultiProgress::new();
    let style = ProgressStyle::with_template("{prefix:30} [{bar:30}] {pos:>3}% {msg}")
        .context("progress style")?
        .progress_chars("=> ");
    let tracked: Vec<(ProgressBar, &str)> = submitted
        .iter()
        .map(|(label, asset)| {
            let bar = bars.add(ProgressBar::new(100));
            bar.set_style(style.clone());
            bar.set_prefix(label.clone());
            (bar, asset.as_str())
        })
        .collect();
    let mut all_ok = true;
    let mut open: Vec<usize> = (0..tracked.len()).collect();
    while !open.is_empty() {
        let mut still = Vec::new();
        for i in open {
            let (bar, asset) = &tracked[i];
            let detail = client.get(&format!("/v1/assets/{asset}"))?;
            let job = &detail["job"];
            let state = job["state"].as_str().unwrap_or("unknown");
            let stages = job["stages"].as_array().cloned().unwrap_or_default();
            let done = stages.iter().filter(|s| s["state"] == "succeeded").count();
            let current = stages
                .iter()
                .find(|s| s["state"] == "running" || s["state"] == "ready");
            let within = current
                .and_then(|s| s["progress"]["fraction"].as_f64())
                .unwrap_or(0.0);
            let total = stages.len().max(1) as f64;
            bar.set_position((100.0 * (done as f64 + within) / total).round() as u64);
            if finished(state) {
                let last_error = stages
                    .iter()
                    .rev()
                    .find_map(|s| s["errors"].as_array().and_then(|e| e.last()))
                    .and_then(|e| e["message"].as_str());
                let message = match (state, last_error) {
                    ("succeeded", _) => "succeeded".to_owned(),
                    (s, Some(e)) => format!("{s}: {e}"),
                    (s, None) => s.to_owned(),
                };
                all_ok &= state == "succeeded";
                bar.finish_with_message(message);
            } else {
                let message = current
                    .map(|s| {
                        let note = s["progress"]["message"].as_str().unwrap_or("");
                        format!("{} {}", s["name"].as_str().unwrap_or(""), note)
                    })
                    .unwrap_or_else(|| state.to_owned());
                bar.set_message(message);
                still.push(i);
            }
        }
        open = still;
        if !open.is_empty() {
            std::thread::sleep(Duration::from_millis(500));
        }
    }
    Ok(if all_ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// `uniphys status`.
pub fn status(args: &StatusArgs) -> anyhow::Result<ExitCode> {
    let client = Client::new(&args.client)?;
    match &args.asset {
        Some(asset) => {
            let detail = client.get(&format!("/v1/assets/{asset}"))?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&detail)?);
                return Ok(ExitCode::SUCCESS);
            }
            let job = &detail["job"];
            println!(
                "{asset}  {}  job {} {}",
                detail["asset"]["source_key"].as_str().unwrap_or(""),
                job["id"].as_str().unwrap_or("-"),
                job["state"].as_str().unwrap_or("-")
            );
            println!(
                "{:<12} {:<10} {:>7} {:>10}  note",
                "stage", "state", "attempt", "secs"
            );
            for stage in job["stages"].as_array().into_iter().flatten() {
                let secs = stage["duration_ms"]
                    .as_i64()
                    .map_or("-".to_owned(), |ms| format!("{:.1}", ms as f64 / 1000.0));
                let running = stage["state"] == "running";
                let note = stage["errors"]
                    .as_array()
                    .and_then(|e| e.last())
                    .and_then(|e| e["message"].as_str())
                    .or_else(|| {
                        running
                            .then(|| stage["progress"]["message"].as_str())
                            .flatten()
                    })
                    .unwrap_or("");
                println!(
                    "{:<12} {:<10} {:>3}/{:<3} {:>10}  {note}",
                    stage["name"].as_str().unwrap_or(""),
                    stage["state"].as_str().unwrap_or(""),
                    stage["attempt"],
                    stage["max_attempts"],
                    secs
                );
            }
        }
        None => {
            let list = client.get("/v1/assets?limit=20")?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&list)?);
                return Ok(ExitCode::SUCCESS);
            }
            println!("{:<14} {:<14} {:<10}", "asset", "job", "state");
            for item in list["items"].as_array().into_iter().flatten() {
                println!(
                    "{:<14} {:<14} {:<10}",
                    item["asset_id"].as_str().unwrap_or(""),
                    item["job_id"].as_str().unwrap_or(""),
                    item["state"].as_str().unwrap_or("")
                );
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}
