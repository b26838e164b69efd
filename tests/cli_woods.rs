//! `nvector import --utias-woods`: the UTIAS Lost in the Woods data set as
//! an odometry2d mission. The test reads the data's CSV files itself and
//! checks, with its own code (not the importer's nor core's), that the
//! truth satisfies every constraint of the mission at every valid step:
//! the heading chain, the motion chain (and, across each motion-capture
//! gap, a completion of the truth that satisfies every step), the initial
//! pose, every range and bearing from the offset laser, the minimum
//! separation of the tubes, distinct tubes within a scan, and the heading
//! and motion drift windows.

use nvector_tests::temp_file;
use serde_json::Value;
use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn woods_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/utias-lost-in-the-woods");
    assert!(
        dir.join("odometry.csv").exists(),
        "the Lost in the Woods data must be at {} (../shared beside the repository)",
        dir.display()
    );
    dir
}

/// Rows of numbers of a CSV with a header.
fn csv(name: &str) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(woods_dir().join(name)).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|c| c.trim().parse().unwrap()).collect())
        .collect()
}

fn import(operator: bool) -> Value {
    let out = temp_file(if operator {
        "woods-operator-ids.json"
    } else {
        "woods-hidden-ids.json"
    });
    let dir = woods_dir();
    let mut args = vec![
        "import",
        "--utias-woods",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    if operator {
        args.push("--operator");
    }
    let o = nvector_tests::nvector()
        .args(&args)
        .output()
        .expect("run nvector");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// `[lo, hi]` of a JSON pair.
fn iv(v: &Value) -> (f64, f64) {
    (f(&v[0]), f(&v[1]))
}

/// A per-step bound: one number or an array.
fn per_step(v: &Value, i: usize) -> f64 {
    if v.is_array() {
        f(&v[i])
    } else {
        f(v)
    }
}

/// `x` within `[lo, hi]`.
fn inside(x: f64, (lo, hi): (f64, f64)) -> bool {
    lo <= x && x <= hi
}

/// Whether some `x + 2 pi k` lies in `[lo, hi]`.
fn inside_mod_2pi(x: f64, (lo, hi): (f64, f64)) -> bool {
    let k = ((lo - x) / (2.0 * PI)).ceil();
    x + 2.0 * PI * k <= hi
}

/// The heading and motion constraints of step i for a given (completed)
/// truth.
fn step_holds(m: &Value, i: usize, h: (f64, f64), p: ([f64; 2], [f64; 2])) -> Result<(), String> {
    let dt = f(&m["dt"]);
    let v = f(&m["inputs"]["speed"]["value"][i]);
    let sv = per_step(&m["inputs"]["speed"]["error"], i);
    let w = f(&m["inputs"]["turn_rate"]["value"][i]);
    let sw = per_step(&m["inputs"]["turn_rate"]["error"], i);
    let he = per_step(&m["heading_error"], i);
    let me = per_step(&m["motion_error"], i);
    let r = h.1 - h.0 - dt * w;
    if r.abs() > he + dt * sw {
        return Err(format!("step {i}: heading residual {r} beyond {he}"));
    }
    // The speed error (0 here) would widen the displacement by dt * sv.
    for (a, trig) in [h.0.cos(), h.0.sin()].into_iter().enumerate() {
        let r = p.1[a] - p.0[a] - dt * v * trig;
        if r.abs() > me + dt * sv {
            return Err(format!(
                "step {i} axis {a}: motion residual {r} beyond {me}"
            ));
        }
    }
    Ok(())
}

/// `heading_drift`: every window `(k, b, exempt_above t)` holds the truth
/// at every pair of valid rows i, i + k, and the completion of the truth
/// by linear interpolation across each gap (the witness of the chain
/// checks) at every pair up to the last valid row:
/// `|th(i+k) - th(i) - S| <= b + X` for S the integrated turn rate (with
/// the input's error) and X the sum of the `heading_error` e_j > t over
/// the window (the exempt, flagged steps). The windows are also much
/// tighter than k per-step bounds (the point of them).
fn check_heading_drift(m: &Value, valid: &[bool], hd: &dyn Fn(usize) -> f64) {
    let n = valid.len() - 1;
    let dt = f(&m["dt"]);
    let last = (0..=n).rev().find(|&k| valid[k]).unwrap();
    let mut th = vec![0.0; last + 1];
    let mut k = 0;
    while k < last {
        let j = (k + 1..=last).find(|&j| valid[j]).unwrap();
        for (x, t) in th.iter_mut().enumerate().take(j + 1).skip(k) {
            *t = hd(k) + (x - k) as f64 / (j - k) as f64 * (hd(j) - hd(k));
        }
        k = j;
    }
    let (mut lo, mut hi) = (vec![0.0], vec![0.0]);
    for i in 0..n {
        let w = f(&m["inputs"]["turn_rate"]["value"][i]);
        let sw = per_step(&m["inputs"]["turn_rate"]["error"], i);
        lo.push(lo[i] + dt * (w - sw));
        hi.push(hi[i] + dt * (w + sw));
    }
    let he: Vec<f64> = (0..n).map(|i| per_step(&m["heading_error"], i)).collect();
    // The ordinary per-step bound: the smallest.
    let ordinary = he.iter().copied().fold(f64::INFINITY, f64::min);
    let windows = m["heading_drift"].as_array().expect("heading_drift");
    let (mut pairs, mut exempting) = (0usize, 0usize);
    for w in windows {
        let (k, b) = (w["steps"].as_u64().unwrap() as usize, f(&w["error"]));
        assert!(k <= n, "window {k} longer than the log");
        // The exempting windows leave out the flagged steps, and some
        // are; the others leave out none.
        let t = w.get("exempt_above").map(f);
        exempting += t.is_some() as usize;
        let mut x = vec![0.0];
        for i in 0..n {
            let exempt = t.is_some_and(|t| he[i] > t);
            x.push(x[i] + if exempt { he[i] } else { 0.0 });
        }
        assert!(
            t.is_none() || x[n] > 10.0,
            "window {k}: exempt sum {}",
            x[n]
        );
        for i in 0..=n - k {
            let (slo, shi) = (lo[i + k] - lo[i], hi[i + k] - hi[i]);
            let bx = b + (x[i + k] - x[i]);
            let holds = |d: f64| d - shi <= bx && slo - d <= bx;
            if valid[i] && valid[i + k] {
                let d = hd(i + k) - hd(i);
                assert!(holds(d), "window {k} at {i}: {d} vs [{slo}, {shi}] +- {bx}");
                pairs += 1;
            }
            if i + k <= last {
                let d = th[i + k] - th[i];
                assert!(
                    holds(d),
                    "completed truth, window {k} at {i}: {d} vs [{slo}, {shi}] +- {bx}"
                );
            }
        }
        // Tighter than k ordinary per-step bounds, ten times from 300
        // steps: the odometry's drift over 600 steps is under 0.6 rad (the
        // k-step table of docs/utias-woods.md, from the data), the
        // per-step bound about 0.025 rad.
        let per_step_sum = k as f64 * ordinary;
        assert!(b < per_step_sum, "window {k}: {b} >= {per_step_sum}");
        if k >= 300 {
            assert!(b < 0.1 * per_step_sum, "window {k}: {b}");
        }
    }
    assert!(exempting >= 50 && windows.len() > exempting, "{windows:?}");
    assert!(pairs > 500_000, "{pairs}");
    assert!(!m["meta"]["heading_drift"]["method"].is_null());
}

/// `motion_drift`: every window `(k, c)` holds the truth at every pair of
/// valid rows i, i + k (the headings inside from this test's own linear
/// completion of the gaps, the witness of the true heading), and the
/// completion itself (positions and headings) at every pair up to the
/// last valid row: `|p(i+k) - p(i) - sum_{j=i}^{i+k-1} dt v(j) (cos th(j),
/// sin th(j))| <= c` (Euclidean). Each bound is below k per-step motion
/// bounds × √2 (what the per-axis bounds give in any rotated frame: the
/// point of the windows).
fn check_motion_drift(
    m: &Value,
    valid: &[bool],
    pos: &dyn Fn(usize) -> [f64; 2],
    hd: &dyn Fn(usize) -> f64,
) {
    let n = valid.len() - 1;
    let dt = f(&m["dt"]);
    let last = (0..=n).rev().find(|&k| valid[k]).unwrap();
    // The completion: linear interpolation between the valid ends.
    let (mut th, mut p) = (vec![0.0; last + 1], vec![[0.0; 2]; last + 1]);
    let mut k = 0;
    while k < last {
        let j = (k + 1..=last).find(|&j| valid[j]).unwrap();
        for x in k..=j {
            let s = (x - k) as f64 / (j - k) as f64;
            th[x] = hd(k) + s * (hd(j) - hd(k));
            p[x] = [
                pos(k)[0] + s * (pos(j)[0] - pos(k)[0]),
                pos(k)[1] + s * (pos(j)[1] - pos(k)[1]),
            ];
        }
        k = j;
    }
    // The speed error is 0 (the import says so): the true speed is the
    // odometry's, and the sums below are the model's exactly.
    let (mut sx, mut sy) = (vec![0.0], vec![0.0]);
    for i in 0..last {
        assert_eq!(per_step(&m["inputs"]["speed"]["error"], i), 0.0);
        let v = f(&m["inputs"]["speed"]["value"][i]);
        sx.push(sx[i] + dt * v * th[i].cos());
        sy.push(sy[i] + dt * v * th[i].sin());
    }
    let me: Vec<f64> = (0..n).map(|i| per_step(&m["motion_error"], i)).collect();
    let ordinary = me.iter().copied().fold(f64::INFINITY, f64::min);
    let windows = m["motion_drift"].as_array().expect("motion_drift");
    let mut pairs = 0usize;
    let mut seen = HashSet::new();
    for w in windows {
        let (k, c) = (w["steps"].as_u64().unwrap() as usize, f(&w["error"]));
        assert!(k >= 1 && k <= n && c >= 0.0, "window {w}");
        seen.insert(k);
        for i in 0..(last + 1).saturating_sub(k) {
            let d = [sx[i + k] - sx[i], sy[i + k] - sy[i]];
            if valid[i] && valid[i + k] {
                let (a, b) = (pos(i), pos(i + k));
                let r = (b[0] - a[0] - d[0]).hypot(b[1] - a[1] - d[1]);
                assert!(r <= c, "window {k} at {i}: {r} > {c}");
                pairs += 1;
            }
            let r = (p[i + k][0] - p[i][0] - d[0]).hypot(p[i + k][1] - p[i][1] - d[1]);
            assert!(r <= c, "completed truth, window {k} at {i}: {r} > {c}");
        }
        let per_step_sum = k as f64 * ordinary * 2f64.sqrt();
        assert!(c < per_step_sum, "window {k}: {c} >= {per_step_sum}");
    }
    // The windows the issue asks for (10 s of odometry and beyond).
    for k in [10, 30, 60, 100, 300] {
        assert!(seen.contains(&k), "no motion_drift window of {k} steps");
    }
    assert!(pairs > 500_000, "{pairs}");
    assert!(!m["meta"]["motion_drift"]["method"].is_null());
}

fn check_truth_satisfies_mission(m: &Value, operator: bool) {
    let odo = csv("odometry.csv");
    let truth = csv("truth.csv");
    let meas = csv("measurements.csv");
    let lms = csv("landmarks.csv");
    let n = odo.len() - 1;
    assert_eq!(m["model"], "odometry2d");
    assert_eq!(m["steps"].as_u64(), Some(n as u64));
    assert_eq!(m["landmark_count"].as_u64(), Some(17));
    assert_eq!(m["sensor_offset"], serde_json::json!([0.219016, 0.0]));
    let dt = f(&m["dt"]);
    assert!((dt - 0.1).abs() < 1e-9);
    // Inputs are the odometry rows 0..N-1.
    for i in 0..n {
        assert_eq!(f(&m["inputs"]["speed"]["value"][i]), odo[i][1]);
        assert_eq!(f(&m["inputs"]["turn_rate"]["value"][i]), odo[i][2]);
    }
    // Truth: null exactly where the motion capture is not valid; headings
    // congruent to theta modulo 2 pi.
    let t = &m["truth"];
    let (tp, th) = (
        t["positions"].as_array().unwrap(),
        t["headings"].as_array().unwrap(),
    );
    assert_eq!((tp.len(), th.len()), (n + 1, n + 1));
    let mut valid = vec![false; n + 1];
    for k in 0..=n {
        valid[k] = truth[k][4] != 0.0;
        assert_eq!(tp[k].is_null(), !valid[k], "row {k}");
        assert_eq!(th[k].is_null(), !valid[k], "row {k}");
        if valid[k] {
            assert_eq!((f(&tp[k][0]), f(&tp[k][1])), (truth[k][1], truth[k][2]));
            let d = f(&th[k]) - truth[k][3];
            assert!(
                (d / (2.0 * PI) - (d / (2.0 * PI)).round()).abs() < 1e-9,
                "row {k}: {d}"
            );
        }
    }
    assert_eq!(valid.iter().filter(|&&v| !v).count(), 331);
    let pos = |k: usize| [f(&tp[k][0]), f(&tp[k][1])];
    let hd = |k: usize| f(&th[k]);
    // Initial pose.
    let ip = &m["initial_position"];
    assert!(inside(pos(0)[0], iv(&ip[0])) && inside(pos(0)[1], iv(&ip[1])));
    assert!(inside(hd(0), iv(&m["initial_heading"])));
    // The chains: every step between valid rows; across a gap, the
    // completion by linear interpolation between its valid ends (a witness
    // that a completion of the truth satisfies every step of the gap).
    let mut k = 0;
    let mut steps_checked = 0;
    while k < n {
        let j = (k + 1..=n).find(|&j| valid[j]);
        let Some(j) = j else { break };
        for i in k..j {
            let s = |x: usize| (x - k) as f64 / (j - k) as f64;
            let h = |x: usize| hd(k) + s(x) * (hd(j) - hd(k));
            let p = |x: usize| {
                [
                    pos(k)[0] + s(x) * (pos(j)[0] - pos(k)[0]),
                    pos(k)[1] + s(x) * (pos(j)[1] - pos(k)[1]),
                ]
            };
            let (h0, h1) = if i == k {
                (hd(k), h(i + 1))
            } else {
                (h(i), h(i + 1))
            };
            let h1 = if i + 1 == j { hd(j) } else { h1 };
            let p0 = if i == k { pos(k) } else { p(i) };
            let p1 = if i + 1 == j { pos(j) } else { p(i + 1) };
            step_holds(m, i, (h0, h1), (p0, p1)).unwrap();
            steps_checked += 1;
        }
        k = j;
    }
    assert!(steps_checked >= n - 10, "{steps_checked} of {n}");
    check_heading_drift(m, &valid, &hd);
    check_motion_drift(m, &valid, &pos, &hd);
    // Landmarks and their separation.
    let tl = t["landmarks"].as_array().unwrap();
    assert_eq!(tl.len(), 17);
    for r in &lms {
        let l = &tl[r[0] as usize];
        assert_eq!((f(&l[0]), f(&l[1])), (r[1], r[2]));
    }
    let sep = f(&m["landmark_min_separation"]);
    assert!(sep > 1.0, "{sep}");
    for a in 0..17 {
        for b in a + 1..17 {
            let d = (f(&tl[a][0]) - f(&tl[b][0])).hypot(f(&tl[a][1]) - f(&tl[b][1]));
            assert!(d >= sep, "tubes {a} and {b}: {d} < {sep}");
        }
    }
    // Detections: one per measurement row, in order; each range and
    // bearing holds the truth; scans see distinct tubes.
    let dets = m["detections"].as_array().unwrap();
    let matching = t["matching"].as_array().unwrap();
    assert_eq!((dets.len(), matching.len()), (meas.len(), meas.len()));
    let off = 0.219016;
    let mut scans: HashMap<u64, HashSet<u64>> = HashMap::new();
    let mut checked = 0;
    for (j, (d, r)) in dets.iter().zip(&meas).enumerate() {
        let step = d["step"].as_u64().unwrap() as usize;
        assert_eq!(step, (r[0] / dt).round() as usize, "detection {j}");
        let label = r[1] as u64;
        assert_eq!(matching[j].as_u64(), Some(label));
        if operator {
            assert_eq!(d["landmark"].as_u64(), Some(label));
        } else {
            assert!(
                d.get("landmark").is_none(),
                "detection {j}: the labels are hidden"
            );
        }
        let scan = d["scan"].as_u64().expect("every detection has a scan");
        assert!(
            scans.entry(scan).or_default().insert(label),
            "detection {j}: tube {label} twice in scan {scan}"
        );
        let (range, bearing) = (iv(&d["range"]), iv(&d["bearing"]));
        assert!(
            inside(r[2], range) && inside_mod_2pi(r[3], bearing),
            "detection {j}: the measurement itself is outside"
        );
        if !valid[step] {
            continue;
        }
        let (p, h) = (pos(step), hd(step));
        let s = [p[0] + off * h.cos(), p[1] + off * h.sin()];
        let l = [f(&tl[label as usize][0]), f(&tl[label as usize][1])];
        let (dx, dy) = (l[0] - s[0], l[1] - s[1]);
        let dist = dx.hypot(dy);
        assert!(
            inside(dist, range),
            "detection {j} (step {step}): true range {dist} not in {range:?}"
        );
        let beta = dy.atan2(dx) - h;
        assert!(
            inside_mod_2pi(beta, bearing),
            "detection {j} (step {step}): true bearing {beta} not in {bearing:?} mod 2 pi"
        );
        checked += 1;
    }
    assert!(checked > 59_000, "{checked}");
    // Detections at the same step share their scan.
    for w in dets.windows(2) {
        assert_eq!(w[0]["step"] == w[1]["step"], w[0]["scan"] == w[1]["scan"]);
    }
    // Tightness, against the data's README (not the importer's output):
    // range residuals from the laser -0.092 to +0.155 m, bearing residuals
    // -0.19 to +0.14 rad, heading steps within 0.018 rad on 98 % of the
    // steps; bounds much wider than that (a wrong sensor point or heading
    // model absorbed by wider bands) fail here.
    for d in dets {
        let (r, b) = (iv(&d["range"]), iv(&d["bearing"]));
        assert!(r.1 - r.0 < 0.30 && b.1 - b.0 < 0.36, "{d}");
    }
    // The range-dependent bands are narrower on average than the constant
    // ones (which they are intersected with; the loop above checked that
    // every true range and bearing is inside).
    let mean = |key: &str| {
        dets.iter()
            .map(|d| iv(&d[key]).1 - iv(&d[key]).0)
            .sum::<f64>()
            / dets.len() as f64
    };
    let constant = |key: &str, margin: &str| {
        let b = iv(&m["meta"][key]);
        b.1 - b.0 + 2.0 * f(&m["meta"][margin])
    };
    assert!(
        mean("bearing") < 0.6 * constant("bearing_error_bounds", "bearing_margin"),
        "{}",
        mean("bearing")
    );
    assert!(
        mean("range") < constant("range_error_bounds", "range_margin"),
        "{}",
        mean("range")
    );
    let he = m["heading_error"].as_array().unwrap();
    let ordinary = he.iter().filter(|e| f(e) < 0.03).count();
    assert!(
        ordinary * 100 > he.len() * 95,
        "{ordinary} of {} steps",
        he.len()
    );
    // The bounds' method is recorded.
    let meta = &m["meta"];
    for key in [
        "method",
        "heading_error",
        "motion_error",
        "range_error_bounds",
        "bearing_error_bounds",
        "true_min_separation",
    ] {
        assert!(!meta[key].is_null(), "meta.{key}");
    }
}

#[test]
fn woods_truth_satisfies_the_mission_with_hidden_ids() {
    check_truth_satisfies_mission(&import(false), false);
}

#[test]
fn woods_truth_satisfies_the_mission_with_operator_ids() {
    check_truth_satisfies_mission(&import(true), true);
}

#[test]
fn woods_import_names_a_missing_file() {
    let dir = temp_file("empty-woods");
    std::fs::create_dir_all(&dir).unwrap();
    let o = nvector_tests::nvector()
        .args(["import", "--utias-woods", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("odometry.csv"), "{err}");
}

#[test]
fn simulate_woods_through_the_cli() {
    let run = |operator: bool, name: &str| {
        let out = temp_file(name);
        let mut args = vec![
            "simulate",
            "--scenario",
            "woods",
            "--seed",
            "4",
            "--steps",
            "500",
            "--landmarks",
            "9",
            "--out",
            out.to_str().unwrap(),
        ];
        if operator {
            args.push("--operator");
        }
        let o = nvector_tests::nvector().args(&args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str::<Value>(&std::fs::read_to_string(&out).unwrap()).unwrap()
    };
    let (a, b, hidden) = (
        run(true, "sim-a.json"),
        run(true, "sim-b.json"),
        run(false, "sim-c.json"),
    );
    assert_eq!(a, b, "deterministic for a seed");
    assert_eq!(a["model"], "odometry2d");
    assert_eq!(a["steps"].as_u64(), Some(500));
    assert_eq!(a["truth"]["headings"].as_array().unwrap().len(), 501);
    assert_eq!(a["truth"]["landmarks"].as_array().unwrap().len(), 9);
    let dets = a["detections"].as_array().unwrap();
    assert!(
        !dets.is_empty()
            && dets
                .iter()
                .all(|d| d["landmark"].is_u64() && d["scan"].is_u64())
    );
    assert!(hidden["detections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|d| d.get("landmark").is_none()));
    let o = nvector_tests::nvector()
        .args(["simulate", "--scenario", "forest"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("woods"));
}

#[test]
fn woods_import_plants_false_ranges() {
    let out = temp_file("woods-false-detections.json");
    let dir = woods_dir();
    let o = nvector_tests::nvector()
        .args([
            "import",
            "--utias-woods",
            dir.to_str().unwrap(),
            "--false-detections",
            "30",
            "--seed",
            "2",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let plain = import(false);
    assert_eq!(m["max_outliers"].as_u64(), Some(30));
    let (dets, truth) = (
        m["detections"].as_array().unwrap(),
        m["truth"]["matching"].as_array().unwrap(),
    );
    // The planted ones: null in the truth, a range only (no bearing, no
    // scan: a false detection is in no scan of the laser).
    let planted: Vec<&Value> = dets
        .iter()
        .zip(truth)
        .filter(|(_, t)| t.is_null())
        .map(|(d, _)| d)
        .collect();
    assert_eq!(planted.len(), 30);
    let (not_false, checked) = nvector_tests::planted_ranges_not_false(&m);
    assert_eq!(checked, 30);
    assert!(not_false.is_empty(), "{not_false:?}");
    assert!(planted
        .iter()
        .all(|d| d.get("bearing").is_none() && d.get("scan").is_none()));
    // The real ones are the plain import's, in the same order.
    let real: Vec<&Value> = dets
        .iter()
        .zip(truth)
        .filter(|(_, t)| !t.is_null())
        .map(|(d, _)| d)
        .collect();
    let plain_dets: Vec<&Value> = plain["detections"].as_array().unwrap().iter().collect();
    assert_eq!(real, plain_dets);
}
