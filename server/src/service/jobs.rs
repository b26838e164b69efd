//! Jobs, the HTTP side: `POST /api/v1/jobs` queues a SLAM job, `GET` and
//! `DELETE /api/v1/jobs/{id}` read and cancel it, `/events` streams its
//! progress as Server-Sent Events, `/result` returns its result (JSON, CSV
//! or SVG). The workers that run jobs are in `worker.rs`.

use super::error::{parse_json, ApiResult, AppError};
use super::state::{owner, AppState};
use super::store::JobRow;
use super::worker::now_ms;
use axum::body::Bytes;
use axum::extract::{Path, Query, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::Json;
use futures_util::stream::{self, Stream};
use nvector_core::slam::propagator::Association;
use serde_json::{json, Value};
use std::convert::Infallible;
use std::time::Duration;

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

pub(super) async fn post_job(
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

pub(super) async fn get_job(
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

pub(super) async fn delete_job(
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

pub(super) async fn job_events(
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
pub(super) struct ResultQuery {
    format: Option<String>,
}

pub(super) async fn job_result(
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
