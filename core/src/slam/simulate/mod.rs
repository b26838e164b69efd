//! Simulated missions with ground truth:
//! - `paper`: the experiment of the paper's section 6 — a unicycle robot
//!   driven by a feedback loop that makes it loop around its start
//!   (cycloid-like), n landmarks, a detection each time the distance to a
//!   landmark reaches a local minimum under a threshold, the range measured
//!   with bounded noise and the landmark seen abeam (side-scan sonar: a
//!   bearing near ±pi/2 with a wide bound), speed and heading sensors with
//!   bounded noise, known start.
//! - `auv`: a Redermor-scale 3-D survey (dt 0.1 s, 60,000 steps) over the six
//!   Redermor seamarks, roll/pitch/yaw and body velocity with bounded errors,
//!   known start and end (GPS), detections at closest approach within sonar
//!   range, seabed depth for each detection.
//!
//! Deterministic for a seed (splitmix64, libm only): the same bits native and
//! in the browser. Every declared error bound strictly exceeds the noise
//! drawn (by a margin that also covers the f64 rounding of the simulation
//! itself), so the truth satisfies every constraint of the mission.

mod auv;
pub mod odometry_scenario;
mod paper;
mod request;
mod scenario;
#[cfg(feature = "openapi")]
mod schema;

pub use crate::rng::Rng;
pub use crate::slam::mission::MAX_LANDMARKS;
use crate::slam::mission::MAX_STEPS;
use auv::auv;
use odometry_scenario::{simulate_woods_with, WoodsOptions};
use paper::paper;
pub use request::{SimulateLimits, SimulateRequest};
pub use scenario::{
    Layout, Scenario, SimulateOptions, AUV_STEPS, MAX_FALSE_DETECTIONS, PAPER_STEPS,
};
use serde_json::Value;

/// A simulated mission with truth, as `nvector-mission/1` JSON.
///
/// Steps, landmarks and false detections above [`MAX_STEPS`],
/// [`MAX_LANDMARKS`] and [`MAX_FALSE_DETECTIONS`] are taken at those limits
/// (the front ends refuse them first): no allocation here is sized by an
/// unchecked number.
pub fn simulate(options: &SimulateOptions) -> Value {
    let o = SimulateOptions {
        steps: options.steps.map(|s| s.min(MAX_STEPS)),
        landmarks: options.landmarks.map(|n| n.min(MAX_LANDMARKS)),
        false_detections: options.false_detections.min(MAX_FALSE_DETECTIONS),
        ..options.clone()
    };
    match o.scenario {
        Scenario::Paper => paper(&o),
        Scenario::Auv => auv(&o),
        Scenario::Woods => simulate_woods_with(
            &WoodsOptions {
                seed: o.seed,
                steps: o.steps,
                landmarks: o.landmarks,
                operator: o.operator,
            },
            o.false_detections,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::paper::MIN_VISITS;
    use super::scenario::wrap;
    use super::*;
    use crate::format::leaf::Integer;
    use crate::slam::mission::Mission;

    /// Values that were changed silently (steps 0 or 1 became 2, 0
    /// landmarks 1) or ignored (landmarks for auv) are refused, named.
    #[test]
    fn out_of_range_and_foreign_options_are_refused_by_name() {
        let ask = |scenario: &str, steps: Option<u64>, landmarks: Option<u64>| {
            SimulateRequest {
                scenario: Some(Value::from(scenario)),
                seed: None,
                steps: steps.map(Integer::Value),
                landmarks: landmarks.map(Integer::Value),
                operator: None,
                noise: None,
                layout: None,
                range_only: None,
                false_detections: None,
            }
            .options(SimulateLimits::CORE)
        };
        for (scenario, steps, landmarks, path) in [
            ("paper", Some(0), None, "steps"),
            ("woods", Some(1), None, "steps"),
            ("paper", None, Some(0), "landmarks"),
            ("woods", None, Some(0), "landmarks"),
            ("auv", None, Some(5), "landmarks"),
        ] {
            let e = ask(scenario, steps, landmarks).expect_err(path);
            assert_eq!(e.path, path, "{scenario} {steps:?} {landmarks:?}: {e:?}");
        }
        let o = ask("paper", Some(2), Some(1)).unwrap();
        assert_eq!((o.steps, o.landmarks), (Some(2), Some(1)));
        assert!(ask("woods", None, Some(5)).is_ok());
    }

    #[test]
    fn deterministic_for_a_seed() {
        let a = simulate(&SimulateOptions::new(Scenario::Paper, 7));
        let b = simulate(&SimulateOptions::new(Scenario::Paper, 7));
        let c = simulate(&SimulateOptions::new(Scenario::Paper, 8));
        assert_eq!(a.to_string(), b.to_string());
        assert_ne!(a.to_string(), c.to_string());
        assert!(!a["detections"].as_array().unwrap().is_empty());
    }

    /// The default output must stay what it was before the layouts,
    /// range-only and false detections existed (figures, benchmarks and
    /// other tests are built on it). The fingerprints below were taken from
    /// main at commit 9f1a2d8 (the options added to the struct, the
    /// generator not yet changed), i.e. from the generator as it was; the
    /// same missions came out of `nvector simulate` there. Lengths are kept
    /// too so a mismatch says whether the text grew.
    #[test]
    fn default_output_is_unchanged() {
        let mut cases = vec![(
            SimulateOptions::new(Scenario::Paper, 1),
            784_990,
            0xafb6_afe8_ac62_5665u64,
        )];
        let mut o = SimulateOptions::new(Scenario::Paper, 7);
        o.operator = true;
        cases.push((o, 786_133, 0xdd4e_07a2_56c8_6a06));
        let mut o = SimulateOptions::new(Scenario::Paper, 3);
        o.landmarks = Some(6);
        o.steps = Some(4000);
        o.noise = 2.0;
        cases.push((o, 314_237, 0xa864_dbca_2f14_f097));
        let mut o = SimulateOptions::new(Scenario::Auv, 2);
        o.steps = Some(3000);
        cases.push((o, 542_623, 0x52fb_5d63_24a8_c929));
        for (o, len, hash) in cases {
            let s = simulate(&o).to_string();
            assert_eq!(
                (s.len(), crate::rng::fnv1a(s.bytes())),
                (len, hash),
                "{o:?}"
            );
        }
    }

    fn options(
        seed: u64,
        layout: Layout,
        range_only: bool,
        false_detections: usize,
    ) -> SimulateOptions {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        o.layout = layout;
        o.range_only = range_only;
        o.false_detections = false_detections;
        o
    }

    /// Every combination of the new options.
    fn variants() -> Vec<(Layout, bool, usize)> {
        let mut v = Vec::new();
        for layout in [Layout::Line, Layout::Ring, Layout::Random] {
            for range_only in [false, true] {
                for k in [0, 5] {
                    v.push((layout, range_only, k));
                }
            }
        }
        v
    }

    #[test]
    fn layout_names_round_trip() {
        for l in [Layout::Line, Layout::Ring, Layout::Random] {
            assert_eq!(Layout::parse(l.name()), Some(l));
        }
        assert_eq!(Layout::parse("circle"), None);
    }

    #[test]
    fn every_option_is_deterministic_for_a_seed() {
        for (layout, range_only, k) in variants() {
            let mut o = options(21, layout, range_only, k);
            o.steps = Some(4000);
            let a = simulate(&o).to_string();
            assert_eq!(a, simulate(&o).to_string(), "{o:?}");
            o.seed = 22;
            assert_ne!(a, simulate(&o).to_string(), "{o:?}");
        }
    }

    fn point(v: &Value) -> [f64; 2] {
        [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()]
    }

    fn interval(v: &Value) -> (f64, f64) {
        (v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
    }

    /// Checks, on the JSON, that the truth satisfies every detection
    /// constraint: a true detection's range holds the true distance, its
    /// bearing the true angle (relative to the true heading, the direction
    /// of the next step), its region the landmark; a false detection
    /// (`matching` null) has a range no landmark's true distance meets.
    /// Returns (true detections, false detections).
    fn check_truth(v: &Value) -> (usize, usize) {
        let t = &v["truth"];
        let positions: Vec<[f64; 2]> = t["positions"]
            .as_array()
            .unwrap()
            .iter()
            .map(point)
            .collect();
        let landmarks: Vec<[f64; 2]> = t["landmarks"]
            .as_array()
            .unwrap()
            .iter()
            .map(point)
            .collect();
        let dets = v["detections"].as_array().unwrap();
        let matching = t["matching"].as_array().unwrap();
        assert_eq!(dets.len(), matching.len());
        let (mut n_true, mut n_false) = (0, 0);
        let mut last = 0;
        for (d, m) in dets.iter().zip(matching) {
            let s = d["step"].as_u64().unwrap() as usize;
            assert!(s >= last, "detections sorted by step");
            last = s;
            let p = positions[s];
            let (lo, hi) = interval(&d["range"]);
            assert!(lo >= 0.0 && lo <= hi);
            match m.as_u64() {
                Some(j) => {
                    n_true += 1;
                    let l = landmarks[j as usize];
                    let r = libm::hypot(l[0] - p[0], l[1] - p[1]);
                    assert!(lo <= r && r <= hi, "range {lo}..{hi} misses {r}");
                    if let Some(b) = d.get("bearing") {
                        let (blo, bhi) = interval(b);
                        let q = positions[s + 1];
                        let heading = libm::atan2(q[1] - p[1], q[0] - p[0]);
                        let beta = libm::atan2(l[1] - p[1], l[0] - p[0]) - heading;
                        // The angle, moved by a multiple of 2 pi into the
                        // bearing's range.
                        let mid = 0.5 * (blo + bhi);
                        let beta = mid + wrap(beta - mid);
                        assert!(
                            blo < beta && beta < bhi,
                            "bearing {blo}..{bhi} misses {beta}"
                        );
                    }
                    if let Some(reg) = d.get("region") {
                        for a in 0..2 {
                            let (rlo, rhi) = interval(&reg[a]);
                            assert!(rlo < l[a] && l[a] < rhi, "region misses the landmark");
                        }
                    }
                }
                None => {
                    assert!(m.is_null());
                    n_false += 1;
                    for l in &landmarks {
                        let r = libm::hypot(l[0] - p[0], l[1] - p[1]);
                        assert!(r < lo || r > hi, "false detection meets a landmark");
                    }
                    assert!(d.get("landmark").is_none());
                }
            }
            assert_eq!(d.get("region").is_some(), d.get("bearing").is_none());
        }
        (n_true, n_false)
    }

    #[test]
    fn the_truth_satisfies_every_constraint() {
        for seed in 1..=4 {
            for (layout, range_only, k) in variants() {
                let mut o = options(seed, layout, range_only, k);
                o.operator = seed % 2 == 0;
                let v = simulate(&o);
                let (n_true, n_false) = check_truth(&v);
                assert!(n_true > 0);
                assert_eq!(n_false, k, "{o:?}");
                assert_eq!(v["max_outliers"].as_u64(), (k > 0).then_some(k as u64));
                for d in v["detections"].as_array().unwrap() {
                    assert_eq!(d.get("region").is_some(), range_only);
                }
                if k == 0 {
                    // A valid mission (missions with false detections need
                    // the `max_outliers` field of the mission format).
                    Mission::from_value(&v).expect("valid mission");
                }
            }
        }
    }

    /// True detections per landmark.
    fn visits(v: &Value) -> Vec<usize> {
        let n = v["landmark_count"].as_u64().unwrap() as usize;
        let mut c = vec![0; n];
        for m in v["truth"]["matching"].as_array().unwrap() {
            if let Some(j) = m.as_u64() {
                c[j as usize] += 1;
            }
        }
        c
    }

    #[test]
    fn every_landmark_is_detected_several_times() {
        for seed in 1..=10 {
            for layout in [Layout::Line, Layout::Ring, Layout::Random] {
                for n in [4, 6] {
                    if layout == Layout::Line && n > 4 {
                        continue; // the line outgrows the path beyond 4
                    }
                    let mut o = options(seed, layout, false, 0);
                    o.landmarks = Some(n);
                    let c = visits(&simulate(&o));
                    assert!(
                        c.iter().all(|&x| x >= MIN_VISITS),
                        "seed {seed} {layout:?} n {n}: {c:?}"
                    );
                }
            }
        }
    }

    /// The smallest gap between two landmarks' projections on an axis.
    fn min_gap(landmarks: &[[f64; 2]], axis: usize) -> f64 {
        let mut x: Vec<f64> = landmarks.iter().map(|l| l[axis]).collect();
        x.sort_by(f64::total_cmp);
        x.windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
    }

    fn landmarks_of(o: &SimulateOptions) -> Vec<[f64; 2]> {
        simulate(o)["truth"]["landmarks"]
            .as_array()
            .unwrap()
            .iter()
            .map(point)
            .collect()
    }

    #[test]
    fn ring_and_random_interleave_the_projections() {
        let mut random_close = 0;
        for seed in 1..=20 {
            let line = landmarks_of(&options(seed, Layout::Line, false, 0));
            // The line's landmarks are 10 m apart on x (±2 m of jitter).
            assert!(min_gap(&line, 0) > 7.0);
            // On the ring, landmarks pair up on both axes.
            for n in [4, 6] {
                let mut o = options(seed, Layout::Ring, false, 0);
                o.landmarks = Some(n);
                let ring = landmarks_of(&o);
                assert!(
                    min_gap(&ring, 0) < 2.0 && min_gap(&ring, 1) < 2.0,
                    "seed {seed}: {ring:?}"
                );
            }
            // Random: at least 8 m apart, yet usually close on both axes.
            let random = landmarks_of(&options(seed, Layout::Random, false, 0));
            for (i, a) in random.iter().enumerate() {
                for b in &random[i + 1..] {
                    assert!(libm::hypot(a[0] - b[0], a[1] - b[1]) >= 8.0);
                }
            }
            if min_gap(&random, 0) < 4.0 && min_gap(&random, 1) < 4.0 {
                random_close += 1;
            }
        }
        assert!(
            random_close >= 10,
            "{random_close} of 20 random layouts interleave"
        );
    }

    #[test]
    fn new_options_leave_the_main_stream_alone() {
        // False detections and regions draw from the second stream: the
        // true detections of a mission are those of the same mission
        // without false detections, and the inputs do not change at all.
        for (layout, range_only) in [
            (Layout::Line, false),
            (Layout::Ring, true),
            (Layout::Random, false),
        ] {
            let a = simulate(&options(5, layout, range_only, 0));
            let b = simulate(&options(5, layout, range_only, 7));
            assert_eq!(a["inputs"], b["inputs"]);
            assert_eq!(a["truth"]["positions"], b["truth"]["positions"]);
            let true_ones: Vec<&Value> = b["detections"]
                .as_array()
                .unwrap()
                .iter()
                .zip(b["truth"]["matching"].as_array().unwrap())
                .filter(|(_, m)| !m.is_null())
                .map(|(d, _)| d)
                .collect();
            let ranges = |ds: Vec<&Value>| {
                ds.iter()
                    .map(|d| (d["step"].clone(), d["range"].clone()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(
                ranges(a["detections"].as_array().unwrap().iter().collect()),
                ranges(true_ones)
            );
        }
        // Range-only changes neither the path nor the ranges.
        let a = simulate(&options(6, Layout::Line, false, 0));
        let b = simulate(&options(6, Layout::Line, true, 0));
        assert_eq!(a["inputs"], b["inputs"]);
        for (x, y) in a["detections"]
            .as_array()
            .unwrap()
            .iter()
            .zip(b["detections"].as_array().unwrap())
        {
            assert_eq!(x["range"], y["range"]);
        }
    }
}
