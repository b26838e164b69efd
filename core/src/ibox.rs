//! Boxes: Cartesian products of intervals, one per axis.

use crate::interval::Interval;
use smallvec::SmallVec;
use std::fmt;

/// A box `x_0 × x_1 × ... × x_{d-1}` of any dimension `d`; up to 3 axes are
/// stored inline (no allocation), which covers 2-D and 3-D missions.
///
/// A box is empty when any of its axes is; [`IntervalBox::set_empty`] makes
/// all axes empty so that emptiness reads the same on every axis.
#[derive(Clone, PartialEq, Default)]
pub struct IntervalBox {
    axes: SmallVec<[Interval; 3]>,
}

impl IntervalBox {
    /// A box from its axes.
    pub fn new(axes: &[Interval]) -> IntervalBox {
        IntervalBox {
            axes: SmallVec::from_slice(axes),
        }
    }

    /// The unbounded box of dimension `dim`.
    pub fn entire(dim: usize) -> IntervalBox {
        IntervalBox {
            axes: SmallVec::from_elem(Interval::ENTIRE, dim),
        }
    }

    /// The empty box of dimension `dim`.
    pub fn empty(dim: usize) -> IntervalBox {
        IntervalBox {
            axes: SmallVec::from_elem(Interval::EMPTY, dim),
        }
    }

    /// The degenerate box holding one point.
    pub fn point(p: &[f64]) -> IntervalBox {
        IntervalBox {
            axes: p.iter().map(|&x| Interval::point(x)).collect(),
        }
    }

    /// Number of axes.
    #[inline]
    pub fn dim(&self) -> usize {
        self.axes.len()
    }

    /// The axes as a slice.
    #[inline]
    pub fn axes(&self) -> &[Interval] {
        &self.axes
    }

    /// The axes, mutable.
    #[inline]
    pub fn axes_mut(&mut self) -> &mut [Interval] {
        &mut self.axes
    }

    /// Whether the box holds no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.axes.iter().any(|a| a.is_empty())
    }

    /// Makes every axis empty.
    pub fn set_empty(&mut self) {
        for a in self.axes.iter_mut() {
            *a = Interval::EMPTY;
        }
    }

    /// Whether the point lies in the box.
    pub fn contains(&self, p: &[f64]) -> bool {
        p.len() == self.dim() && self.axes.iter().zip(p).all(|(a, &x)| a.contains(x))
    }

    /// Whether `self` is a subset of `other`.
    pub fn is_subset(&self, other: &IntervalBox) -> bool {
        self.is_empty()
            || (self.dim() == other.dim()
                && self
                    .axes
                    .iter()
                    .zip(&other.axes)
                    .all(|(a, b)| a.is_subset(*b)))
    }

    /// Whether the two boxes share a point.
    pub fn meets(&self, other: &IntervalBox) -> bool {
        self.axes.iter().zip(&other.axes).all(|(a, b)| a.meets(*b))
    }

    /// Intersection (empty on every axis when empty). Tightness: exact.
    pub fn intersect(&self, other: &IntervalBox) -> IntervalBox {
        let mut r = self.clone();
        r.intersect_with(other);
        r
    }

    /// Intersects in place; returns whether any bound moved.
    pub fn intersect_with(&mut self, other: &IntervalBox) -> bool {
        let mut changed = false;
        for (a, b) in self.axes.iter_mut().zip(&other.axes) {
            let c = a.intersect(*b);
            if c != *a {
                changed = true;
                *a = c;
            }
        }
        if changed && self.is_empty() {
            self.set_empty();
        }
        changed
    }

    /// Hull of the union. Tightness: exact.
    pub fn hull(&self, other: &IntervalBox) -> IntervalBox {
        if self.is_empty() {
            return other.clone();
        }
        if other.is_empty() {
            return self.clone();
        }
        IntervalBox {
            axes: self
                .axes
                .iter()
                .zip(&other.axes)
                .map(|(a, b)| a.hull(*b))
                .collect(),
        }
    }

    /// Diameter: the largest width over the axes (`+inf` when unbounded,
    /// 0 when empty). Rounded up.
    pub fn diameter(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        self.axes.iter().map(|a| a.width()).fold(0.0, f64::max)
    }

    /// Volume: the product of the widths, rounded up (0 when empty).
    pub fn volume(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        self.axes
            .iter()
            .fold(1.0f64, |v, a| (v * a.width()).next_up().max(0.0))
    }

    /// A point near the middle of the box (see [`Interval::mid`]).
    pub fn mid(&self) -> SmallVec<[f64; 3]> {
        self.axes.iter().map(|a| a.mid()).collect()
    }
}

impl std::ops::Index<usize> for IntervalBox {
    type Output = Interval;
    fn index(&self, i: usize) -> &Interval {
        &self.axes[i]
    }
}

impl std::ops::IndexMut<usize> for IntervalBox {
    fn index_mut(&mut self, i: usize) -> &mut Interval {
        &mut self.axes[i]
    }
}

impl fmt::Debug for IntervalBox {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.axes.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersect_and_hull() {
        let a = IntervalBox::new(&[Interval::new(0.0, 2.0), Interval::new(0.0, 2.0)]);
        let b = IntervalBox::new(&[Interval::new(1.0, 3.0), Interval::new(3.0, 4.0)]);
        assert!(a.intersect(&b).is_empty());
        assert!(!a.meets(&b));
        let h = a.hull(&b);
        assert_eq!(h[0], Interval::new(0.0, 3.0));
        assert_eq!(h[1], Interval::new(0.0, 4.0));
        assert_eq!(h.diameter(), 4.0);
    }
}
