//! Scan registration against the closed-world map
//! (core/src/slam/association/odometry2d/scan_map.rs), with planted solutions: n
//! landmarks at least s apart, a map of groups (one detection each) whose
//! boxes hold their true landmark (tight, wide, point, or several groups of
//! one landmark; all n landmarks or only some: the open world), and one
//! scan of 1-11 detections from a pose with any heading (beyond ±pi) and
//! bearings wrapped by multiples of 2 pi, its detection boxes holding their
//! landmark (tight, wide or unbounded: a lost heading). The rule must
//! never join a detection to a group of another landmark and never call a
//! planted world infeasible; it must prove matchings on the random worlds
//! (a rule proving nothing passes the first two checks), and nothing on a
//! square of landmarks seen with unbounded boxes (registration is
//! ambiguous there: four rotations fit).

#![allow(clippy::disallowed_methods)]

use nvector_core::ibox::IntervalBox;
use nvector_core::rng::Rng;
use nvector_core::slam::association::odometry2d::scan_map::ScanMap;
use nvector_core::slam::mission::Mission;
use nvector_core::union_find::Uf;
use nvector_core::Interval;
use serde_json::json;
use std::f64::consts::PI;

/// Uniform picks in 0..n from core's generator.
trait Below {
    fn below(&mut self, n: usize) -> usize;
}

impl Below for Rng {
    fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Landmarks at least `s` apart in a square growing with their number.
fn landmarks(rng: &mut Rng, n: usize, s: f64) -> Vec<[f64; 2]> {
    let side = s * (n as f64).sqrt() * 2.5;
    let mut out: Vec<[f64; 2]> = Vec::new();
    while out.len() < n {
        let c = [rng.unit() * side - side / 2.0, rng.unit() * side];
        if out.iter().all(|l| (l[0] - c[0]).hypot(l[1] - c[1]) >= s) {
            out.push(c);
        }
    }
    out
}

/// A box holding `l`, each side from it by a random share of `w` (0: a
/// point; infinite: unbounded).
fn box_around(rng: &mut Rng, l: [f64; 2], w: f64) -> IntervalBox {
    let mut axis = |x: f64| {
        if w.is_infinite() {
            Interval::ENTIRE
        } else {
            Interval::new(x - rng.unit() * w, x + rng.unit() * w)
        }
    };
    let a = axis(l[0]);
    let b = axis(l[1]);
    IntervalBox::new(&[a, b])
}

/// One planted world: the mission (map detections first, then the scan's),
/// the detection boxes, the true landmark of each detection, the scan.
struct World {
    mission: Mission,
    det: Vec<IntervalBox>,
    truth: Vec<usize>,
    scan: Vec<usize>,
    /// Detections of one map group.
    links: Vec<(usize, usize)>,
    n: usize,
}

/// Range and bearing of `l` from the sensor of a robot at `p` heading `h`
/// (offset `o`), as intervals of half-widths `er`, `eb` around the truth
/// at random places; the bearing shifted by 2 pi `wrap`.
#[allow(clippy::too_many_arguments)]
fn measure(
    rng: &mut Rng,
    p: [f64; 2],
    h: f64,
    o: [f64; 2],
    l: [f64; 2],
    er: f64,
    eb: f64,
    wrap: f64,
) -> (Interval, Interval) {
    let (c, s) = (h.cos(), h.sin());
    let sensor = [p[0] + c * o[0] - s * o[1], p[1] + s * o[0] + c * o[1]];
    let (dx, dy) = (l[0] - sensor[0], l[1] - sensor[1]);
    let r = dx.hypot(dy);
    let b = dy.atan2(dx) - h + 2.0 * PI * wrap;
    let ri = Interval::new(
        (r - er * (1.0 + rng.unit())).max(0.0),
        r + er * (1.0 + rng.unit()),
    );
    let bi = Interval::new(b - eb * (1.0 + rng.unit()), b + eb * (1.0 + rng.unit()));
    (ri, bi)
}

/// Builds a world from the landmarks; `map`: the landmark of each map
/// group; `seen`: the landmarks of the scan; `scan_w`: the width of the
/// scan's detection boxes; `map_w`: the map boxes' width.
fn world(
    rng: &mut Rng,
    lm: &[[f64; 2]],
    map: &[usize],
    seen: &[usize],
    map_w: f64,
    scan_w: f64,
    s: f64,
) -> World {
    let p = [rng.unit() * 4.0 - 2.0, rng.unit() * 4.0 - 2.0];
    let h = rng.unit() * 40.0 - 20.0;
    let o = [0.3 * rng.unit(), 0.1 * rng.unit() - 0.05];
    let (er, eb) = (0.005 + 0.02 * rng.unit(), 0.002 + 0.01 * rng.unit());
    let mut dets = Vec::new();
    let mut det = Vec::new();
    let mut truth = Vec::new();
    let mut links = Vec::new();
    for (x, &g) in map.iter().enumerate() {
        // A group of two detections (the rule reads groups, not singletons).
        let w = if rng.below(4) == 0 {
            map_w * 4.0
        } else {
            map_w
        };
        let w = if rng.below(10) == 0 { 0.0 } else { w };
        let b = box_around(rng, lm[g], w);
        links.push((dets.len(), dets.len() + 1));
        for y in 0..2 {
            dets.push(json!({"step": 1, "range": [1, 2], "bearing": [0, 0.1], "scan": 10_000 + 2 * x + y}));
            det.push(b.clone());
            truth.push(g);
        }
    }
    let mut scan = Vec::new();
    for &g in seen {
        let wrap = (rng.below(5) as f64) - 2.0;
        let (r, b) = measure(rng, p, h, o, lm[g], er, eb, wrap);
        scan.push(dets.len());
        dets.push(
            json!({"step": 1, "range": [r.lo(), r.hi()], "bearing": [b.lo(), b.hi()], "scan": 7}),
        );
        det.push(box_around(rng, lm[g], scan_w));
        truth.push(g);
    }
    let mission = Mission::from_value(&json!({
        "format": "nvector-mission/1",
        "model": "odometry2d",
        "dt": 0.1,
        "steps": 1,
        "initial_position": [[-10, 10], [-10, 10]],
        "initial_heading": [-1, 1],
        "inputs": {
            "speed": {"value": [0.0], "error": 0.05},
            "turn_rate": {"value": [0.0], "error": 0.01}
        },
        "sensor_offset": o,
        "landmark_count": lm.len(),
        "landmark_min_separation": s,
        "detections": dets
    }))
    .expect("a valid mission");
    World {
        mission,
        det,
        truth,
        scan,
        links,
        n: lm.len(),
    }
}

/// Runs the rule on a world; the unions (checked against the truth).
fn check(w: &World, what: &str) -> usize {
    let mut uf = Uf::new(w.det.len());
    for &(a, b) in &w.links {
        uf.union(a, b);
    }
    let map = ScanMap::new(&w.mission, &w.det, &mut uf, w.n).expect("a map");
    let unions = map
        .settle(&w.mission, &w.det, &mut uf, &w.scan)
        .unwrap_or_else(|e| panic!("{what}: a planted world called infeasible: {e}"));
    for &(a, b) in &unions {
        assert_eq!(
            w.truth[a], w.truth[b],
            "{what}: detection {a} (landmark {}) joined to detection {b} (landmark {})",
            w.truth[a], w.truth[b]
        );
    }
    unions.len()
}

/// `k` distinct random picks among `0..n`.
fn pick(rng: &mut Rng, n: usize, k: usize) -> Vec<usize> {
    let mut all: Vec<usize> = (0..n).collect();
    for x in 0..k {
        let y = x + rng.below(n - x);
        all.swap(x, y);
    }
    all.truncate(k);
    all
}

#[test]
fn scan_map_never_joins_two_landmarks() {
    let mut rng = Rng::from_state(20);
    let mut proved = 0;
    let mut proved_closed = 0;
    for case in 0..3000 {
        let n = 3 + rng.below(18);
        let s = [0.5, 1.33, 3.0][rng.below(3)];
        let lm = landmarks(&mut rng, n, s);
        // The map: every landmark (closed world) or only some; sometimes a
        // landmark twice (two groups of one landmark).
        let closed = rng.below(2) == 0;
        let mut map: Vec<usize> = if closed {
            (0..n).collect()
        } else {
            let m = 1 + rng.below(n);
            pick(&mut rng, n, m)
        };
        if rng.below(4) == 0 {
            let again = map[rng.below(map.len())];
            map.push(again);
        }
        let k = 1 + rng.below(n.min(11));
        let seen = pick(&mut rng, n, k);
        let map_w = [0.0, 0.05, 0.3, 1.0, 5.0][rng.below(5)] * s;
        let scan_w = [0.1, 1.0, 10.0, 1e6, f64::INFINITY][rng.below(5)];
        let w = world(&mut rng, &lm, &map, &seen, map_w, scan_w, s);
        let u = check(&w, &format!("case {case}"));
        proved += u;
        if closed {
            proved_closed += u;
        }
    }
    // The rule is not vacuous: it proves matchings, in the closed world too.
    assert!(
        proved > 1000 && proved_closed > 500,
        "proved {proved}, closed {proved_closed}"
    );
}

/// A square of landmarks (and its rotations fit any scan of it): with the
/// scan's boxes unbounded (the heading lost), nothing can be proved.
#[test]
fn scan_map_proves_nothing_on_a_square_seen_without_heading() {
    let mut rng = Rng::from_state(4);
    for case in 0..300 {
        let side = 2.0 + rng.unit() * 3.0;
        let lm = vec![[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]];
        let k = 1 + rng.below(4);
        let seen = pick(&mut rng, 4, k);
        let map_w = [0.0, 0.01, 0.1][rng.below(3)];
        let w = world(
            &mut rng,
            &lm,
            &[0, 1, 2, 3],
            &seen,
            map_w,
            f64::INFINITY,
            1.0,
        );
        assert_eq!(
            check(&w, &format!("square case {case}")),
            0,
            "square case {case}"
        );
    }
    // Tight scan boxes break the symmetry: matchings are proved.
    let mut proved = 0;
    for case in 0..100 {
        let lm = vec![[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]];
        let k = 1 + rng.below(4);
        let seen = pick(&mut rng, 4, k);
        let w = world(&mut rng, &lm, &[0, 1, 2, 3], &seen, 0.05, 0.5, 1.0);
        proved += check(&w, &format!("tight square case {case}"));
    }
    assert!(proved > 50, "proved {proved}");
}

/// Scans of 1, 2 or 3 landmarks of a map on a line (pairwise distances
/// 2, 3, 5, 6, 9, 11: all different) with unbounded boxes (the heading
/// lost): one detection and one pair are ambiguous (nothing proved), a
/// triple is pinned by its distances alone.
#[test]
fn scan_map_uses_distances_when_the_heading_is_lost() {
    let mut rng = Rng::from_state(7);
    // Landmarks on a line at distances 2, 5, 11 from the first: every pair
    // distance differs, so a pair seen with unbounded boxes is pinned.
    let lm = vec![[0.0, 0.0], [2.0, 0.0], [5.0, 0.0], [11.0, 0.0]];
    let mut pinned = 0;
    for case in 0..200 {
        let one = pick(&mut rng, 4, 1);
        let w = world(&mut rng, &lm, &[0, 1, 2, 3], &one, 0.01, f64::INFINITY, 1.0);
        assert_eq!(check(&w, &format!("one case {case}")), 0);
        let two = pick(&mut rng, 4, 2);
        let w = world(&mut rng, &lm, &[0, 1, 2, 3], &two, 0.01, f64::INFINITY, 1.0);
        pinned += check(&w, &format!("two case {case}"));
    }
    // A pair fits its map pair both ways round: nothing proved.
    assert_eq!(pinned, 0);
    // Three points with distinct pairwise distances: each is the one
    // opposite its own pair, so every detection is proved.
    let mut triples = 0;
    for case in 0..200 {
        let three = pick(&mut rng, 4, 3);
        let w = world(
            &mut rng,
            &lm,
            &[0, 1, 2, 3],
            &three,
            0.01,
            f64::INFINITY,
            1.0,
        );
        triples += check(&w, &format!("triple case {case}"));
    }
    assert_eq!(triples, 600);
}
