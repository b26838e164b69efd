//! The radar demo's wasm module (web/www/radar.js): core's radar scenario
//! (`tdoa::simulate::simulate_radar`) and TDOA solver (`tdoa::solve_tdoa`)
//! for the page, JSON text in and out. A crate apart from the page's main
//! module (`nvector-web`) so that the page's wasm does not carry the TDOA
//! solver: `scripts/web.sh build` makes it into `web/www/pkg-radar/`, with
//! its own size budget, and the page loads it only when the radar demo
//! opens.

use nvector_core::nvector::Contractor;
use nvector_core::tdoa::simulate::{simulate_radar, RadarOptions};
use nvector_core::tdoa::{solve_tdoa, tdoa_result_json, TdoaOptions, TdoaProblem};
use nvector_core::InputError;
use serde_json::Value;
use wasm_bindgen::prelude::*;

fn into_error(e: InputError) -> JsError {
    JsError::new(&e.to_string())
}

/// An option of the demo's JSON: a whole number in `0..=max`, or `default`.
fn count(v: &Value, key: &str, default: usize, max: usize) -> Result<usize, JsError> {
    match v.get(key) {
        None | Some(Value::Null) => Ok(default),
        Some(x) => x
            .as_u64()
            .filter(|&n| n <= max as u64)
            .map(|n| n as usize)
            .ok_or_else(|| JsError::new(&format!("{key}: expected a whole number up to {max}"))),
    }
}

/// A radar problem (`nvector-tdoa/1`) from the options `{"seed",
/// "emitters", "receivers", "pulses"}` (each optional; the scenario's
/// limits apply and errors name the option).
#[wasm_bindgen]
pub fn simulate(options: &str) -> Result<String, JsError> {
    let v: Value = serde_json::from_str(options).map_err(|e| JsError::new(&e.to_string()))?;
    let d = RadarOptions::default();
    let o = RadarOptions {
        seed: count(&v, "seed", d.seed as usize, u32::MAX as usize)? as u64,
        emitters: count(&v, "emitters", d.emitters, 1000)?,
        receivers: count(&v, "receivers", d.receivers, 1000)?,
        pulses: count(&v, "pulses", d.pulses, 100_000)?,
        ..d
    };
    simulate_radar(&o)
        .map(|p| p.to_string())
        .map_err(into_error)
}

/// The problem solved as `nvector tdoa` does (default budget and rounds),
/// with `contractor` `none` or an atmost_nvector contractor:
/// `nvector-tdoa-result/1` (`metrics.elapsed_ms` 0: the page times it).
#[wasm_bindgen]
pub fn solve(problem: &str, contractor: &str) -> Result<String, JsError> {
    let p = TdoaProblem::from_json_str(problem).map_err(into_error)?;
    let mode = match contractor {
        "none" => None,
        c => Some(
            Contractor::parse(c)
                .filter(|c| *c != Contractor::Exact)
                .ok_or_else(|| JsError::new(&format!("contractor: unknown '{c}'")))?,
        ),
    };
    let o = TdoaOptions {
        mode,
        ..TdoaOptions::default()
    };
    let s = solve_tdoa(&p, &o);
    Ok(tdoa_result_json(&p, &o, &s, 0.0).to_string())
}
