//! The heading from two detections of one step: a
//! constellation seen in the robot's own frame turns with the heading,
//! whatever the robot's position.
//!
//! # Constraint
//!
//! Two range-and-bearing detections a and b at one step (position p,
//! heading θ, sensor offset o): `l(a) = p + R(θ)(o + m(a))` and `l(b) = p +
//! R(θ)(o + m(b))`, with `m = r(cos β, sin β)`.
//!
//! # Math
//!
//! Subtracting, p and o cancel: `l(a) - l(b) = R(θ)(m(a) - m(b))`. So the
//! direction of `l(a) - l(b)` is θ plus the direction of `m(a) - m(b)`:
//! with the boxes `La - Lb` and `M = m(a) - m(b)` (interval arithmetic),
//! `θ ∈ box_angle(La - Lb) - box_angle(M) + 2πZ` ([`contract_heading`]).
//! Nothing is learnt when either box holds the origin (two detections of
//! one landmark, or landmark boxes that overlap).
//!
//! # Soundness
//!
//! The true landmarks are in their boxes and the true (r, β) in the
//! measurement intervals, so the true vectors lie in the two boxes and
//! the true θ satisfies the equation for some point of each; the
//! contraction keeps every real θ congruent to such a direction
//! difference ([`crate::odometry::angle`], outward-rounded atan2, every
//! copy modulo 2π kept, headings of any magnitude). A detection without a
//! bearing gives no pair. Both detections must see real landmarks (the
//! rounds that call it run with `max_outliers` = 0).
//!
//! # Complexity
//!
//! O(1) per pair: a fixed number of interval operations and at most 8
//! atan2 calls.

use crate::interval::Interval;
use crate::odometry::angle::{box_angle, contract_heading};

/// One detection as the pair rule reads it: its landmark box and its
/// measurement.
#[derive(Debug, Clone, Copy)]
pub struct Seen {
    /// The box of l, the landmark.
    pub landmark: [Interval; 2],
    /// r, the range.
    pub range: Interval,
    /// β, the bearing (None: range only).
    pub bearing: Option<Interval>,
}

/// m = r(cos β, sin β), the landmark from the sensor in the body frame
/// (None without a bearing).
fn body(s: &Seen) -> Option<[Interval; 2]> {
    let b = s.bearing?;
    let r = s.range.intersect(Interval::new(0.0, f64::INFINITY));
    Some([r * b.cos(), r * b.sin()])
}

/// `heading` contracted by the pair (a, b) (module doc); EMPTY proves the
/// two detections inconsistent with their boxes.
pub fn contract_pair_heading(heading: Interval, a: &Seen, b: &Seen) -> Interval {
    let (Some(ma), Some(mb)) = (body(a), body(b)) else {
        return heading;
    };
    let Some(am) = box_angle(ma[0] - mb[0], ma[1] - mb[1]) else {
        return heading;
    };
    contract_heading(
        heading,
        a.landmark[0] - b.landmark[0],
        a.landmark[1] - b.landmark[1],
        am,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    fn unit(rng: &mut Lcg) -> f64 {
        (rng.bits() % 1_000_000) as f64 / 1_000_000.0
    }

    /// Planted poses (headings beyond ±π, bearings wrapped by multiples of
    /// 2π) and two landmarks, boxes of random widths around the truth
    /// (zero, tiny, huge, unbounded): the true heading survives, and with
    /// tight boxes the heading comes back from a wide interval.
    #[test]
    fn planted_pairs_keep_the_true_heading() {
        let mut rng = Lcg::new(4242);
        let tau = 2.0 * std::f64::consts::PI;
        let mut tightened = 0;
        for case in 0..5000 {
            let scale = match case % 6 {
                0 => 1e6,
                1 => 1e-6,
                _ => 1.0,
            };
            let th = (unit(&mut rng) - 0.5) * 400.0;
            let p = [(unit(&mut rng) - 0.5) * 100.0 * scale, 3.0 * scale];
            let o = [(unit(&mut rng) - 0.5) * scale, 0.0];
            let (c, s) = (libm::cos(th), libm::sin(th));
            let sensor = [p[0] + c * o[0] - s * o[1], p[1] + s * o[0] + c * o[1]];
            let seen = |rng: &mut Lcg, l: [f64; 2]| {
                let (dx, dy) = (l[0] - sensor[0], l[1] - sensor[1]);
                let r = libm::hypot(dx, dy);
                let b = libm::atan2(dy, dx) - th + tau * ((rng.bits() % 7) as f64 - 3.0);
                let w = match rng.bits() % 8 {
                    0 => 0.0,
                    1 => f64::INFINITY,
                    2 => 1e3 * scale,
                    _ => unit(rng) * 0.2 * scale,
                };
                let land = if w.is_infinite() {
                    [Interval::ENTIRE; 2]
                } else {
                    [
                        Interval::new(l[0] - unit(rng) * w, l[0] + unit(rng) * w),
                        Interval::new(l[1] - unit(rng) * w, l[1] + unit(rng) * w),
                    ]
                };
                // The truth's own rounding: a relative margin.
                let re = 1e-9 * r + unit(rng) * 0.05 * scale;
                Seen {
                    landmark: [
                        land[0].hull(Interval::centered(l[0], 1e-12 * scale)),
                        land[1].hull(Interval::centered(l[1], 1e-12 * scale)),
                    ],
                    range: Interval::centered(r, re),
                    bearing: (!rng.bits().is_multiple_of(10))
                        .then(|| Interval::centered(b, 1e-9 + unit(rng) * 0.05)),
                }
            };
            let la = [
                p[0] + 3.0 * scale,
                p[1] + (unit(&mut rng) - 0.5) * 6.0 * scale,
            ];
            let lb = if case % 13 == 0 {
                la
            } else {
                [
                    p[0] - 2.0 * scale,
                    p[1] + (unit(&mut rng) - 0.5) * 6.0 * scale,
                ]
            };
            let a = seen(&mut rng, la);
            let b = seen(&mut rng, lb);
            let h = Interval::centered(th, unit(&mut rng) * 3.0 + 1e-9);
            let out = contract_pair_heading(h, &a, &b);
            assert!(
                out.contains(th),
                "case {case}: {th} not in {out} (from {h})"
            );
            tightened += (out.width() < h.width() / 2.0) as usize;
        }
        assert!(tightened > 500, "{tightened}");
    }

    #[test]
    fn no_bearing_or_one_landmark_gives_nothing() {
        let l = [Interval::centered(1.0, 0.1), Interval::centered(2.0, 0.1)];
        let a = Seen {
            landmark: l,
            range: Interval::point(1.0),
            bearing: None,
        };
        let h = Interval::new(-1.0, 1.0);
        assert_eq!(contract_pair_heading(h, &a, &a), h);
        let a = Seen {
            bearing: Some(Interval::point(0.5)),
            ..a
        };
        assert_eq!(contract_pair_heading(h, &a, &a), h);
    }
}
