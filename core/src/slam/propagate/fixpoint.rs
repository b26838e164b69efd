//! The fixpoint of a mission, without the diagnosis of an infeasible
//! result: the robust propagation ([`crate::slam::robust`]) when the mission
//! allows false detections, else the rounds of [`crate::slam::propagate::rounds`].
//!
//! This is the one place that chooses between the two engines; the
//! diagnosis ([`crate::slam::diagnose`]) and the entry points
//! ([`crate::slam::solve`]) sit above it.
//!
//! May import: the propagation layer (`rounds`, `outliers`) and below.

use crate::slam::mission::Mission;
use crate::slam::propagate::rounds::rounds;
use crate::slam::robust::solve_robust;
use crate::slam::types::{Progress, Solution, SolveOptions};
use std::sync::atomic::AtomicBool;

/// The fixpoint alone, without the diagnosis of an infeasible result:
/// the robust propagation ([`crate::slam::robust`]) when the mission allows
/// false detections, else the rounds of [`crate::slam::propagate::rounds`].
pub fn propagate(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    if mission.max_outliers > 0 {
        return solve_robust(mission, mission.max_outliers, options, progress, cancel);
    }
    rounds(mission, options, progress, cancel)
}
