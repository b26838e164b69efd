//! `POST /api/v1/contract`: one atmost_nvector contraction, synchronous,
//! on the blocking pool.

use super::error::{parse_json, ApiResult, AppError};
use super::formats::{ContractRequest, ContractResponse, ErrorBody};
use super::state::{owner, AppState};
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::Json;
use serde_json::{json, Value};

/// One atmost_nvector contraction (spec/formats.md), synchronous.
#[utoipa::path(
    post,
    path = "/contract",
    operation_id = "contract",
    tag = "contraction",
    request_body = ContractRequest,
    responses(
        (status = 200, description = "The contraction", body = ContractResponse),
        (status = 400, description = "Malformed JSON", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 413, description = "More than 100000 boxes, or body too large", body = ErrorBody),
        (status = 422, description = "Invalid request, with the JSON path; or `work_limit`: \
            the exact contractor ran out of its work budget or the time limit", body = ErrorBody),
    )
)]
pub(super) async fn post_contract(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<Json<Value>> {
    owner(&state, &headers)?;
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
    let mut out = tokio::task::spawn_blocking(move || {
        nvector_core::nvector::contract::contract_json(&v, None)
    })
    .await
    .map_err(|_| {
        AppError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            "contraction task failed",
        )
    })?
    .map_err(|e| AppError::bad("invalid_request", e))?;
    out["stats"]["elapsed_us"] = json!(start.elapsed().as_micros() as u64);
    Ok(Json(out))
}
