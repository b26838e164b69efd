//! Branch contraction: a detection whose landmark is one of known regions
//! (docs/design.md, "Detection shapes").
//!
//! # Constraint
//!
//! Detection j (robot position p(t), landmark d(j), its range and bearing
//! constraints) with `d(j) ∈ R(1) ∪ ... ∪ R(m)`, each R(i) a [`Paving`].
//! It holds for the regions of n pairwise-distinct landmarks when at most n
//! landmarks exist (every detection sees one of them), and for the region
//! of the group of j alone.
//!
//! # Math
//!
//! For each region i and each box B of R(i), the branch "d(j) ∈ B":
//! copies of p(t) and B ∩ d(j) contracted by the detection's constraints
//! ([`Shape::contract_piece`]; any [`DetectionShape`]'s in
//! [`branch_pieces`]). The new p(t) and d(j) are the hulls of the
//! surviving pieces. A region none of whose boxes survives cannot hold
//! d(j); when exactly one region survives, detection j sees its landmark.
//!
//! # Soundness
//!
//! The true (p(t), d(j)) satisfy the constraints and d(j) lies in some box
//! B of some R(i), so it lies in that branch's piece, hence in the hull. The
//! true landmark's region survives, so a single survivor is the true one.
//!
//! # Complexity
//!
//! O(d) for each region's hull test, O(m_i d) for each region whose hull
//! the shape meets (m_i boxes).

use super::region::Paving;
use super::shape::{DetectionShape, Shape};
use crate::ibox::IntervalBox;

/// What the branches left.
#[derive(Debug, Clone, PartialEq)]
pub struct Branches {
    /// Hull of the surviving pieces' robot positions (empty when none).
    pub p: IntervalBox,
    /// Hull of the surviving pieces' landmark positions (empty when none).
    pub d: IntervalBox,
    /// Indices (into `regions`) of the regions that may hold the landmark.
    pub surviving: Vec<usize>,
}

/// Contracts the detection of `shape` (its centre is p(t), its cut d(j))
/// under "its landmark is in one of `regions`" (module doc).
pub fn branch(shape: &Shape, regions: &[&Paving]) -> Branches {
    let dim = shape.dim();
    let (hull, surviving) = branch_pieces(shape, regions);
    match hull {
        Some(piece) => Branches {
            p: IntervalBox::new(&piece.p[..dim]),
            d: IntervalBox::new(&piece.d[..dim]),
            surviving,
        },
        None => Branches {
            p: IntervalBox::empty(dim),
            d: IntervalBox::empty(dim),
            surviving,
        },
    }
}

/// The branch contraction of any [`DetectionShape`] under "its position
/// is in one of `regions`" (module doc): the hull of the surviving pieces
/// (`None` when none survives: the constraint is infeasible) and the
/// indices of the regions that may hold the position.
pub fn branch_pieces<S: DetectionShape>(
    shape: &S,
    regions: &[&Paving],
) -> (Option<S::Piece>, Vec<usize>) {
    let mut hull: Option<S::Piece> = None;
    let mut surviving = Vec::new();
    for (i, r) in regions.iter().enumerate() {
        let h = r.hull_ref();
        if h.is_empty() || !shape.meets_box(h.axes()) {
            continue;
        }
        let mut hit = false;
        for b in r.boxes() {
            if let Some(piece) = shape.contract_piece(b.axes()) {
                hit = true;
                hull = Some(match hull {
                    None => piece,
                    Some(acc) => S::hull_pieces(&acc, &piece),
                });
            }
        }
        if hit {
            surviving.push(i);
        }
    }
    (hull, surviving)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;

    #[test]
    fn a_range_that_fits_one_region_picks_it_and_pins_the_robot() {
        // Landmarks near (10, 0) and (-10, 0). A robot in [-2, 2]^2
        // measuring 9.9..10.1 may see either. A robot in [1.5, 2] x [-2, 2]
        // measuring 11.4..12.1 is 7.9..8.9 from the first: only the second
        // fits. A robot in [-2, 2]^2 measuring 11.9..12.1 is pinned (with the
        // landmarks' 0.1 m boxes) to
        // x <= -1.61 (first landmark) or x >= 1.61 (second).
        let regions = [
            Paving::from_box(&IntervalBox::new(&[
                Interval::new(9.9, 10.1),
                Interval::new(-0.1, 0.1),
            ])),
            Paving::from_box(&IntervalBox::new(&[
                Interval::new(-10.1, -9.9),
                Interval::new(-0.1, 0.1),
            ])),
        ];
        let refs: Vec<&Paving> = regions.iter().collect();
        let p = IntervalBox::new(&[Interval::new(-2.0, 2.0), Interval::new(-2.0, 2.0)]);
        let s = Shape::new(
            p.clone(),
            Interval::new(9.9, 10.1),
            None,
            IntervalBox::entire(2),
        );
        assert_eq!(branch(&s, &refs).surviving, vec![0, 1]);
        let mut q = p.clone();
        q[0] = Interval::new(1.5, 2.0);
        let s = Shape::new(q, Interval::new(11.4, 12.1), None, IntervalBox::entire(2));
        let b = branch(&s, &refs);
        assert_eq!(b.surviving, vec![1]);
        assert!(b.d.is_subset(&regions[1].hull()));
        let s = Shape::new(
            p.clone(),
            Interval::new(11.9, 12.1),
            None,
            IntervalBox::entire(2),
        );
        let b = branch(&s, &refs);
        assert_eq!(b.surviving, vec![0, 1]);
        // Each branch pins x to one end; the hull keeps both ends.
        assert!(b.p[0].lo() == -2.0 && b.p[0].hi() == 2.0);
        let one = branch(&s, &refs[..1]);
        assert!(one.p[0].hi() < -1.5, "{:?}", one.p);
    }
}
