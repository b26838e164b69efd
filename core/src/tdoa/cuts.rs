//! Altitude and region cuts of a pulse's emitter position.
//!
//! # Constraint
//!
//! `x_3 in altitude` (a barometric report, a known ground height),
//! `x in region` (the pulse's own region and the problem's
//! `emitter_region`) and `|x - p| in range` for a point p in a box
//! (`distance_from`: an altitude on a curved Earth, p its centre).
//!
//! # Math
//!
//! Intersections of the position's axes with the given intervals; the
//! distance cut is [`crate::contractors::distance::contract_distance`]
//! (HC4Revise) on copies of p and the range.
//!
//! # Soundness
//!
//! An intersection removes only points outside the stated sets, which no
//! solution has (no arithmetic, no rounding); the distance contractor is
//! outward rounded (its own proof).
//!
//! # Complexity
//!
//! O(1).

use crate::contractors::distance::contract_distance;
use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// Intersects `x` with `altitude` (on z) and with each region given.
/// Returns `false` when an axis became empty.
pub fn cut(
    x: &mut [Interval; 3],
    altitude: Option<Interval>,
    regions: &[Option<&IntervalBox>],
) -> bool {
    if let Some(a) = altitude {
        x[2] = x[2].intersect(a);
    }
    for r in regions.iter().flatten() {
        for (xi, ri) in x.iter_mut().zip(r.axes()) {
            *xi = xi.intersect(*ri);
        }
    }
    x.iter().all(|a| !a.is_empty())
}

/// `|x - p| in range` for p in `point` (copies of p and the range are
/// contracted and dropped). Returns `false` when it cannot hold.
pub fn cut_distance(x: &mut [Interval; 3], point: &IntervalBox, range: Interval) -> bool {
    let mut p = [point.axes()[0], point.axes()[1], point.axes()[2]];
    let mut r = range;
    contract_distance(x, &mut p, &mut r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_intersect_and_detect_emptiness() {
        let mut x = [Interval::ENTIRE; 3];
        let r = IntervalBox::new(&[Interval::new(0.0, 1.0); 3]);
        assert!(cut(
            &mut x,
            Some(Interval::new(0.5, 2.0)),
            &[Some(&r), None]
        ));
        assert_eq!(x[2], Interval::new(0.5, 1.0));
        assert!(!cut(&mut x, Some(Interval::new(3.0, 4.0)), &[]));
    }
}
