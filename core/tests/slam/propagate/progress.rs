//! Progress reports of the propagator: what a user reads
//! (round, pass, detections processed, detections still moving, the fall of
//! the max trajectory diameter) is consistent with the result, the fraction
//! never decreases and is 1 exactly at the fixpoint, and cancellation stops
//! within a pass with sound boxes.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::result::{score, SolveStatus};
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::types::{Association, Progress, SolveOptions};
use std::sync::atomic::{AtomicBool, Ordering};

fn mission(seed: u64, steps: usize, operator: bool) -> Mission {
    let mut o = SimulateOptions::new(Scenario::Paper, seed);
    o.steps = Some(steps);
    o.operator = operator;
    Mission::from_value(&simulate(&o)).expect("valid")
}

#[test]
fn reports_are_consistent_with_the_result() {
    for (seed, operator, association) in [
        (1, true, Association::None),
        (2, false, Association::NVector(Contractor::Best)),
        (3, false, Association::NVector(Contractor::Projection)),
    ] {
        let m = mission(seed, 6000, operator);
        let k = m.detections.len();
        let options = SolveOptions {
            association,
            ..SolveOptions::default()
        };
        let mut reports: Vec<Progress> = Vec::new();
        let s = propagate(
            &m,
            &options,
            &mut |p| reports.push(p.clone()),
            &AtomicBool::new(false),
        );
        assert_eq!(s.status, SolveStatus::Consistent, "seed {seed}");
        assert!(
            reports.len() > 2 * s.rounds as usize,
            "seed {seed}: reports within the passes"
        );
        let last = reports.last().unwrap();
        assert_eq!((last.pass, last.round, last.moving), ("round", s.rounds, 0));
        assert_eq!(last.fraction, 1.0);
        assert_eq!(
            last.max_trajectory_diameter,
            s.model.trajectory_diameters().0,
            "seed {seed}: the last diameter is the result's"
        );
        let d0 = reports[0].initial_max_trajectory_diameter;
        let mut round_ends = 0;
        for (i, (a, b)) in reports.iter().zip(&reports[1..]).enumerate() {
            assert!(
                b.fraction >= a.fraction && a.fraction < 1.0,
                "seed {seed} report {i}: fraction {} then {}",
                a.fraction,
                b.fraction
            );
            assert!(b.round >= a.round);
            assert!(b.max_trajectory_diameter <= a.max_trajectory_diameter);
        }
        for p in &reports {
            assert!(["forward", "backward", "association", "round"].contains(&p.pass));
            assert_eq!((p.detections, p.initial_max_trajectory_diameter), (k, d0));
            assert!(p.detections_done <= k && p.moving <= k);
            assert!(p.max_trajectory_diameter <= d0);
            assert!((0.0..=1.0).contains(&p.fraction));
            round_ends += usize::from(p.pass == "round");
        }
        assert_eq!(round_ends, s.rounds as usize);
        assert!(
            last.max_trajectory_diameter < d0 / 5.0,
            "seed {seed}: the diameter falls from dead reckoning ({d0} to {})",
            last.max_trajectory_diameter
        );
    }
}

/// A cancellation seen at a report inside a pass stops there: the status
/// is stopped, the fraction stays below 1, and the boxes hold the truth.
#[test]
fn cancellation_stops_within_a_pass() {
    let m = mission(4, 8000, true);
    let cancel = AtomicBool::new(false);
    let mut reports: Vec<Progress> = Vec::new();
    let s = propagate(
        &m,
        &SolveOptions {
            association: Association::None,
            ..SolveOptions::default()
        },
        &mut |p| {
            reports.push(p.clone());
            if p.round == 2 && p.pass == "forward" {
                cancel.store(true, Ordering::Relaxed);
            }
        },
        &cancel,
    );
    assert_eq!(s.status, SolveStatus::Stopped);
    assert_eq!(s.rounds, 2);
    let last = reports.last().unwrap();
    assert_eq!((last.round, last.pass), (2, "forward"));
    assert!(last.fraction < 1.0);
    let (inside, _, _) = score(&m, &s).unwrap();
    assert!(inside, "stopped early, the boxes are still sound");
}

#[test]
fn max_rounds_stops_below_one() {
    let m = mission(5, 4000, true);
    let mut last = Progress::default();
    let s = propagate(
        &m,
        &SolveOptions {
            association: Association::None,
            max_rounds: 1,
            ..SolveOptions::default()
        },
        &mut |p| last = p.clone(),
        &AtomicBool::new(false),
    );
    assert_eq!((&s.status, s.rounds), (&SolveStatus::Stopped, 1));
    assert!(last.moving > 0 && last.fraction < 1.0);
    assert!(score(&m, &s).unwrap().0);
}

/// With false detections allowed (the robust propagation), the reports
/// follow the same rules: one `"round"` report per round, the fraction
/// rising below 1 until the last round, where nothing moves any more and
/// it is exactly 1. Consensus over subsets (q = 3 here) reports between
/// them (`"association"`, one per propagation), the fraction rising too.
#[test]
fn robust_propagation_reports_its_rounds() {
    let mut o = SimulateOptions::new(Scenario::Paper, 4);
    o.steps = Some(4000);
    o.operator = true;
    o.false_detections = 3;
    let m = Mission::from_value(&simulate(&o)).expect("valid");
    assert!(m.max_outliers > 0);
    let mut reports: Vec<Progress> = Vec::new();
    let s = propagate(
        &m,
        &SolveOptions::default(),
        &mut |p| reports.push(p.clone()),
        &AtomicBool::new(false),
    );
    assert_eq!(s.status, SolveStatus::Consistent);
    for (a, b) in reports.iter().zip(&reports[1..]) {
        assert!(b.fraction >= a.fraction && a.fraction < 1.0, "{a:?} {b:?}");
    }
    let told = reports.iter().filter(|p| p.pass == "association").count();
    assert!(told > 0, "consensus over subsets told nothing");
    for p in reports.iter().filter(|p| p.pass == "association") {
        assert!(
            p.fraction < 0.99 && p.detections_done <= p.detections,
            "{p:?}"
        );
    }
    reports.retain(|p| p.pass == "round");
    assert_eq!(reports.len(), s.rounds as usize);
    assert!(s.rounds >= 2, "{} rounds", s.rounds);
    for (a, b) in reports.iter().zip(&reports[1..]) {
        assert!(b.fraction >= a.fraction && a.fraction < 1.0, "{a:?} {b:?}");
        assert!(a.moving > 0 && b.round == a.round + 1);
    }
    let last = reports.last().unwrap();
    assert_eq!((last.fraction, last.moving, last.round), (1.0, 0, s.rounds));
    assert_eq!(
        last.max_trajectory_diameter,
        s.model.trajectory_diameters().0
    );
    assert!(reports[0].initial_max_trajectory_diameter >= reports[0].max_trajectory_diameter);
}
