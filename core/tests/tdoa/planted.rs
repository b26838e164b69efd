//! Planted-solution property tests of TDOA (core/src/tdoa): an emitter,
//! receivers, a speed, clock biases and emission times are drawn (scales
//! from 1e-3 to 1e150, zero-width and unbounded domains included), the
//! time stamps computed and declared with a slack covering the f64
//! rounding of that computation; then
//! - the arrival contractor and the paving never remove the planted
//!   position or emission time;
//! - solving problems of several emitters (ids hidden, false arrivals with
//!   `max_outliers`) keeps every truth inside and never groups pulses of
//!   two emitters;
//! - a solve stopped early (a time limit) keeps the truth, proves no wrong
//!   group, and its boxes hold the whole solve's;
//! - the radar scenario: truth inside, no matching error.
//!
//! Case count: `PROPTEST_CASES` (default 3000; the solves a tenth).

use nvector_core::interval::Interval;
use nvector_core::nvector::Contractor;
use nvector_core::tdoa::arrival::{contract_arrival, ArrivalData, PulseVars};
use nvector_core::tdoa::problem::TdoaProblem;
use nvector_core::tdoa::pulse::PulseCtx;
use nvector_core::tdoa::result::score;
use nvector_core::tdoa::simulate::{simulate_radar, RadarOptions};
use nvector_core::tdoa::{solve_tdoa, solve_tdoa_with, TdoaOptions};
use proptest::prelude::*;
use serde_json::{json, Value};

use crate::common;

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let s: f64 = (0..3).map(|i| (a[i] - b[i]) * (a[i] - b[i])).sum();
    s.sqrt()
}

/// An interval holding `x` exactly: `x ± w`, one ulp wider each side,
/// or a side unbounded when `open` says so.
fn around(x: f64, w: f64, open: u8) -> Interval {
    let lo = if open & 1 != 0 {
        f64::NEG_INFINITY
    } else {
        (x - w).next_down()
    };
    let hi = if open & 2 != 0 {
        f64::INFINITY
    } else {
        (x + w).next_up()
    };
    Interval::new(lo, hi)
}

/// The time stamp of an arrival, with a slack enclosing the exact real
/// `tau + |x - r| / c + b` (a few roundings, each relative 2^-53).
fn stamp(tau: f64, x: [f64; 3], r: [f64; 3], c: f64, b: f64, w: f64, open: u8) -> Interval {
    let travel = dist(x, r) / c;
    let t = tau + travel + b;
    let slack = 1e-12 * (tau.abs() + travel + b.abs() + t.abs()) + w;
    around(t, slack, open)
}

#[derive(Debug, Clone)]
struct Planted {
    x: [f64; 3],
    tau: f64,
    c: f64,
    rx: Vec<([f64; 3], f64)>,
    scale: f64,
    opens: Vec<u8>,
    widths: Vec<f64>,
}

fn planted() -> impl Strategy<Value = Planted> {
    let scale = prop_oneof![Just(1e-3), Just(1.0), Just(1e4), Just(1e6), Just(1e150)];
    (scale, 2usize..7, any::<u64>()).prop_map(|(scale, m, seed)| {
        let mut g = common::Rng::new(seed);
        let p = |g: &mut common::Rng| {
            [
                g.range(-scale, scale),
                g.range(-scale, scale),
                g.range(-scale, scale),
            ]
        };
        let x = p(&mut g);
        let c = if g.chance(0.2) {
            1.0
        } else {
            g.range(1e-3, 1e9)
        };
        let tau = if g.chance(0.2) {
            0.0
        } else {
            g.range(-1e3, 1e3)
        };
        let rx = (0..m)
            .map(|_| {
                (
                    p(&mut g),
                    if g.chance(0.3) {
                        0.0
                    } else {
                        g.range(-1e-6, 1e-6)
                    },
                )
            })
            .collect();
        let opens = (0..m)
            .map(|_| {
                if g.chance(0.1) {
                    (g.next() % 4) as u8
                } else {
                    0
                }
            })
            .collect();
        let widths = (0..m).map(|_| g.slack(0.3, 1e-6)).collect();
        Planted {
            x,
            tau,
            c,
            rx,
            scale,
            opens,
            widths,
        }
    })
}

fn pulse_problem(s: &Planted, region: Value) -> TdoaProblem {
    let receivers: Vec<Value> = s
        .rx
        .iter()
        .map(|(r, b)| json!({"position": r.iter().map(|v| [*v, *v]).collect::<Vec<_>>(), "clock_bias": [b, b]}))
        .collect();
    let arrivals: Vec<Value> =
        s.rx.iter()
            .enumerate()
            .map(|(i, (r, b))| {
                let t = stamp(s.tau, s.x, *r, s.c, *b, s.widths[i], s.opens[i]);
                json!({"receiver": i, "time": nvector_core::json::interval_to_json(t)})
            })
            .collect();
    TdoaProblem::from_value(&json!({
        "format": "nvector-tdoa/1",
        "propagation_speed": [s.c, s.c],
        "receivers": receivers,
        "pulses": [{"arrivals": arrivals}],
        "emitter_region": region,
    }))
    .expect("a valid problem")
}

proptest! {
    #![proptest_config(common::config(3000))]

    #[test]
    fn arrival_keeps_the_planted_solution(s in planted(), h in prop_oneof![Just(0.0), Just(1e-6), Just(1.0), Just(f64::INFINITY)]) {
        // x starts in a box of half-width h * scale around the truth (a
        // point, tight, wide, unbounded).
        let x0 = s.x.map(|c| around(c, h * s.scale, if h.is_infinite() { 3 } else { 0 }));
        let mut v = PulseVars { x: x0, tau: Interval::ENTIRE };
        for (i, (r, b)) in s.rx.iter().enumerate() {
            let rb = [Interval::point(r[0]), Interval::point(r[1]), Interval::point(r[2])];
            let a = ArrivalData {
                receiver: &rb,
                bias: Interval::point(*b),
                time: stamp(s.tau, s.x, *r, s.c, *b, s.widths[i], s.opens[i]),
                speed: Interval::new(s.c * (1.0 - 1e-9), s.c * (1.0 + 1e-9)),
            };
            prop_assert!(contract_arrival(&mut v, &a));
            prop_assert!(v.tau.contains(s.tau));
            for k in 0..3 {
                prop_assert!(v.x[k].contains(s.x[k]), "axis {k}: {:?} lost {}", v.x[k], s.x[k]);
            }
        }
    }
}

proptest! {
    #![proptest_config(common::config_div(3000, 6, 20))]

    #[test]
    fn paving_keeps_the_planted_solution(s in planted(), tight in any::<bool>()) {
        let h = if tight { s.scale * 1e-3 } else { 2.0 * s.scale };
        let region = json!([[s.x[0] - h, s.x[0] + h], [s.x[1] - h, s.x[1] + h], [s.x[2] - h, s.x[2] + h]]);
        let p = pulse_problem(&s, region);
        let kept: Vec<usize> = (0..s.rx.len()).collect();
        let ctx = PulseCtx { problem: &p, pulse: &p.pulses[0], kept: &kept };
        let v = PulseVars { x: [Interval::ENTIRE; 3], tau: Interval::ENTIRE };
        let out = ctx.pave(v, 32);
        prop_assert!(out.is_some(), "a planted pulse proved empty");
        let out = out.unwrap();
        prop_assert!(out.tau.contains(s.tau), "{:?} lost tau {}", out.tau, s.tau);
        for k in 0..3 {
            prop_assert!(out.x[k].contains(s.x[k]), "axis {k}: {:?} lost {}", out.x[k], s.x[k]);
        }
    }
}

/// A problem of `n` emitters and `k` pulses (ids hidden), with `bad`
/// arrivals replaced by wrong times and `max_outliers` = bad.
fn several(seed: u64, n: usize, k: usize, bad: usize) -> TdoaProblem {
    let mut g = common::Rng::new(seed);
    let em: Vec<[f64; 3]> = (0..n)
        .map(|_| [g.range(-1e4, 1e4), g.range(-1e4, 1e4), g.range(0.0, 100.0)])
        .collect();
    let rx: Vec<[f64; 3]> = (0..5)
        .map(|_| [g.range(-2e4, 2e4), g.range(-2e4, 2e4), g.range(0.0, 50.0)])
        .collect();
    let c = 3e8;
    let mut pulses = Vec::new();
    let mut who = Vec::new();
    for j in 0..k {
        let e = g.below(n);
        let tau = j as f64 * 1e-3;
        let arrivals: Vec<Value> = rx
            .iter()
            .enumerate()
            .map(|(i, r)| json!({"receiver": i, "time": nvector_core::json::interval_to_json(stamp(tau, em[e], *r, c, 0.0, 3e-8, 0))}))
            .collect();
        pulses.push(json!({"arrivals": arrivals, "altitude": [em[e][2] - 5.0, em[e][2] + 5.0]}));
        who.push(e);
    }
    for _ in 0..bad {
        let j = g.below(k);
        let a = g.below(5);
        // Half far (a random time), half near: the true time shifted by
        // 0.2 to 2 us, often still consistent with the other arrivals (the
        // pulse's box moves away from the truth unless that arrival is
        // dropped in some reading).
        let t = if g.chance(0.5) {
            j as f64 * 1e-3 + g.range(0.0, 2e-4)
        } else {
            let old = &pulses[j]["arrivals"][a]["time"];
            (old[0].as_f64().unwrap() + old[1].as_f64().unwrap()) / 2.0 + g.range(2e-7, 2e-6)
        };
        pulses[j]["arrivals"][a]["time"] = json!([t - 3e-8, t + 3e-8]);
    }
    TdoaProblem::from_value(&json!({
        "format": "nvector-tdoa/1",
        "propagation_speed": [c, c],
        "receivers": rx.iter().map(|r| json!({"position": [[r[0]-1.0, r[0]+1.0], [r[1]-1.0, r[1]+1.0], [r[2]-1.0, r[2]+1.0]]})).collect::<Vec<_>>(),
        "pulses": pulses,
        "emitter_count": n,
        "emitter_region": [[-2e4, 2e4], [-2e4, 2e4], [-10.0, 200.0]],
        "max_outliers": bad,
        "truth": {"positions": who.iter().map(|&e| em[e]).collect::<Vec<_>>(), "emitters": em, "matching": who},
    }))
    .expect("a valid problem")
}

proptest! {
    #![proptest_config(common::config_div(3000, 30, 10))]

    #[test]
    fn solving_keeps_the_truth_and_never_joins_two_emitters(
        seed in any::<u64>(), n in 1usize..4, k in 2usize..10, bad in 0usize..3, mode in 0usize..3,
    ) {
        let p = several(seed, n, k, bad);
        let mode = [Contractor::Projection, Contractor::Best, Contractor::Independent][mode];
        let o = TdoaOptions { mode: Some(mode), budget: 24, max_rounds: 4 };
        let s = solve_tdoa(&p, &o);
        prop_assert!(s.infeasible.is_none(), "{:?}", s.infeasible);
        let sc = score(&p, &s).unwrap();
        prop_assert!(sc.truth_inside);
        prop_assert_eq!(sc.matching_errors, 0);
    }
}

proptest! {
    #![proptest_config(common::config_div(3000, 30, 10))]

    /// Stopped early (`solve_tdoa_with` answering false, as a time limit
    /// does), a solve keeps the truth, proves no wrong group, and its boxes
    /// hold those of the whole solve (the rounds only contract).
    #[test]
    fn a_solve_stopped_early_is_sound_and_wider(
        seed in any::<u64>(), n in 1usize..4, k in 2usize..10, bad in 0usize..3, stop in 1usize..4,
    ) {
        let p = several(seed, n, k, bad);
        let o = TdoaOptions { mode: Some(Contractor::Best), budget: 24, max_rounds: 4 };
        let full = solve_tdoa(&p, &o);
        let mut asked = Vec::new();
        let cut = solve_tdoa_with(&p, &o, &mut |done| { asked.push(done); done < stop });
        prop_assert!(cut.rounds <= stop.max(1));
        prop_assert!(asked.iter().all(|&d| d >= 1 && d <= cut.rounds), "{:?}", asked);
        prop_assert!(cut.infeasible.is_none(), "{:?}", cut.infeasible);
        let sc = score(&p, &cut).unwrap();
        prop_assert!(sc.truth_inside);
        prop_assert_eq!(sc.matching_errors, 0);
        for (a, b) in cut.vars.iter().zip(&full.vars) {
            for i in 0..3 {
                prop_assert!(a.x[i].lo() <= b.x[i].lo() && b.x[i].hi() <= a.x[i].hi(),
                    "axis {}: {:?} does not hold {:?}", i, a.x[i], b.x[i]);
            }
        }
    }
}

#[test]
fn radar_scenario_truth_inside_and_no_matching_error() {
    for seed in 1..=2 {
        let o = RadarOptions {
            seed,
            emitters: 3,
            pulses: 30,
            ..RadarOptions::default()
        };
        let p = TdoaProblem::from_value(&simulate_radar(&o).unwrap()).unwrap();
        let s = solve_tdoa(
            &p,
            &TdoaOptions {
                budget: 48,
                ..TdoaOptions::default()
            },
        );
        assert!(s.infeasible.is_none(), "{:?}", s.infeasible);
        let sc = score(&p, &s).unwrap();
        assert!(sc.truth_inside, "seed {seed}");
        assert_eq!(sc.matching_errors, 0, "seed {seed}");
        assert!(
            sc.matching_recall > 0.5,
            "seed {seed}: recall {}",
            sc.matching_recall
        );
    }
}

#[test]
fn an_impossible_arrival_is_infeasible_without_outliers_and_dropped_with() {
    let p = several(7, 1, 3, 0);
    let mut doc = json!({
        "format": "nvector-tdoa/1", "propagation_speed": [3e8, 3e8],
        "receivers": [{"position": [[0,0],[0,0],[0,0]]}, {"position": [[1000,1000],[0,0],[0,0]]}],
        "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 0]}, {"receiver": 1, "time": [1e-3, 1e-3]}]}],
        "emitter_region": [[-1e4, 1e4], [-1e4, 1e4], [-1e4, 1e4]],
    });
    // 1 ms apart over a 1 km baseline: |d1 - d2| = 300 km > 1 km.
    let bad = TdoaProblem::from_value(&doc).unwrap();
    assert!(solve_tdoa(&bad, &TdoaOptions::default())
        .infeasible
        .is_some());
    doc["max_outliers"] = json!(1);
    let ok = TdoaProblem::from_value(&doc).unwrap();
    assert!(solve_tdoa(&ok, &TdoaOptions::default())
        .infeasible
        .is_none());
    assert!(p.pulses.len() == 3);
    // As for missions: a q above the arrival count reads as that count,
    // up to u32::MAX; above it, an error naming the field.
    let arrivals = ok.pulses.iter().map(|p| p.arrivals.len()).sum::<usize>();
    for q in [arrivals as u64 + 1, u64::from(u32::MAX)] {
        doc["max_outliers"] = json!(q);
        let wide = TdoaProblem::from_value(&doc).expect("q above the arrivals");
        assert_eq!(wide.max_outliers, arrivals, "q = {q}");
        assert!(solve_tdoa(&wide, &TdoaOptions::default())
            .infeasible
            .is_none());
    }
    doc["max_outliers"] = json!(u64::from(u32::MAX) + 1);
    let err = TdoaProblem::from_value(&doc).expect_err("q above u32::MAX");
    assert!(err.to_string().contains("max_outliers"), "{err}");
}

#[test]
fn errors_name_the_path() {
    let e = TdoaProblem::from_value(
        &json!({"format": "nvector-tdoa/1", "propagation_speed": [1, 2],
        "receivers": [{"position": [[0, 1], [0, 1]]}], "pulses": []}),
    )
    .unwrap_err();
    assert_eq!(e.path, "receivers[0].position");
    let e = TdoaProblem::from_value(
        &json!({"format": "nvector-tdoa/1", "propagation_speed": [1, 2],
        "receivers": [{"position": [[0, 1], [0, 1], [0, 1]]}],
        "pulses": [{"arrivals": [{"receiver": 3, "time": [0, 1]}]}]}),
    )
    .unwrap_err();
    assert_eq!(e.path, "pulses[0].arrivals[0].receiver");
    let e = TdoaProblem::from_value(
        &json!({"format": "nvector-tdoa/1", "propagation_speed": [0, 2],
        "receivers": [], "pulses": []}),
    )
    .unwrap_err();
    assert_eq!(e.path, "propagation_speed");
    let e = TdoaProblem::from_value(
        &json!({"format": "nvector-tdoa/1", "propagation_speed": [1, 2],
        "receivers": [], "pulses": [], "bogus": 1}),
    )
    .unwrap_err();
    assert!(e.message.contains("bogus"), "{}", e.message);
    let e = TdoaProblem::from_value(
        &json!({"format": "nvector-tdoa/1", "propagation_speed": [1, 2],
        "receivers": [], "pulses": [{"arrivals": [], "emitter": 2}], "emitter_count": 2}),
    )
    .unwrap_err();
    assert_eq!(e.path, "pulses[0].emitter");
}

/// An operator id near the emitter limit takes no memory of its size, and
/// operator groups are kept.
#[test]
fn a_huge_emitter_id_is_a_small_problem() {
    let mut doc: Value = serde_json::to_value(
        simulate_radar(&RadarOptions {
            seed: 5,
            emitters: 2,
            pulses: 6,
            ..RadarOptions::default()
        })
        .unwrap(),
    )
    .unwrap();
    doc["emitter_count"] = json!(1u64 << 20);
    let m = doc["truth"]["matching"].clone();
    let j = (1..6)
        .find(|&j| m[j] == m[0])
        .expect("two pulses of one emitter among 6");
    doc["pulses"][0]["emitter"] = json!((1u64 << 20) - 1);
    doc["pulses"][j]["emitter"] = json!((1u64 << 20) - 1);
    let p = TdoaProblem::from_value(&doc).unwrap();
    let s = solve_tdoa(
        &p,
        &TdoaOptions {
            mode: None,
            budget: 16,
            max_rounds: 2,
        },
    );
    assert!(s.infeasible.is_none(), "{:?}", s.infeasible);
    assert_eq!(s.groups, vec![vec![0, j]]);
    doc["emitter_count"] = json!((1u64 << 20) + 1);
    let e = TdoaProblem::from_value(&doc).unwrap_err();
    assert_eq!(e.path, "emitter_count");
}
