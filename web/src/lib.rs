//! Browser facade over nvector-core: one handle type whose methods take and
//! return the JSON formats of spec/formats.md as strings. Core errors become
//! JavaScript errors naming the JSON path; a panic is reported on the
//! console.

use nvector_core::format::{self, Object};
use nvector_core::nvector::contract::{response_json, ContractRequest};
use nvector_core::nvector::nvalue::{atmost_nvalue, NValue, NValueScratch};
use nvector_core::nvector::{atmost_nvector, Mode};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagator::{solve, Association, Progress, SolveOptions};
use nvector_core::slam::simulate::simulate;
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest};
use nvector_core::InputError;
use serde_json::{json, Value};
use std::sync::atomic::AtomicBool;
use wasm_bindgen::prelude::*;

/// The one error conversion: path and message of a core error.
fn into_error(e: InputError) -> JsError {
    JsError::new(&e.to_string())
}

fn parse(text: &str) -> Result<Value, JsError> {
    serde_json::from_str(text).map_err(|e| JsError::new(&format!("invalid JSON: {e}")))
}

/// A contraction with what the page draws: the response of
/// `nvector-contract-result/1` plus, per axis, the atmost_nvalue kernels of
/// the input boxes (`null` on an axis that needs fewer than n values).
pub fn contract_with_kernels(request: &Value) -> Result<Value, InputError> {
    let req = ContractRequest::from_value(request)?;
    let dim = req.boxes[0].dim();
    let mut kernels = Vec::with_capacity(dim);
    let mut scratch = NValueScratch::default();
    for a in 0..dim {
        let mut d: Vec<_> = req.boxes.iter().map(|b| b[a]).collect();
        match atmost_nvalue(req.n, &mut d, &mut scratch) {
            NValue::Kernels { .. } => kernels.push(json!(scratch
                .kernels
                .iter()
                .map(|&k| nvector_core::json::interval_to_json(k))
                .collect::<Vec<_>>())),
            NValue::Slack { m } | NValue::Infeasible { m } => {
                kernels.push(json!({"min_values": m}))
            }
        }
    }
    let mut boxes = req.boxes.clone();
    let outcome = atmost_nvector(req.n, &mut boxes, req.mode)?;
    let mut out = response_json(&boxes, &outcome);
    out["kernels"] = Value::Array(kernels);
    Ok(out)
}

/// Runs a mission (JSON) to the fixpoint with a contractor name (`none`,
/// `nvalue`, `projection`, `independent`, `shapes`, `best`).
pub fn run_mission(
    mission: &Value,
    contractor: &str,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Value, InputError> {
    let m = Mission::from_value(mission)?;
    m.unsupported()?;
    let association = Association::parse(contractor).ok_or_else(|| {
        InputError::new("contractor", format!("unknown contractor \"{contractor}\""))
    })?;
    let options = SolveOptions {
        association,
        ..SolveOptions::default()
    };
    Ok(solve(&m, &options, progress, &AtomicBool::new(false)))
}

/// Simulation options from JSON: `{"scenario", "seed", "steps",
/// "landmarks", "noise", "operator", "layout", "range_only",
/// "false_detections"}`, read and checked by core as every front end does
/// (core's limits; an option out of range is an error naming it).
pub fn simulate_json(options: &Value) -> Result<Value, InputError> {
    let Object(request) = format::from_value::<Object<SimulateRequest>>(options)?;
    Ok(simulate(&request.options(SimulateLimits::CORE)?))
}

/// The handle the page holds.
#[wasm_bindgen]
pub struct Nvector {}

#[wasm_bindgen]
impl Nvector {
    /// A handle; installs the panic hook.
    #[wasm_bindgen(constructor)]
    pub fn new() -> Nvector {
        console_error_panic_hook::set_once();
        Nvector {}
    }

    /// `nvector-contract/1` request -> response, with per-axis kernels.
    pub fn contract(&self, request: &str) -> Result<String, JsError> {
        contract_with_kernels(&parse(request)?)
            .map(|v| v.to_string())
            .map_err(into_error)
    }

    /// A simulated mission (JSON options -> mission JSON).
    pub fn simulate(&self, options: &str) -> Result<String, JsError> {
        simulate_json(&parse(options)?)
            .map(|v| v.to_string())
            .map_err(into_error)
    }

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

    /// The modes accepted by `contract`.
    pub fn modes(&self) -> String {
        json!([
            Mode::Nvalue.name(),
            Mode::Projection.name(),
            Mode::Independent.name(),
            Mode::Exact.name(),
            Mode::Best.name()
        ])
        .to_string()
    }
}

impl Default for Nvector {
    fn default() -> Self {
        Nvector::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernels_of_the_spec_example() {
        let req = json!({"format": "nvector-contract/1", "n": 2, "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]]});
        let out = contract_with_kernels(&req).unwrap();
        assert_eq!(out["kernels"][0], json!([[1.0, 2.0], [5.0, 6.0]]));
        assert_eq!(out["groups"], json!([[0, 1], [2]]));
    }
}
