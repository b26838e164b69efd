//! Overlapping conflicts (`core/src/slam/robust/hitting.rs` and the
//! hitting-set stage of `core/src/slam/robust/conflicts.rs`), with planted
//! solutions.
//!
//! 1. The rule alone: a planted set of at most q false detections, random
//!    conflicts each holding one of them (the truth is a reading, so every
//!    conflict does), unbounded and huge detection numbers: a detection
//!    outside the planted set is never proved false (the planted set is a
//!    hitting set of size <= q without it), the family is never called
//!    unhittable within q, and some planted ones are proved false.
//! 2. The whole engine on short paper missions, ids hidden, with 7 to 10
//!    false detections of every kind (the simulator's phantoms, a phantom
//!    0.5 m from a real landmark, a range of 1e200, an unbounded range, a
//!    cluster of three ranges consistent with a phantom landmark): never
//!    infeasible, the truth inside, no true detection proved false, no
//!    false detection grouped.
//!
//! The cases come from a fixed seed; `NVECTOR_PROPTEST_CASES` scales them.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::robust::conflicts::{pack, Packing};
use nvector_core::slam::robust::hitting::{hitting_set, minimum, Hit};
use nvector_core::slam::robust::solve_robust;
use nvector_core::slam::simulate::{simulate, Layout, Rng, Scenario, SimulateOptions};
use nvector_core::slam::types::{Association, SolveOptions, SolveStatus};
use serde_json::{json, Value};
use std::sync::atomic::AtomicBool;

fn cases(base: u64) -> u64 {
    std::env::var("NVECTOR_PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .map_or(base, |c| (c * base / 1000).max(base))
}

#[test]
fn planted_drops_are_a_hitting_set_so_no_true_detection_is_proved_false() {
    let mut rng = Rng::new(0x4817_5e75);
    let below = |rng: &mut Rng, n: u64| rng.next_u64() % n.max(1);
    let (mut proved, mut planted_total) = (0, 0);
    for case in 0..cases(3000) {
        // Detection numbers: small, or 2^16 and up (the
        // indices must not size anything but the flags).
        let k = 2 + below(&mut rng, 40) as usize;
        let base = if case.is_multiple_of(7) {
            1usize << 16
        } else {
            0
        };
        let q = below(&mut rng, 11) as usize;
        let mut falses: Vec<usize> = (0..k).filter(|_| below(&mut rng, 4) == 0).collect();
        falses.truncate(q);
        let f = below(&mut rng, 30) as usize;
        let family: Vec<Vec<usize>> = if falses.is_empty() {
            Vec::new()
        } else {
            (0..f)
                .map(|_| {
                    let mut c = vec![falses[below(&mut rng, falses.len() as u64) as usize]];
                    for _ in 0..below(&mut rng, 6) {
                        c.push(below(&mut rng, k as u64) as usize);
                    }
                    c.sort_unstable();
                    c.dedup();
                    c.into_iter().map(|j| j + base).collect()
                })
                .collect()
        };
        let falses: Vec<usize> = falses.into_iter().map(|j| j + base).collect();
        planted_total += falses.len();
        let mut work = 1_000_000;
        match minimum(&family, &[], q, &mut work) {
            Hit::Found(h) => assert!(h.len() <= falses.len(), "case {case}: {h:?} {falses:?}"),
            Hit::None => panic!("case {case}: {family:?} called unhittable by {q}"),
            Hit::Unknown => {}
        }
        for x in base..base + k {
            let mut ban = vec![false; base + k];
            ban[x] = true;
            let mut work = 1_000_000;
            if hitting_set(&family, &ban, q, &mut work) == Hit::None {
                assert!(
                    falses.contains(&x),
                    "case {case}: true {x} proved false by {family:?}, q {q}, planted {falses:?}"
                );
                proved += 1;
            }
        }
    }
    eprintln!("{proved} of {planted_total} planted proved false");
    assert!(proved > 0, "the rule never proved anything");
}

/// A range interval of half-width 0.05 m holding `r`.
fn range(r: f64) -> Value {
    json!([(r - 0.05).max(0.0), r + 0.05])
}

#[test]
fn short_paper_missions_with_up_to_ten_false_detections() {
    let mut rng = Rng::new(0x0018_0010);
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    let mut refuted = 0;
    for case in 0..cases(2) {
        let below = |rng: &mut Rng, n: usize| (rng.next_u64() % n as u64) as usize;
        let mut o = SimulateOptions::new(Scenario::Paper, case + 3);
        let steps = 1500 + below(&mut rng, 500);
        o.steps = Some(steps);
        o.landmarks = Some(3);
        o.layout = [Layout::Line, Layout::Ring, Layout::Random][below(&mut rng, 3)];
        let own = 4 + below(&mut rng, 3);
        o.false_detections = own;
        let mut v = simulate(&o);
        let truth = v.as_object_mut().unwrap().remove("truth").unwrap();
        let positions: Vec<Vec<f64>> = serde_json::from_value(truth["positions"].clone()).unwrap();
        let lms: Vec<Vec<f64>> = serde_json::from_value(truth["landmarks"].clone()).unwrap();
        let mut truth_of: Vec<Option<usize>> =
            serde_json::from_value(truth["matching"].clone()).unwrap();
        let dets = v["detections"].as_array_mut().unwrap();
        let at = |rng: &mut Rng| 1 + below(rng, steps - 1);
        // One of each planted kind: near a landmark, huge, unbounded, and
        // a cluster of three around a phantom landmark.
        let s = at(&mut rng);
        let (p, l) = (&positions[s], &lms[0]);
        dets.push(json!({"step": s, "range": range(libm::hypot(l[0] + 0.5 - p[0], l[1] - p[1]))}));
        dets.push(json!({"step": at(&mut rng), "range": [1e200, 1e201]}));
        dets.push(json!({"step": at(&mut rng), "range": [2.0, "inf"]}));
        let ghost = [lms[1][0] + 15.0, lms[1][1] - 15.0];
        for _ in 0..3 {
            let s = at(&mut rng);
            let p = &positions[s];
            dets.push(
                json!({"step": s, "range": range(libm::hypot(ghost[0] - p[0], ghost[1] - p[1]))}),
            );
        }
        truth_of.extend([None; 6]);
        let q = own + 6;
        v["max_outliers"] = json!(q);
        let m = Mission::from_value(&v).expect("valid mission");
        let k = m.detections.len();
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by_key(|&j| (m.detections[j].step, j));
        let what = format!("case {case} steps {steps} k {k} q {q}");
        match pack(&m, q, &vec![false; k], &order, &options, &cancel) {
            Packing::Infeasible(r) => panic!("{what}: the truth is a reading: {r}"),
            Packing::Skipped => {}
            Packing::Proved {
                proved_false,
                positions: pos,
                ..
            } => {
                for (j, t) in truth_of.iter().enumerate() {
                    assert!(
                        !(proved_false[j] && t.is_some()),
                        "{what}: true {j} proved false"
                    );
                    refuted += usize::from(proved_false[j]);
                }
                if let Some(pos) = pos {
                    for (i, x) in positions.iter().enumerate() {
                        for (a, &c) in x.iter().enumerate() {
                            assert!(pos[i * 2 + a].contains(c), "{what}: step {i} axis {a}");
                        }
                    }
                }
            }
        }
        let s = solve_robust(&m, q, &options, &mut |_| {}, &cancel);
        assert!(
            !matches!(s.status, SolveStatus::Infeasible(_)),
            "{what}: {:?}",
            s.status
        );
        for (i, x) in positions.iter().enumerate() {
            for (a, &c) in x.iter().enumerate() {
                assert!(
                    s.model.pos[i * 2 + a].contains(c),
                    "{what}: solve: step {i} axis {a}"
                );
            }
        }
        for g in &s.matching {
            let first = truth_of[g[0]];
            assert!(first.is_some(), "{what}: false {} grouped {g:?}", g[0]);
            assert!(
                g.iter().all(|&j| truth_of[j] == first),
                "{what}: group {g:?}"
            );
        }
    }
    eprintln!("{refuted} false detections proved false");
}
