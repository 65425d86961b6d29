//! The UniPhys web dashboard: static files built into the binary (see `build.rs`; the pages are
//! `web/static/`, three.js comes from the npm registry at build time) and [`router`], which
//! serves them under `/ui/`. The pages talk to the API's `/v1` routes with the user's API key;
//! this crate knows nothing of the API.
//!
//! | path | answer |
//! |---|---|
//! | `/` , `/ui` | 308 to `/ui/` |
//! | `/ui/` | `index.html` |
//! | `/ui/{path}` | the file, with its content type and an `ETag` (304 on `If-None-Match`) |

use std::sync::LazyLock;

use axum::Router;
use axum::body::Body;
use axum::extract::Path;
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Redirect, Response};
use axum::routing::get;

mod files {
    include!(concat!(env!("OUT_DIR"), "/files.rs"));
}

/// The Content-Security-Policy of every file: nothing is loaded from anywhere but this server,
/// and the only inline script allowed is index.html's import map (by its hash).
static CSP: LazyLock<HeaderValue> = LazyLock::new(|| {
    let policy = format!(
        "default-src 'self'; script-src 'self' {}; style-src 'self' 'unsafe-inline'; \
         img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; base-uri 'none'; \
         frame-ancestors 'none'",
        files::INLINE_SCRIPT_HASHES
    );
    HeaderValue::from_str(&policy)
        .unwrap_or_else(|_| HeaderValue::from_static("default-src 'self'"))
});

/// Whether three.js was bundled from npm; `false` when the build had no npm (the 3D viewer then
/// says so, and everything else works).
#[must_use]
pub fn three_bundled() -> bool {
    files::THREE_BUNDLED
}

/// The paths of every embedded file, relative to `/ui/`.
pub fn file_paths() -> impl Iterator<Item = &'static str> {
    files::FILES.iter().map(|(path, _)| *path)
}

/// Routes serving the dashboard; merge them into the API's router.
pub fn router<S: Clone + Send + Sync + 'static>() -> Router<S> {
    Router::new()
        .route("/", get(|| async { Redirect::permanent("/ui/") }))
        .route("/ui", get(|| async { Redirect::permanent("/ui/") }))
        .route("/ui/", get(|headers: HeaderMap| async move { serve("index.html", &headers) }))
        .route(
            "/ui/{*path}",
            get(|Path(path): Path<String>, headers: HeaderMap| async move {
                serve(&path, &headers)
            }),
        )
}

fn serve(path: &str, headers: &HeaderMap) -> Response {
    let Some((_, bytes)) = files::FILES.iter().find(|(name, _)| *name == path) else {
        return (
            StatusCode::NOT_FOUND,
            [(header::CONTENT_TYPE, "text/plain; charset=utf-8")],
            format!("no dashboard file {path:?}; the dashboard starts at /ui/"),
        )
            .into_response();
    };
    let etag = format!("\"{:016x}\"", fnv1a(bytes));
    let not_modified = headers
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.split(',').any(|tag| tag.trim() == etag));
    let mut response = if not_modified {
        StatusCode::NOT_MODIFIED.into_response()
    } else {
        Response::new(Body::from(*bytes))
    };
    let h = response.headers_mut();
    h.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(content_type(path)),
    );
    // Revalidate every time: a new build serves new files under the same names.
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    h.insert(header::CONTENT_SECURITY_POLICY, CSP.clone());
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    if let Ok(value) = HeaderValue::from_str(&etag) {
        h.insert(header::ETAG, value);
    }
    response
}

fn content_type(path: &str) -> &'static str {
    match path.rsplit_once('.').map(|(_, ext)| ext) {
        Some("html") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("svg") => "image/svg+xml",
        Some("png") => "image/png",
        Some("json") => "application/json",
        Some("ico") => "image/x-icon",
        _ => "application/octet-stream",
    }
}

/// 64-bit FNV-1a: a content tag for `ETag`, not a security digest.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use axum::http::Request;
    use tower::ServiceExt;

    use super::*;

    async fn get_path(path: &str, if_none_match: Option<&str>) -> Response {
        let mut request = Request::get(path);
        if let Some(tag) = if_none_match {
            request = request.header(header::IF_NONE_MATCH, tag);
        }
        router::<()>()
            .oneshot(request.body(Body::empty()).expect("request"))
            .await
            .expect("infallible")
    }

    #[tokio::test]
    async fn the_root_redirects_and_the_index_is_html() {
        let root = get_path("/", None).await;
        assert_eq!(root.status(), StatusCode::PERMANENT_REDIRECT);
        assert_eq!(root.headers()[header::LOCATION], "/ui/");
        let index = get_path("/ui/", None).await;
        assert_eq!(index.status(), StatusCode::OK);
        assert_eq!(
            index.headers()[header::CONTENT_TYPE],
            "text/html; charset=utf-8"
        );
        let csp = index.headers()[header::CONTENT_SECURITY_POLICY]
            .to_str()
            .expect("ascii");
        assert!(
            csp.contains("script-src 'self' 'sha256-"),
            "the import map by hash: {csp}"
        );
        assert!(!csp.contains("script-src 'self' 'unsafe-inline'"), "{csp}");
    }

    #[tokio::test]
    async fn every_file_is_served_with_its_type_and_revalidates_by_etag() {
        for path in file_paths() {
            let first = get_path(&format!("/ui/{path}"), None).await;
            assert_eq!(first.status(), StatusCode::OK, "{path}");
            assert_eq!(first.headers()[header::CONTENT_TYPE], content_type(path));
            let tag = first.headers()[header::ETAG]
                .to_str()
                .expect("ascii")
                .to_owned();
            let again = get_path(&format!("/ui/{path}"), Some(&tag)).await;
            assert_eq!(again.status(), StatusCode::NOT_MODIFIED, "{path}");
        }
    }

    #[test]
    fn the_pages_and_the_viewer_modules_are_embedded() {
        let paths: Vec<&str> = file_paths().collect();
        for needed in ["index.html", "vendor/three/three.module.js"] {
            assert!(paths.contains(&needed), "{needed} missing from {paths:?}");
        }
        if three_bundled() {
            for addon in ["loaders/OBJLoader.js", "controls/OrbitControls.js"] {
                let path = format!("vendor/three/addons/{addon}");
                assert!(paths.contains(&path.as_str()), "{path} missing");
            }
        }
    }

    #[test]
    fn every_module_import_of_the_pages_resolves_to_an_embedded_file() {
        let paths: Vec<&str> = file_paths().collect();
        for (name, bytes) in files::FILES
            .iter()
            .filter(|(n, _)| !n.starts_with("vendor/"))
        {
            let Ok(text) = std::str::from_utf8(bytes) else {
                continue;
            };
            for spec in relative_imports(text) {
                let base = name.rsplit_once('/').map_or("", |(dir, _)| dir);
                let resolved = normalise(base, spec);
                assert!(
                    paths.contains(&resolved.as_str()),
                    "{name} imports {spec} ({resolved}), which is not embedded"
                );
            }
        }
    }

    #[tokio::test]
    async fn an_unknown_file_is_a_404_that_names_it() {
        let response = get_path("/ui/nope.js", None).await;
        assert_eq!(response.status(), StatusCode::NOT_FOUND);
    }

    /// The `./x.js` specifiers of `import ... from './x.js'` and `import('./x.js')`.
    fn relative_imports(text: &str) -> Vec<&str> {
        let mut found = Vec::new();
        for quote in ['\'', '"'] {
            for prefix in ["from ", "import("] {
                let needle = format!("{prefix}{quote}./");
                let mut rest = text;
                while let Some(at) = rest.find(&needle) {
                    let start = at + prefix.len() + 1;
                    let tail = &rest[start..];
                    if let Some(end) = tail.find(quote) {
                        found.push(&tail[..end]);
                    }
                    rest = &rest[start..];
                }
            }
        }
        found
    }

    fn normalise(base: &str, spec: &str) -> String {
        let mut parts: Vec<&str> = base.split('/').filter(|p| !p.is_empty()).collect();
        for part in spec.split('/') {
            match part {
                "." | "" => {}
                ".." => {
                    parts.pop();
                }
                other => parts.push(other),
            }
        }
        parts.join("/")
    }
}
