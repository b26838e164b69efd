//! [`Round`]: what one shapes round works on, handed from step to step
//! instead of nine arguments: the mission's detections, the domains, the
//! proved groups as a union-find, the tolerance, the motion chain and what
//! the round did so far; with the two operations every step uses, the
//! shape of a detection ([`Round::shape_of`]) and the contraction of a
//! detection by a branch result ([`Round::apply`]).
//!
//! Soundness: `apply` intersects the domains with a branch result, a sound
//! enclosure of their solutions ([`crate::shapes::branch`]); an empty
//! intersection is reported as a proof of infeasibility, never skipped.
//! Complexity: O(d) per call.

use super::state::{Chain, Domains, ShapesOutcome};
use crate::contractors::motion_chain::shrinkage;
use crate::ibox::IntervalBox;
use crate::shapes::branch::Branches;
use crate::shapes::shape::{Shape, Sighting};
use crate::slam::mission::Mission;
use crate::union_find::Uf;

/// What the pure shapes need of the mission's detections.
pub fn sightings(mission: &Mission) -> Vec<Sighting> {
    mission
        .detections
        .iter()
        .map(|d| Sighting {
            step: d.step,
            range: d.range,
            bearing: d.bearing,
        })
        .collect()
}

/// One round's context (module doc).
pub(super) struct Round<'r, 'd> {
    /// The detections (steps, ranges, bearings).
    pub mission: &'r Mission,
    /// The domains the round reads and contracts.
    pub dom: Domains<'d>,
    /// The proved groups, growing during the round.
    pub uf: Uf,
    /// A bound moving by at most this much counts as no change.
    pub tol: f64,
    /// The motion chain (sweeps and changed positions).
    pub chain: &'r mut dyn Chain,
    /// What the round did so far.
    pub out: ShapesOutcome,
}

impl Round<'_, '_> {
    /// The step of detection `j`.
    pub fn step_of(&self, j: usize) -> usize {
        self.mission.detections[j].step
    }

    /// The shape of detection `j` on the current domains.
    pub fn shape_of(&self, j: usize) -> Shape {
        let det = &self.mission.detections[j];
        let dim = self.dom.dim;
        let t = det.step;
        Shape::new(
            IntervalBox::new(&self.dom.pos[t * dim..(t + 1) * dim]),
            det.range,
            det.bearing.map(|b| (self.dom.heading_at[j], b)),
            self.dom.det[j].clone(),
        )
    }

    /// The box of p(`t`).
    pub fn position(&self, t: usize) -> IntervalBox {
        let dim = self.dom.dim;
        IntervalBox::new(&self.dom.pos[t * dim..(t + 1) * dim])
    }

    /// Intersects p(step) and d(j) with a branch result; tells the chain of
    /// a shrunk position. Returns whether p(step) moved.
    pub fn apply(&mut self, j: usize, br: &Branches) -> Result<bool, String> {
        let dim = self.dom.dim;
        let t = self.step_of(j);
        let tol = self.tol;
        if br.p.is_empty() || br.d.is_empty() {
            return Err(format!(
                "detection {j} (step {t}): its shape meets no part of its landmark's region"
            ));
        }
        let dom = &mut self.dom;
        let mut p_moved = 0.0f64;
        let mut d_moved = false;
        for a in 0..dim {
            let before = dom.pos[t * dim + a];
            let after = before.intersect(br.p[a]);
            p_moved = p_moved.max(shrinkage(before, after));
            dom.pos[t * dim + a] = after;
            let before = dom.det[j][a];
            let after = before.intersect(br.d[a]);
            d_moved |= shrinkage(before, after) > tol;
            dom.det[j][a] = after;
        }
        if dom.det[j].is_empty() || dom.pos[t * dim..(t + 1) * dim].iter().any(|x| x.is_empty()) {
            return Err(format!(
                "detection {j} (step {t}): its shape meets no part of its landmark's region"
            ));
        }
        if p_moved > tol || d_moved {
            self.out.moved = true;
            self.out.moved_detections.push(j);
        }
        if p_moved > tol {
            self.chain.changed(t);
        }
        Ok(p_moved > tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;

    struct NoChain(Vec<usize>);

    impl Chain for NoChain {
        fn sweep_forward(
            &mut self,
            _pos: &mut [Interval],
            _from: usize,
            to: usize,
        ) -> Result<bool, String> {
            Ok(to == usize::MAX)
        }
        fn changed(&mut self, step: usize) {
            self.0.push(step);
        }
    }

    /// Regression: an infinite bound that a branch leaves unchanged counted
    /// as an infinite move (`-inf - -inf` is NaN, read as "moved"), so an
    /// unbounded position was reported moving in every round. It moves
    /// only when it becomes finite or a finite bound moves by more than the
    /// tolerance.
    #[test]
    fn issue_19_an_unchanged_infinite_bound_has_not_moved() {
        let mission = Mission::from_value(&serde_json::json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [1.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": [{"step": 1, "range": [1, 2]}]
        }))
        .expect("valid mission");
        let half = Interval::new(0.0, f64::INFINITY);
        let mut pos = vec![Interval::ZERO, Interval::ZERO, half, Interval::ENTIRE];
        let mut det = vec![IntervalBox::new(&[Interval::ENTIRE, half])];
        let heading_at = [Interval::ZERO];
        let disp = [Interval::ZERO; 2];
        let br = Branches {
            p: IntervalBox::new(&[half, Interval::ENTIRE]),
            d: IntervalBox::new(&[Interval::ENTIRE, half]),
            surviving: vec![0],
        };
        let mut chain = NoChain(Vec::new());
        let mut round = Round {
            mission: &mission,
            dom: Domains {
                dim: 2,
                pos: &mut pos,
                det: &mut det,
                heading_at: &heading_at,
                disp: &disp,
            },
            uf: Uf::new(1),
            tol: 1e-9,
            chain: &mut chain,
            out: ShapesOutcome::default(),
        };
        assert_eq!(round.apply(0, &br), Ok(false));
        assert!(!round.out.moved && round.out.moved_detections.is_empty());
        // An infinite bound becoming finite is a move.
        let br = Branches {
            p: IntervalBox::new(&[Interval::new(0.0, 5.0), Interval::ENTIRE]),
            ..br
        };
        assert_eq!(round.apply(0, &br), Ok(true));
        assert!(round.out.moved && round.out.moved_detections == [0]);
        drop(round);
        assert_eq!(chain.0, [1]);
    }
}
