//! The scan pose (core/src/odometry/scan_pose.rs), with planted solutions:
//! a true pose (position, a heading anywhere in [-20, 20] rad) and 1-11
//! landmarks seen from a sensor offset, with range and bearing intervals
//! holding the truth (bearings shifted by 2 pi k), a heading interval
//! holding the true heading (0 to 6 rad wide, or a point), a position box
//! holding it (tight, wide, huge or unbounded) and landmark boxes holding
//! their landmarks (a point, tight, wide or unbounded). The contraction
//! must never lose the truth nor call a planted world infeasible; it must
//! also narrow the heading where two tight landmarks are seen (a
//! contractor doing nothing passes the first checks).

#![allow(clippy::disallowed_methods)]

use nvector_core::odometry::scan_pose::{contract_scan_pose, PoseOutcome, PoseReading};
use nvector_core::rng::Rng;
use nvector_core::Interval;
use std::f64::consts::PI;

/// An interval of width `w` holding `x` at a random place.
fn around(rng: &mut Rng, x: f64, w: f64) -> Interval {
    let a = rng.unit() * w;
    Interval::new(x - a, x - a + w)
}

/// A box width drawn among the kinds of the module doc.
fn width(rng: &mut Rng) -> f64 {
    match rng.next_u64() % 6 {
        0 => 0.0,
        1 => rng.range(0.01, 0.5),
        2 => rng.range(0.5, 4.0),
        3 => rng.range(4.0, 50.0),
        4 => 1e7,
        _ => f64::INFINITY,
    }
}

/// A box of width `w` around `x` (unbounded when w is infinite).
fn box_around(rng: &mut Rng, x: [f64; 2], w: f64) -> [Interval; 2] {
    if w.is_infinite() {
        return [Interval::ENTIRE; 2];
    }
    [around(rng, x[0], w), around(rng, x[1], w)]
}

struct World {
    p: [f64; 2],
    th: f64,
    offset: [f64; 2],
    marks: Vec<[f64; 2]>,
}

/// The measurements of a world, each interval holding the truth.
fn readings(rng: &mut Rng, w: &World, tight: bool) -> Vec<PoseReading> {
    let (c, s) = (libm::cos(w.th), libm::sin(w.th));
    let sensor = [
        w.p[0] + c * w.offset[0] - s * w.offset[1],
        w.p[1] + s * w.offset[0] + c * w.offset[1],
    ];
    w.marks
        .iter()
        .map(|l| {
            let (dx, dy) = (l[0] - sensor[0], l[1] - sensor[1]);
            let r = libm::hypot(dx, dy);
            let k = (rng.next_u64() % 5) as f64 - 2.0;
            let b = libm::atan2(dy, dx) - w.th + 2.0 * PI * k;
            let wl = if tight {
                rng.range(0.0, 0.3)
            } else {
                width(rng)
            };
            let (wr, wb) = if tight { (0.05, 0.03) } else { (0.3, 0.2) };
            let (wr, wb) = (rng.range(0.0, wr), rng.range(0.0, wb));
            PoseReading {
                range: around(rng, r, wr),
                bearing: around(rng, b, wb),
                landmark: box_around(rng, *l, wl),
            }
        })
        .collect()
}

fn world(rng: &mut Rng) -> World {
    let p = [rng.sym(50.0), rng.sym(50.0)];
    let count = 1 + (rng.next_u64() % 11) as usize;
    World {
        p,
        th: rng.sym(20.0),
        offset: if rng.unit() < 0.3 {
            [0.0, 0.0]
        } else {
            [rng.sym(0.5), rng.sym(0.5)]
        },
        marks: (0..count)
            .map(|_| {
                let r = rng.range(0.3, 8.0);
                let a = rng.sym(PI);
                [p[0] + r * libm::cos(a), p[1] + r * libm::sin(a)]
            })
            .collect(),
    }
}

fn inside(b: &[Interval; 2], x: [f64; 2]) -> bool {
    b[0].contains(x[0]) && b[1].contains(x[1])
}

/// 4000 planted worlds: the truth survives every contraction.
#[test]
fn planted_pose_and_landmarks_survive() {
    let mut rng = Rng::new(20);
    let mut narrowed = 0;
    for case in 0..4000 {
        let w = world(&mut rng);
        let mut reads = readings(&mut rng, &w, case % 3 == 0);
        let hw = match case % 4 {
            0 => 0.0,
            1 => rng.range(0.0, 0.3),
            2 => rng.range(0.3, 1.5),
            _ => rng.range(1.5, 6.0),
        };
        let mut th = around(&mut rng, w.th, hw);
        let pw = width(&mut rng);
        let mut p = box_around(&mut rng, w.p, pw);
        let before = th;
        let out = contract_scan_pose(&mut p, &mut th, w.offset, &mut reads, 2 + case % 31);
        assert_eq!(
            out,
            PoseOutcome::Contracted,
            "case {case}: planted world called infeasible"
        );
        assert!(
            th.contains(w.th),
            "case {case}: heading {} lost from {th}",
            w.th
        );
        assert!(inside(&p, w.p), "case {case}: position {:?} lost", w.p);
        for (j, r) in reads.iter().enumerate() {
            assert!(
                inside(&r.landmark, w.marks[j]),
                "case {case}: landmark {j} lost"
            );
        }
        if th.width() < 0.5 * before.width() {
            narrowed += 1;
        }
    }
    assert!(
        narrowed > 200,
        "the heading was narrowed on only {narrowed} worlds"
    );
}

/// Two tight landmarks 3 m apart, seen with a heading 1 rad wide and a
/// position box 2 m wide: the heading comes out narrower than 0.4 rad
/// and the position box narrower than 1 m, the truth inside.
#[test]
fn two_tight_landmarks_fix_the_heading() {
    let mut rng = Rng::new(7);
    for case in 0..200 {
        let th_true = rng.sym(10.0);
        let p = [rng.sym(5.0), rng.sym(5.0)];
        let w = World {
            p,
            th: th_true,
            offset: [0.2, 0.0],
            marks: vec![[p[0] + 2.0, p[1] + 1.0], [p[0] - 1.0, p[1] + 1.0]],
        };
        let mut reads = readings(&mut rng, &w, true);
        for (r, l) in reads.iter_mut().zip(&w.marks) {
            r.landmark = [around(&mut rng, l[0], 0.1), around(&mut rng, l[1], 0.1)];
        }
        let mut th = around(&mut rng, th_true, 1.0);
        let mut pos = [around(&mut rng, p[0], 2.0), around(&mut rng, p[1], 2.0)];
        let out = contract_scan_pose(&mut pos, &mut th, w.offset, &mut reads, 32);
        assert_eq!(out, PoseOutcome::Contracted);
        assert!(
            th.contains(th_true) && inside(&pos, p),
            "case {case}: truth lost"
        );
        assert!(
            th.width() < 0.4,
            "case {case}: heading still {} wide",
            th.width()
        );
        assert!(
            pos[0].width() < 1.0 && pos[1].width() < 1.0,
            "case {case}: position still wide"
        );
    }
}

/// A world whose detections contradict every heading of the interval is
/// infeasible: one tight landmark seen in the wrong direction.
#[test]
fn a_contradiction_is_found() {
    let mut p = [Interval::new(-0.1, 0.1), Interval::new(-0.1, 0.1)];
    let mut th = Interval::new(-0.2, 0.2);
    let mut reads = [PoseReading {
        range: Interval::new(2.0, 2.1),
        bearing: Interval::new(-0.05, 0.05),
        // Behind the robot: the bearing says ahead.
        landmark: [Interval::new(-2.1, -1.9), Interval::new(-0.1, 0.1)],
    }];
    let out = contract_scan_pose(&mut p, &mut th, [0.0, 0.0], &mut reads, 8);
    assert_eq!(out, PoseOutcome::Empty);
    // The same seen ahead is consistent.
    let mut th = Interval::new(-0.2, 0.2);
    let mut p = [Interval::new(-0.1, 0.1), Interval::new(-0.1, 0.1)];
    reads[0].landmark = [Interval::new(1.9, 2.1), Interval::new(-0.1, 0.1)];
    let out = contract_scan_pose(&mut p, &mut th, [0.0, 0.0], &mut reads, 8);
    assert_eq!(out, PoseOutcome::Contracted);
}

/// A heading interval whose width overflows (hi - lo = +inf in floats):
/// the pieces must still cover it, so a true heading anywhere inside
/// survives with its position and landmark.
#[test]
fn a_heading_wider_than_the_floats_keeps_the_truth() {
    for th_true in [-1e308, -3.0, 0.0, 1.0, 7e307, 1e308] {
        let (p_true, r_true, b_true) = ([2.0, -1.0], 5.0, 0.3);
        let a = th_true + b_true;
        let l = [
            p_true[0] + r_true * libm::cos(a),
            p_true[1] + r_true * libm::sin(a),
        ];
        let mut p = [Interval::new(-10.0, 10.0), Interval::new(-10.0, 10.0)];
        let mut th = Interval::new(-f64::MAX, f64::MAX);
        let mut reads = vec![PoseReading {
            range: Interval::new(4.9, 5.1),
            bearing: Interval::new(0.29, 0.31),
            landmark: [
                Interval::new(l[0] - 1.0, l[0] + 1.0),
                Interval::new(l[1] - 1.0, l[1] + 1.0),
            ],
        }];
        let out = contract_scan_pose(&mut p, &mut th, [0.0, 0.0], &mut reads, 16);
        assert_eq!(out, PoseOutcome::Contracted, "heading {th_true}");
        assert!(th.contains(th_true), "heading {th_true} lost: {th:?}");
        assert!(inside(&p, p_true), "heading {th_true}: position lost");
        assert!(
            inside(&reads[0].landmark, l),
            "heading {th_true}: landmark lost"
        );
    }
}
