//! Soundness of the heading drift windows (`heading_drift`,
//! core/src/odometry/drift.rs) with planted solutions: a random heading
//! path (headings far beyond ±π, up to ±1e6), turn rates zero, small or
//! huge (the prefix sums then round by many ulps), turn inputs drawn
//! around the truth (points, one-sided, unbounded); each window's bound is
//! the truth's exact largest residual over the window (rational
//! arithmetic, rounded up to the next f64: the truth touches the bound),
//! or more; windows longer than N. The windows alone, and the windows with
//! the odometry chain (`OdometryChain::drift_flat`), must keep every true
//! heading and position. Case count: `PROPTEST_CASES` (default 3000).

#![allow(clippy::disallowed_methods)]
// The planted checks index several parallel arrays by step.
#![allow(clippy::needless_range_loop)]

use num_rational::BigRational;
use nvector_core::odometry::chain::OdometryChain;
use nvector_core::odometry::drift::{DriftWindow, HeadingDrift};
use nvector_core::slam::mission::Mission;
use nvector_core::Interval;
use proptest::prelude::*;

use crate::common;
use common::{floor_f64, rat, Rng};

fn config() -> ProptestConfig {
    common::config(3000)
}

/// The least f64 at least `v`.
fn ceil_f64(v: &BigRational) -> f64 {
    -floor_f64(&-v.clone())
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

/// A turn input holding `x`: the point, widened at random, one-sided, or
/// the whole line.
fn input(rng: &mut Rng, x: f64) -> Interval {
    let w = 1e-3 + x.abs() * 1e-6;
    match rng.below(6) {
        0 | 1 => Interval::point(x),
        2 => Interval::new(x - rng.range(0.0, w), x + rng.range(0.0, w)),
        3 => Interval::new(f64::NEG_INFINITY, x + rng.range(0.0, w)),
        4 => Interval::new(x - rng.range(0.0, w), f64::INFINITY),
        _ => {
            if rng.chance(0.2) {
                Interval::ENTIRE
            } else {
                Interval::point(x)
            }
        }
    }
}

/// A planted heading path: dt, true turn rates, headings th(0..=n)
/// (exact f64s: the residuals below are exact rationals).
struct Planted {
    dt: f64,
    omega: Vec<f64>,
    th: Vec<f64>,
}

fn planted(rng: &mut Rng, n: usize) -> Planted {
    let dt = match rng.below(3) {
        0 => 0.1,
        1 => rng.range(1e-3, 1.0),
        _ => rng.range(1.0, 100.0),
    };
    let scale = match rng.below(5) {
        0 => 0.0,
        1 => 1.0,
        2 => 1e6,
        3 => 1e12,
        _ => 30.0,
    };
    let drift = [0.0, 1e-3, 0.05][rng.below(3)];
    let mut th = vec![heading(rng)];
    let mut omega = Vec::with_capacity(n);
    for i in 0..n {
        let w = if rng.chance(0.1) {
            0.0
        } else {
            rng.range(-1.0, 1.0) * scale
        };
        // A bias that accumulates plus a jitter that does not.
        let f = drift * rng.range(-1.0, 1.0);
        th.push(th[i] + dt * w + f);
        omega.push(w);
    }
    Planted { dt, omega, th }
}

/// The truth's largest |th(i+k) - th(i) - Σ dt·ω(j)| over every i, exact.
fn largest_residual(p: &Planted, k: usize) -> BigRational {
    let n = p.omega.len();
    let mut best = rat(0.0);
    let dt = rat(p.dt);
    for i in 0..=n.saturating_sub(k) {
        if i + k > n {
            break;
        }
        let mut r = rat(p.th[i + k]) - rat(p.th[i]);
        for j in i..i + k {
            r -= dt.clone() * rat(p.omega[j]);
        }
        let a = if r < rat(0.0) { -r } else { r };
        if a > best {
            best = a;
        }
    }
    best
}

/// Windows for the planted path: 1 to 4, k in 1..=n+3, bound touching
/// the truth's largest residual (or above it).
fn windows(rng: &mut Rng, p: &Planted) -> Vec<DriftWindow> {
    let n = p.omega.len();
    (0..1 + rng.below(4))
        .map(|_| {
            let k = 1 + rng.below(n + 3);
            let b = ceil_f64(&largest_residual(p, k));
            let b = if rng.chance(0.5) {
                b
            } else {
                b + rng.range(0.0, 0.1)
            };
            DriftWindow::plain(k as u64, b)
        })
        .collect()
}

proptest! {
    #![proptest_config(config())]

    /// The windows alone keep every planted heading (domains: points at
    /// the truth, random boxes around it, or the whole line).
    #[test]
    fn the_windows_keep_the_planted_headings(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(40);
        let p = planted(&mut rng, n);
        prop_assume!(p.th.iter().all(|x| x.is_finite()));
        let turn: Vec<Interval> = p.omega.iter().map(|&w| input(&mut rng, w)).collect();
        let w = windows(&mut rng, &p);
        let Some(d) = HeadingDrift::new(p.dt, &turn, &[], &w) else {
            return Ok(());
        };
        let mut h: Vec<Interval> = p.th.iter().map(|&t| match rng.below(4) {
            0 => Interval::point(t),
            1 => Interval::new(t - rng.range(0.0, 1.0), t + rng.range(0.0, 1.0)),
            _ => Interval::ENTIRE,
        }).collect();
        let mut moved = vec![false; n + 1];
        for _ in 0..1 + rng.below(3) {
            let tol = [0.0, 1e-9, 1e-3][rng.below(3)];
            let r = d.contract(&mut h, &mut moved, tol);
            prop_assert!(r.is_ok(), "emptied at {r:?}");
        }
        for i in 0..=n {
            prop_assert!(h[i].contains(p.th[i]), "heading {i}: {} not in {:?} (windows {w:?})", p.th[i], h[i]);
        }
    }

    /// The window sums enclose the exact integrated turn rate of every
    /// window of every length.
    #[test]
    fn the_turn_sums_enclose_the_exact_sum(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(40);
        let p = planted(&mut rng, n);
        let turn: Vec<Interval> = p.omega.iter().map(|&w| input(&mut rng, w)).collect();
        let Some(d) = HeadingDrift::new(p.dt, &turn, &[], &[DriftWindow::plain(1, 0.0)]) else {
            return Ok(());
        };
        let dt = rat(p.dt);
        for i in 0..n {
            let mut s = rat(0.0);
            for k in 1..=n - i {
                s += dt.clone() * rat(p.omega[i + k - 1]);
                let e = d.turn_sum(i, k);
                prop_assert!(common::holds(e, &s), "S({i}, {k}) = {s} not in {e:?}");
            }
        }
    }

    /// The windows inside the chain (`drift_flat`): a planted trajectory
    /// (positions from the f64 oracle, per-step bounds at its residuals
    /// plus a margin) with per-step heading bounds left unbounded or
    /// given; the windows and the chain sweeps keep the truth.
    #[test]
    fn the_chain_with_windows_keeps_the_planted_trajectory(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(30);
        let p = planted(&mut rng, n);
        prop_assume!(p.th.iter().all(|x| x.is_finite() && x.abs() < 1e7));
        let mut pos = vec![[rng.range(-10.0, 10.0), rng.range(-10.0, 10.0)]];
        let mut v = Vec::with_capacity(n);
        let mut me = Vec::with_capacity(n);
        for i in 0..n {
            let vi = rng.range(-2.0, 2.0);
            let e = [rng.range(-0.01, 0.01), rng.range(-0.01, 0.01)];
            let s = p.dt * vi;
            pos.push([pos[i][0] + s * p.th[i].cos() + e[0], pos[i][1] + s * p.th[i].sin() + e[1]]);
            // The oracle's residual plus a margin for its rounding.
            let mag = pos[i][0].abs() + pos[i][1].abs() + pos[i + 1][0].abs() + pos[i + 1][1].abs() + s.abs() * (1.0 + p.th[i].abs());
            me.push(e[0].abs().max(e[1].abs()) + 1e-12 * (1.0 + mag));
            v.push(vi);
        }
        let speed: Vec<Interval> = v.iter().map(|&x| Interval::new(x - 1e-12, x + 1e-12)).collect();
        let turn: Vec<Interval> = p.omega.iter().map(|&w| input(&mut rng, w)).collect();
        let w = windows(&mut rng, &p);
        // Per-step heading bound: none (NaN reads as no bound), or the
        // exact one-step window.
        let he = if rng.chance(0.5) { vec![f64::NAN] } else { vec![ceil_f64(&largest_residual(&p, 1))] };
        let chain = OdometryChain::new(p.dt, &speed, &turn, &he, &me).with_drift(p.dt, &turn, &he, &w);
        let mut flat: Vec<Interval> = vec![Interval::ENTIRE; 2 * (n + 1)];
        flat[0] = Interval::point(pos[0][0]);
        flat[1] = Interval::point(pos[0][1]);
        let mut hd = vec![Interval::ENTIRE; n + 1];
        hd[0] = Interval::point(p.th[0]);
        if rng.chance(0.5) {
            hd[n] = Interval::point(p.th[n]);
        }
        for _ in 0..2 {
            let tol = [0.0, 1e-9, 1e-3][rng.below(3)];
            let a = chain.sweep_forward_flat(&mut flat, &mut hd, 0, n, tol);
            let b = chain.sweep_backward_flat(&mut flat, &mut hd, n, 0, tol);
            let c = chain.drift_flat(&mut flat, &mut hd, tol);
            prop_assert!(c.is_ok(), "{a:?} {b:?} {c:?}");
        }
        for i in 0..=n {
            prop_assert!(hd[i].contains(p.th[i]), "heading {i}: {} not in {:?}", p.th[i], hd[i]);
            prop_assert!(flat[2 * i].contains(pos[i][0]) && flat[2 * i + 1].contains(pos[i][1]),
                "position {i}: {:?} not in {:?} {:?}", pos[i], flat[2 * i], flat[2 * i + 1]);
        }
    }

    /// k = 1 is `heading_error`: a chain whose per-step heading bound is
    /// unbounded but with the window (1, e) gives the headings of the
    /// chain with `heading_error` e, up to the window's rounding bound.
    #[test]
    fn a_one_step_window_is_the_heading_error(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let n = 1 + rng.below(30);
        let dt = rng.range(0.01, 1.0);
        let turn: Vec<Interval> = (0..n).map(|_| {
            let w = rng.range(-3.0, 3.0);
            Interval::new(w - rng.range(0.0, 0.01), w + rng.range(0.0, 0.01))
        }).collect();
        let speed = vec![Interval::point(1.0); n];
        let e = rng.range(0.0, 0.05);
        let plain = OdometryChain::new(dt, &speed, &turn, &[e], &[0.01]);
        let drift = HeadingDrift::new(dt, &turn, &[], &[DriftWindow::plain(1, e)]).unwrap();
        let h0 = rng.range(-10.0, 10.0);
        let mut flat = vec![Interval::ENTIRE; 2 * (n + 1)];
        flat[0] = Interval::ZERO;
        flat[1] = Interval::ZERO;
        let mut a = vec![Interval::ENTIRE; n + 1];
        a[0] = Interval::new(h0 - 0.01, h0 + 0.01);
        let mut b = a.clone();
        plain.sweep_forward_flat(&mut flat, &mut a, 0, n, 0.0);
        drift.contract(&mut b, &mut vec![false; n + 1], 0.0).unwrap();
        for i in 0..=n {
            prop_assert!(b[i].contains(a[i].lo()) && b[i].contains(a[i].hi()), "{i}: {:?} vs {:?}", a[i], b[i]);
            let slack = 1e-12 * (1.0 + a[i].lo().abs() + a[i].hi().abs());
            prop_assert!(a[i].lo() - b[i].lo() <= slack && b[i].hi() - a[i].hi() <= slack, "{i}: {:?} vs {:?}", a[i], b[i]);
        }
    }
}

/// A window longer than the chain is vacuous; with a usable one beside
/// it, only the usable one is kept.
#[test]
fn windows_longer_than_the_chain_are_vacuous() {
    let turn = vec![Interval::point(0.5); 8];
    assert!(HeadingDrift::new(
        0.1,
        &turn,
        &[],
        &[
            DriftWindow::plain(9, 0.1),
            DriftWindow::plain(u64::MAX, 0.0)
        ]
    )
    .is_none());
    let d = HeadingDrift::new(
        0.1,
        &turn,
        &[],
        &[DriftWindow::plain(9, 0.1), DriftWindow::plain(8, 0.2)],
    )
    .unwrap();
    assert_eq!(d.windows().map(|(k, _)| k).collect::<Vec<_>>(), vec![8]);
}

/// The woods mission of `opts` with heading drift windows derived from
/// its own truth (every heading known in a simulation): for each k, the
/// largest |th(i+k) - th(i) - sum dt om| in f64 plus 1e-9 (the f64
/// oracle's rounding is far below it).
fn woods_with_windows(
    opts: &nvector_core::slam::simulate::odometry_scenario::WoodsOptions,
) -> Mission {
    let mut v = nvector_core::slam::simulate::odometry_scenario::simulate_woods(opts);
    let n = v["steps"].as_u64().unwrap() as usize;
    let dt = v["dt"].as_f64().unwrap();
    let m = Mission::from_value(&v).unwrap();
    let th: Vec<f64> = m
        .truth
        .as_ref()
        .unwrap()
        .headings
        .as_ref()
        .unwrap()
        .iter()
        .map(|h| h.unwrap())
        .collect();
    let om: Vec<f64> = m.inputs[1].iter().map(|w| w.mid()).collect();
    let mut windows = Vec::new();
    for k in [10usize, 30, 100, 300] {
        if k > n {
            continue;
        }
        let mut worst = 0.0f64;
        for i in 0..=n - k {
            let s: f64 = (i..i + k).map(|j| dt * om[j]).sum();
            // The input's own half-width, summed, is the turn's slack.
            let slack: f64 = (i..i + k)
                .map(|j| dt * (m.inputs[1][j].width() / 2.0))
                .sum();
            worst = worst.max(((th[i + k] - th[i] - s).abs() - slack).max(0.0));
        }
        windows.push(serde_json::json!({"steps": k, "error": worst + 1e-9}));
    }
    v["heading_drift"] = serde_json::Value::Array(windows);
    Mission::from_value(&v).unwrap()
}

/// The track rule with the windows (`relative::advance_from`) on planted
/// woods worlds: every union joins two detections of one true landmark,
/// and the windows join at least as much as without them somewhere.
#[test]
fn tracks_with_windows_only_join_true_pairs() {
    use nvector_core::slam::association::odometry2d::tracks::{track_unions, TrackOptions};
    use nvector_core::slam::model::Model;
    use nvector_core::slam::simulate::odometry_scenario::WoodsOptions;
    use nvector_core::union_find::Uf;
    let (mut with_total, mut without_total) = (0, 0);
    for seed in 1..=12u64 {
        let opts = WoodsOptions {
            seed: 300 + seed,
            steps: Some(400 + (seed as usize % 3) * 200),
            landmarks: Some(8 + (seed as usize % 10)),
            operator: false,
        };
        let mission = woods_with_windows(&opts);
        assert!(!mission.heading_drift.is_empty());
        let truth = mission.truth.as_ref().unwrap().matching.clone();
        let model = Model::new(&mission);
        let chain = model.odometry.as_ref().unwrap();
        assert!(chain.drift().is_some(), "seed {seed}: no window constrains");
        let mut uf = Uf::new(mission.detections.len());
        let u = track_unions(&mission, chain, &mut uf, TrackOptions::default());
        with_total += u.len();
        for (a, b) in u {
            assert!(
                truth[a].is_some() && truth[a] == truth[b],
                "seed {seed}: joined {a} and {b}"
            );
        }
        let mut plain = mission.clone();
        plain.heading_drift.clear();
        let model = Model::new(&plain);
        let mut uf = Uf::new(plain.detections.len());
        without_total += track_unions(
            &plain,
            model.odometry.as_ref().unwrap(),
            &mut uf,
            TrackOptions::default(),
        )
        .len();
    }
    assert!(
        with_total >= without_total,
        "{with_total} < {without_total}"
    );
}

/// The solver with the windows on planted woods worlds: consistent, truth
/// inside (headings and positions), no matching error.
#[test]
fn the_solver_with_windows_keeps_the_truth_on_woods_worlds() {
    use nvector_core::slam::simulate::odometry_scenario::WoodsOptions;
    use nvector_core::slam::solve::solve;
    use nvector_core::slam::types::{Association, SolveOptions};
    use std::sync::atomic::AtomicBool;
    for seed in 1..=4u64 {
        let opts = WoodsOptions {
            seed: 500 + seed,
            steps: Some(300),
            landmarks: Some(8),
            operator: false,
        };
        let mission = woods_with_windows(&opts);
        let options = SolveOptions {
            association: Association::parse("best").unwrap(),
            ..SolveOptions::default()
        };
        let v = solve(&mission, &options, &mut |_| {}, &AtomicBool::new(false));
        assert_eq!(v["status"], "consistent", "seed {seed}: {}", v["status"]);
        assert_eq!(v["score"]["truth_inside"], true, "seed {seed}");
        assert_eq!(v["score"]["matching_errors"], 0, "seed {seed}");
    }
}
