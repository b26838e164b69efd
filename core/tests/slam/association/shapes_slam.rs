//! The `shapes` contractor through the whole SLAM engine on simulated
//! missions (the paper scenario, every layout, with bearings and range
//! only, with and without the operator's ids): the truth stays inside every
//! box, no two detections of different landmarks are grouped, the mission
//! stays consistent, and a landmark region is given per group.
//!
//! `PROPTEST_CASES` scales the number of cases (halved here); seeds and
//! persisted failures: tests/common/mod.rs (`config`).

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve;
use nvector_core::slam::types::{Association, SolveOptions};
use proptest::prelude::*;
use std::sync::atomic::AtomicBool;

use crate::common;

fn run(mission: &Mission, mode: Contractor) -> serde_json::Value {
    let options = SolveOptions {
        association: Association::NVector(mode),
        ..SolveOptions::default()
    };
    solve(mission, &options, &mut |_| {}, &AtomicBool::new(false))
}

proptest! {
    #![proptest_config(common::config_div(1000, 2, 10))]

    #[test]
    fn simulated_missions_keep_the_truth(
        seed in 0u64..1_000_000,
        steps in 200usize..3000,
        landmarks in 1usize..7,
        noise in 0.3..3.0f64,
        layout in 0usize..3,
        range_only in any::<bool>(),
        operator in any::<bool>(),
    ) {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        o.steps = Some(steps);
        o.landmarks = Some(landmarks);
        o.noise = noise;
        o.layout = [Layout::Line, Layout::Ring, Layout::Random][layout];
        o.range_only = range_only;
        o.operator = operator;
        let mission = Mission::from_value(&simulate(&o)).expect("valid");
        for mode in [Contractor::Shapes, Contractor::Best] {
            let r = run(&mission, mode);
            prop_assert_eq!(&r["status"], "consistent", "seed {} {:?}: {}", seed, mode, r["reason"]);
            prop_assert_eq!(&r["score"]["truth_inside"], true, "seed {} {:?}", seed, mode);
            prop_assert_eq!(&r["score"]["matching_errors"], 0, "seed {} {:?}", seed, mode);
            let groups = r["matching"].as_array().map_or(0, |m| m.len());
            if groups > 0 {
                let regions = r["landmark_regions"].as_array().expect("landmark_regions");
                prop_assert_eq!(regions.len(), groups);
                // Each paving holds its group's true landmark.
                let truth = mission.truth.as_ref().expect("truth");
                for (g, paving) in r["matching"].as_array().expect("matching").iter().zip(regions) {
                    let j = g[0].as_u64().expect("index") as usize;
                    let l = truth.matching[j].expect("a true detection");
                    let point = &truth.landmarks[l];
                    let inside = paving.as_array().expect("boxes").iter().any(|b| {
                        b.as_array().is_some_and(|axes| {
                            axes.iter().zip(point.iter()).all(|(a, &x)| {
                                a[0].as_f64().is_some_and(|lo| lo <= x) && a[1].as_f64().is_some_and(|hi| x <= hi)
                            })
                        })
                    });
                    prop_assert!(inside, "seed {} {:?}: the region of group {} misses its landmark", seed, mode, g);
                }
            }
        }
    }
}

/// `shapes` in a plain contraction request is `best` (docs/formats.md).
#[test]
fn shapes_is_best_on_plain_boxes() {
    use nvector_core::nvector::atmost_nvector;
    use nvector_core::{Interval, IntervalBox};
    let b = |x0: f64, x1: f64, y0: f64, y1: f64| {
        IntervalBox::new(&[Interval::new(x0, x1), Interval::new(y0, y1)])
    };
    let boxes = vec![
        b(1.0, 6.0, 2.0, 6.0),
        b(3.0, 5.0, 6.0, 9.0),
        b(4.0, 10.0, 1.0, 4.0),
        b(5.0, 9.0, 3.0, 7.0),
        b(9.0, 11.0, 0.0, 5.0),
    ];
    let (mut a, mut c) = (boxes.clone(), boxes);
    let x = atmost_nvector(2, &mut a, Contractor::Shapes).expect("valid");
    let y = atmost_nvector(2, &mut c, Contractor::Best).expect("valid");
    assert_eq!(a, c);
    assert_eq!(x, y);
    assert_eq!(Contractor::parse("shapes"), Some(Contractor::Shapes));
    assert_eq!(Contractor::Shapes.name(), "shapes");
}
