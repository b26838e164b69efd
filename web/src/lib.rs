//! Browser facade over nvector-core: one handle type whose methods take and
//! return the JSON formats of docs/formats.md as strings. Core errors become
//! JavaScript errors naming the JSON path; a panic is reported on the
//! console.
//!
//! Four features split it into the page's modules (scripts/web.sh):
//! `playground` (`contract`, `modes`: atmost_nvector alone, the module the
//! page fetches first), `figures` (`outlines`, `boundaries`: the drawing
//! outlines, fetched when the SLAM demo or the missions tab first draws),
//! `slam` (`run`: the solver, a binary mission in) and `simulate`
//! (`simulate`, `readMission`: the simulators and the mission reader),
//! both fetched when the SLAM demo first runs. A build with all four (the
//! default: native, tests) has every method.

#[cfg(feature = "figures")]
mod figures;
#[cfg(any(feature = "slam", feature = "simulate"))]
mod slam;
#[cfg(feature = "figures")]
pub use figures::{region_boundaries, shape_outlines};
#[cfg(all(feature = "slam", feature = "simulate"))]
pub use slam::run_mission;
#[cfg(feature = "slam")]
pub use slam::run_model;
#[cfg(feature = "simulate")]
pub use slam::{read_mission, simulate_json};

#[cfg(feature = "playground")]
use nvector_core::nvector::contract::{response_json, ContractRequest};
#[cfg(feature = "playground")]
use nvector_core::nvector::nvalue::{atmost_nvalue, NValue, NValueScratch};
#[cfg(feature = "playground")]
use nvector_core::nvector::{atmost_nvector, Contractor};
use nvector_core::InputError;
#[cfg(feature = "playground")]
use serde_json::json;
#[cfg(any(feature = "playground", feature = "simulate"))]
use serde_json::Value;
use wasm_bindgen::prelude::*;

/// The one error conversion: path and message of a core error.
pub(crate) fn into_error(e: InputError) -> JsError {
    JsError::new(&e.to_string())
}

#[cfg(any(feature = "playground", feature = "simulate"))]
pub(crate) fn parse(text: &str) -> Result<Value, JsError> {
    serde_json::from_str(text).map_err(|e| JsError::new(&format!("invalid JSON: {e}")))
}

#[cfg(feature = "playground")]
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
}

#[cfg(feature = "playground")]
#[wasm_bindgen]
impl Nvector {
    /// `nvector-contract/1` request -> response, with per-axis kernels.
    pub fn contract(&self, request: &str) -> Result<String, JsError> {
        contract_with_kernels(&parse(request)?)
            .map(|v| v.to_string())
            .map_err(into_error)
    }

    /// The modes accepted by `contract`.
    pub fn modes(&self) -> String {
        json!([
            Contractor::Nvalue.name(),
            Contractor::Projection.name(),
            Contractor::Independent.name(),
            Contractor::Exact.name(),
            Contractor::Best.name()
        ])
        .to_string()
    }
}

impl Default for Nvector {
    fn default() -> Self {
        Nvector::new()
    }
}

#[cfg(all(test, feature = "playground"))]
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
