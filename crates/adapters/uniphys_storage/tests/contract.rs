//! The storage contract (create-only writes, checksummed "already present", conflicts, streaming
//! files, key validation) run against every kind of store: local directory, memory, and S3 through
//! moto's server when it is installed.
#![allow(clippy::unwrap_used)]

use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures::TryStreamExt;
use object_store::aws::{AmazonS3Builder, S3ConditionalPut, S3CopyIfNotExists};
use object_store::path::Path as StorePath;
use object_store::{ObjectStore, ObjectStoreExt, PutMode, PutPayload};
use sha2::{Digest, Sha256};
use uniphys_storage::{
    ArtifactKey, ArtifactStore, PutOutcome, STAGING_PREFIX, StorageError, StorageOptions,
};

/// Size of the file streamed through `put_file`: more than one 8 MiB multipart part.
const BIG_FILE_BYTES: usize = 12 << 20;

/// Deterministic pseudo-random bytes (xorshift), different for each `seed`.
fn pseudo_random(len: usize, seed: u64) -> Vec<u8> {
    let mut x = seed | 1;
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x.to_le_bytes()[3]
        })
        .collect()
}

fn export_key() -> ArtifactKey {
    ArtifactKey {
        asset: "cabinet".into(),
        stage: "export".into(),
        stage_version: 2,
        input_digest: "ab12".into(),
    }
}

async fn check_put_once(store: &ArtifactStore) {
    let urdf = export_key().file("model.urdf").unwrap();
    assert_eq!(
        store.put_once(&urdf, b"<robot/>".to_vec()).await.unwrap(),
        PutOutcome::Created
    );
    assert_eq!(
        store.put_once(&urdf, b"<robot/>".to_vec()).await.unwrap(),
        PutOutcome::AlreadyPresent
    );
    let conflict = store.put_once(&urdf, b"<robot name='x'/>".to_vec()).await;
    assert!(
        matches!(&conflict, Err(StorageError::Conflict { key }) if *key == urdf),
        "{conflict:?}"
    );
    // The original content is unchanged.
    assert_eq!(store.get(&urdf).await.unwrap(), b"<robot/>");
    assert_eq!(store.head(&urdf).await.unwrap(), Some(8));
    assert_eq!(
        store.sha256_hex(&urdf).await.unwrap(),
        hex::encode(Sha256::digest(b"<robot/>"))
    );
    // An empty object is content too.
    let empty = export_key().file("empty.txt").unwrap();
    assert_eq!(
        store.put_once(&empty, Vec::new()).await.unwrap(),
        PutOutcome::Created
    );
    assert_eq!(
        store.put_once(&empty, Vec::new()).await.unwrap(),
        PutOutcome::AlreadyPresent
    );
    assert!(matches!(
        store.put_once(&empty, b"x".to_vec()).await,
        Err(StorageError::Conflict { .. })
    ));
}

async fn check_missing_and_invalid_keys(store: &ArtifactStore, scratch: &Path) {
    let missing = export_key().file("missing.bin").unwrap();
    assert_eq!(store.head(&missing).await.unwrap(), None);
    assert!(matches!(
        store.get(&missing).await,
        Err(StorageError::NotFound { .. })
    ));
    assert!(matches!(
        store.get_stream(&missing).await.map(|_| ()),
        Err(StorageError::NotFound { .. })
    ));
    assert!(matches!(
        store.get_to_file(&missing, &scratch.join("missing")).await,
        Err(StorageError::NotFound { .. })
    ));
    assert!(!scratch.join("missing").exists());
    assert!(!scratch.join("missing.partial").exists());

    let file = scratch.join("small.bin");
    std::fs::write(&file, b"abc").unwrap();
    for bad in [
        "../escape",
        "a/../../b",
        "a//b",
        "./a",
        "a/.",
        "",
        "a/\u{0}b",
    ] {
        assert!(
            matches!(
                store.put_once(bad, b"x".to_vec()).await,
                Err(StorageError::InvalidKey(_))
            ),
            "put_once {bad:?}"
        );
        assert!(
            matches!(
                store.put_file(bad, &file).await,
                Err(StorageError::InvalidKey(_))
            ),
            "put_file {bad:?}"
        );
        assert!(
            matches!(store.head(bad).await, Err(StorageError::InvalidKey(_))),
            "head {bad:?}"
        );
        assert!(
            matches!(
                store.get_stream(bad).await.map(|_| ()),
                Err(StorageError::InvalidKey(_))
            ),
            "get_stream {bad:?}"
        );
    }
}

async fn check_files(store: &ArtifactStore, scratch: &Path) {
    let mesh_key = export_key().file("meshes/body.glb").unwrap();
    let original = pseudo_random(BIG_FILE_BYTES, 7);
    let source = scratch.join("body.glb");
    std::fs::write(&source, &original).unwrap();

    assert_eq!(
        store.put_file(&mesh_key, &source).await.unwrap(),
        PutOutcome::Created
    );
    assert_eq!(
        store.put_file(&mesh_key, &source).await.unwrap(),
        PutOutcome::AlreadyPresent
    );
    // put_once and put_file agree on what "the same content" is.
    assert_eq!(
        store.put_once(&mesh_key, original.clone()).await.unwrap(),
        PutOutcome::AlreadyPresent
    );
    let other = scratch.join("other.glb");
    std::fs::write(&other, pseudo_random(BIG_FILE_BYTES, 8)).unwrap();
    assert!(matches!(
        store.put_file(&mesh_key, &other).await,
        Err(StorageError::Conflict { .. })
    ));

    let size = u64::try_from(BIG_FILE_BYTES).unwrap();
    assert_eq!(store.head(&mesh_key).await.unwrap(), Some(size));
    let target = scratch.join("down/loaded/body.glb");
    assert_eq!(store.get_to_file(&mesh_key, &target).await.unwrap(), size);
    assert!(std::fs::read(&target).unwrap() == original);

    let (streamed_size, stream) = store.get_stream(&mesh_key).await.unwrap();
    assert_eq!(streamed_size, size);
    let chunks: Vec<bytes::Bytes> = stream.try_collect().await.unwrap();
    assert!(chunks.concat() == original);

    // A second file races no one: a different key is created independently.
    let copy_key = export_key().file("meshes/other.glb").unwrap();
    assert_eq!(
        store.put_file(&copy_key, &other).await.unwrap(),
        PutOutcome::Created
    );
    assert!(matches!(
        store
            .put_file(&copy_key, &scratch.join("no-such-file"))
            .await,
        Err(StorageError::Conflict { .. } | StorageError::LocalFile { .. })
    ));

    // Uploads leave nothing in the staging area, and listing shows only artifacts.
    assert_eq!(
        store.list(STAGING_PREFIX).await.unwrap(),
        Vec::<String>::new()
    );
    let prefix = export_key().to_string();
    assert_eq!(
        store.list(&prefix).await.unwrap(),
        [
            format!("{prefix}/empty.txt"),
            format!("{prefix}/meshes/body.glb"),
            format!("{prefix}/meshes/other.glb"),
            format!("{prefix}/model.urdf"),
        ]
    );
}

async fn check_delete_prefix(store: &ArtifactStore) {
    store
        .put_once("cabinetry/x", b"keep".to_vec())
        .await
        .unwrap();
    let prefix = export_key().to_string();
    assert_eq!(store.delete_prefix(&prefix).await.unwrap(), 4);
    assert_eq!(store.list(&prefix).await.unwrap(), Vec::<String>::new());
    // Prefixes are whole components: `cabinet` does not match `cabinetry`.
    assert_eq!(store.delete_prefix("cabinet").await.unwrap(), 0);
    assert_eq!(store.get("cabinetry/x").await.unwrap(), b"keep");
    // One object: deleted, and deleting it again (or a missing key) is not an error.
    store.put_once("single/y", b"gone".to_vec()).await.unwrap();
    store.delete("single/y").await.unwrap();
    assert!(matches!(
        store.get("single/y").await,
        Err(uniphys_storage::StorageError::NotFound { .. })
    ));
    store.delete("single/y").await.unwrap();
}

/// Two writers racing on one key with different content: exactly one wins, the other gets a
/// conflict, and the stored object is the winner's, whichever path (conditional write or the
/// existence check before it) caught the loser.
///
/// Under `Writes::ConditionalNotAtomic` both writers may also be answered `Created`, as long as
/// the stored object is exactly one writer's bytes (never a mix, never lost).
async fn check_racing_writers(store: &ArtifactStore, scratch: &Path, writes: Writes) {
    for round in 0..4u64 {
        let key = format!("race/{round}/bytes.bin");
        let (a, b) = (
            pseudo_random(1000, 2 * round + 1),
            pseudo_random(1000, 2 * round + 2),
        );
        let (ra, rb) = tokio::join!(
            store.put_once(&key, a.clone()),
            store.put_once(&key, b.clone())
        );
        let stored = store.get(&key).await.unwrap();
        judge_race(
            &format!("put_once race {round}"),
            (ra, rb),
            &stored,
            (&a, &b),
            writes,
        );

        let key = format!("race/{round}/file.bin");
        let (fa, fb) = (scratch.join("race-a"), scratch.join("race-b"));
        std::fs::write(&fa, &a).unwrap();
        std::fs::write(&fb, &b).unwrap();
        let (ra, rb) = tokio::join!(store.put_file(&key, &fa), store.put_file(&key, &fb));
        let stored = store.get(&key).await.unwrap();
        judge_race(
            &format!("put_file race {round}"),
            (ra, rb),
            &stored,
            (&a, &b),
            writes,
        );
    }
    assert_eq!(store.delete_prefix("race").await.unwrap(), 8);
}

/// The two racing writers' outcomes `(ra, rb)` and the `stored` object against their bytes
/// `(a, b)`, as [`check_racing_writers`] requires; `what` names the race in a failure.
fn judge_race(
    what: &str,
    outcomes: (
        Result<PutOutcome, StorageError>,
        Result<PutOutcome, StorageError>,
    ),
    stored: &[u8],
    (a, b): (&[u8], &[u8]),
    writes: Writes,
) {
    match outcomes {
        (Ok(PutOutcome::Created), Err(StorageError::Conflict { .. })) => assert!(stored == a),
        (Err(StorageError::Conflict { .. }), Ok(PutOutcome::Created)) => assert!(stored == b),
        (Ok(PutOutcome::Created), Ok(PutOutcome::Created))
            if writes == Writes::ConditionalNotAtomic =>
        {
            assert!(stored == a || stored == b, "{what}: torn object");
        }
        other => panic!("{what}: {other:?}"),
    }
}

/// How a store catches a second writer.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Writes {
    /// Create-only writes in the store: racing writers are told apart.
    Conditional,
    /// Create-only writes that the store checks and applies in two steps (moto's `If-None-Match`
    /// is not atomic, unlike S3's): a sequential re-run is refused, but two writers racing may
    /// both be answered `Created`; the stored object must still be one writer's whole bytes.
    ConditionalNotAtomic,
    /// The head-compare-put fallback: sequential re-runs are caught, racing writers are not
    /// (both may see "absent" and the last write wins), so races are not checked.
    Fallback,
}

async fn check_contract(store: &ArtifactStore, scratch: &Path, writes: Writes) {
    check_put_once(store).await;
    if writes != Writes::Fallback {
        check_racing_writers(store, scratch, writes).await;
    }
    check_missing_and_invalid_keys(store, scratch).await;
    check_files(store, scratch).await;
    check_delete_prefix(store).await;
}

#[tokio::test]
async fn local_directory_store_keeps_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("artifacts");
    let store =
        ArtifactStore::from_url(root.to_str().unwrap(), &StorageOptions::default()).unwrap();
    let scratch = dir.path().join("scratch");
    std::fs::create_dir_all(&scratch).unwrap();
    check_contract(&store, &scratch, Writes::Conditional).await;
    // Nothing escaped the store's directory.
    assert!(!dir.path().join("escape").exists());
    assert_eq!(
        std::fs::read(root.join("cabinetry/x")).unwrap(),
        b"keep".to_vec()
    );
}

#[tokio::test]
async fn memory_store_keeps_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let store = ArtifactStore::from_url("memory://", &StorageOptions::default()).unwrap();
    check_contract(&store, dir.path(), Writes::Conditional).await;
}

/// A moto S3 server on a free port, stopped when dropped.
struct Moto {
    child: Child,
    endpoint: String,
}

impl Drop for Moto {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn moto_server_binary() -> Option<PathBuf> {
    let venv = std::env::var_os("UNIPHYS_VENV").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../.venv"),
        PathBuf::from,
    );
    let bin = venv.join("bin/moto_server");
    bin.is_file().then_some(bin)
}

fn start_moto() -> Option<Moto> {
    let bin = moto_server_binary()?;
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let child = Command::new(bin)
        .args(["-H", "127.0.0.1", "-p", &port.to_string()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let moto = Moto {
        child,
        endpoint: format!("http://127.0.0.1:{port}"),
    };
    // Startup wait, not a timing assertion: moto takes a few seconds to import.
    let deadline = Instant::now() + Duration::from_secs(60);
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "moto_server did not start");
        std::thread::sleep(Duration::from_millis(100));
    }
    Some(moto)
}

/// Creates a bucket (moto accepts unsigned bucket creation; `object_store` cannot create buckets).
async fn create_bucket(endpoint: &str, bucket: &str) {
    let response = reqwest::Client::new()
        .put(format!("{endpoint}/{bucket}"))
        .send()
        .await
        .unwrap();
    assert!(response.status().is_success(), "{}", response.status());
}

fn moto_options(endpoint: &str) -> StorageOptions {
    StorageOptions {
        endpoint: Some(endpoint.to_owned()),
        region: Some("us-east-1".into()),
        access_key_id: Some("testing".into()),
        secret_access_key: Some("testing".into()),
        session_token: None,
        allow_http: true,
        virtual_hosted_style: false,
    }
}

#[tokio::test]
async fn s3_store_on_moto_keeps_the_contract() {
    let moto = start_moto().expect(
        "moto_server is missing from the venv: run the README's test command, which installs it",
    );
    let dir = tempfile::tempdir().unwrap();
    create_bucket(&moto.endpoint, "artifacts").await;
    let options = moto_options(&moto.endpoint);

    // Bucket root.
    let store = ArtifactStore::from_url("s3://artifacts", &options).unwrap();
    check_contract(&store, dir.path(), Writes::ConditionalNotAtomic).await;

    // A prefix inside the bucket isolates a second store from the first.
    let prefixed = ArtifactStore::from_url("s3://artifacts/tenant-a/run-1", &options).unwrap();
    check_contract(&prefixed, dir.path(), Writes::ConditionalNotAtomic).await;
    assert_eq!(store.get("cabinetry/x").await.unwrap(), b"keep");
    assert_eq!(
        store.get("tenant-a/run-1/cabinetry/x").await.unwrap(),
        b"keep"
    );

    // What the create-only paths rely on, asked of moto directly through object_store: a put with
    // `If-None-Match: *` and a multipart copy completed with `If-None-Match: *` onto an existing key
    // are both refused (moto answers 412), never applied.
    let raw = AmazonS3Builder::new()
        .with_bucket_name("artifacts")
        .with_region("us-east-1")
        .with_endpoint(&moto.endpoint)
        .with_allow_http(true)
        .with_access_key_id("testing")
        .with_secret_access_key("testing")
        .with_copy_if_not_exists(S3CopyIfNotExists::Multipart)
        .build()
        .unwrap();
    let existing = StorePath::from("cabinetry/x");
    let refused = raw
        .put_opts(
            &existing,
            PutPayload::from_static(b"other"),
            PutMode::Create.into(),
        )
        .await;
    assert!(
        matches!(refused, Err(object_store::Error::AlreadyExists { .. })),
        "{refused:?}"
    );
    let source = StorePath::from("probe/source");
    raw.put(&source, PutPayload::from_static(b"other"))
        .await
        .unwrap();
    let refused = raw.copy_if_not_exists(&source, &existing).await;
    assert!(
        matches!(refused, Err(object_store::Error::AlreadyExists { .. })),
        "{refused:?}"
    );
    assert_eq!(store.get("cabinetry/x").await.unwrap(), b"keep");

    // Wrong bucket: an error, not a panic or a silent success.
    let missing = ArtifactStore::from_url("s3://no-such-bucket", &options).unwrap();
    assert!(missing.put_once("a/b", b"x".to_vec()).await.is_err());
}

/// The fallback path for stores without conditional puts (head, compare, then put), run against
/// moto with conditional puts switched off in `object_store`.
#[tokio::test]
async fn s3_store_without_conditional_put_falls_back_to_head_and_compare() {
    let moto = start_moto().expect(
        "moto_server is missing from the venv: run the README's test command, which installs it",
    );
    let dir = tempfile::tempdir().unwrap();
    create_bucket(&moto.endpoint, "fallback").await;
    let s3 = AmazonS3Builder::new()
        .with_bucket_name("fallback")
        .with_region("us-east-1")
        .with_endpoint(&moto.endpoint)
        .with_allow_http(true)
        .with_access_key_id("testing")
        .with_secret_access_key("testing")
        .with_conditional_put(S3ConditionalPut::Disabled)
        .build()
        .unwrap();
    let store = ArtifactStore::from_object_store(Arc::new(s3));
    check_contract(&store, dir.path(), Writes::Fallback).await;
}
