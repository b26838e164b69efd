//! `Arrival`: one time stamp of a pulse, with the pulse's emission time as
//! a variable.
//!
//! # Constraint
//!
//! `|x - r| = c (t - tau - b)` for the emitter position x (3-D), the
//! emission time tau, a receiver position r in the receiver's box, c in the
//! propagation speed, t in the time stamp's interval and b in the
//! receiver's clock bias: a distance constraint whose radius is
//! `rho = c (t - tau - b)`.
//!
//! # Math
//!
//! Forward: `d = t - tau - b`, `d ∩= [0, +inf)` (a distance is >= 0 and
//! c > 0), `rho = c d`; then the distance contractor
//! ([`crate::contractors::distance::contract_distance`], HC4Revise on
//! `Σ (x_i - r_i)^2 = rho^2`) contracts x, a copy of r and rho. Backward:
//! `d ∩= rho / c`, `tau ∩= t - b - d`. With tau unbounded and x in a
//! bounded box the first arrival bounds tau; every other arrival of the
//! pulse then contracts x: the difference of two arrivals is a hyperbolic
//! shell, which the shared tau carries.
//!
//! # Soundness
//!
//! Each step is the interval projection of one primitive equation computed
//! with outward-rounded operations ([`Interval`]), so a point (x, tau, r, c,
//! t, b) satisfying the constraint stays in every projection; the receiver's
//! box, c, t and b are inputs and are only read (contracted copies are
//! dropped), so nothing outside the pulse is narrowed.
//!
//! # Complexity
//!
//! O(1): about 30 interval operations.

use crate::contractors::distance::contract_distance;
use crate::interval::Interval;

/// The variables of one pulse: its emitter's position and emission time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulseVars {
    /// Emitter position (x east, y north, z up).
    pub x: [Interval; 3],
    /// Emission time.
    pub tau: Interval,
}

impl PulseVars {
    /// Whether a domain is empty.
    pub fn is_empty(&self) -> bool {
        self.tau.is_empty() || self.x.iter().any(|a| a.is_empty())
    }

    /// The hull of two states.
    pub fn hull(&self, o: &PulseVars) -> PulseVars {
        PulseVars {
            x: [
                self.x[0].hull(o.x[0]),
                self.x[1].hull(o.x[1]),
                self.x[2].hull(o.x[2]),
            ],
            tau: self.tau.hull(o.tau),
        }
    }
}

/// The data of one arrival: receiver box, clock bias, time stamp, speed.
#[derive(Debug, Clone, Copy)]
pub struct ArrivalData<'a> {
    /// The receiver's position box (3 axes).
    pub receiver: &'a [Interval],
    /// Its clock bias.
    pub bias: Interval,
    /// The time stamp.
    pub time: Interval,
    /// The propagation speed (lower bound > 0).
    pub speed: Interval,
}

/// Contracts `v` under the arrival constraint. Returns `false` when a
/// domain became empty (the arrival cannot hold within `v`).
pub fn contract_arrival(v: &mut PulseVars, a: &ArrivalData) -> bool {
    let nonneg = Interval::new(0.0, f64::INFINITY);
    let mut d = (a.time - v.tau - a.bias).intersect(nonneg);
    if d.is_empty() {
        return false;
    }
    let mut rho = a.speed * d;
    let mut r = [a.receiver[0], a.receiver[1], a.receiver[2]];
    if !contract_distance(&mut v.x, &mut r, &mut rho) {
        return false;
    }
    d = d.intersect(rho / a.speed);
    if d.is_empty() {
        return false;
    }
    v.tau = v.tau.intersect(a.time - a.bias - d);
    !v.tau.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_arrival_bounds_the_emission_time() {
        let c = Interval::point(300.0);
        let r = [
            Interval::point(0.0),
            Interval::point(0.0),
            Interval::point(0.0),
        ];
        let mut v = PulseVars {
            x: [
                Interval::new(300.0, 600.0),
                Interval::point(0.0),
                Interval::point(0.0),
            ],
            tau: Interval::ENTIRE,
        };
        let a = ArrivalData {
            receiver: &r,
            bias: Interval::ZERO,
            time: Interval::point(10.0),
            speed: c,
        };
        assert!(contract_arrival(&mut v, &a));
        // distance 300..600 at c = 300: travel 1..2 s, tau in [8, 9].
        assert!(v.tau.lo() > 7.99 && v.tau.hi() < 9.01, "{:?}", v.tau);
        assert!(v.tau.contains(8.0) && v.tau.contains(9.0));
    }

    #[test]
    fn an_arrival_before_the_emission_is_empty() {
        let r = [Interval::point(0.0); 3];
        let mut v = PulseVars {
            x: [Interval::point(1.0); 3],
            tau: Interval::new(5.0, 6.0),
        };
        let a = ArrivalData {
            receiver: &r,
            bias: Interval::ZERO,
            time: Interval::point(4.0),
            speed: Interval::point(1.0),
        };
        assert!(!contract_arrival(&mut v, &a));
    }
}
