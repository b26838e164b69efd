//! `HeadingDrift`: the odometry2d heading drift bound over windows
//! (`heading_drift`, docs/formats.md).
//!
//! # Constraint
//!
//! For each window `(k, b)` of the mission and every i with i + k <= N:
//!
//! `|θ(i+k) - θ(i) - S(i, k)| <= b`, `S(i, k) = Σ_{j=i}^{i+k-1} dt·ω(j)`,
//!
//! with ω(j) the turn rate, anywhere in its input interval (the integrated
//! turn rate is the window's input, with the input's own bounds). The
//! per-step `heading_error` is the window k = 1; a real odometry's heading
//! residual over k steps is far below k times the per-step bound when
//! most of the per-step residual is jitter that does not accumulate
//! (docs/utias-woods.md).
//!
//! # Math
//!
//! With `[a_j, c_j] ∋ dt·ω(j)` (outward-rounded), `S(i, k)` lies in
//! `[Σ a_j, Σ c_j]`. Prefix sums `A(m) = fl(A(m-1) + a_{m-1})`, `C(m)`
//! likewise (round to nearest), computed once: O(N) memory, O(1) per
//! window sum. Forward over i increasing,
//! `θ(i+k) ∩= θ(i) + [ΣA - b, ΣC + b]`; backward over i decreasing,
//! `θ(i) ∩= θ(i+k) - [ΣA - b, ΣC + b]`, each window in turn.
//!
//! # Soundness
//!
//! Each addition of the prefix is rounded to nearest: its error is at most
//! `u·|result| <= u·M` (u = 2^-53, M the largest |prefix| of the chain;
//! an exact sum when the result is subnormal). The k additions between
//! A(i) and A(i+k) therefore put `A(i+k) - A(i)` within `k·u·M` of the
//! exact `Σ a_j`; that difference is rounded down (up for C), and the
//! bound `R(k) = k·u·M`, rounded up, is subtracted (added): the exact sum
//! lies inside. A non-finite `a_j` (an unbounded input: `-inf`) is counted
//! apart (a prefix count) and the window sums holding one are unbounded on
//! that side; a prefix that overflows (M infinite) disables the windows
//! (no contraction, never a NaN). A window bound `b` that is NaN, negative
//! or infinite, `k = 0` or `k > N` constrains nothing and is skipped. Each
//! contraction is the interval projection of the constraint onto θ(i+k)
//! or θ(i), outward-rounded: the true headings stay inside.
//!
//! # Complexity
//!
//! O(N) to build (four arrays of N + 1), O(N) per window per direction,
//! no allocation in the sweeps and none sized by k.

use crate::contractors::motion_chain::shrinkage;
use crate::interval::Interval;

/// u = 2^-53, the unit roundoff of f64 (round to nearest).
const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;

/// The heading drift windows of a chain of N steps, with the prefix sums
/// of the turn inputs (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct HeadingDrift {
    /// `(k, [-(b + R(k)), b + R(k)])`, 1 <= k <= N, b finite and >= 0
    /// (only the upper bound is read).
    windows: Vec<(usize, Interval)>,
    /// M, the largest |prefix sum| (finite).
    largest: f64,
    /// `A(m)`, m = 0..=N: the prefix sums of the finite lower bounds.
    lo: Vec<f64>,
    /// `C(m)`: the prefix sums of the finite upper bounds.
    hi: Vec<f64>,
    /// How many of the first m lower (upper) bounds are infinite.
    lo_inf: Vec<u32>,
    hi_inf: Vec<u32>,
}

impl HeadingDrift {
    /// The windows `(k, b)` over the chain of `turn_rate.len()` steps with
    /// time step `dt`. `None` when no window constrains anything (none
    /// given, every k = 0 or > N, every b unusable, `dt` not finite and >
    /// 0, or a prefix sum overflowed).
    pub fn new(dt: f64, turn_rate: &[Interval], windows: &[(u64, f64)]) -> Option<HeadingDrift> {
        let n = turn_rate.len();
        let usable = |&(k, b): &(u64, f64)| k >= 1 && k <= n as u64 && b >= 0.0 && b.is_finite();
        let dt_ok = dt.is_finite() && dt > 0.0;
        if !dt_ok || !windows.iter().any(usable) {
            return None;
        }
        let mut d = HeadingDrift {
            windows: Vec::new(),
            largest: 0.0,
            lo: Vec::with_capacity(n + 1),
            hi: Vec::with_capacity(n + 1),
            lo_inf: Vec::with_capacity(n + 1),
            hi_inf: Vec::with_capacity(n + 1),
        };
        let (mut a, mut c, mut na, mut nc) = (0.0f64, 0.0f64, 0u32, 0u32);
        let mut largest = 0.0f64;
        d.push(a, c, na, nc);
        for w in turn_rate {
            let s = w.scale(dt);
            if s.is_empty() {
                // An empty input: no turn rate exists; treat it as no
                // bound (the chain's own sweep reports the emptiness).
                (na, nc) = (na + 1, nc + 1);
            } else {
                if s.lo().is_finite() {
                    a += s.lo();
                } else {
                    na += 1;
                }
                if s.hi().is_finite() {
                    c += s.hi();
                } else {
                    nc += 1;
                }
            }
            largest = largest.max(a.abs()).max(c.abs());
            d.push(a, c, na, nc);
        }
        if !largest.is_finite() {
            return None;
        }
        d.largest = largest;
        for &(k, b) in windows.iter().filter(|w| usable(w)) {
            // b + R(k), rounded up.
            let r = d.rounding(k as usize).add(Interval::point(b)).hi();
            d.windows.push((k as usize, Interval::new(-r, r)));
        }
        Some(d)
    }

    /// R(k) = k·u·M, rounded up (as a point interval's enclosure): how far
    /// a prefix difference over k steps may be from the exact sum.
    fn rounding(&self, k: usize) -> Interval {
        Interval::point(k as f64)
            .mul(Interval::point(self.largest))
            .scale(UNIT_ROUNDOFF)
    }

    fn push(&mut self, a: f64, c: f64, na: u32, nc: u32) {
        self.lo.push(a);
        self.hi.push(c);
        self.lo_inf.push(na);
        self.hi_inf.push(nc);
    }

    /// N, the number of steps.
    pub fn steps(&self) -> usize {
        self.lo.len() - 1
    }

    /// The windows kept, `(k, b + R(k))`.
    pub fn windows(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.windows.iter().map(|&(k, w)| (k, w.hi()))
    }

    /// An enclosure of `S(i, k) = Σ_{j=i}^{i+k-1} dt·ω(j)` for ω in its
    /// inputs (i + k <= N).
    pub fn turn_sum(&self, i: usize, k: usize) -> Interval {
        self.widened(i, k, self.rounding(k).hi())
    }

    /// `[A(i+k) - A(i) - r, C(i+k) - C(i) + r]`, rounded outwards: with
    /// r >= R(k), an enclosure of S(i, k) widened by r - R(k). The two
    /// prefix differences are widened before they are paired (with r = 0
    /// they may cross: a point input's two rounded prefixes differ).
    fn widened(&self, i: usize, k: usize, r: f64) -> Interval {
        let j = i + k;
        let lo = if self.lo_inf[j] != self.lo_inf[i] {
            f64::NEG_INFINITY
        } else {
            Interval::point(self.lo[j])
                .sub(Interval::point(self.lo[i]))
                .sub(Interval::point(r))
                .lo()
        };
        let hi = if self.hi_inf[j] != self.hi_inf[i] {
            f64::INFINITY
        } else {
            Interval::point(self.hi[j])
                .sub(Interval::point(self.hi[i]))
                .add(Interval::point(r))
                .hi()
        };
        Interval::new(lo, hi)
    }

    /// `θ(i+k) - θ(i)` as the windows of exactly k steps bound it: the
    /// intersection of `S(i, k) + [-b, b]` over them (the whole line when
    /// none has k steps or i + k > N). O(W).
    pub fn relative_heading(&self, i: usize, k: usize) -> Interval {
        let mut h = Interval::ENTIRE;
        if i + k <= self.steps() {
            for &(wk, w) in &self.windows {
                if wk == k {
                    h = h.intersect(self.increment(i, k, w));
                }
            }
        }
        h
    }

    /// `S(i, k) + [-b, b]` for the window `w = [-(b + R(k)), b + R(k)]`
    /// of k steps.
    fn increment(&self, i: usize, k: usize, w: Interval) -> Interval {
        self.widened(i, k, w.hi())
    }

    /// One forward then one backward sweep of every window over
    /// `heading` (N + 1 intervals). Marks in `moved` (N + 1 flags) the
    /// states whose heading moved by more than `tol`. `Err(step)`: the
    /// heading of that step became empty. `Ok(changed)`.
    pub fn contract(
        &self,
        heading: &mut [Interval],
        moved: &mut [bool],
        tol: f64,
    ) -> Result<bool, usize> {
        let n = self.steps();
        assert!(
            heading.len() == n + 1 && moved.len() == n + 1,
            "a drift of {n} steps needs {} headings",
            n + 1
        );
        let mut changed = false;
        for &(k, w) in &self.windows {
            for i in 0..=n - k {
                let h = heading[i + k].intersect(heading[i] + self.increment(i, k, w));
                changed |= Self::store(heading, moved, i + k, h, tol)?;
            }
            for i in (0..=n - k).rev() {
                let h = heading[i].intersect(heading[i + k] - self.increment(i, k, w));
                changed |= Self::store(heading, moved, i, h, tol)?;
            }
        }
        Ok(changed)
    }

    /// heading[s] = h, marking s when it moved by more than `tol`.
    fn store(
        heading: &mut [Interval],
        moved: &mut [bool],
        s: usize,
        h: Interval,
        tol: f64,
    ) -> Result<bool, usize> {
        if h.is_empty() {
            return Err(s);
        }
        if h == heading[s] {
            return Ok(false);
        }
        if shrinkage(heading[s], h) > tol {
            moved[s] = true;
        }
        heading[s] = h;
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_carries_a_known_heading_forward_and_back() {
        // 20 steps turning 1 rad/s at dt 0.1: S(i, 10) = 1.
        let turn = vec![Interval::point(1.0); 20];
        let d = HeadingDrift::new(0.1, &turn, &[(10, 0.05)]).unwrap();
        let mut h = vec![Interval::ENTIRE; 21];
        h[5] = Interval::point(0.5);
        let mut moved = vec![false; 21];
        assert!(d.contract(&mut h, &mut moved, 0.0).unwrap());
        assert!(h[15].contains(1.5) && h[15].width() < 0.1 + 1e-9);
        assert!(h[15].width() > 0.1 - 1e-9);
        assert!(h[0] == Interval::ENTIRE && h[20] == Interval::ENTIRE);
        assert!(moved[15] && !moved[14] && !moved[16]);
        // And back: from th(20) to th(10) and th(0).
        h[20] = Interval::point(2.0);
        d.contract(&mut h, &mut moved, 0.0).unwrap();
        assert!(h[10].contains(1.0) && h[0].contains(0.0) && h[0].width() < 0.2 + 1e-9);
    }

    #[test]
    fn unusable_windows_give_none() {
        let turn = vec![Interval::point(1.0); 5];
        assert!(HeadingDrift::new(0.1, &turn, &[]).is_none());
        assert!(HeadingDrift::new(0.1, &turn, &[(6, 0.1), (0, 0.1)]).is_none());
        assert!(HeadingDrift::new(0.1, &turn, &[(2, f64::NAN), (2, -1.0)]).is_none());
        assert!(HeadingDrift::new(f64::NAN, &turn, &[(2, 0.1)]).is_none());
        let huge = vec![Interval::point(f64::MAX); 5];
        assert!(HeadingDrift::new(10.0, &huge, &[(2, 0.1)]).is_none());
    }

    #[test]
    fn an_unbounded_input_unbounds_the_windows_over_it() {
        let mut turn = vec![Interval::point(1.0); 10];
        turn[4] = Interval::new(0.0, f64::INFINITY);
        let d = HeadingDrift::new(0.1, &turn, &[(3, 0.0)]).unwrap();
        let s = d.turn_sum(2, 3);
        assert!(s.hi() == f64::INFINITY && s.lo() <= 0.2 && s.lo() > 0.2 - 1e-12);
        assert!(d.turn_sum(5, 3).contains(0.3) && d.turn_sum(5, 3).width() < 1e-12);
    }
}
