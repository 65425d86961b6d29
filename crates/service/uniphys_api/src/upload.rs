//! Streaming an upload to a spool file while hashing it, under a size cap; and the names and
//! content types of stored files.

use std::path::PathBuf;
use std::time::Duration;

use axum::body::{Body, Bytes};
use futures::StreamExt;
use sha2::{Digest, Sha256};
use tempfile::TempPath;
use tokio::io::AsyncWriteExt;
use uniphys_archive::{ArchiveError, ArchiveKind, ArchiveLimits};
use uniphys_types::SourceFormat;

use crate::error::{ApiError, ApiResult, error_chain};

/// Longest stored filename, in bytes (the extension is kept when a name is cut).
const MAX_FILENAME_BYTES: usize = 120;
/// Spool files of this service start with this, so a restart can sweep the ones a crash left.
const SPOOL_PREFIX: &str = "uniphys-upload-";
/// A spool file untouched this long belongs to no upload in progress.
pub(crate) const STALE_SPOOL: std::time::Duration = std::time::Duration::from_secs(3600);

/// An upload on local disk (deleted when dropped), with its digest and size.
#[derive(Debug)]
pub(crate) struct Spooled {
    /// The spool file.
    pub path: TempPath,
    /// Lowercase hex SHA-256 of the content.
    pub sha256_hex: String,
    /// Its size.
    pub size_bytes: u64,
}

/// Writes `body` to a new file in `dir` (or the system temp dir), hashing it on the way; the body
/// is never held whole in memory. More than `max_bytes` answers 413, and no bytes for
/// `pause_max` answers 408; either leaves no file.
pub(crate) async fn spool_body(
    body: Body,
    dir: Option<PathBuf>,
    max_bytes: u64,
    pause_max: Duration,
) -> ApiResult<Spooled> {
    let chunk_error = |e: Paced<axum::Error>| match e {
        Paced::Stalled => ApiError::RequestTimeout(format!(
            "the upload stopped arriving: no bytes for {} s; send the body without pauses",
            pause_max.as_secs_f64()
        )),
        Paced::Failed(e) => {
            ApiError::bad_request("invalid_body", format!("reading the upload failed: {e}"))
        }
    };
    spool(
        paced(body.into_data_stream(), pause_max),
        dir,
        max_bytes,
        chunk_error,
    )
    .await
}

/// A chunk error of a stream read with a pause limit: the stream's own, or no chunk in time.
enum Paced<E> {
    /// No chunk arrived within the limit.
    Stalled,
    /// The stream failed.
    Failed(E),
}

/// `stream` with every wait for a chunk limited to `pause_max`; a stall ends the stream with
/// [`Paced::Stalled`].
fn paced<S, E>(
    stream: S,
    pause_max: Duration,
) -> impl futures::Stream<Item = Result<Bytes, Paced<E>>> + Unpin
where
    S: futures::Stream<Item = Result<Bytes, E>> + Unpin,
{
    Box::pin(futures::stream::unfold(
        (stream, false),
        move |(mut stream, stalled)| async move {
            if stalled {
                return None;
            }
            match tokio::time::timeout(pause_max, stream.next()).await {
                Err(_) => Some((Err(Paced::Stalled), (stream, true))),
                Ok(None) => None,
                Ok(Some(chunk)) => Some((chunk.map_err(Paced::Failed), (stream, false))),
            }
        },
    ))
}

/// Writes the chunks of `stream` to a new spool file, hashing them, up to `max_bytes`; a chunk
/// error becomes `read_error(e)`.
pub(crate) async fn spool<S, E>(
    mut stream: S,
    dir: Option<PathBuf>,
    max_bytes: u64,
    read_error: impl Fn(E) -> ApiError,
) -> ApiResult<Spooled>
where
    S: futures::Stream<Item = Result<Bytes, E>> + Unpin,
{
    let (file, path) = spool_file(dir).await?;
    let mut file = tokio::fs::File::from_std(file);
    let mut hasher = Sha256::new();
    let mut size_bytes = 0u64;
    while let Some(chunk) = stream.next().await {
        let chunk = chunk.map_err(&read_error)?;
        size_bytes += chunk.len() as u64;
        if size_bytes > max_bytes {
            return Err(too_large(max_bytes));
        }
        hasher.update(&chunk);
        file.write_all(&chunk).await.map_err(spool_error)?;
    }
    file.flush().await.map_err(spool_error)?;
    Ok(Spooled {
        path,
        sha256_hex: hex::encode(hasher.finalize()),
        size_bytes,
    })
}

/// A new, empty spool file in `dir` (or the system temp dir), removed when its path is dropped.
pub(crate) async fn spool_file(dir: Option<PathBuf>) -> ApiResult<(std::fs::File, TempPath)> {
    Ok(tokio::task::spawn_blocking(move || {
        let mut builder = tempfile::Builder::new();
        builder.prefix(SPOOL_PREFIX);
        match dir {
            Some(dir) => builder.tempfile_in(dir),
            None => builder.tempfile(),
        }
    })
    .await
    .map_err(|e| ApiError::Internal(format!("spool task failed: {e}")))?
    .map_err(|e| ApiError::Internal(format!("cannot create a spool file: {}", error_chain(&e))))?
    .into_parts())
}

/// The lowercase hex SHA-256 and the size of the file at `path` (blocking).
pub(crate) fn digest_file(path: &std::path::Path) -> std::io::Result<(String, u64)> {
    let mut file = std::fs::File::open(path)?;
    let mut hasher = Sha256::new();
    let size = std::io::copy(&mut file, &mut hasher)?;
    Ok((hex::encode(hasher.finalize()), size))
}

/// Removes this service's spool files in `dir` (or the system temp dir) untouched for
/// `older_than`: uploads a crash cut off. Returns how many were removed.
pub(crate) fn sweep_stale_spool(
    dir: Option<&std::path::Path>,
    older_than: std::time::Duration,
) -> usize {
    let dir = dir.map_or_else(std::env::temp_dir, std::path::Path::to_path_buf);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return 0;
    };
    entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(SPOOL_PREFIX))
        .filter(|e| {
            e.metadata()
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age >= older_than)
        })
        .filter(|e| std::fs::remove_file(e.path()).is_ok())
        .count()
}

fn spool_error(e: std::io::Error) -> ApiError {
    ApiError::Internal(format!("writing the spool file failed: {e}"))
}

/// The 413 answer for uploads over `max_bytes`.
pub(crate) fn too_large(max_bytes: u64) -> ApiError {
    ApiError::PayloadTooLarge(format!(
        "upload exceeds the limit of {max_bytes} bytes; split the asset or submit it by object-store key"
    ))
}

/// A filename safe to use as the last component of an object key: the basename of `raw`, with
/// every character outside `[A-Za-z0-9._-]` replaced by `_`, no leading dots, and an extension
/// (required, since stages pick their reader by it).
pub(crate) fn sanitize_filename(raw: &str) -> ApiResult<String> {
    let base = raw.rsplit(['/', '\\']).next().unwrap_or_default();
    let cleaned: String = base
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let cleaned = cleaned.trim_start_matches('.');
    let Some((stem, ext)) = cleaned
        .rsplit_once('.')
        .filter(|(s, e)| !s.is_empty() && !e.is_empty())
    else {
        return Err(ApiError::Unprocessable(format!(
            "filename must be a name with an extension such as cabinet.glb, got {raw:?}"
        )));
    };
    let keep = MAX_FILENAME_BYTES.saturating_sub(ext.len() + 1).max(1);
    let stem = &stem[..stem.len().min(keep)];
    Ok(format!("{stem}.{ext}"))
}

/// The stored name of a source file (see [`sanitize_filename`]) whose extension names a format
/// the pipeline reads, or an archive holding one (`.zip`, `.tar`, `.tar.gz`, `.tgz`); 415
/// naming both otherwise.
pub(crate) fn source_filename(raw: &str) -> ApiResult<String> {
    let name = sanitize_filename(raw)?;
    let extension = name.rsplit_once('.').map(|(_, e)| e).unwrap_or_default();
    if SourceFormat::from_extension(extension).is_none() && ArchiveKind::from_name(&name).is_none()
    {
        return Err(ApiError::UnsupportedMediaType(format!(
            "{raw:?} is not a file the pipeline reads: the extension .{extension} names no supported format; send one of {}, or an archive ({}) holding one with the files it refers to",
            SourceFormat::listed_extensions(),
            ArchiveKind::ENDINGS.join(", ")
        )));
    }
    Ok(name)
}

/// Checks a spooled archive (every entry read, nothing written) when `filename` names one (a
/// single file passes as it is): 422 with the reason for one the limits or rules refuse (a path
/// out of its folder, a link, a bomb, no asset in it).
pub(crate) async fn check_archive(
    path: &std::path::Path,
    filename: &str,
    limits: ArchiveLimits,
) -> ApiResult<()> {
    let Some(kind) = ArchiveKind::from_name(filename) else {
        return Ok(());
    };
    let path = path.to_path_buf();
    let listed =
        tokio::task::spawn_blocking(move || uniphys_archive::inspect(&path, kind, &limits))
            .await
            .map_err(|e| ApiError::Internal(format!("archive check failed: {e}")))?;
    match listed {
        Ok(listing) => {
            tracing::debug!(filename, main_file = %listing.main_file, files = listing.files, "archive checked");
            Ok(())
        }
        Err(e @ ArchiveError::Io { .. }) => Err(ApiError::Internal(format!(
            "checking the archive {filename}: {e}"
        ))),
        Err(e) => Err(ApiError::Unprocessable(format!(
            "the archive {filename} is refused: {e}"
        ))),
    }
}

/// The 422 answer for a source without bytes.
pub(crate) fn empty_source(what: &str) -> ApiError {
    ApiError::Unprocessable(format!("{what} is empty: an asset needs the file's bytes"))
}

/// The content type served for a stored file, by its extension.
pub(crate) fn content_type_for(name: &str) -> &'static str {
    let ext = name
        .rsplit_once('.')
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "glb" => "model/gltf-binary",
        "gltf" => "model/gltf+json",
        "obj" => "model/obj",
        "stl" => "model/stl",
        "mtl" => "model/mtl",
        "urdf" | "xml" | "mjcf" | "sdf" => "application/xml",
        "json" => "application/json",
        "png" => "image/png",
        "jpg" | "jpeg" => "image/jpeg",
        "txt" | "log" => "text/plain; charset=utf-8",
        "zip" => "application/zip",
        "tar" => "application/x-tar",
        "gz" | "tgz" => "application/gzip",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_restart_sweeps_only_its_own_stale_spool_files() {
        let dir = tempfile::tempdir().expect("tempdir");
        let old = dir.path().join(format!("{SPOOL_PREFIX}old"));
        let fresh = dir.path().join(format!("{SPOOL_PREFIX}fresh"));
        let other = dir.path().join("upload-someone-else");
        for path in [&old, &fresh, &other] {
            std::fs::write(path, b"x").expect("write");
        }
        let two_hours_ago = std::time::SystemTime::now() - 2 * STALE_SPOOL;
        for path in [&old, &other] {
            std::fs::File::options()
                .write(true)
                .open(path)
                .and_then(|f| f.set_modified(two_hours_ago))
                .expect("age the file");
        }
        assert_eq!(sweep_stale_spool(Some(dir.path()), STALE_SPOOL), 1);
        assert!(!old.exists() && fresh.exists() && other.exists());
    }

    #[test]
    fn filenames_keep_their_basename_and_extension_only() {
        let ok = |raw: &str| sanitize_filename(raw).expect(raw);
        assert_eq!(ok("cabinet.glb"), "cabinet.glb");
        assert_eq!(ok("../../etc/passwd.txt"), "passwd.txt");
        assert_eq!(ok("C:\\models\\my chair (1).OBJ"), "my_chair__1_.OBJ");
        assert_eq!(ok("..hidden.glb"), "hidden.glb");
        let long = format!("{}.glb", "a".repeat(500));
        assert_eq!(ok(&long).len(), MAX_FILENAME_BYTES);
        assert!(ok(&long).ends_with(".glb"));
        for bad in ["", "noext", ".glb", "x.", "dir/", ".."] {
            assert!(sanitize_filename(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn content_types_follow_the_extension() {
        assert_eq!(content_type_for("export/model.urdf"), "application/xml");
        assert_eq!(content_type_for("a.GLB"), "model/gltf-binary");
        assert_eq!(content_type_for("blob"), "application/octet-stream");
    }

    #[tokio::test]
    async fn spooling_hashes_and_stops_at_the_cap() {
        let dir = tempfile::tempdir().expect("temp dir");
        let spooled = spool_body(
            Body::from("abc"),
            Some(dir.path().into()),
            3,
            Duration::from_secs(5),
        )
        .await
        .expect("within the cap");
        assert_eq!(spooled.size_bytes, 3);
        assert_eq!(
            spooled.sha256_hex,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        drop(spooled);
        let err = spool_body(
            Body::from("abcd"),
            Some(dir.path().into()),
            3,
            Duration::from_secs(5),
        )
        .await
        .expect_err("over the cap");
        assert!(matches!(err, ApiError::PayloadTooLarge(_)));
        let left = std::fs::read_dir(dir.path()).expect("read dir").count();
        assert_eq!(left, 0, "spool files are removed");
    }
}
