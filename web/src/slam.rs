//! The SLAM demo's part of the facade: run a mission to the fixpoint
//! (feature `slam`, the solver module) and simulate one (feature
//! `simulate`, the simulators' module): two modules, a step toward each
//! within issue 17's 160,000 bytes of brotli (the solver's is not yet:
//! BENCHMARKS.md, "The page's wasm transfer").

use crate::{into_error, parse, Nvector};
#[cfg(feature = "simulate")]
use nvector_core::format::{self, Object};
#[cfg(feature = "slam")]
use nvector_core::slam::mission::Mission;
#[cfg(feature = "simulate")]
use nvector_core::slam::simulate::{simulate, SimulateLimits, SimulateRequest};
#[cfg(feature = "slam")]
use nvector_core::slam::solve::solve;
#[cfg(feature = "slam")]
use nvector_core::slam::types::{Association, Progress, SolveOptions};
use nvector_core::InputError;
use serde_json::Value;
#[cfg(feature = "slam")]
use std::sync::atomic::AtomicBool;
use wasm_bindgen::prelude::*;

#[cfg(feature = "slam")]
/// Runs a mission (JSON) to the fixpoint with a contractor name (`none`,
/// `nvalue`, `projection`, `independent`, `shapes`, `best`).
pub fn run_mission(
    mission: &Value,
    contractor: &str,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Value, InputError> {
    let m = Mission::from_value(mission)?;
    let association = Association::parse(contractor).ok_or_else(|| {
        InputError::new("contractor", format!("unknown contractor \"{contractor}\""))
    })?;
    let options = SolveOptions {
        association,
        ..SolveOptions::default()
    };
    Ok(solve(&m, &options, progress, &AtomicBool::new(false)))
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
}

#[cfg(feature = "slam")]
#[wasm_bindgen]
impl Nvector {
    /// Runs a mission; `progress(round, max_diameter, fraction)` is called
    /// after each round.
    pub fn run(
        &self,
        mission: &str,
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
        run_mission(&parse(mission)?, contractor, &mut cb)
            .map(|v| v.to_string())
            .map_err(into_error)
    }
}
