//! Landmark regions as pavings: the landmark of a proved group lies in the
//! intersection of its members' shapes (the paper's closing remark: "the
//! intersection of several spheres"), kept as a bounded list of boxes
//! (docs/design.md, "Detection shapes").
//!
//! # Constraint
//!
//! For a group G (detections proved to see one landmark L):
//! `L ∈ ∩_{j ∈ G} A(j)`, with A(j) the detection shapes of [`super::shape`].
//!
//! # Math
//!
//! A [`Paving`] is a finite set of boxes whose union holds L. It starts as
//! one box (the group's common detection box) and is refined two ways:
//! - [`Paving::cut`] by a shape A: every box B becomes the d-part of
//!   `A.contract_piece(B)` (a box holding A ∩ B), or is dropped when that is
//!   proved empty;
//! - [`Paving::refine`]: the widest boxes are bisected at their midpoints
//!   (while the count stays within a bound and boxes are wider than a
//!   resolution), and each half is cut by the given shapes.
//!
//! # Soundness
//!
//! The union of the boxes holds L before and after each step: a cut keeps a
//! superset of A ∩ B for every box B (and L ∈ A), a bisection replaces a
//! box by two halves covering it. Boxes never grow (contractions only
//! shrink), so boxes that were disjoint stay disjoint.
//!
//! # Complexity
//!
//! A cut is O(m d) for m boxes; a refinement O(m_new · s · d) for s shapes.
//! Both bounded by the box count limit.

use super::shape::{bisect, DetectionShape, MAX_DIM};
use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// A union of boxes holding a landmark (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Paving {
    dim: usize,
    boxes: Vec<IntervalBox>,
    /// The hull of `boxes`, kept by every method that changes them.
    hull: IntervalBox,
}

impl Paving {
    /// The paving of one box (empty when the box is).
    pub fn from_box(b: &IntervalBox) -> Paving {
        let mut p = Paving {
            dim: b.dim(),
            boxes: if b.is_empty() {
                Vec::new()
            } else {
                vec![b.clone()]
            },
            hull: IntervalBox::empty(b.dim()),
        };
        p.rehull();
        p
    }

    /// A paving from boxes (empty ones are dropped).
    pub fn from_boxes(dim: usize, boxes: Vec<IntervalBox>) -> Paving {
        let mut p = Paving {
            dim,
            boxes: boxes.into_iter().filter(|b| !b.is_empty()).collect(),
            hull: IntervalBox::empty(dim),
        };
        p.rehull();
        p
    }

    fn rehull(&mut self) {
        let mut h = IntervalBox::empty(self.dim);
        for b in &self.boxes {
            h = h.hull(b);
        }
        self.hull = h;
    }

    /// Number of axes.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The boxes.
    pub fn boxes(&self) -> &[IntervalBox] {
        &self.boxes
    }

    /// Whether no box is left (the landmark has no possible position: the
    /// group is infeasible).
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// The hull of the boxes (the empty box when there are none).
    pub fn hull(&self) -> IntervalBox {
        self.hull.clone()
    }

    /// The hull, borrowed. O(1).
    pub fn hull_ref(&self) -> &IntervalBox {
        &self.hull
    }

    /// Widest box's diameter (0 when empty).
    pub fn resolution(&self) -> f64 {
        self.boxes.iter().map(|b| b.diameter()).fold(0.0, f64::max)
    }

    /// Cuts every box by the shape (module doc). Returns whether a box
    /// changed or was dropped. O(m d).
    pub fn cut<S: DetectionShape>(&mut self, shape: &S) -> bool {
        let dim = self.dim;
        // Every point of the hull allowed: every box's contraction gives
        // it back (equal bounds, so nothing is written below).
        if !self.boxes.is_empty() && shape.keeps(self.hull.axes()) {
            return false;
        }
        let mut changed = false;
        self.boxes.retain_mut(|b| {
            // A box every point of which the shape allows is left as the
            // contraction would leave it (`keeps`: the same bits).
            if shape.keeps(b.axes()) {
                return true;
            }
            match shape.contract_piece(b.axes()) {
                None => {
                    changed = true;
                    false
                }
                Some(piece) => {
                    let d = S::position(&piece);
                    for a in 0..dim {
                        if d[a] != b[a] {
                            changed = true;
                            b[a] = d[a];
                        }
                    }
                    true
                }
            }
        });
        if changed {
            self.rehull();
        }
        changed
    }

    /// Intersects every box with `b`, dropping those that miss it. Returns
    /// whether anything changed.
    pub fn intersect_box(&mut self, b: &IntervalBox) -> bool {
        let mut changed = false;
        self.boxes.retain_mut(|x| {
            changed |= x.intersect_with(b);
            !x.is_empty()
        });
        if changed {
            self.rehull();
        }
        changed
    }

    /// The paving of the points in both pavings: the pairwise intersections
    /// of their boxes (at most `max_boxes`, else `self` is only intersected
    /// with `other`'s hull — a superset, so still sound).
    pub fn intersect(&mut self, other: &Paving, max_boxes: usize) {
        let mut out = Vec::new();
        for a in &self.boxes {
            for b in &other.boxes {
                if a.meets(b) {
                    out.push(a.intersect(b));
                    if out.len() > max_boxes {
                        let h = other.hull();
                        self.intersect_box(&h);
                        return;
                    }
                }
            }
        }
        out.retain(|b| !b.is_empty());
        self.boxes = out;
        self.rehull();
    }

    /// Bisects boxes wider than `resolution`, widest first, while the count
    /// stays within `max_boxes`; every half is cut by each of `shapes`
    /// (dropped when one excludes it). Returns whether anything changed.
    /// O(new boxes · shapes · d).
    pub fn refine<S: DetectionShape>(
        &mut self,
        shapes: &[&S],
        resolution: f64,
        max_boxes: usize,
    ) -> bool {
        let changed = self.split(shapes, resolution, max_boxes);
        if changed {
            self.rehull();
        }
        changed
    }

    fn split<S: DetectionShape>(
        &mut self,
        shapes: &[&S],
        resolution: f64,
        max_boxes: usize,
    ) -> bool {
        let mut changed = false;
        // Each pass splits at least one box; passes are capped so that an
        // unbounded box (whose halves stay unbounded) cannot loop forever.
        for _ in 0..64 {
            // The widest boxes first; stop when none is above the
            // resolution or the count would pass the bound.
            let mut order: Vec<(f64, usize)> = self
                .boxes
                .iter()
                .enumerate()
                .map(|(i, b)| (b.diameter(), i))
                .filter(|&(w, _)| w > resolution)
                .collect();
            if order.is_empty() {
                return changed;
            }
            let room = max_boxes.saturating_sub(self.boxes.len());
            if room == 0 {
                return changed;
            }
            crate::sort::sort_by(&mut order, |a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            order.truncate(room);
            let mut split = vec![false; self.boxes.len()];
            for &(_, i) in &order {
                split[i] = true;
            }
            let mut next = Vec::with_capacity(self.boxes.len() + order.len());
            for (i, b) in self.boxes.drain(..).enumerate() {
                if !split[i] {
                    next.push(b);
                    continue;
                }
                changed = true;
                let (l, r) = bisect(&b);
                for mut half in [l, r] {
                    if cut_all(&mut half, shapes) {
                        next.push(half);
                    }
                }
            }
            self.boxes = next;
        }
        changed
    }

    /// Whether the shape may meet the paving (`false` proves it misses
    /// every box). O(m d).
    pub fn meets_shape<S: DetectionShape>(&self, shape: &S) -> bool {
        let h = &self.hull;
        if h.is_empty() || !shape.meets_box(h.axes()) {
            return false;
        }
        self.boxes.iter().any(|b| shape.meets_box(b.axes()))
    }

    /// Whether the two pavings may share a point (`false` proves they do
    /// not). O(m m').
    pub fn meets(&self, other: &Paving) -> bool {
        if !self.hull.meets(&other.hull) {
            return false;
        }
        self.boxes
            .iter()
            .any(|a| other.boxes.iter().any(|b| a.meets(b)))
    }

    /// Whether `p` lies in some box.
    pub fn contains(&self, p: &[f64]) -> bool {
        self.boxes.iter().any(|b| b.contains(p))
    }
}

/// Cuts `b` by every shape; `false` when one excludes it.
fn cut_all<S: DetectionShape>(b: &mut IntervalBox, shapes: &[&S]) -> bool {
    let dim = b.dim();
    for s in shapes {
        // `keeps`: the contraction would leave `b` as it is, bit for bit.
        if s.keeps(b.axes()) {
            continue;
        }
        match s.contract_piece(b.axes()) {
            None => return false,
            Some(piece) => {
                let axes: [Interval; MAX_DIM] = S::position(&piece);
                b.axes_mut().copy_from_slice(&axes[..dim]);
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::shape::Shape;

    fn annulus(cx: f64, cy: f64, r0: f64, r1: f64) -> Shape {
        Shape::new(
            IntervalBox::point(&[cx, cy]),
            Interval::new(r0, r1),
            None,
            IntervalBox::new(&[Interval::new(-50.0, 50.0), Interval::new(-50.0, 50.0)]),
        )
    }

    #[test]
    fn two_circles_leave_two_small_blobs() {
        // Circles of radius 5 around (0, 0) and (6, 0) cross at (3, ±4).
        let (a, b) = (annulus(0.0, 0.0, 4.9, 5.1), annulus(6.0, 0.0, 4.9, 5.1));
        let mut p = Paving::from_box(&a.hull());
        p.cut(&b);
        p.refine(&[&a, &b], 0.05, 4096);
        assert!(p.contains(&[3.0, 4.0]) && p.contains(&[3.0, -4.0]));
        let h = p.hull();
        assert!(h[0].lo() > 2.0 && h[0].hi() < 4.0, "{h:?}");
        assert!(!p.contains(&[3.0, 0.0]));
        assert!(p
            .boxes()
            .iter()
            .all(|b| b[1].lo() > 3.0 || b[1].hi() < -3.0));
    }
}
