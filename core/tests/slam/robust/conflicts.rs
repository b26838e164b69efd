//! Conflict packing (`core/src/slam/robust/conflicts.rs`): planted 4 to
//! 10 false detections (q > 3, where consensus over subsets does not
//! apply) of every kind in simulated paper missions, ids hidden: the
//! simulator's own phantoms (a range and bearing to a point that is no
//! landmark), a range to nothing, a phantom within 0.5 m of a real
//! landmark, a range of 1000 m, a huge range (1e200), an unbounded range,
//! a true range moved off, a cluster of three ranges consistent with a
//! phantom landmark that does not exist; q the number planted and one
//! more. Checked: the mission is never called infeasible, every conflict
//! holds a false detection (the true ones alone are a reading) and the
//! conflicts are pairwise disjoint, no true detection is proved false,
//! the positions enclose the truth, and the whole robust solve keeps the
//! truth inside and never groups a false detection nor two landmarks.
//! The rule must also prove something: some runs report groups.
//!
//! The cases come from a fixed seed; `NVECTOR_PROPTEST_CASES` scales them.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::robust::conflicts::{pack, Packing};
use nvector_core::slam::robust::solve_robust;
use nvector_core::slam::simulate::{simulate, Layout, Rng, Scenario, SimulateOptions};
use nvector_core::slam::types::{Association, SolveOptions};
use serde_json::{json, Value};
use std::sync::atomic::AtomicBool;

fn cases() -> u64 {
    std::env::var("NVECTOR_PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .map_or(10, |c| (c / 100).max(10))
}

/// A range interval of half-width 0.05 m holding `r`.
fn range(r: f64) -> Value {
    json!([(r - 0.05).max(0.0), r + 0.05])
}

struct Planted {
    mission: Mission,
    positions: Vec<Vec<f64>>,
    truth_of: Vec<Option<usize>>,
    what: String,
}

/// A paper mission with `budget` false detections: the simulator's own
/// (even cases) or planted by kind (odd cases).
fn plant(case: u64, rng: &mut Rng, budget: usize) -> Planted {
    let below = |rng: &mut Rng, n: usize| (rng.next_u64() % n as u64) as usize;
    let mut o = SimulateOptions::new(Scenario::Paper, case + 1);
    let steps = 2500 + below(rng, 1500);
    o.steps = Some(steps);
    o.landmarks = Some(2 + below(rng, 2));
    o.layout = [Layout::Line, Layout::Ring, Layout::Random][below(rng, 3)];
    let own = case.is_multiple_of(2);
    if own {
        o.false_detections = budget;
    }
    let mut v = simulate(&o);
    let truth = v.as_object_mut().unwrap().remove("truth").unwrap();
    let positions: Vec<Vec<f64>> = serde_json::from_value(truth["positions"].clone()).unwrap();
    let lms: Vec<Vec<f64>> = serde_json::from_value(truth["landmarks"].clone()).unwrap();
    let matching: Vec<Option<usize>> = serde_json::from_value(truth["matching"].clone()).unwrap();
    let mut truth_of = matching;
    let mut kinds = Vec::new();
    let n = lms.len();
    let dets = v["detections"].as_array_mut().unwrap();
    let mut left = if own { 0 } else { budget };
    while left > 0 {
        let at = |rng: &mut Rng| 1 + below(rng, steps - 1);
        let kind = below(rng, 7);
        let s = at(rng);
        let p = positions[s].clone();
        let r = match kind {
            0 => range(0.5 + 13.5 * rng.unit()),
            1 => {
                let l = &lms[below(rng, n)];
                let (a, e) = (rng.sym(std::f64::consts::PI), 0.5 * rng.unit());
                range(libm::hypot(
                    l[0] + e * libm::cos(a) - p[0],
                    l[1] + e * libm::sin(a) - p[1],
                ))
            }
            2 => range(1000.0),
            3 => json!([1e200, 1e201]),
            4 => json!([0.5 + 5.0 * rng.unit(), "inf"]),
            5 => {
                let true_ones: Vec<usize> = (0..truth_of.len())
                    .filter(|&i| truth_of[i].is_some())
                    .collect();
                let i = true_ones[below(rng, true_ones.len())];
                let shift = 1.0 + 4.0 * rng.unit();
                let r = &dets[i]["range"];
                let (lo, hi) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
                dets[i]["range"] = json!([lo + shift, hi + shift]);
                truth_of[i] = None;
                kinds.push(kind);
                left -= 1;
                continue;
            }
            _ if left >= 3 => {
                let ghost = [lms[0][0] + 15.0, lms[0][1] - 15.0];
                for _ in 0..3 {
                    let s = at(rng);
                    let p = &positions[s];
                    let r = libm::hypot(ghost[0] - p[0], ghost[1] - p[1]);
                    dets.push(json!({"step": s, "range": range(r)}));
                    truth_of.push(None);
                }
                kinds.push(kind);
                left -= 3;
                continue;
            }
            _ => continue,
        };
        dets.push(json!({"step": s, "range": r}));
        truth_of.push(None);
        kinds.push(kind);
        left -= 1;
    }
    if let Some(o) = v.as_object_mut() {
        o.remove("max_outliers");
    }
    Planted {
        mission: Mission::from_value(&v).expect("valid mission"),
        positions,
        truth_of,
        what: format!("case {case} own {own} kinds {kinds:?}"),
    }
}

fn order_of(m: &Mission) -> Vec<usize> {
    let mut order: Vec<usize> = (0..m.detections.len()).collect();
    order.sort_by_key(|&j| (m.detections[j].step, j));
    order
}

#[test]
fn planted_false_detections_keep_the_truth_and_are_never_grouped() {
    let mut rng = Rng::new(0xc0f1_1c75);
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    let (mut runs, mut packed, mut grouped) = (0, 0, 0);
    for case in 0..cases() {
        let planted = 4 + (rng.next_u64() % 3) as usize;
        let p = plant(case, &mut rng, planted);
        let k = p.mission.detections.len();
        let falses = p.truth_of.iter().filter(|t| t.is_none()).count();
        for q in [falses, falses + 1] {
            let what = format!("{} q {q}", p.what);
            runs += 1;
            let r = pack(
                &p.mission,
                q,
                &vec![false; k],
                &order_of(&p.mission),
                &options,
                &cancel,
            );
            match r {
                Packing::Skipped => {}
                Packing::Infeasible(r) => panic!("{what}: the truth is a reading: {r}"),
                Packing::Proved {
                    proved_false,
                    conflicts,
                    positions,
                    ..
                } => {
                    packed += 1;
                    eprintln!(
                        "{what}: k {k} conflicts {conflicts:?} proved false {:?}",
                        (0..k).filter(|&j| proved_false[j]).collect::<Vec<_>>()
                    );
                    let mut seen = vec![false; k];
                    for c in &conflicts {
                        assert!(
                            c.iter().any(|&j| p.truth_of[j].is_none()),
                            "{what}: conflict {c:?} holds only true detections"
                        );
                        for &j in c {
                            assert!(!seen[j], "{what}: conflicts overlap at {j}");
                            assert!(!proved_false[j], "{what}: {j} proved false and in {c:?}");
                            seen[j] = true;
                        }
                    }
                    for (j, t) in p.truth_of.iter().enumerate() {
                        assert!(
                            !(proved_false[j] && t.is_some()),
                            "{what}: true detection {j} proved false"
                        );
                    }
                    if let Some(pos) = positions {
                        for (i, x) in p.positions.iter().enumerate() {
                            for (a, &c) in x.iter().enumerate() {
                                assert!(
                                    pos[i * 2 + a].contains(c),
                                    "{what}: step {i} axis {a}: {c} outside {:?}",
                                    pos[i * 2 + a]
                                );
                            }
                        }
                    }
                }
            }
            let s = solve_robust(&p.mission, q, &options, &mut |_| {}, &cancel);
            assert!(
                !matches!(
                    s.status,
                    nvector_core::slam::types::SolveStatus::Infeasible(_)
                ),
                "{what}: robust solve infeasible: {:?}",
                s.status
            );
            for (i, x) in p.positions.iter().enumerate() {
                for (a, &c) in x.iter().enumerate() {
                    assert!(
                        s.model.pos[i * 2 + a].contains(c),
                        "{what}: solve: step {i} axis {a}: {c} outside"
                    );
                }
            }
            grouped += usize::from(!s.matching.is_empty());
            for g in &s.matching {
                let first = p.truth_of[g[0]];
                assert!(first.is_some(), "{what}: false {} grouped {g:?}", g[0]);
                for &j in g {
                    assert_eq!(p.truth_of[j], first, "{what}: group {g:?}");
                }
            }
        }
    }
    eprintln!("{runs} runs, {packed} packed, {grouped} with groups");
    assert!(packed > 0, "the packing never found a conflict");
    assert!(grouped > 0, "the rule never led to a proved group");
}

/// The disjoint packing after the overlapping conflicts (`State::stages`):
/// on the paper mission of `nvector simulate --scenario paper --seed 9
/// --layout ring --false-detections 5` the free conflicts and Reiter's
/// loop prove 4 phantoms false and leave the fifth open; the packing then
/// finds its conflict, which accounts for q. Without it nothing is
/// grouped (seen: recall 0.00 before branch plazaq). Checked: the truth
/// inside, no true detection proved false, groups reported, none holding
/// a false detection or two landmarks.
#[test]
fn the_packing_after_the_overlapping_conflicts_accounts_for_the_last_phantom() {
    let mut o = SimulateOptions::new(Scenario::Paper, 9);
    o.layout = Layout::Ring;
    o.false_detections = 5;
    let v = simulate(&o);
    let m = Mission::from_value(&v).unwrap();
    let t = m.truth.as_ref().unwrap();
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let s = solve_robust(
        &m,
        m.max_outliers,
        &options,
        &mut |_| {},
        &AtomicBool::new(false),
    );
    assert!(
        !matches!(
            s.status,
            nvector_core::slam::types::SolveStatus::Infeasible(_)
        ),
        "{:?}",
        s.status
    );
    for (i, x) in t.positions.iter().enumerate() {
        for (a, &c) in x.iter().enumerate() {
            assert!(s.model.pos[i * 2 + a].contains(c), "step {i} axis {a}");
        }
    }
    for (j, d) in s.model.det.iter().enumerate() {
        assert!(
            t.matching[j].is_none() || !d.is_empty(),
            "true {j} proved false"
        );
    }
    assert!(!s.matching.is_empty(), "no group proved");
    for g in &s.matching {
        let first = t.matching[g[0]];
        assert!(first.is_some(), "false {} grouped {g:?}", g[0]);
        assert!(g.iter().all(|&j| t.matching[j] == first), "{g:?}");
    }
}
