//! `OdometryChain`: the odometry2d motion chain (formats.md, model
//! `"odometry2d"`), with the heading a variable of the propagation.
//!
//! # Constraint
//!
//! For i = 0..N-1, with the state (p(i), θ(i)), p = (x, y), θ a real number
//! (not taken modulo 2π; no wrapping is ever done here):
//!
//! - `θ(i+1) = θ(i) + dt·ω(i) + f(i)`, `|f(i)| <= heading_error(i)`;
//! - `p(i+1) = p(i) + dt·v(i)·(cos θ(i), sin θ(i)) + e(i)`,
//!   `|e(i)| <= motion_error(i)` on each axis,
//!
//! with the inputs v(i) (speed, signed) and ω(i) (turn rate) in their
//! intervals.
//!
//! # Math
//!
//! Precomputed once: `Δθ(i) = dt·ω(i) + [-f, f]`, `s(i) = dt·v(i)`,
//! `E(i) = [-e, e]`. Forward sweep, i increasing:
//! `θ(i+1) ∩= θ(i) + Δθ(i)`, `D = s(i)·(cos θ(i), sin θ(i)) + E(i)`,
//! `p(i+1) ∩= p(i) + D`. Backward sweep, i decreasing:
//! `θ(i) ∩= θ(i+1) - Δθ(i)`, `p(i) ∩= p(i+1) - D` (D from the current
//! θ(i)), and the heading from the displacement: when s(i) excludes 0,
//! `(cos θ(i), sin θ(i)) ∈ Q = (p(i+1) - p(i) - E(i)) / s(i)` (per axis),
//! so θ(i) ∈ angle(Q) + 2πZ when Q excludes the origin
//! ([`contract_heading`]).
//!
//! # Soundness
//!
//! Every step is the interval projection of one of the two equations,
//! with outward-rounded operations and core's sound sin/cos: the true
//! (p, θ) satisfy both equations with inputs inside their intervals, so
//! they lie in every right-hand side. The heading contraction is
//! [`contract_heading`]'s (sound for real headings of any magnitude:
//! every copy `A + 2πk` is kept). A bound that is NaN or negative is read
//! as "no bound" (the whole line), never as an empty interval.
//!
//! # Complexity
//!
//! O(1) per step, O(N) per sweep, no allocation in the sweeps.

use crate::contractors::motion_chain::{shrinkage, Sweep};
use crate::interval::Interval;
use crate::odometry::angle::{contract_heading, heading_moved};
use crate::odometry::drift::{DriftWindow, HeadingDrift};
use crate::odometry::motion_drift::{MotionDrift, MotionWindow};

/// The inputs of an odometry2d chain of N steps, precomputed as intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct OdometryChain {
    /// `dt·v(i)`, i < N.
    step: Vec<Interval>,
    /// `dt·ω(i) + [-f(i), f(i)]`, i < N.
    turn: Vec<Interval>,
    /// `[-e(i), e(i)]`, i < N.
    error: Vec<Interval>,
    /// The heading drift windows (`heading_drift`), when the mission has
    /// any that constrain ([`OdometryChain::with_drift`]).
    drift: Option<HeadingDrift>,
    /// The motion drift windows (`motion_drift`), when the mission has any
    /// that constrain ([`OdometryChain::with_motion_drift`]).
    motion: Option<MotionDrift>,
}

/// p(k) of flat positions (2 intervals per state).
fn flat(pos: &[Interval], k: usize) -> [Interval; 2] {
    [pos[2 * k], pos[2 * k + 1]]
}

/// A symmetric bound `[-e, e]`; NaN, negative or infinite `e`: the whole
/// line (sound: no bound).
fn symmetric(e: f64) -> Interval {
    if e >= 0.0 && e.is_finite() {
        Interval::new(-e, e)
    } else {
        Interval::ENTIRE
    }
}

/// The value of a per-step bound given as one number or N numbers.
fn per_step(values: &[f64], i: usize) -> f64 {
    match values.len() {
        0 => 0.0,
        1 => values[0],
        _ => values.get(i).copied().unwrap_or(f64::INFINITY),
    }
}

/// Where a sweep found an empty domain: the step whose position or heading
/// emptied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Emptied {
    /// The step (0..=N) whose domain became empty.
    pub step: usize,
}

impl OdometryChain {
    /// The chain of `speed.len()` steps. `speed` and `turn_rate` hold one
    /// interval per step (the caller checks they have the same length N;
    /// the shorter one sets N here); `heading_error` and `motion_error`
    /// hold no number (0), one (every step) or N numbers (a missing one
    /// reads as no bound). `dt` must be finite and > 0 (else every
    /// displacement is unbounded).
    pub fn new(
        dt: f64,
        speed: &[Interval],
        turn_rate: &[Interval],
        heading_error: &[f64],
        motion_error: &[f64],
    ) -> OdometryChain {
        let n = speed.len().min(turn_rate.len());
        let dt_ok = dt.is_finite() && dt > 0.0;
        let mut step = Vec::with_capacity(n);
        let mut turn = Vec::with_capacity(n);
        let mut error = Vec::with_capacity(n);
        for i in 0..n {
            if dt_ok {
                step.push(speed[i].scale(dt));
                turn.push(turn_rate[i].scale(dt) + symmetric(per_step(heading_error, i)));
            } else {
                step.push(Interval::ENTIRE);
                turn.push(Interval::ENTIRE);
            }
            error.push(symmetric(per_step(motion_error, i)));
        }
        OdometryChain {
            step,
            turn,
            error,
            drift: None,
            motion: None,
        }
    }

    /// The chain with the heading drift windows of the mission
    /// (`heading_drift`; [`HeadingDrift`]), over the same `dt`,
    /// `turn_rate` and `heading_error` as [`OdometryChain::new`] (the
    /// per-step bounds of the steps a window exempts).
    pub fn with_drift(
        mut self,
        dt: f64,
        turn_rate: &[Interval],
        heading_error: &[f64],
        windows: &[DriftWindow],
    ) -> OdometryChain {
        let n = self.steps();
        let turn = &turn_rate[..n.min(turn_rate.len())];
        self.drift = HeadingDrift::new(dt, turn, heading_error, windows);
        self
    }

    /// The chain with the motion drift windows of the mission
    /// (`motion_drift`; [`MotionDrift`]).
    pub fn with_motion_drift(mut self, windows: &[MotionWindow]) -> OdometryChain {
        self.motion = MotionDrift::new(windows, self.steps());
        self
    }

    /// The motion drift windows, when any constrain.
    pub fn motion_drift(&self) -> Option<&MotionDrift> {
        self.motion.as_ref()
    }

    /// The heading drift windows, when any constrain.
    pub fn drift(&self) -> Option<&HeadingDrift> {
        self.drift.as_ref()
    }

    /// The heading drift windows over th(0..=N) ([`HeadingDrift::contract`],
    /// one forward and one backward sweep per window), then the chain
    /// swept forward and backward from every state whose heading moved by
    /// more than `tol` (stopping like [`OdometryChain::sweep_forward_flat`]),
    /// on flat positions. `Ok(work)`: the window steps and chain steps
    /// visited (0 without windows); `Err`: the step whose domain emptied.
    /// O(N) per window, plus the sweeps (O(N)); one allocation of N + 1
    /// flags when a window moved a heading.
    pub fn drift_flat(
        &self,
        pos: &mut [Interval],
        heading: &mut [Interval],
        tol: f64,
    ) -> Result<usize, Emptied> {
        let Some(d) = &self.drift else {
            return Ok(0);
        };
        let n = self.steps();
        let mut moved = vec![false; n + 1];
        let mut work = 2 * d.windows().count() * (n + 1);
        if !d
            .contract(heading, &mut moved, tol)
            .map_err(|step| Emptied { step })?
        {
            return Ok(work);
        }
        let mut s = 0;
        while s < n {
            if !moved[s] {
                s += 1;
                continue;
            }
            match self.sweep_forward_flat(pos, heading, s, n, tol) {
                Sweep::Empty(step) => return Err(Emptied { step }),
                // Steps s..s+v-1 done: state s+v's own step is not.
                Sweep::Done(v) => (work, s) = (work + v, s + v.max(1)),
            }
        }
        // Backward: a moved th(s) is read by the steps s (p(s) from
        // p(s+1)) and s-1 (th(s-1) from th(s)): sweep from state s+1.
        let mut s = n + 1;
        while s > 0 {
            s -= 1;
            if !moved[s] {
                continue;
            }
            let from = (s + 1).min(n);
            match self.sweep_backward_flat(pos, heading, from, 0, tol) {
                Sweep::Empty(step) => return Err(Emptied { step }),
                // Steps from-1 down to from-v done: step from-v-1 is not,
                // so state from-v is looked at again.
                Sweep::Done(v) => (work, s) = (work + v, s.min(from + 1 - v.min(from))),
            }
        }
        Ok(work)
    }

    /// N, the number of steps (N + 1 states).
    pub fn steps(&self) -> usize {
        self.step.len()
    }

    /// `dt·v(i)`, the signed distance run in step i (before its error).
    pub fn step_length(&self, i: usize) -> Interval {
        self.step[i]
    }

    /// `[-e(i), e(i)]`, the per-axis error of step i's displacement.
    pub fn motion_error(&self, i: usize) -> Interval {
        self.error[i]
    }

    /// `Δθ(i) = dt·ω(i) + [-f(i), f(i)]`.
    pub fn heading_increment(&self, i: usize) -> Interval {
        self.turn[i]
    }

    /// The displacement `dt·v(i)·(cos θ, sin θ) + [-e(i), e(i)]` of step
    /// i for a heading in `heading`.
    pub fn displacement(&self, i: usize, heading: Interval) -> [Interval; 2] {
        let s = self.step[i];
        let e = self.error[i];
        [s * heading.cos() + e, s * heading.sin() + e]
    }

    /// State i+1 contracted from state i (forward; see the module doc).
    fn forward_state(
        &self,
        i: usize,
        (p, h): ([Interval; 2], Interval),
        (p1, h1): ([Interval; 2], Interval),
    ) -> Result<([Interval; 2], Interval), Emptied> {
        let hn = h1.intersect(h + self.turn[i]);
        let d = self.displacement(i, h);
        let pn = [p1[0].intersect(p[0] + d[0]), p1[1].intersect(p[1] + d[1])];
        if hn.is_empty() || pn[0].is_empty() || pn[1].is_empty() {
            return Err(Emptied { step: i + 1 });
        }
        Ok((pn, hn))
    }

    /// State i contracted from state i+1 (backward, with the heading
    /// contraction from the displacement; see the module doc).
    fn backward_state(
        &self,
        i: usize,
        (p, h): ([Interval; 2], Interval),
        (p1, h1): ([Interval; 2], Interval),
    ) -> Result<([Interval; 2], Interval), Emptied> {
        let mut hn = h.intersect(h1 - self.turn[i]);
        let d = self.displacement(i, hn);
        let pn = [p[0].intersect(p1[0] - d[0]), p[1].intersect(p1[1] - d[1])];
        if hn.is_empty() || pn[0].is_empty() || pn[1].is_empty() {
            return Err(Emptied { step: i });
        }
        let s = self.step[i];
        if s.lo() > 0.0 || s.hi() < 0.0 {
            let e = self.error[i];
            let qx = (p1[0] - pn[0] - e) / s;
            let qy = (p1[1] - pn[1] - e) / s;
            if !(qx.contains(0.0) && qy.contains(0.0)) {
                hn = contract_heading(hn, qx, qy, Interval::ZERO);
                if hn.is_empty() {
                    return Err(Emptied { step: i });
                }
            }
        }
        Ok((pn, hn))
    }

    /// One forward step i -> i+1 (see the module doc). `Err` when a domain
    /// of step i+1 became empty; `Ok(changed)`.
    pub fn forward_step(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        i: usize,
    ) -> Result<bool, Emptied> {
        let (p, h) = self.forward_state(i, (pos[i], heading[i]), (pos[i + 1], heading[i + 1]))?;
        let changed = h != heading[i + 1] || p != pos[i + 1];
        heading[i + 1] = h;
        pos[i + 1] = p;
        Ok(changed)
    }

    /// One backward step i+1 -> i, with the heading contraction from the
    /// displacement (see the module doc). `Err` when a domain of step i
    /// became empty; `Ok(changed)`.
    pub fn backward_step(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        i: usize,
    ) -> Result<bool, Emptied> {
        let (p, h) = self.backward_state(i, (pos[i], heading[i]), (pos[i + 1], heading[i + 1]))?;
        let changed = h != heading[i] || p != pos[i];
        heading[i] = h;
        pos[i] = p;
        Ok(changed)
    }

    /// The propagator's stopping sweep on flat positions (`pos[2k..2k+2]`
    /// is p(k), as in `slam::model::Model::pos`): forward over the steps
    /// `from..to` (`to` at most N, states from+1..=to), stopping at the
    /// first state that moves by at most `tol` (as
    /// [`OdometryChain::sweep_forward`]). `Sweep::Done(steps visited)` or
    /// `Sweep::Empty(state)`.
    pub fn sweep_forward_flat(
        &self,
        pos: &mut [Interval],
        heading: &mut [Interval],
        from: usize,
        to: usize,
        tol: f64,
    ) -> Sweep {
        let to = to.min(self.steps());
        for i in from..to {
            let a = (flat(pos, i), heading[i]);
            let old = (flat(pos, i + 1), heading[i + 1]);
            match self.forward_state(i, a, old) {
                Err(e) => return Sweep::Empty(e.step),
                Ok((p, h)) => {
                    let changed = p != old.0 || h != old.1;
                    (pos[2 * i + 2], pos[2 * i + 3], heading[i + 1]) = (p[0], p[1], h);
                    if !changed || Self::moved(old, &p, h) <= tol {
                        return Sweep::Done(i + 1 - from);
                    }
                }
            }
        }
        Sweep::Done(to.saturating_sub(from))
    }

    /// Backward on flat positions over the steps `from-1` down to `to`
    /// (states from-1..=to), stopping like
    /// [`OdometryChain::sweep_forward_flat`].
    pub fn sweep_backward_flat(
        &self,
        pos: &mut [Interval],
        heading: &mut [Interval],
        from: usize,
        to: usize,
        tol: f64,
    ) -> Sweep {
        let from = from.min(self.steps());
        for i in (to..from).rev() {
            let old = (flat(pos, i), heading[i]);
            let b = (flat(pos, i + 1), heading[i + 1]);
            match self.backward_state(i, old, b) {
                Err(e) => return Sweep::Empty(e.step),
                Ok((p, h)) => {
                    let changed = p != old.0 || h != old.1;
                    (pos[2 * i], pos[2 * i + 1], heading[i]) = (p[0], p[1], h);
                    if !changed || Self::moved(old, &p, h) <= tol {
                        return Sweep::Done(from - i);
                    }
                }
            }
        }
        Sweep::Done(from.saturating_sub(to))
    }

    /// Forward sweep over steps `from..N` (states from+1..=N).
    /// `pos` and `heading` hold N + 1 entries. `Ok(changed)`.
    pub fn forward(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        from: usize,
    ) -> Result<bool, Emptied> {
        self.check_len(pos, heading);
        let mut changed = false;
        for i in from..self.steps() {
            changed |= self.forward_step(pos, heading, i)?;
        }
        Ok(changed)
    }

    /// Backward sweep over steps `to-1` down to 0 (states to-1..=0), `to`
    /// at most N. `Ok(changed)`.
    pub fn backward(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        to: usize,
    ) -> Result<bool, Emptied> {
        self.check_len(pos, heading);
        let mut changed = false;
        for i in (0..to.min(self.steps())).rev() {
            changed |= self.backward_step(pos, heading, i)?;
        }
        Ok(changed)
    }

    /// How far the bounds of state k moved from `old` (see
    /// [`shrinkage`]).
    fn moved(old: ([Interval; 2], Interval), pos: &[Interval; 2], heading: Interval) -> f64 {
        shrinkage(old.0[0], pos[0])
            .max(shrinkage(old.0[1], pos[1]))
            .max(heading_moved(old.1, heading))
    }

    /// Forward sweep from state `from` (steps from..N), stopping at the
    /// first state that does not change, or whose bounds move by at most
    /// `tol` (as [`crate::contractors::motion_chain::sweep_forward`] does: what
    /// lies beyond would only move by that much; stopping early is sound,
    /// it only contracts less). `Sweep::Done(steps visited)` or
    /// `Sweep::Empty(state)`. The positions as points: the same sweep as
    /// [`OdometryChain::sweep_forward_flat`] (one implementation).
    pub fn sweep_forward(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        from: usize,
        tol: f64,
    ) -> Sweep {
        self.check_len(pos, heading);
        self.sweep_forward_flat(pos.as_flattened_mut(), heading, from, self.steps(), tol)
    }

    /// Backward sweep from state `from` (at most N): steps from-1 down to
    /// 0, stopping like [`OdometryChain::sweep_forward`]; the same sweep as
    /// [`OdometryChain::sweep_backward_flat`].
    pub fn sweep_backward(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
        from: usize,
        tol: f64,
    ) -> Sweep {
        self.check_len(pos, heading);
        self.sweep_backward_flat(pos.as_flattened_mut(), heading, from, 0, tol)
    }

    /// A forward sweep over the whole chain, then a backward one.
    /// `Ok(changed)`; `Err` names the first step found empty.
    pub fn contract(
        &self,
        pos: &mut [[Interval; 2]],
        heading: &mut [Interval],
    ) -> Result<bool, Emptied> {
        let a = self.forward(pos, heading, 0)?;
        let b = self.backward(pos, heading, self.steps())?;
        Ok(a || b)
    }

    fn check_len(&self, pos: &[[Interval; 2]], heading: &[Interval]) {
        assert!(
            pos.len() == self.steps() + 1 && heading.len() == self.steps() + 1,
            "an odometry chain of {} steps needs {} states, got {} positions and {} headings",
            self.steps(),
            self.steps() + 1,
            pos.len(),
            heading.len()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_run_east_then_back() {
        // 10 steps at 1 m/s, dt = 0.1, no turn, heading known to be 0:
        // x(10) in [1 - 10e, 1 + 10e].
        let n = 10;
        let chain = OdometryChain::new(
            0.1,
            &vec![Interval::point(1.0); n],
            &vec![Interval::ZERO; n],
            &[0.0],
            &[0.001],
        );
        let mut pos = vec![[Interval::ENTIRE; 2]; n + 1];
        let mut heading = vec![Interval::ENTIRE; n + 1];
        pos[0] = [Interval::ZERO, Interval::ZERO];
        heading[0] = Interval::ZERO;
        assert!(chain.contract(&mut pos, &mut heading).unwrap());
        assert!(pos[n][0].contains(1.0) && pos[n][0].width() < 0.021);
        assert!(heading[n].contains(0.0) && heading[n].width() < 1e-12);
    }

    #[test]
    fn a_sweep_stops_where_nothing_changes() {
        let n = 50;
        let chain = OdometryChain::new(
            0.1,
            &vec![Interval::point(1.0); n],
            &vec![Interval::point(0.1); n],
            &[0.01],
            &[0.001],
        );
        let mut pos = vec![[Interval::ENTIRE; 2]; n + 1];
        let mut heading = vec![Interval::ENTIRE; n + 1];
        pos[0] = [Interval::ZERO, Interval::ZERO];
        heading[0] = Interval::ZERO;
        assert_eq!(
            chain.sweep_forward(&mut pos, &mut heading, 0, 0.0),
            Sweep::Done(n)
        );
        // Already contracted: the next sweep stops at its first state.
        assert_eq!(
            chain.sweep_forward(&mut pos, &mut heading, 0, 0.0),
            Sweep::Done(1)
        );
        // A tighter heading at state 20 travels forward to the end.
        heading[20] = heading[20].intersect(Interval::new(0.19, 0.21));
        assert_eq!(
            chain.sweep_forward(&mut pos, &mut heading, 20, 0.0),
            Sweep::Done(n - 20)
        );
        // 0.02 wide at state 20, 0.02 more per step (was 1.0 at state n).
        assert!(heading[n].width() < 0.02 + 0.02 * 30.0 + 1e-9);
    }

    #[test]
    fn the_heading_comes_back_from_positions() {
        // Heading unknown, positions known: the displacement (1, 0) at
        // speed 10 (dt 0.1) says the heading is 0 mod 2pi; the copy inside
        // [5, 7] is 2pi.
        let chain = OdometryChain::new(
            0.1,
            &[Interval::point(10.0)],
            &[Interval::ZERO],
            &[0.0],
            &[0.01],
        );
        let mut pos = vec![[Interval::ZERO; 2], [Interval::point(1.0), Interval::ZERO]];
        let mut heading = vec![Interval::new(5.0, 7.0), Interval::new(5.0, 7.0)];
        chain.contract(&mut pos, &mut heading).unwrap();
        let two_pi = 2.0 * std::f64::consts::PI;
        assert!(heading[0].contains(two_pi) && heading[0].width() < 0.05);
    }

    #[test]
    fn a_nan_bound_reads_as_no_bound() {
        let chain = OdometryChain::new(
            0.1,
            &[Interval::point(1.0)],
            &[Interval::ZERO],
            &[f64::NAN],
            &[-1.0],
        );
        let mut pos = vec![[Interval::ZERO; 2], [Interval::ENTIRE; 2]];
        let mut heading = vec![Interval::ZERO, Interval::ENTIRE];
        chain.contract(&mut pos, &mut heading).unwrap();
        assert!(heading[1] == Interval::ENTIRE && pos[1][0] == Interval::ENTIRE);
    }
}
