//! `PulseShell`: the set of emitter positions one pulse allows, as a
//! detection shape ([`crate::shapes::shape::DetectionShape`]) for the shapes
//! machinery (witnesses, regions, branch contraction).
//!
//! # Constraint
//!
//! Pulse k with kept arrivals i (receiver r_i in its box, bias b_i, time
//! stamp t_i, speed c, all intervals) allows the emitter positions
//!
//! `S(k) = {x ∈ X_k : ∃ tau ∈ T_k, ∀ i kept: |x - r_i| = c (t_i - tau - b_i)}`
//!
//! with the pulse's cuts (altitude, regions, distance) on x, X_k and T_k the
//! pulse's current boxes. Eliminating tau between two arrivals gives
//! `|x - r_i| - |x - r_j| = c (t_i - t_j - b_i + b_j)`: S(k) is the
//! intersection of hyperbolic shells over the receiver pairs (the shared tau
//! carries them). Its hull is the pulse's box; the set itself is much
//! thinner, and the shells of two emitters are often disjoint where their
//! boxes overlap.
//!
//! With `max_outliers` the shape is the **union over the pulse's allowed
//! readings** (the drop sets of size `lo..=hi` of [`super::readings`]: every
//! consistent sub-problem drops at least `lo` and at most `hi` of this
//! pulse's arrivals), each reading's S(k) with its own kept arrivals. Past
//! [`super::readings::MAX_READINGS`] drop sets, or when at most one arrival
//! would be kept, the shape is the cut box alone (one reading keeping no
//! arrival): wider, never unsound.
//!
//! # Math
//!
//! [`PulseShell::contract_piece`] (the branch "x in B"): for each reading,
//! the pulse's fixpoint ([`super::pulse::PulseCtx::fixpoint`]: the cuts and
//! every kept arrival's contractor, swept) from (X_k ∩ B, T_k); the piece is
//! the hull over the readings of the surviving (x, tau). B is excluded when
//! every reading's fixpoint is empty. [`PulseShell::paving`]: a
//! [`Paving`] of X_k cut and refined by the shell. Disjointness: the quick
//! test is the boxes' ([`DetectionShape::disjoint_quick`]); the paved one
//! ([`crate::shapes::shape::disjoint_paved`]) bisects the common box, each
//! piece excluded by one of the two shells.
//!
//! # Soundness
//!
//! A solution (x, tau) of a reading with x ∈ B satisfies that reading's
//! constraints, which the fixpoint only projects with outward-rounded
//! interval operations: it stays in that reading's contracted box, hence in
//! the hull. Every solution of every allowed sub-problem is one of the
//! readings' (docs/outliers.md), so `meets_box(B) == false` proves that no
//! sub-problem puts the emitter in B, and two shells proved disjoint prove
//! two distinct emitters in every sub-problem. An empty shell (an empty
//! box) proves no disjointness (the witnesses check it).
//!
//! # Complexity
//!
//! [`PulseShell::contract_piece`]: O(R · MAX_SWEEPS · m) arrival
//! contractions for R readings (at most 64) of at most m arrivals;
//! a paving or paved test: that times its box budget.

use super::arrival::PulseVars;
use super::problem::TdoaProblem;
use super::pulse::PulseCtx;
use super::readings::reading_sets;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::region::Paving;
use crate::shapes::shape::{DetectionShape, MAX_DIM};

/// The emitter set of one pulse (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct PulseShell<'a> {
    problem: &'a TdoaProblem,
    pulse: usize,
    vars: PulseVars,
    bounds: IntervalBox,
    /// Kept-arrival lists, one per reading (`[[]]`: the cuts alone).
    readings: Vec<Vec<usize>>,
}

impl<'a> PulseShell<'a> {
    /// The shell of pulse `k` within `vars` (its current boxes), over the
    /// readings dropping `lo..=hi` of its arrivals (`0, 0` without
    /// `max_outliers`).
    pub fn new(
        problem: &'a TdoaProblem,
        k: usize,
        vars: PulseVars,
        lo: usize,
        hi: usize,
    ) -> PulseShell<'a> {
        let readings = reading_sets(problem, k, lo, hi).unwrap_or_else(|| vec![Vec::new()]);
        PulseShell {
            problem,
            pulse: k,
            vars,
            bounds: IntervalBox::new(&vars.x),
            readings,
        }
    }

    /// The pulse's index.
    pub fn pulse(&self) -> usize {
        self.pulse
    }

    /// The boxes the shell lies in.
    pub fn vars(&self) -> PulseVars {
        self.vars
    }

    /// A paving of the shell: its box cut by it, then refined (boxes wider
    /// than `resolution` bisected while at most `max_boxes`).
    pub fn paving(&self, resolution: f64, max_boxes: usize) -> Paving {
        let mut p = Paving::from_box(&self.bounds);
        p.cut(self);
        p.refine(&[self], resolution, max_boxes);
        p
    }
}

impl DetectionShape for PulseShell<'_> {
    type Piece = PulseVars;

    fn dim(&self) -> usize {
        3
    }

    fn is_empty(&self) -> bool {
        self.vars.is_empty()
    }

    fn bounds(&self) -> &IntervalBox {
        &self.bounds
    }

    fn contract_piece(&self, b: &[Interval]) -> Option<PulseVars> {
        let mut start = self.vars;
        for (x, c) in start.x.iter_mut().zip(b) {
            *x = x.intersect(*c);
        }
        if start.is_empty() {
            return None;
        }
        let pulse = &self.problem.pulses[self.pulse];
        let mut acc: Option<PulseVars> = None;
        for kept in &self.readings {
            let ctx = PulseCtx {
                problem: self.problem,
                pulse,
                kept,
            };
            let mut v = start;
            if ctx.fixpoint(&mut v) && !v.is_empty() {
                acc = Some(acc.map_or(v, |a| a.hull(&v)));
            }
        }
        acc
    }

    fn position(piece: &PulseVars) -> [Interval; MAX_DIM] {
        piece.x
    }

    fn hull_pieces(a: &PulseVars, b: &PulseVars) -> PulseVars {
        a.hull(b)
    }

    fn disjoint_quick(&self, other: &Self) -> bool {
        !self.is_empty() && !other.is_empty() && !self.bounds.meets(&other.bounds)
    }

    /// The boxes say little of hyperbolic shells: always worth it.
    fn worth_paving(&self, _other: &Self) -> bool {
        true
    }

    fn thickness(&self) -> f64 {
        self.bounds.diameter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::shape::disjoint_paved;
    use crate::shapes::witnesses::Item;
    use crate::tdoa::problem::{Arrival, Pulse, Receiver};

    const C: f64 = 3e8;

    /// Four receivers on a 10 km square, pulses sent at 0 from `emitters`,
    /// time stamps ± 1 ns.
    fn problem(emitters: &[[f64; 3]]) -> TdoaProblem {
        let rx = [
            [0.0, 0.0, 0.0],
            [1e4, 0.0, 0.0],
            [0.0, 1e4, 0.0],
            [1e4, 1e4, 50.0],
        ];
        let pulses = emitters
            .iter()
            .map(|e| Pulse {
                arrivals: rx
                    .iter()
                    .enumerate()
                    .map(|(i, r)| {
                        let d: f64 = (0..3)
                            .map(|a| (e[a] - r[a]) * (e[a] - r[a]))
                            .sum::<f64>()
                            .sqrt();
                        let t = d / C;
                        Arrival {
                            receiver: i,
                            time: Interval::new(t - 1e-9, t + 1e-9),
                        }
                    })
                    .collect(),
                altitude: Some(Interval::new(-1.0, 1.0)),
                region: None,
                emitter: None,
                distance_from: None,
            })
            .collect();
        TdoaProblem {
            name: "shells".into(),
            speed: Interval::point(C),
            receivers: rx
                .iter()
                .map(|r| Receiver {
                    position: IntervalBox::point(r),
                    clock_bias: Interval::ZERO,
                })
                .collect(),
            pulses,
            emitter_count: Some(2),
            emitter_region: None,
            max_outliers: 0,
            meta: serde_json::Value::Null,
            truth: None,
        }
    }

    /// Two emitters 600 m apart inside one common 10 km box: the boxes
    /// meet, the shells do not (proved by bisection); two pulses of one
    /// emitter are not called disjoint.
    #[test]
    fn shells_separate_what_boxes_cannot() {
        let p = problem(&[[3e3, 4e3, 0.0], [3.6e3, 4e3, 0.0], [3e3, 4e3, 0.0]]);
        let v = PulseVars {
            x: [
                Interval::new(0.0, 1e4),
                Interval::new(0.0, 1e4),
                Interval::new(-1.0, 1.0),
            ],
            tau: Interval::new(-1e-3, 1e-3),
        };
        let s: Vec<PulseShell> = (0..3).map(|k| PulseShell::new(&p, k, v, 0, 0)).collect();
        assert!(!s[0].disjoint_quick(&s[1]));
        assert!(disjoint_paved(&s[0], &s[1], 64));
        assert!(Item::Shape(&s[0]).disjoint(&Item::Shape(&s[1])));
        assert!(!Item::Shape(&s[0]).disjoint(&Item::Shape(&s[2])));
        // The paving of one shell is small and holds its emitter.
        let r = s[0].paving(0.0, 64);
        assert!(r.contains(&[3e3, 4e3, 0.0]));
        assert!(r.hull().diameter() < 100.0, "{:?}", r.hull());
        assert!(!r.meets_shape(&s[1]) && r.meets_shape(&s[2]));
    }
}
