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
//! - False detections ([`simulate_woods_with`], `max_outliers`): K
//!   range-and-bearing detections in the robot's scans of phantom points in
//!   the sensor's field, at least `landmark_min_separation` + 0.5 m from
//!   every landmark, from a stream of their own (the true mission is the
//!   same bits with or without them): seen once, seen two or three times
//!   from nearby scans, or (operator missions) seen once under a real
//!   landmark's label; `max_outliers` K.
//!
//! Deterministic for a seed (splitmix64, libm only). Every declared bound
//! strictly exceeds the noise drawn by a margin (1e-9) that covers the f64
//! rounding of the simulation, so the truth satisfies every constraint.

use super::scenario::{boxed, int, interval, mission_head};
use crate::format::leaf::{Finite, List, PerStep, PointsIn};
use crate::format::mission_doc::{ChannelDoc, DetectionDoc, InputsDoc, MissionDoc, TruthDoc};
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
    detections: Vec<DetectionDoc>,
    /// The true landmark of each detection (`truth.matching`).
    matching: Vec<usize>,
    /// The scans: their step and their count of detections, by scan
    /// number.
    steps: Vec<(usize, usize)>,
}

/// Where the sensor is at step i of a drive, and its heading.
fn sensor(d: &Drive, i: usize) -> ([f64; 2], f64) {
    let (p, th) = (d.p[i], d.th[i]);
    (
        [p[0] + OFFSET * libm::cos(th), p[1] + OFFSET * libm::sin(th)],
        th,
    )
}

/// A detection at step i in scan `scan` of a point at true range r and
/// true bearing beta: the noise drawn from `rng`, the intervals as wide as
/// the declared bounds, the operator's `landmark` when given.
fn measured(
    rng: &mut Rng,
    (i, scan): (usize, usize),
    (r, beta): (f64, f64),
    landmark: Option<usize>,
) -> DetectionDoc {
    let rm = r + rng.sym(RANGE_NOISE);
    let bm = wrap(beta + rng.sym(BEARING_NOISE));
    let (er, eb) = (RANGE_NOISE + MARGIN, BEARING_NOISE + MARGIN);
    DetectionDoc {
        step: Some(int(i)),
        range: Some(interval((rm - er).max(0.0), rm + er)),
        bearing: Some(interval(bm - eb, bm + eb)),
        landmark: landmark.map(int),
        scan: Some(int(scan)),
        ..DetectionDoc::default()
    }
}

/// A scan every `SCAN_EVERY` steps: each landmark in range and field of
/// view detected once (see the module comment); `operator` writes the true
/// landmark as the detection's `landmark`.
fn scans(rng: &mut Rng, d: &Drive, landmarks: &[[f64; 2]], operator: bool) -> Scans {
    let mut out = Scans {
        detections: Vec::new(),
        matching: Vec::new(),
        steps: Vec::new(),
    };
    let n = d.p.len() - 1;
    let mut scan = 0usize;
    for i in (0..=n).step_by(SCAN_EVERY) {
        let (s, th) = sensor(d, i);
        let mut seen = 0;
        for (j, l) in landmarks.iter().enumerate() {
            let (dx, dy) = (l[0] - s[0], l[1] - s[1]);
            let r = libm::hypot(dx, dy);
            let beta = wrap(libm::atan2(dy, dx) - th);
            if r > MAX_RANGE || beta.abs() > FIELD_OF_VIEW {
                continue;
            }
            let det = measured(rng, (i, scan), (r, beta), operator.then_some(j));
            out.detections.push(det);
            out.matching.push(j);
            seen += 1;
        }
        if seen > 0 {
            out.steps.push((i, seen));
            scan += 1;
        }
    }
    out
}

/// Kinds of false detection, dealt round-robin from a kind the seed draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// A phantom point seen once.
    Isolated,
    /// A phantom point seen two or three times from nearby scans.
    Repeated,
    /// A phantom point seen once, with a real landmark's label (operator
    /// missions only).
    Labelled,
}

/// The nearest phantom a sensor reports, metres (true ranges of the woods
/// run from about 0.3 m; a phantom's range interval never reaches 0).
const PHANTOM_MIN_RANGE: f64 = 0.5;
/// A phantom's clearance beyond `landmark_min_separation`, metres.
pub const PHANTOM_CLEARANCE: f64 = 0.5;
/// Scans on either side of a phantom's first scan where a repeated
/// phantom may be seen again.
const NEARBY_SCANS: usize = 10;
/// Draws per phantom before the field is taken as having no room.
const PHANTOM_DRAWS: usize = 1000;
/// The stream of the false detections (the true mission never draws from
/// it: its bits do not depend on them).
const PHANTOM_STREAM: u64 = 0x5048_414E_544F_4D53;

/// The false detections drawn, in the order drawn: their JSON, their
/// phantom points and their scan numbers. (Flat vectors of types the page's
/// wasm already has: a vector of a new type brings its own code.)
#[derive(Default)]
struct Phantoms {
    detections: Vec<DetectionDoc>,
    points: Vec<[f64; 2]>,
    scans: Vec<usize>,
}

/// The true range and bearing of q from the sensor at step i when q lies
/// in the sensor's field (range in [`PHANTOM_MIN_RANGE`], `MAX_RANGE`],
/// bearing within the field of view).
fn in_field(d: &Drive, i: usize, q: [f64; 2]) -> Option<(f64, f64)> {
    let (s, th) = sensor(d, i);
    let (dx, dy) = (q[0] - s[0], q[1] - s[1]);
    let r = libm::hypot(dx, dy);
    let beta = wrap(libm::atan2(dy, dx) - th);
    let inside = (PHANTOM_MIN_RANGE..=MAX_RANGE).contains(&r) && beta.abs() <= FIELD_OF_VIEW;
    inside.then_some((r, beta))
}

/// Where false detections go: the drive, the scans (step, count of true
/// detections), the landmarks and the clearance a phantom keeps from each.
struct Field<'a> {
    drive: &'a Drive,
    scans: &'a [(usize, usize)],
    landmarks: &'a [[f64; 2]],
    clearance: f64,
}

impl Field<'_> {
    /// A phantom point in the field of a random scan, at least the
    /// clearance from every landmark: the scan's number and the point
    /// (None when the draw misses).
    fn draw(&self, rng: &mut Rng) -> Option<(usize, [f64; 2])> {
        let a = (rng.next_u64() % self.scans.len() as u64) as usize;
        let (s, th) = sensor(self.drive, self.scans[a].0);
        let r = rng.range(PHANTOM_MIN_RANGE, MAX_RANGE);
        let b = th + rng.sym(FIELD_OF_VIEW);
        let q = [s[0] + r * libm::cos(b), s[1] + r * libm::sin(b)];
        let clear = self
            .landmarks
            .iter()
            .all(|l| libm::hypot(l[0] - q[0], l[1] - q[1]) >= self.clearance + MARGIN);
        let seen = in_field(self.drive, self.scans[a].0, q).is_some();
        (clear && seen).then_some((a, q))
    }

    /// The scans that see q: scan a first, then `want` - 1 others within
    /// `NEARBY_SCANS` whose field holds q, drawn at random; None when too
    /// few scans do.
    fn seen_from(&self, rng: &mut Rng, a: usize, q: [f64; 2], want: usize) -> Option<Vec<usize>> {
        let near = a.saturating_sub(NEARBY_SCANS)..(a + NEARBY_SCANS + 1).min(self.scans.len());
        // Loops rather than iterator adaptors and `swap_remove`: less code
        // in the page's wasm (800 bytes).
        let mut others: Vec<usize> = Vec::new();
        for b in near {
            if b != a && in_field(self.drive, self.scans[b].0, q).is_some() {
                others.push(b);
            }
        }
        if others.len() + 1 < want {
            return None;
        }
        let mut chosen = vec![a];
        while chosen.len() < want {
            // `swap_remove`: the last moves into the slot drawn.
            let k = (rng.next_u64() % others.len() as u64) as usize;
            chosen.push(others[k]);
            others[k] = others[others.len() - 1];
            others.pop();
        }
        Some(chosen)
    }

    /// `want` detections of one phantom point (a label on each for
    /// `Labelled`) added to `out`; false after `PHANTOM_DRAWS` draws
    /// without room.
    fn place(&self, rng: &mut Rng, kind: Kind, want: usize, out: &mut Phantoms) -> bool {
        for _ in 0..PHANTOM_DRAWS {
            let Some((a, q)) = self.draw(rng) else {
                continue;
            };
            let Some(chosen) = self.seen_from(rng, a, q, want) else {
                continue;
            };
            let label = (kind == Kind::Labelled)
                .then(|| (rng.next_u64() % self.landmarks.len() as u64) as usize);
            for scan in chosen {
                let step = self.scans[scan].0;
                // Some: `draw` and `seen_from` checked it.
                let seen = in_field(self.drive, step, q).unwrap_or_default();
                out.detections
                    .push(measured(rng, (step, scan), seen, label));
                out.points.push(q);
                out.scans.push(scan);
            }
            return true;
        }
        false
    }
}

/// k false detections in the scans of a drive, from their own stream: the
/// kinds dealt round-robin (isolated, repeated two or three times, and with
/// `operator` a wrong label), starting at a kind the seed draws. A repeated
/// phantom that finds too few nearby scans is seen once; once a phantom
/// finds no room in `PHANTOM_DRAWS` draws (a field covered by the
/// landmarks' clearances, or no scan at all), the rest are dropped.
fn phantoms(seed: u64, k: usize, operator: bool, field: &Field) -> Phantoms {
    let mut out = Phantoms::default();
    if k == 0 || field.scans.is_empty() {
        return out;
    }
    let mut rng = Rng::new(seed ^ PHANTOM_STREAM);
    let kinds: &[Kind] = if operator {
        &[Kind::Isolated, Kind::Repeated, Kind::Labelled]
    } else {
        &[Kind::Isolated, Kind::Repeated]
    };
    let mut turn = (rng.next_u64() % kinds.len() as u64) as usize;
    while out.scans.len() < k {
        let kind = kinds[turn % kinds.len()];
        turn += 1;
        let want = match kind {
            Kind::Repeated => (2 + (rng.next_u64() % 2) as usize).min(k - out.scans.len()),
            _ => 1,
        };
        let placed = field.place(&mut rng, kind, want, &mut out)
            || (want > 1 && field.place(&mut rng, Kind::Isolated, 1, &mut out));
        if !placed {
            break;
        }
    }
    out
}

/// The true detections and the false ones merged, scan by scan: the true
/// ones first, then the false ones in the order drawn (a counting sort by
/// scan number). Returns the detections, `truth.matching` (None, null in
/// the JSON, for a false one) and each false detection's phantom point.
/// (Its shape, a counting sort, indices and `Option`s, keeps the page's
/// simulators' module within its budget, scripts/web.sh.)
fn merge(mut s: Scans, mut f: Phantoms) -> (Vec<DetectionDoc>, Vec<Option<usize>>, Vec<[f64; 2]>) {
    // start[a]..start[a + 1]: the false detections of scan a in `order`.
    let mut start = vec![0usize; s.steps.len() + 1];
    for &a in &f.scans {
        start[a + 1] += 1;
    }
    for a in 0..s.steps.len() {
        start[a + 1] += start[a];
    }
    let mut next = start.clone();
    let mut order = vec![0usize; f.scans.len()];
    for (i, &a) in f.scans.iter().enumerate() {
        order[next[a]] = i;
        next[a] += 1;
    }
    let total = s.detections.len() + order.len();
    let (mut detections, mut matching, mut points) = (
        Vec::with_capacity(total),
        Vec::with_capacity(total),
        Vec::with_capacity(order.len()),
    );
    // Indices and `take` rather than a consuming iterator: less code in
    // the page's wasm.
    let mut t = 0;
    for (a, &(_, count)) in s.steps.iter().enumerate() {
        for _ in 0..count {
            detections.push(std::mem::take(&mut s.detections[t]));
            matching.push(Some(s.matching[t]));
            t += 1;
        }
        for &i in &order[start[a]..start[a + 1]] {
            detections.push(std::mem::take(&mut f.detections[i]));
            matching.push(None);
            points.push(f.points[i]);
        }
    }
    (detections, matching, points)
}

/// The woods mission with truth, as `nvector-mission/1` JSON (model
/// `odometry2d`).
pub fn simulate_woods(o: &WoodsOptions) -> Value {
    simulate_woods_with(o, 0)
}

/// The woods mission with `false_detections` false range-and-bearing
/// detections (see [`phantoms`]; `slam::simulate` takes them at its
/// `MAX_FALSE_DETECTIONS`, and nothing here is allocated by the number
/// asked, only by the number placed): each in
/// a scan of the robot, as wide as a true one, of a phantom point in the
/// sensor's field at least `landmark_min_separation` +
/// [`PHANTOM_CLEARANCE`] from every landmark; `null` in `truth.matching`,
/// `max_outliers` set to `false_detections`, the phantom point of each in
/// `meta.false_points` (in the order of the false detections). 0 gives
/// [`simulate_woods`]'s mission, bit for bit.
pub fn simulate_woods_with(o: &WoodsOptions, false_detections: usize) -> Value {
    let k = false_detections;
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
    let declared = separation.is_finite().then_some(separation - 0.01);
    let field = Field {
        drive: &d,
        scans: &s.steps,
        landmarks: &landmarks,
        clearance: declared.unwrap_or(0.0) + PHANTOM_CLEARANCE,
    };
    let false_ones = phantoms(o.seed, k, o.operator, &field);
    let (detections, matching, points) = merge(s, false_ones);
    let mut meta = json!({
        "scenario": "woods",
        "seed": o.seed,
        "scan_every": SCAN_EVERY,
        "max_range": MAX_RANGE,
        "field_of_view": FIELD_OF_VIEW,
    });
    let mut name = String::from("woods");
    if k > 0 {
        name += &format!("-false-{k}");
        meta["false_detections"] = json!(k);
        meta["false_points"] = json!(points);
    }
    let speed = ChannelDoc::measured(d.speed, SPEED_NOISE + MARGIN);
    let turn_rate = ChannelDoc::measured(d.turn, 0.0);
    let m = MissionDoc {
        initial_position: Some(boxed(&[
            [-INITIAL_ERROR, INITIAL_ERROR],
            [-INITIAL_ERROR, INITIAL_ERROR],
        ])),
        initial_heading: Some(interval(d.th[0] - INITIAL_ERROR, d.th[0] + INITIAL_ERROR)),
        inputs: Some(InputsDoc {
            speed: Some(speed),
            turn_rate: Some(turn_rate),
            ..InputsDoc::default()
        }),
        heading_error: Some(PerStep::One(HEADING_NOISE + MARGIN)),
        motion_error: Some(PerStep::One(MOTION_NOISE + MARGIN)),
        sensor_offset: Some(List(vec![Finite(OFFSET), Finite(0.0)])),
        detections: Some(List(detections)),
        landmark_count: Some(int(count)),
        landmark_min_separation: declared.map(Finite),
        max_outliers: (k > 0).then(|| int(k)),
        meta: Some(meta),
        truth: Some(TruthDoc {
            positions: Some(PointsIn::rows(2, d.p.as_flattened())),
            headings: Some(List(d.th.into_iter().map(|h| Some(Finite(h))).collect())),
            landmarks: Some(PointsIn::rows(2, landmarks.as_flattened())),
            matching: Some(List(matching.into_iter().map(|j| j.map(int)).collect())),
        }),
        ..mission_head(format!("{name}-{}", o.seed), "odometry2d", DT, n)
    };
    crate::format::to_value(&m)
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

    /// Without false detections the mission is what it was before they
    /// existed: the fingerprints (length, FNV-1a of the text) were taken
    /// from main at 08cf419, the generator as it was.
    #[test]
    fn no_false_detections_leave_the_mission_unchanged() {
        for (seed, steps, landmarks, operator, len, hash) in [
            (1, None, None, false, 1_588_756, 0xa150_99b6_43fb_2724u64),
            (2, Some(300), None, true, 194_483, 0x3038_4682_b3e7_88e1),
            (5, Some(800), Some(9), false, 287_782, 0xbdd2_48f7_740d_ac47),
        ] {
            let o = WoodsOptions {
                seed,
                steps,
                landmarks,
                operator,
            };
            for s in [simulate_woods(&o), simulate_woods_with(&o, 0)] {
                let s = s.to_string();
                assert_eq!(
                    (s.len(), crate::rng::fnv1a(s.bytes())),
                    (len, hash),
                    "{o:?}"
                );
            }
        }
    }
}
