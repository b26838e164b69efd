//! The physics-guided propagator. OWNER: helper B.

use super::mission::Mission;
use serde_json::Value;
use std::sync::atomic::AtomicBool;

/// How to tie detections to landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Association {
    /// Basic model: only operator `landmark` fields tie detections.
    None,
    /// atmost_nvector with this contractor.
    NVector(crate::nvector::Mode),
}

/// Options of a SLAM job.
#[derive(Debug, Clone)]
pub struct SolveOptions {
    /// Association mode (`--contractor`).
    pub association: Association,
    /// Most propagation rounds.
    pub max_rounds: u32,
    /// Changes below this stop sweeps.
    pub tolerance: f64,
}

/// Progress report.
#[derive(Debug, Clone)]
pub struct Progress {
    /// Current round.
    pub round: u32,
    /// Current max trajectory diameter.
    pub max_trajectory_diameter: f64,
    /// Estimated fraction done, 0..=1.
    pub fraction: f64,
}

/// Runs a mission to the fixpoint; returns the `nvector-result/1` JSON.
/// `elapsed_ms` is measured by the caller (core has no clock) and may be
/// filled in afterwards.
pub fn solve(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Value {
    let _ = (mission, options, progress, cancel);
    Value::Null
}
