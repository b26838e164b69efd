//! Browser facade over nvector-core: one handle type whose methods take and
//! return the JSON formats of docs/formats.md as strings. Core errors become
//! JavaScript errors naming the JSON path; a panic is reported on the
//! console.

use nvector_core::format::{self, Object};
use nvector_core::nvector::contract::{response_json, ContractRequest};
use nvector_core::nvector::nvalue::{atmost_nvalue, NValue, NValueScratch};
use nvector_core::nvector::{atmost_nvector, Contractor};
use nvector_core::outline::{shape_outline, union_boundary};
use nvector_core::shapes::shape::{Shape, MAX_DIM};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::{simulate, SimulateLimits, SimulateRequest};
use nvector_core::slam::solve::solve;
use nvector_core::slam::types::{Association, Progress, SolveOptions};
use nvector_core::{InputError, Interval, IntervalBox};
use serde_json::{json, Value};
use std::cmp::Ordering;
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
/// `"scenario": "woods"` is core's woods generator (an odometry2d robot
/// among identical landmarks, with scans).
pub fn simulate_json(options: &Value) -> Result<Value, InputError> {
    let Object(request) = format::from_value::<Object<SimulateRequest>>(options)?;
    Ok(simulate(&request.options(SimulateLimits::CORE)?))
}

/// Reads the flat numbers of an outline request, naming the place of a bad
/// one (`shapes[3].range`).
struct Numbers<'a> {
    what: &'static str,
    rest: &'a [f64],
}

impl Numbers<'_> {
    fn take(&mut self, item: usize, field: &str) -> Result<f64, InputError> {
        let (x, rest) = self.rest.split_first().ok_or_else(|| {
            InputError::new(
                format!("{}[{item}].{field}", self.what),
                "the list ends early",
            )
        })?;
        self.rest = rest;
        Ok(*x)
    }

    fn interval(&mut self, item: usize, field: &str) -> Result<Interval, InputError> {
        let (lo, hi) = (self.take(item, field)?, self.take(item, field)?);
        let ordered = matches!(lo.partial_cmp(&hi), Some(Ordering::Less | Ordering::Equal));
        if !ordered || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
            return Err(InputError::new(
                format!("{}[{item}].{field}", self.what),
                "not an interval: the lower bound is above the upper one, infinite \
                 the wrong way or not a number",
            ));
        }
        Ok(Interval::new(lo, hi))
    }

    /// A count of items of `size` numbers each, bounded by what is left.
    fn count(&mut self, item: usize, field: &str, size: usize) -> Result<usize, InputError> {
        let n = self.take(item, field)?;
        if !(n >= 0.0 && n.fract() == 0.0 && n * size as f64 <= self.rest.len() as f64) {
            return Err(InputError::new(
                format!("{}[{item}].{field}", self.what),
                "not a count of the boxes that follow (4 numbers each)",
            ));
        }
        Ok(n as usize)
    }

    fn boxed(&mut self, item: usize, field: &str, dim: usize) -> Result<IntervalBox, InputError> {
        let mut axes = [Interval::ZERO; MAX_DIM];
        for a in axes.iter_mut().take(dim) {
            *a = self.interval(item, field)?;
        }
        Ok(IntervalBox::new(&axes[..dim]))
    }
}

/// The outlines of detection shapes, computed by core
/// (core/src/outline.rs), from flat numbers (a Float64Array in the page: no
/// JSON for thousands of shapes). Per shape: `dim` (1 to 3); the centre
/// box's `2 dim` bounds (lo, hi per axis); the range's lo, hi; 0, or 1 and
/// the heading's lo, hi and the bearing's lo, hi; the cut box's `2 dim`
/// bounds (infinite for no cut). The answer, per shape: `n_outer, n_hole`,
/// then the outer polygon's `2 n_outer` and the hole's `2 n_hole`
/// coordinates (x, y, ...; `n_outer` = 0: nothing to draw). The outer
/// polygon is counter-clockwise, the hole clockwise: filled with the
/// nonzero rule, the outline encloses the shape.
pub fn shape_outlines(input: &[f64]) -> Result<Vec<f64>, InputError> {
    let mut r = Numbers {
        what: "shapes",
        rest: input,
    };
    let mut out = Vec::new();
    let mut i = 0;
    while !r.rest.is_empty() {
        let dim = r.take(i, "dim")?;
        if !(1.0..=MAX_DIM as f64).contains(&dim) || dim.fract() != 0.0 {
            return Err(InputError::new(
                format!("shapes[{i}].dim"),
                "expected 1, 2 or 3 axes",
            ));
        }
        let dim = dim as usize;
        let centre = r.boxed(i, "centre", dim)?;
        let range = r.interval(i, "range")?;
        let bearing = match r.take(i, "bearing")? {
            0.0 => None,
            1.0 => Some((r.interval(i, "heading")?, r.interval(i, "bearing")?)),
            _ => {
                return Err(InputError::new(
                    format!("shapes[{i}].bearing"),
                    "expected 0 (no bearing) or 1 (heading and bearing follow)",
                ))
            }
        };
        let cut = r.boxed(i, "cut", dim)?;
        match shape_outline(&Shape::new(centre, range, bearing, cut)) {
            Some(o) => {
                let hole = o.hole.as_deref().unwrap_or(&[]);
                out.extend([o.outer.len() as f64, hole.len() as f64]);
                out.extend(o.outer.iter().chain(hole).flatten());
            }
            None => out.extend([0.0, 0.0]),
        }
        i += 1;
    }
    Ok(out)
}

/// The boundaries of landmark regions (unions of boxes), computed by core
/// (core/src/outline.rs), from flat numbers. Per region: the number of
/// boxes, then per box x lo, x hi, y lo, y hi. The answer, per region: the
/// number of segments, then per segment x0, y0, x1, y1; -1 (and nothing
/// after it) for a region of too many boxes to trace (core's
/// `MAX_UNION_BOXES`: the page draws its fill alone).
pub fn region_boundaries(input: &[f64]) -> Result<Vec<f64>, InputError> {
    let mut r = Numbers {
        what: "regions",
        rest: input,
    };
    let mut out = Vec::new();
    let mut i = 0;
    while !r.rest.is_empty() {
        let n = r.count(i, "boxes", 4)?;
        let mut boxes = Vec::with_capacity(n);
        for _ in 0..n {
            boxes.push(r.boxed(i, "boxes", 2)?);
        }
        match union_boundary(&boxes) {
            Some(segments) => {
                out.push(segments.len() as f64);
                out.extend(segments.iter().flatten().flatten());
            }
            None => out.push(-1.0),
        }
        i += 1;
    }
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

    /// The outlines of detection shapes (see [`shape_outlines`]).
    pub fn outlines(&self, shapes: &[f64]) -> Result<Vec<f64>, JsError> {
        shape_outlines(shapes).map_err(into_error)
    }

    /// The boundaries of landmark regions (see [`region_boundaries`]).
    pub fn boundaries(&self, regions: &[f64]) -> Result<Vec<f64>, JsError> {
        region_boundaries(regions).map_err(into_error)
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

    #[test]
    fn outlines_of_a_ring_a_cut_away_shape_and_a_sector() {
        let inf = f64::INFINITY;
        let ring = [2.0, 0.0, 1.0, 0.0, 1.0, 5.0, 6.0, 0.0, -inf, inf, -inf, inf];
        let away = [
            2.0, 0.0, 1.0, 0.0, 1.0, 5.0, 6.0, 0.0, 50.0, 60.0, 50.0, 60.0,
        ];
        let sector = [
            2.0, 0.0, 1.0, 0.0, 1.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, -inf, inf, -inf, inf,
        ];
        let input: Vec<f64> = [&ring[..], &away, &sector].concat();
        let out = shape_outlines(&input).unwrap();
        let (n0, h0) = (out[0] as usize, out[1] as usize);
        assert!(n0 >= 3 && h0 >= 3, "a ring has a hole: {out:?}");
        let mut k = 2 + 2 * (n0 + h0);
        assert_eq!(&out[k..k + 2], &[0.0, 0.0], "cut away: nothing to draw");
        k += 2;
        let (n2, h2) = (out[k] as usize, out[k + 1] as usize);
        assert!(n2 >= 3 && h2 == 0, "a sector from range 0 has no hole");
        assert_eq!(out.len(), k + 2 + 2 * n2);
        // Every vertex of the sector lies in the quarter plane x, y >= 0
        // widened by the box (bearing [0, 0.5] from the box [0, 1]^2).
        assert!(out[k + 2..]
            .chunks(2)
            .all(|p| p[0] >= -1e-6 && p[1] >= -1e-6));
    }

    #[test]
    fn region_boundaries_of_two_overlapping_boxes() {
        let out = region_boundaries(&[
            2.0, 0.0, 2.0, 0.0, 1.0, 1.0, 3.0, 0.0, 1.0, 1.0, 5.0, 6.0, 5.0, 6.0,
        ])
        .unwrap();
        // Region 0: 6 segments (the rectangle [0, 3] x [0, 1], its bottom
        // and top sides in two pieces each); region 1: a square's 4 sides.
        assert_eq!(out[0], 6.0);
        assert_eq!(out[1 + 24], 4.0);
        assert_eq!(out.len(), 1 + 24 + 1 + 16);
    }

    #[test]
    fn outline_errors_name_the_place() {
        let e = shape_outlines(&[2.0, 0.0, 1.0, 0.0, 1.0, 3.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].range"), "{e}");
        let e = shape_outlines(&[4.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].dim"), "{e}");
        let e = shape_outlines(&[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[1].centre"), "{e}");
        let e = shape_outlines(&[1.0, 0.0, 1.0, 0.0, 1.0, 2.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].bearing"), "{e}");
        let e = region_boundaries(&[1e9, 0.0]).unwrap_err();
        assert!(e.to_string().contains("regions[0].boxes"), "{e}");
        let e = region_boundaries(&[1.0, 0.0, f64::NAN, 0.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("regions[0].boxes"), "{e}");
    }
}
