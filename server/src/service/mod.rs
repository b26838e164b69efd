//! The HTTP service of spec/api.md: missions, jobs, contraction and
//! simulation over REST, progress as Server-Sent Events, the page served at
//! `/`. `app(state)` builds the router; `serve(config)` runs it.
//!
//! One file per resource: `missions`, `jobs` (HTTP side; the workers are in
//! `worker`), `contract`, `simulate`; `error` (the one `AppError`),
//! `config` (`Config`), `state` (`AppState`, API keys), `metrics` (health,
//! readiness, Prometheus text), `openapi` (the document), `store`
//! (storage).

mod config;
mod contract;
mod error;
mod jobs;
mod metrics;
mod missions;
pub mod openapi;
mod simulate;
mod state;
pub mod store;
pub mod worker;

pub use config::Config;
pub use error::AppError;
pub use state::AppState;

use axum::extract::DefaultBodyLimit;
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware;
use axum::routing::{get, post};
use axum::{Json, Router};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use store::Store;
use worker::Workers;

const BUILTIN_PAGE: &str = "<!doctype html><meta charset=utf-8><title>nvector</title><h1>nvector</h1><p>The web UI is not built: run <code>make run</code> (it builds web/www). The API is at <code>/api/v1</code>.</p>";

async fn api_not_found() -> AppError {
    AppError::new(StatusCode::NOT_FOUND, "not_found", "no such endpoint")
}

/// The router of the whole service.
pub fn app(state: AppState) -> Router {
    let api = Router::new()
        .route(
            "/missions",
            post(missions::post_mission).get(missions::list_missions),
        )
        .route(
            "/missions/{id}",
            get(missions::get_mission).delete(missions::delete_mission),
        )
        .route("/jobs", post(jobs::post_job))
        .route("/jobs/{id}", get(jobs::get_job).delete(jobs::delete_job))
        .route("/jobs/{id}/events", get(jobs::job_events))
        .route("/jobs/{id}/result", get(jobs::job_result))
        .route("/contract", post(contract::post_contract))
        .route("/simulate", post(simulate::post_simulate))
        .route("/openapi.json", get(|| async { Json(openapi::document()) }))
        .fallback(api_not_found);
    let mut router = Router::new()
        .nest("/api/v1", api)
        .route("/healthz", get(metrics::healthz))
        .route("/readyz", get(metrics::readyz))
        .route("/metrics", get(metrics::metrics))
        .layer(DefaultBodyLimit::max(state.config.max_body));
    let dir = state.config.static_dir.clone();
    if dir.join("index.html").exists() {
        router = router.fallback_service(tower_http::services::ServeDir::new(dir));
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
/// accepting requests, running jobs are stopped at their next progress
/// point and put back in the queue (another process, or the next start,
/// finishes them). Jobs left running by a process that died are re-queued
/// once their lease expires.
pub async fn serve(
    addr: std::net::SocketAddr,
    store: Arc<dyn Store>,
    config: Config,
    workers_n: usize,
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
    let mut handles = worker::start(workers_n, store.clone(), workers.clone());
    handles.push(worker::start_lease_keeper(
        store.clone(),
        workers.clone(),
        config.job_lease,
    ));
    let state = AppState {
        store,
        config: Arc::new(config),
        workers: workers.clone(),
        requests: Arc::new(Mutex::new(BTreeMap::new())),
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
