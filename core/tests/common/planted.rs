//! Missions planted with their truth ON the boundary of the intervals.
//!
//! The truth (positions, landmarks) is made of f64 numbers, so it is known
//! exactly; every measured quantity derived from it is computed with the
//! project's own outward-rounded interval operations and not widened by a
//! margin: a displacement bound is the magnitude of the interval difference
//! of two point boxes, a range the interval distance between two point boxes
//! ([`distance_between`]), so the true value lies within an ulp or two of a
//! bound. Then, half of the time, a random slack is added on one side or
//! the other (so bounds at the truth, near it and far from it all occur).
//! Coincidences are generated on purpose: the robot standing still (a zero
//! displacement, a zero motion error), the robot on a landmark (range
//! `[0, 0]`, exactly), integer coordinates (exact sums and distances),
//! boxes whose bound is the truth, and false detections in exactly the
//! number `max_outliers` allows.

// Axes index several parallel arrays.
#![allow(clippy::needless_range_loop)]

use super::Rng;
use nvector_core::contractors::motion_chain::{auv_displacement, unicycle_displacement};
use nvector_core::shapes::shape::distance_between;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::{Solution, SolveStatus};
use nvector_core::Interval;
use serde_json::{json, Value};

/// What to plant.
#[derive(Debug, Clone)]
pub struct Options {
    /// 2 (unicycle2d) or 3 (auv3d).
    pub dim: usize,
    /// N: positions p(0..=N).
    pub steps: usize,
    /// Landmarks placed (not all need be seen).
    pub landmarks: usize,
    /// Probability that a step has a detection.
    pub detect: f64,
    /// Probability that a detection has a bearing.
    pub bearings: f64,
    /// Probability that a true detection carries its (true) operator label.
    pub labels: f64,
    /// False detections (no landmark), and `max_outliers` set to exactly
    /// this number.
    pub false_detections: usize,
}

impl Options {
    /// A small random mission shape in `dim` dimensions.
    pub fn random(rng: &mut Rng, dim: usize) -> Options {
        Options {
            dim,
            steps: 3 + rng.below(45),
            landmarks: 1 + rng.below(4),
            detect: rng.range(0.1, 0.6),
            bearings: if rng.chance(0.5) { 0.0 } else { 0.7 },
            labels: if rng.chance(0.6) { 0.0 } else { 0.4 },
            false_detections: 0,
        }
    }
}

/// A planted mission and its truth.
#[derive(Debug, Clone)]
pub struct PlantedMission {
    /// The mission JSON (with its `truth`).
    pub value: Value,
    /// The parsed mission.
    pub mission: Mission,
    pub dim: usize,
    /// p(0..=N).
    pub positions: Vec<Vec<f64>>,
    pub landmarks: Vec<Vec<f64>>,
    /// Per detection (input order): its landmark, `None` when false.
    pub matching: Vec<Option<usize>>,
}

/// `x` as a JSON interval.
pub fn iv(x: Interval) -> Value {
    json!([x.lo(), x.hi()])
}

/// A coordinate: an integer half of the time (exact sums and distances,
/// coincidences), else any float in [-w, w].
fn coord(rng: &mut Rng, w: f64) -> f64 {
    if rng.chance(0.5) {
        (rng.range(-w, w)).round()
    } else {
        rng.range(-w, w)
    }
}

/// `x` widened by a random slack on each side, zero half of the time (the
/// lower bound kept >= `floor`).
fn widen(rng: &mut Rng, x: Interval, w: f64, floor: f64) -> Interval {
    let (a, b) = (rng.slack(0.5, w), rng.slack(0.5, w));
    // x.lo() - a rounds to nearest but stays <= x.lo(): still an enclosure.
    Interval::new((x.lo() - a).max(floor).min(x.lo()), x.hi() + b)
}

/// A box holding `p`, each side at `p` with probability 1/2.
fn box_around(rng: &mut Rng, p: &[f64], w: f64) -> Vec<Interval> {
    p.iter()
        .map(|&c| widen(rng, Interval::point(c), w, f64::NEG_INFINITY))
        .collect()
}

fn box_json(b: &[Interval]) -> Value {
    Value::Array(b.iter().map(|&x| iv(x)).collect())
}

/// An enclosure of the true bearing of `l` seen from `p` with heading `h`
/// (a point): libm's atan2 widened by two ulps on each side (it is within
/// one), minus the heading with outward rounding.
pub fn bearing_enclosure(p: &[f64], l: &[f64], h: f64) -> Interval {
    let a = libm::atan2(l[1] - p[1], l[0] - p[0]);
    // The arguments l - p are rounded too: exact when both are integers or
    // equal; otherwise the rounding of the difference moves the angle by
    // at most about 2 ulp of the angle's scale: widen by 8 ulps.
    let mut lo = a;
    let mut hi = a;
    for _ in 0..8 {
        lo = lo.next_down();
        hi = hi.next_up();
    }
    Interval::new(lo, hi) - Interval::point(h)
}

/// A planted mission (module doc).
pub fn mission(rng: &mut Rng, o: &Options) -> PlantedMission {
    let dim = o.dim;
    let n_steps = o.steps.max(1);
    // Landmarks at least 2 m apart (distinct landmarks are distinct points).
    let mut landmarks: Vec<Vec<f64>> = Vec::new();
    while landmarks.len() < o.landmarks.max(1) {
        let mut l = vec![coord(rng, 12.0), coord(rng, 12.0)];
        if dim == 3 {
            l.push(-1.0 - coord(rng, 6.0).abs());
        }
        let far = landmarks.iter().all(|m| {
            let d2: f64 = (0..dim).map(|a| (m[a] - l[a]) * (m[a] - l[a])).sum();
            d2 >= 4.0
        });
        if far {
            landmarks.push(l);
        }
    }
    // The walk. Each step has inputs (speed and heading; for auv3d roll,
    // pitch, yaw and the body velocity), exact points; `dv` is the interval
    // displacement the model computes from them (the project's own
    // functions) and the motion error covers the rest: the magnitude of
    // the interval difference `p(i+1) - p(i) - dv` (so the true
    // displacement lies in the model's box, within an ulp or two of a
    // bound), plus a slack half of the time. Steps: a move of the inputs
    // (p(i+1) = p(i) + the middle of dv: a box off-centre from 0, its
    // bound at the truth to the ulp), the robot standing still, a move in
    // quarter metres with no velocity (exact sums), or a step onto a
    // landmark within reach.
    let dt = if rng.chance(0.5) { 1.0 } else { 0.5 };
    let mut positions = vec![(0..dim).map(|_| coord(rng, 4.0)).collect::<Vec<f64>>()];
    let mut channels: Vec<Vec<f64>> =
        vec![Vec::with_capacity(n_steps); if dim == 2 { 2 } else { 6 }];
    let mut motion_error = Vec::with_capacity(n_steps);
    let mut h = rng.range(-3.0, 3.0);
    for _ in 0..n_steps {
        let last = positions.last().expect("p(0)").clone();
        h += rng.range(-0.5, 0.5);
        let kind = rng.unit();
        let moving = kind < 0.55;
        let v = if moving { rng.range(-0.3, 1.0) } else { 0.0 };
        let inputs: Vec<f64> = if dim == 2 {
            vec![v, h]
        } else {
            let small = |rng: &mut Rng| if moving { rng.range(-0.15, 0.15) } else { 0.0 };
            vec![small(rng), small(rng), h, v, small(rng), small(rng)]
        };
        let pt = Interval::point;
        let dv: Vec<Interval> = if dim == 2 {
            unicycle_displacement(dt, pt(inputs[0]), pt(inputs[1]), 0.0).to_vec()
        } else {
            let c = &inputs;
            auv_displacement(
                dt,
                pt(c[0]),
                pt(c[1]),
                pt(c[2]),
                [pt(c[3]), pt(c[4]), pt(c[5])],
                0.0,
            )
            .to_vec()
        };
        let next: Vec<f64> = if moving {
            (0..dim).map(|a| last[a] + dv[a].mid()).collect()
        } else if kind < 0.7 {
            last.clone()
        } else if kind < 0.9 {
            (0..dim)
                .map(|a| {
                    let w = if a == 2 { 0.2 } else { 0.6 };
                    last[a] + (rng.range(-w, w) * 4.0).round() / 4.0
                })
                .collect()
        } else {
            let l = &landmarks[rng.below(landmarks.len())];
            let d2: f64 = (0..dim).map(|a| (l[a] - last[a]) * (l[a] - last[a])).sum();
            if d2 < 16.0 {
                l.clone()
            } else {
                last.clone()
            }
        };
        let mut e = 0.0f64;
        for a in 0..dim {
            let residual = pt(next[a]) - pt(last[a]) - dv[a];
            e = e.max(residual.mag());
        }
        motion_error.push(e + rng.slack(0.5, 0.1));
        for (c, x) in channels.iter_mut().zip(&inputs) {
            c.push(*x);
        }
        positions.push(next);
    }
    let headings: Vec<f64> = channels[if dim == 2 { 1 } else { 2 }].clone();
    let channel = |x: &[f64]| json!({"value": x, "error": 0.0});
    let (model, inputs) = if dim == 2 {
        (
            "unicycle2d",
            json!({"speed": channel(&channels[0]), "heading": channel(&channels[1])}),
        )
    } else {
        let names = ["roll", "pitch", "yaw", "vx", "vy", "vz"];
        let mut o = serde_json::Map::new();
        for (name, c) in names.iter().zip(&channels) {
            o.insert((*name).into(), channel(c));
        }
        ("auv3d", Value::Object(o))
    };
    let range_err = rng.range(0.01, 1.0);
    let bearing_err = rng.range(0.001, 0.3);
    let mut dets: Vec<(Value, Option<usize>)> = Vec::new();
    for t in 0..=n_steps {
        if !rng.chance(o.detect) {
            continue;
        }
        let p = &positions[t];
        let l = if rng.chance(0.5) {
            (0..landmarks.len())
                .min_by(|&a, &b| {
                    let sq = |l: &[f64]| -> f64 {
                        (0..dim).map(|x| (l[x] - p[x]) * (l[x] - p[x])).sum()
                    };
                    let (da, db) = (sq(&landmarks[a]), sq(&landmarks[b]));
                    da.total_cmp(&db)
                })
                .expect("a landmark")
        } else {
            rng.below(landmarks.len())
        };
        let lm = &landmarks[l];
        let pb: Vec<Interval> = p.iter().map(|&x| Interval::point(x)).collect();
        let lb: Vec<Interval> = lm.iter().map(|&x| Interval::point(x)).collect();
        let range = if p == lm && rng.chance(0.5) {
            // The robot on the landmark: an exact zero range.
            Interval::point(0.0)
        } else {
            widen(rng, distance_between(&pb, &lb), range_err, 0.0)
        };
        let mut d = json!({"step": t, "range": iv(range)});
        if rng.chance(o.bearings) {
            let h = headings[t.min(n_steps - 1)];
            let b = widen(
                rng,
                bearing_enclosure(p, lm, h),
                bearing_err,
                f64::NEG_INFINITY,
            );
            d["bearing"] = iv(b);
        }
        if rng.chance(0.2) {
            d["region"] = box_json(&box_around(rng, lm, 5.0));
        }
        if dim == 3 && rng.chance(0.3) {
            d["depth"] = iv(widen(rng, Interval::point(lm[2]), 1.0, f64::NEG_INFINITY));
        }
        if rng.chance(o.labels) {
            d["landmark"] = json!(l);
        }
        dets.push((d, Some(l)));
    }
    for _ in 0..o.false_detections {
        let t = rng.below(n_steps + 1);
        let a = rng.range(0.0, 30.0);
        dets.push((
            json!({"step": t, "range": [a, a + rng.slack(0.3, 2.0)]}),
            None,
        ));
    }
    if rng.chance(0.3) {
        // Any order (the output keeps the input order).
        for i in (1..dets.len()).rev() {
            let j = rng.below(i + 1);
            dets.swap(i, j);
        }
    } else {
        dets.sort_by_key(|(d, _)| d["step"].as_u64());
    }
    let matching: Vec<Option<usize>> = dets.iter().map(|(_, l)| *l).collect();
    let mut v = json!({
        "format": "nvector-mission/1",
        "name": "planted on the boundary",
        "model": model,
        "dt": dt,
        "steps": n_steps,
        "initial_position": box_json(&box_around(rng, &positions[0], 0.3)),
        "inputs": inputs,
        "motion_error": motion_error,
        "detections": dets.iter().map(|(d, _)| d.clone()).collect::<Vec<_>>(),
        "truth": {
            "positions": positions,
            "landmarks": landmarks,
            "matching": matching,
        },
    });
    if rng.chance(0.3) {
        v["final_position"] = box_json(&box_around(rng, &positions[n_steps], 0.3));
    }
    if rng.chance(0.85) {
        v["landmark_count"] = json!(landmarks.len() + rng.below(2));
    }
    if rng.chance(0.3) {
        let hull: Vec<Interval> = (0..dim)
            .map(|a| {
                let lo = landmarks.iter().map(|l| l[a]).fold(f64::INFINITY, f64::min);
                let hi = landmarks
                    .iter()
                    .map(|l| l[a])
                    .fold(f64::NEG_INFINITY, f64::max);
                widen(rng, Interval::new(lo, hi), 3.0, f64::NEG_INFINITY)
            })
            .collect();
        v["landmark_region"] = box_json(&hull);
    }
    if o.false_detections > 0 {
        v["max_outliers"] = json!(o.false_detections);
    }
    let mission = Mission::from_value(&v).unwrap_or_else(|e| panic!("planted mission: {e}"));
    PlantedMission {
        value: v,
        mission,
        dim,
        positions,
        landmarks,
        matching,
    }
}

impl PlantedMission {
    /// The mission again after `value` was edited.
    pub fn reparse(&mut self) {
        self.value["truth"]["matching"] = json!(self.matching);
        self.mission = Mission::from_value(&self.value).expect("valid mission");
    }

    /// Moves the range of detection `j` by `shift` metres (a measurement
    /// off its bounds: the detection becomes false in the truth).
    pub fn corrupt_range(&mut self, j: usize, shift: f64) {
        let r = &self.value["detections"][j]["range"];
        let (lo, hi) = (
            r[0].as_f64().expect("lo") + shift,
            r[1].as_f64().expect("hi") + shift,
        );
        self.value["detections"][j]["range"] = json!([lo.max(0.0), hi.max(0.0)]);
        self.matching[j] = None;
        self.reparse();
    }

    /// Every soundness check of a solution against the planted truth:
    /// not infeasible, every position and every true detection's box holds
    /// the truth, every matching group is one landmark's (no false
    /// detection in it), every group's landmark box holds the landmark.
    pub fn check(&self, s: &Solution) -> Result<(), String> {
        if let SolveStatus::Infeasible(r) = &s.status {
            return Err(format!("infeasible: {r}"));
        }
        let m = &s.model;
        for (i, p) in self.positions.iter().enumerate() {
            if !m.position(i).contains(p) {
                return Err(format!("p({i}) = {p:?} lost: {:?}", m.position(i).axes()));
            }
        }
        for (j, l) in self.matching.iter().enumerate() {
            if let Some(l) = l {
                if !m.det[j].contains(&self.landmarks[*l]) {
                    return Err(format!(
                        "detection {j} lost landmark {l} at {:?}: {:?}",
                        self.landmarks[*l],
                        m.det[j].axes()
                    ));
                }
            }
        }
        for (g, b) in s.matching.iter().zip(s.landmarks()) {
            let l = self.matching[g[0]];
            if l.is_none() || g.iter().any(|&j| self.matching[j] != l) {
                let truth: Vec<Option<usize>> = g.iter().map(|&j| self.matching[j]).collect();
                return Err(format!("group {g:?} is not one landmark's: {truth:?}"));
            }
            let l = l.expect("checked");
            if !b.contains(&self.landmarks[l]) {
                return Err(format!("the landmark box of group {g:?} lost landmark {l}"));
            }
        }
        Ok(())
    }
}
