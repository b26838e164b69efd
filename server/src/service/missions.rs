//! Missions: `POST /api/v1/missions` (JSON body or multipart `file`),
//! `GET /api/v1/missions` (paged), `GET` and `DELETE /api/v1/missions/{id}`.

use super::config::Config;
use super::error::{parse_json, ApiResult, AppError};
use super::state::{owner, AppState};
use super::store;
use super::worker::now_ms;
use axum::body::Bytes;
use axum::extract::{FromRequest, Multipart, Path, Query, Request, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use nvector_core::slam::mission::Mission;
use serde_json::{json, Value};

/// The mission JSON of a request: a JSON body, or the `file` field of a
/// multipart form.
async fn mission_body(req: Request, state: &AppState) -> ApiResult<Vec<u8>> {
    let ctype = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ctype.starts_with("multipart/form-data") {
        let mut mp = Multipart::from_request(req, state).await.map_err(|e| {
            AppError::new(StatusCode::BAD_REQUEST, "invalid_multipart", e.body_text())
        })?;
        loop {
            let field = mp.next_field().await.map_err(|e| {
                AppError::new(StatusCode::BAD_REQUEST, "invalid_multipart", e.body_text())
            })?;
            let Some(field) = field else {
                return Err(AppError::new(
                    StatusCode::BAD_REQUEST,
                    "invalid_multipart",
                    "the form has no `file` field",
                )
                .at("file"));
            };
            if field.name() == Some("file") {
                let bytes = field.bytes().await.map_err(|e| {
                    AppError::new(StatusCode::BAD_REQUEST, "invalid_multipart", e.body_text())
                })?;
                return Ok(bytes.to_vec());
            }
        }
    }
    if !(ctype.is_empty() || ctype.starts_with("application/json")) {
        return Err(AppError::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "unsupported_media_type",
            format!("expected application/json or multipart/form-data, found {ctype}"),
        ));
    }
    let bytes = Bytes::from_request(req, state).await.map_err(|e| {
        AppError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "body_too_large",
            e.body_text(),
        )
    })?;
    Ok(bytes.to_vec())
}

pub(super) fn check_mission(v: &Value, config: &Config) -> ApiResult<Mission> {
    // Cheap limits first, before building the model.
    if let Some(n) = v.get("steps").and_then(Value::as_u64) {
        if n as usize > config.max_steps {
            return Err(AppError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                "too_large",
                format!(
                    "{n} steps is above this service's limit of {}",
                    config.max_steps
                ),
            )
            .at("steps"));
        }
    }
    if let Some(d) = v.get("detections").and_then(Value::as_array) {
        if d.len() > config.max_detections {
            return Err(AppError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                "too_large",
                format!(
                    "{} detections is above this service's limit of {}",
                    d.len(),
                    config.max_detections
                ),
            )
            .at("detections"));
        }
    }
    Mission::from_value(v).map_err(|e| AppError::bad("invalid_mission", e))
}

pub(super) fn mission_summary(id: &str, m: &Mission) -> Value {
    json!({"id": id, "name": m.name, "steps": m.steps, "detections": m.detections.len()})
}

pub(super) async fn store_mission(
    state: &AppState,
    owner: &str,
    v: &Value,
) -> ApiResult<(String, Mission)> {
    let m = check_mission(v, &state.config)?;
    let id = format!("m-{}", uuid::Uuid::new_v4().simple());
    let row = store::mission_row(id.clone(), &m, now_ms());
    let body = v.to_string();
    let owner = owner.to_string();
    state
        .db(move |st| st.insert_mission(&owner, &row, &body))
        .await?;
    Ok((id, m))
}

pub(super) async fn post_mission(
    State(state): State<AppState>,
    req: Request,
) -> ApiResult<(StatusCode, Json<Value>)> {
    let owner = owner(&state, req.headers())?;
    let bytes = mission_body(req, &state).await?;
    let v = parse_json(&bytes)?;
    let (id, m) = store_mission(&state, &owner, &v).await?;
    Ok((StatusCode::CREATED, Json(mission_summary(&id, &m))))
}

#[derive(serde::Deserialize)]
pub(super) struct Page {
    limit: Option<i64>,
    after: Option<String>,
}

pub(super) async fn list_missions(
    State(state): State<AppState>,
    headers: HeaderMap,
    page: Result<Query<Page>, axum::extract::rejection::QueryRejection>,
) -> ApiResult<Json<Value>> {
    let owner = owner(&state, &headers)?;
    let Query(page) =
        page.map_err(|e| AppError::new(StatusCode::BAD_REQUEST, "invalid_query", e.body_text()))?;
    let limit = page.limit.unwrap_or(100);
    if !(1..=1000).contains(&limit) {
        return Err(AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_query",
            "limit must be between 1 and 1000",
        )
        .at("limit"));
    }
    let after = page.after.clone();
    let rows = state
        .db(move |st| st.list_missions(&owner, after.as_deref(), limit))
        .await?;
    let next = if rows.len() as i64 == limit {
        rows.last().map(|r| r.id.clone())
    } else {
        None
    };
    let items: Vec<Value> = rows
        .iter()
        .map(|r| json!({"id": r.id, "name": r.name, "steps": r.steps, "detections": r.detections, "created_ms": r.created}))
        .collect();
    Ok(Json(json!({"missions": items, "next": next})))
}

pub(super) async fn get_mission(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    let owner = owner(&state, &headers)?;
    let body = state
        .db(move |st| st.mission_body(&owner, &id))
        .await?
        .ok_or_else(|| AppError::not_found("mission"))?;
    Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
}

pub(super) async fn delete_mission(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> ApiResult<StatusCode> {
    let owner = owner(&state, &headers)?;
    if state.db(move |st| st.delete_mission(&owner, &id)).await? {
        Ok(StatusCode::NO_CONTENT)
    } else {
        Err(AppError::not_found("mission"))
    }
}
