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

pub use super::mission::MAX_LANDMARKS;
use super::mission::MAX_STEPS;
use super::woods::{simulate_woods_with, WoodsOptions, WOODS_STEPS};
use crate::error::InputError;
use crate::format::leaf::{Finite, Integer};
use crate::json::{box_to_json, interval_to_json};
pub use crate::rng::Rng;
use crate::{Interval, IntervalBox};
use serde::Deserialize;
use serde_json::{json, Value};

/// Which scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scenario {
    /// The paper's section 6 experiment.
    Paper,
    /// Redermor-scale AUV survey.
    Auv,
    /// An odometry2d robot among identical landmarks, with scans
    /// ([`super::woods`]).
    Woods,
}

impl Scenario {
    /// Parses `paper` / `auv` / `woods`.
    pub fn parse(s: &str) -> Option<Scenario> {
        match s {
            "paper" => Some(Scenario::Paper),
            "auv" => Some(Scenario::Auv),
            "woods" => Some(Scenario::Woods),
            _ => None,
        }
    }

    /// The name `parse` reads.
    pub fn name(self) -> &'static str {
        match self {
            Scenario::Paper => "paper",
            Scenario::Auv => "auv",
            Scenario::Woods => "woods",
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

/// Most false detections a simulation adds (every front end refuses more,
/// naming the option; each costs up to 1000 draws).
pub const MAX_FALSE_DETECTIONS: usize = 100_000;

/// Steps of the paper scenario by default.
pub const PAPER_STEPS: usize = 10_000;

/// Steps of the AUV scenario by default.
pub const AUV_STEPS: usize = 60_000;

/// Simulation options.
#[derive(Debug, Clone)]
pub struct SimulateOptions {
    /// Scenario.
    pub scenario: Scenario,
    /// Seed.
    pub seed: u64,
    /// Steps (None: the scenario's default: 10,000 for paper, 60,000 for
    /// auv, 3,000 for woods).
    pub steps: Option<usize>,
    /// Landmarks (None: 4 for paper, 17 for woods; auv always uses the 6
    /// seamarks).
    pub landmarks: Option<usize>,
    /// Write the true matching as operator `landmark` fields.
    pub operator: bool,
    /// Scale of the sensor noise bounds (1 = the scenario's defaults;
    /// paper and auv only).
    pub noise: f64,
    /// Landmark layout (paper only; default `Line`).
    pub layout: Layout,
    /// Range-only detections with a rough landmark region instead of a
    /// bearing (paper only: the paper's P''; default false).
    pub range_only: bool,
    /// Extra detections of no landmark (paper and woods; default 0).
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

/// Steps where the distance series has a local minimum below `threshold`.
fn closest_approaches(dist: &[f64], threshold: f64) -> Vec<usize> {
    (1..dist.len().saturating_sub(1))
        .filter(|&i| dist[i] < threshold && dist[i - 1] > dist[i] && dist[i] <= dist[i + 1])
        .collect()
}

/// Seed salt of the second random stream: the options beyond today's
/// default (`ring` / `random` layouts, range-only regions, false detections)
/// draw only from it, so the main stream, and with it the default mission,
/// is bit for bit what it was before they existed.
const EXTRA_STREAM: u64 = 0x5049_4E47_5245_4749;

/// Closest approaches below the threshold that make a landmark "detected
/// several times": the `random` layout keeps only landmarks the path passes
/// by at least this often.
const MIN_VISITS: usize = 3;

/// Distance of every position to a point.
fn distances(positions: &[[f64; 2]], l: [f64; 2]) -> Vec<f64> {
    positions
        .iter()
        .map(|p| libm::hypot(p[0] - l[0], p[1] - l[1]))
        .collect()
}

/// `ring`: n landmarks evenly on a circle of radius 11 m around the start
/// (the middle of the band the robot sweeps, so the path passes near each
/// once per turn), at the angles pi (2j + 1) / n with a small jitter (±0.05
/// rad, ±0.5 m). That rotation is symmetric about both axes for even n: the
/// landmarks pair up on x and on y, so no axis projection separates them and
/// the per-axis contractors group nothing (odd n: all but one pair up).
fn ring_layout(rng: &mut Rng, n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|j| {
            let a = std::f64::consts::PI * (2 * j + 1) as f64 / n as f64 + rng.sym(0.05);
            let r = 11.0 + rng.sym(0.5);
            [r * libm::cos(a), r * libm::sin(a)]
        })
        .collect()
}

/// `random`: n landmarks uniform in the square [-13, 13]^2 around the start
/// (the band the robot sweeps reaches about 21 m from the start), at least
/// `sep` apart (8 m, a little more than the detection threshold, so that a
/// detection is not within reach of two landmarks at once), and passed by
/// the path at least `MIN_VISITS` times. A candidate failing either test is
/// drawn again; after 200 failures the separation shrinks by 10 % (many
/// landmarks) and the best-visited separated candidate is taken (short
/// paths), so the loop always ends.
fn random_layout(rng: &mut Rng, n: usize, positions: &[[f64; 2]], threshold: f64) -> Vec<[f64; 2]> {
    let half = 13.0;
    let mut sep: f64 = 8.0;
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(n);
    while out.len() < n {
        let mut best: Option<([f64; 2], usize)> = None;
        let mut chosen = None;
        for _ in 0..200 {
            let c = [rng.sym(half), rng.sym(half)];
            if out
                .iter()
                .any(|l| libm::hypot(l[0] - c[0], l[1] - c[1]) < sep)
            {
                continue;
            }
            let visits = closest_approaches(&distances(positions, c), threshold).len();
            if visits >= MIN_VISITS {
                chosen = Some(c);
                break;
            }
            if best.is_none_or(|(_, v)| visits > v) {
                best = Some((c, visits));
            }
        }
        match chosen.or(best.map(|(c, _)| c)) {
            Some(c) => out.push(c),
            None => sep *= 0.9,
        }
    }
    out
}

/// The declared bearing of a point seen at angle `beta` (radians, relative
/// to the heading): the side (±pi/2), widened to hold `beta`.
fn bearing_interval(beta: f64, bearing_err: f64) -> Value {
    // Side-scan sonar: only the side is known, as an angle near ±pi/2.
    let side = if beta >= 0.0 {
        std::f64::consts::FRAC_PI_2
    } else {
        -std::f64::consts::FRAC_PI_2
    };
    // The true bearing: near the side at a closest approach; declared
    // with a bound that holds it (checked: widen when the approach is
    // not exactly abeam, e.g. at the start of the run).
    let off = wrap(beta - side).abs();
    let half = bearing_err.max(off + 0.02);
    interval_json(side - half, side + half)
}

/// Half-width of a range-only detection's `region` (m).
const REGION_HALF: f64 = 15.0;
/// Largest offset of a `region`'s centre from the landmark, per axis (m).
const REGION_OFFSET: f64 = 5.0;

/// The rough region of a range-only detection (the paper's P''): a box of
/// half-width 15 m whose centre is the landmark moved by up to 5 m on each
/// axis, so the landmark is inside by at least 10 m but not at the centre
/// (the box does not give the position away), and boxes of landmarks up to
/// 20 m apart overlap (it does not give the matching away either).
fn region(rng: &mut Rng, l: [f64; 2]) -> Value {
    let c = [l[0] + rng.sym(REGION_OFFSET), l[1] + rng.sym(REGION_OFFSET)];
    box_to_json(&IntervalBox::new(&[
        Interval::new(c[0] - REGION_HALF, c[0] + REGION_HALF),
        Interval::new(c[1] - REGION_HALF, c[1] + REGION_HALF),
    ]))
}

/// A detection of the paper scenario before it becomes JSON: the step, the
/// landmark (None: a false detection) and the point seen (the landmark, or
/// the phantom a false detection reports).
struct Seen {
    step: usize,
    landmark: Option<usize>,
    point: [f64; 2],
}

/// The paper scenario's noise bounds for a noise scale.
struct PaperNoise {
    speed: f64,
    heading: f64,
    range: f64,
}

/// The paper scenario's drive: the true positions (steps + 1) and
/// headings, and the measured speed and heading of each step.
struct Drive {
    positions: Vec<[f64; 2]>,
    headings: Vec<f64>,
    speed_meas: Vec<f64>,
    heading_meas: Vec<f64>,
}

/// `line`: landmarks spread around the start, 10 m apart along x and
/// alternating north and south (as in the paper's Figure 9, their
/// projections on the first axis are apart, so that the per-axis
/// contractors can work too). Drawn in every layout, so the main stream
/// (path and sensor noise) is the same for a seed whatever the layout.
fn line_layout(rng: &mut Rng, n_landmarks: usize) -> Vec<[f64; 2]> {
    (0..n_landmarks)
        .map(|j| {
            let x = 10.0 * (j as f64 - (n_landmarks as f64 - 1.0) / 2.0) + rng.sym(1.0);
            let y = if j % 2 == 0 { 10.0 } else { -10.0 } + rng.sym(2.0);
            [x, y]
        })
        .collect()
}

/// Feedback loop: the robot pursues a point running along an epicycle
/// around the start (small loops whose centre turns on a circle): the
/// robot loops around its start in a cycloid-like path, passing by every
/// landmark once per turn.
fn paper_drive(rng: &mut Rng, steps: usize, dt: f64, noise: &PaperNoise) -> Drive {
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
    let mut d = Drive {
        positions: vec![[x, y]],
        headings: Vec::with_capacity(steps),
        speed_meas: Vec::with_capacity(steps),
        heading_meas: Vec::with_capacity(steps),
    };
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
        d.headings.push(h);
        d.speed_meas.push(v + rng.sym(noise.speed));
        d.heading_meas.push(h + rng.sym(noise.heading));
        x += dt * v * libm::cos(h);
        y += dt * v * libm::sin(h);
        d.positions.push([x, y]);
    }
    d
}

/// What the robot sees: the closest approaches to each landmark, then
/// the false detections. By step, true detections by landmark, false ones
/// after them (in the order drawn): a stable sort keeps the true ones as
/// they were. (Ties broken by the drawn order: the order of a stable sort,
/// without the stable sort's code in the page's wasm.)
fn paper_seen(
    o: &SimulateOptions,
    extra: &mut Rng,
    landmarks: &[[f64; 2]],
    positions: &[[f64; 2]],
    (threshold, range_err): (f64, f64),
) -> Vec<Seen> {
    let mut seen: Vec<Seen> = Vec::new();
    for (j, &l) in landmarks.iter().enumerate() {
        for s in closest_approaches(&distances(positions, l), threshold) {
            seen.push(Seen {
                step: s,
                landmark: Some(j),
                point: l,
            });
        }
    }
    seen.extend(false_detections(
        extra,
        o.false_detections,
        positions,
        landmarks,
        threshold,
        range_err,
    ));
    let mut keyed: Vec<(usize, usize, usize)> = seen
        .iter()
        .enumerate()
        .map(|(i, d)| (d.step, d.landmark.unwrap_or(usize::MAX), i))
        .collect();
    crate::sort::sort_ord(&mut keyed);
    let mut slots: Vec<Option<Seen>> = seen.into_iter().map(Some).collect();
    keyed
        .iter()
        .filter_map(|&(_, _, i)| slots[i].take())
        .collect()
}

/// The detections as JSON, and the true matching (`null` for a false
/// detection). The main stream draws the noise of true detections only.
fn paper_detections(
    o: &SimulateOptions,
    (rng, extra): (&mut Rng, &mut Rng),
    seen: &[Seen],
    drive: &Drive,
    range_err: f64,
) -> (Vec<Value>, Vec<Value>) {
    let bearing_err: f64 = 0.1;
    let steps = drive.headings.len();
    let mut det_json = Vec::new();
    let mut matching = Vec::new();
    for d in seen {
        let (s, l) = (d.step, d.point);
        let p = drive.positions[s];
        let r = libm::hypot(l[0] - p[0], l[1] - p[1]);
        let r_meas = r + if d.landmark.is_some() {
            rng.sym(range_err)
        } else {
            extra.sym(range_err)
        };
        let mut dj = json!({
            "step": s,
            "range": interval_json((r_meas - range_err - MARGIN).max(0.0), r_meas + range_err + MARGIN),
        });
        if o.range_only {
            dj["region"] = region(extra, l);
        } else {
            let hd = drive.headings[s.min(steps - 1)];
            let beta = wrap(libm::atan2(l[1] - p[1], l[0] - p[0]) - hd);
            dj["bearing"] = bearing_interval(beta, bearing_err);
        }
        if o.operator {
            if let Some(j) = d.landmark {
                dj["landmark"] = json!(j);
            }
        }
        det_json.push(dj);
        matching.push(d.landmark.map_or(Value::Null, |j| json!(j)));
    }
    (det_json, matching)
}

/// The mission's name (without the seed) and `meta`, naming the options
/// beyond the default.
fn paper_name_meta(o: &SimulateOptions) -> (String, Value) {
    let mut name = String::from("paper");
    let mut meta = json!({"scenario": "paper", "seed": o.seed, "generator": "nvector simulate"});
    if o.layout != Layout::Line {
        name += &format!("-{}", o.layout.name());
        meta["layout"] = json!(o.layout.name());
    }
    if o.range_only {
        name += "-range-only";
        meta["range_only"] = json!(true);
    }
    if o.false_detections > 0 {
        name += &format!("-false-{}", o.false_detections);
        meta["false_detections"] = json!(o.false_detections);
    }
    (name, meta)
}

fn paper(o: &SimulateOptions) -> Value {
    let mut rng = Rng::new(o.seed);
    // Only the options beyond the default draw from this one.
    let mut extra = Rng::new(o.seed ^ EXTRA_STREAM);
    let steps = o.steps.unwrap_or(PAPER_STEPS).max(2);
    let n_landmarks = o.landmarks.unwrap_or(4).max(1);
    let dt = 0.1;
    let noise = o.noise.max(0.0);
    let err = PaperNoise {
        speed: 0.03 * noise,
        heading: 0.02 * noise,
        range: 0.1 * noise,
    };
    let threshold = 6.0;
    let line = line_layout(&mut rng, n_landmarks);
    let drive = paper_drive(&mut rng, steps, dt, &err);
    let landmarks = match o.layout {
        Layout::Line => line,
        Layout::Ring => ring_layout(&mut extra, n_landmarks),
        Layout::Random => random_layout(&mut extra, n_landmarks, &drive.positions, threshold),
    };
    let seen = paper_seen(
        o,
        &mut extra,
        &landmarks,
        &drive.positions,
        (threshold, err.range),
    );
    let (det_json, matching) =
        paper_detections(o, (&mut rng, &mut extra), &seen, &drive, err.range);
    let e0 = 0.01;
    let (name, meta) = paper_name_meta(o);
    let mut mission = json!({
        "format": "nvector-mission/1",
        "name": format!("{name}-seed-{}", o.seed),
        "model": "unicycle2d",
        "dt": dt,
        "steps": steps,
        "initial_position": box_to_json(&IntervalBox::new(&[Interval::new(-e0, e0), Interval::new(-e0, e0)])),
        "final_position": null,
        "inputs": {
            "speed": channel(&drive.speed_meas, err.speed + MARGIN),
            "heading": channel(&drive.heading_meas, err.heading + MARGIN),
        },
        "motion_error": MARGIN,
        "detections": det_json,
        "landmark_count": n_landmarks,
        "meta": meta,
        "truth": {
            "positions": drive.positions,
            "landmarks": landmarks,
            "matching": matching,
        }
    });
    if o.false_detections > 0 {
        mission["max_outliers"] = json!(o.false_detections);
    }
    mission
}

/// `k` false detections: each at a step drawn uniformly in 1..steps, of a
/// phantom point at a distance uniform in [1, threshold] (the span of the
/// true ranges) in a uniform direction, kept only when no landmark's true
/// distance from the robot comes within 1 m of that range (more than the
/// range bound): a range to no landmark. Up to 1000 draws per detection; a
/// detection that finds no such step is dropped (only possible on very
/// short paths where the robot never leaves a landmark's reach).
fn false_detections(
    rng: &mut Rng,
    k: usize,
    positions: &[[f64; 2]],
    landmarks: &[[f64; 2]],
    threshold: f64,
    range_err: f64,
) -> Vec<Seen> {
    let steps = positions.len() - 1;
    let mut out = Vec::with_capacity(k);
    for _ in 0..k {
        for _ in 0..1000 {
            let s = 1 + (rng.next_u64() % (steps as u64 - 1).max(1)) as usize;
            let r = 1.0 + rng.unit() * (threshold - 1.0);
            let a = rng.sym(std::f64::consts::PI);
            let p = positions[s];
            let q = [p[0] + r * libm::cos(a), p[1] + r * libm::sin(a)];
            let far = landmarks
                .iter()
                .all(|l| (libm::hypot(l[0] - p[0], l[1] - p[1]) - r).abs() > range_err + 1.0);
            if far {
                out.push(Seen {
                    step: s,
                    landmark: None,
                    point: q,
                });
                break;
            }
        }
    }
    out
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

/// The distance between two 3-D points, with basic operations and the
/// correctly rounded `libm::sqrt` only (`f64::powi` has no specified
/// precision: it may differ between platforms).
fn distance3(q: &[f64; 3], l: &[f64; 3]) -> f64 {
    let (dx, dy, dz) = (q[0] - l[0], q[1] - l[1], q[2] - l[2]);
    libm::sqrt(dx * dx + dy * dy + dz * dz)
}

/// The survey's waypoints: legs along y, 50 m apart, x from 60 to 660 m.
fn auv_waypoints() -> Vec<[f64; 2]> {
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
    waypoints
}

/// The auv scenario's drive along the waypoints: the true positions
/// (steps + 1) and the six measured channels (roll, pitch, yaw, vx, vy,
/// vz) of each step, with the angle, yaw and velocity error bounds.
fn auv_drive(
    rng: &mut Rng,
    (steps, dt): (usize, f64),
    waypoints: &[[f64; 2]],
    start: [f64; 3],
    [angle_err, yaw_err, vel_err]: [f64; 3],
) -> (Vec<[f64; 3]>, [Vec<f64>; 6]) {
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
    (positions, ch)
}

/// The sonar detections (closest approaches within the sonar range, by
/// step then seamark) as JSON, and the true matching.
fn auv_detections(
    o: &SimulateOptions,
    rng: &mut Rng,
    positions: &[[f64; 3]],
    (sonar_range, range_err): (f64, f64),
) -> (Vec<Value>, Vec<usize>) {
    let mut detections: Vec<(usize, usize)> = Vec::new();
    for (j, l) in SEAMARKS.iter().enumerate() {
        let dist: Vec<f64> = positions.iter().map(|q| distance3(q, l)).collect();
        for s in closest_approaches(&dist, sonar_range) {
            detections.push((s, j));
        }
    }
    crate::sort::sort_ord(&mut detections);
    let mut det_json = Vec::new();
    let mut matching = Vec::new();
    for &(s, j) in &detections {
        let q = positions[s];
        let l = SEAMARKS[j];
        let r = distance3(&q, &l);
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
    (det_json, matching)
}

fn auv(o: &SimulateOptions) -> Value {
    let mut rng = Rng::new(o.seed);
    let steps = o.steps.unwrap_or(AUV_STEPS).max(2);
    let dt = 0.1;
    let noise = o.noise.max(0.0);
    let (angle_err, yaw_err, vel_err) = (0.001 * noise, 0.002 * noise, 0.004 * noise);
    let range_err = 0.2 * noise;
    let sonar_range = 60.0;
    let auv_depth = 5.0;
    let waypoints = auv_waypoints();
    let start = [waypoints[0][0], waypoints[0][1] - 20.0, auv_depth];
    let errs3 = [angle_err, yaw_err, vel_err];
    let (positions, ch) = auv_drive(&mut rng, (steps, dt), &waypoints, start, errs3);
    let (det_json, matching) = auv_detections(o, &mut rng, &positions, (sonar_range, range_err));
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

// The simulation options as the front ends give them (`POST /simulate`,
// the page's SLAM demo, Python's `simulate`, `nvector simulate`): one type,
// read from JSON by the JSON front ends or filled in by the others, and one
// validation with one set of limits ([`SimulateRequest::options`]): core's
// ([`SimulateLimits::CORE`]), or a service's own, lower ones.

/// The largest values accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimulateLimits {
    /// Most steps.
    pub max_steps: u64,
    /// Most false detections.
    pub max_false_detections: u64,
}

impl SimulateLimits {
    /// Core's limits (the CLI, the page, Python).
    pub const CORE: SimulateLimits = SimulateLimits {
        max_steps: MAX_STEPS as u64,
        max_false_detections: MAX_FALSE_DETECTIONS as u64,
    };
}

/// A simulation request: every field optional but `scenario`; `null` is
/// absence. Unknown fields are refused, naming them.
#[derive(Debug, Default, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulateRequest {
    /// `"paper"`, `"auv"` or `"woods"` (any JSON, checked by the
    /// validation).
    pub scenario: Option<Value>,
    /// Seed (default 1).
    pub seed: Option<Integer>,
    /// Steps (default: the scenario's; at least 2, at most the limit).
    pub steps: Option<Integer>,
    /// Landmarks (paper; default 4, at most 64; 0 reads as 1).
    pub landmarks: Option<Integer>,
    /// Write the true matching as operator ids (default false).
    pub operator: Option<bool>,
    /// Scale of the noise bounds, in [0, 100] (default 1).
    pub noise: Option<Finite>,
    /// `"line"`, `"ring"` or `"random"` (paper; default line).
    pub layout: Option<Value>,
    /// Range-only detections (paper; default false).
    pub range_only: Option<bool>,
    /// Extra false detections (paper and woods; default 0).
    pub false_detections: Option<Integer>,
}

fn bad(path: &str, message: impl Into<String>) -> InputError {
    InputError::new(path, message)
}

impl SimulateRequest {
    /// The validated options under `limits`; errors name the field.
    pub fn options(&self, limits: SimulateLimits) -> Result<SimulateOptions, InputError> {
        let scenario = match &self.scenario {
            None | Some(Value::Null) => Some(Scenario::Paper),
            Some(v) => v.as_str().and_then(Scenario::parse),
        }
        .ok_or_else(|| {
            bad(
                "scenario",
                "scenario must be \"paper\", \"auv\" or \"woods\"",
            )
        })?;
        let seed = self.seed.map_or(Ok(1), |s| s.at_most(u64::MAX, "seed"))?;
        let mut o = SimulateOptions::new(scenario, seed);
        let default_steps = match scenario {
            Scenario::Paper => PAPER_STEPS,
            Scenario::Auv => AUV_STEPS,
            Scenario::Woods => WOODS_STEPS,
        } as u64;
        let steps = match self.steps {
            Some(s) => s.at_most(limits.max_steps, "steps")?,
            None => default_steps.min(limits.max_steps),
        };
        // A mission has at least one motion step between two positions
        // and one landmark: a smaller value was raised silently before.
        if steps < 2 {
            return Err(bad(
                "steps",
                format!("steps must be at least 2, not {steps}"),
            ));
        }
        o.steps = Some(steps as usize);
        o.landmarks = self
            .landmarks
            .map(|n| n.at_most(MAX_LANDMARKS as u64, "landmarks"))
            .transpose()?
            .map(|n| {
                if n == 0 {
                    Err(bad("landmarks", "landmarks must be at least 1, not 0"))
                } else {
                    Ok(n as usize)
                }
            })
            .transpose()?;
        o.operator = self.operator.unwrap_or(false);
        if let Some(Finite(n)) = self.noise {
            if !(0.0..=100.0).contains(&n) {
                return Err(bad("noise", "noise must be in [0, 100]"));
            }
            o.noise = n;
        }
        if let Some(x) = &self.layout {
            o.layout = x.as_str().and_then(Layout::parse).ok_or_else(|| {
                bad(
                    "layout",
                    format!("unknown layout {x} (expected line, ring or random)"),
                )
            })?;
        }
        o.range_only = self.range_only.unwrap_or(false);
        let max_false = limits.max_false_detections.min(MAX_FALSE_DETECTIONS as u64);
        o.false_detections =
            self.false_detections
                .map_or(Ok(0), |k| k.at_most(max_false, "false_detections"))? as usize;
        foreign_options(&o)?;
        Ok(o)
    }
}

/// Options of other scenarios pass only at their defaults: the first set
/// away from its default that `o`'s scenario does not take is an error
/// naming it.
fn foreign_options(o: &SimulateOptions) -> Result<(), InputError> {
    let scenario = o.scenario;
    // (field, set away from its default, this scenario takes it, who does)
    let (paper, not_woods) = (scenario == Scenario::Paper, scenario != Scenario::Woods);
    let not_auv = scenario != Scenario::Auv;
    let only = [
        (
            "layout",
            o.layout != Layout::Line,
            paper,
            "the paper scenario",
        ),
        ("range_only", o.range_only, paper, "the paper scenario"),
        (
            "false_detections",
            o.false_detections > 0,
            not_auv,
            "the paper and woods scenarios",
        ),
        (
            "noise",
            o.noise != 1.0,
            not_woods,
            "the paper and auv scenarios",
        ),
        (
            "landmarks",
            o.landmarks.is_some(),
            not_auv,
            "the paper and woods scenarios",
        ),
    ];
    match only.iter().find(|(_, set, takes, _)| *set && !takes) {
        Some((field, _, _, owner)) => Err(bad(field, format!("{field} applies to {owner} only"))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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

    /// FNV-1a over the JSON text: a fingerprint of a whole mission.
    fn fnv(s: &str) -> u64 {
        s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
        })
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
            assert_eq!((s.len(), fnv(&s)), (len, hash), "{o:?}");
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

#[cfg(test)]
mod request_tests {
    use super::*;
    use crate::format::{from_value, Object};
    use serde_json::json;

    fn options(v: Value) -> Result<SimulateOptions, InputError> {
        from_value::<Object<SimulateRequest>>(&v)?
            .0
            .options(SimulateLimits::CORE)
    }

    #[test]
    fn defaults_and_limits() {
        let o = options(json!({"scenario": "paper"})).unwrap();
        assert_eq!((o.seed, o.steps, o.landmarks), (1, Some(PAPER_STEPS), None));
        // Below 2 steps was read as 2, 0 landmarks as 1: refused now.
        let e = options(json!({"scenario": "auv", "steps": 0, "seed": null})).unwrap_err();
        assert_eq!(e.path, "steps");
        let o = options(json!({"scenario": "auv", "steps": 2, "seed": null})).unwrap();
        assert_eq!((o.steps, o.landmarks), (Some(2), None));
        let limits = SimulateLimits {
            max_steps: 20_000,
            max_false_detections: 7,
        };
        let o = SimulateRequest {
            scenario: Some(json!("auv")),
            ..SimulateRequest::default()
        }
        .options(limits)
        .unwrap();
        assert_eq!(o.steps, Some(20_000), "the default, at most the limit");
        let o = options(json!({"scenario": "woods", "false_detections": 100_000})).unwrap();
        assert_eq!(o.false_detections, MAX_FALSE_DETECTIONS);
    }

    #[test]
    fn errors_name_the_field() {
        for (v, want) in [
            (json!({"scenario": "moon"}), "scenario: scenario must be"),
            (json!({"layout": "spiral"}), "layout"),
            (
                json!({"scenario": "paper", "landmarks": 65}),
                "landmarks: 65 is above the limit 64",
            ),
            (
                json!({"scenario": "paper", "steps": 2_000_001}),
                "steps: 2000001 is above the limit 2000000",
            ),
            (
                json!({"scenario": "paper", "noise": -1}),
                "noise: noise must be in [0, 100]",
            ),
            (
                json!({"scenario": "paper", "noise": "x"}),
                "noise: expected a finite number, found a string",
            ),
            (
                json!({"scenario": "paper", "layout": "spiral"}),
                "layout: unknown layout \"spiral\"",
            ),
            (
                json!({"scenario": "paper", "false_detections": 100_001}),
                "false_detections: 100001 is above the limit 100000",
            ),
            (
                json!({"scenario": "woods", "false_detections": 100_001}),
                "false_detections: 100001 is above the limit 100000",
            ),
            (
                json!({"scenario": "auv", "false_detections": 2}),
                "false_detections: false_detections applies to the paper and woods scenarios only",
            ),
            (
                json!({"scenario": "auv", "range_only": true}),
                "range_only: range_only applies to the paper scenario only",
            ),
            (
                json!({"scenario": "paper", "operator": 1}),
                "operator: expected a boolean, found a number",
            ),
            (
                json!({"scenario": "paper", "stpes": 1}),
                "stpes: unknown field `stpes`",
            ),
            (json!([]), "expected an object, found an array"),
        ] {
            let e = options(v).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e} does not start with {want}");
        }
    }
}
