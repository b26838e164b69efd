//! Soundness of the odometry2d pieces (core/src/odometry): a planted
//! solution (true positions, headings, landmark; inputs and measurements
//! drawn inside their intervals) survives every contraction. Headings run
//! far beyond ±π (up to ±1e6), bearings are given wrapped by any multiple of
//! 2π, speeds are signed, zero, tiny or huge, domains are points, touch the
//! truth, or are unbounded. Case count: `PROPTEST_CASES` (default 3000);
//! seeds and persisted failures: tests/common/mod.rs (`config`).
//!
//! The planted values are computed with the platform's f64 maths (an
//! oracle independent of core's libm-based code); each measurement interval
//! is widened by a margin that covers the oracle's own rounding (stated at
//! each draw), so the planted tuple is an exact real solution.

#![allow(clippy::disallowed_methods)]

use nvector_core::contractors::motion_chain::Sweep;
use nvector_core::odometry::angle::{box_angle, contract_periodic};
use nvector_core::odometry::chain::OdometryChain;
use nvector_core::odometry::sector::Sector;
use nvector_core::odometry::sensor::OffsetDetection;
use nvector_core::Interval;
use proptest::prelude::*;

use crate::common;
use common::Rng;

const TAU: f64 = 2.0 * std::f64::consts::PI;

fn config() -> ProptestConfig {
    common::config(3000)
}

/// A heading: small, beyond ±π, far beyond (±1e4), or huge (±1e6).
fn heading(rng: &mut Rng) -> f64 {
    match rng.below(5) {
        0 => rng.range(-3.2, 3.2),
        1 => rng.range(-20.0, 20.0),
        2 => rng.range(-1e4, 1e4),
        3 => rng.range(-1e6, 1e6),
        _ => (rng.below(9) as f64 - 4.0) * std::f64::consts::FRAC_PI_2,
    }
}

/// A coordinate: zero, small, large, or huge (near overflow).
fn coord(rng: &mut Rng) -> f64 {
    match rng.below(7) {
        0 => 0.0,
        6 => rng.range(-1e300, 1e300),
        1 => rng.range(-1.0, 1.0),
        2 => rng.range(-1e6, 1e6),
        3 => rng.range(-1e12, 1e12),
        _ => rng.range(-20.0, 20.0),
    }
}

/// A domain holding `x` (with the margin `m >= 0` on both sides): the
/// truth widened by the margin only (touching), by random amounts, on one
/// side, or the whole line.
fn around(rng: &mut Rng, x: f64, m: f64) -> Interval {
    let w = 1e-3 + x.abs() * 1e-6;
    let i = match rng.below(6) {
        0 => Interval::new(x - m, x + m),
        1 => Interval::new(x - m, x + m + rng.slack(0.3, 10.0 * w)),
        2 => Interval::new(x - m - rng.slack(0.3, 10.0 * w), x + m),
        3 => Interval::ENTIRE,
        4 => Interval::new(x - m - rng.range(0.0, 1.0), f64::INFINITY),
        _ => Interval::new(x - m - rng.slack(0.2, w), x + m + rng.slack(0.2, w)),
    };
    // x - m and x + m are rounded: one ulp more makes them hold x - m.
    Interval::new(i.lo().next_down(), i.hi().next_up())
}

/// The relative size of f64 rounding on values of magnitude up to `s`.
fn eps(s: f64) -> f64 {
    1e-13 * (1.0 + s)
}

proptest! {
    #![proptest_config(config())]

    /// `box_angle` and `contract_periodic`: a point v and a heading θ
    /// congruent to its direction (θ = atan2(v) + 2πk); the box around v
    /// is widened by a margin that holds the exact point at angle θ (the
    /// oracle's rounding); the heading's domain holds θ. The contracted
    /// domain must still hold θ.
    #[test]
    fn periodic_contraction_keeps_the_planted_heading(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let theta = heading(&mut rng);
        let rho = match rng.below(3) { 0 => rng.range(1e-6, 1e-3), 1 => rng.range(0.1, 10.0), _ => rng.range(1.0, 1e9) };
        let v = [rho * theta.cos(), rho * theta.sin()];
        // |computed v - exact v| <= rho * (error of cos/sin of a rounded θ).
        let m = rho * eps(theta.abs()) * 10.0;
        let x = around(&mut rng, v[0], m);
        let y = around(&mut rng, v[1], m);
        let t = around(&mut rng, theta, 0.0);
        if let Some(a) = box_angle(x, y) {
            prop_assert!(a.width() <= std::f64::consts::PI + 1e-9);
            let c = contract_periodic(t, a);
            prop_assert!(c.contains(theta), "theta {theta} t {t:?} arc {a:?} -> {c:?}");
        } else {
            prop_assert!(x.contains(0.0) && y.contains(0.0));
        }
    }

    /// The odometry chain: a random trajectory (headings far beyond ±π,
    /// signed, zero, tiny or huge speeds), inputs drawn around the truth,
    /// per-step error bounds at the oracle's residual plus a margin, random
    /// domains holding the truth; three rounds of forward and backward
    /// sweeps in a random order must keep every true position and heading.
    #[test]
    fn the_odometry_chain_keeps_the_planted_trajectory(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(30);
        let dt = match rng.below(3) { 0 => 0.1, 1 => rng.range(1e-3, 1.0), _ => rng.range(1.0, 100.0) };
        let mut th = vec![heading(&mut rng)];
        let mut p = vec![[coord(&mut rng), coord(&mut rng)]];
        let (mut v, mut w) = (Vec::new(), Vec::new());
        let scale = match rng.below(5) { 0 => 0.0, 1 => 1e-9, 2 => 1.0, 3 => 1e300, _ => 1e6 };
        for i in 0..n {
            let vi = if rng.chance(0.1) { 0.0 } else { rng.range(-2.0, 2.0) * scale };
            let wi = if rng.chance(0.1) { 0.0 } else { rng.range(-3.0, 3.0) };
            let f = rng.range(-0.01, 0.01) * rng.below(2) as f64;
            let e = [rng.range(-0.01, 0.01), rng.range(-0.01, 0.01)];
            th.push(th[i] + dt * wi + f);
            p.push([
                p[i][0] + dt * vi * th[i].cos() + e[0] * rng.below(2) as f64,
                p[i][1] + dt * vi * th[i].sin() + e[1] * rng.below(2) as f64,
            ]);
            v.push(vi);
            w.push(wi);
        }
        prop_assume!(p.iter().flatten().chain(th.iter()).all(|x| x.is_finite()));
        // The error bounds: the oracle's residuals, plus the margin of the
        // oracle's rounding on the magnitudes involved.
        let mut he = Vec::new();
        let mut me = Vec::new();
        for i in 0..n {
            let r = th[i + 1] - th[i] - dt * w[i];
            he.push(r.abs() + eps(th[i].abs() + th[i + 1].abs() + (dt * w[i]).abs()));
            let s = dt * v[i];
            let rx = p[i + 1][0] - p[i][0] - s * th[i].cos();
            let ry = p[i + 1][1] - p[i][1] - s * th[i].sin();
            let mag = p[i][0].abs() + p[i][1].abs() + p[i + 1][0].abs() + p[i + 1][1].abs() + s.abs() * (1.0 + th[i].abs());
            me.push(rx.abs().max(ry.abs()) + eps(mag));
        }
        // Inputs around the truth (dt·v is rounded: the margin covers it).
        let speed: Vec<Interval> = v.iter().map(|&x| around(&mut rng, x, eps(x.abs()))).collect();
        let turn: Vec<Interval> = w.iter().map(|&x| around(&mut rng, x, eps(x.abs()))).collect();
        let one_bound = rng.chance(0.2);
        let (he, me) = if one_bound {
            (vec![he.iter().cloned().fold(0.0, f64::max)], vec![me.iter().cloned().fold(0.0, f64::max)])
        } else {
            (he, me)
        };
        let chain = OdometryChain::new(dt, &speed, &turn, &he, &me);
        let mut pos: Vec<[Interval; 2]> = p.iter().map(|q| {
            if rng.chance(0.3) { [around(&mut rng, q[0], 0.0), around(&mut rng, q[1], 0.0)] } else { [Interval::ENTIRE; 2] }
        }).collect();
        let mut hd: Vec<Interval> = th.iter().map(|&t| if rng.chance(0.3) { around(&mut rng, t, 0.0) } else { Interval::ENTIRE }).collect();
        pos[0] = [around(&mut rng, p[0][0], 0.0), around(&mut rng, p[0][1], 0.0)];
        hd[0] = around(&mut rng, th[0], 0.0);
        for _ in 0..3 {
            let r = match rng.below(3) {
                0 => chain.contract(&mut pos, &mut hd),
                1 => chain.backward(&mut pos, &mut hd, n).and_then(|_| chain.forward(&mut pos, &mut hd, 0)),
                _ => {
                    // Stopping sweeps from a random state, with a random
                    // tolerance.
                    let (k, tol) = (rng.below(n + 1), [0.0, 1e-9, 1e-3][rng.below(3)]);
                    let a = chain.sweep_forward(&mut pos, &mut hd, k, tol);
                    let b = chain.sweep_backward(&mut pos, &mut hd, k, tol);
                    prop_assert!(!matches!(a, Sweep::Empty(_)) && !matches!(b, Sweep::Empty(_)), "{a:?} {b:?}");
                    Ok(true)
                }
            };
            prop_assert!(r.is_ok(), "emptied: {r:?}");
        }
        for i in 0..=n {
            prop_assert!(hd[i].contains(th[i]), "heading {i}: {} not in {:?}", th[i], hd[i]);
            prop_assert!(pos[i][0].contains(p[i][0]) && pos[i][1].contains(p[i][1]),
                "position {i}: {:?} not in {:?}", p[i], pos[i]);
        }
    }

    /// The offset detection: a random pose (heading far beyond ±π), sensor
    /// offset (zero, small, or large), landmark; range and bearing computed
    /// from the sensor point, the bearing wrapped by 2πk (k in -3..=3) and
    /// widened by a margin covering the oracle's rounding (which grows as
    /// the range shrinks); domains around the truth. The contraction must
    /// succeed and keep the true position, heading and landmark.
    #[test]
    fn the_offset_detection_keeps_the_planted_pose(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let mut case = planted_detection(&mut rng);
        let truth = case.truth;
        for _ in 0..1 + rng.below(3) {
            prop_assert!(case.det.contract(&mut case.p, &mut case.h, &mut case.d), "emptied: {case:?}");
        }
        prop_assert!(case.h.contains(truth.th), "heading {} not in {:?}", truth.th, case.h);
        prop_assert!(case.p[0].contains(truth.p[0]) && case.p[1].contains(truth.p[1]), "position {:?} not in {:?}", truth.p, case.p);
        prop_assert!(case.d[0].contains(truth.d[0]) && case.d[1].contains(truth.d[1]), "landmark {:?} not in {:?}", truth.d, case.d);
    }

    /// The sector: with the planted detection, every box holding the true
    /// landmark meets the sector, the heading given that box holds the
    /// true heading, the outer box holds the landmark; two detections of
    /// the same landmark from two planted poses are never called disjoint.
    #[test]
    fn sectors_keep_the_planted_landmark(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let a = planted_detection(&mut rng);
        let truth = a.truth;
        let sa = Sector::new(a.p, a.h, a.det, a.d);
        let b = [around(&mut rng, truth.d[0], 0.0), around(&mut rng, truth.d[1], 0.0)];
        prop_assert!(sa.meets(&b), "{sa:?} misses {b:?}");
        prop_assert!(sa.heading_given(&b).contains(truth.th));
        let ob = sa.outer_box();
        prop_assert!(ob[0].contains(truth.d[0]) && ob[1].contains(truth.d[1]), "outer {ob:?}");
        // A second detection of the same landmark.
        let c = planted_detection_of(&mut rng, truth.d);
        let sc = Sector::new(c.p, c.h, c.det, c.d);
        let budget = 1 + rng.below(200);
        prop_assert!(!sa.disjoint(&sc, budget) && !sc.disjoint(&sa, budget), "{sa:?} / {sc:?}");
    }
}

#[derive(Debug, Clone, Copy)]
struct Truth {
    p: [f64; 2],
    th: f64,
    d: [f64; 2],
}

#[derive(Debug, Clone, Copy)]
struct Case {
    truth: Truth,
    det: OffsetDetection,
    p: [Interval; 2],
    h: Interval,
    d: [Interval; 2],
}

fn planted_detection(rng: &mut Rng) -> Case {
    let p = [coord(rng), coord(rng)];
    let r = match rng.below(4) {
        0 => 0.0,
        1 => rng.range(1e-6, 0.1),
        2 => rng.range(0.1, 10.0),
        _ => rng.range(10.0, 1e6),
    };
    let th = heading(rng);
    let phi = rng.range(-4.0, 4.0);
    let o = match rng.below(3) {
        0 => [0.0, 0.0],
        1 => [0.219016, 0.0],
        _ => [rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)],
    };
    let s = [
        p[0] + o[0] * th.cos() - o[1] * th.sin(),
        p[1] + o[0] * th.sin() + o[1] * th.cos(),
    ];
    let d = [s[0] + r * (th + phi).cos(), s[1] + r * (th + phi).sin()];
    planted_from(rng, p, th, o, d)
}

/// A pose that sees the landmark `d` (within 10 m).
fn planted_detection_of(rng: &mut Rng, d: [f64; 2]) -> Case {
    let th = heading(rng);
    let a = rng.range(-4.0, 4.0);
    let r = rng.range(0.0, 10.0);
    let o = if rng.chance(0.5) {
        [0.0, 0.0]
    } else {
        [0.219016, 0.0]
    };
    let s = [d[0] - r * a.cos(), d[1] - r * a.sin()];
    let p = [
        s[0] - o[0] * th.cos() + o[1] * th.sin(),
        s[1] - o[0] * th.sin() - o[1] * th.cos(),
    ];
    planted_from(rng, p, th, o, d)
}

/// The measurements and domains of the planted (p, θ, o, d): the range and
/// bearing recomputed from the rounded values, widened by the margins of
/// the oracle's rounding.
fn planted_from(rng: &mut Rng, p: [f64; 2], th: f64, o: [f64; 2], d: [f64; 2]) -> Case {
    let s = [
        p[0] + o[0] * th.cos() - o[1] * th.sin(),
        p[1] + o[0] * th.sin() + o[1] * th.cos(),
    ];
    let (dx, dy) = (d[0] - s[0], d[1] - s[1]);
    let r = (dx * dx + dy * dy).sqrt();
    let mag = p[0].abs() + p[1].abs() + d[0].abs() + d[1].abs() + o[0].abs() + o[1].abs();
    // |computed s - exact s| and the differences: eps(mag) absolute.
    let abs_err = eps(mag + th.abs() * (o[0].abs() + o[1].abs()));
    let mr = 4.0 * abs_err + eps(r);
    let k = rng.below(7) as f64 - 3.0;
    let beta = dy.atan2(dx) - th + k * TAU;
    let mb = if r > 0.0 {
        4.0 * abs_err / r + eps(th.abs() + beta.abs())
    } else {
        f64::INFINITY
    };
    let range = around(rng, r, mr).intersect(Interval::new(0.0, f64::INFINITY));
    let bearing = if rng.chance(0.8) {
        Some(if mb.is_finite() && mb < 1.0 {
            around(rng, beta, mb)
        } else {
            Interval::ENTIRE
        })
    } else {
        None
    };
    let det = OffsetDetection::new(range, bearing, o);
    Case {
        truth: Truth { p, th, d },
        det,
        p: [around(rng, p[0], 0.0), around(rng, p[1], 0.0)],
        h: around(rng, th, 0.0),
        d: [around(rng, d[0], 0.0), around(rng, d[1], 0.0)],
    }
}
