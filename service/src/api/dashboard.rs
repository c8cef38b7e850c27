//! The web dashboard's files, embedded in the binary (no CDN, works
//! offline): the page at `/` and its scripts, styles and vendored
//! libraries under `/ui/`. The page only uses the public API. Sources in
//! `service/dashboard/` (libraries refreshed by its `vendor.sh`).

use axum::extract::Path;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};

use crate::error::{BridgeError, ErrorCode};

/// One embedded file: its path under `/ui/`, media type and bytes.
struct Asset {
    path: &'static str,
    media_type: &'static str,
    bytes: &'static [u8],
}

macro_rules! asset {
    ($path:literal, $media_type:expr) => {
        Asset {
            path: $path,
            media_type: $media_type,
            bytes: include_bytes!(concat!("../../dashboard/", $path)),
        }
    };
}

/// Browsers run module scripts only with a JavaScript media type.
const JS: &str = "text/javascript; charset=utf-8";

const ASSETS: &[Asset] = &[
    asset!("index.html", "text/html; charset=utf-8"),
    asset!("app.js", JS),
    asset!("arm.js", JS),
    asset!("projections.js", JS),
    asset!("kinematics.js", JS),
    asset!("plugins.js", JS),
    asset!("jog.js", JS),
    asset!("travel.js", JS),
    asset!("dom.js", JS),
    asset!("style.css", "text/css; charset=utf-8"),
    asset!("vendor/three.module.js", JS),
    asset!("vendor/three.core.js", JS),
    asset!("vendor/OrbitControls.js", JS),
    asset!("vendor/LICENSES.md", "text/markdown; charset=utf-8"),
];

fn serve(path: &str) -> Response {
    let Some(a) = ASSETS.iter().find(|a| a.path == path) else {
        return super::problem::Problem::from(BridgeError::new(
            ErrorCode::NotFound,
            format!("no dashboard file {path}"),
        ))
        .into_response();
    };
    let mut r = (StatusCode::OK, a.bytes).into_response();
    let h = r.headers_mut();
    h.insert(header::CONTENT_TYPE, HeaderValue::from_static(a.media_type));
    // Vendored libraries change only with a new binary; the page and its
    // own script are checked on every load.
    let cache = if a.path.starts_with("vendor/") {
        "public, max-age=86400"
    } else {
        "no-cache"
    };
    h.insert(header::CACHE_CONTROL, HeaderValue::from_static(cache));
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(CSP),
    );
    r
}

/// The page runs only its own files and talks only to this service: no
/// inline script or style attribute runs even if text from a plugin or a
/// controller ever reached the page as markup, and no other site may
/// frame it.
const CSP: &str = "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; \
    connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// `GET /`: the dashboard page.
pub(super) async fn page() -> Response {
    serve("index.html")
}

/// `GET /ui/{*path}`: its files.
pub(super) async fn file(Path(path): Path<String>) -> Response {
    serve(&path)
}

#[cfg(test)]
mod tests {
    /// The embedded scripts are served as JavaScript, and the page's own
    /// files load nothing from the internet (the SVG namespace is a name,
    /// not a download).
    #[test]
    fn scripts_are_javascript_and_the_page_is_offline() {
        for a in super::ASSETS {
            if a.path.ends_with(".js") {
                assert_eq!(a.media_type, super::JS, "{}", a.path);
            }
            if !a.path.starts_with("vendor/") {
                let text =
                    String::from_utf8_lossy(a.bytes).replace("http://www.w3.org/2000/svg", "");
                assert!(
                    !text.contains("http://") && !text.contains("https://"),
                    "{} refers to the network",
                    a.path
                );
            }
        }
    }
}
