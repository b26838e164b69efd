//! The `paper` scenario: the experiment of the paper's section 6 (the
//! module doc of [`super`]), with its landmark layouts (`line`, `ring`,
//! `random`), range-only regions and false detections.

use super::scenario::{
    boxed, closest_approaches, int, interval, mission_head, wrap, Layout, SimulateOptions, MARGIN,
    PAPER_STEPS,
};
use crate::format::leaf::{BoxIn, Integer, IntervalIn, List, PerStep, PointsIn};
use crate::format::mission_doc::{ChannelDoc, DetectionDoc, InputsDoc, MissionDoc, TruthDoc};
use crate::rng::Rng;
use serde_json::{json, Value};

/// Seed salt of the second random stream: the options beyond today's
/// default (`ring` / `random` layouts, range-only regions, false detections)
/// draw only from it, so the main stream, and with it the default mission,
/// is bit for bit what it was before they existed.
const EXTRA_STREAM: u64 = 0x5049_4E47_5245_4749;

/// Closest approaches below the threshold that make a landmark "detected
/// several times": the `random` layout keeps only landmarks the path passes
/// by at least this often.
pub(super) const MIN_VISITS: usize = 3;

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
fn bearing_interval(beta: f64, bearing_err: f64) -> IntervalIn {
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
    interval(side - half, side + half)
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
fn region(rng: &mut Rng, l: [f64; 2]) -> BoxIn {
    let c = [l[0] + rng.sym(REGION_OFFSET), l[1] + rng.sym(REGION_OFFSET)];
    boxed(&[
        [c[0] - REGION_HALF, c[0] + REGION_HALF],
        [c[1] - REGION_HALF, c[1] + REGION_HALF],
    ])
}

/// A detection of the paper scenario before it becomes a document: the step, the
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

/// The detections, and the true matching (`None` for a false
/// detection). The main stream draws the noise of true detections only.
fn paper_detections(
    o: &SimulateOptions,
    (rng, extra): (&mut Rng, &mut Rng),
    seen: &[Seen],
    drive: &Drive,
    range_err: f64,
) -> (Vec<DetectionDoc>, Vec<Option<Integer>>) {
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
        let mut dj = DetectionDoc {
            step: Some(int(s)),
            range: Some(interval(
                (r_meas - range_err - MARGIN).max(0.0),
                r_meas + range_err + MARGIN,
            )),
            ..DetectionDoc::default()
        };
        if o.range_only {
            dj.region = Some(region(extra, l));
        } else {
            let hd = drive.headings[s.min(steps - 1)];
            let beta = wrap(libm::atan2(l[1] - p[1], l[0] - p[0]) - hd);
            dj.bearing = Some(bearing_interval(beta, bearing_err));
        }
        if o.operator {
            dj.landmark = d.landmark.map(int);
        }
        det_json.push(dj);
        matching.push(d.landmark.map(int));
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

pub(super) fn paper(o: &SimulateOptions) -> Value {
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
    let speed = ChannelDoc::measured(drive.speed_meas, err.speed + MARGIN);
    let heading = ChannelDoc::measured(drive.heading_meas, err.heading + MARGIN);
    let mission = MissionDoc {
        initial_position: Some(boxed(&[[-e0, e0], [-e0, e0]])),
        inputs: Some(InputsDoc {
            speed: Some(speed),
            heading: Some(heading),
            ..InputsDoc::default()
        }),
        motion_error: Some(PerStep::One(MARGIN)),
        detections: Some(List(det_json)),
        landmark_count: Some(int(n_landmarks)),
        max_outliers: (o.false_detections > 0).then(|| int(o.false_detections)),
        meta: Some(meta),
        truth: Some(TruthDoc {
            positions: Some(PointsIn::rows(2, drive.positions.as_flattened())),
            landmarks: Some(PointsIn::rows(2, landmarks.as_flattened())),
            matching: Some(List(matching)),
            headings: None,
        }),
        ..mission_head(format!("{name}-seed-{}", o.seed), "unicycle2d", dt, steps)
    };
    crate::format::to_value(&mission)
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
