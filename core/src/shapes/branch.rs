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
use super::shape::{DetectionShape, Piece, Shape, MAX_DIM};
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
    let (hull, surviving) = branch_pieces(shape, regions);
    branches(shape, hull, surviving)
}

/// The branch's boxes from its hull piece (empty boxes when no piece
/// survived) and the surviving regions.
pub(crate) fn branches(shape: &Shape, hull: Option<Piece>, surviving: Vec<usize>) -> Branches {
    let dim = shape.dim();
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
///
/// For shapes that can tell a piece the hull already holds
/// ([`DetectionShape::absorbs`]), each region's extreme boxes are
/// contracted first, so that the hull soon holds most other pieces, which
/// are then not contracted. The hull is the same set in any order, and
/// the same bits except where +0 and -0 meet: a hull with a zero bound is
/// made again in the regions' own order, every box contracted.
pub fn branch_pieces<S: DetectionShape>(
    shape: &S,
    regions: &[&Paving],
) -> (Option<S::Piece>, Vec<usize>) {
    if S::ABSORBS {
        let (hull, surviving) = extremes_first(shape, regions);
        if !hull.as_ref().is_some_and(|h| shape.zero_bound(h)) {
            return (hull, surviving);
        }
    }
    every_box(shape, regions)
}

/// [`branch_pieces`] contracting every box, in the regions' order.
pub(super) fn every_box<S: DetectionShape>(
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
                hull = Some(hull.map_or(piece, |acc| S::hull_pieces(&acc, &piece)));
            }
        }
        if hit {
            surviving.push(i);
        }
    }
    (hull, surviving)
}

/// [`branch_pieces`] with each region's extreme boxes first (the first box
/// with the least lower bound and with the greatest upper bound, on each
/// axis), then the others in order, those the hull absorbs skipped once
/// the region survives.
pub(super) fn extremes_first<S: DetectionShape>(
    shape: &S,
    regions: &[&Paving],
) -> (Option<S::Piece>, Vec<usize>) {
    let mut hull: Option<S::Piece> = None;
    let mut surviving = Vec::new();
    for (i, r) in regions.iter().enumerate() {
        let h = r.hull_ref();
        if h.is_empty() {
            continue;
        }
        // The piece of the region's hull holds the piece of every box.
        let Some(outer) = shape.contract_piece(h.axes()) else {
            continue;
        };
        let boxes = r.boxes();
        let first = extremes(boxes);
        let mut hit = false;
        let order = first
            .iter()
            .copied()
            .chain((0..boxes.len()).filter(|k| !first.contains(k)));
        for (n, k) in order.enumerate() {
            let b = boxes[k].axes();
            if hit
                && n >= first.len()
                && hull
                    .as_ref()
                    .is_some_and(|acc| shape.absorbs(acc, &outer, b))
            {
                continue;
            }
            if let Some(piece) = shape.contract_piece(b) {
                hit = true;
                hull = Some(hull.map_or(piece, |acc| S::hull_pieces(&acc, &piece)));
            }
        }
        if hit {
            surviving.push(i);
        }
    }
    (hull, surviving)
}

/// The indices of the first box with the least lower bound and of the
/// first with the greatest upper bound on each axis, without repeats, in
/// increasing order.
fn extremes(boxes: &[IntervalBox]) -> Vec<usize> {
    // Per axis: the least lower bound and its box, the greatest upper
    // bound and its box, in one pass over the boxes.
    let mut best = [(f64::INFINITY, 0, f64::NEG_INFINITY, 0); MAX_DIM];
    let dim = boxes.first().map_or(0, IntervalBox::dim);
    for (k, b) in boxes.iter().enumerate() {
        for (x, e) in b.axes().iter().zip(best.iter_mut()) {
            if x.lo() < e.0 {
                (e.0, e.1) = (x.lo(), k);
            }
            if x.hi() > e.2 {
                (e.2, e.3) = (x.hi(), k);
            }
        }
    }
    let mut out: Vec<usize> = best[..dim].iter().flat_map(|e| [e.1, e.3]).collect();
    crate::sort::sort_usize(&mut out);
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;
    use crate::rng::Rng;
    use crate::shapes::shape::Piece;

    fn bits(p: &Option<Piece>) -> Vec<u64> {
        p.iter()
            .flat_map(|p| p.p.iter().chain(&p.d))
            .flat_map(|x| [x.lo().to_bits(), x.hi().to_bits()])
            .collect()
    }

    /// A bound drawn among the awkward values (zeros of both signs,
    /// huge, infinite) or an ordinary one.
    fn bound(rng: &mut Rng, scale: f64) -> f64 {
        match rng.next_u64() % 10 {
            0 => 0.0,
            1 => -0.0,
            2 => f64::MAX * rng.sym(1.0),
            3 => f64::INFINITY,
            _ => rng.sym(scale),
        }
    }

    fn interval(rng: &mut Rng, scale: f64) -> Interval {
        let (a, b) = (bound(rng, scale), bound(rng, scale));
        let (a, b) = if rng.next_u64().is_multiple_of(2) {
            (a, b)
        } else {
            (-a, -b)
        };
        let i = Interval::new(a.min(b), a.max(b));
        if i.is_empty() {
            Interval::new(-scale, scale)
        } else {
            i
        }
    }

    /// Skipping the boxes whose piece the hull already holds gives the
    /// same bits as contracting them all: shapes with and without a
    /// bearing, 2-D and 3-D, regions of bisected boxes (so that many lie
    /// inside the hull), bounds of zero, huge and infinite values.
    #[test]
    fn absorbed_boxes_change_no_bit() {
        let mut rng = Rng::new(38);
        let mut skipped = 0usize;
        for case in 0..3000 {
            let dim = 2 + (case % 5 == 0) as usize;
            let scale = [1.0, 10.0, 1e6][case % 3];
            let axes = |rng: &mut Rng, w: f64| -> IntervalBox {
                let v: Vec<Interval> = (0..dim)
                    .map(|_| {
                        let c = rng.sym(scale);
                        Interval::new(c - w * rng.unit(), c + w * rng.unit())
                    })
                    .collect();
                IntervalBox::new(&v)
            };
            let centre = if case % 7 == 0 {
                IntervalBox::new(
                    &(0..dim)
                        .map(|_| interval(&mut rng, scale))
                        .collect::<Vec<_>>(),
                )
            } else {
                let w = scale * rng.unit();
                axes(&mut rng, w)
            };
            let range = if case % 11 == 0 {
                interval(&mut rng, scale)
            } else {
                let r = scale * rng.unit();
                Interval::new(r, r + scale * 0.2 * rng.unit())
            };
            let bearing = (case % 2 == 0).then(|| {
                let b = rng.sym(3.2);
                (Interval::new(-0.1, 0.1), Interval::new(b, b + rng.unit()))
            });
            let cut = if case % 3 == 0 {
                IntervalBox::entire(dim)
            } else {
                axes(&mut rng, 3.0 * scale)
            };
            // Regions on the annulus around the centre box's middle, or
            // anywhere.
            let on_ring: Vec<f64> = centre
                .axes()
                .iter()
                .map(|x| x.mid().clamp(-scale, scale) + range.hi().min(scale) * rng.sym(1.0))
                .collect();
            let shape = Shape::new(centre, range, bearing, cut);
            let regions: Vec<Paving> = (0..1 + case % 3)
                .map(|_| {
                    let w = scale * (0.1 + rng.unit());
                    let mut start = axes(&mut rng, w);
                    if !rng.next_u64().is_multiple_of(4) {
                        let w = scale * 0.3 * rng.unit();
                        let v: Vec<Interval> = on_ring
                            .iter()
                            .map(|&c| Interval::new(c - w, c + w))
                            .collect();
                        start = IntervalBox::new(&v);
                    }
                    let mut p = Paving::from_box(&start);
                    let boxes = 8 + (rng.next_u64() % 60) as usize;
                    p.refine::<Shape>(&[], 0.0, boxes);
                    p
                })
                .collect();
            let refs: Vec<&Paving> = regions.iter().collect();
            let (hull, surviving) = branch_pieces(&shape, &refs);
            let (want, want_surviving) = every_box(&shape, &refs);
            assert_eq!(surviving, want_surviving, "case {case}");
            assert_eq!(bits(&hull), bits(&want), "case {case}: {hull:?} {want:?}");
            if let Some(acc) = &want {
                for r in &refs {
                    if let Some(outer) = shape.contract_piece(r.hull_ref().axes()) {
                        let absorbed = r
                            .boxes()
                            .iter()
                            .filter(|b| shape.absorbs(acc, &outer, b.axes()));
                        skipped += absorbed.count();
                    }
                }
            }
        }
        // The test means something only if boxes are skipped.
        assert!(skipped > 10_000, "{skipped}");
    }

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
