//! `HeadingDrift`: the odometry2d heading drift bound over windows
//! (`heading_drift`, docs/formats.md).
//!
//! # Constraint
//!
//! For each window `(k, b)` of the mission and every i with i + k <= N:
//!
//! `|θ(i+k) - θ(i) - S(i, k)| <= b + X(i, k)`, `S(i, k) = Σ_{j=i}^{i+k-1} dt·ω(j)`,
//!
//! with ω(j) the turn rate, anywhere in its input interval (the integrated
//! turn rate is the window's input, with the input's own bounds), and
//! `X(i, k) = Σ_{j=i, e_j > t}^{i+k-1} e_j` the exempt steps' own bounds
//! when the window has `exempt_above` t (e_j the step's `heading_error`;
//! X = 0 without t): the residuals of the steps with `e_j <= t` sum to at
//! most b, each exempt step adds its own per-step bound (its residual is
//! at most e_j), so a few large single-step residuals (flagged steps) no
//! longer set every window's bound. The
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
//! `θ(i) ∩= θ(i+k) - [ΣA - b, ΣC + b]`, each window in turn. With an
//! exempt level t, b is `b + X(i, k)`, X from the prefix sums
//! `P_t(m) = fl(P_t(m-1) + e_{m-1}·[e_{m-1} > t])`: one array per
//! distinct t (at most [`MAX_EXEMPT_LEVELS`]), O(1) per window sum.
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
//! The exempt sums take the same argument: the e_j are >= 0 and the
//! prefix P_t is rounded to nearest, so `P_t(i+k) - P_t(i)` is within
//! `k·u·M_t` of the exact `X(i, k)` (M_t = P_t(N), the largest); the
//! difference is rounded up and `k·u·M_t` added, rounded up: an upper
//! bound of X, which only widens the increment. An e_j that is infinite
//! (or NaN, negative, missing: an unbounded step) above t is counted apart
//! and a window over it is unbounded (no contraction); a level whose sum
//! overflows, a ninth level, or an `exempt_above` that is NaN, negative or
//! infinite leaves its windows out (sound: fewer constraints). A step is
//! exempt by the exact comparison `e_j > t` of two f64.
//!
//! # Complexity
//!
//! O(N) to build (four arrays of N + 1, plus two per distinct
//! `exempt_above`: at most 8, never W × N), O(N) per window per
//! direction, no allocation in the sweeps and none sized by k.
//! `relative_heading(i, k)` finds the windows of k steps by binary search
//! in the windows sorted by k: O(log W) plus those windows.

use crate::interval::Interval;
use crate::odometry::angle::heading_moved;

/// u = 2^-53, the unit roundoff of f64 (round to nearest).
const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;

/// `k·u·M` rounded up (as a point interval's enclosure): how far the
/// difference of two round-to-nearest prefix sums k additions apart may be
/// from the exact sum, M the largest |prefix| (module doc, "Soundness").
fn prefix_rounding(k: usize, largest: f64) -> Interval {
    Interval::point(k as f64)
        .mul(Interval::point(largest))
        .scale(UNIT_ROUNDOFF)
}

/// The most distinct `exempt_above` values of one chain (one prefix
/// array each); a window with a ninth value is left out (sound: a
/// window less).
pub const MAX_EXEMPT_LEVELS: usize = 8;

/// One heading drift window of the mission (`heading_drift[x]`): k steps,
/// the bound b, and the optional threshold above which a step's own
/// `heading_error` is added to b instead (`exempt_above`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriftWindow {
    /// k, the window's length in steps.
    pub steps: u64,
    /// b, the bound on the non-exempt residuals over the window (rad).
    pub error: f64,
    /// The steps whose `heading_error` is above this are exempt (None:
    /// none is).
    pub exempt_above: Option<f64>,
}

impl DriftWindow {
    /// A window without exempt steps.
    pub fn plain(steps: u64, error: f64) -> DriftWindow {
        DriftWindow {
            steps,
            error,
            exempt_above: None,
        }
    }
}

/// The exempt steps of one `exempt_above` value t: prefix sums of the
/// finite `e_j > t` (rounded to nearest), a count of the infinite ones,
/// and the largest prefix (finite).
#[derive(Debug, Clone, PartialEq)]
struct Exempt {
    above: f64,
    sum: Vec<f64>,
    inf: Vec<u32>,
    largest: f64,
}

impl Exempt {
    /// The prefixes over `e` (per step, infinite when unbounded); None
    /// when the finite sum overflows.
    fn new(above: f64, e: &[f64]) -> Option<Exempt> {
        let mut x = Exempt {
            above,
            sum: Vec::with_capacity(e.len() + 1),
            inf: Vec::with_capacity(e.len() + 1),
            largest: 0.0,
        };
        let (mut s, mut c) = (0.0f64, 0u32);
        x.sum.push(s);
        x.inf.push(c);
        for &ej in e {
            if ej > above {
                if ej.is_finite() {
                    s += ej;
                } else {
                    c += 1;
                }
            }
            x.sum.push(s);
            x.inf.push(c);
        }
        x.largest = s;
        s.is_finite().then_some(x)
    }

    /// An upper bound of `Σ_{j=i}^{i+k-1} e_j` over the exempt steps:
    /// the prefix difference rounded up plus `k·u·M`, rounded up
    /// (infinite when an exempt e_j is).
    fn over(&self, i: usize, k: usize) -> f64 {
        if self.inf[i + k] != self.inf[i] {
            return f64::INFINITY;
        }
        Interval::point(self.sum[i + k])
            .sub(Interval::point(self.sum[i]))
            .add(prefix_rounding(k, self.largest))
            .hi()
    }
}

/// One window kept: k, `b + R(k)` rounded up, and the index of its
/// exempt level.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Window {
    k: usize,
    w: f64,
    level: Option<usize>,
}

/// The heading drift windows of a chain of N steps, with the prefix sums
/// of the turn inputs and of the exempt steps' bounds (see the module
/// doc).
#[derive(Debug, Clone, PartialEq)]
pub struct HeadingDrift {
    /// The windows, sorted by k (1 <= k <= N, b finite and >= 0).
    windows: Vec<Window>,
    /// One per distinct `exempt_above` (at most [`MAX_EXEMPT_LEVELS`]).
    levels: Vec<Exempt>,
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

/// `e_j`, step j's heading bound given as one number or N numbers (as
/// the chain reads `heading_error`), infinite when unbounded (NaN,
/// negative, infinite, or missing).
fn step_bound(e: &[f64], j: usize) -> f64 {
    let v = match e.len() {
        0 => 0.0,
        1 => e[0],
        _ => e.get(j).copied().unwrap_or(f64::INFINITY),
    };
    if v >= 0.0 {
        v
    } else {
        f64::INFINITY
    }
}

impl HeadingDrift {
    /// The windows over the chain of `turn_rate.len()` steps with time
    /// step `dt` and per-step heading bounds `heading_error` (one number
    /// or N, as [`crate::odometry::chain::OdometryChain::new`] reads
    /// them). `None` when no window constrains anything (none given,
    /// every k = 0 or > N, every b or `exempt_above` unusable, `dt` not
    /// finite and > 0, or a prefix sum overflowed).
    pub fn new(
        dt: f64,
        turn_rate: &[Interval],
        heading_error: &[f64],
        windows: &[DriftWindow],
    ) -> Option<HeadingDrift> {
        let n = turn_rate.len();
        let usable = |w: &&DriftWindow| {
            w.steps >= 1
                && w.steps <= n as u64
                && w.error >= 0.0
                && w.error.is_finite()
                && w.exempt_above.is_none_or(|t| t >= 0.0 && t.is_finite())
        };
        let dt_ok = dt.is_finite() && dt > 0.0;
        if !dt_ok || !windows.iter().any(|w| usable(&w)) {
            return None;
        }
        let mut d = Self::prefixes(dt, turn_rate)?;
        let e: Vec<f64> = match windows.iter().any(|w| w.exempt_above.is_some()) {
            true => (0..n).map(|j| step_bound(heading_error, j)).collect(),
            false => Vec::new(),
        };
        for w in windows.iter().filter(usable) {
            let level = match w.exempt_above {
                None => None,
                Some(t) => match d.level(t, &e) {
                    Some(l) => Some(l),
                    None => continue,
                },
            };
            let k = w.steps as usize;
            // b + R(k), rounded up.
            let r = d.rounding(k).add(Interval::point(w.error)).hi();
            d.windows.push(Window { k, w: r, level });
        }
        d.windows.sort_by_key(|w| w.k);
        (!d.windows.is_empty()).then_some(d)
    }

    /// The index of the exempt level `t`, made when new (None: a ninth
    /// level, or its sum overflowed).
    fn level(&mut self, t: f64, e: &[f64]) -> Option<usize> {
        if let Some(l) = self.levels.iter().position(|x| x.above == t) {
            return Some(l);
        }
        if self.levels.len() >= MAX_EXEMPT_LEVELS {
            return None;
        }
        self.levels.push(Exempt::new(t, e)?);
        Some(self.levels.len() - 1)
    }

    /// The turn input prefixes, no window yet (None: a prefix overflowed).
    fn prefixes(dt: f64, turn_rate: &[Interval]) -> Option<HeadingDrift> {
        let n = turn_rate.len();
        let mut d = HeadingDrift {
            windows: Vec::new(),
            levels: Vec::new(),
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
        Some(d)
    }

    /// R(k) = k·u·M, rounded up (as a point interval's enclosure): how far
    /// a prefix difference over k steps may be from the exact sum.
    fn rounding(&self, k: usize) -> Interval {
        prefix_rounding(k, self.largest)
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

    /// The windows kept, `(k, b + R(k))`, by increasing k.
    pub fn windows(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.windows.iter().map(|w| (w.k, w.w))
    }

    /// How many distinct `exempt_above` values the windows kept use.
    pub fn exempt_levels(&self) -> usize {
        self.levels.len()
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
    /// The whole line when r is infinite.
    fn widened(&self, i: usize, k: usize, r: f64) -> Interval {
        if !r.is_finite() {
            return Interval::ENTIRE;
        }
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
    /// intersection of their increments (the whole line when none has k
    /// steps or i + k > N). O(log W + the windows of k steps).
    pub fn relative_heading(&self, i: usize, k: usize) -> Interval {
        let mut h = Interval::ENTIRE;
        if i + k <= self.steps() {
            let first = self.windows.partition_point(|w| w.k < k);
            for w in self.windows[first..].iter().take_while(|w| w.k == k) {
                h = h.intersect(self.increment(i, w));
            }
        }
        h
    }

    /// `S(i, k) + [-(b + X), b + X]` for the window `w` of k steps, X the
    /// exempt steps' bounds summed over the window (0 without a level),
    /// rounded up.
    fn increment(&self, i: usize, w: &Window) -> Interval {
        let r = match w.level {
            None => w.w,
            Some(l) => Interval::point(w.w)
                .add(Interval::point(self.levels[l].over(i, w.k)))
                .hi(),
        };
        self.widened(i, w.k, r)
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
        for w in &self.windows {
            let k = w.k;
            for i in 0..=n - k {
                let h = heading[i + k].intersect(heading[i] + self.increment(i, w));
                changed |= Self::store(heading, moved, i + k, h, tol)?;
            }
            for i in (0..=n - k).rev() {
                let h = heading[i].intersect(heading[i + k] - self.increment(i, w));
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
        if heading_moved(heading[s], h) > tol {
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
        let d = HeadingDrift::new(0.1, &turn, &[], &[DriftWindow::plain(10, 0.05)]).unwrap();
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
        assert!(HeadingDrift::new(0.1, &turn, &[], &[]).is_none());
        assert!(HeadingDrift::new(
            0.1,
            &turn,
            &[],
            &[DriftWindow::plain(6, 0.1), DriftWindow::plain(0, 0.1)]
        )
        .is_none());
        assert!(HeadingDrift::new(
            0.1,
            &turn,
            &[],
            &[DriftWindow::plain(2, f64::NAN), DriftWindow::plain(2, -1.0)]
        )
        .is_none());
        assert!(HeadingDrift::new(f64::NAN, &turn, &[], &[DriftWindow::plain(2, 0.1)]).is_none());
        let huge = vec![Interval::point(f64::MAX); 5];
        assert!(HeadingDrift::new(10.0, &huge, &[], &[DriftWindow::plain(2, 0.1)]).is_none());
    }

    #[test]
    fn an_unbounded_input_unbounds_the_windows_over_it() {
        let mut turn = vec![Interval::point(1.0); 10];
        turn[4] = Interval::new(0.0, f64::INFINITY);
        let d = HeadingDrift::new(0.1, &turn, &[], &[DriftWindow::plain(3, 0.0)]).unwrap();
        let s = d.turn_sum(2, 3);
        assert!(s.hi() == f64::INFINITY && s.lo() <= 0.2 && s.lo() > 0.2 - 1e-12);
        assert!(d.turn_sum(5, 3).contains(0.3) && d.turn_sum(5, 3).width() < 1e-12);
    }

    fn exempt(steps: u64, error: f64, t: f64) -> DriftWindow {
        DriftWindow {
            steps,
            error,
            exempt_above: Some(t),
        }
    }

    #[test]
    fn exempt_steps_add_their_own_bound() {
        // 10 steps, no turn; step 4 flagged (0.3), the others 0.01.
        let turn = vec![Interval::point(0.0); 10];
        let mut e = vec![0.01; 10];
        e[4] = 0.3;
        let d = HeadingDrift::new(0.1, &turn, &e, &[exempt(3, 0.02, 0.01)]).unwrap();
        // Windows [0, 3) and [5, 8): b = 0.02; [3, 6) holds step 4.
        let a = d.relative_heading(0, 3);
        assert!(a.hi() >= 0.02 && a.hi() < 0.02 + 1e-12 && a.lo() <= -0.02);
        assert!(d.relative_heading(5, 3).hi() < 0.02 + 1e-12);
        let c = d.relative_heading(3, 3);
        assert!(c.hi() >= 0.32 && c.hi() < 0.32 + 1e-12 && c.lo() <= -0.32);
        // Not a window length: the whole line.
        assert_eq!(d.relative_heading(0, 2), Interval::ENTIRE);
        assert_eq!(d.exempt_levels(), 1);
    }

    #[test]
    fn an_unbounded_exempt_step_unbounds_its_windows() {
        let turn = vec![Interval::point(0.0); 8];
        let mut e = vec![0.01; 8];
        e[2] = f64::INFINITY;
        e[5] = f64::NAN;
        let d = HeadingDrift::new(1.0, &turn, &e, &[exempt(2, 0.0, 0.01)]).unwrap();
        assert_eq!(d.relative_heading(1, 2), Interval::ENTIRE);
        assert_eq!(d.relative_heading(5, 2), Interval::ENTIRE);
        assert!(d.relative_heading(3, 2).hi() < 1e-12);
        let mut h = vec![Interval::point(0.0); 9];
        h[3] = Interval::ENTIRE;
        d.contract(&mut h, &mut [false; 9], 0.0).unwrap();
        assert!(h[3].width() < 1e-12);
    }

    #[test]
    fn exempt_levels_are_shared_and_capped() {
        let turn = vec![Interval::point(0.0); 12];
        let e = vec![0.5; 12];
        // Ten levels over windows of 1..=10 steps: eight kept.
        let w: Vec<DriftWindow> = (1..=10).map(|k| exempt(k, 0.1, 0.01 * k as f64)).collect();
        let d = HeadingDrift::new(1.0, &turn, &e, &w).unwrap();
        assert_eq!(d.exempt_levels(), MAX_EXEMPT_LEVELS);
        assert_eq!(d.windows().count(), 8);
        // One level for many windows; unusable thresholds left out.
        let mut w: Vec<DriftWindow> = (1..=12).map(|k| exempt(k, 0.1, 0.2)).collect();
        w.push(exempt(2, 0.1, f64::NAN));
        w.push(exempt(2, 0.1, -1.0));
        w.push(exempt(2, 0.1, f64::INFINITY));
        let d = HeadingDrift::new(1.0, &turn, &e, &w).unwrap();
        assert_eq!((d.exempt_levels(), d.windows().count()), (1, 12));
        assert!(HeadingDrift::new(1.0, &turn, &e, &w[12..]).is_none());
        // Sorted by k whatever the order given.
        let w = [DriftWindow::plain(5, 0.1), DriftWindow::plain(2, 0.1)];
        let d = HeadingDrift::new(1.0, &turn, &[], &w).unwrap();
        assert_eq!(d.windows().map(|w| w.0).collect::<Vec<_>>(), vec![2, 5]);
        assert!(d.relative_heading(0, 5).hi() < 0.1 + 1e-12);
    }
}
