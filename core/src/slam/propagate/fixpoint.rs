//! The fixpoint of a mission, without the diagnosis of an infeasible
//! result: the robust propagation ([`super::outliers`]) when the mission
//! allows false detections, else the rounds of [`super::rounds`].
//!
//! This is the one place that chooses between the two engines; the
//! diagnosis ([`super::diagnose`]) and the entry points
//! ([`super::solve`]) sit above it.
//!
//! May import: the propagation layer (`rounds`, `outliers`) and below.

use super::mission::Mission;
use super::outliers::solve_robust;
use super::rounds::rounds;
use super::types::{Progress, Solution, SolveOptions};
use std::sync::atomic::AtomicBool;

/// The fixpoint alone, without the diagnosis of an infeasible result:
/// the robust propagation ([`super::outliers`]) when the mission allows
/// false detections, else the rounds of [`super::rounds`].
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
