//! `OffsetDetection`: a range (and bearing) detection measured from a point
//! fixed in the robot's body frame (`sensor_offset`), under an uncertain
//! heading that is a variable (odometry2d) or an input interval
//! (unicycle2d).
//!
//! # Constraint
//!
//! With p the robot position, θ its heading (a real number), o = (o_f, o_l)
//! the sensor offset (metres forward and left), d the landmark, r the range
//! and β the bearing:
//!
//! - `s = p + R(θ)·o = p + (o_f cos θ - o_l sin θ, o_f sin θ + o_l cos θ)`;
//! - `|d - s| = r`;
//! - with a bearing: `d = s + r·(cos(θ + β), sin(θ + β))`.
//!
//! # Math
//!
//! O = R(θ)·o in interval arithmetic, S = p + O; then
//! [`contract_distance`] on (S, d, r); with a bearing [`contract_bearing`]
//! on (S, d, θ, β, r) and the distance again. The heading is contracted
//! ([`contract_heading`], every copy modulo 2π kept) three ways:
//!
//! 1. from the bearing: the direction of d - S is θ + β;
//! 2. from the body frame: d - p = R(θ)·L with L = o + r·(cos β, sin β), so
//!    the direction of d - p is θ + angle(L) when the box L excludes the
//!    origin;
//! 3. from the offset: O = S - p = R(θ)·o, so the direction of S - p is
//!    θ + angle(o) (o ≠ 0; this one works for range-only detections too).
//!
//! Then O is recomputed from the contracted θ and `p ∩= S - O`,
//! `S ∩= p + O`.
//!
//! # Soundness
//!
//! Each step is the interval projection of one of the equations above
//! (outward rounding, sound sin/cos/atan2); the true (p, θ, d) with r and
//! β in their intervals satisfy every equation, so they survive every
//! step. The heading contractions keep every real θ congruent to a
//! direction of the box (see [`crate::odometry::angle`]). With o = 0, S is
//! p exactly and the contractor is the plain distance and bearing ones
//! plus the heading contraction 1.
//!
//! # Complexity
//!
//! O(1): a fixed number of interval operations and at most 12 atan2 calls.

use crate::contractors::bearing::contract_bearing;
use crate::contractors::distance::contract_distance;
use crate::interval::Interval;
use crate::odometry::angle::{box_angle, contract_heading};

/// One detection's measurement: range, optional bearing, sensor offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffsetDetection {
    /// r, the range (cut to [0, +inf) when used).
    pub range: Interval,
    /// β, the bearing relative to the heading, when measured (any real
    /// interval: a bearing given beyond ±π is fine).
    pub bearing: Option<Interval>,
    /// o, the sensor's place in the body frame (forward, left), metres.
    pub offset: [f64; 2],
}

/// `R(θ)·o` for a heading in `heading` (exactly 0 when o = 0).
pub fn rotate_offset(heading: Interval, offset: [f64; 2]) -> [Interval; 2] {
    if offset == [0.0, 0.0] {
        return [Interval::ZERO; 2];
    }
    let (c, s) = (heading.cos(), heading.sin());
    let (f, l) = (Interval::point(offset[0]), Interval::point(offset[1]));
    if f.is_empty() || l.is_empty() {
        // A non-finite offset: the sensor may be anywhere.
        return [Interval::ENTIRE; 2];
    }
    [f * c - l * s, f * s + l * c]
}

fn any_empty(xs: &[Interval]) -> bool {
    xs.iter().any(|x| x.is_empty())
}

impl OffsetDetection {
    /// A detection.
    pub fn new(range: Interval, bearing: Option<Interval>, offset: [f64; 2]) -> OffsetDetection {
        OffsetDetection {
            range,
            bearing,
            offset,
        }
    }

    /// The sensor point's box `p + R(θ)·o`.
    pub fn sensor_box(&self, p: &[Interval; 2], heading: Interval) -> [Interval; 2] {
        let o = rotate_offset(heading, self.offset);
        [p[0] + o[0], p[1] + o[1]]
    }

    /// Contracts the robot position `p`, the heading and the landmark `d`
    /// (see the module doc). Returns `false` when a domain became empty
    /// (then the domains are left in an unspecified contracted state).
    pub fn contract(
        &self,
        p: &mut [Interval; 2],
        heading: &mut Interval,
        d: &mut [Interval; 2],
    ) -> bool {
        let mut r = self.range.intersect(Interval::new(0.0, f64::INFINITY));
        if r.is_empty() || heading.is_empty() || any_empty(p) || any_empty(d) {
            return false;
        }
        let zero_offset = self.offset == [0.0, 0.0];
        let mut o = rotate_offset(*heading, self.offset);
        let mut s = [p[0] + o[0], p[1] + o[1]];
        if !contract_distance(&mut s, d, &mut r) {
            return false;
        }
        if let Some(beta) = self.bearing {
            if beta.is_empty() {
                return false;
            }
            if !contract_bearing(&mut s, d, *heading, beta, r)
                || !contract_distance(&mut s, d, &mut r)
            {
                return false;
            }
            // 1. The direction of d - S is θ + β.
            *heading = contract_heading(*heading, d[0] - s[0], d[1] - s[1], beta);
            if heading.is_empty() {
                return false;
            }
            // 2. The direction of d - p is θ + angle(L).
            if !zero_offset {
                let l = [
                    Interval::point(self.offset[0]) + r * beta.cos(),
                    Interval::point(self.offset[1]) + r * beta.sin(),
                ];
                if let Some(al) = box_angle(l[0], l[1]) {
                    *heading = contract_heading(*heading, d[0] - p[0], d[1] - p[1], al);
                    if heading.is_empty() {
                        return false;
                    }
                }
            }
        }
        if !zero_offset {
            // 3. S - p = R(θ)·o: the direction of S - p is θ + angle(o).
            let so = [o[0].intersect(s[0] - p[0]), o[1].intersect(s[1] - p[1])];
            if any_empty(&so) {
                return false;
            }
            let ao = box_angle(
                Interval::point(self.offset[0]),
                Interval::point(self.offset[1]),
            );
            if let Some(ao) = ao {
                *heading = contract_heading(*heading, so[0], so[1], ao);
                if heading.is_empty() {
                    return false;
                }
            }
            o = rotate_offset(*heading, self.offset);
            o = [o[0].intersect(so[0]), o[1].intersect(so[1])];
        }
        for a in 0..2 {
            p[a] = p[a].intersect(s[a] - o[a]);
        }
        !(any_empty(p) || any_empty(d) || any_empty(&o))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_landmark_ahead_fixes_the_heading() {
        // Robot at the origin, laser 0.2 m ahead, landmark at (3.2, 0):
        // range 3, bearing 0; heading in [-1, 1]: it comes back to about
        // ±0.01 (the landmark's direction from the robot).
        let det = OffsetDetection::new(
            Interval::centered(3.0, 0.01),
            Some(Interval::centered(0.0, 0.01)),
            [0.2, 0.0],
        );
        let mut p = [Interval::centered(0.0, 0.01); 2];
        let mut h = Interval::new(-1.0, 1.0);
        let mut d = [Interval::centered(3.2, 0.01), Interval::centered(0.0, 0.01)];
        assert!(det.contract(&mut p, &mut h, &mut d));
        assert!(h.contains(0.0) && h.width() < 0.05, "{h:?}");
        // The same, the landmark seen behind: infeasible.
        let mut p = [Interval::centered(0.0, 0.01); 2];
        let mut h = Interval::new(-0.1, 0.1);
        let mut d = [
            Interval::centered(-3.2, 0.01),
            Interval::centered(0.0, 0.01),
        ];
        assert!(!det.contract(&mut p, &mut h, &mut d));
    }
}
