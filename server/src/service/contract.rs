//! `POST /api/v1/contract`: one atmost_nvector contraction, synchronous,
//! on the blocking pool, with bounded work: core's node budget for the
//! exact contractor, and this service's time limit per request
//! (`--contract-time-limit`, default 10 s) through core's cancellation
//! flag, which is also set when the client goes away. Either limit answers
//! 422 with code `work_limit`.

use super::error::ErrorBody;
use super::error::{parse_json, ApiResult, AppError};
use super::error::{MalformedJson, Unauthorized};
use super::state::{AppState, Owner};
use axum::body::Bytes;
use axum::extract::State;
use axum::http::StatusCode;
use axum::Json;
use nvector_core::format::contract::ContractDoc as ContractRequest;
use nvector_core::nvector::contract::ContractResponse;
use nvector_core::nvector::contract::{contract_json_with, ContractError};
use nvector_core::nvector::hitting_set::{Limits, WorkLimit};
use serde_json::{json, Value};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// One atmost_nvector contraction (docs/formats.md), synchronous.
#[utoipa::path(
    post,
    path = "/contract",
    operation_id = "contract",
    tag = "contraction",
    request_body = ContractRequest,
    responses(
        (status = 200, description = "The contraction", body = ContractResponse),
        MalformedJson,
        Unauthorized,
        (status = 413, description = "More than 100000 boxes, or body too large", body = ErrorBody),
        (status = 422, description = "Invalid request, with the JSON path; or code `work_limit`: \
            the exact contractor ran out of its work budget or of this service's time limit \
            per contraction (the message names the limit)", body = ErrorBody),
    )
)]
pub(super) async fn post_contract(
    State(state): State<AppState>,
    _owner: Owner,
    body: Bytes,
) -> ApiResult<Json<Value>> {
    let v = parse_json(&body)?;
    if v.get("boxes")
        .and_then(Value::as_array)
        .is_some_and(|b| b.len() > 100_000)
    {
        return Err(AppError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "too_large",
            "at most 100000 boxes per contraction",
        )
        .at("boxes"));
    }
    let start = std::time::Instant::now();
    let mut out = contract_within(v, state.config.contract_time_limit).await?;
    out["stats"]["elapsed_us"] = json!(start.elapsed().as_micros() as u64);
    Ok(Json(out))
}

/// Sets its flag when dropped: the contraction of a request whose client
/// went away (its handler future dropped) stops too.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Runs one contraction on the blocking pool with core's work limits (the
/// exact contractor's node budget) and a cancellation flag set at
/// `time_limit`; a limit reached is a 422 `work_limit` naming it.
async fn contract_within(request: Value, time_limit: Duration) -> ApiResult<Value> {
    let cancel = Arc::new(AtomicBool::new(false));
    let _guard = CancelOnDrop(cancel.clone());
    let flag = cancel.clone();
    let task = tokio::task::spawn_blocking(move || {
        let limits = Limits {
            cancel: Some(&flag),
            ..Limits::default()
        };
        contract_json_with(&request, None, &limits)
    });
    let deadline = tokio::spawn(async move {
        tokio::time::sleep(time_limit).await;
        cancel.store(true, Ordering::Relaxed);
    });
    let result = task.await;
    deadline.abort();
    let result = result.map_err(|_| {
        AppError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            "contraction task failed",
        )
    })?;
    result.map_err(|e| match e {
        ContractError::Input(e) => AppError::bad("invalid_request", e),
        ContractError::Limit(WorkLimit::Cancelled) => AppError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "work_limit",
            format!(
                "the exact contractor was stopped by this service's time limit of {} s \
                 per contraction before an answer; use fewer boxes or axes, or a \
                 polynomial contractor (best)",
                time_limit.as_secs_f64()
            ),
        ),
        ContractError::Limit(l) => AppError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "work_limit",
            l.to_string(),
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The worst case of `exact`'s work limit: 40 overlapping boxes in 8-D, n = 6.
    fn worst_case() -> Value {
        let mut state: u64 = 12;
        let mut unit = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes: Vec<Vec<[f64; 2]>> = (0..40)
            .map(|_| {
                (0..8)
                    .map(|_| {
                        let c = (unit() * 10.0).round();
                        let a = (4.0 + unit() * 4.0).round();
                        let b = (4.0 + unit() * 4.0).round();
                        [c - a, c + b]
                    })
                    .collect()
            })
            .collect();
        json!({"format": "nvector-contract/1", "n": 6, "boxes": boxes, "contractor": "exact"})
    }

    /// The deadline stops the exact contractor: 422 `work_limit` naming
    /// the time limit (a 20 ms limit, far below what the node budget
    /// takes on this instance).
    #[tokio::test]
    async fn the_deadline_stops_exact_naming_the_limit() {
        let e = contract_within(worst_case(), Duration::from_millis(20))
            .await
            .expect_err("stopped");
        assert_eq!(
            (e.status, e.code),
            (StatusCode::UNPROCESSABLE_ENTITY, "work_limit")
        );
        assert!(e.message.contains("time limit of 0.02 s"), "{}", e.message);
        // Bad input is still bad input.
        let e = contract_within(json!({"format": "x"}), Duration::from_secs(1))
            .await
            .expect_err("refused");
        assert_eq!((e.code, e.path.as_str()), ("invalid_request", "format"));
    }
}
