//! The propagator on missions planted with their truth on the boundary of
//! every interval (tests/common/planted.rs: ranges that are the interval
//! distance between point boxes, motion bounds that are the interval
//! difference of the true positions, the robot standing on a landmark with
//! a range of exactly 0, 2-D and 3-D, bearings, regions, depths, labels,
//! false detections in exactly the number `max_outliers` allows): under
//! every contractor the truth stays inside, no group mixes landmarks and
//! nothing is called infeasible. `score` (the result's scorer) must agree.
//!
//! `PROPTEST_CASES` scales the number of cases (common::config).

use nvector_core::nvector::Contractor;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::result::score;
use nvector_core::slam::types::{Association, SolveOptions};
use proptest::prelude::*;
use std::sync::atomic::AtomicBool;

use crate::common;
use common::planted::{self, PlantedMission};
use common::Rng;

const MODES: [Association; 6] = [
    Association::None,
    Association::NVector(Contractor::Nvalue),
    Association::NVector(Contractor::Projection),
    Association::NVector(Contractor::Independent),
    Association::NVector(Contractor::Best),
    Association::NVector(Contractor::Shapes),
];

fn run_all(pm: &PlantedMission, seed: u64) -> Result<(), TestCaseError> {
    for association in MODES {
        let options = SolveOptions {
            association,
            ..SolveOptions::default()
        };
        let s = propagate(&pm.mission, &options, &mut |_| {}, &AtomicBool::new(false));
        pm.check(&s).map_err(|e| {
            TestCaseError::fail(format!(
                "seed {seed} {}: {e}\nmission: {}",
                association.name(),
                pm.value
            ))
        })?;
        let (inside, errors, _) = score(&pm.mission, &s).expect("the mission has its truth");
        prop_assert!(
            inside && errors == 0,
            "seed {seed} {}: score says inside {inside}, {errors} matching errors",
            association.name()
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::config(48))]

    /// Every contractor keeps the boundary truth (module doc).
    #[test]
    fn every_contractor_keeps_a_truth_on_the_boundary(seed in any::<u64>(), three in any::<bool>()) {
        let mut rng = Rng::new(seed);
        let o = planted::Options::random(&mut rng, if three { 3 } else { 2 });
        let pm = planted::mission(&mut rng, &o);
        run_all(&pm, seed)?;
    }

    /// Exactly `max_outliers` false detections (q at its bound): the
    /// robust propagation keeps the truth of the true detections.
    #[test]
    fn exactly_q_false_detections_keep_the_truth(seed in any::<u64>(), three in any::<bool>(), q in 1usize..4) {
        let mut rng = Rng::new(seed);
        let mut o = planted::Options::random(&mut rng, if three { 3 } else { 2 });
        o.false_detections = q;
        let pm = planted::mission(&mut rng, &o);
        run_all(&pm, seed)?;
    }
}

/// The robot standing on the landmark (range exactly [0, 0]) at two steps,
/// and between them a step that keeps it still (motion error 0): the
/// ranges are tangent at a point, the centres coincide. Every contractor
/// keeps (0, 0) and the landmark, and groups the two detections or not,
/// but never calls the mission infeasible.
#[test]
fn coincident_robot_and_landmark_with_zero_ranges() {
    let v = serde_json::json!({
        "format": "nvector-mission/1",
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [0.0, 0.0], "error": 0}, "heading": {"value": [0.0, 1.0], "error": 0}},
        "motion_error": [0.0, 1.0],
        "detections": [
            {"step": 0, "range": [0, 0]},
            {"step": 1, "range": 0},
            {"step": 2, "range": [1, 1], "bearing": [-1, -1]},
        ],
        "landmark_count": 1,
        "truth": {"positions": [[0, 0], [0, 0], [-1, 0]], "landmarks": [[0, 0]], "matching": [0, 0, 0]}
    });
    let mission = nvector_core::slam::mission::Mission::from_value(&v).unwrap();
    let pm = PlantedMission {
        value: v,
        mission,
        dim: 2,
        positions: vec![vec![0.0, 0.0], vec![0.0, 0.0], vec![-1.0, 0.0]],
        landmarks: vec![vec![0.0, 0.0]],
        matching: vec![Some(0), Some(0), Some(0)],
    };
    run_all(&pm, 0).unwrap();
}

/// The planted missions are not vacuous: over fixed seeds, `best` proves
/// matchings on them (so the group checks above check something).
#[test]
fn planted_missions_prove_matchings() {
    let (mut groups, mut dets) = (0, 0);
    for seed in 0..100u64 {
        let mut rng = Rng::new(seed);
        let o = planted::Options::random(&mut rng, 2 + (seed % 2) as usize);
        let pm = planted::mission(&mut rng, &o);
        let s = propagate(
            &pm.mission,
            &SolveOptions::default(),
            &mut |_| {},
            &AtomicBool::new(false),
        );
        pm.check(&s).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        dets += pm.mission.detections.len();
        groups += s.matching.len();
    }
    assert!(
        dets > 500 && groups > 30,
        "{dets} detections, {groups} groups"
    );
}
