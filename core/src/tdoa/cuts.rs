//! Altitude and region cuts of a pulse's emitter position.
//!
//! # Constraint
//!
//! `x_3 in altitude` (a barometric report, a known ground height) and
//! `x in region` (the pulse's own region and the problem's
//! `emitter_region`).
//!
//! # Math
//!
//! Intersections of the position's axes with the given intervals.
//!
//! # Soundness
//!
//! An intersection removes only points outside the stated sets, which no
//! solution has; no arithmetic, hence no rounding.
//!
//! # Complexity
//!
//! O(1).

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
