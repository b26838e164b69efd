//! The HTTP service of spec/api.md: missions, jobs, contraction and
//! simulation over REST, progress as Server-Sent Events, the page served at
//! `/`. `app(state)` builds the router; `serve(config)` runs it.

pub mod jobs;
pub mod openapi;
pub mod store;

use axum::body::Bytes;
use axum::extract::{
    DefaultBodyLimit, FromRequest, MatchedPath, Multipart, Path, Query, Request, State,
};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use futures_util::stream::{self, Stream};
use jobs::{now_ms, Workers};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagator::Association;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use serde_json::{json, Value};
use std::collections::{BTreeMap, HashSet};
use std::convert::Infallible;
use std::sync::{Arc, Mutex};
use std::time::Duration;
use store::{JobRow, Store};

/// Service configuration (flags of `nvector serve`).
#[derive(Debug, Clone)]
pub struct Config {
    /// Largest request body (bytes).
    pub max_body: usize,
    /// Most steps in a mission.
    pub max_steps: usize,
    /// Most detections in a mission.
    pub max_detections: usize,
    /// Most queued jobs (then 429).
    pub max_queue: i64,
    /// Default and largest job time limit (s).
    pub job_time_limit_s: f64,
    /// Directory of the page.
    pub static_dir: std::path::PathBuf,
    /// API keys (empty: no authentication).
    pub api_keys: HashSet<String>,
    /// Allowed CORS origins (empty: CORS off).
    pub cors_origins: Vec<String>,
    /// How long a running job may go without its process's heartbeat
    /// before it is re-queued.
    pub job_lease: std::time::Duration,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            max_body: 64 << 20,
            max_steps: 2_000_000,
            max_detections: 100_000,
            max_queue: 1000,
            job_time_limit_s: 300.0,
            static_dir: "web/www".into(),
            api_keys: HashSet::new(),
            cors_origins: Vec::new(),
            job_lease: std::time::Duration::from_secs(10),
        }
    }
}

/// Shared state of the handlers.
#[derive(Clone)]
pub struct AppState {
    /// Storage.
    pub store: Arc<dyn Store>,
    /// Configuration.
    pub config: Arc<Config>,
    /// Workers (wake-ups, metrics).
    pub workers: Arc<Workers>,
    /// Requests by (route, status).
    pub requests: Arc<Mutex<BTreeMap<(String, u16), u64>>>,
}

impl AppState {
    /// Runs a storage call on the blocking pool: database drivers block, and
    /// the async workers must keep serving.
    async fn db<T: Send + 'static>(
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

/// A client or service error, as the spec's JSON error body.
#[derive(Debug)]
pub struct AppError {
    status: StatusCode,
    code: &'static str,
    message: String,
    path: String,
    retry_after: Option<u64>,
}

impl AppError {
    fn new(status: StatusCode, code: &'static str, message: impl Into<String>) -> AppError {
        AppError {
            status,
            code,
            message: message.into(),
            path: String::new(),
            retry_after: None,
        }
    }

    fn at(mut self, path: impl Into<String>) -> AppError {
        self.path = path.into();
        self
    }

    fn not_found(what: &str) -> AppError {
        AppError::new(
            StatusCode::NOT_FOUND,
            "not_found",
            format!("no such {what}"),
        )
    }

    fn bad(code: &'static str, e: nvector_core::InputError) -> AppError {
        AppError::new(StatusCode::UNPROCESSABLE_ENTITY, code, e.message).at(e.path)
    }
}

impl From<store::StoreError> for AppError {
    fn from(e: store::StoreError) -> Self {
        tracing::error!("{e}");
        AppError::new(
            StatusCode::SERVICE_UNAVAILABLE,
            "storage_unavailable",
            "the storage is unavailable, try again",
        )
    }
}

impl IntoResponse for AppError {
    fn into_response(self) -> Response {
        let body =
            json!({"error": {"code": self.code, "message": self.message, "path": self.path}});
        let mut r = (self.status, Json(body)).into_response();
        if let Some(s) = self.retry_after {
            r.headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(s));
        }
        r
    }
}

type ApiResult<T> = Result<T, AppError>;

/// The owner of a request: its API key, or "" when keys are off.
fn owner(state: &AppState, headers: &HeaderMap) -> ApiResult<String> {
    if state.config.api_keys.is_empty() {
        return Ok(String::new());
    }
    let key = headers
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::trim);
    match key {
        Some(k) if state.config.api_keys.contains(k) => Ok(k.to_string()),
        _ => Err(AppError::new(
            StatusCode::UNAUTHORIZED,
            "unauthorized",
            "missing or unknown API key (Authorization: Bearer KEY)",
        )),
    }
}

fn parse_json(bytes: &[u8]) -> ApiResult<Value> {
    serde_json::from_slice(bytes).map_err(|e| {
        AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_json",
            format!("invalid JSON: {e}"),
        )
    })
}

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

fn check_mission(v: &Value, config: &Config) -> ApiResult<Mission> {
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

fn mission_summary(id: &str, m: &Mission) -> Value {
    json!({"id": id, "name": m.name, "steps": m.steps, "detections": m.detections.len()})
}

async fn store_mission(state: &AppState, owner: &str, v: &Value) -> ApiResult<(String, Mission)> {
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

async fn post_mission(
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
struct Page {
    limit: Option<i64>,
    after: Option<String>,
}

async fn list_missions(
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

async fn get_mission(
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

async fn delete_mission(
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

fn job_json(j: &JobRow) -> Value {
    let mut v = json!({
        "id": j.id,
        "mission": j.mission,
        "state": j.state,
        "contractor": j.contractor,
        "progress": {"round": j.round, "max_trajectory_diameter": j.diameter, "fraction": j.fraction},
        "created_ms": j.created,
        "started_ms": j.started,
        "finished_ms": j.finished,
    });
    if let Some(e) = &j.error {
        v["error"] = json!(e);
    }
    if j.attempts > 0 {
        v["attempts"] = json!(j.attempts);
    }
    if let Some(r) = &j.runner {
        v["runner"] = json!(r);
    }
    v
}

async fn post_job(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<(StatusCode, Json<Value>)> {
    let owner = owner(&state, &headers)?;
    let v = parse_json(&body)?;
    let obj = nvector_core::json::object(&v, "").map_err(|e| AppError::bad("invalid_job", e))?;
    nvector_core::json::check_fields(
        obj,
        &["mission", "contractor", "max_rounds", "time_limit_s"],
        "",
    )
    .map_err(|e| AppError::bad("invalid_job", e))?;
    let mission = obj
        .get("mission")
        .and_then(Value::as_str)
        .ok_or_else(|| {
            AppError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "invalid_job",
                "expected the mission id (a string)",
            )
            .at("mission")
        })?
        .to_string();
    let body = {
        let (owner, mission) = (owner.clone(), mission.clone());
        state
            .db(move |st| st.mission_body(&owner, &mission))
            .await?
            .ok_or_else(|| AppError::not_found("mission").at("mission"))?
    };
    let contractor = match obj.get("contractor") {
        None | Some(Value::Null) => {
            let has_n = serde_json::from_str::<Value>(&body).ok().and_then(|m| m.get("landmark_count").cloned()).is_some_and(|n| !n.is_null());
            if has_n { "best" } else { "none" }.to_string()
        }
        Some(Value::String(s)) if Association::parse(s).is_some() => s.clone(),
        Some(other) => {
            return Err(AppError::new(
                StatusCode::UNPROCESSABLE_ENTITY,
                "invalid_job",
                format!("unknown contractor {other} (expected none, nvalue, projection, independent or best)"),
            )
            .at("contractor"))
        }
    };
    let max_rounds = match obj.get("max_rounds") {
        None | Some(Value::Null) => 10_000,
        Some(x) => nvector_core::json::integer(x, "max_rounds", u32::MAX as u64)
            .map_err(|e| AppError::bad("invalid_job", e))? as i64,
    };
    let limit = state.config.job_time_limit_s;
    let time_limit_s = match obj.get("time_limit_s") {
        None | Some(Value::Null) => limit,
        Some(x) => {
            let t = nvector_core::json::number(x, "time_limit_s")
                .map_err(|e| AppError::bad("invalid_job", e))?;
            if !(t > 0.0 && t <= limit) {
                return Err(AppError::new(
                    StatusCode::UNPROCESSABLE_ENTITY,
                    "invalid_job",
                    format!("time_limit_s must be in (0, {limit}], found {t}"),
                )
                .at("time_limit_s"));
            }
            t
        }
    };
    if state.db(|st| st.queued_count()).await? >= state.config.max_queue {
        let mut e = AppError::new(
            StatusCode::TOO_MANY_REQUESTS,
            "queue_full",
            "too many queued jobs, retry later",
        );
        e.retry_after = Some(5);
        return Err(e);
    }
    let job = JobRow {
        id: format!("j-{}", uuid::Uuid::new_v4().simple()),
        mission,
        state: "queued".into(),
        contractor,
        max_rounds,
        time_limit_s,
        round: 0,
        diameter: None,
        fraction: 0.0,
        error: None,
        created: now_ms(),
        started: None,
        finished: None,
        attempts: 0,
        runner: None,
    };
    let id = job.id.clone();
    state.db(move |st| st.insert_job(&owner, &job)).await?;
    state.workers.notify();
    Ok((
        StatusCode::ACCEPTED,
        Json(json!({"id": id, "state": "queued"})),
    ))
}

async fn get_job(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> ApiResult<Json<Value>> {
    let owner = owner(&state, &headers)?;
    let j = state
        .db(move |st| st.job(&owner, &id))
        .await?
        .ok_or_else(|| AppError::not_found("job"))?;
    Ok(Json(job_json(&j)))
}

async fn delete_job(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> ApiResult<(StatusCode, Json<Value>)> {
    let owner = owner(&state, &headers)?;
    let (o, i) = (owner.clone(), id.clone());
    let cancelled = state.db(move |st| st.cancel_job(&o, &i, now_ms())).await?;
    state.workers.changed(&id);
    match cancelled {
        None => Err(AppError::not_found("job")),
        Some(s) if s == "queued" || s == "running" => Ok((
            StatusCode::ACCEPTED,
            Json(json!({"id": id, "state": "cancelled"})),
        )),
        Some(s) => Err(AppError::new(
            StatusCode::CONFLICT,
            "job_ended",
            format!("the job has already ended ({s})"),
        )),
    }
}

async fn job_events(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
) -> ApiResult<Sse<impl Stream<Item = Result<Event, Infallible>>>> {
    let owner = owner(&state, &headers)?;
    {
        let (o, i) = (owner.clone(), id.clone());
        state
            .db(move |st| st.job(&o, &i))
            .await?
            .ok_or_else(|| AppError::not_found("job"))?;
    }
    // The stream wakes when a worker of this process reports a change of
    // this job (an in-memory broadcast of job ids), and polls storage every
    // half second anyway, for jobs run by another process sharing the
    // database. An event is sent when the job changes; the stream ends
    // after the terminal state.
    let rx = state.workers.changes.subscribe();
    let s = stream::unfold(
        (state, owner, id, String::new(), false, rx),
        |(state, owner, id, last, done, mut rx)| async move {
            if done {
                return None;
            }
            loop {
                let (o, i) = (owner.clone(), id.clone());
                let job = state.db(move |st| st.job(&o, &i)).await.ok().flatten();
                let Some(job) = job else {
                    let ev = Event::default()
                        .event("end")
                        .data(json!({"id": id, "state": "deleted"}).to_string());
                    return Some((Ok(ev), (state, owner, id, last, true, rx)));
                };
                let text = job_json(&job).to_string();
                let terminal = matches!(job.state.as_str(), "done" | "failed" | "cancelled");
                if text != last {
                    let ev = Event::default()
                        .event(if terminal { "end" } else { "progress" })
                        .data(text.clone());
                    return Some((Ok(ev), (state, owner, id, text, terminal, rx)));
                }
                let poll = tokio::time::sleep(Duration::from_millis(500));
                tokio::pin!(poll);
                loop {
                    tokio::select! {
                        _ = &mut poll => break,
                        r = rx.recv() => match r {
                            Ok(changed) if changed != id => continue,
                            Err(tokio::sync::broadcast::error::RecvError::Closed) => {
                                (&mut poll).await;
                                break;
                            }
                            _ => break,
                        },
                    }
                }
            }
        },
    );
    Ok(Sse::new(s).keep_alive(KeepAlive::default()))
}

#[derive(serde::Deserialize)]
struct ResultQuery {
    format: Option<String>,
}

async fn job_result(
    State(state): State<AppState>,
    headers: HeaderMap,
    Path(id): Path<String>,
    q: Result<Query<ResultQuery>, axum::extract::rejection::QueryRejection>,
) -> ApiResult<Response> {
    let owner = owner(&state, &headers)?;
    let Query(q) =
        q.map_err(|e| AppError::new(StatusCode::BAD_REQUEST, "invalid_query", e.body_text()))?;
    let job = {
        let (o, i) = (owner.clone(), id.clone());
        state
            .db(move |st| st.job(&o, &i))
            .await?
            .ok_or_else(|| AppError::not_found("job"))?
    };
    if job.state != "done" {
        return Err(AppError::new(
            StatusCode::CONFLICT,
            "not_done",
            format!("the job is {}, no result yet", job.state),
        ));
    }
    let text = {
        let (o, i) = (owner.clone(), id.clone());
        state
            .db(move |st| st.result(&o, &i))
            .await?
            .ok_or_else(|| AppError::not_found("result"))?
    };
    match q.format.as_deref().unwrap_or("json") {
        "json" => Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response()),
        "csv" => {
            let v = parse_json(text.as_bytes())?;
            Ok(([(header::CONTENT_TYPE, "text/csv")], trajectory_csv(&v)).into_response())
        }
        "svg" => {
            let v = parse_json(text.as_bytes())?;
            let mission_id = job.mission.clone();
            let mission = state
                .db(move |st| st.mission_body(&owner, &mission_id))
                .await?
                .and_then(|b| serde_json::from_str(&b).ok())
                .unwrap_or(Value::Null);
            Ok((
                [(header::CONTENT_TYPE, "image/svg+xml")],
                crate::cli::plot::render_svg(&v, &mission),
            )
                .into_response())
        }
        other => Err(AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_query",
            format!("unknown format '{other}' (json, csv or svg)"),
        )
        .at("format")),
    }
}

/// The trajectory as CSV: `step,x_lo,x_hi,y_lo,y_hi[,z_lo,z_hi]`.
pub fn trajectory_csv(result: &Value) -> String {
    let traj = result["trajectory"].as_array().cloned().unwrap_or_default();
    let dim = traj
        .iter()
        .find_map(|b| b.as_array().map(Vec::len))
        .unwrap_or(2);
    let names = ["x", "y", "z"];
    let mut out = String::from("step");
    for n in names.iter().take(dim) {
        out.push_str(&format!(",{n}_lo,{n}_hi"));
    }
    out.push('\n');
    for (i, b) in traj.iter().enumerate() {
        out.push_str(&i.to_string());
        for a in 0..dim {
            let cell = |k: usize| match &b[a][k] {
                Value::Number(n) => n.to_string(),
                Value::String(s) => s.clone(),
                _ => "empty".into(),
            };
            out.push_str(&format!(",{},{}", cell(0), cell(1)));
        }
        out.push('\n');
    }
    out
}

async fn post_contract(
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

async fn post_simulate(
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

async fn healthz() -> &'static str {
    "ok\n"
}

async fn readyz(State(state): State<AppState>) -> ApiResult<&'static str> {
    state.db(|st| st.ping()).await?;
    Ok("ready\n")
}

async fn metrics(State(state): State<AppState>) -> ApiResult<Response> {
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

async fn count_requests(State(state): State<AppState>, req: Request, next: Next) -> Response {
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

const BUILTIN_PAGE: &str = "<!doctype html><meta charset=utf-8><title>nvector</title><h1>nvector</h1><p>The web UI is not built: run <code>make run</code> (it builds web/www). The API is at <code>/api/v1</code>.</p>";

async fn api_not_found() -> AppError {
    AppError::new(StatusCode::NOT_FOUND, "not_found", "no such endpoint")
}

/// The router of the whole service.
pub fn app(state: AppState) -> Router {
    let api = Router::new()
        .route("/missions", post(post_mission).get(list_missions))
        .route("/missions/{id}", get(get_mission).delete(delete_mission))
        .route("/jobs", post(post_job))
        .route("/jobs/{id}", get(get_job).delete(delete_job))
        .route("/jobs/{id}/events", get(job_events))
        .route("/jobs/{id}/result", get(job_result))
        .route("/contract", post(post_contract))
        .route("/simulate", post(post_simulate))
        .route("/openapi.json", get(|| async { Json(openapi::document()) }))
        .fallback(api_not_found);
    let mut router = Router::new()
        .nest("/api/v1", api)
        .route("/healthz", get(healthz))
        .route("/readyz", get(readyz))
        .route("/metrics", get(metrics))
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
            count_requests,
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
    let requeued = tokio::task::spawn_blocking(move || st.requeue_stale(jobs::now_ms(), lease_ms))
        .await
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())?;
    if requeued > 0 {
        tracing::info!("re-queued {requeued} job(s) left running by a stopped process");
    }
    let workers = Workers::new();
    let mut handles = jobs::start(workers_n, store.clone(), workers.clone());
    handles.push(jobs::start_lease_keeper(
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
