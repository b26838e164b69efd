//! `max_outliers` over arrivals: the readings of one pulse (which of its
//! arrivals a sub-problem drops) and what holds in all of them.
//!
//! # Constraint
//!
//! With `max_outliers` = q the solution set is the union, over every choice
//! of at most q dropped arrivals (in the whole problem), of the solutions
//! of the problem without them (docs/outliers.md: every box encloses every
//! solution of every such sub-problem).
//!
//! # Math
//!
//! For pulse k, [`least_drops`] finds d_k, the least number of its arrivals
//! whose removal is not proved empty by the paving ([`super::pulse`]):
//! every consistent sub-problem drops at least d_k arrivals of pulse k, so
//! it drops at most `b_k = q - Σ_{j != k} d_j` of them. [`hull`] is the
//! hull, over the drop sets of pulse k of size in [d_k, b_k], of the
//! paving's answer for the arrivals kept: the q-relaxed intersection of the
//! arrivals' evidence, per pulse.
//!
//! # Soundness
//!
//! d_k is a lower bound (a drop set proved empty has no solution, even
//! alone), hence b_k an upper bound, of the drops of pulse k in any
//! consistent sub-problem; each sub-problem's pulse-k solutions are in the
//! paving of its own drop set, hence in the hull. Past [`MAX_READINGS`]
//! drop sets, or when at most one arrival would be kept, the pulse keeps
//! its cut box (no arrival evidence): wider, never unsound.
//!
//! # Complexity
//!
//! At most [`MAX_READINGS`] pavings per pulse and call.

use super::arrival::PulseVars;
use super::cuts::cut;
use super::problem::TdoaProblem;
use super::pulse::PulseCtx;

/// Most drop sets enumerated for one pulse.
pub const MAX_READINGS: usize = 64;

/// The kept-arrival lists of the drop sets of size `s` out of `m`, or
/// `None` past `cap` of them.
fn kept_sets(m: usize, s: usize, cap: usize) -> Option<Vec<Vec<usize>>> {
    let keep = m.checked_sub(s)?;
    let mut out = Vec::new();
    let mut idx: Vec<usize> = (0..keep).collect();
    loop {
        if out.len() >= cap {
            return None;
        }
        out.push(idx.clone());
        // Next combination of `keep` out of `m`, in lexicographic order.
        let Some(i) = (0..keep).rev().find(|&i| idx[i] < m - keep + i) else {
            return Some(out);
        };
        idx[i] += 1;
        for j in i + 1..keep {
            idx[j] = idx[j - 1] + 1;
        }
    }
}

/// The least number of pulse `k`'s arrivals whose removal is not proved
/// empty, searched up to `max`; `None` when every drop set up to `max` is
/// proved empty. Past [`MAX_READINGS`] drop sets of one size it answers
/// that size (nothing more is proved).
pub fn least_drops(
    p: &TdoaProblem,
    k: usize,
    v: PulseVars,
    max: usize,
    budget: usize,
) -> Option<usize> {
    let pulse = &p.pulses[k];
    let m = pulse.arrivals.len();
    for s in 0..=max.min(m) {
        let Some(sets) = kept_sets(m, s, MAX_READINGS) else {
            return Some(s);
        };
        let feasible = sets.iter().any(|kept| {
            let ctx = PulseCtx {
                problem: p,
                pulse,
                kept,
            };
            ctx.pave(v, budget).is_some()
        });
        if feasible {
            return Some(s);
        }
    }
    None
}

/// The kept-arrival lists of pulse `k`'s drop sets of size `lo..=hi`, or
/// `None` when the pulse keeps no arrival evidence (past
/// [`MAX_READINGS`] drop sets, or when at most one arrival would be kept:
/// then only its cuts hold, module doc).
pub fn reading_sets(p: &TdoaProblem, k: usize, lo: usize, hi: usize) -> Option<Vec<Vec<usize>>> {
    let m = p.pulses[k].arrivals.len();
    if m.saturating_sub(hi) <= 1 {
        return None;
    }
    let mut sets = Vec::new();
    for s in lo..=hi.min(m) {
        let mut more = kept_sets(m, s, MAX_READINGS - sets.len().min(MAX_READINGS))?;
        sets.append(&mut more);
    }
    Some(sets)
}

/// The hull over the drop sets of pulse `k` of size in `lo..=hi` of the
/// paving of `v` (`None`: every one proved empty).
pub fn hull(
    p: &TdoaProblem,
    k: usize,
    v: PulseVars,
    lo: usize,
    hi: usize,
    budget: usize,
) -> Option<PulseVars> {
    let pulse = &p.pulses[k];
    let Some(sets) = reading_sets(p, k, lo, hi) else {
        let mut c = v;
        let regions = [pulse.region.as_ref(), p.emitter_region.as_ref()];
        return cut(&mut c.x, pulse.altitude, &regions).then_some(c);
    };
    let mut acc: Option<PulseVars> = None;
    for kept in &sets {
        let ctx = PulseCtx {
            problem: p,
            pulse,
            kept,
        };
        if let Some(r) = ctx.pave(v, budget) {
            acc = Some(acc.map_or(r, |a| a.hull(&r)));
        }
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn combinations_are_all_listed() {
        assert_eq!(kept_sets(4, 2, 100).unwrap().len(), 6);
        assert_eq!(kept_sets(5, 0, 100).unwrap(), vec![vec![0, 1, 2, 3, 4]]);
        assert_eq!(kept_sets(3, 3, 100).unwrap(), vec![Vec::<usize>::new()]);
        assert!(kept_sets(30, 10, 64).is_none());
        assert!(kept_sets(2, 3, 64).is_none());
    }
}
