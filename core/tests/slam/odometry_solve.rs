//! odometry2d and `sensor_offset` solved end to end:
//! planted solutions through `slam::solve` for every contractor. The woods
//! scenario (seeds, ids hidden and operator) and random missions with
//! headings far beyond ±π, bearings given with any multiple of 2π added,
//! offsets, detections without a bearing, null truth entries; unicycle2d
//! with an offset too. Every true position, heading and landmark must lie
//! in its box (`score.truth_inside`, which compares real headings, never
//! modulo 2π), and a planted mission is never proved infeasible.

#![allow(clippy::disallowed_methods)]

use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use nvector_core::slam::solve::solve;
use nvector_core::slam::types::{Association, SolveOptions};
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

const CONTRACTORS: [&str; 5] = ["none", "nvalue", "projection", "independent", "best"];

fn run(m: &Mission, contractor: &str) -> Value {
    let options = SolveOptions {
        association: Association::parse(contractor).unwrap(),
        ..SolveOptions::default()
    };
    solve(m, &options, &mut |_| {}, &AtomicBool::new(false))
}

/// The truth is inside every box, the run is not infeasible, and the
/// headings are there (N+1 intervals) for odometry2d.
fn check(m: &Mission, r: &Value, what: &str) {
    assert_ne!(r["status"], "infeasible", "{what}: {}", r["reason"]);
    assert_eq!(r["score"]["truth_inside"], true, "{what}: {}", r["score"]);
    assert_eq!(r["score"]["matching_errors"], 0, "{what}");
    if m.model.name() == "odometry2d" {
        let h = r["headings"].as_array().expect("headings");
        assert_eq!(h.len(), m.steps + 1, "{what}");
        // Check the headings here too, against the truth, as reals.
        let t = m.truth.as_ref().unwrap().headings.as_ref().unwrap();
        for (i, (b, t)) in h.iter().zip(t).enumerate() {
            if let Some(t) = t {
                let (lo, hi) = (
                    b[0].as_f64().unwrap_or(f64::NEG_INFINITY),
                    b[1].as_f64().unwrap_or(f64::INFINITY),
                );
                assert!(lo <= *t && *t <= hi, "{what}: heading {i}: {t} not in {b}");
            }
        }
    } else {
        assert!(r.get("headings").is_none(), "{what}");
    }
}

#[test]
fn woods_seeds_keep_the_truth_for_every_contractor() {
    for seed in 1..=3 {
        for operator in [false, true] {
            let v = simulate_woods(&WoodsOptions {
                seed,
                steps: Some(200),
                landmarks: Some(9),
                operator,
            });
            let m = Mission::from_value(&v).unwrap();
            // Dead reckoning alone: the same mission without detections.
            let mut blind = v.clone();
            blind["detections"] = json!([]);
            blind["truth"]["matching"] = json!([]);
            let blind = Mission::from_value(&blind).unwrap();
            let r = run(&blind, "none");
            check(&blind, &r, &format!("woods seed {seed} dead reckoning"));
            let dead = r["metrics"]["max_heading_width"].as_f64().unwrap();
            for c in CONTRACTORS {
                let r = run(&m, c);
                check(
                    &m,
                    &r,
                    &format!("woods seed {seed} operator {operator} {c}"),
                );
                assert_eq!(r["status"], "consistent", "seed {seed} {c}");
                // With the operator's ids the detections bring the
                // heading back: the widest heading stays well below dead
                // reckoning's.
                let w = r["metrics"]["max_heading_width"].as_f64().unwrap();
                assert!(w <= dead, "seed {seed} {c}: {w} > {dead}");
                if operator {
                    assert!(
                        w < dead / 2.0,
                        "seed {seed} {c}: heading width {w}, dead reckoning {dead}"
                    );
                }
            }
        }
    }
}

/// With the ids hidden, the tracks (relative evidence under the
/// minimum separation) and the shared landmark boxes bring the heading
/// back: the association contractors keep the truth and find most
/// matchings (the separation rule on absolute boxes alone matched about 1 %
/// of the detections, and the heading stayed dead reckoning's).
#[test]
fn woods_ids_hidden_tracks_bring_the_heading_back() {
    for seed in 1..=3 {
        let v = simulate_woods(&WoodsOptions {
            seed,
            steps: Some(300),
            landmarks: Some(9),
            operator: false,
        });
        let m = Mission::from_value(&v).unwrap();
        let r = run(&m, "none");
        check(&m, &r, &format!("woods seed {seed} none"));
        let dead = r["metrics"]["max_heading_width"].as_f64().unwrap();
        for c in ["nvalue", "best"] {
            let r = run(&m, c);
            check(&m, &r, &format!("woods seed {seed} ids hidden {c}"));
            let recall = r["score"]["matching_recall"].as_f64().unwrap();
            assert!(recall > 0.5, "seed {seed} {c}: recall {recall}");
            let w = r["metrics"]["max_heading_width"].as_f64().unwrap();
            assert!(
                w < 0.8 * dead,
                "seed {seed} {c}: heading width {w}, dead reckoning {dead}"
            );
        }
    }
}

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sym(&mut self, a: f64) -> f64 {
        (2.0 * self.next() - 1.0) * a
    }
    fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}

/// A random mission with a planted truth: odometry2d (or unicycle2d),
/// headings from anywhere in [-40, 40] rad, an offset, bearings with a
/// random multiple of 2π added, some without bearing, some truth entries
/// null. Every declared bound exceeds the noise drawn by at least 1e-7.
fn random_mission(rng: &mut Lcg, odometry: bool) -> Value {
    let n = 5 + rng.below(60);
    let dt = 0.05 + rng.next() * 0.5;
    let count = 1 + rng.below(5);
    let lms: Vec<[f64; 2]> = (0..count).map(|_| [rng.sym(8.0), rng.sym(8.0)]).collect();
    let offset = match rng.below(4) {
        0 => [0.0, 0.0],
        _ => [rng.sym(1.0), rng.sym(1.0)],
    };
    let (se, we, he, me) = (
        rng.next() * 0.1 + 1e-6,
        rng.next() * 0.05 + 1e-6,
        rng.next() * 0.02 + 1e-6,
        rng.next() * 0.02 + 1e-6,
    );
    let (re, be) = (rng.next() * 0.2 + 1e-6, rng.next() * 0.1 + 1e-6);
    let margin = 1e-7;
    let mut th = rng.sym(40.0);
    let th0 = th;
    let mut p = [rng.sym(2.0), rng.sym(2.0)];
    let (mut pos, mut head) = (vec![p], vec![th]);
    let (mut speed, mut turn, mut heading_in) = (vec![], vec![], vec![]);
    for _ in 0..n {
        let v = rng.sym(2.0);
        let w = rng.sym(1.0);
        let h_used = th;
        let f = rng.sym(he - margin);
        let e = [rng.sym(me - margin), rng.sym(me - margin)];
        p = [
            p[0] + dt * v * h_used.cos() + e[0],
            p[1] + dt * v * h_used.sin() + e[1],
        ];
        // unicycle2d: the heading input is th(i) measured within we.
        heading_in.push(h_used + rng.sym(we - margin));
        th += dt * w + f;
        speed.push(v + rng.sym(se - margin));
        turn.push(w + rng.sym(we - margin));
        pos.push(p);
        head.push(th);
    }
    let mut dets = vec![];
    let mut matching = vec![];
    for _ in 0..(1 + rng.below(3 * n)) {
        let t = rng.below(n + 1);
        let l = rng.below(count);
        // unicycle2d has no heading at N: heading(N-1) stands for it, so
        // the truth's sensor there is taken with th(N-1) (the truth must
        // satisfy the mission's constraints).
        let h = if odometry {
            head[t]
        } else {
            head[t.min(n - 1)]
        };
        let s = [
            pos[t][0] + offset[0] * h.cos() - offset[1] * h.sin(),
            pos[t][1] + offset[0] * h.sin() + offset[1] * h.cos(),
        ];
        let dx = [lms[l][0] - s[0], lms[l][1] - s[1]];
        let r = (dx[0].hypot(dx[1]) + rng.sym(re - margin)).max(0.0);
        let mut det = json!({"step": t, "range": [(r - re).max(0.0), r + re]});
        if rng.below(4) > 0 {
            let k = rng.below(5) as f64 - 2.0;
            let b = dx[1].atan2(dx[0]) - h + rng.sym(be - margin) + 2.0 * PI * k;
            det["bearing"] = json!([b - be, b + be]);
        }
        dets.push(det);
        matching.push(l);
    }
    let null_or = |i: usize, x: Value| if i % 7 == 3 { Value::Null } else { x };
    let positions: Vec<Value> = pos
        .iter()
        .enumerate()
        .map(|(i, q)| {
            if i == 0 {
                json!(q)
            } else {
                null_or(i, json!(q))
            }
        })
        .collect();
    let mut m = json!({
        "format": "nvector-mission/1",
        "model": if odometry { "odometry2d" } else { "unicycle2d" },
        "dt": dt,
        "steps": n,
        "initial_position": [[pos[0][0] - 0.01, pos[0][0] + 0.01], [pos[0][1] - 0.01, pos[0][1] + 0.01]],
        "motion_error": me,
        "sensor_offset": offset,
        "detections": dets,
        "truth": {"positions": positions, "landmarks": lms, "matching": matching},
    });
    if rng.below(2) == 0 {
        m["landmark_count"] = json!(count);
    }
    if odometry {
        m["inputs"] = json!({
            "speed": {"value": speed, "error": se},
            "turn_rate": {"value": turn, "error": we},
        });
        m["initial_heading"] = json!([th0 - 0.02, th0 + 0.02]);
        m["heading_error"] = json!(he);
        if rng.below(3) == 0 {
            m["final_heading"] = json!([th - 0.1, th + 0.1]);
        }
        let hs: Vec<Value> = head
            .iter()
            .enumerate()
            .map(|(i, h)| null_or(i + 1, json!(h)))
            .collect();
        m["truth"]["headings"] = json!(hs);
    } else {
        m["inputs"] = json!({
            "speed": {"value": speed, "error": se},
            "heading": {"value": heading_in, "error": we},
        });
    }
    if rng.below(3) == 0 {
        m["final_position"] = json!([[p[0] - 0.5, p[0] + 0.5], [p[1] - 0.5, p[1] + 0.5]]);
    }
    m
}

#[test]
fn random_planted_missions_keep_the_truth() {
    let mut rng = Lcg(20);
    let mut consistent = 0;
    let cases = 300;
    for case in 0..cases {
        let odometry = case % 4 != 3;
        let v = random_mission(&mut rng, odometry);
        let m = Mission::from_value(&v).unwrap_or_else(|e| panic!("case {case}: {e}"));
        for c in CONTRACTORS {
            let r = run(&m, c);
            check(&m, &r, &format!("case {case} ({}) {c}", m.model.name()));
            consistent += (r["status"] == "consistent") as usize;
        }
    }
    assert!(consistent > cases * CONTRACTORS.len() / 2, "{consistent}");
}

/// The same missions with false detections allowed (the robust
/// propagation reads the detections restated from p when there is an
/// offset): still the truth inside.
#[test]
fn random_planted_missions_with_max_outliers_keep_the_truth() {
    let mut rng = Lcg(7);
    for case in 0..60 {
        let mut v = random_mission(&mut rng, case % 2 == 0);
        v["max_outliers"] = json!(1);
        let m = Mission::from_value(&v).unwrap();
        for c in ["none", "projection", "best"] {
            let r = run(&m, c);
            check(&m, &r, &format!("case {case} ({}) {c} q=1", m.model.name()));
        }
    }
}

/// The restated detections of `seen_from_p` hold the true range
/// and bearing from p (up to 2π) of random planted sightings.
#[test]
fn seen_from_p_keeps_the_true_range_and_bearing() {
    let mut rng = Lcg(3);
    for case in 0..3000 {
        let v = random_mission(&mut rng, true);
        let m = Mission::from_value(&v).unwrap();
        let seen = m.seen_from_p();
        // Restated (the offset dropped), or borrowed: no offset to fold.
        assert!(seen.sensor_offset.is_none_or(|o| o == [0.0, 0.0]));
        let t = m.truth.as_ref().unwrap();
        for (j, d) in seen.detections.iter().enumerate() {
            let step = d.step;
            let (Some(Some(th)), true) = (
                t.headings.as_ref().map(|h| h[step]),
                t.positions_known.as_ref().is_none_or(|k| k[step]),
            ) else {
                continue;
            };
            let p = &t.positions[step];
            let l = &t.landmarks[t.matching[j].unwrap()];
            let (dx, dy) = (l[0] - p[0], l[1] - p[1]);
            let r = dx.hypot(dy);
            assert!(
                d.range.lo() - 1e-9 <= r && r <= d.range.hi() + 1e-9,
                "case {case} det {j}: {r} not in {:?}",
                d.range
            );
            if let Some(b) = d.bearing {
                let a = dy.atan2(dx) - th;
                let k = ((b.mid() - a) / (2.0 * PI)).round();
                let a = a + 2.0 * PI * k;
                assert!(
                    b.lo() - 1e-9 <= a && a <= b.hi() + 1e-9,
                    "case {case} det {j}: {a} not in {b:?}"
                );
            }
        }
    }
}

/// Scans are evidence for the shapes (`best`): a scan with more detections
/// than landmark_count is infeasible, and so is an operator matching that
/// labels two detections of one scan as one landmark.
#[test]
fn scans_are_pairwise_distinct_landmarks() {
    let v = simulate_woods(&WoodsOptions {
        seed: 3,
        steps: Some(200),
        landmarks: Some(9),
        operator: false,
    });
    // The largest scan.
    let mut sizes = std::collections::BTreeMap::new();
    for d in v["detections"].as_array().unwrap() {
        *sizes.entry(d["scan"].as_u64().unwrap()).or_insert(0usize) += 1;
    }
    let (&scan, &most) = sizes.iter().max_by_key(|(_, &c)| c).unwrap();
    assert!(most >= 2, "{most}");
    let mut w = v.clone();
    w["landmark_count"] = json!(most - 1);
    w["truth"] = Value::Null;
    // Infeasible (the scan rule or atmost_nvector, whichever first).
    let r = run(&Mission::from_value(&w).unwrap(), "best");
    assert_eq!(r["status"], "infeasible", "scan {scan}");
    // Two detections of one scan labelled as one landmark.
    let mut w = v.clone();
    let two: Vec<usize> = v["detections"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .filter(|(_, d)| d["scan"] == json!(scan))
        .map(|(j, _)| j)
        .take(2)
        .collect();
    w["detections"][two[0]]["landmark"] = json!(0);
    w["detections"][two[1]]["landmark"] = json!(0);
    w["truth"] = Value::Null;
    let r = run(&Mission::from_value(&w).unwrap(), "best");
    assert_eq!(r["status"], "infeasible", "{}", r["reason"]);
}

/// Two detections of one scan with the same annulus: only the scan says
/// they are distinct. Labelled as one landmark by the operator, the
/// mission is infeasible under `best`; without the scan field it is
/// consistent.
#[test]
fn a_scan_pair_labelled_as_one_landmark_is_infeasible() {
    let mut v = json!({
        "format": "nvector-mission/1",
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": 1,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [0.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
        "landmark_count": 2,
        "detections": [
            {"step": 0, "range": [1, 3], "landmark": 0, "scan": 5},
            {"step": 0, "range": [1, 3], "landmark": 0, "scan": 5}
        ]
    });
    let r = run(&Mission::from_value(&v).unwrap(), "best");
    assert_eq!(r["status"], "infeasible", "{r}");
    v["detections"][1]["scan"] = json!(6);
    let r = run(&Mission::from_value(&v).unwrap(), "best");
    assert_eq!(r["status"], "consistent", "{}", r["reason"]);
}
