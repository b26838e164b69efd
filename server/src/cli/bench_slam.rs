//! SLAM measures of `nvector bench`: one forward+backward sweep of the
//! motion chain against a plain summing pass, the paper scenario to the
//! fixpoint, the Redermor-scale AUV survey end to end, the paper's
//! experiment over seeds 1..10 (diameter ratios, truth inside, matching),
//! propagation on a 10^6-step mission against a 10^5-step one, and `best`
//! on that mission against `none`.

use super::measure::{median_ms, paired_ms, Bench};
use nvector_core::contractors::motion_chain::{sweep_backward, sweep_forward, Sweep};
use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::{score, SolveStatus};
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::solve::{solve, solve_model};
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::Interval;
use serde_json::{json, Value};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

fn solve_with(m: &Mission, a: Association) -> Value {
    let o = SolveOptions {
        association: a,
        ..SolveOptions::default()
    };
    solve(m, &o, &mut |_| {}, &AtomicBool::new(false))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs the SLAM measures, handing each line to the bench's `emit`.
pub fn run(b: &mut Bench) {
    let runs = if b.quick { 3 } else { 15 };
    sweep_1e6_2d(b, runs);
    paper_fixpoint(b, runs);
    auv_60k_total(b, runs);
    propagate_1e6(b, runs);
    best_1e6(b);
    paper_seeds_1_10(b);
}

/// One forward + one backward sweep of the motion chain on 10^6 steps
/// against a plain summing pass.
fn sweep_1e6_2d(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("sweep_1e6_2d") else {
        return;
    };
    let n = if b.quick { 100_000 } else { 1_000_000 };
    let dim = 2;
    let disp: Vec<Interval> = (0..n * dim)
        .map(|i| {
            let x = ((i * 7919) % 1000) as f64 * 1e-3;
            Interval::new(x, x + 0.01)
        })
        .collect();
    // Positions unknown but the start (0) and the end, known to 5 mm
    // (a GPS fix): the forward sweep bounds every step from the start,
    // the backward sweep then tightens every step from the end. Both
    // directions visit all N steps (checked below).
    let mut fresh = vec![Interval::ENTIRE; (n + 1) * dim];
    fresh[0] = Interval::ZERO;
    fresh[1] = Interval::ZERO;
    let mut reckoned = fresh.clone();
    sweep_forward(&mut reckoned, &disp, dim, 0, 0.0);
    let last = n * dim;
    for a in 0..dim {
        let lo = reckoned[last + a].lo();
        fresh[last + a] = Interval::new(lo, lo + 0.005);
    }
    let visits = {
        let mut p = fresh.clone();
        let f = sweep_forward(&mut p, &disp, dim, 0, 0.0);
        let b = sweep_backward(&mut p, &disp, dim, n, 0.0);
        (f, b)
    };
    assert_eq!(
        visits,
        (Sweep::Done(n), Sweep::Done(n)),
        "both sweeps visit every step"
    );
    // Baseline: one pass summing the same arrays (both bounds of the
    // displacements and of the positions), timed in alternation.
    let (base, ms, ratio) = paired_ms(
        runs,
        || (),
        |_| {
            let mut s = 0.0f64;
            for x in disp.iter().chain(&fresh) {
                s += x.lo() + x.hi();
            }
            s
        },
        || fresh.clone(),
        |mut p| {
            sweep_forward(&mut p, &disp, dim, 0, 0.0);
            sweep_backward(&mut p, &disp, dim, n, 0.0);
            p
        },
    );
    let baseline = format!("sum_pass_1e6_2d{}", b.suffix);
    b.emit(
        json!({"name": name, "ms": ms, "baseline": baseline, "baseline_ms": base, "ratio": ratio, "goal": 3.0}),
    );
}

/// The paper scenario (seed 1) to the fixpoint with `best`.
fn paper_fixpoint(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("paper_fixpoint") else {
        return;
    };
    let m = Mission::from_value(&simulate(&SimulateOptions::new(Scenario::Paper, 1)))
        .expect("valid mission");
    let ms = median_ms(
        runs,
        || (),
        |_| solve_with(&m, Association::NVector(Contractor::Best)),
    );
    b.emit(
        json!({"name": name, "ms": ms, "steps": m.steps, "detections": m.detections.len(), "goal_ms": 50.0}),
    );
}

/// The Redermor-scale AUV survey end to end (parse + model + fixpoint).
fn auv_60k_total(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("auv_60k_total") else {
        return;
    };
    let mut o = SimulateOptions::new(Scenario::Auv, 1);
    if b.quick {
        o.steps = Some(6000);
    }
    let text = simulate(&o).to_string();
    let ms = median_ms(
        runs.min(5),
        || (),
        |_| {
            // The parse of `nvector run` and of the service's jobs:
            // straight into typed data.
            let m = Mission::from_json(&text).expect("valid mission");
            solve_with(&m, Association::NVector(Contractor::Best))
        },
    );
    b.emit(
        json!({"name": name, "ms": ms, "goal_ms": 1000.0, "what": "parse + precompute + fixpoint, best contractor"}),
    );
}

/// The paper mission of `steps` steps, seed 5 (operator's ids or not).
pub fn paper_1e6_mission(steps: usize, operator: bool) -> Mission {
    let mut o = SimulateOptions::new(Scenario::Paper, 5);
    o.steps = Some(steps);
    o.operator = operator;
    Mission::from_value(&simulate(&o)).expect("valid mission")
}

pub fn solve_options(association: Association) -> SolveOptions {
    SolveOptions {
        association,
        ..SolveOptions::default()
    }
}

/// The paper scenario with the operator's ids, seed 5, basic model: the
/// time to the fixpoint (model and propagation; the simulation and the
/// parse are not timed), against 10 times fewer steps, timed in
/// alternation. Goals: under 1 s, ratio at most 12 (linear time).
fn propagate_1e6(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("propagate_1e6") else {
        return;
    };
    let (big, small) = if b.quick {
        (100_000, 10_000)
    } else {
        (1_000_000, 100_000)
    };
    let (mb, ms_) = (paper_1e6_mission(big, true), paper_1e6_mission(small, true));
    let options = solve_options(Association::None);
    let run = |m: &Mission| solve_model(m, &options, &mut |_| {}, &AtomicBool::new(false));
    let check = run(&mb);
    let (inside, errors, _) = score(&mb, &check).expect("simulated missions have truth");
    let consistent = check.status == SolveStatus::Consistent;
    let (base, ms, ratio) = paired_ms(runs.min(7), || (), |_| run(&ms_), || (), |_| run(&mb));
    b.emit(json!({
        "name": name, "ms": ms, "baseline": format!("propagate_{small}"), "baseline_ms": base,
        "ratio": ratio, "goal_ratio": 12.0, "goal_ms": 1000.0,
        "steps": mb.steps, "detections": mb.detections.len(), "rounds": check.rounds,
        "contractions": check.contractions, "consistent": consistent,
        "truth_inside": inside, "matching_errors": errors,
    }));
}

/// `best` on the 10^6-step paper mission (seed 5), ids hidden
/// and with the operator's ids, each against `none` on the same mission:
/// the time to the fixpoint (model and propagation, like
/// `propagate_1e6`), median of 3 runs. Goals: under 0.6 s with the
/// operator's ids, under 1 s with the ids hidden.
fn best_1e6(b: &mut Bench) {
    if b.wanted("best_1e6").is_none() {
        return;
    }
    let steps = if b.quick { 100_000 } else { 1_000_000 };
    for (operator, goal) in [(true, 600.0), (false, 1000.0)] {
        let m = paper_1e6_mission(steps, operator);
        let run = |a: Association| {
            let o = solve_options(a);
            solve_model(&m, &o, &mut |_| {}, &AtomicBool::new(false))
        };
        let check = run(Association::NVector(Contractor::Best));
        let (inside, errors, recall) = score(&m, &check).expect("simulated missions have truth");
        let (base, ms, _) = paired_ms(
            3,
            || (),
            |_| run(Association::None),
            || (),
            |_| run(Association::NVector(Contractor::Best)),
        );
        let ids = if operator { "operator" } else { "hidden" };
        b.emit(json!({
            "name": format!("best_1e6_{ids}{}", b.suffix), "ms": ms, "baseline": "none", "baseline_ms": base,
            "goal_ms": goal, "steps": m.steps, "detections": m.detections.len(),
            "rounds": check.rounds, "consistent": check.status == SolveStatus::Consistent,
            "truth_inside": inside, "matching_errors": errors, "matching_recall": recall,
            "groups": check.matching.len(),
        }));
    }
}

/// The paper's experiment over seeds 1..10: diameter ratios, truth inside,
/// matching.
fn paper_seeds_1_10(b: &mut Bench) {
    let Some(name) = b.wanted("paper_seeds_1_10") else {
        return;
    };
    let seeds: Vec<u64> = if b.quick {
        (1..=3).collect()
    } else {
        (1..=10).collect()
    };
    let modes = [
        ("none", Association::None),
        ("projection", Association::NVector(Contractor::Projection)),
        ("independent", Association::NVector(Contractor::Independent)),
    ];
    let mut diam: Vec<Vec<f64>> = vec![Vec::new(); modes.len() + 1];
    let mut recall: Vec<Vec<f64>> = vec![Vec::new(); modes.len() + 1];
    let mut all_inside = true;
    let mut errors = 0u64;
    let mut ms = Vec::new();
    for &seed in &seeds {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        let m = Mission::from_value(&simulate(&o)).expect("valid mission");
        o.operator = true;
        let mo = Mission::from_value(&simulate(&o)).expect("valid mission");
        let runs = modes
            .iter()
            .map(|(_, a)| (&m, *a))
            .chain([(&mo, Association::None)]);
        for (i, (mission, a)) in runs.enumerate() {
            let t = Instant::now();
            let r = solve_with(mission, a);
            ms.push(t.elapsed().as_secs_f64() * 1e3);
            diam[i].push(
                r["metrics"]["max_trajectory_diameter"]
                    .as_f64()
                    .unwrap_or(f64::INFINITY),
            );
            recall[i].push(r["score"]["matching_recall"].as_f64().unwrap_or(0.0));
            all_inside &= r["score"]["truth_inside"] == true && r["status"] == "consistent";
            errors += r["score"]["matching_errors"].as_u64().unwrap_or(u64::MAX);
        }
    }
    b.emit(seeds_line(
        &name,
        seeds.len(),
        &diam,
        &recall,
        all_inside,
        errors,
        ms,
    ));
}

/// The line of `paper_seeds_1_10` from its per-seed figures (diameters and
/// recalls per association: none, projection, independent, operator).
fn seeds_line(
    name: &str,
    seeds: usize,
    diam: &[Vec<f64>],
    recall: &[Vec<f64>],
    all_inside: bool,
    errors: u64,
    ms: Vec<f64>,
) -> Value {
    let med: Vec<f64> = diam.iter().map(|d| median(d.clone())).collect();
    let ratios =
        |k: usize| -> Vec<f64> { diam[0].iter().zip(&diam[k]).map(|(b, x)| b / x).collect() };
    json!({
        "name": name,
        "seeds": seeds,
        "median_max_diameter": {"none": med[0], "projection": med[1], "independent": med[2], "operator": med[3]},
        "median_ratio_basic_over_projection": median(ratios(1)),
        "median_ratio_basic_over_independent": median(ratios(2)),
        "min_ratio_basic_over_projection": ratios(1).into_iter().fold(f64::INFINITY, f64::min),
        "median_operator_over_projection": median(diam[3].iter().zip(&diam[1]).map(|(o, x)| o / x).collect()),
        "median_operator_over_independent": median(diam[3].iter().zip(&diam[2]).map(|(o, x)| o / x).collect()),
        "median_recall": {"projection": median(recall[1].clone()), "independent": median(recall[2].clone())},
        "truth_inside_everywhere": all_inside,
        "matching_errors": errors,
        "goal": 10.0,
        "ms": median(ms),
    })
}
