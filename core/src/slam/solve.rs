//! The entry points of the SLAM pipeline, at its top: a mission in, a
//! typed [`Solution`] ([`solve_model`]) or the `nvector-result/1` JSON
//! ([`solve`]) out. The fixpoint ([`super::propagate::fixpoint`]), then, when it
//! proves the mission infeasible, the diagnosis ([`super::diagnose`])
//! names a minimal set of detections to check.
//!
//! May import: every layer of `slam` below it.

use super::diagnose::minimal_correction;
use super::mission::Mission;
use super::propagate::fixpoint::propagate;
use super::result::result_json;
use super::types::{Progress, Solution, SolveOptions, SolveStatus};
use serde_json::Value;
use std::sync::atomic::AtomicBool;

/// Most propagations the diagnosis of an infeasible mission may run.
const DIAGNOSIS_TESTS: usize = 64;

/// Runs a mission to the fixpoint and returns the typed solution.
pub fn solve_model(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    let mut solution = propagate(mission, options, progress, cancel);
    if let SolveStatus::Infeasible(reason) = &mut solution.status {
        // Name the detections to check (docs/design.md, "False detections";
        // spec: a minimal set whose removal makes the mission consistent).
        if let Some(c) = minimal_correction(mission, options, cancel, DIAGNOSIS_TESTS) {
            let what = if c.minimal {
                "a minimal set"
            } else {
                "a set (not proved minimal: the diagnosis budget ran out)"
            };
            reason.push_str(&format!(
                "; removing detections {:?} makes the mission consistent ({what}, found in {} propagations)",
                c.detections, c.tests
            ));
        }
    }
    solution
}

/// Runs a mission to the fixpoint; returns the `nvector-result/1` JSON
/// (`metrics.elapsed_ms` is 0: core has no clock; callers fill it in).
pub fn solve(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Value {
    let solution = solve_model(mission, options, progress, cancel);
    result_json(mission, options, &solution)
}
