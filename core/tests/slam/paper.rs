//! The paper's experiment end to end: simulated missions run through every
//! association mode; the truth stays inside every box and no two
//! detections of different landmarks are grouped.

use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::types::Association;

use crate::common;

use common::{solve_json, ASSOCIATIONS};

#[test]
fn paper_scenario_truth_inside_and_no_matching_error() {
    for seed in 1..=3 {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        o.steps = None;
        let mission = Mission::from_value(&simulate(&o)).expect("simulated missions are valid");
        for assoc in ASSOCIATIONS {
            let r = solve_json(&mission, assoc);
            assert_eq!(
                r["status"], "consistent",
                "seed {seed} {assoc:?}: {}",
                r["reason"]
            );
            assert_eq!(r["score"]["truth_inside"], true, "seed {seed} {assoc:?}");
            assert_eq!(r["score"]["matching_errors"], 0, "seed {seed} {assoc:?}");
            eprintln!(
                "seed {seed} {:12} max diam {:8.3} recall {:.2} rounds {}",
                assoc.name(),
                r["metrics"]["max_trajectory_diameter"]
                    .as_f64()
                    .unwrap_or(f64::INFINITY),
                r["score"]["matching_recall"],
                r["metrics"]["rounds"]
            );
        }
    }
}

#[test]
fn operator_matching_run() {
    let mut o = SimulateOptions::new(Scenario::Paper, 4);
    o.steps = Some(3000);
    o.operator = true;
    let mission = Mission::from_value(&simulate(&o)).unwrap();
    let r = solve_json(&mission, Association::None);
    assert_eq!(r["score"]["truth_inside"], true);
    assert_eq!(r["score"]["matching_errors"], 0);
    // With the operator's matching, exactly the detections of landmarks
    // seen at least twice are grouped.
    let t = mission.truth.as_ref().unwrap();
    let seen_twice = t
        .matching
        .iter()
        .filter(|&&l| t.matching.iter().filter(|&&m| m == l).count() >= 2)
        .count();
    let expected = seen_twice as f64 / t.matching.len() as f64;
    assert_eq!(r["score"]["matching_recall"].as_f64().unwrap(), expected);
    assert_eq!(r["metrics"]["matched_detections"], seen_twice);
}
