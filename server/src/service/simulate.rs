//! `POST /api/v1/simulate`: a simulated mission, returned and stored.
//!
//! Every field but `scenario` is optional, and `null` means absent (as in
//! the mission format). `layout`, `range_only` and `false_detections` are
//! for the paper scenario only (with `auv` only their defaults pass), as in
//! `nvector simulate`.

use super::error::{parse_json, ApiResult, AppError};
use super::formats::{ErrorBody, Mission};
use super::missions::{mission_summary, store_mission, MissionSummary};
use super::state::{owner, AppState};
use axum::body::Bytes;
use axum::extract::State;
use axum::http::{HeaderMap, StatusCode};
use axum::Json;
use nvector_core::json::{check_fields, integer, number, object};
use nvector_core::slam::simulate::{self, simulate, Layout, Scenario, SimulateOptions};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use utoipa::ToSchema;

/// The scenarios' default steps (core's `simulate`).
const PAPER_STEPS: u64 = 10_000;
const AUV_STEPS: u64 = 60_000;
/// Most landmarks of a simulated paper mission (core's limit, as
/// `nvector simulate`).
const MAX_LANDMARKS: u64 = simulate::MAX_LANDMARKS as u64;
/// Most false detections (core's limit, as `nvector simulate`: each costs
/// up to 1000 draws).
const MAX_FALSE_DETECTIONS: u64 = simulate::MAX_FALSE_DETECTIONS as u64;

/// The landmark layouts of the paper scenario.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum LayoutName {
    /// 10 m apart along x (the paper's Figure 9; the default).
    Line,
    /// Evenly on a circle around the start.
    Ring,
    /// Uniformly in a square, at least 8 m apart.
    Random,
}

/// The only layout of the auv scenario.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum LineLayout {
    /// The default.
    Line,
}

/// A simulation of the paper's experiment.
#[derive(Deserialize, ToSchema)]
#[allow(dead_code)] // Described, not built: core's parser reads the body.
#[serde(deny_unknown_fields)]
pub struct PaperSimulation {
    /// `"paper"`.
    #[schema(inline)]
    pub scenario: PaperName,
    /// The seed (default 1).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 18446744073709551615u64)]
    pub seed: Option<u64>,
    /// Steps (default 10,000, at most this service's limit; below 2 reads
    /// as 2).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 2000000)]
    pub steps: Option<u64>,
    /// Landmarks (default 4; 0 reads as 1).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 64)]
    pub landmarks: Option<u64>,
    /// Write the true matching as operator `landmark` fields (default
    /// false).
    #[serde(default)]
    pub operator: Option<bool>,
    /// Scale of the sensor noise bounds (default 1).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 100)]
    pub noise: Option<f64>,
    /// Landmark layout (default `line`).
    #[serde(default)]
    pub layout: Option<LayoutName>,
    /// Range-only detections with a rough landmark region instead of a
    /// bearing (the paper's P''; default false).
    #[serde(default)]
    pub range_only: Option<bool>,
    /// Extra detections of no landmark (`null` in truth.matching,
    /// `max_outliers` set; default 0; at most this service's limit on
    /// detections). Fewer are drawn when the mission would hold more
    /// detections in all than that limit: the mission's `max_outliers` says
    /// how many.
    #[serde(default)]
    #[schema(minimum = 0, maximum = 100000)]
    pub false_detections: Option<u64>,
}

/// `"paper"`.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum PaperName {
    /// The paper scenario.
    Paper,
}

/// `"auv"`.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum AuvName {
    /// The AUV scenario.
    Auv,
}

/// A simulated AUV survey (the paper-only options at their defaults).
#[derive(Deserialize, ToSchema)]
#[allow(dead_code)] // Described, not built: core's parser reads the body.
#[serde(deny_unknown_fields)]
pub struct AuvSimulation {
    /// `"auv"`.
    #[schema(inline)]
    pub scenario: AuvName,
    /// The seed (default 1).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 18446744073709551615u64)]
    pub seed: Option<u64>,
    /// Steps (default 60,000, at most this service's limit; below 2 reads
    /// as 2).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 2000000)]
    pub steps: Option<u64>,
    /// Ignored: the survey always has its 6 seamarks (0..=64 accepted).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 64)]
    pub landmarks: Option<u64>,
    /// Write the true matching as operator `landmark` fields.
    #[serde(default)]
    pub operator: Option<bool>,
    /// Scale of the sensor noise bounds (default 1).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 100)]
    pub noise: Option<f64>,
    /// Only the default, `line`.
    #[serde(default)]
    #[schema(inline)]
    pub layout: Option<LineLayout>,
    /// Only the default, false.
    #[serde(default)]
    pub range_only: Option<bool>,
    /// Only the default, 0.
    #[serde(default)]
    #[schema(minimum = 0, maximum = 0)]
    pub false_detections: Option<u64>,
}

/// A simulation request: the paper's experiment or an AUV survey.
#[derive(Deserialize, ToSchema)]
#[allow(dead_code)] // Described, not built: core's parser reads the body.
#[serde(untagged)]
#[schema(example = json!({"scenario": "paper", "seed": 3, "steps": 2000, "operator": true}))]
pub enum SimulateRequest {
    /// `"scenario": "paper"`.
    Paper(PaperSimulation),
    /// `"scenario": "auv"`.
    Auv(AuvSimulation),
}

/// The stored simulated mission.
#[derive(Serialize, ToSchema)]
pub struct Simulated {
    /// The stored mission's summary.
    #[serde(flatten)]
    pub summary: MissionSummary,
    /// The mission itself, with its truth.
    #[schema(value_type = Mission)]
    pub mission: Value,
}

fn invalid(path: &str, message: impl Into<String>) -> AppError {
    AppError::new(StatusCode::UNPROCESSABLE_ENTITY, "invalid_request", message).at(path)
}

/// A present, non-null field.
fn field<'a>(obj: &'a Map<String, Value>, k: &str) -> Option<&'a Value> {
    obj.get(k).filter(|v| !v.is_null())
}

/// The options of a request; errors name the field.
fn options(v: &Value, max_steps: u64, max_detections: u64) -> ApiResult<SimulateOptions> {
    let bad = |e| AppError::bad("invalid_request", e);
    let obj = object(v, "").map_err(bad)?;
    check_fields(
        obj,
        &[
            "scenario",
            "seed",
            "steps",
            "landmarks",
            "operator",
            "noise",
            "layout",
            "range_only",
            "false_detections",
        ],
        "",
    )
    .map_err(bad)?;
    let scenario = match obj
        .get("scenario")
        .and_then(Value::as_str)
        .map(Scenario::parse)
    {
        Some(Some(s)) => s,
        _ => return Err(invalid("scenario", "scenario must be \"paper\" or \"auv\"")),
    };
    let int = |k: &str, max: u64| -> ApiResult<Option<u64>> {
        field(obj, k)
            .map(|x| integer(x, k, max).map_err(bad))
            .transpose()
    };
    let boolean = |k: &str| -> ApiResult<bool> {
        match field(obj, k) {
            None => Ok(false),
            Some(Value::Bool(b)) => Ok(*b),
            Some(o) => Err(invalid(
                k,
                format!(
                    "expected true or false, found {}",
                    nvector_core::json::kind(o)
                ),
            )),
        }
    };
    let mut o = SimulateOptions::new(scenario, int("seed", u64::MAX)?.unwrap_or(1));
    // Absent: the scenario's default, at most this service's limit.
    let default_steps = match scenario {
        Scenario::Paper => PAPER_STEPS,
        _ => AUV_STEPS,
    };
    o.steps = Some(
        int("steps", max_steps)?
            .unwrap_or(default_steps.min(max_steps))
            .max(2) as usize,
    );
    o.landmarks = int("landmarks", MAX_LANDMARKS)?.map(|s| s.max(1) as usize);
    o.operator = boolean("operator")?;
    if let Some(x) = field(obj, "noise") {
        let n = number(x, "noise").map_err(bad)?;
        if !(0.0..=100.0).contains(&n) {
            return Err(invalid("noise", "noise must be in [0, 100]"));
        }
        o.noise = n;
    }
    if let Some(x) = field(obj, "layout") {
        o.layout = x.as_str().and_then(Layout::parse).ok_or_else(|| {
            invalid(
                "layout",
                format!("unknown layout {x} (expected line, ring or random)"),
            )
        })?;
    }
    o.range_only = boolean("range_only")?;
    o.false_detections =
        int("false_detections", MAX_FALSE_DETECTIONS.min(max_detections))?.unwrap_or(0) as usize;
    if scenario != Scenario::Paper {
        let (path, what) = if o.layout != Layout::Line {
            ("layout", "layout")
        } else if o.range_only {
            ("range_only", "range_only")
        } else if o.false_detections > 0 {
            ("false_detections", "false_detections")
        } else {
            return Ok(o);
        };
        return Err(invalid(
            path,
            format!("{what} applies to the paper scenario only"),
        ));
    }
    Ok(o)
}

/// A simulated mission, returned and stored.
#[utoipa::path(
    post,
    path = "/simulate",
    operation_id = "simulate",
    tag = "missions",
    request_body = SimulateRequest,
    responses(
        (status = 201, description = "The mission, stored (with its truth)", body = Simulated,
            links(
                ("getMission" = (operation_id = "getMission", parameters(("id" = "$response.body#/id")),
                    description = "The stored mission")),
                ("createJob" = (operation_id = "createJob", request_body = json!({"mission": "$response.body#/id"}),
                    description = "A SLAM job on it")),
                ("deleteMission" = (operation_id = "deleteMission", parameters(("id" = "$response.body#/id")),
                    description = "Delete it"))
            )),
        (status = 400, description = "Malformed JSON", body = ErrorBody),
        (status = 401, description = "Missing or unknown API key", body = ErrorBody),
        (status = 413, description = "Request body too large", body = ErrorBody),
        (status = 422, description = "Invalid field, with its path", body = ErrorBody),
        (status = 503, description = "Storage unavailable", body = ErrorBody),
    )
)]
pub(super) async fn post_simulate(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Bytes,
) -> ApiResult<(StatusCode, Json<Simulated>)> {
    let owner = owner(&state, &headers)?;
    let v = parse_json(&body)?;
    let o = options(
        &v,
        state.config.max_steps as u64,
        state.config.max_detections as u64,
    )?;
    let max_detections = state.config.max_detections;
    let mission = tokio::task::spawn_blocking(move || {
        let mission = simulate(&o);
        let count = mission["detections"].as_array().map_or(0, Vec::len);
        if count > max_detections && o.false_detections > 0 {
            // The true detections do not depend on the false ones (drawn
            // from a second stream): fewer false ones fit the limit.
            let fewer = SimulateOptions {
                false_detections: o.false_detections.saturating_sub(count - max_detections),
                ..o
            };
            simulate(&fewer)
        } else {
            mission
        }
    })
    .await
    .map_err(|_| {
        AppError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            "internal",
            "simulation task failed",
        )
    })?;
    let count = mission["detections"].as_array().map_or(0, Vec::len);
    if count > max_detections {
        return Err(AppError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            "too_large",
            format!(
                "the simulated mission has {count} detections, above this service's limit of {max_detections}"
            ),
        )
        .at("landmarks"));
    }
    let (id, m) = store_mission(&state, &owner, &mission, false).await?;
    Ok((
        StatusCode::CREATED,
        Json(Simulated {
            summary: mission_summary(&id, &m),
            mission,
        }),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn err(v: Value) -> String {
        let Err(e) = options(&v, 1000, 100_000) else {
            panic!("accepted: {v}");
        };
        format!("{}: {}", e.path, e.message)
    }

    /// Null is absent; a non-boolean `operator` is refused (it used to
    /// read as false).
    #[test]
    fn nulls_are_absent_and_types_are_checked() {
        let o = options(
            &json!({"scenario": "paper", "steps": null, "seed": null, "noise": null, "operator": null}),
            1000,
            100_000,
        )
        .unwrap();
        assert_eq!(
            (o.steps, o.seed, o.noise, o.operator),
            (Some(1000), 1, 1.0, false)
        );
        let o = options(&json!({"scenario": "auv", "seed": 5.0}), 2_000_000, 100_000).unwrap();
        assert_eq!((o.steps, o.seed), (Some(60_000), 5));
        assert_eq!(
            err(json!({"scenario": "paper", "operator": "yes"})),
            "operator: expected true or false, found a string"
        );
        assert!(err(json!({"scenario": "paper", "steps": 1001})).starts_with("steps:"));
    }

    #[test]
    fn paper_only_options() {
        let o = options(
            &json!({"scenario": "paper", "layout": "ring", "range_only": true, "false_detections": 3}),
            1000,
            100_000,
        )
        .unwrap();
        assert_eq!(
            (o.layout, o.range_only, o.false_detections),
            (Layout::Ring, true, 3)
        );
        assert!(options(
            &json!({"scenario": "auv", "layout": "line", "range_only": false, "false_detections": 0}),
            1000,
            100_000
        )
        .is_ok());
        assert_eq!(
            err(json!({"scenario": "auv", "layout": "ring"})),
            "layout: layout applies to the paper scenario only"
        );
        assert!(
            err(json!({"scenario": "paper", "layout": "spiral"})).starts_with("layout: unknown")
        );
        assert!(
            err(json!({"scenario": "paper", "false_detections": 100001}))
                .starts_with("false_detections:")
        );
        // Bounded by the service's limit on detections.
        assert!(options(
            &json!({"scenario": "paper", "false_detections": 51}),
            1000,
            50
        )
        .is_err());
    }
}
