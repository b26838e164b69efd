//! Properties of the SLAM engine on simulated missions: truth inside and no
//! matching error for every contractor on many random missions; the truth
//! is never read; the same input gives the same bits; a wrong operator
//! matching is proved infeasible.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::types::Association;
use proptest::prelude::*;

use common::{solve_json, ASSOCIATIONS};

use crate::common;

proptest! {
    #![proptest_config(common::config_div(3000, 15, 10))]

    #[test]
    fn random_small_missions_keep_the_truth(seed in 0u64..1_000_000, steps in 200usize..2500, landmarks in 1usize..6, noise in 0.2..3.0f64, operator in any::<bool>()) {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        o.steps = Some(steps);
        o.landmarks = Some(landmarks);
        o.noise = noise;
        o.operator = operator;
        let mission = Mission::from_value(&simulate(&o)).expect("valid");
        for assoc in ASSOCIATIONS {
            let r = solve_json(&mission, assoc);
            prop_assert_eq!(&r["status"], "consistent", "seed {} {:?}: {}", seed, assoc, r["reason"]);
            prop_assert_eq!(&r["score"]["truth_inside"], true, "seed {} {:?}", seed, assoc);
            prop_assert_eq!(&r["score"]["matching_errors"], 0, "seed {} {:?}", seed, assoc);
        }
    }
}

#[test]
fn the_truth_is_never_read() {
    let mut o = SimulateOptions::new(Scenario::Paper, 11);
    o.steps = Some(3000);
    let with = simulate(&o);
    let mut without = with.clone();
    without.as_object_mut().unwrap().remove("truth");
    let a = solve_json(
        &Mission::from_value(&with).unwrap(),
        Association::NVector(Contractor::Best),
    );
    let b = solve_json(
        &Mission::from_value(&without).unwrap(),
        Association::NVector(Contractor::Best),
    );
    for key in [
        "trajectory",
        "detections",
        "landmarks",
        "matching",
        "status",
    ] {
        assert_eq!(a[key], b[key], "{key} changed when the truth was removed");
    }
    assert!(a.get("score").is_some() && b.get("score").is_none());
}

#[test]
fn same_input_same_bits() {
    let mut o = SimulateOptions::new(Scenario::Paper, 12);
    o.steps = Some(3000);
    let m = Mission::from_value(&simulate(&o)).unwrap();
    let a = solve_json(&m, Association::NVector(Contractor::Independent)).to_string();
    let b = solve_json(&m, Association::NVector(Contractor::Independent)).to_string();
    assert_eq!(a, b);
}

#[test]
fn wrong_operator_matching_is_infeasible() {
    // Tie two detections of different landmarks (far apart) to one landmark.
    let (mut v, truth) = common::operator_paper(13, 4000);
    let j = truth
        .iter()
        .position(|&l| l != truth[0])
        .expect("two landmarks detected");
    v["detections"][j]["landmark"] = v["detections"][0]["landmark"].clone();
    let r = solve_json(&Mission::from_value(&v).unwrap(), Association::None);
    assert_eq!(r["status"], "infeasible");
    let reason = r["reason"].as_str().unwrap();
    assert!(
        reason.contains("detection"),
        "reason names the detections: {reason}"
    );
}

#[test]
fn auv_survey_keeps_the_truth() {
    // A shortened Redermor-scale survey (the full 60,000 steps run in
    // `nvector bench`): the truth stays inside with every contractor.
    let mut o = SimulateOptions::new(Scenario::Auv, 1);
    o.steps = Some(15_000);
    let m = Mission::from_value(&simulate(&o)).unwrap();
    assert!(!m.detections.is_empty());
    for assoc in [Association::None, Association::NVector(Contractor::Best)] {
        let r = solve_json(&m, assoc);
        assert_eq!(r["status"], "consistent", "{assoc:?}: {}", r["reason"]);
        assert_eq!(r["score"]["truth_inside"], true, "{assoc:?}");
        assert_eq!(r["score"]["matching_errors"], 0, "{assoc:?}");
    }
}
