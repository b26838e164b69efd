//! `POST /api/v1/simulate`: a simulated mission, returned and stored.

use super::error::{parse_json, ApiResult, AppError};
use super::missions::{mission_summary, store_mission};
use super::state::{owner, AppState};
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::Json;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use serde_json::Value;

pub(super) async fn post_simulate(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<(StatusCode, Json<Value>)> {
    let owner = owner(&state, &headers)?;
    let v = parse_json(&body)?;
    let obj =
        nvector_core::json::object(&v, "").map_err(|e| AppError::bad("invalid_request", e))?;
    nvector_core::json::check_fields(
        obj,
        &[
            "scenario",
            "seed",
            "steps",
            "landmarks",
            "operator",
            "noise",
        ],
        "",
    )
    .map_err(|e| AppError::bad("invalid_request", e))?;
    let scenario = match obj
        .get("scenario")
        .and_then(Value::as_str)
        .map(Scenario::parse)
    {
        Some(Some(s)) => s,
        _ => {
            return Err(AppError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "invalid_request",
                "scenario must be \"paper\" or \"auv\"",
            )
            .at("scenario"))
        }
    };
    let int = |k: &str, max: u64| -> ApiResult<Option<u64>> {
        match obj.get(k) {
            None | Some(Value::Null) => Ok(None),
            Some(x) => nvector_core::json::integer(x, k, max)
                .map(Some)
                .map_err(|e| AppError::bad("invalid_request", e)),
        }
    };
    let mut o = SimulateOptions::new(scenario, int("seed", u64::MAX)?.unwrap_or(1));
    o.steps = int("steps", state.config.max_steps as u64)?.map(|s| s.max(2) as usize);
    o.landmarks = int("landmarks", 64)?.map(|s| s.max(1) as usize);
    o.operator = obj
        .get("operator")
        .and_then(Value::as_bool)
        .unwrap_or(false);
    if let Some(x) = obj.get("noise") {
        let n = nvector_core::json::number(x, "noise")
            .map_err(|e| AppError::bad("invalid_request", e))?;
        if !(0.0..=100.0).contains(&n) {
            return Err(AppError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "invalid_request",
                "noise must be in [0, 100]",
            )
            .at("noise"));
        }
        o.noise = n;
    }
    let mission = tokio::task::spawn_blocking(move || simulate(&o))
        .await
        .map_err(|_| {
            AppError::new(
                StatusCode::INTERNAL_SERVER_ERROR,
                "internal",
                "simulation task failed",
            )
        })?;
    let (id, m) = store_mission(&state, &owner, &mission).await?;
    let mut out = mission_summary(&id, &m);
    out["mission"] = mission;
    Ok((StatusCode::CREATED, Json(out)))
}
