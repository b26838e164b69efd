//! The motion drift windows of odometry2d (`motion_drift`):
//! what the odometry's position error is over k steps, read between two
//! steps of the relative evidence ([`crate::odometry::relative`]).
//!
//! # Constraint
//!
//! For each window `{steps: k, error: c}` and every i with i + k <= N, the
//! Euclidean norm
//! `|p(i+k) - p(i) - sum_{j=i}^{i+k-1} s(j)(cos θ(j), sin θ(j))| <= c`,
//! with `s(j) = dt·v(j)` the true step lengths and θ(j) the true headings
//! (docs/formats.md). A window may exempt the steps whose per-step bound
//! e(j) is above `exempt_above` t: each adds `e(j)·√2` to c (the norm of a
//! vector within `[-e, e]²`), so the statement reads
//! `|...| <= c + √2 · sum_{j in [i, i+k), e(j) > t} e(j)`: a few flagged
//! steps no longer set every window's bound. The per-step `motion_error` e(j) bounds each term of
//! that sum's residual per axis; an odometry whose per-step residual is
//! mostly jitter of the reference (a motion capture's) drifts far less
//! over k steps than k·e (docs/utias-woods.md: 0.16 m against 0.25 m per
//! axis over 10 steps, 0.42 m against 2.5 m over 100).
//!
//! # Math
//!
//! In the body frame of step i (the relative pose of
//! [`crate::odometry::relative`]): `P(k) = R(-θ(i))(p(k) - p(i))` and
//! `H(j) = θ(j) - θ(i)`. Rotating the statement by `-θ(i)` keeps the
//! norm: `|P(i+k) - sum_j s(j)(cos H(j), sin H(j))| <= c`. So with the
//! *nominal* sum `Q(k) = sum_j s(j)(cos H(j), sin H(j))` enclosed from
//! the enclosures of s(j) and H(j) (no per-step error), `P(i+k)` lies in
//! `Q(k) + [-c, c]²` (a disc of radius c lies in its square). The relative
//! pose is intersected with that box at each step whose distance to i is
//! the length of a window ([`MotionDrift::bound`]). The exempt sums are
//! carried along by the relative pose, one per distinct t ([`Exempt`]),
//! as it advances step by step.
//!
//! # Soundness
//!
//! The true s(j) lie in the step-length intervals and the true H(j) in the
//! relative pose's heading enclosures (themselves sound), so the interval
//! evaluation of the nominal sum (outward rounding, core's sound sin and
//! cos) encloses the true nominal sum; the true P(i+k) differs from it by a
//! vector of norm at most c (plus the exempt steps' e(j)·√2), each axis by
//! at most that. Without exemptions the bound is used as given: `[-c, c]`
//! is exact; the exempt sums and `c + √2·X` are rounded up (interval
//! additions and products), and an infinite or NaN e(j) makes its window
//! say nothing. A window longer than N
//! constrains nothing; several windows of one length keep the smallest
//! bound (each holds, so the smallest does).
//!
//! # Complexity
//!
//! [`MotionDrift::new`] sorts the windows, O(w log w); [`MotionDrift::bound`]
//! is a binary search and the windows of k steps, O(log w + w_k);
//! [`MotionDrift::exempt_step`] O(levels) per step. Memory O(w), whatever
//! N or k.

use crate::interval::Interval;
use crate::odometry::drift::{DriftWindow, MAX_EXEMPT_LEVELS};

/// √2 rounded up (the nearest double, 1.4142135623730951, is above √2).
pub(crate) const SQRT_2_ABOVE: f64 = std::f64::consts::SQRT_2;

/// The exempt steps' `e(j)·√2` summed since the first step of a relative
/// pose, one sum per distinct `exempt_above` of the windows (rounded up).
pub type Exempt = [f64; MAX_EXEMPT_LEVELS];

/// One motion drift window: over any `steps` consecutive steps (k >= 1)
/// the position's residual against the odometry's nominal displacement
/// has a Euclidean norm of at most `error` metres (c >= 0), the steps whose
/// `motion_error` is above `exempt_above` exempt. The same data as a
/// heading drift window, read as metres.
pub type MotionWindow = DriftWindow;

/// The windows of a mission, by length, for [`MotionDrift::bound`].
#[derive(Debug, Clone, PartialEq)]
pub struct MotionDrift {
    /// (k, c, the window's level in `levels` or `NO_LEVEL`), sorted by k,
    /// k <= N; of the plain windows of one k only the smallest c.
    by_steps: Vec<(u64, f64, usize)>,
    /// The distinct `exempt_above` values, at most [`MAX_EXEMPT_LEVELS`].
    levels: Vec<f64>,
}

/// The level of a window without exemptions.
const NO_LEVEL: usize = usize::MAX;

impl MotionDrift {
    /// The windows that can constrain a chain of `steps` steps (k <= N, c
    /// a number >= 0, t a number >= 0 when given); None when none can. A
    /// window with a level beyond the first [`MAX_EXEMPT_LEVELS`] distinct
    /// ones is left out (the mission's reader refuses it before).
    pub fn new(windows: &[MotionWindow], steps: usize) -> Option<MotionDrift> {
        let mut levels: Vec<f64> = Vec::new();
        let mut by_steps: Vec<(u64, f64, usize)> = Vec::new();
        for w in windows {
            if w.steps < 1 || w.steps > steps as u64 || w.error.is_nan() || w.error < 0.0 {
                continue;
            }
            let level = match w.exempt_above {
                None => NO_LEVEL,
                Some(t) if t >= 0.0 => match levels.iter().position(|&x| x == t) {
                    Some(l) => l,
                    None if levels.len() < MAX_EXEMPT_LEVELS => {
                        levels.push(t);
                        levels.len() - 1
                    }
                    None => continue,
                },
                Some(_) => continue,
            };
            by_steps.push((w.steps, w.error, level));
        }
        // c >= 0: its bits order as the numbers do.
        crate::sort::total_by_key(&mut by_steps, |&(k, c, l)| (k, l, c.to_bits()));
        // One plain window per k (the smallest c); exempting ones all kept.
        by_steps.dedup_by(|b, a| a.0 == b.0 && a.2 == NO_LEVEL && b.2 == NO_LEVEL);
        (!by_steps.is_empty()).then_some(MotionDrift { by_steps, levels })
    }

    /// The exempt sums after step i, whose per-axis bound is `e` (module
    /// doc): `e·√2` added, rounded up, to the sum of every level below e.
    pub fn exempt_step(&self, exempt: &Exempt, e: f64) -> Exempt {
        let mut out = *exempt;
        for (x, &t) in out.iter_mut().zip(&self.levels) {
            if e.is_nan() || e > t {
                *x = if e.is_finite() && x.is_finite() {
                    let add = Interval::point(e) * Interval::point(SQRT_2_ABOVE);
                    (Interval::point(*x) + add).hi()
                } else {
                    f64::INFINITY
                };
            }
        }
        out
    }

    /// `[-r, r]` with r the tightest bound of the windows of exactly `k`
    /// steps, `exempt` the exempt sums over those k steps (module doc);
    /// None when no window has k steps or none is finite.
    pub fn bound(&self, k: usize, exempt: &Exempt) -> Option<Interval> {
        let k = k as u64;
        let first = self.by_steps.partition_point(|w| w.0 < k);
        let mut r = f64::INFINITY;
        for &(_, c, level) in self.by_steps[first..].iter().take_while(|w| w.0 == k) {
            let b = match level {
                NO_LEVEL => c,
                l if exempt[l].is_finite() => {
                    (Interval::point(c) + Interval::point(exempt[l])).hi()
                }
                _ => continue,
            };
            if b < r {
                r = b;
            }
        }
        r.is_finite().then(|| Interval::new(-r, r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(steps: u64, error: f64) -> MotionWindow {
        MotionWindow::plain(steps, error)
    }

    const NONE: Exempt = [0.0; MAX_EXEMPT_LEVELS];

    #[test]
    fn the_tightest_window_of_each_length_is_kept() {
        let d = MotionDrift::new(&[w(5, 0.3), w(2, 0.1), w(5, 0.2), w(40, 1.0)], 10).unwrap();
        assert_eq!(d.bound(5, &NONE), Some(Interval::new(-0.2, 0.2)));
        assert_eq!(d.bound(2, &NONE), Some(Interval::new(-0.1, 0.1)));
        assert_eq!(d.bound(3, &NONE), None);
        // Longer than the chain: dropped.
        assert_eq!(d.bound(40, &NONE), None);
        assert!(MotionDrift::new(&[w(40, 1.0)], 10).is_none());
        assert!(MotionDrift::new(&[], 10).is_none());
    }

    #[test]
    fn exempt_steps_add_their_bound_times_root_two() {
        let t = |steps, error, t| MotionWindow {
            steps,
            error,
            exempt_above: Some(t),
        };
        let d = MotionDrift::new(&[t(3, 0.1, 0.05), w(3, 0.5), t(3, 0.2, 0.5)], 10).unwrap();
        let mut x = NONE;
        for e in [0.01, 0.3, 0.02] {
            x = d.exempt_step(&x, e);
        }
        // Level 0 (t = 0.05) exempts the 0.3 step: 0.1 + 0.3·√2 = 0.524;
        // level 1 (t = 0.5) none: 0.2; the plain window 0.5.
        let r = d.bound(3, &x).unwrap();
        assert_eq!(r, Interval::new(-0.2, 0.2));
        let mut y = NONE;
        for e in [0.6, 0.6, 0.6] {
            y = d.exempt_step(&y, e);
        }
        // Every step exempt on both levels: 0.1 + 1.8·√2 and 0.2 +
        // 1.8·√2, above the plain 0.5.
        assert_eq!(d.bound(3, &y).unwrap(), Interval::new(-0.5, 0.5));
        let z = d.exempt_step(&NONE, f64::INFINITY);
        assert_eq!(z[0], f64::INFINITY);
        // NaN is exempt everywhere (no bound), never a small number.
        assert_eq!(d.exempt_step(&NONE, f64::NAN)[1], f64::INFINITY);
        let only = MotionDrift::new(&[t(2, 0.1, 0.0)], 5).unwrap();
        assert_eq!(only.bound(2, &only.exempt_step(&NONE, f64::INFINITY)), None);
    }
}
