//! `POST /api/v1/simulate`: a simulated mission, returned and stored.
//!
//! Every field but `scenario` is optional, and `null` means absent (as in
//! the mission format). `layout` and `range_only` are for the paper
//! scenario only (with `auv` and `woods` only their defaults pass),
//! `false_detections` for paper and woods, `noise` for paper and auv, as in
//! `nvector simulate`. A woods
//! request whose mission could hold more detections than this service's
//! limit is refused before it is simulated (413).

use super::error::{ApiResult, AppError, Body, RequestBody};
use super::error::{BodyTooLarge, InvalidField, MalformedJson, StorageUnavailable, Unauthorized};
use super::missions::{mission_summary, store_mission, MissionSummary};
use super::state::{AppState, Owner};
use axum::extract::State;
use axum::http::StatusCode;
use axum::Json;
use nvector_core::format::mission_doc::MissionDoc as Mission;
use nvector_core::slam::simulate::odometry_scenario as woods;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest as Options};
use serde::Serialize;
use serde_json::Value;
use utoipa::ToSchema;

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

// The body is read as core's one simulation request type, whose schema
// (core/src/slam/simulate/schema.rs) the document gives.
impl RequestBody for Options {
    const CODE: &'static str = "invalid_request";
}

/// A simulated mission, returned and stored.
#[utoipa::path(
    post,
    path = "/simulate",
    operation_id = "simulate",
    tag = "missions",
    request_body = Options,
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
        MalformedJson,
        Unauthorized,
        BodyTooLarge,
        InvalidField,
        StorageUnavailable,
    )
)]
pub(super) async fn post_simulate(
    State(state): State<AppState>,
    Owner(owner): Owner,
    Body(request): Body<Options>,
) -> ApiResult<(StatusCode, Json<Simulated>)> {
    let limits = SimulateLimits {
        max_steps: state.config.max_steps as u64,
        max_false_detections: state.config.max_detections as u64,
    };
    // The API names its scenario (its document marks `scenario` required);
    // the CLI and the page default to the paper's.
    if request.scenario.is_none() {
        let e = nvector_core::InputError::new("scenario", "missing field `scenario`");
        return Err(AppError::bad("invalid_request", e));
    }
    let o = request
        .options(limits)
        .map_err(|e| AppError::bad("invalid_request", e))?;
    let max_detections = state.config.max_detections;
    woods_fits(&o, max_detections)?;
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

/// A woods request whose mission could hold more detections than the
/// service's limit is refused before the simulation allocates anything of
/// that size (each scan sees each landmark at most once).
fn woods_fits(o: &SimulateOptions, max_detections: usize) -> ApiResult<()> {
    if o.scenario != Scenario::Woods {
        return Ok(());
    }
    let (steps, landmarks) = (
        o.steps.unwrap_or(woods::WOODS_STEPS),
        o.landmarks.unwrap_or(woods::WOODS_LANDMARKS),
    );
    let bound = woods::max_detections(steps, landmarks);
    if bound <= max_detections {
        return Ok(());
    }
    Err(AppError::new(
        StatusCode::PAYLOAD_TOO_LARGE,
        "too_large",
        format!(
            "a woods mission of {steps} steps among {landmarks} landmarks may hold {bound} detections, above this service's limit of {max_detections}: ask for fewer steps or landmarks"
        ),
    )
    .at("steps"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nvector_core::format::{from_value, Object};
    use nvector_core::slam::simulate::Layout;
    use nvector_core::InputError;
    use serde_json::json;

    /// The options of a body under this service's limits, as the handler
    /// reads them.
    fn options(
        v: &Value,
        max_steps: u64,
        max_detections: u64,
    ) -> Result<SimulateOptions, InputError> {
        from_value::<Object<Options>>(v)?.0.options(SimulateLimits {
            max_steps,
            max_false_detections: max_detections,
        })
    }

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
            "operator: expected a boolean, found a string"
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
        // False detections: paper and woods, not auv.
        let o = options(
            &json!({"scenario": "woods", "false_detections": 4}),
            1000,
            100_000,
        )
        .unwrap();
        assert_eq!((o.scenario, o.false_detections), (Scenario::Woods, 4));
        assert_eq!(
            err(json!({"scenario": "auv", "false_detections": 1})),
            "false_detections: false_detections applies to the paper and woods scenarios only"
        );
        assert!(options(
            &json!({"scenario": "woods", "false_detections": 51}),
            1000,
            50
        )
        .is_err());
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
