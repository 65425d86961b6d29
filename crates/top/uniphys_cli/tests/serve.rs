//! The embedded service end to end, as a user runs it: `uniphys serve` with no configuration
//! (SQLite and a local directory under its data dir), `uniphys submit --watch` of two example
//! files through the real pipeline, `uniphys status`, a readable error for an unknown asset, and
//! a clean exit on SIGTERM.

use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn uniphys(data_dir: &Path, api_url: &str) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_uniphys"));
    command
        .env_clear()
        .env("PATH", std::env::var("PATH").unwrap_or_default())
        .env("UNIPHYS_DATA_DIR", data_dir)
        .env("UNIPHYS_API_URL", api_url);
    command
}

#[test]
fn serve_submit_watch_status_and_shutdown() {
    let dir = tempfile::tempdir().expect("temp dir");
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("free port");
    let api_url = format!("http://127.0.0.1:{port}");
    let mut server = uniphys(dir.path(), &api_url)
        .args(["serve", "--listen", &format!("127.0.0.1:{port}")])
        .env("UNIPHYS_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("serve starts");
    let stderr = server.stderr.take().expect("stderr");
    let mut lines = BufReader::new(stderr).lines();
    let until = Instant::now() + Duration::from_secs(60);
    loop {
        let line = lines
            .next()
            .expect("serve is running")
            .expect("stderr line");
        if line.starts_with("API on http://") {
            break;
        }
        assert!(Instant::now() < until, "serve did not start");
    }
    std::thread::spawn(move || lines.for_each(drop));
    assert!(
        dir.path().join("api-key").exists(),
        "serve wrote the local API key"
    );

    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../test_data/examples");
    let submit = uniphys(dir.path(), &api_url)
        .args(["submit", "--watch"])
        .arg(examples.join("mug.glb"))
        .arg(examples.join("box_with_lid.glb"))
        .output()
        .expect("submit runs");
    let stdout = String::from_utf8_lossy(&submit.stdout);
    assert!(
        submit.status.success(),
        "submit --watch: {stdout}{}",
        String::from_utf8_lossy(&submit.stderr)
    );
    assert!(
        stdout.contains("asset_1") && stdout.contains("asset_2"),
        "{stdout}"
    );

    let again = uniphys(dir.path(), &api_url)
        .arg("submit")
        .arg(examples.join("mug.glb"))
        .output()
        .expect("submit runs");
    let again_out = String::from_utf8_lossy(&again.stdout);
    assert!(
        again_out.contains("asset_1") && again_out.contains("already submitted"),
        "{again_out}"
    );

    let status = uniphys(dir.path(), &api_url)
        .args(["status", "asset_1"])
        .output()
        .expect("status runs");
    let status_out = String::from_utf8_lossy(&status.stdout);
    assert!(status.status.success(), "{status_out}");
    for expected in ["ingest", "convert", "succeeded", "mug.glb"] {
        assert!(status_out.contains(expected), "{expected} in {status_out}");
    }

    let unknown = uniphys(dir.path(), &api_url)
        .args(["status", "asset_999"])
        .output()
        .expect("status runs");
    assert_eq!(unknown.status.code(), Some(2));
    let message = String::from_utf8_lossy(&unknown.stderr);
    assert!(
        message.contains("404") && message.contains("asset"),
        "{message}"
    );

    for (args, expected) in [
        (&["stage", "pause", "convert"][..], "convert: paused"),
        (&["stage", "paused"][..], "convert"),
        (&["stage", "resume", "convert"][..], "convert: resumed"),
    ] {
        let out = uniphys(dir.path(), &api_url)
            .args(args)
            .output()
            .expect("stage runs");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && text.contains(expected),
            "{args:?}: {text}"
        );
    }

    let term = Command::new("kill")
        .args(["-TERM", &server.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(term.success());
    let exit = server.wait().expect("serve exits");
    assert!(exit.success(), "serve exit on SIGTERM: {exit}");
}
