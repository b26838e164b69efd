//! The `woods` scenario: an odometry2d robot among identical landmarks, in
//! the manner of UTIAS "Lost in the Woods" (docs/utias-woods.md).
//!
//! n landmarks (default 17) in a rectangle of 2.6·sqrt(n) m by 1.3·sqrt(n)
//! m around the start, at least 1.5 m apart (the separation shrinks by 10 %
//! after 200 rejected draws, so the loop always ends); the robot drives
//! between random waypoints in the rectangle, at 0.35 m/s with short spells
//! of backing up at -0.15 m/s, turning at most 0.5 rad/s towards the
//! waypoint. The heading is a real number (it is never wrapped: the truth's
//! headings run beyond ±pi as the robot circles).
//!
//! - Odometry: `speed` = true speed + noise (|.| < 0.02 m/s, declared 0.02),
//!   `turn_rate` exact; the heading step carries a noise f with
//!   |f| < 0.01 rad (declared `heading_error` 0.01) and the position step a
//!   noise e with |e| < 0.01 m per axis (declared `motion_error` 0.01).
//! - A laser 0.2 m ahead of the centre (`sensor_offset` [0.2, 0]) scans
//!   every 2 steps: each landmark within 5 m and ±2.1 rad of the heading is
//!   detected once (`scan` = the scan's index), with range noise below
//!   0.05 m and bearing noise below 0.05 rad (declared 0.05 each); the
//!   bearing is given wrapped into (-pi, pi].
//! - `landmark_min_separation`: the smallest true distance between two
//!   landmarks less 0.01 m.
//! - Initial pose known to ±0.01 m and ±0.01 rad.
//!
//! Deterministic for a seed (splitmix64, libm only). Every declared bound
//! strictly exceeds the noise drawn by a margin (1e-9) that covers the f64
//! rounding of the simulation, so the truth satisfies every constraint.

use crate::rng::Rng;
use crate::slam::mission::{MAX_LANDMARKS, MAX_STEPS};
use serde_json::{json, Value};

/// Options of the woods scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct WoodsOptions {
    /// The seed.
    pub seed: u64,
    /// N (default 3000; at most `MAX_STEPS`).
    pub steps: Option<usize>,
    /// n (default 17; at most `MAX_LANDMARKS`).
    pub landmarks: Option<usize>,
    /// Write the true matching as operator `landmark` fields.
    pub operator: bool,
}

/// Steps of the woods scenario by default.
pub const WOODS_STEPS: usize = 3000;

/// Landmarks of the woods scenario by default (as many as Lost in the
/// Woods' tubes).
pub const WOODS_LANDMARKS: usize = 17;

/// A scan every this many steps.
pub const SCAN_EVERY: usize = 2;
/// Most detections a woods mission of `steps` steps and `landmarks`
/// landmarks can hold (each scan sees each landmark at most once): what a
/// front end with a limit on detections checks before it simulates.
pub fn max_detections(steps: usize, landmarks: usize) -> usize {
    (steps / SCAN_EVERY + 1).saturating_mul(landmarks)
}

const MARGIN: f64 = 1e-9;
const DT: f64 = 0.1;
const SPEED_NOISE: f64 = 0.02;
const HEADING_NOISE: f64 = 0.01;
const MOTION_NOISE: f64 = 0.01;
const RANGE_NOISE: f64 = 0.05;
const BEARING_NOISE: f64 = 0.05;
const MAX_RANGE: f64 = 5.0;
const FIELD_OF_VIEW: f64 = 2.1;
const OFFSET: f64 = 0.2;
const MAX_TURN: f64 = 0.5;
const INITIAL_ERROR: f64 = 0.01;

fn wrap(a: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    let w = a - two_pi * libm::round(a / two_pi);
    if w <= -std::f64::consts::PI {
        w + two_pi
    } else {
        w
    }
}

/// n landmarks in [-hx, hx] × [-hy, hy], at least `sep` apart (shrunk by
/// 10 % after 200 rejections in a row).
fn layout(rng: &mut Rng, n: usize, hx: f64, hy: f64) -> Vec<[f64; 2]> {
    let mut sep: f64 = 1.5;
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(n);
    while out.len() < n {
        let mut placed = false;
        for _ in 0..200 {
            let c = [rng.sym(hx), rng.sym(hy)];
            // Keep the start (the origin) clear of landmarks.
            if libm::hypot(c[0], c[1]) < 0.5 {
                continue;
            }
            if out
                .iter()
                .all(|l| libm::hypot(l[0] - c[0], l[1] - c[1]) >= sep)
            {
                out.push(c);
                placed = true;
                break;
            }
        }
        if !placed {
            sep *= 0.9;
        }
    }
    out
}

/// The smallest distance between two landmarks (infinite for fewer than
/// two).
fn min_separation(landmarks: &[[f64; 2]]) -> f64 {
    let mut separation = f64::INFINITY;
    for (a, la) in landmarks.iter().enumerate() {
        for lb in &landmarks[a + 1..] {
            separation = separation.min(libm::hypot(la[0] - lb[0], la[1] - lb[1]));
        }
    }
    separation
}

/// The true drive: N+1 poses and the N odometry samples.
struct Drive {
    /// True positions p(0..=N).
    p: Vec<[f64; 2]>,
    /// True headings th(0..=N) (never wrapped).
    th: Vec<f64>,
    /// Measured speeds (true speed + noise), one per step.
    speed: Vec<f64>,
    /// Turn rates (exact), one per step.
    turn: Vec<f64>,
}

/// The robot's drive of `n` steps between random waypoints of
/// [-hx, hx] × [-hy, hy] (see the module comment).
fn drive(rng: &mut Rng, n: usize, hx: f64, hy: f64) -> Drive {
    let mut p = vec![[0.0f64; 2]; n + 1];
    let mut th = vec![0.0f64; n + 1];
    th[0] = rng.sym(std::f64::consts::PI);
    let mut speed = Vec::with_capacity(n);
    let mut turn = Vec::with_capacity(n);
    let mut waypoint = [rng.sym(hx), rng.sym(hy)];
    let mut backing = 0usize;
    let mut v = 0.0f64;
    for i in 0..n {
        if libm::hypot(waypoint[0] - p[i][0], waypoint[1] - p[i][1]) < 0.5 {
            waypoint = [rng.sym(hx), rng.sym(hy)];
        }
        if backing == 0 && rng.unit() < 0.003 {
            backing = 20;
        }
        let target = if backing > 0 {
            backing -= 1;
            -0.15
        } else {
            0.35
        };
        v += (target - v) * 0.2;
        let want = libm::atan2(waypoint[1] - p[i][1], waypoint[0] - p[i][0]);
        let w = (1.5 * wrap(want - th[i])).clamp(-MAX_TURN, MAX_TURN);
        let f = rng.sym(HEADING_NOISE);
        let e = [rng.sym(MOTION_NOISE), rng.sym(MOTION_NOISE)];
        th[i + 1] = th[i] + DT * w + f;
        p[i + 1] = [
            p[i][0] + DT * v * libm::cos(th[i]) + e[0],
            p[i][1] + DT * v * libm::sin(th[i]) + e[1],
        ];
        speed.push(v + rng.sym(SPEED_NOISE));
        turn.push(w);
    }
    Drive { p, th, speed, turn }
}

/// The laser's detections along a drive, and their true landmarks.
struct Scans {
    /// The mission's `detections`.
    detections: Vec<Value>,
    /// The true landmark of each detection (`truth.matching`).
    matching: Vec<usize>,
}

/// A scan every `SCAN_EVERY` steps: each landmark in range and field of
/// view detected once (see the module comment); `operator` writes the true
/// landmark as the detection's `landmark`.
fn scans(rng: &mut Rng, d: &Drive, landmarks: &[[f64; 2]], operator: bool) -> Scans {
    let mut out = Scans {
        detections: Vec::new(),
        matching: Vec::new(),
    };
    let n = d.p.len() - 1;
    let mut scan = 0usize;
    for i in (0..=n).step_by(SCAN_EVERY) {
        let (p, th) = (d.p[i], d.th[i]);
        let s = [p[0] + OFFSET * libm::cos(th), p[1] + OFFSET * libm::sin(th)];
        let mut any = false;
        for (j, l) in landmarks.iter().enumerate() {
            let (dx, dy) = (l[0] - s[0], l[1] - s[1]);
            let r = libm::hypot(dx, dy);
            let beta = wrap(libm::atan2(dy, dx) - th);
            if r > MAX_RANGE || beta.abs() > FIELD_OF_VIEW {
                continue;
            }
            let rm = r + rng.sym(RANGE_NOISE);
            let bm = wrap(beta + rng.sym(BEARING_NOISE));
            let (er, eb) = (RANGE_NOISE + MARGIN, BEARING_NOISE + MARGIN);
            let mut det = json!({
                "step": i,
                "range": [(rm - er).max(0.0), rm + er],
                "bearing": [bm - eb, bm + eb],
                "scan": scan,
            });
            if operator {
                det["landmark"] = json!(j);
            }
            out.detections.push(det);
            out.matching.push(j);
            any = true;
        }
        if any {
            scan += 1;
        }
    }
    out
}

/// The woods mission with truth, as `nvector-mission/1` JSON (model
/// `odometry2d`).
pub fn simulate_woods(o: &WoodsOptions) -> Value {
    let mut rng = Rng::new(o.seed ^ 0x574F_4F44_5331);
    let n = o.steps.unwrap_or(WOODS_STEPS).clamp(1, MAX_STEPS);
    let count = o
        .landmarks
        .unwrap_or(WOODS_LANDMARKS)
        .clamp(1, MAX_LANDMARKS);
    let root = libm::sqrt(count as f64);
    let (hx, hy) = (1.3 * root, 0.65 * root);
    let landmarks = layout(&mut rng, count, hx, hy);
    let separation = min_separation(&landmarks);
    let d = drive(&mut rng, n, hx, hy);
    let s = scans(&mut rng, &d, &landmarks, o.operator);
    let mut m = json!({
        "format": "nvector-mission/1",
        "name": format!("woods-{}", o.seed),
        "model": "odometry2d",
        "dt": DT,
        "steps": n,
        "initial_position": [[-INITIAL_ERROR, INITIAL_ERROR], [-INITIAL_ERROR, INITIAL_ERROR]],
        "final_position": null,
        "initial_heading": [d.th[0] - INITIAL_ERROR, d.th[0] + INITIAL_ERROR],
        "inputs": {
            "speed": {"value": d.speed, "error": SPEED_NOISE + MARGIN},
            "turn_rate": {"value": d.turn, "error": 0.0},
        },
        "heading_error": HEADING_NOISE + MARGIN,
        "motion_error": MOTION_NOISE + MARGIN,
        "sensor_offset": [OFFSET, 0.0],
        "detections": s.detections,
        "landmark_count": count,
        "meta": {
            "scenario": "woods",
            "seed": o.seed,
            "scan_every": SCAN_EVERY,
            "max_range": MAX_RANGE,
            "field_of_view": FIELD_OF_VIEW,
        },
        "truth": {
            "positions": d.p,
            "headings": d.th,
            "landmarks": landmarks,
            "matching": s.matching,
        },
    });
    if separation.is_finite() {
        m["landmark_min_separation"] = json!(separation - 0.01);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_and_sized() {
        let o = WoodsOptions {
            seed: 3,
            steps: Some(400),
            landmarks: None,
            operator: true,
        };
        let (a, b) = (simulate_woods(&o), simulate_woods(&o));
        assert_eq!(a, b);
        assert_eq!(a["steps"], 400);
        assert_eq!(a["truth"]["landmarks"].as_array().unwrap().len(), 17);
        assert!(!a["detections"].as_array().unwrap().is_empty());
    }
}
