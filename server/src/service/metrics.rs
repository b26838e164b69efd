//! Operations: `/healthz` (liveness), `/readyz` (storage reachable),
//! `/metrics` (Prometheus text: jobs by state, job durations, requests by
//! route and status) and the middleware that counts requests.

use super::error::ApiResult;
use super::formats::ErrorBody;
use super::state::AppState;
use axum::extract::{MatchedPath, Request, State};
use axum::http::header;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

/// Liveness.
#[utoipa::path(get, path = "/healthz", operation_id = "healthz", tag = "operations",
    responses((status = 200, description = "`ok`", content_type = "text/plain", body = String)))]
pub(super) async fn healthz() -> &'static str {
    "ok\n"
}

/// Readiness: the storage is reachable.
#[utoipa::path(get, path = "/readyz", operation_id = "readyz", tag = "operations",
    responses(
        (status = 200, description = "`ready`", content_type = "text/plain", body = String),
        (status = 503, description = "Storage unavailable", body = ErrorBody),
    ))]
pub(super) async fn readyz(State(state): State<AppState>) -> ApiResult<&'static str> {
    state.db(|st| st.ping()).await?;
    Ok("ready\n")
}

/// Prometheus text: jobs by state, job durations, requests by route and
/// status.
#[utoipa::path(get, path = "/metrics", operation_id = "metrics", tag = "operations",
    responses(
        (status = 200, description = "Prometheus text format 0.0.4", content_type = "text/plain", body = String),
        (status = 503, description = "Storage unavailable", body = ErrorBody),
    ))]
pub(super) async fn metrics(State(state): State<AppState>) -> ApiResult<Response> {
    let mut out = String::new();
    out.push_str("# HELP nvector_jobs Jobs by state.\n# TYPE nvector_jobs gauge\n");
    let counts = state.db(|st| st.counts()).await?;
    for s in ["queued", "running", "done", "failed", "cancelled"] {
        let n = counts.iter().find(|(k, _)| k == s).map_or(0, |(_, n)| *n);
        out.push_str(&format!("nvector_jobs{{state=\"{s}\"}} {n}\n"));
    }
    out.push_str("# HELP nvector_job_duration_ms Duration of finished jobs in this process.\n# TYPE nvector_job_duration_ms histogram\n");
    let durations = state
        .workers
        .durations
        .lock()
        .map(|d| d.clone())
        .unwrap_or_default();
    let mut cumulative = 0;
    for le in [10.0, 50.0, 100.0, 500.0, 1000.0, 5000.0, 30000.0, 300000.0] {
        cumulative = durations.iter().filter(|&&d| d <= le).count();
        out.push_str(&format!(
            "nvector_job_duration_ms_bucket{{le=\"{le}\"}} {cumulative}\n"
        ));
    }
    let _ = cumulative;
    out.push_str(&format!(
        "nvector_job_duration_ms_bucket{{le=\"+Inf\"}} {}\n",
        durations.len()
    ));
    out.push_str(&format!(
        "nvector_job_duration_ms_sum {}\n",
        durations.iter().sum::<f64>()
    ));
    out.push_str(&format!(
        "nvector_job_duration_ms_count {}\n",
        durations.len()
    ));
    out.push_str("# HELP nvector_http_requests Requests by route and status.\n# TYPE nvector_http_requests counter\n");
    if let Ok(r) = state.requests.lock() {
        for ((route, status), n) in r.iter() {
            out.push_str(&format!(
                "nvector_http_requests{{route=\"{route}\",status=\"{status}\"}} {n}\n"
            ));
        }
    }
    Ok(([(header::CONTENT_TYPE, "text/plain; version=0.0.4")], out).into_response())
}

pub(super) async fn count_requests(
    State(state): State<AppState>,
    req: Request,
    next: Next,
) -> Response {
    let route = req
        .extensions()
        .get::<MatchedPath>()
        .map_or_else(|| "unmatched".to_string(), |p| p.as_str().to_string());
    let resp = next.run(req).await;
    if let Ok(mut r) = state.requests.lock() {
        *r.entry((route, resp.status().as_u16())).or_insert(0) += 1;
    }
    resp
}
