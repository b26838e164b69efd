//! Angles on the real line: the direction arc of a box and the contraction
//! of a heading to the copies of an arc.
//!
//! # Constraints
//!
//! - [`box_angle`]: for a box V = X × Y not containing the origin, an
//!   interval A with `atan2(v) ∈ A + 2πZ` for every v ∈ V (the angle of v
//!   taken as any real number congruent to it).
//! - [`contract_periodic`]: `θ ∈ T` and `θ ∈ A + 2πZ` (θ congruent modulo
//!   2π to a point of A): T is contracted to the hull of T ∩ (A + 2πZ).
//!   This is how a heading that is a real number (not taken modulo 2π) is
//!   contracted by a direction, which is only known modulo 2π.
//!
//! # Math
//!
//! The angle of a point is continuous on a half-plane that excludes the
//! origin, with no critical point (its level sets are rays from the
//! origin), so its extremes over a box inside such a half-plane are at the
//! box's corners. With the half-plane chosen by the box's position
//! (x > 0: atan2(y, x) ∈ (-π/2, π/2); x < 0: π + atan2(-y, -x); y > 0:
//! atan2(y, x) ∈ (0, π); y < 0: -atan2(-y, x)), the branch cut of atan2
//! never crosses the box and A is the hull of the four corner angles
//! (infinite corners included: atan2 gives the limit angle), widened.
//!
//! For the periodic contraction, the copies `A + 2πk` are ordered by k
//! (A's width is below 2π, else nothing is contracted); the first copy
//! that is not wholly below T gives the new lower bound
//! `max(T.lo, (A + 2πk).lo)`, the last copy not wholly above T the new
//! upper bound; no copy in between: T is emptied.
//!
//! # Soundness
//!
//! libm's atan2 is within one ulp (musl's); each bound of A is moved three
//! ulps outwards, and π is added as the interval [fl(π), succ(fl(π))]
//! (fl(π) < π < succ(fl(π))). `A + 2πk` is computed in interval arithmetic
//! (k exact as f64 below 2^53, 2π enclosed), so each computed copy holds
//! the exact one; a copy is skipped only when its enclosure lies wholly
//! outside T, and the search for the first copy starts from a k checked to
//! be wholly below T (else nothing is contracted), so no copy that meets T
//! is ever skipped. Bounds beyond 1e12 in magnitude are not contracted
//! (the float grid of k·2π there is too coarse to be worth it).
//!
//! # Complexity
//!
//! O(1): four atan2 calls; at most a few copies tried per bound.

use crate::contractors::motion_chain::shrinkage;
use crate::interval::{pred, succ, Interval};

/// An enclosure of π: [fl(π), succ(fl(π))] (fl(π) is below π).
pub const PI: Interval = Interval::new_unchecked(std::f64::consts::PI, 3.141_592_653_589_793_6);

/// An enclosure of 2π (the doubling of [`PI`]'s bounds is exact).
pub const TWO_PI: Interval =
    Interval::new_unchecked(2.0 * std::f64::consts::PI, 2.0 * 3.141_592_653_589_793_6);

/// Largest bound magnitude [`contract_periodic`] contracts.
pub const PERIODIC_LIMIT: f64 = 1e12;

fn down3(x: f64) -> f64 {
    pred(pred(pred(x)))
}

fn up3(x: f64) -> f64 {
    succ(succ(succ(x)))
}

/// The hull of atan2 over the four corners of `y × x` (argument order of
/// atan2), widened three ulps per bound; the caller guarantees the box lies
/// in a half-plane that the branch cut of atan2 does not cross.
fn corner_hull(y: Interval, x: Interval) -> Interval {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for a in [y.lo(), y.hi()] {
        for b in [x.lo(), x.hi()] {
            let t = libm::atan2(a, b);
            lo = lo.min(t);
            hi = hi.max(t);
        }
    }
    Interval::new(down3(lo), up3(hi))
}

/// The direction arc of the box `x × y`: an interval A such that the angle
/// of every point of the box is in `A + 2πZ`; `None` when the box is empty
/// or holds the origin (every direction). The width of A is at most π plus
/// a few ulps. See the module doc.
pub fn box_angle(x: Interval, y: Interval) -> Option<Interval> {
    if x.is_empty() || y.is_empty() {
        return None;
    }
    if x.lo() > 0.0 {
        Some(corner_hull(y, x))
    } else if x.hi() < 0.0 {
        Some(PI + corner_hull(-y, -x))
    } else if y.lo() > 0.0 {
        Some(corner_hull(y, x))
    } else if y.hi() < 0.0 {
        Some(-corner_hull(-y, x))
    } else {
        None
    }
}

/// How far the bounds of a heading moved from `old` to `new`, for the
/// fixpoint's "still moving" tests: [`shrinkage`], except that a move
/// counts as 0 when one bound is the same in both and beyond
/// [`PERIODIC_LIMIT`] in magnitude (infinite included) while the other
/// bound is within it in both (a bound coming in from beyond the limit
/// still counts).
///
/// Why: the bearing constraints reach a heading through
/// [`contract_periodic`], which keeps a bound beyond the limit. On such a
/// heading, `[-inf, H]` or `[L, 1e300]`, two bearings that disagree modulo
/// 2π move the near bound by about a turn per round, each to the next
/// copy of its arc, without ever reaching a fixpoint: an inconsistent set
/// of detections (as the consensus over subsets tries) then ran
/// `max_rounds` rounds. The heading stays wider than a turn all along, so
/// a displacement's cos and sin and a bearing's direction computed from
/// it do not change. Not counting the move only stops the propagation
/// earlier, which is sound (the boxes stay enclosures); what may be lost
/// is a contraction that a far absolute heading bound would bring after
/// a number of rounds proportional to its distance in turns. O(1).
pub fn heading_moved(old: Interval, new: Interval) -> f64 {
    let far = |b: f64| b.abs() > PERIODIC_LIMIT;
    let creeping = !new.is_empty()
        && !old.is_empty()
        && ((old.lo() == new.lo() && far(old.lo()) && !far(old.hi()) && !far(new.hi()))
            || (old.hi() == new.hi() && far(old.hi()) && !far(old.lo()) && !far(new.lo())));
    if creeping {
        return 0.0;
    }
    shrinkage(old, new)
}

/// The hull of `t ∩ (arc + 2πZ)` (see the module doc): `t` unchanged when
/// `arc` is 2π wide or more, or when a bound of `t` is beyond 1e12 in
/// magnitude (that bound is kept); empty when no copy of `arc` meets `t`
/// (or when either is empty).
pub fn contract_periodic(t: Interval, arc: Interval) -> Interval {
    if t.is_empty() || arc.is_empty() {
        return Interval::EMPTY;
    }
    if !arc.is_bounded() || arc.width() >= TWO_PI.lo() || arc.mag() > PERIODIC_LIMIT {
        return t;
    }
    let copy = |k: f64| arc + TWO_PI.scale(k);
    let mut lo = t.lo();
    let mut hi = t.hi();
    if lo.is_finite() && lo.abs() <= PERIODIC_LIMIT {
        // k0: a copy surely below t (checked), then walk up.
        let k0 = ((lo - arc.hi()) / TWO_PI.lo()).floor() - 2.0;
        if copy(k0).hi() < lo {
            let mut k = k0 + 1.0;
            let mut found = false;
            for _ in 0..8 {
                let c = copy(k);
                if c.hi() >= lo {
                    lo = lo.max(c.lo());
                    found = true;
                    break;
                }
                k += 1.0;
            }
            if !found {
                lo = t.lo();
            }
        }
    }
    if hi.is_finite() && hi.abs() <= PERIODIC_LIMIT {
        let k0 = ((hi - arc.lo()) / TWO_PI.lo()).ceil() + 2.0;
        if copy(k0).lo() > hi {
            let mut k = k0 - 1.0;
            let mut found = false;
            for _ in 0..8 {
                let c = copy(k);
                if c.lo() <= hi {
                    hi = hi.min(c.hi());
                    found = true;
                    break;
                }
                k -= 1.0;
            }
            if !found {
                hi = t.hi();
            }
        }
    }
    Interval::new(lo, hi)
}

/// `t ∩ (box_angle(x, y) - offset + 2πZ)`: the heading contraction from "the
/// direction of the vector (x, y) is the heading plus an angle in
/// `offset`". `t` unchanged when the box holds the origin.
pub fn contract_heading(t: Interval, x: Interval, y: Interval, offset: Interval) -> Interval {
    match box_angle(x, y) {
        Some(a) => contract_periodic(t, a - offset),
        None => {
            if x.is_empty() || y.is_empty() {
                Interval::EMPTY
            } else {
                t
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heading_creeping_beside_a_far_bound_is_not_moving() {
        let inf = f64::INFINITY;
        let (a, b) = (Interval::new(-inf, -147.6), Interval::new(-inf, -149.5));
        assert_eq!(heading_moved(a, b), 0.0);
        let (a, b) = (
            Interval::new(125_629.0, 1e300),
            Interval::new(125_632.0, 1e300),
        );
        assert_eq!(heading_moved(a, b), 0.0);
        // A bound coming in from beyond the limit counts, as does any move
        // of a heading with both bounds near.
        assert_eq!(heading_moved(Interval::new(-inf, inf), b), inf);
        assert!(heading_moved(Interval::new(-1e300, 1e300), Interval::new(-1e300, 5.0)) > 1e299);
        assert_eq!(
            heading_moved(Interval::new(0.0, 7.0), Interval::new(0.5, 7.0)),
            0.5
        );
        assert_eq!(
            heading_moved(Interval::new(-inf, 3.0), Interval::new(-2.0, 3.0)),
            inf
        );
        // An emptied heading counts as moving (shrinkage: +inf).
        assert_eq!(
            heading_moved(Interval::new(-inf, 3.0), Interval::EMPTY),
            inf
        );
    }

    #[test]
    fn pi_encloses_pi() {
        assert!(PI.lo() < PI.hi() && PI.hi() == succ(std::f64::consts::PI));
        assert!(TWO_PI.lo() == 2.0 * std::f64::consts::PI);
    }

    #[test]
    fn quadrant_boxes() {
        let a = box_angle(Interval::new(1.0, 2.0), Interval::new(-1.0, 1.0)).unwrap();
        assert!(a.lo() < -0.78 && a.hi() > 0.78 && a.width() < 1.6);
        // Across the branch cut at -x: angles near pi, a narrow arc.
        let a = box_angle(Interval::new(-2.0, -1.0), Interval::new(-0.1, 0.1)).unwrap();
        assert!(a.contains(std::f64::consts::PI) && a.width() < 0.21);
        let a = box_angle(Interval::new(-1.0, 1.0), Interval::new(-2.0, -1.0)).unwrap();
        assert!(a.contains(-std::f64::consts::FRAC_PI_2));
        assert!(box_angle(Interval::new(-1.0, 1.0), Interval::new(-1.0, 1.0)).is_none());
        let a = box_angle(
            Interval::new(1.0, f64::INFINITY),
            Interval::new(1.0, f64::INFINITY),
        )
        .unwrap();
        assert!(a.lo() <= 0.0 && a.hi() >= std::f64::consts::FRAC_PI_2);
    }

    #[test]
    fn periodic_contraction_keeps_far_copies() {
        // Heading in [100, 110], direction in [0, 0.1] mod 2pi: copies at
        // 2pi*16 = 100.53 and 2pi*17 = 106.81.
        let t = contract_periodic(Interval::new(100.0, 110.0), Interval::new(0.0, 0.1));
        assert!(t.contains(16.0 * 2.0 * std::f64::consts::PI));
        assert!(t.contains(17.0 * 2.0 * std::f64::consts::PI + 0.1));
        assert!(t.lo() > 100.5 && t.hi() < 107.0);
        // No copy: empty.
        assert!(contract_periodic(Interval::new(1.0, 2.0), Interval::new(3.0, 4.0)).is_empty());
        // Unbounded t: only the finite bound moves.
        let t = contract_periodic(Interval::new(0.5, f64::INFINITY), Interval::new(0.0, 0.1));
        let tau = 2.0 * std::f64::consts::PI;
        assert!(t.hi() == f64::INFINITY && t.lo() > tau - 1e-9 && t.lo() < tau + 0.01);
    }
}
