//! `slam::check` (`nvector check`): no violation in truthful missions
//! (random worlds whose bounds are fitted on the truth, many of them
//! exactly: the truth on the boundary; unbounded bounds; zero and huge
//! coordinates; the simulators' missions), and exactly the planted one,
//! with its path and excess, when one bound of such a mission is moved
//! past the truth by a known amount, for each kind of constraint.

use crate::common::Rng;
use nvector_core::slam::check::types::Violation;
use nvector_core::slam::check::{check_value, Report};
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use serde_json::{json, Value};

fn cos(x: f64) -> f64 {
    libm::cos(x)
}
fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// An odometry2d world: truth drawn within bounds, then the bounds fitted
/// on the truth (tight: exactly the float residual, the truth on the
/// boundary; else with a random margin).
struct World {
    m: Value,
    /// True positions, headings, landmarks.
    p: Vec<[f64; 2]>,
    th: Vec<f64>,
    lm: Vec<[f64; 2]>,
    /// Per detection: (step, landmark, true range, true bearing).
    det: Vec<(usize, usize, f64, f64)>,
    dt: f64,
    speed: Vec<f64>,
    turn: Vec<f64>,
    offset: [f64; 2],
    /// The magnitude of the coordinates.
    scale: f64,
}

/// A margin: 0 (tight) or a small random one.
fn margin(r: &mut Rng, tight: bool) -> f64 {
    if tight {
        0.0
    } else {
        r.slack(0.3, 0.1)
    }
}

/// The margin of a bound fitted on a value computed in floats (a sine, a
/// square root, a difference of coordinates of magnitude `scale`): the
/// value is within a few ulps of the exact one, so the tight bound is that
/// value widened by 1e-12 relative (the truth is then on the boundary up
/// to 1e-12 of the magnitudes, and inside it exactly).
fn computed(r: &mut Rng, tight: bool, x: f64, scale: f64) -> f64 {
    margin(r, tight) + 1e-12 * (1.0 + x.abs() + scale)
}

fn odometry_world(seed: u64, scale: f64) -> World {
    let mut r = Rng::new(seed);
    let tight = r.chance(0.5);
    let n = 3 + r.below(25);
    let dt = r.range(0.05, 1.0);
    let offset = if r.chance(0.5) {
        [r.range(-0.5, 0.5), r.range(-0.5, 0.5)]
    } else {
        [0.0, 0.0]
    };
    let mut p = vec![[r.range(-1.0, 1.0) * scale, r.range(-1.0, 1.0) * scale]];
    let mut th = vec![r.range(-3.0, 3.0)];
    let (mut speed, mut turn) = (Vec::new(), Vec::new());
    for i in 0..n {
        let (s, w) = (r.range(-0.5, 2.0), r.range(-0.5, 0.5));
        speed.push(s);
        turn.push(w);
        th.push(th[i] + dt * w + r.range(-0.01, 0.01));
        let (c, sn) = (cos(th[i]), sin(th[i]));
        p.push([
            p[i][0] + dt * s * c + r.range(-0.05, 0.05),
            p[i][1] + dt * s * sn + r.range(-0.05, 0.05),
        ]);
    }
    let lm: Vec<[f64; 2]> = (0..2 + r.below(5))
        .map(|_| {
            [
                p[0][0] + r.range(-30.0, 30.0),
                p[0][1] + r.range(-30.0, 30.0),
            ]
        })
        .collect();
    let mut det = Vec::new();
    // Every landmark seen (operator ids are the true ids, below
    // landmark_count), then more detections.
    for j in 0..lm.len() + r.below(8) {
        let t = r.below(n + 1);
        let l = if j < lm.len() { j } else { r.below(lm.len()) };
        let (c, s) = (cos(th[t]), sin(th[t]));
        let sx = p[t][0] + c * offset[0] - s * offset[1];
        let sy = p[t][1] + s * offset[0] + c * offset[1];
        let (dx, dy) = (lm[l][0] - sx, lm[l][1] - sy);
        det.push((
            t,
            l,
            (dx * dx + dy * dy).sqrt(),
            libm::atan2(dy, dx) - th[t],
        ));
    }
    let mut w = World {
        m: Value::Null,
        p,
        th,
        lm,
        det,
        dt,
        speed,
        turn,
        offset,
        scale,
    };
    w.m = w.mission(&mut r, tight);
    w
}

impl World {
    fn n(&self) -> usize {
        self.speed.len()
    }

    /// The heading residual of step i (float).
    fn heading_residual(&self, i: usize) -> f64 {
        (self.th[i + 1] - self.th[i] - self.dt * self.turn[i]).abs()
    }

    /// The largest per-axis position residual of step i (float).
    fn motion_residual(&self, i: usize) -> f64 {
        let s = self.dt * self.speed[i];
        let dx = self.p[i + 1][0] - self.p[i][0] - s * cos(self.th[i]);
        let dy = self.p[i + 1][1] - self.p[i][1] - s * sin(self.th[i]);
        dx.abs().max(dy.abs())
    }

    /// The heading drift residual over `[i, i + k)`.
    fn heading_window(&self, i: usize, k: usize) -> f64 {
        let sum: f64 = (i..i + k).map(|j| self.dt * self.turn[j]).sum();
        (self.th[i + k] - self.th[i] - sum).abs()
    }

    /// The motion drift residual's norm over `[i, i + k)`.
    fn motion_window(&self, i: usize, k: usize) -> f64 {
        let (mut x, mut y) = (
            self.p[i + k][0] - self.p[i][0],
            self.p[i + k][1] - self.p[i][1],
        );
        for j in i..i + k {
            x -= self.dt * self.speed[j] * cos(self.th[j]);
            y -= self.dt * self.speed[j] * sin(self.th[j]);
        }
        (x * x + y * y).sqrt()
    }

    /// A heading drift window of k steps that exempts the steps whose
    /// bound is above the median, with the least bound the truth allows:
    /// the largest, over the starts, of the residual less the exempt
    /// steps' bounds (0 at least).
    fn exempt_heading_window(&self, he: &[f64], k: usize) -> Value {
        let mut sorted = he.to_vec();
        sorted.sort_by(f64::total_cmp);
        let t = sorted[sorted.len() / 2];
        let b = (0..=self.n() - k)
            .map(|i| {
                let x: f64 = he[i..i + k].iter().filter(|&&e| e > t).sum();
                self.heading_window(i, k) - x
            })
            .fold(0.0, f64::max);
        json!({"steps": k, "error": b + 1e-12 * (1.0 + self.scale), "exempt_above": t})
    }

    /// The same for the motion drift (each exempt step counts e·√2).
    fn exempt_motion_window(&self, me: &[f64], k: usize) -> Value {
        let mut sorted = me.to_vec();
        sorted.sort_by(f64::total_cmp);
        let t = sorted[sorted.len() / 2];
        let c = (0..=self.n() - k)
            .map(|i| {
                let x: f64 = me[i..i + k].iter().filter(|&&e| e > t).sum();
                self.motion_window(i, k) - x * std::f64::consts::SQRT_2
            })
            .fold(0.0, f64::max);
        json!({"steps": k, "error": c + 1e-12 * (1.0 + self.scale), "exempt_above": t})
    }

    fn interval(r: &mut Rng, x: f64, tight: bool) -> Value {
        let lo = if r.chance(0.1) {
            json!("-inf")
        } else {
            json!(x - margin(r, tight))
        };
        let hi = if r.chance(0.1) {
            json!("inf")
        } else {
            json!(x + margin(r, tight))
        };
        json!([lo, hi])
    }

    fn mission(&self, r: &mut Rng, tight: bool) -> Value {
        let n = self.n();
        let he: Vec<f64> = (0..n)
            .map(|i| self.heading_residual(i) + computed(r, tight, 1.0, self.scale))
            .collect();
        let me: Vec<f64> = (0..n)
            .map(|i| self.motion_residual(i) + computed(r, tight, 1.0, self.scale))
            .collect();
        let k = 1 + r.below(n);
        let hb = (0..=n - k)
            .map(|i| self.heading_window(i, k))
            .fold(0.0, f64::max)
            + 1e-12 * (1.0 + self.scale);
        let mb = (0..=n - k)
            .map(|i| self.motion_window(i, k))
            .fold(0.0, f64::max)
            + 1e-12 * (1.0 + self.scale);
        let dets: Vec<Value> = self
            .det
            .iter()
            .enumerate()
            .map(|(j, &(t, l, range, bearing))| {
                let turns = (r.below(5) as f64 - 2.0) * std::f64::consts::TAU;
                let b = bearing + turns;
                let (r0, r1) = (
                    computed(r, tight, range, self.scale),
                    computed(r, tight, range, self.scale),
                );
                let (b0, b1) = (
                    computed(r, tight, b, self.scale),
                    computed(r, tight, b, self.scale),
                );
                let mut d = json!({"step": t, "range": [range - r0, range + r1],
                    "bearing": [b - b0, b + b1], "landmark": l});
                if r.chance(0.3) {
                    d["region"] = json!([
                        Self::interval(r, self.lm[l][0], tight),
                        Self::interval(r, self.lm[l][1], tight)
                    ]);
                }
                // One scan per detection (distinct landmarks trivially).
                d["scan"] = json!(j);
                d
            })
            .collect();
        let (x0, xn) = (self.p[0], self.p[n]);
        let mut seen: Vec<usize> = self.det.iter().map(|d| d.1).collect();
        seen.sort();
        seen.dedup();
        let mut sep = f64::INFINITY;
        for (x, &a) in seen.iter().enumerate() {
            for &b in &seen[x + 1..] {
                let (dx, dy) = (self.lm[a][0] - self.lm[b][0], self.lm[a][1] - self.lm[b][1]);
                sep = sep.min((dx * dx + dy * dy).sqrt());
            }
        }
        let lx = self.lm.iter().map(|l| l[0]);
        let ly = self.lm.iter().map(|l| l[1]);
        let region = json!([
            [
                lx.clone().fold(f64::INFINITY, f64::min),
                lx.fold(f64::NEG_INFINITY, f64::max)
            ],
            [
                ly.clone().fold(f64::INFINITY, f64::min),
                ly.fold(f64::NEG_INFINITY, f64::max)
            ]
        ]);
        let mut m = json!({
            "format": "nvector-mission/1", "model": "odometry2d", "dt": self.dt, "steps": n,
            "initial_position": [Self::interval(r, x0[0], tight), Self::interval(r, x0[1], tight)],
            "final_position": [Self::interval(r, xn[0], tight), Self::interval(r, xn[1], tight)],
            "initial_heading": Self::interval(r, self.th[0], tight),
            "final_heading": Self::interval(r, self.th[n], tight),
            "inputs": {"speed": {"value": self.speed, "error": 0.0}, "turn_rate": {"value": self.turn, "error": 0.0}},
            "heading_error": he, "motion_error": me,
            "heading_drift": [{"steps": k, "error": hb}, {"steps": n + 5, "error": 0.0}, self.exempt_heading_window(&he, k)],
            "motion_drift": [{"steps": k, "error": mb}, self.exempt_motion_window(&me, k)],
            "sensor_offset": self.offset,
            "detections": dets,
            "landmark_count": seen.len(),
            "landmark_region": region,
            "truth": {"positions": self.p, "landmarks": self.lm, "headings": self.th,
                      "matching": self.det.iter().map(|d| d.1).collect::<Vec<_>>()}
        });
        if seen.len() > 1 {
            m["landmark_min_separation"] = json!(sep - 1e-12 * (sep + self.scale));
        }
        m
    }
}

/// A mission of the world with one edit, checked.
type Plant<'a> = dyn Fn(&dyn Fn(&mut Value)) -> Report + 'a;

fn check(m: &Value) -> Report {
    check_value(m).unwrap_or_else(|e| panic!("{e}: {m}"))
}

/// The one violation of `r`, at `path`, with an excess within `tol` of
/// `excess`.
fn only(r: &Report, path: &str, kind: &str, excess: f64, tol: f64) -> Violation {
    let v: Vec<&Violation> = r.violations.iter().collect();
    assert_eq!(
        v.len(),
        1,
        "expected exactly {path}, found {:?}",
        r.violations
    );
    assert_eq!(v[0].path, path);
    assert_eq!(v[0].kind.name(), kind);
    assert!(
        (v[0].excess - excess).abs() <= tol,
        "{path}: excess {} instead of {excess}",
        v[0].excess
    );
    assert!(v[0].excess > 0.0 && !v[0].outlier);
    v[0].clone()
}

#[test]
fn truthful_odometry_worlds_have_no_violation() {
    for seed in 0..2000u64 {
        let scale = [0.0, 1.0, 1e3, 1e6][(seed % 4) as usize];
        let w = odometry_world(seed, scale);
        let r = check(&w.m);
        assert!(r.violations.is_empty(), "seed {seed}: {:?}", r.violations);
        assert_eq!(r.unchecked, 0);
    }
}

#[test]
fn unknown_truth_is_not_checked_and_breaks_nothing() {
    let w = odometry_world(7, 1.0);
    let mut m = w.m.clone();
    m["truth"]["positions"][1] = Value::Null;
    m["truth"]["headings"][2] = Value::Null;
    let r = check(&m);
    assert!(r.violations.is_empty(), "{:?}", r.violations);
    assert!(r.unchecked > 0);
}

/// Each kind of constraint of an odometry2d mission, moved past the truth
/// by delta: exactly that violation, with excess delta.
#[test]
fn each_planted_odometry_violation_is_found_exactly() {
    for seed in 0..300u64 {
        let w = odometry_world(seed, [1.0, 1e3][(seed % 2) as usize]);
        let delta = [1e-3, 0.5, 7.0][(seed % 3) as usize];
        let n = w.n();
        let i = seed as usize % n;
        let tol = 1e-9 * (1.0 + delta) + 1e-9 * w.p[0][0].abs();
        let plant = |f: &dyn Fn(&mut Value)| {
            let mut m = w.m.clone();
            // The exempting windows read the per-step bounds: without
            // them, lowering a step's bound breaks that step alone.
            for name in ["heading_drift", "motion_drift"] {
                m[name]
                    .as_array_mut()
                    .unwrap()
                    .retain(|w| w.get("exempt_above").is_none());
            }
            f(&mut m);
            check(&m)
        };
        let x0 = w.p[0][0];
        let r = plant(&|m| m["initial_position"][0] = json!([x0 + delta, x0 + delta + 1.0]));
        only(&r, "initial_position[0]", "initial_position", delta, tol);
        let yn = w.p[n][1];
        let r = plant(&|m| m["final_position"][1] = json!([yn - delta - 1.0, yn - delta]));
        only(&r, "final_position[1]", "final_position", delta, tol);
        let t0 = w.th[0];
        let r = plant(&|m| m["initial_heading"] = json!([t0 + delta, t0 + delta]));
        only(&r, "initial_heading", "initial_heading", delta, 1e-9);
        let tn = w.th[n];
        let r = plant(&|m| m["final_heading"] = json!([tn - delta - 1.0, tn - delta]));
        only(&r, "final_heading", "final_heading", delta, 1e-9);
        // The step's own bound lowered below its residual (the drift
        // windows, whose bounds do not depend on it, still hold).
        let small = delta.min(1e-3);
        let hr = w.heading_residual(i);
        if hr > small {
            let r = plant(&|m| m["heading_error"][i] = json!(hr - small));
            only(
                &r,
                &format!("heading_error[{i}]"),
                "heading_step",
                small,
                1e-9,
            );
        }
        let mr = w.motion_residual(i);
        if mr > small {
            let r = plant(&|m| m["motion_error"][i] = json!(mr - small));
            only(
                &r,
                &format!("motion_error[{i}]"),
                "motion_step",
                small,
                1e-9,
            );
        }
        planted_windows(&w, small, &plant);
        planted_detection(&w, seed, delta, &plant);
    }
}

/// The drift windows over the whole run (one window start, i = 0).
fn planted_windows(w: &World, small: f64, plant: &Plant) {
    let n = w.n();
    let hw = w.heading_window(0, n);
    if hw > small {
        let r = plant(&|m| m["heading_drift"] = json!([{"steps": n, "error": hw - small}]));
        only(&r, "heading_drift[0]", "heading_drift", small, 1e-9);
    }
    let mw = w.motion_window(0, n);
    if mw > small {
        let r = plant(&|m| m["motion_drift"] = json!([{"steps": n, "error": mw - small}]));
        let v = only(&r, "motion_drift[0]", "motion_drift", small, 1e-9);
        assert_eq!(v.step, Some(0));
    }
}

fn planted_detection(w: &World, seed: u64, delta: f64, plant: &Plant) {
    let j = seed as usize % w.det.len();
    let (t, l, range, bearing) = w.det[j];
    let tol = 1e-9 * (1.0 + range);
    let r = plant(&|m| m["detections"][j]["range"] = json!([range + delta, range + delta + 1.0]));
    let v = only(&r, &format!("detections[{j}].range"), "range", delta, tol);
    assert_eq!(
        (v.step, v.landmark, v.detection),
        (Some(t), Some(l), Some(j))
    );
    if delta < 3.0 {
        let r = plant(&|m| {
            m["detections"][j]["bearing"] = json!([bearing - 0.2 - delta, bearing - delta])
        });
        only(
            &r,
            &format!("detections[{j}].bearing"),
            "bearing",
            delta,
            1e-9,
        );
    }
    let lx = w.lm[l][0];
    let r =
        plant(&|m| m["detections"][j]["region"] = json!([[lx + delta, "inf"], ["-inf", "inf"]]));
    only(
        &r,
        &format!("detections[{j}].region[0]"),
        "region",
        delta,
        tol,
    );
    // The landmark region: its lower x raised past the leftmost landmark
    // (by less than the gap to the next).
    let mut xs: Vec<f64> = w.lm.iter().map(|l| l[0]).collect();
    xs.sort_by(f64::total_cmp);
    let d = delta.min((xs[1] - xs[0]) / 2.0);
    if d > 0.0 {
        let r = plant(&|m| m["landmark_region"][0] = json!([xs[0] + d, "inf"]));
        only(
            &r,
            "landmark_region[0]",
            "landmark_region",
            d,
            1e-9 * (1.0 + xs[0].abs()),
        );
    }
    let seen = w.m["landmark_count"].as_u64().unwrap() as usize;
    if seen > 1 {
        let r = plant(&|m| {
            m["landmark_count"] = json!(seen - 1);
            for d in m["detections"].as_array_mut().unwrap() {
                d.as_object_mut().unwrap().remove("landmark");
            }
        });
        only(&r, "landmark_count", "landmark_count", 1.0, 0.0);
        planted_pairs(w, delta, plant);
    }
}

/// Operator ids, scans and the separation.
fn planted_pairs(w: &World, delta: f64, plant: &Plant) {
    let a = 0;
    let Some(b) = (1..w.det.len()).find(|&b| w.det[b].1 != w.det[a].1) else {
        return;
    };
    let la = w.det[a].1;
    let r = plant(&|m| m["detections"][b]["landmark"] = json!(la));
    only(
        &r,
        &format!("detections[{b}].landmark"),
        "landmark",
        1.0,
        0.0,
    );
    if let Some(c) = (1..w.det.len()).find(|&c| w.det[c].1 == w.det[a].1) {
        let r = plant(&|m| m["detections"][c]["scan"] = json!(0));
        only(&r, &format!("detections[{c}].scan"), "scan", 1.0, 0.0);
    }
    let sep = w.m["landmark_min_separation"].as_f64().unwrap();
    let r = plant(&|m| m["landmark_min_separation"] = json!(sep + delta));
    let close = r
        .violations
        .iter()
        .filter(|v| v.kind.name() == "landmark_min_separation")
        .count();
    assert!(
        close >= 1 && close == r.violations.len(),
        "{:?}",
        r.violations
    );
    let best = r.violations.iter().map(|v| v.excess).fold(0.0, f64::max);
    assert!(
        (best - delta).abs() <= 1e-9 * (1.0 + sep),
        "{best} vs {delta}"
    );
}

/// With the operator's ids hidden, a detection its true landmark breaks
/// but another landmark satisfies is not a violation (the rule of
/// docs/cli.md); with the ids given, it is.
#[test]
fn a_detection_without_id_holds_when_some_landmark_satisfies_it() {
    let m = json!({
        "format": "nvector-mission/1", "model": "unicycle2d", "dt": 1.0, "steps": 1,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [0.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
        "detections": [{"step": 0, "range": [5, 5]}, {"step": 1, "range": [4, 4], "landmark": 0}],
        "truth": {"positions": [[0, 0], [0, 0]], "landmarks": [[3, 0], [3, 4]], "matching": [0, 0]}
    });
    let r = check(&m);
    // Detection 0: landmark 0 is 3 m away, landmark 1 is 5 m: it holds.
    // Detection 1 is tied by its id to landmark 0, 3 m away: 1 m short.
    only(&r, "detections[1].range", "range", 1.0, 1e-12);
    let mut ids = m.clone();
    ids["detections"][0]["landmark"] = json!(0);
    assert_eq!(check(&ids).violations.len(), 2);
    // A false detection (truth null) no landmark satisfies: its
    // violations are measured against the nearest landmark; with
    // max_outliers covering it, they do not count.
    let mut f = m.clone();
    f["detections"][0]["range"] = json!([7, 8]);
    f["truth"]["matching"] = json!([null, 0]);
    f["detections"][1]["range"] = json!([3, 3]);
    let r = check(&f);
    let v = only(&r, "detections[0].range", "range", 2.0, 1e-12);
    assert_eq!(v.landmark, Some(1));
    f["max_outliers"] = json!(1);
    let r = check(&f);
    assert_eq!((r.broken(), r.violations.len()), (0, 1));
    assert!(r.violations[0].outlier);
}

/// A truth exactly on every bound of a unicycle2d step and detection
/// (exact dyadic values): no violation; 1e-12 past a bound: a violation
/// (one ulp past is within the outward rounding of the solver's own
/// contractors, which keep it too).
#[test]
fn exactly_on_the_bound_is_not_a_violation() {
    let mission = |x1: f64, e: f64, lo: f64| {
        json!({
            "format": "nvector-mission/1", "model": "unicycle2d", "dt": 0.5, "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"lo": [2.0], "hi": [4.0]}, "heading": {"value": [0.0], "error": 0}},
            "motion_error": e,
            "detections": [{"step": 1, "range": [lo, 5.0], "bearing": [0, 0]}],
            "truth": {"positions": [[0, 0], [x1, 0.25]], "landmarks": [[x1 + 4.0, 0.25]], "matching": [0]}
        })
    };
    // Displacement x in [1, 2] (+- e), y in [0, 0] +- e: y = 0.25 = e.
    assert!(check(&mission(2.25, 0.25, 4.0)).violations.is_empty());
    assert!(check(&mission(0.75, 0.25, 4.0)).violations.is_empty());
    let r = check(&mission(2.25 + 1e-12, 0.25, 4.0));
    only(&r, "motion_error", "motion_step", 1e-12, 1e-14);
    let r = check(&mission(2.25, 0.25, 4.0 + 1e-12));
    only(&r, "detections[0].range", "range", 1e-12, 1e-14);
}

/// The simulators' missions are truthful: paper (unicycle2d), auv
/// (auv3d) and woods (odometry2d, with false detections covered by
/// max_outliers).
#[test]
fn simulated_missions_have_no_violation() {
    for seed in 1..=6u64 {
        for (scenario, steps) in [
            (Scenario::Paper, 400),
            (Scenario::Auv, 600),
            (Scenario::Woods, 300),
        ] {
            let mut o = SimulateOptions::new(scenario, seed);
            o.steps = Some(steps);
            o.operator = seed % 2 == 0;
            if scenario != Scenario::Auv && seed > 3 {
                o.false_detections = 3;
            }
            let m = simulate(&o);
            let r = check(&m);
            assert_eq!(
                r.broken(),
                0,
                "{scenario:?} seed {seed}: {:?}",
                r.violations
            );
        }
    }
}

/// auv3d: a depth and a 3-D range moved past the truth.
#[test]
fn planted_auv_violations_are_found() {
    let mut o = SimulateOptions::new(Scenario::Auv, 3);
    o.steps = Some(600);
    o.operator = true;
    let m = simulate(&o);
    let j = 0;
    let t = &m["truth"];
    let l = t["matching"][j].as_u64().unwrap() as usize;
    let z = t["landmarks"][l][2].as_f64().unwrap();
    let mut d = m.clone();
    d["detections"][j]["depth"] = json!([z + 0.5, z + 2.0]);
    only(&check(&d), "detections[0].depth", "depth", 0.5, 1e-9);
    let step = m["detections"][j]["step"].as_u64().unwrap() as usize;
    let p = &t["positions"][step];
    let dist: f64 = (0..3)
        .map(|a| {
            let d = t["landmarks"][l][a].as_f64().unwrap() - p[a].as_f64().unwrap();
            d * d
        })
        .sum::<f64>()
        .sqrt();
    let mut r = m.clone();
    r["detections"][j]["range"] = json!([dist + 2.0, dist + 3.0]);
    let v = check(&r);
    assert!(v
        .violations
        .iter()
        .any(|v| v.path == "detections[0].range" && (v.excess - 2.0).abs() < 1e-6));
    assert_eq!(v.violations.len(), 1, "{:?}", v.violations);
    // A step whose speed bounds miss the truth's displacement.
    let mut s = m.clone();
    s["inputs"]["vx"] = json!({"value": vec![50.0; 600], "error": 0.0});
    let r = check(&s);
    assert!(r.violations.iter().all(|v| v.kind.name() == "motion_step"));
    assert!(r.violations.len() >= 590, "{}", r.violations.len());
}

/// The check agrees with the solver: a mission whose truth the check
/// accepts ends with the truth inside; a range narrowed past the truth is
/// reported, and the solver, which contracts with it, loses the truth.
#[test]
fn check_agrees_with_the_solvers_truth_inside() {
    use nvector_core::slam::mission::Mission;
    use nvector_core::slam::result::score;
    use nvector_core::slam::solve::solve_model;
    use nvector_core::slam::types::SolveOptions;
    let mut o = SimulateOptions::new(Scenario::Paper, 5);
    o.steps = Some(300);
    o.operator = true;
    let m = simulate(&o);
    let inside = |v: &Value| {
        let mission = Mission::from_value(v).unwrap();
        let s = solve_model(
            &mission,
            &SolveOptions::default(),
            &mut |_| {},
            &Default::default(),
        );
        score(&mission, &s).unwrap().0
    };
    assert!(check(&m).violations.is_empty());
    assert!(inside(&m));
    let mut narrow = m.clone();
    let r0 = narrow["detections"][0]["range"].clone();
    let (lo, hi) = (r0[0].as_f64().unwrap(), r0[1].as_f64().unwrap());
    narrow["detections"][0]["range"] = json!([hi + 3.0, hi + 4.0]);
    let r = check(&narrow);
    assert_eq!(r.violations.len(), 1);
    assert!(r.violations[0].excess >= 3.0 - (hi - lo));
    assert!(!inside(&narrow));
    let mut wide = m.clone();
    wide["detections"][0]["range"] = json!([0.0, hi + 4.0]);
    assert!(check(&wide).violations.is_empty());
    assert!(inside(&wide));
}

#[test]
fn a_mission_without_truth_is_refused() {
    let mut m = odometry_world(1, 1.0).m;
    m.as_object_mut().unwrap().remove("truth");
    let e = check_value(&m).unwrap_err();
    assert_eq!(e.path, "truth");
    assert!(e.message.contains("no truth"), "{e}");
}
