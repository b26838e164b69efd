//! Operations: `/healthz` (liveness), `/readyz` (storage reachable),
//! `/metrics` (OpenMetrics text of the families in `meters`) and the
//! middleware that counts and times requests.

use super::error::ApiResult;
use super::error::StorageUnavailable;
use super::meters::{RequestLabels, StateLabel};
use super::state::AppState;
use super::store::JobState;
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
        StorageUnavailable,
    ))]
pub(super) async fn readyz(State(state): State<AppState>) -> ApiResult<&'static str> {
    state.db(|st| st.ping()).await?;
    Ok("ready\n")
}

/// Metrics, OpenMetrics text (prometheus-client): jobs by state (from
/// storage: all processes), histograms of job durations and queue waits by
/// lane and of request latencies, counters of requests and worker deaths
/// (this process).
#[utoipa::path(get, path = "/metrics", operation_id = "metrics", tag = "operations",
    responses(
        (status = 200, description = "OpenMetrics text 1.0.0 (Prometheus reads it)",
            content_type = "application/openmetrics-text", body = String),
        StorageUnavailable,
    ))]
pub(super) async fn metrics(State(state): State<AppState>) -> ApiResult<Response> {
    let counts = state.db(|st| st.counts()).await?;
    let meters = &state.workers.meters;
    for s in JobState::ALL {
        let n = counts.iter().find(|(k, _)| *k == s).map_or(0, |(_, n)| *n);
        meters
            .jobs
            .get_or_create(&StateLabel {
                state: s.as_str().into(),
            })
            .set(n);
    }
    Ok((
        [(
            header::CONTENT_TYPE,
            "application/openmetrics-text; version=1.0.0; charset=utf-8",
        )],
        meters.encode(),
    )
        .into_response())
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
    let start = std::time::Instant::now();
    let resp = next.run(req).await;
    let labels = RequestLabels {
        route,
        status: resp.status().as_u16(),
    };
    let meters = &state.workers.meters;
    meters.http_requests.get_or_create(&labels).inc();
    meters
        .http_request_duration_ms
        .get_or_create(&labels)
        .observe(start.elapsed().as_secs_f64() * 1e3);
    resp
}
