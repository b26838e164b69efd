//! The state shared by the handlers, and the owner of a request (its API
//! key).

use super::config::Config;
use super::error::{ApiResult, AppError};
use super::store::{self, Store};
use super::worker::Workers;
use axum::extract::FromRequestParts;
use axum::http::request::Parts;
use axum::http::{header, HeaderMap, StatusCode};
use std::sync::Arc;

/// Shared state of the handlers.
#[derive(Clone)]
pub struct AppState {
    /// Storage.
    pub store: Arc<dyn Store>,
    /// Configuration.
    pub config: Arc<Config>,
    /// Workers (wake-ups, event streams, metrics).
    pub workers: Arc<Workers>,
}

impl AppState {
    /// Runs a storage call on the blocking pool: database drivers block, and
    /// the async workers must keep serving.
    pub(super) async fn db<T: Send + 'static>(
        &self,
        f: impl FnOnce(&dyn Store) -> store::StoreResult<T> + Send + 'static,
    ) -> ApiResult<T> {
        let st = self.store.clone();
        tokio::task::spawn_blocking(move || f(&*st))
            .await
            .map_err(|_| {
                AppError::new(
                    StatusCode::INTERNAL_SERVER_ERROR,
                    "internal",
                    "storage task failed",
                )
            })?
            .map_err(AppError::from)
    }
}

/// The owner of a request: its API key, or "" when keys are off.
pub(super) fn owner(state: &AppState, headers: &HeaderMap) -> ApiResult<String> {
    if state.config.api_keys.is_empty() {
        return Ok(String::new());
    }
    // The scheme's name is case-insensitive (RFC 9110, 11.1): "bearer"
    // and "BEARER" name it too.
    let key = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.split_once(' '))
        .filter(|(scheme, _)| scheme.eq_ignore_ascii_case("bearer"))
        .map(|(_, k)| k.trim());
    match key {
        Some(k) if state.config.api_keys.contains(k) => Ok(k.to_string()),
        _ => Err(AppError::new(
            StatusCode::UNAUTHORIZED,
            "unauthorized",
            "missing or unknown API key (Authorization: Bearer KEY)",
        )),
    }
}

/// The owner of a request as an extractor (a handler argument): its API
/// key, or "" when keys are off; 401 otherwise.
pub(super) struct Owner(pub String);

impl FromRequestParts<AppState> for Owner {
    type Rejection = AppError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> ApiResult<Owner> {
        owner(state, &parts.headers).map(Owner)
    }
}
