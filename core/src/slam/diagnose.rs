//! Which measurements to check when a mission is infeasible: a minimal set
//! of detections whose removal makes the propagation consistent (a
//! *minimal correction set*), found with the propagator itself as the
//! consistency test.
//!
//! # Method
//!
//! Detections are taken in time order (step, then index). The set `kept`
//! starts empty (consistent: else the detections are not the cause and
//! there is nothing to name). While `kept ∪ rest` is infeasible, a binary
//! search finds the longest prefix of `rest` that `kept` can take while
//! staying consistent; the detection right after that prefix is a culprit:
//! `kept ∪ prefix` is consistent and adding it makes it infeasible. It goes
//! into the correction set, the prefix into `kept`, and the search goes on
//! with what follows. At the end `kept` (every detection but the
//! correction set) is consistent, and each culprit was infeasible together
//! with a subset of `kept`; as propagation only ever proves more with more
//! constraints, adding any one culprit back to `kept` is infeasible too:
//! the set is minimal (no proper subset restores consistency).
//!
//! This is the deletion filter of the diagnosis literature (Chinneck,
//! *Feasibility and Infeasibility in Optimization*, 2008) turned towards
//! correction sets, with the binary search of QuickXplain (Junker, AAAI
//! 2004) over the time order.
//!
//! # Complexity
//!
//! O(c · log k) propagations for a correction set of c detections among k,
//! each test a whole propagation of the sub-mission; `max_tests` bounds the
//! work (then the answer is a correction set that may not be minimal).

use super::mission::Mission;
use super::propagate::fixpoint::propagate;
use super::types::{SolveOptions, SolveStatus};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};

/// A set of detections whose removal makes the mission consistent.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Correction {
    /// Detection indices (input order), sorted.
    pub detections: Vec<usize>,
    /// Whether the set is minimal (false when `max_tests` ran out: then the
    /// set also holds every detection not yet examined).
    pub minimal: bool,
    /// Propagations run.
    pub tests: usize,
}

/// A minimal correction set of an infeasible mission, or `None` when the
/// mission without any detection is infeasible already (the motion data
/// are the cause), when the whole mission is consistent, or when cancelled.
pub fn minimal_correction(
    mission: &Mission,
    options: &SolveOptions,
    cancel: &AtomicBool,
    max_tests: usize,
) -> Option<Correction> {
    let tests = Cell::new(0usize);
    let consistent = |kept: &[usize]| -> Option<bool> {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        tests.set(tests.get() + 1);
        let mut sub = mission.clone();
        let mut sorted = kept.to_vec();
        crate::sort::sort_usize(&mut sorted);
        sub.detections = sorted
            .iter()
            .map(|&j| mission.detections[j].clone())
            .collect();
        sub.detection_count = sub.detections.len();
        sub.truth = None;
        // Consistency of the detections themselves: no outlier allowed.
        sub.max_outliers = 0;
        let s = propagate(&sub, options, &mut |_| {}, cancel);
        Some(!matches!(s.status, SolveStatus::Infeasible(_)))
    };
    if !consistent(&[])? {
        return None;
    }
    let mut rest: Vec<usize> = (0..mission.detections.len()).collect();
    let dets = &mission.detections;
    crate::sort::sort_indices_by(&mut rest, |a, b| dets[a].step.cmp(&dets[b].step));
    let mut kept: Vec<usize> = Vec::new();
    let mut culprits: Vec<usize> = Vec::new();
    let with = |kept: &[usize], more: &[usize]| -> Vec<usize> {
        let mut v = kept.to_vec();
        v.extend_from_slice(more);
        v
    };
    let mut first = true;
    while !rest.is_empty() {
        if tests.get() >= max_tests {
            culprits.extend_from_slice(&rest);
            crate::sort::sort_usize(&mut culprits);
            return Some(Correction {
                detections: culprits,
                minimal: false,
                tests: tests.get(),
            });
        }
        if consistent(&with(&kept, &rest))? {
            if first {
                return None;
            }
            break;
        }
        first = false;
        // kept ∪ rest[..lo] consistent, kept ∪ rest[..hi] infeasible.
        let (mut lo, mut hi) = (0usize, rest.len());
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if consistent(&with(&kept, &rest[..mid]))? {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        kept.extend_from_slice(&rest[..lo]);
        culprits.push(rest[lo]);
        rest.drain(..hi);
    }
    crate::sort::sort_usize(&mut culprits);
    Some(Correction {
        detections: culprits,
        minimal: true,
        tests: tests.get(),
    })
}
