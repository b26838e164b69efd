//! Free conflicts from distinct pairs (`core/src/slam/robust/cliques.rs`),
//! with planted solutions: paper missions, ids hidden, with false
//! detections of every kind planted (the simulator's phantoms, a range
//! 0.5 m off a real landmark's, a cluster of three consistent with a
//! phantom landmark, a range of 1e200, an unbounded range, a bearing
//! turned by 0.2 rad). Every clique must hold a false detection (n + 1
//! true detections see at most n landmarks: a clique of true ones would
//! be a distinct pair that sees one landmark), and its true members must
//! see pairwise distinct landmarks; the whole engine keeps the truth and
//! groups no false detection.
//!
//! The cases come from a fixed seed; `NVECTOR_PROPTEST_CASES` scales them.
//! What the cliques and the packing find on mission files is measured by
//! `cargo run --release -p nvector-core --example measure_robust`.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::robust::cliques::clique_conflicts;
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

fn order_of(m: &Mission) -> Vec<usize> {
    let mut order: Vec<usize> = (0..m.detections.len()).collect();
    order.sort_by_key(|&j| (m.detections[j].step, j));
    order
}

/// Checks every clique of `m` against the truth; returns how many there
/// are.
fn check_cliques(m: &Mission, truth: &[Option<usize>], what: &str) -> usize {
    let k = m.detections.len();
    let cliques = clique_conflicts(m, &Model::new(m), &vec![true; k], &order_of(m));
    let n = m.landmark_count.unwrap();
    for c in &cliques {
        assert_eq!(c.len(), n + 1, "{what}: clique {c:?}");
        let seen: Vec<usize> = c.iter().filter_map(|&j| truth[j]).collect();
        assert!(
            seen.len() < c.len(),
            "{what}: clique {c:?} of true detections only (landmarks {seen:?})"
        );
        for (a, &x) in seen.iter().enumerate() {
            assert!(
                !seen[a + 1..].contains(&x),
                "{what}: clique {c:?} holds two detections of landmark {x}"
            );
        }
    }
    cliques.len()
}

/// A range interval of half-width 0.05 m holding `r`.
fn range(r: f64) -> Value {
    json!([(r - 0.05).max(0.0), r + 0.05])
}

/// A short paper mission, ids hidden, with the simulator's phantoms and
/// planted false detections of every kind; its truth matching.
fn planted(case: u64, rng: &mut Rng) -> (Mission, Vec<Option<usize>>, Vec<Vec<f64>>) {
    let below = |rng: &mut Rng, n: usize| (rng.next_u64() % n as u64) as usize;
    let mut o = SimulateOptions::new(Scenario::Paper, case + 11);
    let steps = 1200 + below(rng, 800);
    o.steps = Some(steps);
    o.landmarks = Some(3 + below(rng, 2));
    o.layout = [Layout::Line, Layout::Ring, Layout::Random][below(rng, 3)];
    let own = below(rng, 5);
    o.false_detections = own;
    let mut v = simulate(&o);
    let truth = v.as_object_mut().unwrap().remove("truth").unwrap();
    let positions: Vec<Vec<f64>> = serde_json::from_value(truth["positions"].clone()).unwrap();
    let lms: Vec<Vec<f64>> = serde_json::from_value(truth["landmarks"].clone()).unwrap();
    let mut truth_of: Vec<Option<usize>> =
        serde_json::from_value(truth["matching"].clone()).unwrap();
    let dets = v["detections"].as_array_mut().unwrap();
    let at = |rng: &mut Rng| 1 + below(rng, steps - 1);
    let s = at(rng);
    let (p, l) = (&positions[s], &lms[0]);
    dets.push(json!({"step": s, "range": range(libm::hypot(l[0] + 0.5 - p[0], l[1] - p[1]))}));
    dets.push(json!({"step": at(rng), "range": [1e200, 1e201]}));
    dets.push(json!({"step": at(rng), "range": [2.0, "inf"]}));
    let ghost = [lms[1][0] + 15.0, lms[1][1] - 15.0];
    for _ in 0..3 {
        let s = at(rng);
        let p = &positions[s];
        dets.push(
            json!({"step": s, "range": range(libm::hypot(ghost[0] - p[0], ghost[1] - p[1]))}),
        );
    }
    let mut extra = 6;
    // A true detection's bearing turned by 0.2 rad (a copy: the true one
    // stays).
    if let Some(d) = dets.iter().find(|d| d.get("bearing").is_some()).cloned() {
        let mut d = d;
        let b: Vec<f64> = serde_json::from_value(d["bearing"].clone()).unwrap();
        d["bearing"] = json!([b[0] + 0.2, b[1] + 0.2]);
        dets.push(d);
        extra += 1;
    }
    truth_of.extend(std::iter::repeat_n(None, extra));
    v["max_outliers"] = json!(own + extra);
    (
        Mission::from_value(&v).expect("valid mission"),
        truth_of,
        positions,
    )
}

#[test]
fn cliques_always_hold_a_false_detection() {
    let mut rng = Rng::new(0x0018_c11c);
    let mut found = 0;
    for case in 0..cases(40) {
        let (m, truth, _) = planted(case, &mut rng);
        found += check_cliques(&m, &truth, &format!("case {case}"));
    }
    eprintln!("{found} cliques");
    assert!(
        found > 0,
        "no clique was ever found: the test proves nothing"
    );
}

#[test]
fn ten_simulated_phantoms_keep_the_truth() {
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        ..SolveOptions::default()
    };
    let cancel = AtomicBool::new(false);
    let mut rng = Rng::new(0x0018_0a10);
    for case in 0..cases(3) {
        let (m, truth, positions) = planted(case + 100, &mut rng);
        let what = format!("case {case}");
        check_cliques(&m, &truth, &what);
        let q = m.max_outliers;
        let s = solve_robust(&m, q, &options, &mut |_| {}, &cancel);
        assert!(
            !matches!(s.status, SolveStatus::Infeasible(_)),
            "{what}: {:?}",
            s.status
        );
        for (i, x) in positions.iter().enumerate() {
            for (a, &c) in x.iter().enumerate() {
                assert!(s.model.pos[i * 2 + a].contains(c), "{what}: step {i}");
            }
        }
        for (j, t) in truth.iter().enumerate() {
            assert!(
                t.is_none() || !s.model.det[j].is_empty(),
                "{what}: true {j} proved false"
            );
        }
        for g in &s.matching {
            let first = truth[g[0]];
            assert!(first.is_some(), "{what}: false {} grouped {g:?}", g[0]);
            assert!(g.iter().all(|&j| truth[j] == first), "{what}: {g:?}");
        }
    }
}
