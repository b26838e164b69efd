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

use crate::json::{box_to_json, interval_to_json};
use crate::{Interval, IntervalBox};
use serde_json::{json, Value};

/// Which scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scenario {
    /// The paper's section 6 experiment.
    Paper,
    /// Redermor-scale AUV survey.
    Auv,
}

impl Scenario {
    /// Parses `paper` / `auv`.
    pub fn parse(s: &str) -> Option<Scenario> {
        match s {
            "paper" => Some(Scenario::Paper),
            "auv" => Some(Scenario::Auv),
            _ => None,
        }
    }
}

/// Where the paper scenario puts its landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// 10 m apart along x, alternating north and south (the paper's
    /// Figure 9; today's default).
    Line,
    /// Evenly on a circle around the start, with jitter: the x and y
    /// projections interleave.
    Ring,
    /// Uniformly in a square around the start, with a minimum separation.
    Random,
}

impl Layout {
    /// Parses `line` / `ring` / `random`.
    pub fn parse(s: &str) -> Option<Layout> {
        match s {
            "line" => Some(Layout::Line),
            "ring" => Some(Layout::Ring),
            "random" => Some(Layout::Random),
            _ => None,
        }
    }

    /// The name `parse` reads.
    pub fn name(self) -> &'static str {
        match self {
            Layout::Line => "line",
            Layout::Ring => "ring",
            Layout::Random => "random",
        }
    }
}

/// Simulation options.
#[derive(Debug, Clone)]
pub struct SimulateOptions {
    /// Scenario.
    pub scenario: Scenario,
    /// Seed.
    pub seed: u64,
    /// Steps (None: the scenario's default: 10,000 for paper, 60,000 for auv).
    pub steps: Option<usize>,
    /// Landmarks (None: 4 for paper; auv always uses the 6 seamarks).
    pub landmarks: Option<usize>,
    /// Write the true matching as operator `landmark` fields.
    pub operator: bool,
    /// Scale of the sensor noise bounds (1 = the scenario's defaults).
    pub noise: f64,
    /// Landmark layout (paper only; default `Line`).
    pub layout: Layout,
    /// Range-only detections with a rough landmark region instead of a
    /// bearing (paper only: the paper's P''; default false).
    pub range_only: bool,
    /// Extra detections of no landmark (paper only; default 0).
    pub false_detections: usize,
}

impl SimulateOptions {
    /// Defaults for a scenario and seed.
    pub fn new(scenario: Scenario, seed: u64) -> SimulateOptions {
        SimulateOptions {
            scenario,
            seed,
            steps: None,
            landmarks: None,
            operator: false,
            noise: 1.0,
            layout: Layout::Line,
            range_only: false,
            false_detections: 0,
        }
    }
}

/// splitmix64: small, fast, and the same everywhere.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x6E76_6563_746F_7221)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-a, a).
    pub fn sym(&mut self, a: f64) -> f64 {
        a * (2.0 * self.unit() - 1.0)
    }
}

/// Margin added to every declared error bound, above the largest noise
/// drawn: covers the f64 rounding of the simulation (relative 1e-16 on
/// values below 1e4), so the truth is inside even though the simulation is
/// computed in floating point.
const MARGIN: f64 = 1e-9;

fn wrap(a: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    a - two_pi * libm::floor((a + std::f64::consts::PI) / two_pi)
}

fn channel(values: &[f64], error: f64) -> Value {
    json!({"value": values, "error": error})
}

fn interval_json(lo: f64, hi: f64) -> Value {
    interval_to_json(Interval::new(lo, hi))
}

/// A simulated mission with truth, as `nvector-mission/1` JSON.
pub fn simulate(options: &SimulateOptions) -> Value {
    match options.scenario {
        Scenario::Paper => paper(options),
        Scenario::Auv => auv(options),
    }
}

/// Steps where the distance series has a local minimum below `threshold`.
fn closest_approaches(dist: &[f64], threshold: f64) -> Vec<usize> {
    (1..dist.len().saturating_sub(1))
        .filter(|&i| dist[i] < threshold && dist[i - 1] > dist[i] && dist[i] <= dist[i + 1])
        .collect()
}

fn paper(o: &SimulateOptions) -> Value {
    let mut rng = Rng::new(o.seed);
    let steps = o.steps.unwrap_or(10_000).max(2);
    let n_landmarks = o.landmarks.unwrap_or(4).max(1);
    let dt = 0.1;
    let noise = o.noise.max(0.0);
    let speed_err = 0.03 * noise;
    let heading_err = 0.02 * noise;
    let range_err = 0.1 * noise;
    let bearing_err: f64 = 0.1;
    let threshold = 6.0;
    // Landmarks spread around the start, 10 m apart along x and alternating
    // north and south (as in the paper's Figure 9, their projections on the
    // first axis are apart, so that the per-axis contractors can work too).
    let landmarks: Vec<[f64; 2]> = (0..n_landmarks)
        .map(|j| {
            let x = 10.0 * (j as f64 - (n_landmarks as f64 - 1.0) / 2.0) + rng.sym(1.0);
            let y = if j % 2 == 0 { 10.0 } else { -10.0 } + rng.sym(2.0);
            [x, y]
        })
        .collect();
    // Feedback loop: the robot pursues a point running along an epicycle
    // around the start (small loops whose centre turns on a circle): the
    // robot loops around its start in a cycloid-like path, passing by every
    // landmark once per turn.
    let (big_r, big_w) = (
        11.0 + rng.sym(1.0),
        2.0 * std::f64::consts::PI / (110.0 + rng.sym(10.0)),
    );
    let (small_r, small_w) = (
        4.0 + rng.sym(0.5),
        2.0 * std::f64::consts::PI / (24.0 + rng.sym(2.0)),
    );
    let phase = rng.sym(3.0);
    let path = |t: f64| {
        [
            big_r * libm::cos(big_w * t + phase) + small_r * libm::cos(small_w * t),
            big_r * libm::sin(big_w * t + phase) + small_r * libm::sin(small_w * t),
        ]
    };
    let p0 = path(0.0);
    let (mut x, mut y) = (0.0f64, 0.0f64);
    let mut h = libm::atan2(p0[1], p0[0]);
    let mut positions = vec![[x, y]];
    let (mut speed_meas, mut heading_meas) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    let mut headings = Vec::with_capacity(steps);
    for i in 0..steps {
        // The pursued point starts at the start and joins the epicycle.
        let t = i as f64 * dt;
        let blend = (t / 10.0).min(1.0);
        let q = path(t + 1.0);
        let target = [blend * q[0], blend * q[1]];
        let want = libm::atan2(target[1] - y, target[0] - x);
        let turn = wrap(want - h).clamp(-1.2 * dt, 1.2 * dt);
        h = wrap(h + turn);
        let v = libm::hypot(target[0] - x, target[1] - y).clamp(0.3, 2.0);
        headings.push(h);
        speed_meas.push(v + rng.sym(speed_err));
        heading_meas.push(h + rng.sym(heading_err));
        x += dt * v * libm::cos(h);
        y += dt * v * libm::sin(h);
        positions.push([x, y]);
    }
    let mut detections: Vec<(usize, usize)> = Vec::new();
    for (j, l) in landmarks.iter().enumerate() {
        let dist: Vec<f64> = positions
            .iter()
            .map(|p| libm::hypot(p[0] - l[0], p[1] - l[1]))
            .collect();
        for s in closest_approaches(&dist, threshold) {
            detections.push((s, j));
        }
    }
    detections.sort_unstable();
    let mut det_json = Vec::new();
    let mut matching = Vec::new();
    for &(s, j) in &detections {
        let p = positions[s];
        let l = landmarks[j];
        let r = libm::hypot(l[0] - p[0], l[1] - p[1]);
        let r_meas = r + rng.sym(range_err);
        let hd = headings[s.min(steps - 1)];
        let beta = wrap(libm::atan2(l[1] - p[1], l[0] - p[0]) - hd);
        // Side-scan sonar: only the side is known, as an angle near ±pi/2.
        let side = if beta >= 0.0 {
            std::f64::consts::FRAC_PI_2
        } else {
            -std::f64::consts::FRAC_PI_2
        };
        let mut d = json!({
            "step": s,
            "range": interval_json((r_meas - range_err - MARGIN).max(0.0), r_meas + range_err + MARGIN),
        });
        // The true bearing: near the side at a closest approach; declared
        // with a bound that holds it (checked: widen when the approach is
        // not exactly abeam, e.g. at the start of the run).
        let off = wrap(beta - side).abs();
        let half = bearing_err.max(off + 0.02);
        d["bearing"] = interval_json(side - half, side + half);
        if o.operator {
            d["landmark"] = json!(j);
        }
        det_json.push(d);
        matching.push(j);
    }
    let e0 = 0.01;
    json!({
        "format": "nvector-mission/1",
        "name": format!("paper-seed-{}", o.seed),
        "model": "unicycle2d",
        "dt": dt,
        "steps": steps,
        "initial_position": box_to_json(&IntervalBox::new(&[Interval::new(-e0, e0), Interval::new(-e0, e0)])),
        "final_position": null,
        "inputs": {
            "speed": channel(&speed_meas, speed_err + MARGIN),
            "heading": channel(&heading_meas, heading_err + MARGIN),
        },
        "motion_error": MARGIN,
        "detections": det_json,
        "landmark_count": n_landmarks,
        "meta": {"scenario": "paper", "seed": o.seed, "generator": "nvector simulate"},
        "truth": {
            "positions": positions,
            "landmarks": landmarks,
            "matching": matching,
        }
    })
}

/// The six Redermor seamarks (x, y, depth), from ../shared/data/README.md.
const SEAMARKS: [[f64; 3]; 6] = [
    [594.053, 374.729, 19.0],
    [599.609, 484.553, 19.0],
    [601.461, 557.357, 19.0],
    [94.013, -2.868, 19.0],
    [119.941, 84.752, 20.0],
    [127.349, 156.328, 20.0],
];

fn auv(o: &SimulateOptions) -> Value {
    let mut rng = Rng::new(o.seed);
    let steps = o.steps.unwrap_or(60_000).max(2);
    let dt = 0.1;
    let noise = o.noise.max(0.0);
    let (angle_err, yaw_err, vel_err) = (0.001 * noise, 0.002 * noise, 0.004 * noise);
    let range_err = 0.2 * noise;
    let sonar_range = 60.0;
    let auv_depth = 5.0;
    // Lawn-mower survey: legs along y, 50 m apart, over the seamark area.
    let mut waypoints = Vec::new();
    let mut xw = 60.0;
    let mut up = true;
    while xw <= 660.0 {
        let (y0, y1) = if up { (-60.0, 600.0) } else { (600.0, -60.0) };
        waypoints.push([xw, y0]);
        waypoints.push([xw, y1]);
        xw += 50.0;
        up = !up;
    }
    let start = [waypoints[0][0], waypoints[0][1] - 20.0, auv_depth];
    let mut p = start;
    let mut yaw = std::f64::consts::FRAC_PI_2;
    let mut wp = 0usize;
    let mut positions = vec![p];
    let mut ch: [Vec<f64>; 6] = Default::default();
    for _ in 0..steps {
        let target = waypoints[wp.min(waypoints.len() - 1)];
        if libm::hypot(target[0] - p[0], target[1] - p[1]) < 10.0 && wp + 1 < waypoints.len() {
            wp += 1;
        }
        let want = libm::atan2(target[1] - p[1], target[0] - p[0]);
        yaw = wrap(yaw + wrap(want - yaw).clamp(-0.3 * dt, 0.3 * dt));
        let roll = 0.02 * libm::sin(0.3 * positions.len() as f64 * dt);
        let pitch = 0.01 * libm::cos(0.2 * positions.len() as f64 * dt);
        let v = [1.5, 0.05 * libm::sin(0.01 * positions.len() as f64), 0.0];
        let (cf, sf) = (libm::cos(roll), libm::sin(roll));
        let (ct, st) = (libm::cos(pitch), libm::sin(pitch));
        let (cp, sp) = (libm::cos(yaw), libm::sin(yaw));
        let r = [
            [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
            [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
            [-st, ct * sf, ct * cf],
        ];
        for a in 0..3 {
            p[a] += dt * (r[a][0] * v[0] + r[a][1] * v[1] + r[a][2] * v[2]);
        }
        positions.push(p);
        ch[0].push(roll + rng.sym(angle_err));
        ch[1].push(pitch + rng.sym(angle_err));
        ch[2].push(yaw + rng.sym(yaw_err));
        for a in 0..3 {
            ch[3 + a].push(v[a] + rng.sym(vel_err));
        }
    }
    let mut detections: Vec<(usize, usize)> = Vec::new();
    for (j, l) in SEAMARKS.iter().enumerate() {
        let dist: Vec<f64> = positions
            .iter()
            .map(|q| {
                libm::sqrt((q[0] - l[0]).powi(2) + (q[1] - l[1]).powi(2) + (q[2] - l[2]).powi(2))
            })
            .collect();
        for s in closest_approaches(&dist, sonar_range) {
            detections.push((s, j));
        }
    }
    detections.sort_unstable();
    let mut det_json = Vec::new();
    let mut matching = Vec::new();
    for &(s, j) in &detections {
        let q = positions[s];
        let l = SEAMARKS[j];
        let r = libm::sqrt((q[0] - l[0]).powi(2) + (q[1] - l[1]).powi(2) + (q[2] - l[2]).powi(2));
        let r_meas = r + rng.sym(range_err);
        let mut d = json!({
            "step": s,
            "range": interval_json((r_meas - range_err - MARGIN).max(0.0), r_meas + range_err + MARGIN),
            "depth": interval_json(l[2] - 1.0, l[2] + 1.0),
        });
        if o.operator {
            d["landmark"] = json!(j);
        }
        det_json.push(d);
        matching.push(j);
    }
    let gps = 2.0;
    let end = positions[steps];
    let names = ["roll", "pitch", "yaw", "vx", "vy", "vz"];
    let errs = [angle_err, angle_err, yaw_err, vel_err, vel_err, vel_err];
    let mut inputs = serde_json::Map::new();
    for a in 0..6 {
        inputs.insert(names[a].into(), channel(&ch[a], errs[a] + MARGIN));
    }
    let around = |c: [f64; 3], r: f64, dz: f64| {
        box_to_json(&IntervalBox::new(&[
            Interval::new(c[0] - r, c[0] + r),
            Interval::new(c[1] - r, c[1] + r),
            Interval::new(c[2] - dz, c[2] + dz),
        ]))
    };
    json!({
        "format": "nvector-mission/1",
        "name": format!("auv-seed-{}", o.seed),
        "model": "auv3d",
        "dt": dt,
        "steps": steps,
        "initial_position": around(start, gps, 0.5),
        "final_position": around(end, gps, 0.5),
        "inputs": Value::Object(inputs),
        "motion_error": MARGIN,
        "detections": det_json,
        "landmark_count": SEAMARKS.len(),
        "meta": {"scenario": "auv", "seed": o.seed, "generator": "nvector simulate"},
        "truth": {
            "positions": positions,
            "landmarks": SEAMARKS,
            "matching": matching,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_for_a_seed() {
        let a = simulate(&SimulateOptions::new(Scenario::Paper, 7));
        let b = simulate(&SimulateOptions::new(Scenario::Paper, 7));
        let c = simulate(&SimulateOptions::new(Scenario::Paper, 8));
        assert_eq!(a.to_string(), b.to_string());
        assert_ne!(a.to_string(), c.to_string());
        assert!(!a["detections"].as_array().unwrap().is_empty());
    }
}
