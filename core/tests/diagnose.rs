//! The minimal correction set of an infeasible mission: removing it makes
//! the propagation consistent, and putting any one of its detections back
//! makes it infeasible again (both re-checked here by running the
//! propagator on the sub-missions, independently of the search).

use nvector_core::slam::diagnose::minimal_correction;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagator::{solve_model, Association, SolveOptions};
use nvector_core::slam::result::SolveStatus;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use serde_json::json;
use std::sync::atomic::AtomicBool;

fn options() -> SolveOptions {
    SolveOptions {
        association: Association::None,
        ..SolveOptions::default()
    }
}

fn infeasible(m: &Mission, keep: impl Fn(usize) -> bool) -> bool {
    let mut sub = m.clone();
    sub.detections = (0..m.detections.len())
        .filter(|&j| keep(j))
        .map(|j| m.detections[j].clone())
        .collect();
    sub.detection_count = sub.detections.len();
    sub.truth = None;
    let s = solve_model(&sub, &options(), &mut |_| {}, &AtomicBool::new(false));
    matches!(s.status, SolveStatus::Infeasible(_))
}

fn check_minimal_correction(m: &Mission) -> Vec<usize> {
    assert!(
        infeasible(m, |_| true),
        "the planted errors make it infeasible"
    );
    let c = minimal_correction(m, &options(), &AtomicBool::new(false), 500)
        .expect("detections are the cause");
    eprintln!("correction {c:?}");
    assert!(c.minimal, "{c:?}");
    assert!(!c.detections.is_empty());
    assert!(
        !infeasible(m, |j| !c.detections.contains(&j)),
        "removing {:?} restores consistency",
        c.detections
    );
    for &x in &c.detections {
        assert!(
            infeasible(m, |j| j == x || !c.detections.contains(&j)),
            "{x} put back alone must be infeasible: {:?}",
            c.detections
        );
    }
    c.detections
}

#[test]
fn a_range_off_its_bounds_is_named() {
    let mut o = SimulateOptions::new(Scenario::Paper, 21);
    o.steps = Some(3000);
    o.operator = true;
    let mut v = simulate(&o);
    // Detection 5's range interval moved 8 m off the true distance.
    let r = v["detections"][5]["range"].clone();
    let (lo, hi) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
    v["detections"][5]["range"] = json!([lo + 8.0, hi + 8.0]);
    let m = Mission::from_value(&v).unwrap();
    let c = check_minimal_correction(&m);
    assert!(c.len() <= 3, "a small set for one bad measurement: {c:?}");
}

#[test]
fn two_wrong_labels_give_a_minimal_set() {
    let mut o = SimulateOptions::new(Scenario::Paper, 13);
    o.steps = Some(4000);
    o.operator = true;
    let mut v = simulate(&o);
    let truth: Vec<u64> = v["truth"]["matching"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    let k = truth.len();
    for j in [k / 3, 2 * k / 3] {
        let wrong = (truth[j] + 1) % 4;
        v["detections"][j]["landmark"] = json!(wrong);
    }
    let m = Mission::from_value(&v).unwrap();
    check_minimal_correction(&m);
}

#[test]
fn motion_data_at_fault_names_no_detection() {
    let mut o = SimulateOptions::new(Scenario::Paper, 2);
    o.steps = Some(1000);
    let mut v = simulate(&o);
    // A final position far from where the inputs can lead.
    v["final_position"] = json!([[500, 501], [500, 501]]);
    let m = Mission::from_value(&v).unwrap();
    assert!(minimal_correction(&m, &options(), &AtomicBool::new(false), 100).is_none());
}

#[test]
fn a_consistent_mission_has_nothing_to_correct() {
    let mut o = SimulateOptions::new(Scenario::Paper, 4);
    o.steps = Some(1500);
    let m = Mission::from_value(&simulate(&o)).unwrap();
    assert!(minimal_correction(&m, &options(), &AtomicBool::new(false), 100).is_none());
}
