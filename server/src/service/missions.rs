//! Missions: `POST /api/v1/missions` (JSON body or multipart `file`),
//! `GET /api/v1/missions` (paged), `GET` and `DELETE /api/v1/missions/{id}`.
//! The mission itself is read and validated by core (`Mission::from_value`);
//! its document schema is core's `format::mission_doc::MissionDoc` (named `Mission`).

use super::config::Config;
use super::error::ErrorBody;
use super::error::{parse_json, ApiResult, AppError};
use super::error::{NoSuchMission, StorageUnavailable, Unauthorized};
use super::state::{AppState, Owner};
use super::store;
use super::worker::now_ms;
use axum::extract::{FromRequest, Multipart, Path, Query, Request, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use futures_util::StreamExt;
use nvector_core::format::leaf::{Integer, List};
use nvector_core::format::mission_doc::MissionDoc;
use nvector_core::slam::mission::Mission;
use serde::Serialize;
use serde_json::Value;
use utoipa::{IntoParams, ToSchema};

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
                let upload = MissionUpload {
                    file: Vec::from(bytes),
                };
                return Ok(upload.file);
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
    read_body(req, state.config.max_body).await
}

/// A request body read into one buffer: its declared `Content-Length`
/// (within `max`, which the body limit layer has checked) reserved once,
/// so that a large upload is held once while it is read, not as chunks
/// plus their concatenation. Past `max`: 413.
async fn read_body(req: Request, max: usize) -> ApiResult<Vec<u8>> {
    let declared = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<usize>().ok())
        .unwrap_or(0);
    let mut out = Vec::with_capacity(declared.min(max));
    let mut stream = req.into_body().into_data_stream();
    while let Some(chunk) = stream.next().await {
        let chunk = chunk.map_err(|_| {
            AppError::new(
                StatusCode::BAD_REQUEST,
                "invalid_body",
                "the request body could not be read to its end",
            )
        })?;
        if out.len() + chunk.len() > max {
            return Err(AppError::new(
                StatusCode::PAYLOAD_TOO_LARGE,
                "body_too_large",
                format!("the request body is above this service's limit of {max} bytes"),
            ));
        }
        out.extend_from_slice(&chunk);
    }
    Ok(out)
}

/// Validates a mission: this service's limits on steps and (for an upload)
/// detections first, then core's parser.
pub(super) fn check_mission(v: &Value, config: &Config, uploaded: bool) -> ApiResult<Mission> {
    // Another of the project's formats (a result uploaded as a mission):
    // said so, before its fields are read as a mission's.
    let declared = v.get("format").and_then(Value::as_str);
    if let Some(note) = super::formats::other_format(declared, "nvector-mission/1") {
        return Err(AppError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "invalid_mission",
            format!("not a mission: {note}"),
        )
        .at("format"));
    }
    // Cheap limits first, before building the model.
    if let Some(n) = v
        .get("steps")
        .and_then(|s| nvector_core::json::integer(s, "steps", u64::MAX).ok())
    {
        if n > config.max_steps as u64 {
            return Err(too_many_steps(n, config));
        }
    }
    if let Some(d) = v
        .get("detections")
        .and_then(Value::as_array)
        .filter(|_| uploaded)
    {
        if d.len() > config.max_detections {
            return Err(too_many_detections(d.len(), config));
        }
    }
    Mission::from_value(v).map_err(|e| AppError::bad("invalid_mission", e))
}

/// 413 for a mission of `n` steps, above the service's limit.
fn too_many_steps(n: u64, config: &Config) -> AppError {
    AppError::new(
        StatusCode::PAYLOAD_TOO_LARGE,
        "too_large",
        format!(
            "{n} steps is above this service's limit of {}",
            config.max_steps
        ),
    )
    .at("steps")
}

/// 413 for a mission of `n` detections, above the service's limit.
fn too_many_detections(n: usize, config: &Config) -> AppError {
    AppError::new(
        StatusCode::PAYLOAD_TOO_LARGE,
        "too_large",
        format!(
            "{n} detections is above this service's limit of {}",
            config.max_detections
        ),
    )
    .at("detections")
}

/// A stored mission, as `POST /missions` and `POST /simulate` answer.
#[derive(Serialize, ToSchema)]
pub struct MissionSummary {
    /// The mission's id (`m-...`).
    pub id: String,
    /// Its name.
    pub name: String,
    /// N, its steps.
    pub steps: u64,
    /// Its number of detections.
    pub detections: u64,
}

/// One mission of a list.
#[derive(Serialize, ToSchema)]
pub struct MissionItem {
    /// The mission's id.
    pub id: String,
    /// Its name.
    pub name: String,
    /// N, its steps.
    pub steps: i64,
    /// Its number of detections.
    pub detections: i64,
    /// When it was stored (ms since the Unix epoch).
    pub created_ms: i64,
    /// The size of the stored mission JSON, in bytes.
    pub bytes: i64,
}

/// A page of missions, oldest first.
#[derive(Serialize, ToSchema)]
pub struct MissionList {
    /// The missions of this page.
    pub missions: Vec<MissionItem>,
    /// The `after` of the next page; null on the last page.
    pub next: Option<String>,
}

/// A multipart upload of a mission: the form's reading builds it.
#[derive(ToSchema)]
pub struct MissionUpload {
    /// The mission JSON (the bytes of the form's `file` part).
    #[schema(value_type = MissionDoc)]
    pub file: Vec<u8>,
}

pub(super) fn mission_summary(id: &str, m: &Mission) -> MissionSummary {
    MissionSummary {
        id: id.to_string(),
        name: m.name.clone(),
        steps: m.steps as u64,
        detections: m.detections.len() as u64,
    }
}

/// Validates and stores a mission. A simulated one (`uploaded` false) is
/// not held to the upload limit on detections: its size is bounded by the
/// simulation's own limits (steps, false detections).
pub(super) async fn store_mission(
    state: &AppState,
    owner: &str,
    v: &Value,
    uploaded: bool,
) -> ApiResult<(String, Mission)> {
    let m = check_mission(v, &state.config, uploaded)?;
    let id = insert_mission(state, owner, &m, v.to_string()).await?;
    Ok((id, m))
}

/// Stores a validated mission with its JSON text; its new id.
async fn insert_mission(
    state: &AppState,
    owner: &str,
    m: &Mission,
    body: String,
) -> ApiResult<String> {
    let row = store::mission_row(String::new(), m, now_ms(), body.len());
    insert_row(state, owner, row, body).await
}

/// Stores a mission's row (given a new id here) and JSON text; the id.
async fn insert_row(
    state: &AppState,
    owner: &str,
    mut row: store::MissionRow,
    body: String,
) -> ApiResult<String> {
    let id = format!("m-{}", uuid::Uuid::new_v4().simple());
    row.id = id.clone();
    let owner = owner.to_string();
    state
        .db(move |st| st.insert_mission(&owner, &row, &body))
        .await?;
    Ok(id)
}

/// Store a mission: a JSON body, or a multipart form with a `file` field.
#[utoipa::path(
    post,
    path = "/missions",
    operation_id = "createMission",
    tag = "missions",
    request_body(
        description = "The mission (docs/formats.md), as JSON or as the `file` field of a form",
        content(
            (MissionDoc = "application/json"),
            (MissionUpload = "multipart/form-data")
        )
    ),
    responses(
        (status = 201, description = "Stored", body = MissionSummary,
            links(
                ("getMission" = (operation_id = "getMission", parameters(("id" = "$response.body#/id")),
                    description = "The stored mission")),
                ("createJob" = (operation_id = "createJob", request_body = json!({"mission": "$response.body#/id"}),
                    description = "A SLAM job on it")),
                ("deleteMission" = (operation_id = "deleteMission", parameters(("id" = "$response.body#/id")),
                    description = "Delete it and its jobs"))
            )),
        (status = 400, description = "Malformed JSON or form", body = ErrorBody),
        Unauthorized,
        (status = 413, description = "Body, steps or detections above this service's limits", body = ErrorBody),
        (status = 415, description = "Neither JSON nor a form", body = ErrorBody),
        (status = 422, description = "Invalid mission, with the JSON path", body = ErrorBody),
        StorageUnavailable,
    )
)]
pub(super) async fn post_mission(
    State(state): State<AppState>,
    Owner(owner): Owner,
    req: Request,
) -> ApiResult<(StatusCode, Json<MissionSummary>)> {
    let bytes = mission_body(req, &state).await?;
    // The mission is held while its row and summary are made, then
    // dropped before the text is compacted and stored.
    let m = match typed_upload(&bytes, &state.config) {
        Some(read) => read?,
        None => {
            // The text is not a mission read straight into typed data: the
            // JSON tree's reading names what is wrong, as it always has.
            let v = parse_json(&bytes)?;
            check_mission(&v, &state.config, true)?
        }
    };
    let summary = mission_summary("", &m);
    let mut row = store::mission_row(String::new(), &m, now_ms(), 0);
    drop(m);
    let body = nvector_core::format::compact_json(String::from_utf8(bytes).unwrap_or_default());
    row.bytes = body.len() as i64;
    let id = insert_row(&state, &owner, row, body).await?;
    Ok((StatusCode::CREATED, Json(MissionSummary { id, ..summary })))
}

/// An uploaded mission read straight from its text into typed data
/// (`Mission::from_doc` of core's `MissionDoc`): no JSON tree is built,
/// so a large upload costs its body and its typed data, not the tree's
/// several times the body. `None` when the text is not valid JSON, repeats
/// a key, declares another format or does not read as a mission document:
/// the caller then reads it through a JSON tree ([`parse_json`],
/// [`check_mission`]), whose errors name the problem and its path (one
/// message for each kind of error, whichever path a body takes). The
/// service's limits on steps and detections are checked before the model
/// is built, as [`check_mission`] does.
fn typed_upload(bytes: &[u8], config: &Config) -> Option<ApiResult<Mission>> {
    let text = std::str::from_utf8(bytes).ok()?;
    serde_json::from_str::<serde::de::IgnoredAny>(text).ok()?;
    if nvector_core::format::duplicate_key(text).is_some() {
        return None;
    }
    let doc: MissionDoc = nvector_core::format::from_str(text).ok()?;
    let declared = doc.format.as_ref().and_then(Value::as_str);
    if super::formats::other_format(declared, "nvector-mission/1").is_some() {
        return None;
    }
    if let Some(Integer::Value(n)) = doc.steps {
        if n > config.max_steps as u64 {
            return Some(Err(too_many_steps(n, config)));
        }
    }
    if let Some(List(d)) = &doc.detections {
        if d.len() > config.max_detections {
            return Some(Err(too_many_detections(d.len(), config)));
        }
    }
    Some(Mission::from_doc(doc).map_err(|e| AppError::bad("invalid_mission", e)))
}

/// The page of `GET /missions`.
#[derive(IntoParams)]
#[into_params(parameter_in = Query)]
pub(super) struct Page {
    /// Most missions in the page (default 100).
    #[param(minimum = 1, maximum = 1000)]
    limit: Option<i64>,
    /// The `next` of the previous page: list the missions after this id.
    after: Option<String>,
}

impl Page {
    /// The page of a query's pairs: each parameter at most once, `limit` an
    /// integer in 1..=1000; an error names the parameter. Other parameters
    /// are ignored.
    fn read(pairs: &[(String, String)]) -> ApiResult<Page> {
        let bad = |name: &str, message: String| {
            AppError::new(StatusCode::BAD_REQUEST, "invalid_query", message).at(name)
        };
        let mut page = Page {
            limit: None,
            after: None,
        };
        for (name, value) in pairs {
            match name.as_str() {
                "limit" => {
                    if page.limit.is_some() {
                        return Err(bad("limit", "limit is given twice".into()));
                    }
                    let n = value
                        .parse::<i64>()
                        .ok()
                        .filter(|n| (1..=1000).contains(n) && !value.starts_with('+'))
                        .ok_or_else(|| {
                            bad(
                                "limit",
                                format!(
                                    "limit must be an integer between 1 and 1000, not `{value}`"
                                ),
                            )
                        })?;
                    page.limit = Some(n);
                }
                "after" => {
                    if page.after.is_some() {
                        return Err(bad("after", "after is given twice".into()));
                    }
                    page.after = Some(value.clone());
                }
                _ => {}
            }
        }
        Ok(page)
    }
}

/// List missions, oldest first, a page at a time.
#[utoipa::path(
    get,
    path = "/missions",
    operation_id = "listMissions",
    tag = "missions",
    params(Page),
    responses(
        (status = 200, description = "A page of missions", body = MissionList),
        (status = 400, description = "Bad `limit`", body = ErrorBody),
        (status = 404, description = "An `after` that was never a mission of this key", body = ErrorBody),
        Unauthorized,
        StorageUnavailable,
    )
)]
pub(super) async fn list_missions(
    State(state): State<AppState>,
    Owner(owner): Owner,
    pairs: Result<Query<Vec<(String, String)>>, axum::extract::rejection::QueryRejection>,
) -> ApiResult<Json<MissionList>> {
    let Query(pairs) = pairs
        .map_err(|e| AppError::new(StatusCode::BAD_REQUEST, "invalid_query", e.body_text()))?;
    let page = Page::read(&pairs)?;
    let limit = page.limit.unwrap_or(100);
    let after = page.after.clone();
    let Some(rows) = state
        .db(move |st| st.list_missions(&owner, after.as_deref(), limit))
        .await?
    else {
        // 404, not 400: any string is a well-formed `after` (the OpenAPI
        // document says so); this one names no mission.
        return Err(AppError::new(
            StatusCode::NOT_FOUND,
            "not_found",
            "after: no mission of yours has this id (give the `next` of a page, or leave `after` out to start from the first)",
        )
        .at("after"));
    };
    let next = if rows.len() as i64 == limit {
        rows.last().map(|r| r.id.clone())
    } else {
        None
    };
    let missions = rows
        .into_iter()
        .map(|r| MissionItem {
            id: r.id,
            name: r.name,
            steps: r.steps,
            detections: r.detections,
            created_ms: r.created,
            bytes: r.bytes,
        })
        .collect();
    Ok(Json(MissionList { missions, next }))
}

/// The mission as stored.
#[utoipa::path(
    get,
    path = "/missions/{id}",
    operation_id = "getMission",
    tag = "missions",
    params(("id" = String, Path, description = "The mission's id")),
    responses(
        (status = 200, description = "The mission, as uploaded", body = MissionDoc),
        Unauthorized,
        NoSuchMission,
        StorageUnavailable,
    )
)]
pub(super) async fn get_mission(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
) -> ApiResult<Response> {
    let body = state
        .db(move |st| st.mission_body(&owner, &id))
        .await?
        .ok_or_else(|| AppError::not_found("mission"))?;
    Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
}

/// Delete a mission and its jobs.
#[utoipa::path(
    delete,
    path = "/missions/{id}",
    operation_id = "deleteMission",
    tag = "missions",
    params(("id" = String, Path, description = "The mission's id")),
    responses(
        (status = 204, description = "Deleted"),
        Unauthorized,
        NoSuchMission,
        StorageUnavailable,
    )
)]
pub(super) async fn delete_mission(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
) -> ApiResult<StatusCode> {
    if state.db(move |st| st.delete_mission(&owner, &id)).await? {
        Ok(StatusCode::NO_CONTENT)
    } else {
        Err(AppError::not_found("mission"))
    }
}
