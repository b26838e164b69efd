//! The HTTP service of docs/api.md: missions, jobs, contraction and
//! simulation over REST, progress as Server-Sent Events, the page served at
//! `/`. `app(state)` builds the router; `serve(config)` runs it.
//!
//! One file per resource: `missions`, `jobs` (HTTP side; the workers are in
//! `worker`, each running its jobs in a worker process: `worker_process`
//! is the service's side of one, `job_runner` what runs inside it),
//! `contract`, `simulate`, `tdoa` (TDOA jobs); `error` (the one `AppError`), `config`
//! (`Config`, sizes), `state` (`AppState`, API keys), `metrics` (health,
//! readiness, the `/metrics` endpoint) and `meters` (the metric families),
//! `openapi` (the document, from the handlers and from core's format types), `store` (storage).

mod body_limit;
pub mod config;
mod contract;
mod docs_page;
mod error;
pub mod formats;
pub mod job_runner;
mod jobs;
mod meters;
mod metrics;
mod missions;
pub mod openapi;
mod result_files;
mod simulate;
mod state;
pub mod store;
mod tdoa;
pub mod worker;
mod worker_process;

pub use config::{default_job_memory, format_size, parse_size, Config, MIN_JOB_MEMORY};
pub use error::AppError;
pub use state::AppState;
pub use worker::PoolConfig;

use axum::extract::DefaultBodyLimit;
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware;
use axum::routing::get;
use axum::{Extension, Router};
use std::sync::Arc;
use store::Store;
use tower_http::services::ServeDir;
use tower_http::set_header::SetResponseHeader;
use utoipa::OpenApi;
use utoipa_axum::router::OpenApiRouter;
use utoipa_axum::routes;
use worker::Workers;

const BUILTIN_PAGE: &str = "<!doctype html><meta charset=utf-8><title>nvector</title><h1>nvector</h1><p>The web UI is not built: run <code>make run</code> (it builds web/www). The API is at <code>/api/v1</code>.</p>";

async fn api_not_found() -> AppError {
    AppError::new(StatusCode::NOT_FOUND, "not_found", "no such endpoint")
}

/// The routes of the API and of the operations endpoints, each with its
/// OpenAPI path (the document is built from the same registrations).
fn routes() -> OpenApiRouter<AppState> {
    let api = OpenApiRouter::new()
        .routes(routes!(missions::post_mission, missions::list_missions))
        .routes(routes!(missions::get_mission, missions::delete_mission))
        .routes(routes!(jobs::post_job))
        .routes(routes!(jobs::get_job, jobs::delete_job))
        .routes(routes!(jobs::job_events))
        .routes(routes!(jobs::job_result))
        .routes(routes!(contract::post_contract))
        .routes(routes!(simulate::post_simulate))
        .routes(routes!(tdoa::post_tdoa))
        .routes(routes!(openapi::openapi_json))
        .fallback(api_not_found);
    OpenApiRouter::with_openapi(openapi::ApiDoc::openapi())
        .nest("/api/v1", api)
        .routes(routes!(metrics::healthz))
        .routes(routes!(metrics::readyz))
        .routes(routes!(metrics::metrics))
}

/// The OpenAPI document of a service with this configuration.
#[cfg(test)]
pub fn document(config: &Config) -> serde_json::Value {
    openapi::finish(routes().into_openapi(), config)
}

/// The page's static files: the brotli or gzip copy that `scripts/web.sh
/// build` wrote beside each file (`x.wasm.br`, `x.wasm.gz`) when the client
/// accepts it, else the file itself. No file name carries a content hash,
/// so every answer is revalidated (`Cache-Control: no-cache`: a cache keeps
/// it and asks with `If-Modified-Since`, answered 304 while unchanged), and
/// `Vary: Accept-Encoding` keeps caches from mixing the encodings.
fn static_files(
    dir: std::path::PathBuf,
) -> SetResponseHeader<SetResponseHeader<ServeDir, HeaderValue>, HeaderValue> {
    let files = ServeDir::new(dir).precompressed_br().precompressed_gzip();
    let files = SetResponseHeader::overriding(
        files,
        header::CACHE_CONTROL,
        HeaderValue::from_static("no-cache"),
    );
    SetResponseHeader::overriding(
        files,
        header::VARY,
        HeaderValue::from_static("accept-encoding"),
    )
}

/// The router of the whole service.
pub fn app(state: AppState) -> Router {
    let (router, api) = routes().split_for_parts();
    let doc = Arc::new(openapi::finish(api, &state.config));
    let mut router = router
        .merge(docs_page::router())
        .layer(Extension(doc))
        .layer(DefaultBodyLimit::max(state.config.max_body))
        .layer(middleware::from_fn_with_state(
            state.clone(),
            body_limit::limit_body,
        ));
    let dir = state.config.static_dir.clone();
    if dir.join("index.html").exists() {
        router = router.fallback_service(static_files(dir));
    } else {
        router = router.route(
            "/",
            get(|| async {
                (
                    [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
                    BUILTIN_PAGE,
                )
            }),
        );
    }
    if !state.config.cors_origins.is_empty() {
        let origins: Vec<HeaderValue> = state
            .config
            .cors_origins
            .iter()
            .filter_map(|o| o.parse().ok())
            .collect();
        router = router.layer(
            tower_http::cors::CorsLayer::new()
                .allow_origin(origins)
                .allow_methods(tower_http::cors::Any)
                .allow_headers(tower_http::cors::Any),
        );
    }
    router
        .route_layer(middleware::from_fn_with_state(
            state.clone(),
            metrics::count_requests,
        ))
        .layer(middleware::from_fn(error::json_errors))
        .with_state(state)
}

/// Opens the storage named by a `--database` URL: `sqlite://PATH` or
/// `postgres://...` (with `pool_size` connections).
pub fn open_store(url: &str, pool_size: usize) -> Result<Arc<dyn Store>, String> {
    if let Some(path) = url.strip_prefix("sqlite://") {
        return store::SqliteStore::open(path)
            .map(|s| Arc::new(s) as Arc<dyn Store>)
            .map_err(|e| e.to_string());
    }
    if url.starts_with("postgres://") || url.starts_with("postgresql://") {
        return store::PostgresStore::open(url, pool_size)
            .map(|s| Arc::new(s) as Arc<dyn Store>)
            .map_err(|e| e.to_string());
    }
    Err(format!(
        "unsupported database URL '{url}' (expected sqlite://PATH or postgres://USER@HOST:PORT/DB)"
    ))
}

/// Runs the service until SIGTERM or Ctrl-C. On shutdown the server stops
/// accepting requests, running jobs are stopped (their worker processes
/// killed) and put back in the queue (another process, or the next start,
/// finishes them). Jobs left running by a process that died are re-queued
/// once their lease expires.
pub async fn serve(
    addr: std::net::SocketAddr,
    store: Arc<dyn Store>,
    config: Config,
    pool: PoolConfig,
) -> Result<(), String> {
    let lease_ms = config.job_lease.as_millis() as i64;
    let st = store.clone();
    let requeued =
        tokio::task::spawn_blocking(move || st.requeue_stale(worker::now_ms(), lease_ms))
            .await
            .map_err(|e| e.to_string())?
            .map_err(|e| e.to_string())?;
    if requeued > 0 {
        tracing::info!("re-queued {requeued} job(s) left running by a stopped process");
    }
    let workers = Workers::new();
    let mut handles = worker::start(&pool, store.clone(), workers.clone());
    handles.push(worker::start_lease_keeper(
        store.clone(),
        workers.clone(),
        config.job_lease,
    ));
    let state = AppState {
        store,
        config: Arc::new(config),
        workers: workers.clone(),
    };
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|e| format!("binding {addr}: {e}"))?;
    let local = listener.local_addr().map_err(|e| e.to_string())?;
    tracing::info!(
        "nvector serving on http://{local} (process {})",
        state.store.instance()
    );
    println!("nvector serving on http://{local}");
    axum::serve(listener, app(state))
        .with_graceful_shutdown(shutdown_signal())
        .await
        .map_err(|e| e.to_string())?;
    workers
        .stopping
        .store(true, std::sync::atomic::Ordering::SeqCst);
    workers.notify();
    for h in handles {
        let _ = h.join();
    }
    Ok(())
}

async fn shutdown_signal() {
    let ctrl_c = async {
        let _ = tokio::signal::ctrl_c().await;
    };
    #[cfg(unix)]
    let term = async {
        if let Ok(mut s) = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())
        {
            s.recv().await;
        }
    };
    #[cfg(not(unix))]
    let term = std::future::pending::<()>();
    tokio::select! {
        _ = ctrl_c => {},
        _ = term => {},
    }
}

/// A small configuration for the unit tests.
#[cfg(test)]
pub(crate) fn test_state() -> Config {
    Config {
        max_steps: 1000,
        max_detections: 50,
        job_time_limit_s: 7.5,
        ..Config::default()
    }
}
