//! `Bearing`: the landmark d is seen from the robot position p at range r
//! and at angle β relative to the robot's heading θ (counter-clockwise,
//! radians; for auv3d, θ is the yaw and the angle is in the horizontal
//! plane):
//! `(d_x, d_y) = (p_x, p_y) + ρ (cos(θ + β), sin(θ + β))`, with ρ = r in
//! 2-D and ρ = sqrt(r^2 - (d_z - p_z)^2), the horizontal range, in 3-D.
//!
//! # Math
//!
//! φ = θ + β, c = cos φ, s = sin φ (interval extensions), then
//! `d ∩= p + ρ (c, s)` and `p ∩= d - ρ (c, s)` on the horizontal axes.
//!
//! # Soundness
//!
//! The true (θ, β, r, p, d) satisfy the equation; θ, β, r lie in their
//! intervals, so the true ρ, c, s lie in the computed enclosures
//! (outward-rounded operations, sound `sin`/`cos`), and the true d and p in
//! the right-hand sides.
//!
//! # Complexity
//!
//! O(1). Reference: Jaulin, "A nonlinear set-membership approach for the
//! localization and map building of an underwater robot", IEEE T-RO 2009.

use crate::interval::Interval;

/// Contracts the horizontal axes of `p` and `d` (2 or 3 axes each) under the
/// bearing constraint. Returns `false` when a domain became empty.
pub fn contract_bearing(
    p: &mut [Interval],
    d: &mut [Interval],
    heading: Interval,
    bearing: Interval,
    range: Interval,
) -> bool {
    let phi = heading + bearing;
    contract_bearing_trig(p, d, phi.cos(), phi.sin(), range)
}

/// [`contract_bearing`] given c = cos(θ + β) and s = sin(θ + β) (the same
/// bits as the enclosures it computes): a caller that contracts one
/// detection many times (a shape against every box of a paving) computes
/// them once.
pub fn contract_bearing_trig(
    p: &mut [Interval],
    d: &mut [Interval],
    cos_phi: Interval,
    sin_phi: Interval,
    range: Interval,
) -> bool {
    let r = range.intersect(Interval::new(0.0, f64::INFINITY));
    let rho = if p.len() >= 3 {
        (r.sqr() - (d[2] - p[2]).sqr()).sqrt()
    } else {
        r
    };
    if rho.is_empty() {
        return false;
    }
    let dx = rho * cos_phi;
    let dy = rho * sin_phi;
    d[0] = d[0].intersect(p[0] + dx);
    d[1] = d[1].intersect(p[1] + dy);
    p[0] = p[0].intersect(d[0] - dx);
    p[1] = p[1].intersect(d[1] - dy);
    !(d[0].is_empty() || d[1].is_empty() || p[0].is_empty() || p[1].is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn abeam_landmark_lies_to_the_left() {
        // Heading east (0), bearing +pi/2 (port side), range 10: the landmark
        // is 10 m north of the robot.
        let mut p = [Interval::point(0.0), Interval::point(0.0)];
        let mut d = [Interval::ENTIRE, Interval::ENTIRE];
        let half_pi = Interval::point(std::f64::consts::FRAC_PI_2);
        assert!(contract_bearing(
            &mut p,
            &mut d,
            Interval::ZERO,
            half_pi,
            Interval::point(10.0)
        ));
        // cos(fl(pi/2)) = 6.1e-17: d_x is within 1e-9 of 0.
        assert!(d[0].lo() > -1e-9 && d[0].hi() < 1e-9);
        assert!(d[1].contains(10.0) && d[1].width() < 1e-9);
    }
}
