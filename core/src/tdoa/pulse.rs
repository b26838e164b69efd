//! The per-pulse fixpoint and its paving: one pulse's emitter position and
//! emission time under its kept arrivals, its altitude and its regions.
//!
//! # Constraint
//!
//! The conjunction of the pulse's cuts ([`super::cuts`]) and of the arrival
//! constraints ([`super::arrival`]) of the arrivals kept (a reading of
//! `max_outliers` drops some).
//!
//! # Math
//!
//! [`fixpoint`]: sweeps of the cuts and of every kept arrival until no
//! domain shrinks by more than [`SHRINK`] of its width (at most
//! [`MAX_SWEEPS`]). [`pave`]: branch and contract on the position — the
//! widest leaf is bisected on its widest axis, each half contracted by
//! [`fixpoint`], empty halves dropped — for at most `budget` bisections;
//! the answer is the hull of the leaves (a paving of the hyperbolic shells'
//! intersection, whose hull is far tighter than one box fixpoint).
//!
//! # Soundness
//!
//! The fixpoint composes sound contractors. The two halves of a bisection
//! cover the leaf, so every solution stays in a surviving leaf, hence in
//! the hull. Stopping early (sweeps, budget) only leaves boxes wider.
//!
//! # Complexity
//!
//! O(budget · MAX_SWEEPS · m) arrival contractions for m kept arrivals,
//! O(budget) extra memory.

use super::arrival::{contract_arrival, ArrivalData, PulseVars};
use super::cuts::{cut, cut_distance};
use super::problem::{Pulse, TdoaProblem};
use crate::interval::Interval;

/// Most sweeps of one fixpoint.
pub const MAX_SWEEPS: usize = 40;
/// A sweep that shrinks no domain by more than this share of its width
/// ends the fixpoint.
pub const SHRINK: f64 = 1e-3;
/// Default number of bisections of a pulse's paving.
pub const DEFAULT_BUDGET: usize = 96;

/// The contraction context of one pulse under one reading.
pub struct PulseCtx<'a> {
    /// The problem.
    pub problem: &'a TdoaProblem,
    /// The pulse.
    pub pulse: &'a Pulse,
    /// Indices of the arrivals kept.
    pub kept: &'a [usize],
}

fn shrank(before: Interval, after: Interval) -> bool {
    let w = before.width();
    if !w.is_finite() {
        return after.width() < w || after.lo() != before.lo() || after.hi() != before.hi();
    }
    w - after.width() > SHRINK * w
}

impl PulseCtx<'_> {
    fn data(&self, a: usize) -> ArrivalData<'_> {
        let arr = self.pulse.arrivals[a];
        let r = &self.problem.receivers[arr.receiver];
        ArrivalData {
            receiver: r.position.axes(),
            bias: r.clock_bias,
            time: arr.time,
            speed: self.problem.speed,
        }
    }

    /// Contracts `v` to a fixpoint; `false` when it is proved empty.
    pub fn fixpoint(&self, v: &mut PulseVars) -> bool {
        let regions = [
            self.pulse.region.as_ref(),
            self.problem.emitter_region.as_ref(),
        ];
        for _ in 0..MAX_SWEEPS {
            let before = *v;
            if !cut(&mut v.x, self.pulse.altitude, &regions) {
                return false;
            }
            if let Some((p, r)) = &self.pulse.distance_from {
                if !cut_distance(&mut v.x, p, *r) {
                    return false;
                }
            }
            for &a in self.kept {
                if !contract_arrival(v, &self.data(a)) {
                    return false;
                }
            }
            let moved = (0..3).any(|i| shrank(before.x[i], v.x[i])) || shrank(before.tau, v.tau);
            if !moved {
                break;
            }
        }
        true
    }

    /// The hull of a paving of `v` with at most `budget` bisections, or
    /// `None` when every leaf is proved empty.
    pub fn pave(&self, v: PulseVars, budget: usize) -> Option<PulseVars> {
        let mut start = v;
        if !self.fixpoint(&mut start) {
            return None;
        }
        let mut leaves = vec![start];
        for _ in 0..budget {
            let Some((i, axis)) = widest(&leaves) else {
                break;
            };
            let leaf = leaves.swap_remove(i);
            let mid = leaf.x[axis].mid();
            for half in [
                Interval::new(leaf.x[axis].lo(), mid),
                Interval::new(mid, leaf.x[axis].hi()),
            ] {
                let mut h = leaf;
                h.x[axis] = half;
                if self.fixpoint(&mut h) {
                    leaves.push(h);
                }
            }
            if leaves.is_empty() {
                return None;
            }
        }
        leaves
            .iter()
            .skip(1)
            .fold(leaves.first().copied(), |acc, l| acc.map(|a| a.hull(l)))
    }
}

/// The leaf with the widest bounded, splittable axis, and that axis.
fn widest(leaves: &[PulseVars]) -> Option<(usize, usize)> {
    let mut best: Option<(usize, usize, f64)> = None;
    for (i, l) in leaves.iter().enumerate() {
        for (axis, a) in l.x.iter().enumerate() {
            let w = a.width();
            let m = a.mid();
            let splittable = w.is_finite() && m > a.lo() && m < a.hi();
            if splittable && best.is_none_or(|b| w > b.2) {
                best = Some((i, axis, w));
            }
        }
    }
    best.map(|(i, a, _)| (i, a))
}
