//! The shapes' incremental schedule of `best` (a group whose
//! inputs did not move is not worked again; with every landmark named by
//! the operator the names give the distinct pairs instead of the shapes)
//! may only skip work that proves nothing: on random missions (the paper
//! scenario over seeds, layouts, range-only or not, operator ids or
//! hidden; the woods scenario, odometry2d), every box of `rounds` lies in
//! the box of `rounds_full_shapes` (the full work in every round, the
//! schedule before), its groups hold the full work's groups, and the truth
//! lies in every box. A schedule that skips work that tightens (as running
//! the shapes only in rounds where the cheap contractors settled did, see
//! BENCHMARKS.md) fails here.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagate::rounds::{rounds, rounds_full_shapes};
use nvector_core::slam::result::{score, Solution, SolveStatus};
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use nvector_core::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::Interval;
use std::sync::atomic::AtomicBool;

/// Whether `a` lies in `b` (an empty `a` lies in everything).
fn inside(a: Interval, b: Interval) -> bool {
    a.is_empty() || (!b.is_empty() && b.lo() <= a.lo() && a.hi() <= b.hi())
}

/// The first box of `new` (positions, then detections) not inside the
/// matching box of `old`, named.
fn wider(new: &Solution, old: &Solution) -> Option<String> {
    let pos = new.model.pos.iter().zip(&old.model.pos).enumerate();
    for (i, (&a, &b)) in pos {
        if !inside(a, b) {
            return Some(format!("position value {i}: {a:?} not in {b:?}"));
        }
    }
    for (j, (a, b)) in new.model.det.iter().zip(&old.model.det).enumerate() {
        for x in 0..a.dim() {
            if !inside(a[x], b[x]) {
                return Some(format!(
                    "detection {j} axis {x}: {:?} not in {:?}",
                    a[x], b[x]
                ));
            }
        }
    }
    None
}

/// Whether every group of `old` lies in one group of `new`.
fn refines(new: &[Vec<usize>], old: &[Vec<usize>]) -> bool {
    old.iter()
        .all(|g| new.iter().any(|h| g.iter().all(|j| h.contains(j))))
}

/// Solves `mission` both ways with `best`; panics naming `what` unless
/// the incremental result is the full one or tighter. Returns whether the
/// two differ at all (a box or a group).
fn compare(mission: &Mission, what: &str) -> bool {
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    let new = rounds(mission, &options, &mut |_| {}, &cancel);
    let old = rounds_full_shapes(mission, &options, &mut |_| {}, &cancel);
    match (&new.status, &old.status) {
        (SolveStatus::Consistent, SolveStatus::Consistent) => {}
        (SolveStatus::Infeasible(_), SolveStatus::Infeasible(_)) => return false,
        (a, b) => panic!("{what}: status {a:?} against the full work's {b:?}"),
    }
    let (truth, errors, _) = score(mission, &new).expect("simulated missions have truth");
    assert!(truth, "{what}: the truth is outside a box");
    assert_eq!(errors, 0, "{what}: matching errors");
    if let Some(w) = wider(&new, &old) {
        panic!("{what}: a box is wider than with the full work: {w}");
    }
    assert!(
        refines(&new.matching, &old.matching),
        "{what}: a group of the full work is lost"
    );
    wider(&old, &new).is_some() || new.matching != old.matching
}

fn paper(seed: u64, layout: Layout, range_only: bool, operator: bool, steps: usize) -> Mission {
    let mut o = SimulateOptions::new(Scenario::Paper, seed);
    o.steps = Some(steps);
    o.layout = layout;
    o.range_only = range_only;
    o.operator = operator;
    Mission::from_value(&simulate(&o)).expect("a simulated mission is valid")
}

/// Missions per layout and mode: 6, or `PROPTEST_CASES` / 50 (at least 2).
fn cases() -> u64 {
    ["PROPTEST_CASES", "NVECTOR_PROPTEST_CASES"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.parse::<u64>().ok())
        .map_or(6, |c| (c / 50).max(2))
}

#[test]
fn the_incremental_shapes_give_the_full_boxes_or_tighter_on_the_paper_scenario() {
    let mut differ = 0;
    let mut runs = 0;
    for seed in 1..=cases() {
        for layout in [Layout::Line, Layout::Ring, Layout::Random] {
            for (range_only, operator) in
                [(false, false), (true, false), (false, true), (true, true)]
            {
                let steps = 600 + 300 * (seed as usize % 4);
                let m = paper(seed, layout, range_only, operator, steps);
                let what = format!(
                    "paper seed {seed} {} range_only {range_only} operator {operator} steps {steps}",
                    layout.name()
                );
                differ += usize::from(compare(&m, &what));
                runs += 1;
            }
        }
    }
    eprintln!("{differ} of {runs} missions differ from the full work (tighter)");
}

#[test]
fn the_incremental_shapes_give_the_full_boxes_or_tighter_on_the_woods_scenario() {
    for seed in 1..=2 {
        for operator in [false, true] {
            let v = simulate_woods(&WoodsOptions {
                seed,
                steps: Some(400),
                landmarks: None,
                operator,
            });
            let m = Mission::from_value(&v).expect("a simulated mission is valid");
            compare(&m, &format!("woods seed {seed} operator {operator}"));
        }
    }
}
