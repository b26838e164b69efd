//! The minimum separation inside the passes
//! (core/src/slam/association/odometry2d/sequential.rs), with planted solutions:
//! landmarks at least s apart, detection boxes that hold their true
//! landmark (narrow, wide, zero-width, unbounded, far from the origin),
//! read in a random order as a pass reads them. The rule must never join
//! detections of two true landmarks and never call the planted world
//! infeasible; and it must join something (a rule that merges nothing
//! passes the first two checks).
//!
//! Then the whole solver on woods missions (ids hidden, `best`): truth
//! inside and no matching error.

#![allow(clippy::disallowed_methods)]

use nvector_core::ibox::IntervalBox;
use nvector_core::rng::Rng;
use nvector_core::slam::association::odometry2d::sequential::SeparationGrid;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use nvector_core::union_find::Uf;
use nvector_core::Interval;

/// Landmarks at least `s` apart (rejection sampling in a square whose
/// side grows with their number), shifted by `origin`.
fn landmarks(rng: &mut Rng, n: usize, s: f64, origin: f64) -> Vec<[f64; 2]> {
    let side = s * (n as f64).sqrt() * 2.5;
    let mut out: Vec<[f64; 2]> = Vec::new();
    while out.len() < n {
        let c = [origin + rng.unit() * side, origin + rng.unit() * side];
        if out
            .iter()
            .all(|l| ((l[0] - c[0]).powi(2) + (l[1] - c[1]).powi(2)).sqrt() >= s)
        {
            out.push(c);
        }
    }
    out
}

/// A box holding `l`: each side from the landmark by a random share of
/// `w` (0: a point box; infinite: unbounded).
fn box_around(rng: &mut Rng, l: [f64; 2], w: f64) -> IntervalBox {
    let axis = |rng: &mut Rng, x: f64| {
        if w.is_infinite() {
            return Interval::new(f64::NEG_INFINITY, f64::INFINITY);
        }
        let a = rng.unit() * w;
        let b = rng.unit() * w;
        // Outward: the rounding of x - a and x + b must not lose x.
        Interval::new((x - a).min(x), (x + b).max(x))
    };
    IntervalBox::new(&[axis(rng, l[0]), axis(rng, l[1])])
}

#[test]
fn planted_boxes_only_join_detections_of_one_landmark() {
    let mut rng = Rng::from_state(20);
    let mut joined = 0usize;
    for case in 0..3000 {
        let s = match case % 4 {
            0 => 1.5,
            1 => 1e-3,
            2 => 1e4,
            _ => 0.2 + rng.unit() * 3.0,
        };
        let origin = match case % 5 {
            0 => 1e9,
            1 => -1e12,
            _ => 0.0,
        };
        let n = 1 + (rng.next_u64() % 25) as usize;
        let lm = landmarks(&mut rng, n, s, origin);
        let k = 1 + (rng.next_u64() % 120) as usize;
        let mut truth = Vec::with_capacity(k);
        let mut det = Vec::with_capacity(k);
        for _ in 0..k {
            let t = (rng.next_u64() % n as u64) as usize;
            let w = match rng.next_u64() % 8 {
                0 => 0.0,
                1 => f64::INFINITY,
                2 => s * (1.0 + rng.unit() * 3.0),
                _ => s * rng.unit() * 0.7,
            };
            truth.push(t);
            det.push(box_around(&mut rng, lm[t], w));
        }
        let mut uf = Uf::new(k);
        // Some detections start in proved groups (tracks): true pairs.
        for _ in 0..k / 4 {
            let a = (rng.next_u64() % k as u64) as usize;
            let b = (rng.next_u64() % k as u64) as usize;
            if truth[a] == truth[b] {
                uf.union(a, b);
            }
        }
        // Root boxes: the intersection of their members' (as the rounds
        // hold them).
        for j in 0..k {
            let r = uf.find(j);
            if r != j {
                let b = det[j].clone();
                det[r].intersect_with(&b);
            }
        }
        let mut grid = SeparationGrid::new(k, s).expect("s > 0");
        for _ in 0..2 {
            for j in 0..k {
                let u = grid.merge(&mut det, &mut uf, j).unwrap_or_else(|e| {
                    panic!("case {case}: planted world called infeasible: {e}")
                });
                for (a, b) in u {
                    assert_eq!(truth[a], truth[b], "case {case}: joined {a} and {b}");
                    joined += 1;
                }
            }
        }
        for a in 0..k {
            let ra = uf.find(a);
            let l = lm[truth[a]];
            assert!(
                det[ra][0].contains(l[0]) && det[ra][1].contains(l[1]),
                "case {case}: the group box of {a} lost its landmark"
            );
            for b in a + 1..k {
                if uf.find(b) == ra {
                    assert_eq!(truth[a], truth[b], "case {case}: {a} and {b} in one group");
                }
            }
        }
    }
    assert!(joined > 1000, "the rule joined only {joined} pairs");
}

/// The whole solver with the rule, ids hidden, `best`, short woods
/// missions (headings beyond ±pi as the robot circles, bearings wrapped
/// into (-pi, pi] by the generator): truth inside, no matching error.
#[test]
fn woods_missions_keep_the_truth_and_make_no_error() {
    use nvector_core::slam::result::score;
    use nvector_core::slam::solve::solve_model;
    use nvector_core::slam::types::SolveOptions;
    use std::sync::atomic::AtomicBool;
    for seed in [2u64, 4, 7] {
        let m = simulate_woods(&WoodsOptions {
            seed,
            steps: Some(400),
            landmarks: Some(9 + seed as usize),
            operator: false,
        });
        let mission = Mission::from_value(&m).expect("a woods mission");
        // The default: `best`.
        let options = SolveOptions::default();
        let sol = solve_model(&mission, &options, &mut |_| {}, &AtomicBool::new(false));
        let (inside, errors, recall) = score(&mission, &sol).expect("truth");
        assert!(inside, "seed {seed}: truth outside");
        assert_eq!(errors, 0, "seed {seed}");
        assert!(recall > 0.5, "seed {seed}: recall {recall}");
    }
}
