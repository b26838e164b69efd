//! The SLAM demo's part of the facade: simulate a mission and read one
//! (JSON, validated as every front end does) into its binary form
//! (feature `simulate`, the simulators' module), and run a binary mission
//! to the fixpoint (feature `slam`, the solver's module, which has no JSON
//! reader: within the aim of 160,000 bytes of brotli; docs/journal/benchmarks-2026-11.md, "The
//! page's wasm transfer").

#[cfg(feature = "simulate")]
use crate::parse;
use crate::{into_error, Nvector};
#[cfg(feature = "simulate")]
use nvector_core::format::{self, Object};
#[cfg(feature = "simulate")]
use nvector_core::slam::simulate::{simulate, SimulateLimits, SimulateRequest};
#[cfg(feature = "slam")]
use nvector_core::slam::solve::solve;
#[cfg(feature = "slam")]
use nvector_core::slam::types::{Association, Progress, SolveOptions};
#[cfg(any(feature = "slam", feature = "simulate"))]
use nvector_core::slam::{codec, mission::Mission};
use nvector_core::InputError;
use serde_json::Value;
#[cfg(feature = "slam")]
use std::sync::atomic::AtomicBool;
use wasm_bindgen::prelude::*;

#[cfg(feature = "slam")]
/// Runs a validated mission to the fixpoint with a contractor name
/// (`none`, `nvalue`, `projection`, `independent`, `shapes`, `best`).
pub fn run_model(
    m: &Mission,
    contractor: &str,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Value, InputError> {
    let association = Association::parse(contractor).ok_or_else(|| {
        InputError::new("contractor", format!("unknown contractor \"{contractor}\""))
    })?;
    let options = SolveOptions {
        association,
        ..SolveOptions::default()
    };
    Ok(solve(m, &options, progress, &AtomicBool::new(false)))
}

#[cfg(all(feature = "slam", feature = "simulate"))]
/// Runs a mission (JSON) as the page does: read and validated
/// ([`read_mission`], the simulators' module), handed over as its binary
/// form, run ([`run_model`] of [`codec::decode`], the solver's module).
pub fn run_mission(
    mission: &Value,
    contractor: &str,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Value, InputError> {
    run_model(
        &codec::decode(&read_mission(mission)?)?,
        contractor,
        progress,
    )
}

#[cfg(feature = "simulate")]
/// A mission (JSON) read and validated as every front end does
/// ([`Mission::from_value`]: the same errors, with JSON paths), in the
/// binary form the solver's module reads ([`codec::encode`]).
pub fn read_mission(mission: &Value) -> Result<Vec<u8>, InputError> {
    Ok(codec::encode(&Mission::from_value(mission)?))
}

#[cfg(feature = "simulate")]
/// Simulation options from JSON: `{"scenario", "seed", "steps",
/// "landmarks", "noise", "operator", "layout", "range_only",
/// "false_detections"}`, read and checked by core as every front end does
/// (core's limits; an option out of range is an error naming it).
/// `"scenario": "woods"` is core's woods generator (an odometry2d robot
/// among identical landmarks, with scans).
pub fn simulate_json(options: &Value) -> Result<Value, InputError> {
    let Object(request) = format::from_value::<Object<SimulateRequest>>(options)?;
    Ok(simulate(&request.options(SimulateLimits::CORE)?))
}

#[cfg(feature = "simulate")]
#[wasm_bindgen]
impl Nvector {
    /// A simulated mission (JSON options -> mission JSON).
    pub fn simulate(&self, options: &str) -> Result<String, JsError> {
        simulate_json(&parse(options)?)
            .map(|v| v.to_string())
            .map_err(into_error)
    }

    /// A mission (JSON text) read and validated, in the binary form `run`
    /// takes (errors name the JSON path).
    #[wasm_bindgen(js_name = readMission)]
    pub fn read_mission(&self, mission: &str) -> Result<Vec<u8>, JsError> {
        read_mission(&parse(mission)?).map_err(into_error)
    }
}

#[cfg(feature = "slam")]
#[wasm_bindgen]
impl Nvector {
    /// Runs a mission given in the binary form of `readMission` (the
    /// simulators' module); `progress(round, max_diameter, fraction)` is
    /// called after each round.
    pub fn run(
        &self,
        mission: &[u8],
        contractor: &str,
        progress: &js_sys::Function,
    ) -> Result<String, JsError> {
        let mut cb = |p: &Progress| {
            let _ = progress.call3(
                &JsValue::NULL,
                &JsValue::from(p.round),
                &JsValue::from(p.max_trajectory_diameter),
                &JsValue::from(p.fraction),
            );
        };
        codec::decode(mission)
            .and_then(|m| run_model(&m, contractor, &mut cb))
            .map(|v| v.to_string())
            .map_err(into_error)
    }
}
