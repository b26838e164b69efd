//! `nvector check`: every constraint of a mission that its truth breaks,
//! and by how much (docs/cli.md, "check"; the output in docs/formats.md,
//! "Check").
//!
//! The constraints are those the solver contracts with, evaluated on the
//! truth's point values with the same interval functions
//! ([`motion`]: the boxes, the steps, the drift windows; [`detections`]:
//! the detections and landmarks). A violation is decided soundly: a truth
//! exactly on a bound is never one, and a truth the check accepts is kept
//! by the solver's basic contractors (each step's and each detection's
//! contractor is run on the truth's point boxes as well).
//!
//! With `max_outliers` q > 0 the solver allows q detections to be false
//! or outside their bounds: when the detections that break a constraint
//! are at most q, their violations are marked `outlier` and do not count
//! as broken ([`Report::broken`]).

pub mod detections;
pub mod motion;
pub mod types;

use crate::error::InputError;
use crate::slam::mission::Mission;
use motion::PathStyle;
use serde_json::{json, Value};
use types::{Truthy, Violation};

/// What the check found.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// Every constraint broken, in the order: boxes, steps, drift
    /// windows, detections, landmarks.
    pub violations: Vec<Violation>,
    /// Constraints not checked because the truth does not know a value
    /// they need (a `null` position, a missing heading).
    pub unchecked: usize,
    /// How many detections break a constraint.
    pub broken_detections: usize,
    /// The mission's `max_outliers`.
    pub max_outliers: usize,
}

impl Report {
    /// The violations that count (those `max_outliers` does not cover).
    pub fn broken(&self) -> usize {
        self.violations.iter().filter(|v| !v.outlier).count()
    }

    /// `{"violations": [...], "unchecked": n, "broken_detections": b,
    /// "max_outliers": q}` (docs/formats.md, "Check").
    pub fn to_json(&self) -> Value {
        let v: Vec<Value> = self.violations.iter().map(Violation::to_json).collect();
        json!({
            "violations": v,
            "unchecked": self.unchecked,
            "broken_detections": self.broken_detections,
            "max_outliers": self.max_outliers,
        })
    }
}

/// The check of a validated mission; `style` says how the mission wrote
/// its per-step bounds (for the paths). Err: the mission has no truth.
pub fn check(m: &Mission, style: &PathStyle) -> Result<Report, InputError> {
    if m.truth.is_none() {
        return Err(InputError::new(
            "truth",
            "the mission has no truth: there is nothing to check its bounds against",
        ));
    }
    let mut t = Truthy { m, unchecked: 0 };
    let mut out = Vec::new();
    motion::boxes(&mut t, &mut out);
    motion::steps(&mut t, style, &mut out);
    motion::heading_drift(&mut t, &mut out);
    motion::motion_drift(&mut t, &mut out);
    let matched = detections::detections(&mut t, &mut out);
    detections::landmarks(&t, &matched, &mut out);
    let mut broken: Vec<usize> = out
        .iter()
        .filter(|v| v.kind.of_a_detection())
        .filter_map(|v| v.detection)
        .collect();
    crate::sort::sort_usize(&mut broken);
    broken.dedup();
    if !broken.is_empty() && broken.len() <= m.max_outliers {
        for v in out.iter_mut().filter(|v| v.kind.of_a_detection()) {
            v.outlier = true;
        }
    }
    Ok(Report {
        violations: out,
        unchecked: t.unchecked,
        broken_detections: broken.len(),
        max_outliers: m.max_outliers,
    })
}

/// How a mission's JSON writes `motion_error` and `heading_error`.
pub fn path_style(v: &Value) -> PathStyle {
    PathStyle {
        motion_error_array: v.get("motion_error").is_some_and(Value::is_array),
        heading_error_array: v.get("heading_error").is_some_and(Value::is_array),
    }
}

/// The check of a mission given as a JSON value (validated first: errors
/// name the JSON path).
pub fn check_value(v: &Value) -> Result<Report, InputError> {
    let m = Mission::from_value(v)?;
    check(&m, &path_style(v))
}

/// The check of a mission given as JSON text.
pub fn check_json(text: &str) -> Result<Report, InputError> {
    let v: Value = crate::format::from_str(text)?;
    check_value(&v)
}
