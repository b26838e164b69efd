//! The API reference page: `GET /api/docs` is Redoc rendering the
//! service's own OpenAPI document (`/api/v1/openapi.json`), with Redoc's
//! script served by the service itself at `/api/docs/redoc.standalone.js`
//! (vendored from npm in server/assets/redoc and compiled into the binary),
//! so that the page fetches nothing from outside. A Content-Security-Policy
//! holds it to that: Redoc's bundle asks for its maker's logo on a CDN,
//! which the browser refuses (Redoc then drops the image).

use axum::http::header;
use axum::response::IntoResponse;
use axum::routing::get;
use axum::Router;

/// Redoc 2.5.2's standalone bundle (MIT; server/assets/redoc/LICENSE).
static REDOC_JS: &[u8] = include_bytes!("../../assets/redoc/redoc.standalone.js");

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
        REDOC_JS,
    )
}

/// The routes of the page and its script (no state).
pub fn router<S: Clone + Send + Sync + 'static>() -> Router<S> {
    Router::new()
        .route("/api/docs", get(page))
        .route("/api/docs/", get(page))
        .route("/api/docs/redoc.standalone.js", get(script))
}
