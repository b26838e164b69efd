//! `nvector-tdoa-result/1` (JSON writing) and the score against the truth.

use super::problem::TdoaProblem;
use super::solve::{TdoaOptions, TdoaSolution};
use crate::ibox::IntervalBox;
use crate::json::{bound_to_json, box_to_json, interval_to_json};
use serde_json::{json, Value};

/// The format name of the result.
pub const RESULT_FORMAT: &str = "nvector-tdoa-result/1";

/// The score against the truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TdoaScore {
    /// Every pulse's box (and group's box) holds its true emitter.
    pub truth_inside: bool,
    /// Pairs of pulses in a proved group whose true emitters differ (or
    /// are unknown).
    pub matching_errors: usize,
    /// Share of the pulses with a true emitter that are in a group of size
    /// >= 2 (1 when there is none).
    pub matching_recall: f64,
}

/// The emitter box of a group: the intersection of its pulses' boxes.
pub fn group_box(s: &TdoaSolution, g: &[usize]) -> IntervalBox {
    let mut b = IntervalBox::new(&s.vars[g[0]].x);
    for &j in &g[1..] {
        b.intersect_with(&IntervalBox::new(&s.vars[j].x));
    }
    b
}

/// The score, when the problem has a truth.
pub fn score(p: &TdoaProblem, s: &TdoaSolution) -> Option<TdoaScore> {
    let t = p.truth.as_ref()?;
    let mut inside = true;
    for (v, pos) in s.vars.iter().zip(&t.positions) {
        if let Some(pt) = pos {
            inside &= IntervalBox::new(&v.x).contains(pt);
        }
    }
    let mut errors = 0;
    for g in &s.groups {
        if let Some(e) = g.iter().find_map(|&j| t.matching[j]) {
            if let Some(pt) = t.emitters.get(e) {
                inside &= group_box(s, g).contains(pt);
            }
        }
        for (x, &a) in g.iter().enumerate() {
            for &b in &g[x + 1..] {
                match (t.matching[a], t.matching[b]) {
                    (Some(ea), Some(eb)) if ea == eb => {}
                    _ => errors += 1,
                }
            }
        }
    }
    let real = t.matching.iter().filter(|m| m.is_some()).count();
    let grouped = s
        .groups
        .iter()
        .flatten()
        .filter(|&&j| t.matching[j].is_some())
        .count();
    let recall = if real == 0 {
        1.0
    } else {
        grouped as f64 / real as f64
    };
    Some(TdoaScore {
        truth_inside: inside,
        matching_errors: errors,
        matching_recall: recall,
    })
}

/// Max and median of the pulses' position box diameters.
pub fn diameters(s: &TdoaSolution) -> (f64, f64) {
    let mut d: Vec<f64> = s
        .vars
        .iter()
        .map(|v| IntervalBox::new(&v.x).diameter())
        .collect();
    crate::sort::floats(&mut d);
    let max = d.last().copied().unwrap_or(0.0);
    let median = if d.is_empty() { 0.0 } else { d[d.len() / 2] };
    (max, median)
}

/// The result JSON (`metrics.elapsed_ms` as given: the caller measures).
pub fn tdoa_result_json(
    p: &TdoaProblem,
    o: &TdoaOptions,
    s: &TdoaSolution,
    elapsed_ms: f64,
) -> Value {
    let (max_d, median_d) = diameters(s);
    let mut out = json!({
        "format": RESULT_FORMAT,
        "name": p.name,
        "status": if s.infeasible.is_some() {
            "infeasible"
        } else if s.stopped {
            "stopped"
        } else {
            "consistent"
        },
        "contractor": o.mode.map_or("none", |m| m.name()),
        "pulses": s.vars.iter().map(|v| box_to_json(&IntervalBox::new(&v.x))).collect::<Vec<_>>(),
        "emission_times": s.vars.iter().map(|v| interval_to_json(v.tau)).collect::<Vec<_>>(),
        "matching": s.groups,
        "emitters": s.groups.iter().map(|g| box_to_json(&group_box(s, g))).collect::<Vec<_>>(),
        "metrics": {
            "max_pulse_diameter": bound_to_json(max_d),
            "median_pulse_diameter": bound_to_json(median_d),
            "rounds": s.rounds,
            "elapsed_ms": elapsed_ms,
        },
    });
    if let Some(reason) = &s.infeasible {
        out["reason"] = reason.clone().into();
    }
    if let Some(sc) = score(p, s) {
        out["score"] = json!({
            "truth_inside": sc.truth_inside,
            "matching_errors": sc.matching_errors,
            "matching_recall": sc.matching_recall,
        });
    }
    out
}

/// The JSON Schema of what [`tdoa_result_json`] writes (feature `openapi`:
/// the server's document, `GET /jobs/{id}/result` of a TDOA job), kept next
/// to the writer it describes.
#[cfg(feature = "openapi")]
pub fn result_schema() -> Value {
    let bound = json!({"oneOf": [{"type": "number"}, {"type": "string", "enum": ["-inf", "inf"]}]});
    let interval = json!({"oneOf": [
        {"type": "array", "items": bound, "minItems": 2, "maxItems": 2},
        {"type": "string", "enum": ["empty"]}
    ], "description": "[lo, hi] (bounds are numbers, \"-inf\" or \"inf\"), or \"empty\"."});
    let boxed = json!({"oneOf": [
        {"type": "array", "items": interval, "minItems": 3, "maxItems": 3},
        {"type": "string", "enum": ["empty"]}
    ], "description": "A box of 3 intervals (x, y, z in metres), or \"empty\"."});
    json!({
        "type": "object",
        "description": "The result of a TDOA job (`nvector-tdoa-result/1`, docs/formats.md).",
        "required": ["format", "name", "status", "contractor", "pulses", "emission_times",
                     "matching", "emitters", "metrics"],
        "properties": {
            "format": {"type": "string", "enum": [RESULT_FORMAT]},
            "name": {"type": "string", "description": "The problem's name."},
            "status": {"type": "string", "enum": ["consistent", "infeasible", "stopped"]},
            "reason": {"type": "string", "description": "Why it is infeasible (with `infeasible`)."},
            "contractor": {"type": "string", "description": "The atmost_nvector contractor, or `none`."},
            "pulses": {"type": "array", "items": boxed,
                       "description": "One box per pulse: its emitter's position."},
            "emission_times": {"type": "array", "items": interval,
                               "description": "One interval per pulse: its emission time (s)."},
            "matching": {"type": "array",
                         "items": {"type": "array", "items": {"type": "integer", "minimum": 0}},
                         "description": "Groups of pulse indices proved to share an emitter."},
            "emitters": {"type": "array", "items": boxed,
                         "description": "One box per group of `matching`."},
            "metrics": {
                "type": "object",
                "required": ["max_pulse_diameter", "median_pulse_diameter", "rounds", "elapsed_ms"],
                "properties": {
                    "max_pulse_diameter": bound,
                    "median_pulse_diameter": bound,
                    "rounds": {"type": "integer", "minimum": 0},
                    "elapsed_ms": {"type": "number", "minimum": 0}
                }
            },
            "score": {
                "type": "object",
                "description": "Against the problem's truth, when it has one.",
                "required": ["truth_inside", "matching_errors", "matching_recall"],
                "properties": {
                    "truth_inside": {"type": "boolean"},
                    "matching_errors": {"type": "integer", "minimum": 0},
                    "matching_recall": {"type": "number", "minimum": 0, "maximum": 1}
                }
            }
        }
    })
}
