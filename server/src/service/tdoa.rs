//! TDOA passive location as jobs: `POST /api/v1/tdoa` stores a problem
//! (`nvector-tdoa/1`, read and validated by core's `TdoaProblem`) and queues
//! a job on it, run by the same workers, queue, limits, owner, states,
//! cancellation, progress and errors as SLAM jobs (`jobs.rs`); the job's
//! result (`GET /jobs/{id}/result`) is `nvector-tdoa-result/1`.
//!
//! The problem is stored beside the missions with an id `t-...` (which is
//! how a worker knows a job's kind: `job_runner::JobKind::of`), readable at
//! `GET /missions/{id}` and deleted (with its jobs) by `DELETE
//! /missions/{id}`, but not listed by `GET /missions`. Its queue cost is
//! pulses x arrivals, as a mission's is steps x detections.

use super::error::ErrorBody;
use super::error::{parse_json, ApiResult, AppError};
use super::error::{QueueFull, StorageUnavailable, Unauthorized};
use super::jobs::{contractor_names, enqueue, new_job, or_list};
use super::state::{AppState, Owner};
use super::store::{JobState, MissionRow};
use super::worker::now_ms;
use axum::body::Bytes;
use axum::extract::{FromRequest, Query, Request, State};
use axum::http::{header, StatusCode};
use axum::Json;
use nvector_core::format::tdoa::TdoaDoc;
use nvector_core::slam::types::Association;
use nvector_core::tdoa::TdoaProblem;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::{IntoParams, ToSchema};

/// The options of a TDOA job (query parameters; all optional).
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
pub(super) struct TdoaQuery {
    /// The atmost_nvector contractor over the pulses' positions, or `none`
    /// (the operator's matching only); default `best`.
    #[param(value_type = Option<Association>)]
    contractor: Option<String>,
    /// The round cap (default 8; at most 1000).
    #[param(value_type = Option<u32>, minimum = 1, maximum = 1000)]
    max_rounds: Option<String>,
    /// The time limit in seconds (default and largest: this service's job
    /// time limit); the rounds stop there and the (sound, wider) result is
    /// kept with `error_code` `time_limit`.
    #[param(value_type = Option<f64>, exclusive_minimum = 0, maximum = 300)]
    time_limit_s: Option<String>,
}

fn invalid_query(name: &str, message: String) -> AppError {
    AppError::new(StatusCode::BAD_REQUEST, "invalid_query", message).at(name)
}

impl TdoaQuery {
    fn contractor(&self) -> ApiResult<String> {
        match self.contractor.as_deref() {
            None => Ok("best".into()),
            Some(s) if Association::parse(s).is_some() => Ok(s.into()),
            Some(s) => Err(invalid_query(
                "contractor",
                format!(
                    "unknown contractor '{s}' (expected {})",
                    or_list(&contractor_names())
                ),
            )),
        }
    }

    fn max_rounds(&self) -> ApiResult<i64> {
        match self.max_rounds.as_deref() {
            None => Ok(8),
            Some(s) => match s.parse::<i64>() {
                Ok(n) if (1..=1000).contains(&n) => Ok(n),
                _ => Err(invalid_query(
                    "max_rounds",
                    format!("max_rounds must be an integer in 1..=1000, found '{s}'"),
                )),
            },
        }
    }

    fn time_limit_s(&self, limit: f64) -> ApiResult<f64> {
        match self.time_limit_s.as_deref() {
            None => Ok(limit),
            Some(s) => match s.parse::<f64>() {
                Ok(t) if t > 0.0 && t <= limit => Ok(t),
                _ => Err(invalid_query(
                    "time_limit_s",
                    format!("time_limit_s must be a number in (0, {limit}], found '{s}'"),
                )),
            },
        }
    }
}

/// A queued TDOA job.
#[derive(Serialize, ToSchema)]
pub struct TdoaQueued {
    /// The job's id (`j-...`): follow it at `/jobs/{id}`, its result at
    /// `/jobs/{id}/result`.
    pub id: String,
    /// `queued`.
    pub state: JobState,
    /// The stored problem's id (`t-...`), the job's `mission`.
    pub problem: String,
    /// Its number of pulses.
    pub pulses: u64,
    /// Its number of arrivals.
    pub arrivals: u64,
}

/// Validates a problem: core's parser (422 naming the JSON path), then this
/// service's limit on arrivals (413), the TDOA counterpart of detections.
fn check_problem(v: &Value, max_arrivals: usize) -> ApiResult<TdoaProblem> {
    let p = TdoaProblem::from_value(v).map_err(|e| AppError::bad("invalid_tdoa", e))?;
    let arrivals: usize = p.pulses.iter().map(|k| k.arrivals.len()).sum();
    if arrivals > max_arrivals {
        return Err(AppError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "too_large",
            format!("{arrivals} arrivals is above this service's limit of {max_arrivals}"),
        )
        .at("pulses"));
    }
    Ok(p)
}

/// Store a TDOA problem and queue a job on it.
#[utoipa::path(
    post,
    path = "/tdoa",
    operation_id = "createTdoaJob",
    tag = "tdoa",
    params(TdoaQuery),
    request_body(
        description = "The problem (docs/formats.md, \"TDOA passive location\")",
        content((TdoaDoc = "application/json"))
    ),
    responses(
        (status = 202, description = "Stored and queued", body = TdoaQueued,
            links(
                ("getJob" = (operation_id = "getJob", parameters(("id" = "$response.body#/id")),
                    description = "The job and its progress")),
                ("jobResult" = (operation_id = "jobResult", parameters(("id" = "$response.body#/id")),
                    description = "Its nvector-tdoa-result/1, once done")),
                ("cancelJob" = (operation_id = "cancelJob", parameters(("id" = "$response.body#/id")),
                    description = "Cancel it")),
                ("getMission" = (operation_id = "getMission", parameters(("id" = "$response.body#/problem")),
                    description = "The stored problem"))
            )),
        (status = 400, description = "Malformed JSON, or a bad query parameter", body = ErrorBody),
        Unauthorized,
        (status = 413, description = "Body or arrivals above this service's limits", body = ErrorBody),
        (status = 415, description = "Not JSON", body = ErrorBody),
        (status = 422, description = "Invalid problem, with the JSON path", body = ErrorBody),
        QueueFull,
        StorageUnavailable,
    )
)]
pub(super) async fn post_tdoa(
    State(state): State<AppState>,
    Owner(owner): Owner,
    query: Result<Query<TdoaQuery>, axum::extract::rejection::QueryRejection>,
    req: Request,
) -> ApiResult<(StatusCode, Json<TdoaQueued>)> {
    let Query(q) = query
        .map_err(|e| AppError::new(StatusCode::BAD_REQUEST, "invalid_query", e.body_text()))?;
    let contractor = q.contractor()?;
    let max_rounds = q.max_rounds()?;
    let time_limit_s = q.time_limit_s(state.config.job_time_limit_s)?;
    let ctype = req
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !(ctype.is_empty() || ctype.starts_with("application/json")) {
        return Err(AppError::new(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            "unsupported_media_type",
            format!("expected application/json, found {ctype}"),
        ));
    }
    let bytes = Bytes::from_request(req, &state).await.map_err(|e| {
        AppError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "body_too_large",
            e.body_text(),
        )
    })?;
    let v = parse_json(&bytes)?;
    let p = check_problem(&v, state.config.max_detections)?;
    let arrivals: usize = p.pulses.iter().map(|k| k.arrivals.len()).sum();
    let id = format!("t-{}", uuid::Uuid::new_v4().simple());
    let (pulses, body) = (p.pulses.len() as u64, v.to_string());
    let row = MissionRow {
        id: id.clone(),
        name: p.name.clone(),
        steps: p.pulses.len() as i64,
        detections: arrivals as i64,
        created: now_ms(),
        bytes: body.len() as i64,
    };
    drop((p, v));
    {
        let (owner, row) = (owner.clone(), row);
        state
            .db(move |st| st.insert_mission(&owner, &row, &body))
            .await?;
    }
    let job = new_job(id.clone(), contractor, max_rounds, time_limit_s);
    let job_id = job.id.clone();
    if let Err(e) = enqueue(&state, owner.clone(), job).await {
        // Not queued (queue full): the problem goes too.
        let (o, i) = (owner, id.clone());
        let _ = state.db(move |st| st.delete_mission(&o, &i)).await;
        return Err(e);
    }
    Ok((
        StatusCode::ACCEPTED,
        Json(TdoaQueued {
            id: job_id,
            state: JobState::Queued,
            problem: id,
            pulses,
            arrivals: arrivals as u64,
        }),
    ))
}
