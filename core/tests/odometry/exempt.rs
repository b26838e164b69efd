//! Soundness of the heading drift windows that exempt steps
//! (`heading_drift[x].exempt_above`, core/src/odometry/drift.rs) with
//! planted solutions: a random heading path (headings far beyond ±π, up
//! to ±1e6) whose per-step residuals are ordinary (small, zero) or
//! flagged (large, huge); every step's `heading_error` e_j at least its
//! exact residual (touching it, or above; some infinite or NaN:
//! unbounded), so every step may be exempt; windows of random k with
//! `exempt_above` t from the bounds drawn (0, the ordinary bound, a
//! flagged one, random) or none, each window's b the exact largest
//! |sum of the residuals of the steps with e_j <= t| over the window
//! (rounded up to the next f64: the truth touches the bound), or more.
//! `contract` and `relative_heading` must keep the planted headings.
//! Case count: `PROPTEST_CASES` (default 3000).

#![allow(clippy::disallowed_methods)]
#![allow(clippy::needless_range_loop)]

use num_rational::BigRational;
use nvector_core::odometry::drift::{DriftWindow, HeadingDrift};
use nvector_core::Interval;
use proptest::prelude::*;

use crate::common;
use common::{ceil_f64, rat, Rng};

fn config() -> ProptestConfig {
    common::config(3000)
}

/// A planted chain: dt, true turn rates, headings th(0..=n), the exact
/// per-step residuals and the per-step bounds e_j >= |residual|.
struct Chain {
    dt: f64,
    omega: Vec<f64>,
    th: Vec<f64>,
    residual: Vec<BigRational>,
    e: Vec<f64>,
    ordinary: f64,
}

/// A heading: small, beyond ±π, far beyond, or huge.
fn heading(rng: &mut Rng) -> f64 {
    match rng.below(4) {
        0 => rng.range(-3.2, 3.2),
        1 => rng.range(-20.0, 20.0),
        2 => rng.range(-1e4, 1e4),
        _ => rng.range(-1e6, 1e6),
    }
}

/// A flagged step's residual: large, huge or zero.
fn flagged_residual(rng: &mut Rng) -> f64 {
    match rng.below(4) {
        0 => rng.range(-0.3, 0.3),
        1 => rng.range(-5.0, 5.0),
        2 => rng.range(-1e6, 1e6),
        _ => 0.0,
    }
}

fn chain(rng: &mut Rng, n: usize) -> Chain {
    let dt = [0.1, rng.range(1e-3, 1.0), rng.range(1.0, 100.0)][rng.below(3)];
    let scale = [0.0, 1.0, 1e6, 30.0][rng.below(4)];
    let ordinary = [0.0, 1e-3, 0.025, rng.range(0.0, 0.1)][rng.below(4)];
    let share = [0.0, 0.05, 0.2, 0.6][rng.below(4)];
    let bias = ordinary * rng.range(-1.0, 1.0);
    let mut th = vec![heading(rng)];
    let (mut omega, mut flagged) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for i in 0..n {
        let w = if rng.chance(0.1) {
            0.0
        } else {
            rng.range(-1.0, 1.0) * scale
        };
        let f = rng.chance(share);
        // Ordinary: a bias that accumulates plus a jitter that does not.
        let r = match f {
            true => flagged_residual(rng),
            false => 0.5 * bias + 0.5 * ordinary * rng.range(-1.0, 1.0),
        };
        th.push(th[i] + dt * w + r);
        omega.push(w);
        flagged.push(f);
    }
    let dtr = rat(dt);
    let residual: Vec<BigRational> = (0..n)
        .map(|j| rat(th[j + 1]) - rat(th[j]) - dtr.clone() * rat(omega[j]))
        .collect();
    let e = (0..n)
        .map(|j| {
            let r = residual[j].clone();
            let touch = ceil_f64(&if r < rat(0.0) { -r } else { r });
            match (flagged[j], rng.below(8)) {
                (true, 0) => f64::INFINITY,
                (true, 1) => f64::NAN,
                (true, 2) => touch + rng.range(0.0, 0.1),
                (true, _) => touch,
                (false, 0) => touch,
                (false, _) => touch.max(ordinary),
            }
        })
        .collect();
    Chain {
        dt,
        omega,
        th,
        residual,
        e,
        ordinary,
    }
}

/// Whether step j is exempt at t (NaN: unbounded, exempt).
fn exempt(e: f64, t: Option<f64>) -> bool {
    t.is_some_and(|t| e.is_nan() || e > t)
}

/// The exact largest |sum of the non-exempt residuals| over the windows
/// of k steps.
fn largest(c: &Chain, k: usize, t: Option<f64>) -> BigRational {
    let n = c.omega.len();
    let mut best = rat(0.0);
    for i in 0..=n - k {
        let mut s = rat(0.0);
        for j in i..i + k {
            if !exempt(c.e[j], t) {
                s += c.residual[j].clone();
            }
        }
        let a = if s < rat(0.0) { -s } else { s };
        if a > best {
            best = a;
        }
    }
    best
}

/// 1 to 6 windows, k in 1..=n, t from the bounds drawn or none, b
/// touching the truth (or above).
fn windows(rng: &mut Rng, c: &Chain) -> Vec<DriftWindow> {
    let n = c.omega.len();
    let finite: Vec<f64> = c.e.iter().copied().filter(|x| x.is_finite()).collect();
    (0..1 + rng.below(6))
        .map(|_| {
            let k = 1 + rng.below(n);
            let t = match rng.below(6) {
                0 => None,
                1 => Some(0.0),
                2 => Some(
                    finite
                        .get(rng.below(finite.len().max(1)))
                        .copied()
                        .unwrap_or(0.0),
                ),
                3 => Some(rng.range(0.0, 1.0)),
                _ => Some(c.ordinary),
            };
            let b = ceil_f64(&largest(c, k, t));
            let b = if rng.chance(0.7) {
                b
            } else {
                b + rng.range(0.0, 0.01)
            };
            DriftWindow {
                steps: k as u64,
                error: b,
                exempt_above: t,
            }
        })
        .collect()
}

/// The turn inputs: points at the truth, widened, or one-sided.
fn inputs(rng: &mut Rng, c: &Chain) -> Vec<Interval> {
    c.omega
        .iter()
        .map(|&x| {
            let w = 1e-3 + x.abs() * 1e-6;
            match rng.below(5) {
                0 | 1 => Interval::point(x),
                2 => Interval::new(x - rng.range(0.0, w), x + rng.range(0.0, w)),
                3 => Interval::new(f64::NEG_INFINITY, x),
                _ => Interval::new(x, x + rng.range(0.0, w)),
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(config())]

    /// The windows with exempt steps keep every planted heading, in
    /// `contract` (domains: points at the truth, boxes around it, or the
    /// whole line) and in `relative_heading` (every i, every k).
    #[test]
    fn exempting_windows_keep_the_planted_headings(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(40);
        let c = chain(&mut rng, n);
        prop_assume!(c.th.iter().all(|x| x.is_finite()));
        let turn = inputs(&mut rng, &c);
        let w = windows(&mut rng, &c);
        let Some(d) = HeadingDrift::new(c.dt, &turn, &c.e, &w) else {
            return Ok(());
        };
        for i in 0..n {
            for k in 1..=n - i {
                let r = d.relative_heading(i, k);
                let truth = rat(c.th[i + k]) - rat(c.th[i]);
                prop_assert!(common::holds(r, &truth), "relative_heading({i}, {k}) = {r:?} misses {truth} (windows {w:?}, e {:?})", c.e);
            }
        }
        let mut h: Vec<Interval> = c.th.iter().map(|&t| match rng.below(4) {
            0 => Interval::point(t),
            1 => Interval::new(t - rng.range(0.0, 1.0), t + rng.range(0.0, 1.0)),
            _ => Interval::ENTIRE,
        }).collect();
        let mut moved = vec![false; n + 1];
        for _ in 0..1 + rng.below(3) {
            let tol = [0.0, 1e-9, 1e-3][rng.below(3)];
            let r = d.contract(&mut h, &mut moved, tol);
            prop_assert!(r.is_ok(), "emptied at {r:?} (windows {w:?}, e {:?})", c.e);
        }
        for i in 0..=n {
            prop_assert!(h[i].contains(c.th[i]), "heading {i}: {} not in {:?} (windows {w:?})", c.th[i], h[i]);
        }
    }
}

/// The exemption is what lets the truth through: a chain with one large
/// flagged step and windows bounding only the ordinary residuals; without
/// the exempt sum the truth is cut (the statement without exemptions is
/// false here), with it the truth stays.
#[test]
fn without_the_exempt_sum_the_truth_is_cut() {
    let n = 10;
    let turn = vec![Interval::point(0.0); n];
    let mut e = vec![0.01; n];
    e[4] = 0.5;
    // th: ordinary residual 0.001 per step, 0.5 at step 4.
    let mut th = vec![0.0f64];
    for j in 0..n {
        th.push(th[j] + if j == 4 { 0.5 } else { 0.001 });
    }
    let w = [DriftWindow {
        steps: 3,
        error: 0.0031,
        exempt_above: Some(0.01),
    }];
    let d = HeadingDrift::new(1.0, &turn, &e, &w).unwrap();
    let mut h: Vec<Interval> = th.iter().map(|&t| Interval::point(t)).collect();
    h[6] = Interval::ENTIRE;
    assert!(d.contract(&mut h, &mut [false; 11], 0.0).is_ok());
    assert!(h[6].contains(th[6]));
    let plain = HeadingDrift::new(1.0, &turn, &e, &[DriftWindow::plain(3, 0.0031)]).unwrap();
    let mut h: Vec<Interval> = th.iter().map(|&t| Interval::point(t)).collect();
    assert!(plain.contract(&mut h, &mut [false; 11], 0.0).is_err());
}
