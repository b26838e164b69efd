//! The API reference page: `GET /api/docs` is Redoc rendering the
//! service's own OpenAPI document (`/api/v1/openapi.json`), with Redoc's
//! script served by the service itself at `/api/docs/redoc.standalone.js`
//! (vendored from npm in server/assets/redoc and compiled into the binary),
//! so that the page fetches nothing from outside. Redoc's bundle asks for
//! its maker's logo on a CDN: the script is served with that address
//! replaced by an empty image of its own (`data:`), so that the browser
//! asks nothing of another origin (a refused request was a console error).
//! A Content-Security-Policy holds the page to its origin all the same.

use axum::http::header;
use axum::response::IntoResponse;
use axum::routing::get;
use axum::Router;
use std::sync::OnceLock;

/// Redoc 2.5.2's standalone bundle (MIT; server/assets/redoc/LICENSE).
static REDOC_JS: &[u8] = include_bytes!("../../assets/redoc/redoc.standalone.js");

/// The address of the logo Redoc's bundle draws in its menu, on another
/// origin.
const LOGO: &str = "\"https://cdn.redoc.ly/redoc/logo-mini.svg\"";
/// What the served script asks for instead: an empty 1 px image, no request.
const NO_LOGO: &str =
    "\"data:image/svg+xml,%3Csvg xmlns='http://www.w3.org/2000/svg' width='1' height='1'/%3E\"";

/// Redoc's script as served: the logo's address replaced (the test
/// `the_script_asks_no_other_origin` fails if a new bundle moves it).
fn redoc_js() -> &'static [u8] {
    static JS: OnceLock<Vec<u8>> = OnceLock::new();
    JS.get_or_init(|| {
        String::from_utf8_lossy(REDOC_JS)
            .replace(LOGO, NO_LOGO)
            .into_bytes()
    })
}

/// The page: Redoc on the service's document, no external font or script.
const PAGE: &str = r#"<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>nvector API reference</title>
<style>body { margin: 0; font-family: sans-serif; } .back { padding: 6px 12px; font-size: 14px; background: #f4f4f4; border-bottom: 1px solid #ddd; }</style>
</head>
<body>
<div class="back"><a href="/">nvector</a> · API reference, from <a href="/api/v1/openapi.json">/api/v1/openapi.json</a></div>
<div id="redoc-container"><noscript>This page needs JavaScript; the document itself is <a href="/api/v1/openapi.json">/api/v1/openapi.json</a>.</noscript></div>
<script src="/api/docs/redoc.standalone.js"></script>
<script>
Redoc.init("/api/v1/openapi.json", {
  hideDownloadButton: false,
  disableSearch: false,
  expandResponses: "200,201,202",
  theme: { typography: { fontFamily: "sans-serif", headings: { fontFamily: "sans-serif" } } }
}, document.getElementById("redoc-container"));
</script>
</body>
</html>
"#;

/// Everything from the service itself; inline script and styles (the
/// `Redoc.init` call, Redoc's generated styles), workers from blobs
/// (Redoc's search index), images and fonts also from `data:` URLs.
const POLICY: &str = "default-src 'self'; script-src 'self' 'unsafe-inline'; \
    style-src 'self' 'unsafe-inline'; img-src 'self' data:; font-src 'self' data:; \
    worker-src 'self' blob:; connect-src 'self'; base-uri 'none'; form-action 'none'";

async fn page() -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8"),
            (header::CACHE_CONTROL, "no-cache"),
            (header::CONTENT_SECURITY_POLICY, POLICY),
        ],
        PAGE,
    )
}

async fn script() -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "text/javascript; charset=utf-8"),
            (header::CACHE_CONTROL, "public, max-age=86400"),
        ],
        redoc_js(),
    )
}

/// The routes of the page and its script (no state).
pub fn router<S: Clone + Send + Sync + 'static>() -> Router<S> {
    Router::new()
        .route("/api/docs", get(page))
        .route("/api/docs/", get(page))
        .route("/api/docs/redoc.standalone.js", get(script))
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_script_asks_no_other_origin() {
        let js = String::from_utf8_lossy(super::REDOC_JS);
        assert!(
            js.contains(super::LOGO),
            "the bundle no longer names its logo so: look again for https:// images"
        );
        let served = String::from_utf8_lossy(super::redoc_js());
        assert!(!served.contains("cdn.redoc.ly"));
        assert!(served.contains(super::NO_LOGO));
    }
}
