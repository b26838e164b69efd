//! Jobs, the HTTP side: `POST /api/v1/jobs` queues a SLAM job, `GET` and
//! `DELETE /api/v1/jobs/{id}` read and cancel it, `/events` streams its
//! progress as Server-Sent Events, `/result` returns its result (JSON, CSV
//! or SVG). The workers that run jobs are in `worker.rs`.

use super::error::ErrorBody;
use super::error::{parse_json_value, ApiResult, AppError, Body, RequestBody};
use super::error::{
    BodyTooLarge, InvalidField, MalformedJson, NoSuchJob, NoSuchMission, QueueFull,
    StorageUnavailable, Unauthorized,
};
use super::job_runner::JobKind;
use super::state::{AppState, Owner};
use super::store::{JobErrorCode, JobRow, JobState, QueuePolicy, Queued};
use super::worker::now_ms;
use axum::extract::{Path, Query, State};
use axum::http::{header, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::Json;
use futures_util::stream::{self, Stream};
use nvector_core::format::leaf::{Finite, Integer};
use nvector_core::slam::result::SlamResult;
use nvector_core::slam::types::Association;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};
use std::convert::Infallible;
use std::time::Duration;
use utoipa::{IntoParams, ToSchema};

/// The contractors core accepts for a SLAM job ([`Association::names`]).
pub fn contractor_names() -> Vec<&'static str> {
    Association::names()
}

/// "a, b or c".
pub(super) fn or_list(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

// The body of `POST /jobs`, read by `Body`.
/// A SLAM job to queue.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({"mission": "m-0123456789abcdef0123456789abcdef", "contractor": "best"}))]
pub struct JobRequest {
    /// The mission's id.
    #[serde(default)]
    #[schema(value_type = String, required = true)]
    pub mission: Option<Value>,
    /// The contractor (default: `best` when the mission has a
    /// `landmark_count`, else `none`).
    #[serde(default)]
    #[schema(value_type = Option<Association>)]
    pub contractor: Option<Value>,
    /// The round cap (default 10,000; 0 reads as 1).
    #[serde(default)]
    #[schema(value_type = Option<u32>, minimum = 0, maximum = 4294967295u32)]
    pub max_rounds: Option<Integer>,
    /// The time limit in seconds (default and largest: this service's job
    /// time limit).
    #[serde(default)]
    #[schema(value_type = Option<f64>, exclusive_minimum = 0, maximum = 300)]
    pub time_limit_s: Option<Finite>,
}

impl RequestBody for JobRequest {
    const CODE: &'static str = "invalid_job";
}

fn invalid_job(path: &str, message: impl Into<String>) -> AppError {
    AppError::new(StatusCode::UNPROCESSABLE_ENTITY, "invalid_job", message).at(path)
}

impl JobRequest {
    /// The mission's id.
    fn mission_id(&self) -> ApiResult<String> {
        match &self.mission {
            Some(Value::String(s)) => Ok(s.clone()),
            _ => Err(invalid_job("mission", "expected the mission id (a string)")),
        }
    }

    /// The contractor's name; by default `best` when the mission (its JSON
    /// text) has a `landmark_count`, else `none`.
    fn contractor(&self, mission_body: &str) -> ApiResult<String> {
        match &self.contractor {
            None | Some(Value::Null) => {
                /// Only the field that decides (the rest skipped unread).
                #[derive(Deserialize)]
                struct Counted {
                    #[serde(default)]
                    landmark_count: Option<serde::de::IgnoredAny>,
                }
                let has_n = serde_json::from_str::<Counted>(mission_body)
                    .is_ok_and(|m| m.landmark_count.is_some());
                Ok(if has_n { "best" } else { "none" }.to_string())
            }
            Some(Value::String(s)) if Association::parse(s).is_some() => Ok(s.clone()),
            Some(other) => Err(invalid_job(
                "contractor",
                format!(
                    "unknown contractor {other} (expected {})",
                    or_list(&contractor_names())
                ),
            )),
        }
    }

    /// The round cap (default 10,000).
    fn max_rounds(&self) -> ApiResult<i64> {
        match &self.max_rounds {
            None => Ok(10_000),
            Some(x) => x
                .at_most(u32::MAX as u64, "max_rounds")
                .map(|n| n as i64)
                .map_err(|e| AppError::bad("invalid_job", e)),
        }
    }

    /// The time limit, in (0, `limit`] (default `limit`).
    fn time_limit_s(&self, limit: f64) -> ApiResult<f64> {
        match self.time_limit_s {
            None => Ok(limit),
            Some(Finite(t)) if t > 0.0 && t <= limit => Ok(t),
            Some(Finite(t)) => Err(invalid_job(
                "time_limit_s",
                format!("time_limit_s must be in (0, {limit}], found {t}"),
            )),
        }
    }
}

/// A new queued job.
pub(super) fn new_job(
    mission: String,
    contractor: String,
    max_rounds: i64,
    time_limit_s: f64,
) -> JobRow {
    JobRow {
        id: format!("j-{}", uuid::Uuid::new_v4().simple()),
        mission,
        state: JobState::Queued,
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
        error_code: None,
        attempts: 0,
        runner: None,
        crashes: 0,
        cost: 0,
    }
}

/// Queues `job` for `owner` (the queue limit checked by the insert itself,
/// one atomic step) and wakes the workers.
pub(super) async fn enqueue(state: &AppState, owner: String, job: JobRow) -> ApiResult<()> {
    let policy = QueuePolicy {
        max_queue: state.config.max_queue,
        short_cost: state.config.short_job_cost,
        long_delay_ms: i64::try_from(state.config.long_job_delay.as_millis()).unwrap_or(i64::MAX),
    };
    match state
        .db(move |st| st.insert_job(&owner, &job, &policy))
        .await?
    {
        Queued::Yes => {
            state.workers.notify();
            Ok(())
        }
        Queued::Full => {
            let mut e = AppError::new(
                StatusCode::TOO_MANY_REQUESTS,
                "queue_full",
                "too many queued jobs, retry later",
            );
            e.retry_after = Some(5);
            Err(e)
        }
        Queued::NoMission => Err(AppError::not_found("mission").at("mission")),
    }
}

/// A job's progress.
#[derive(Serialize, ToSchema)]
pub struct JobProgress {
    /// Propagation rounds so far.
    pub round: i64,
    /// The largest trajectory box diameter so far (null while unknown or
    /// unbounded).
    pub max_trajectory_diameter: Option<f64>,
    /// The fraction of the work done, in [0, 1].
    pub fraction: f64,
}

/// A job.
#[derive(Serialize, ToSchema)]
pub struct Job {
    /// The job's id (`j-...`).
    pub id: String,
    /// Its mission's id.
    pub mission: String,
    /// Its state.
    pub state: JobState,
    /// Its association mode.
    pub contractor: String,
    /// Its progress.
    pub progress: JobProgress,
    /// When it was queued (ms since the Unix epoch).
    pub created_ms: i64,
    /// When it last started.
    pub started_ms: Option<i64>,
    /// When it ended.
    pub finished_ms: Option<i64>,
    /// Why it failed, or that a time limit cut it short, for a person
    /// (a failure of its worker process names the limit or the signal).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false)]
    pub error: Option<String>,
    /// The same as a word a client can test, with `error`.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false, value_type = Option<JobErrorCode>)]
    pub error_code: Option<JobErrorCode>,
    /// Times a worker claimed it (1 unless re-queued).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false)]
    pub attempts: Option<i64>,
    /// The id of the nvector process that runs or ran it.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false)]
    pub runner: Option<String>,
    /// Times the worker process running it died (abort, killed); at the
    /// service's `--job-attempts` it fails (`worker_crashed`).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(nullable = false, minimum = 1)]
    pub worker_crashes: Option<i64>,
}

impl From<&JobRow> for Job {
    fn from(j: &JobRow) -> Job {
        Job {
            id: j.id.clone(),
            mission: j.mission.clone(),
            state: j.state,
            contractor: j.contractor.clone(),
            progress: JobProgress {
                round: j.round,
                max_trajectory_diameter: j.diameter.filter(|d| d.is_finite()),
                fraction: j.fraction,
            },
            created_ms: j.created,
            started_ms: j.started,
            finished_ms: j.finished,
            // docs/api.md: the error says why in a word a client can test,
            // then the message (`error_code` holds the word alone).
            error: j.error.as_ref().map(|e| match &j.error_code {
                Some(c) if !e.starts_with(c.as_str()) => format!("{c}: {e}"),
                _ => e.clone(),
            }),
            error_code: j.error_code.as_deref().and_then(JobErrorCode::parse),
            attempts: (j.attempts > 0).then_some(j.attempts),
            runner: j.runner.clone(),
            worker_crashes: (j.crashes > 0).then_some(j.crashes),
        }
    }
}

/// One Server-Sent Event of `GET /jobs/{id}/events` (the stream sends
/// these, converted to axum's `Event`).
#[derive(ToSchema)]
pub struct JobEvent {
    /// `progress` while the job runs, `end` once, last.
    pub event: JobEventName,
    /// A `Job` object as JSON (or `{"id", "state": "deleted"}` when the job
    /// was deleted meanwhile).
    #[schema(content_media_type = "application/json")]
    pub data: String,
}

impl From<JobEvent> for Event {
    fn from(e: JobEvent) -> Event {
        let name = match e.event {
            JobEventName::Progress => "progress",
            JobEventName::End => "end",
        };
        Event::default().event(name).data(e.data)
    }
}

/// The names of a job's events.
#[derive(ToSchema)]
#[schema(rename_all = "lowercase")]
pub enum JobEventName {
    /// The job changed.
    Progress,
    /// The job ended (or was deleted); the stream closes.
    End,
}

/// A job's id and state, as `POST /jobs` and `DELETE /jobs/{id}` answer.
#[derive(Serialize, ToSchema)]
pub struct JobQueued {
    /// The job's id.
    pub id: String,
    /// `queued` (POST) or `cancelled` (DELETE).
    pub state: JobState,
}

fn job_json(j: &JobRow) -> String {
    serde_json::to_string(&Job::from(j)).unwrap_or_default()
}

/// Queue a SLAM job on a stored mission.
#[utoipa::path(
    post,
    path = "/jobs",
    operation_id = "createJob",
    tag = "jobs",
    request_body = JobRequest,
    responses(
        (status = 202, description = "Queued", body = JobQueued,
            links(
                ("getJob" = (operation_id = "getJob", parameters(("id" = "$response.body#/id")),
                    description = "The job and its progress")),
                ("jobEvents" = (operation_id = "jobEvents", parameters(("id" = "$response.body#/id")),
                    description = "Its progress as Server-Sent Events")),
                ("jobResult" = (operation_id = "jobResult", parameters(("id" = "$response.body#/id")),
                    description = "Its result, once done")),
                ("cancelJob" = (operation_id = "cancelJob", parameters(("id" = "$response.body#/id")),
                    description = "Cancel it"))
            )),
        MalformedJson,
        Unauthorized,
        NoSuchMission,
        BodyTooLarge,
        InvalidField,
        QueueFull,
        StorageUnavailable,
    )
)]
pub(super) async fn post_job(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Body(req): Body<JobRequest>,
) -> ApiResult<(StatusCode, Json<JobQueued>)> {
    let mission = req.mission_id()?;
    let body = {
        let (owner, mission) = (owner.clone(), mission.clone());
        state
            .db(move |st| st.mission_body(&owner, &mission))
            .await?
            .ok_or_else(|| AppError::not_found("mission").at("mission"))?
    };
    let contractor = match (&req.contractor, JobKind::of(&mission)) {
        // A TDOA problem (`POST /tdoa`) run again: `best` by default.
        (None | Some(Value::Null), JobKind::Tdoa) => "best".to_string(),
        _ => req.contractor(&body)?,
    };
    drop(body);
    let max_rounds = req.max_rounds()?;
    let time_limit_s = req.time_limit_s(state.config.job_time_limit_s)?;
    let job = new_job(mission, contractor, max_rounds, time_limit_s);
    let id = job.id.clone();
    enqueue(&state, owner, job).await?;
    Ok((
        StatusCode::ACCEPTED,
        Json(JobQueued {
            id,
            state: JobState::Queued,
        }),
    ))
}

/// A job and its progress.
#[utoipa::path(
    get,
    path = "/jobs/{id}",
    operation_id = "getJob",
    tag = "jobs",
    params(("id" = String, Path, description = "The job's id")),
    responses(
        (status = 200, description = "The job", body = Job,
            links(
                ("getMission" = (operation_id = "getMission", parameters(("id" = "$response.body#/mission")),
                    description = "The job's mission")),
                ("jobResult" = (operation_id = "jobResult", parameters(("id" = "$response.body#/id")),
                    description = "Its result, once done")),
                ("jobEvents" = (operation_id = "jobEvents", parameters(("id" = "$response.body#/id")),
                    description = "Its progress as Server-Sent Events"))
            )),
        Unauthorized,
        NoSuchJob,
        StorageUnavailable,
    )
)]
pub(super) async fn get_job(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
) -> ApiResult<Json<Job>> {
    let j = state
        .db(move |st| st.job(&owner, &id))
        .await?
        .ok_or_else(|| AppError::not_found("job"))?;
    Ok(Json(Job::from(&j)))
}

/// Cancel a queued or running job. The job stays, in state `cancelled`
/// (this is a cancellation, not a deletion: `GET` still answers it).
#[utoipa::path(
    delete,
    path = "/jobs/{id}",
    operation_id = "cancelJob",
    tag = "jobs",
    params(("id" = String, Path, description = "The job's id")),
    responses(
        (status = 202, description = "Cancelled", body = JobQueued),
        Unauthorized,
        NoSuchJob,
        (status = 409, description = "The job has already ended", body = ErrorBody),
        StorageUnavailable,
    )
)]
pub(super) async fn delete_job(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
) -> ApiResult<(StatusCode, Json<JobQueued>)> {
    let (o, i) = (owner.clone(), id.clone());
    let cancelled = state.db(move |st| st.cancel_job(&o, &i, now_ms())).await?;
    state.workers.changed(&id);
    match cancelled {
        None => Err(AppError::not_found("job")),
        Some(s) if s.is_active() => Ok((
            StatusCode::ACCEPTED,
            Json(JobQueued {
                id,
                state: JobState::Cancelled,
            }),
        )),
        Some(s) => Err(AppError::new(
            StatusCode::CONFLICT,
            "job_ended",
            format!("the job has already ended ({s})"),
        )),
    }
}

/// The job's progress as Server-Sent Events: a `progress` event (a `Job`
/// object) whenever it changes, then one `end` event with the final state,
/// and the stream closes.
#[utoipa::path(
    get,
    path = "/jobs/{id}/events",
    operation_id = "jobEvents",
    tag = "jobs",
    params(("id" = String, Path, description = "The job's id")),
    responses(
        (status = 200, description = "text/event-stream: events `progress` and `end`, each data a Job object",
            content_type = "text/event-stream", body = JobEvent),
        Unauthorized,
        NoSuchJob,
        StorageUnavailable,
    )
)]
pub(super) async fn job_events(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
) -> ApiResult<Sse<impl Stream<Item = Result<Event, Infallible>>>> {
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
                    let ev = Event::from(JobEvent {
                        event: JobEventName::End,
                        data: json!({"id": id, "state": "deleted"}).to_string(),
                    });
                    return Some((Ok(ev), (state, owner, id, last, true, rx)));
                };
                let text = job_json(&job);
                let terminal = job.state.is_terminal();
                if text != last {
                    let ev = Event::from(JobEvent {
                        event: if terminal {
                            JobEventName::End
                        } else {
                            JobEventName::Progress
                        },
                        data: text.clone(),
                    });
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

/// The result's formats.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum ResultFormat {
    /// The result JSON (`nvector-result/1`; `nvector-tdoa-result/1` for a
    /// TDOA job, whose result is JSON only).
    Json,
    /// The trajectory as CSV: `step,x_lo,x_hi,y_lo,y_hi[,z_lo,z_hi]` (a
    /// TDOA job: its pulse boxes, `pulse,x_lo,...,z_hi`).
    Csv,
    /// The figure (SVG; a TDOA job: receivers, pulse boxes by proved
    /// group, emitter regions and truth in the x-y plane).
    Svg,
}

/// The query of `GET /jobs/{id}/result`.
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub(super) struct ResultQuery {
    /// `json` (default), `csv` or `svg`.
    #[param(value_type = Option<ResultFormat>)]
    format: Option<String>,
}

/// The 409 of a result asked for before the job is done: it may still
/// come (queued, running), or never (failed, cancelled).
fn not_done(state: JobState) -> AppError {
    let message = match state {
        JobState::Failed | JobState::Cancelled => {
            format!("the job is {state}: it has no result and will have none")
        }
        _ => format!("the job is {state}, no result yet"),
    };
    AppError::new(StatusCode::CONFLICT, "not_done", message)
}

/// The result of a finished job.
#[utoipa::path(
    get,
    path = "/jobs/{id}/result",
    operation_id = "jobResult",
    tag = "jobs",
    params(("id" = String, Path, description = "The job's id"), ResultQuery),
    responses(
        (status = 200, description = "The result",
            content(
                (SlamResult = "application/json"),
                (String = "text/csv"),
                (String = "image/svg+xml")
            )),
        (status = 400, description = "Unknown `format`", body = ErrorBody),
        Unauthorized,
        NoSuchJob,
        (status = 409, description = "The job is not done", body = ErrorBody),
        StorageUnavailable,
    )
)]
pub(super) async fn job_result(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Path(id): Path<String>,
    q: Result<Query<ResultQuery>, axum::extract::rejection::QueryRejection>,
) -> ApiResult<Response> {
    let Query(q) =
        q.map_err(|e| AppError::new(StatusCode::BAD_REQUEST, "invalid_query", e.body_text()))?;
    let job = {
        let (o, i) = (owner.clone(), id.clone());
        state
            .db(move |st| st.job(&o, &i))
            .await?
            .ok_or_else(|| AppError::not_found("job"))?
    };
    if job.state != JobState::Done {
        return Err(not_done(job.state));
    }
    let text = {
        let (o, i) = (owner.clone(), id.clone());
        state
            .db(move |st| st.result(&o, &i))
            .await?
            .ok_or_else(|| AppError::not_found("result"))?
    };
    let format = q.format.as_deref().unwrap_or("json");
    if JobKind::of(&job.mission) == JobKind::Tdoa && matches!(format, "csv" | "svg") {
        let v = parse_json_value(text.as_bytes())?;
        if format == "csv" {
            let csv = super::result_files::pulses_csv(&v).map_err(unreadable)?;
            return Ok(([(header::CONTENT_TYPE, "text/csv")], csv).into_response());
        }
        let problem_id = job.mission.clone();
        let problem = state
            .db(move |st| st.mission_body(&owner, &problem_id))
            .await?
            .and_then(|b| serde_json::from_str(&b).ok())
            .unwrap_or(Value::Null);
        let svg = super::result_files::tdoa_svg(&v, &problem);
        return Ok(([(header::CONTENT_TYPE, "image/svg+xml")], svg).into_response());
    }
    match format {
        "json" => Ok(([(header::CONTENT_TYPE, "application/json")], text).into_response()),
        "csv" | "svg" => {
            let v = parse_json_value(text.as_bytes())?;
            // The mission: its `dt` (the CSV's times), its truth (the figure).
            let mission_id = job.mission.clone();
            let mission = state
                .db(move |st| st.mission_body(&owner, &mission_id))
                .await?
                .and_then(|b| serde_json::from_str(&b).ok())
                .unwrap_or(Value::Null);
            Ok(if format == "csv" {
                let result = nvector_core::format::result::read_value(&v).map_err(unreadable)?;
                (
                    [(header::CONTENT_TYPE, "text/csv")],
                    super::result_files::trajectory_csv(&result, &mission),
                )
                    .into_response()
            } else {
                (
                    [(header::CONTENT_TYPE, "image/svg+xml")],
                    crate::render::render_svg(&v, &mission),
                )
                    .into_response()
            })
        }
        other => Err(AppError::new(
            StatusCode::BAD_REQUEST,
            "invalid_query",
            format!("unknown format '{other}' (json, csv or svg)"),
        )
        .at("format")),
    }
}

/// A stored result that does not read as its format: the service's own
/// fault (it wrote the result), named.
fn unreadable(e: nvector_core::InputError) -> AppError {
    AppError::new(
        StatusCode::INTERNAL_SERVER_ERROR,
        "internal",
        format!("the stored result does not read: {e}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The word a job's `error_code` serializes to is the word the workers
    /// store, and every stored word reads back as its code (a code whose
    /// serde name and stored word differed would vanish from jobs).
    #[test]
    fn error_codes_round_trip() {
        for c in JobErrorCode::ALL {
            assert_eq!(serde_json::to_value(c).unwrap(), json!(c.as_str()));
            assert_eq!(JobErrorCode::parse(c.as_str()), Some(c));
        }
        assert_eq!(JobErrorCode::parse("killed"), None);
    }
}
