//! The minimal correction set of an infeasible mission: removing it makes
//! the propagation consistent, and putting any one of its detections back
//! makes it infeasible again (both re-checked here by running the
//! propagator on the sub-missions, independently of the search).

use nvector_core::slam::diagnose::minimal_correction;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::result::SolveStatus;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, SolveOptions};
use proptest::prelude::*;
use serde_json::json;
use std::sync::atomic::AtomicBool;

use crate::common;
use common::planted;
use common::Rng;

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
    let (mut v, truth) = common::operator_paper(13, 4000);
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

/// The minimal correction set re-checked on the mission, independently of
/// the search: `None` exactly when the mission is consistent (its motion
/// data hold the truth, so without detections it always is); else a sorted
/// set of distinct detection indices, marked minimal, whose removal makes
/// the propagation consistent, and each of whose members put back alone
/// makes it infeasible again.
fn recheck(m: &Mission, options: &SolveOptions) -> Result<Option<Vec<usize>>, String> {
    let run = |keep: &dyn Fn(usize) -> bool| -> bool {
        let mut sub = m.clone();
        sub.detections = (0..m.detections.len())
            .filter(|&j| keep(j))
            .map(|j| m.detections[j].clone())
            .collect();
        sub.detection_count = sub.detections.len();
        sub.truth = None;
        let s = propagate(&sub, options, &mut |_| {}, &AtomicBool::new(false));
        matches!(s.status, SolveStatus::Infeasible(_))
    };
    let infeasible = run(&|_| true);
    let c = minimal_correction(m, options, &AtomicBool::new(false), 1000);
    let Some(c) = c else {
        return if infeasible {
            Err("infeasible, and no correction named".into())
        } else {
            Ok(None)
        };
    };
    if !infeasible {
        return Err(format!("consistent, yet a correction {c:?}"));
    }
    let k = m.detections.len();
    if !c.minimal
        || c.detections.is_empty()
        || c.detections.windows(2).any(|w| w[0] >= w[1])
        || c.detections.iter().any(|&j| j >= k)
    {
        return Err(format!("not a minimal set of detections: {c:?}"));
    }
    if run(&|j| !c.detections.contains(&j)) {
        return Err(format!("removing {:?} leaves it infeasible", c.detections));
    }
    for &x in &c.detections {
        if !run(&|j| j == x || !c.detections.contains(&j)) {
            return Err(format!(
                "{x} put back alone is consistent: {:?} is not minimal",
                c.detections
            ));
        }
    }
    Ok(Some(c.detections))
}

/// Detection 0 sees the landmark at 10 m; detections 1 and 3 (later) are
/// labelled with the same landmark but measure 50 m and 30 m from the same
/// standing robot: each conflicts with detection 0 alone (detection 2,
/// unlabelled, with nothing). The search takes 0, names 1, and must still
/// test 3 against 0: the correction is {1, 3} (a search that forgot
/// detection 0 once past it would name 1 alone, and the mission without 1
/// is still infeasible).
#[test]
fn two_culprits_against_one_earlier_detection() {
    let v = json!({
        "format": "nvector-mission/1",
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": 4,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [0, 0, 0, 0], "error": 0}, "heading": {"value": [0, 0, 0, 0], "error": 0}},
        "detections": [
            {"step": 1, "range": [10, 10], "landmark": 0},
            {"step": 2, "range": [50, 50], "landmark": 0},
            {"step": 3, "range": [5, 6]},
            {"step": 4, "range": [30, 30], "landmark": 0},
        ],
        "landmark_count": 2,
    });
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(recheck(&m, &options()).unwrap(), Some(vec![1, 3]));
}

proptest! {
    #![proptest_config(common::config(40))]

    /// Random missions planted on the boundary (tests/common/planted.rs),
    /// operator labels on many detections, then 1 to 3 ranges moved off
    /// their bounds: the diagnosis is re-checked on the mission itself
    /// (`recheck`), with the basic model and with `best`.
    #[test]
    fn random_missions_are_diagnosed_soundly(seed in any::<u64>(), three in any::<bool>(), bad in 1usize..4, best in any::<bool>()) {
        let mut rng = Rng::new(seed);
        let mut o = planted::Options::random(&mut rng, if three { 3 } else { 2 });
        o.labels = 0.7;
        o.detect = o.detect.max(0.3);
        let mut pm = planted::mission(&mut rng, &o);
        let k = pm.mission.detections.len();
        prop_assume!(k >= 2);
        for _ in 0..bad {
            let j = rng.below(k);
            let shift = if rng.chance(0.5) { rng.range(3.0, 30.0) } else { -rng.range(3.0, 30.0) };
            pm.corrupt_range(j, shift);
        }
        let options = if best { SolveOptions::default() } else { self::options() };
        recheck(&pm.mission, &options).map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}\n{}", pm.value)))?;
    }
}

/// The random missions above are not vacuous: over fixed seeds, most are
/// infeasible and get a correction of several detections.
#[test]
fn random_corrupted_missions_need_corrections() {
    let (mut named, mut several) = (0, 0);
    for seed in 0..40u64 {
        let mut rng = Rng::new(seed);
        let mut o = planted::Options::random(&mut rng, 2);
        o.labels = 0.7;
        o.detect = o.detect.max(0.3);
        let mut pm = planted::mission(&mut rng, &o);
        let k = pm.mission.detections.len();
        if k < 2 {
            continue;
        }
        for _ in 0..3 {
            let j = rng.below(k);
            pm.corrupt_range(j, rng.range(3.0, 30.0));
        }
        if let Some(c) =
            recheck(&pm.mission, &options()).unwrap_or_else(|e| panic!("seed {seed}: {e}"))
        {
            named += 1;
            several += usize::from(c.len() > 1);
        }
    }
    assert!(
        named >= 20 && several >= 5,
        "{named} corrections, {several} of several detections"
    );
}
