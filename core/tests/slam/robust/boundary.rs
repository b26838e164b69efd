//! The robust propagation (max_outliers = q > 0, core/src/slam/robust/mod.rs)
//! with its truth ON the boundary: the start is an exact point, seen by
//! q + 1 true detections (so its evidence is tight and not dropped by the
//! q-relaxed intersection), and the true robot then moves by exactly the
//! lower (or upper) bound of every displacement box the model computes:
//! the true positions are the exact real sums `p(0) + Σ D(s).lo`, not
//! floats, checked with rationals. The evidence bounds carried along the
//! chain (running sums of displacement bounds, keys relative to them) must
//! round outwards at every step to keep them; rounding to nearest loses
//! them. Exactly q false detections come on top now and then.
//!
//! `PROPTEST_CASES` sets the number of cases (common::config).

use num_rational::BigRational;
use nvector_core::shapes::shape::distance_between;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::result::SolveStatus;
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::Interval;
use proptest::prelude::*;
use serde_json::json;
use std::sync::atomic::AtomicBool;

use crate::common;
use common::planted::iv;
use common::{holds, rat, Rng};

fn run(seed: u64, q: usize, upper: bool, with_false: bool) -> Result<(), String> {
    let mut rng = Rng::new(seed);
    let steps = 10 + rng.below(150);
    let p0 = [rng.range(-5.0, 5.0), rng.range(-5.0, 5.0)];
    let landmark = [rng.range(-20.0, 20.0), rng.range(-20.0, 20.0)];
    // Motion errors with every mantissa bit in use: the sums are inexact.
    let errors: Vec<f64> = (0..steps).map(|_| rng.range(0.01, 0.3)).collect();
    let speeds: Vec<f64> = (0..steps)
        .map(|_| {
            if rng.chance(0.5) {
                0.0
            } else {
                rng.range(-0.5, 1.0)
            }
        })
        .collect();
    let headings: Vec<f64> = (0..steps).map(|_| rng.range(-3.0, 3.0)).collect();
    let pts = |x: &[f64]| -> Vec<Interval> { x.iter().map(|&c| Interval::point(c)).collect() };
    let range = distance_between(&pts(&p0), &pts(&landmark));
    let mut dets: Vec<serde_json::Value> = (0..=q)
        .map(|_| json!({"step": 0, "range": iv(range)}))
        .collect();
    if with_false {
        for _ in 0..q {
            let a = rng.range(0.0, 30.0);
            dets.push(json!({"step": rng.below(steps + 1), "range": [a, a + 1.0]}));
        }
    }
    let v = json!({
        "format": "nvector-mission/1",
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": steps,
        "initial_position": [[p0[0], p0[0]], [p0[1], p0[1]]],
        "inputs": {"speed": {"value": speeds, "error": 0}, "heading": {"value": headings, "error": 0}},
        "motion_error": errors,
        "detections": dets,
        "max_outliers": q,
    });
    let mission = Mission::from_value(&v).map_err(|e| e.to_string())?;
    // The true positions: each step moves by a bound of the model's box.
    let disp = Model::new(&mission).disp;
    let mut truth: Vec<[BigRational; 2]> = vec![[rat(p0[0]), rat(p0[1])]];
    for s in 0..steps {
        let last = truth[s].clone();
        let step = |a: usize| {
            let d = disp[s * 2 + a];
            rat(if upper { d.hi() } else { d.lo() })
        };
        truth.push([&last[0] + step(0), &last[1] + step(1)]);
    }
    let options = SolveOptions {
        association: Association::None,
        ..SolveOptions::default()
    };
    let sol = propagate(&mission, &options, &mut |_| {}, &AtomicBool::new(false));
    if let SolveStatus::Infeasible(r) = &sol.status {
        return Err(format!("infeasible: {r}"));
    }
    for (t, p) in truth.iter().enumerate() {
        for (a, v) in p.iter().enumerate() {
            let x = sol.model.pos[t * 2 + a];
            if !holds(x, v) {
                return Err(format!(
                    "p({t}) axis {a} lost: {x:?} (the truth is the exact sum of the {} bounds)",
                    if upper { "upper" } else { "lower" }
                ));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::config(300))]

    /// Module doc.
    #[test]
    fn robust_evidence_keeps_a_truth_on_the_bounds(seed in any::<u64>(), q in 1usize..4, upper in any::<bool>(), with_false in any::<bool>()) {
        run(seed, q, upper, with_false).map_err(|e| TestCaseError::fail(format!("seed {seed} q {q}: {e}")))?;
    }
}

/// The same on fixed seeds, both bounds, q = 1 (the smallest robust case).
#[test]
fn robust_evidence_keeps_the_bounds_on_fixed_seeds() {
    for seed in 0..40 {
        for upper in [false, true] {
            run(seed, 1, upper, false).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        }
    }
}
