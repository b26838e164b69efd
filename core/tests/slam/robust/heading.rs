//! The headings in the robust rounds (`core/src/slam/robust/heading.rs`):
//! planted odometry2d missions with up to q false detections, solved with
//! `max_outliers` = q. Random chains with a true trajectory and true
//! headings (headings far beyond ±π, up to 1e6 rad; bearings given with
//! any multiple of 2π added; sensor offsets; detections without a bearing;
//! zero-width and unbounded turn-rate samples, zero and huge per-step
//! heading errors, drift windows), true detections (operator labels or
//! not) plus false ones of every kind: a bearing pointing nowhere (a true
//! range, a wrong bearing), a detection near a true landmark, a range and
//! bearing to nothing, a consistent phantom landmark seen from several
//! steps (as many as the budget allows), a true detection with a wrong
//! label. Every true heading and position must stay in its box and the
//! mission is never infeasible. The rule must also do something: in a
//! share of the cases (about 10 %; at least 5 % asked) some heading is
//! narrower than with the detections all removed (before the rule the
//! robust rounds left every heading at dead reckoning: 0 cases).
//!
//! Breaking the rule (the passes keeping the budget-th best evidence
//! instead of the (budget+1)-th) fails here: at case 374, a true heading
//! cut by one false bearing (q = 1). So does consensus over subsets
//! intersecting its feasible sets' headings instead of taking their hull
//! (case 186, q = 3, a true heading near -6e5 rad cut).
//!
//! Deterministic (a fixed seed); `NVECTOR_PROPTEST_CASES` scales the cases
//! (1000 = as is).

#![allow(clippy::disallowed_methods)]

use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::types::{Association, SolveOptions, SolveStatus};
use nvector_core::Interval;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

fn cases(default: u64) -> u64 {
    std::env::var("NVECTOR_PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .map_or(default, |c| (c * default / 1000).max(20))
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

/// The kinds of false detections planted.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// A true range with a bearing pointing elsewhere.
    WrongBearing,
    /// Range and bearing to a point within 0.5 m of a true landmark.
    NearLandmark,
    /// Range and bearing to a random point.
    Nothing,
    /// Range and bearing to one phantom landmark, from several steps.
    Phantom,
    /// A true detection labelled as another landmark (operator only).
    WrongLabel,
}

const KINDS: [Kind; 5] = [
    Kind::WrongBearing,
    Kind::NearLandmark,
    Kind::Nothing,
    Kind::Phantom,
    Kind::WrongLabel,
];

/// A planted mission: the JSON, the true positions and headings.
struct Planted {
    mission: Value,
    pos: Vec<[f64; 2]>,
    head: Vec<f64>,
    what: String,
}

/// The true chain: positions, headings and the inputs (turn-rate bounds
/// as lo/hi, some samples zero-width, some unbounded).
struct Drive {
    pos: Vec<[f64; 2]>,
    head: Vec<f64>,
    speed: Vec<f64>,
    turn_lo: Vec<Value>,
    turn_hi: Vec<Value>,
    heading_error: Vec<f64>,
    /// The true turn rates.
    turn: Vec<f64>,
}

/// Every declared bound exceeds the noise drawn by at least this much.
const MARGIN: f64 = 1e-7;

fn drive(rng: &mut Lcg, n: usize, dt: f64, th0: f64, se: f64, me: f64) -> Drive {
    let mut th = th0;
    let mut p = [rng.sym(2.0), rng.sym(2.0)];
    let mut d = Drive {
        pos: vec![p],
        head: vec![th],
        speed: vec![],
        turn_lo: vec![],
        turn_hi: vec![],
        heading_error: vec![],
        turn: vec![],
    };
    for _ in 0..n {
        let v = rng.sym(2.0);
        let w = rng.sym(1.0);
        let he = match rng.below(10) {
            0 => 0.0,
            1 => 1e300,
            _ => rng.next() * 0.02 + 1e-6,
        };
        let f = if he > 1.0 {
            rng.sym(0.05)
        } else {
            rng.sym((he - MARGIN).max(0.0))
        };
        let e = [rng.sym(me - MARGIN), rng.sym(me - MARGIN)];
        p = [
            p[0] + dt * v * th.cos() + e[0],
            p[1] + dt * v * th.sin() + e[1],
        ];
        th += dt * w + f;
        d.speed.push(v + rng.sym(se - MARGIN));
        // The turn rate's bounds: zero width (exact), a band, or unbounded.
        let (lo, hi) = match rng.below(12) {
            0 => (json!(w), json!(w)),
            1 => (json!("-inf"), json!(w + 0.01)),
            2 => (json!(w - 0.01), json!("inf")),
            _ => {
                let we = rng.next() * 0.05 + 1e-6;
                let m = w + rng.sym(we - MARGIN);
                (json!(m - we), json!(m + we))
            }
        };
        d.turn_lo.push(lo);
        d.turn_hi.push(hi);
        d.heading_error.push(he);
        d.turn.push(w);
        d.pos.push(p);
        d.head.push(th);
    }
    d
}

/// A detection of the point `l` from step `t` of the truth: range and
/// (wrapped by a random multiple of 2π, or absent) bearing, with the
/// sensor offset. `bearing_shift` rotates the bearing.
fn detect(
    rng: &mut Lcg,
    d: &Drive,
    offset: [f64; 2],
    t: usize,
    l: [f64; 2],
    with_bearing: bool,
    bearing_shift: f64,
) -> Value {
    let (re, be) = (rng.next() * 0.2 + 1e-6, rng.next() * 0.1 + 1e-6);
    let h = d.head[t];
    let s = [
        d.pos[t][0] + offset[0] * h.cos() - offset[1] * h.sin(),
        d.pos[t][1] + offset[0] * h.sin() + offset[1] * h.cos(),
    ];
    let dx = [l[0] - s[0], l[1] - s[1]];
    let r = (dx[0].hypot(dx[1]) + rng.sym(re - MARGIN)).max(0.0);
    let mut det = json!({"step": t, "range": [(r - re).max(0.0), r + re]});
    if with_bearing {
        let k = rng.below(5) as f64 - 2.0;
        let b = dx[1].atan2(dx[0]) - h + rng.sym(be - MARGIN) + 2.0 * PI * k + bearing_shift;
        det["bearing"] = json!([b - be, b + be]);
    }
    det
}

/// Half the time, a `region` (a box known to hold the landmark: the
/// point seen, a random half-width, sometimes zero) on `det`.
fn with_region(rng: &mut Lcg, mut det: Value, l: [f64; 2]) -> Value {
    if rng.below(2) == 0 {
        let w = if rng.below(6) == 0 {
            0.0
        } else {
            0.05 + rng.next() * 0.5
        };
        det["region"] = json!([[l[0] - w, l[0] + w], [l[1] - w, l[1] + w]]);
    }
    det
}

/// Plants up to `q` false detections of random kinds into `dets`.
#[allow(clippy::too_many_arguments)]
fn plant_false(
    rng: &mut Lcg,
    d: &Drive,
    offset: [f64; 2],
    lms: &[[f64; 2]],
    q: usize,
    operator: bool,
    dets: &mut Vec<Value>,
    kinds: &mut Vec<Kind>,
) {
    let n = d.head.len() - 1;
    let planted = rng.below(q + 1);
    let mut left = planted;
    while left > 0 {
        let kind = KINDS[rng.below(KINDS.len())];
        let t = rng.below(n + 1);
        let l = rng.below(lms.len());
        let mut det = match kind {
            Kind::WrongBearing => {
                let shift = 0.3 + rng.next() * (2.0 * PI - 0.6);
                let det = detect(rng, d, offset, t, lms[l], true, shift);
                with_region(rng, det, lms[l])
            }
            Kind::NearLandmark => {
                let a = rng.sym(PI);
                let r = 0.1 + rng.next() * 0.4;
                let x = [lms[l][0] + r * a.cos(), lms[l][1] + r * a.sin()];
                let bearing = rng.below(4) > 0;

                let det = detect(rng, d, offset, t, x, bearing, 0.0);
                with_region(rng, det, x)
            }
            Kind::Nothing => {
                let x = [rng.sym(15.0), rng.sym(15.0)];
                let det = detect(rng, d, offset, t, x, true, 0.0);
                with_region(rng, det, x)
            }
            Kind::Phantom => {
                // A consistent phantom: 1..=left detections of one point.
                let x = [rng.sym(12.0), rng.sym(12.0)];
                let count = 1 + rng.below(left);
                let label = 1000 + dets.len();
                for _ in 0..count {
                    let t = rng.below(n + 1);
                    let bearing = rng.below(5) > 0;

                    let det = detect(rng, d, offset, t, x, bearing, 0.0);
                    let mut det = with_region(rng, det, x);
                    if operator {
                        det["landmark"] = json!(label);
                    }
                    dets.push(det);
                    kinds.push(kind);
                }
                left -= count;
                continue;
            }
            Kind::WrongLabel => {
                if !operator || lms.len() < 2 {
                    continue;
                }
                let bearing = rng.below(4) > 0;

                let det = detect(rng, d, offset, t, lms[l], bearing, 0.0);
                let mut det = with_region(rng, det, lms[l]);
                det["landmark"] = json!((l + 1) % lms.len());
                dets.push(det);
                kinds.push(kind);
                left -= 1;
                continue;
            }
        };
        if operator {
            det["landmark"] = json!(if rng.below(2) == 0 {
                l
            } else {
                2000 + dets.len()
            });
        }
        dets.push(det);
        kinds.push(kind);
        left -= 1;
    }
}

/// The largest |th(i+k) - th(i) - Σ dt·ω(j)| of the truth over the
/// windows of k steps, plus 1e-7 (the truth's own rounding): a window
/// bound the truth meets, as tight as the truth allows.
fn drift_bound(d: &Drive, dt: f64, k: usize) -> f64 {
    let n = d.turn.len();
    let mut worst = 0.0f64;
    for i in 0..=(n - k) {
        let s: f64 = (i..i + k).map(|j| dt * d.turn[j]).sum();
        worst = worst.max((d.head[i + k] - d.head[i] - s).abs());
    }
    worst * (1.0 + 1e-9) + 1e-7
}

/// A random planted mission with `max_outliers` = q.
fn plant(rng: &mut Lcg) -> Planted {
    let n = 4 + rng.below(24);
    let dt = 0.05 + rng.next() * 0.5;
    let count = 1 + rng.below(4);
    let lms: Vec<[f64; 2]> = (0..count).map(|_| [rng.sym(8.0), rng.sym(8.0)]).collect();
    let offset = match rng.below(3) {
        0 => [0.0, 0.0],
        _ => [rng.sym(1.0), rng.sym(1.0)],
    };
    let se = if rng.below(8) == 0 {
        0.0
    } else {
        rng.next() * 0.1 + 1e-6
    };
    let me = rng.next() * 0.02 + 1e-6;
    let th0 = match rng.below(8) {
        0 => rng.sym(1e6),
        _ => rng.sym(40.0),
    };
    let d = drive(rng, n, dt, th0, se, me);
    let operator = rng.below(2) == 0;
    let q = 1 + rng.below(3);
    let mut dets = vec![];
    let mut kinds = vec![];
    for _ in 0..(1 + rng.below(2 * n)) {
        let t = rng.below(n + 1);
        let l = rng.below(count);
        let bearing = rng.below(4) > 0;

        let det = detect(rng, &d, offset, t, lms[l], bearing, 0.0);
        let mut det = with_region(rng, det, lms[l]);
        if operator {
            det["landmark"] = json!(l);
        }
        dets.push(det);
    }
    plant_false(rng, &d, offset, &lms, q, operator, &mut dets, &mut kinds);
    let th = d.head[n];
    let mut m = json!({
        "format": "nvector-mission/1",
        "model": "odometry2d",
        "dt": dt,
        "steps": n,
        "initial_position": [[d.pos[0][0] - 0.01, d.pos[0][0] + 0.01], [d.pos[0][1] - 0.01, d.pos[0][1] + 0.01]],
        "initial_heading": [th0 - 0.02, th0 + 0.02],
        "inputs": {
            "speed": {"value": d.speed, "error": se},
            "turn_rate": {"lo": d.turn_lo, "hi": d.turn_hi},
        },
        "heading_error": d.heading_error,
        "motion_error": me,
        "sensor_offset": offset,
        "detections": dets,
        "max_outliers": q,
    });
    if rng.below(3) == 0 {
        m["final_heading"] = json!([th - 0.1, th + 0.1]);
    }
    if rng.below(3) == 0 {
        let k = 1 + rng.below(n);
        m["heading_drift"] = json!([{"steps": k, "error": drift_bound(&d, dt, k)}]);
    }
    if !operator && rng.below(2) == 0 {
        m["landmark_count"] = json!(count);
    }
    Planted {
        mission: m,
        pos: d.pos,
        head: d.head,
        what: format!("n {n} q {q} operator {operator} false {kinds:?}"),
    }
}

/// The solution's headings, the truth checked inside.
fn solve_and_check(p: &Planted, mission: &Value, case: u64, association: &str) -> Vec<Interval> {
    let m = Mission::from_value(mission).unwrap();
    let options = SolveOptions {
        association: Association::parse(association).unwrap(),
        ..SolveOptions::default()
    };
    let s = propagate(&m, &options, &mut |_| {}, &AtomicBool::new(false));
    let what = format!("case {case} ({}, {association})", p.what);
    if let SolveStatus::Infeasible(reason) = &s.status {
        panic!("{what}: infeasible: {reason}");
    }
    for (t, h) in p.head.iter().enumerate() {
        let b = s.model.heading[t];
        assert!(b.contains(*h), "{what}: heading {t}: {h} not in {b:?}");
    }
    for (t, x) in p.pos.iter().enumerate() {
        for (a, &v) in x.iter().enumerate() {
            let b = s.model.pos[2 * t + a];
            assert!(b.contains(v), "{what}: position {t}[{a}]: {v} not in {b:?}");
        }
    }
    s.model.heading
}

/// Every true heading and position stays inside, never infeasible; and in
/// some cases the detections narrow a heading below the dead reckoning's
/// (the same mission without detections).
#[test]
fn planted_headings_and_positions_stay_inside() {
    let mut rng = Lcg(0x0018_4EAD);
    let total = cases(2000);
    let (mut compared, mut narrower) = (0u32, 0u32);
    for case in 0..total {
        let p = plant(&mut rng);
        let association = if case % 32 == 0 { "best" } else { "none" };
        let h = solve_and_check(&p, &p.mission, case, association);
        if case % 4 == 1 {
            let mut blind = p.mission.clone();
            blind["detections"] = json!([]);
            blind.as_object_mut().unwrap().remove("max_outliers");
            let dead = solve_and_check(&p, &blind, case, "none");
            compared += 1;
            let narrowed = h
                .iter()
                .zip(&dead)
                .any(|(a, b)| a.width() < 0.9 * b.width());
            narrower += u32::from(narrowed);
        }
    }
    assert!(
        narrower * 20 >= compared,
        "a heading narrowed in only {narrower} of {compared} cases"
    );
}

/// A mission of the planted family above (case 888 of the generator: 9
/// steps, 8 detections, q = 1, turn inputs up to 1e300 wide) on which the
/// consensus over subsets' solves of inconsistent detection sets moved a
/// heading's near bound by about a turn per round towards its far bound
/// (1e300) and ran the 10,000 rounds of `max_rounds`: 2,710,477
/// contractions for 8 detections. The heading's moves with a far bound
/// fixed no longer count as moving (`odometry::angle::heading_moved`), so
/// each solve reaches its fixpoint in a few rounds; the answer stays
/// consistent and every heading keeps the initial heading's bound.
#[test]
fn a_heading_with_a_far_bound_reaches_a_fixpoint() {
    let mission: Value = serde_json::from_str(include_str!("far_heading.json")).unwrap();
    let m = Mission::from_value(&mission).unwrap();
    for association in ["none", "best"] {
        let options = SolveOptions {
            association: Association::parse(association).unwrap(),
            ..SolveOptions::default()
        };
        let s = propagate(&m, &options, &mut |_| {}, &AtomicBool::new(false));
        assert_eq!(s.status, SolveStatus::Consistent, "{association}");
        assert!(
            s.contractions < 100_000,
            "{association}: {} contractions",
            s.contractions
        );
        let h0 = s.model.heading[0];
        assert!(h0.lo() <= -31.157458864541987 && h0.hi() >= -31.117458864541987);
    }
}
