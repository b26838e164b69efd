//! Tracks with false detections (core/src/slam/robust/track_groups.rs) on
//! planted woods worlds: false detections of every kind are added (a
//! phantom far from every landmark, one near a true landmark, a phantom
//! landmark seen from several steps, one between two landmarks closer than
//! 2s seen from several steps, a true detection moved), and the valid
//! groups built with the budget = their count never hold true detections
//! of two landmarks; the groups do form (a rule that merges nothing passes
//! the first check); and the whole engine with `max_outliers` keeps the
//! truth inside and reports no group holding a false detection.

use nvector_core::slam::association::odometry2d::tracks::TrackOptions;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::robust::track_groups::robust_track_groups;
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use serde_json::{json, Value};

use crate::common::Rng;

/// The sensor point and heading of step t in truth.
fn sensor(v: &Value, t: usize) -> Option<([f64; 2], f64)> {
    let p = v["truth"]["positions"][t].as_array()?;
    let th = v["truth"]["headings"][t].as_f64()?;
    let o = &v["sensor_offset"];
    let (ox, oy) = (o[0].as_f64().unwrap_or(0.0), o[1].as_f64().unwrap_or(0.0));
    let (x, y) = (p[0].as_f64()?, p[1].as_f64()?);
    let (s, c) = libm::sincos(th);
    Some(([x + c * ox - s * oy, y + s * ox + c * oy], th))
}

/// A false detection at step t reading the point `at`, with the widths of
/// the true detection `like`, in its scan; `null` in truth.
fn plant(v: &mut Value, like: usize, at: [f64; 2]) {
    let d = v["detections"][like].clone();
    let t = d["step"].as_u64().unwrap() as usize;
    let Some((s, th)) = sensor(v, t) else { return };
    let (dx, dy) = (at[0] - s[0], at[1] - s[1]);
    let r = libm::hypot(dx, dy);
    let b = libm::atan2(dy, dx) - th;
    let wr = d["range"][1].as_f64().unwrap() - d["range"][0].as_f64().unwrap();
    let wb = d["bearing"][1].as_f64().unwrap() - d["bearing"][0].as_f64().unwrap();
    let mut f = json!({"step": t, "range": [r - wr / 2.0, r + wr / 2.0],
        "bearing": [b - wb / 2.0, b + wb / 2.0]});
    if !d["scan"].is_null() {
        f["scan"] = d["scan"].clone();
    }
    v["detections"].as_array_mut().unwrap().push(f);
    v["truth"]["matching"]
        .as_array_mut()
        .unwrap()
        .push(Value::Null);
}

fn landmarks(v: &Value) -> Vec<[f64; 2]> {
    v["truth"]["landmarks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| [l[0].as_f64().unwrap(), l[1].as_f64().unwrap()])
        .collect()
}

/// Adds `k` false detections of the module doc's kinds; returns how many.
fn plant_false(v: &mut Value, rng: &mut Rng, k: usize) -> usize {
    let ls = landmarks(v);
    let s = v["landmark_min_separation"].as_f64().unwrap();
    let true_count = v["detections"].as_array().unwrap().len();
    let mut planted = 0;
    let mut tries = 0;
    while planted < k && tries < 10_000 {
        tries += 1;
        let like = rng.below(true_count);
        let truth = v["truth"]["matching"][like].as_u64();
        let Some(l) = truth.map(|l| ls[l as usize]) else {
            continue;
        };
        let kind = rng.below(5);
        let far = |p: [f64; 2]| {
            ls.iter()
                .all(|m| libm::hypot(p[0] - m[0], p[1] - m[1]) > s + 0.5)
        };
        let at = match kind {
            // Far from every landmark.
            0 => [l[0] + rng.range(-6.0, 6.0), l[1] + rng.range(-6.0, 6.0)],
            // Near the landmark it copies.
            1 => [l[0] + rng.range(-0.3, 0.3), l[1] + rng.range(-0.3, 0.3)],
            // Between two landmarks closer than 2s.
            2 => {
                let Some(m) = ls
                    .iter()
                    .find(|m| **m != l && libm::hypot(m[0] - l[0], m[1] - l[1]) < 2.0 * s)
                else {
                    continue;
                };
                [(l[0] + m[0]) / 2.0, (l[1] + m[1]) / 2.0]
            }
            // A phantom landmark beside this one.
            3 => [l[0] + rng.range(-2.0, 2.0), l[1] + rng.range(-2.0, 2.0)],
            // The true point moved along the ray.
            _ => {
                let (sp, _) = sensor(v, v["detections"][like]["step"].as_u64().unwrap() as usize)
                    .unwrap_or(([0.0, 0.0], 0.0));
                let f = 1.0 + rng.range(0.15, 0.6);
                [sp[0] + (l[0] - sp[0]) * f, sp[1] + (l[1] - sp[1]) * f]
            }
        };
        if kind == 0 && !far(at) {
            continue;
        }
        // Kinds 2 and 3 are seen again from the next detections' steps
        // (a consistent phantom landmark).
        let repeats = if (2..4).contains(&kind) {
            1 + rng.below(3)
        } else {
            1
        };
        for r in 0..repeats.min(k - planted) {
            let other = (like + 5 * r).min(true_count - 1);
            plant(v, other, at);
            planted += 1;
        }
    }
    v["max_outliers"] = json!(planted);
    planted
}

#[test]
fn valid_groups_never_join_two_true_landmarks() {
    let mut rng = Rng::new(20);
    let mut big = 0;
    for seed in 1..=16u64 {
        let opts = WoodsOptions {
            seed: 300 + seed,
            steps: Some(150 + (seed as usize % 4) * 50),
            landmarks: Some(6 + (seed as usize % 12)),
            operator: false,
        };
        let mut v = simulate_woods(&opts);
        let k = 1 + rng.below(8);
        let planted = plant_false(&mut v, &mut rng, k);
        let mission = Mission::from_value(&v).expect("a woods mission");
        let truth = mission.truth.as_ref().expect("truth").matching.clone();
        let model = Model::new(&mission);
        let chain = model.odometry.as_ref().expect("odometry2d");
        let live = vec![true; mission.detections.len()];
        for budget in [planted, planted + 2] {
            let groups =
                robust_track_groups(&mission, chain, &live, budget, TrackOptions::default());
            for g in &groups {
                let mut seen = g.iter().filter_map(|&j| truth[j]);
                if let Some(first) = seen.next() {
                    for other in seen {
                        assert_eq!(first, other, "seed {seed}, budget {budget}: group {g:?}");
                    }
                }
                big += usize::from(g.len() >= 10);
            }
        }
    }
    assert!(big >= 32, "only {big} groups of 10 or more members formed");
}

/// The whole engine, `best`, ids hidden, q = the false detections planted:
/// consistent, truth inside, no matching error (a group holding a false
/// detection is one).
#[test]
fn the_robust_engine_keeps_the_truth_with_planted_false_detections() {
    use nvector_core::nvector::Contractor;
    use nvector_core::slam::types::{Association, SolveOptions};
    use std::sync::atomic::AtomicBool;
    let mut rng = Rng::new(21);
    for seed in 1..=2u64 {
        let opts = WoodsOptions {
            seed: 400 + seed,
            steps: Some(100),
            landmarks: Some(8),
            operator: false,
        };
        let mut v = simulate_woods(&opts);
        plant_false(&mut v, &mut rng, seed as usize * 3);
        let m = Mission::from_value(&v).expect("valid mission");
        let options = SolveOptions {
            association: Association::NVector(Contractor::Best),
            ..SolveOptions::default()
        };
        let r =
            nvector_core::slam::solve::solve(&m, &options, &mut |_| {}, &AtomicBool::new(false));
        assert_eq!(r["status"], "consistent", "seed {seed}: {}", r["reason"]);
        assert_eq!(r["score"]["truth_inside"], true, "seed {seed}");
        assert_eq!(r["score"]["matching_errors"], 0, "seed {seed}");
    }
}
