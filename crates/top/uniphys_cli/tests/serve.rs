//! The embedded service end to end, as a user runs it: `uniphys serve` with no configuration
//! (SQLite and a local directory under its data dir), `uniphys submit --watch` of two example
//! files and a real PartNet-Mobility folder (packed by `submit`) through the real pipeline into a
//! batch, `uniphys status`, a readable error for an unknown asset, `uniphys dataset export` of the
//! batch (and again, resumed; and by the service into its object store), and a clean exit on
//! SIGTERM.

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
    // A table with a drawer, as PartNet-Mobility ships it: a URDF and its OBJ and MTL files.
    let table = uniphys_examples::shared_partnet_object("gensim2-20453");
    let submit = uniphys(dir.path(), &api_url)
        .args(["submit", "--watch", "--batch", "shelf"])
        .arg(examples.join("mug.glb"))
        .arg(examples.join("box_with_lid.glb"))
        .arg(&table)
        .output()
        .expect("submit runs");
    let stdout = String::from_utf8_lossy(&submit.stdout);
    assert!(
        submit.status.success(),
        "submit --watch: {stdout}{}",
        String::from_utf8_lossy(&submit.stderr)
    );
    assert!(
        stdout.contains("asset_1") && stdout.contains("asset_2") && stdout.contains("asset_3"),
        "{stdout}"
    );
    assert!(
        String::from_utf8_lossy(&submit.stderr).contains("read from mobility.urdf"),
        "the folder was packed"
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

    // A manifest of objects already in the store (the local store is a folder of the data dir),
    // one missing: the others go on, the missing one is named; sent again, nothing new.
    let incoming = dir.path().join("objects/incoming/t1");
    std::fs::create_dir_all(&incoming).expect("incoming");
    for name in ["cabinet.glb", "mug.glb"] {
        std::fs::copy(examples.join(name), incoming.join(format!("copy-{name}"))).expect("copy");
    }
    let manifest = dir.path().join("manifest.jsonl");
    std::fs::write(
        &manifest,
        "{\"url\": \"incoming/t1/copy-cabinet.glb\"}\n{\"url\": \"incoming/t1/gone.glb\"}\n{\"url\": \"incoming/t1/copy-mug.glb\"}\n",
    )
    .expect("manifest");
    let send = || {
        uniphys(dir.path(), &api_url)
            .args(["submit", "--batch", "copies"])
            .arg(&manifest)
            .output()
            .expect("submit runs")
    };
    let sent = send();
    let sent_out = String::from_utf8_lossy(&sent.stdout);
    assert!(sent.status.success(), "{sent_out}");
    assert!(
        sent_out.contains("item 1: refused") && sent_out.contains("gone.glb"),
        "{sent_out}"
    );
    // The cabinet is new; the mug's bytes were submitted above under another name.
    assert!(
        sent_out.contains("1 new, 1 already submitted, 1 refused"),
        "{sent_out}"
    );
    let resent = send();
    let resent_out = String::from_utf8_lossy(&resent.stdout);
    assert!(
        resent_out.contains("0 new, 2 already submitted, 1 refused"),
        "{resent_out}"
    );

    let out = dir.path().join("datasets");
    let export = || {
        uniphys(dir.path(), &api_url)
            .args(["dataset", "export", "--batch", "shelf", "--out"])
            .arg(&out)
            .output()
            .expect("export runs")
    };
    let first = export();
    let first_out = String::from_utf8_lossy(&first.stdout);
    assert!(
        first.status.success() && first_out.contains("3 assets") && first_out.contains("3 new"),
        "{first_out}{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let root = out.join("shelf");
    let index = std::fs::read_to_string(root.join("index.csv")).expect("index");
    let rows: Vec<&str> = index.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{index}");
    let table_row = rows
        .iter()
        .find(|r| r.contains("gensim2-20453"))
        .expect("the table's row");
    let entity = root.join(table_row.split(',').next().expect("entity"));
    for file in [
        "model.urdf",
        "model.xml",
        "meta_data.json",
        "annotations/object.json",
        "annotations/part_0.json",
        "parts/part_0.obj",
        "npzs/model.npz",
        "coordinate_frame.json",
    ] {
        assert!(
            entity.join(file).is_file(),
            "{file} in {}",
            entity.display()
        );
    }
    // One movable joint, the drawer's slide, declared by the URDF.
    let fields: Vec<&str> = table_row.split(',').collect();
    assert_eq!((fields[7], fields[9]), ("1", "1"), "{table_row}");
    assert!(root.join("statistics.json").is_file() && root.join("failures.csv").is_file());
    let again = export();
    let again_out = String::from_utf8_lossy(&again.stdout);
    assert!(
        again.status.success() && again_out.contains("0 new, 3 already there"),
        "{again_out}"
    );
    // The same batch written by the service into its object store, the same entities.
    let in_store = uniphys(dir.path(), &api_url)
        .args(["dataset", "export", "--batch", "shelf", "--in-store"])
        .output()
        .expect("export runs");
    let in_store_out = String::from_utf8_lossy(&in_store.stdout);
    assert!(
        in_store.status.success() && in_store_out.contains("3 new and 0 already there"),
        "{in_store_out}{}",
        String::from_utf8_lossy(&in_store.stderr)
    );
    let stored = dir.path().join("objects/datasets/t1/shelf");
    let stored_index = std::fs::read_to_string(stored.join("index.csv")).expect("stored index");
    let entities = |index: &str| -> Vec<String> {
        let mut e: Vec<String> = index
            .lines()
            .skip(1)
            .map(|r| r.split(',').next().unwrap_or_default().to_owned())
            .collect();
        e.sort();
        e
    };
    assert_eq!(entities(&stored_index), entities(&index));
    let stored_entity = stored.join(table_row.split(',').next().expect("entity"));
    assert_eq!(
        std::fs::read(stored_entity.join("model.xml")).expect("stored model.xml"),
        std::fs::read(entity.join("model.xml")).expect("model.xml")
    );
    assert!(stored.join("export.json").is_file() && stored.join("failures.csv").is_file());

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
