//! Shapes in the frame of a nearby step: detection pairs proved to see
//! distinct landmarks from their relative geometry (docs/design.md, "Detection
//! shapes").
//!
//! # Constraint
//!
//! Two detections i, j at steps s < t with shapes A(i), A(j). If A(i) and
//! A(j) are disjoint, landmark(i) ≠ landmark(j).
//!
//! # Math
//!
//! The absolute boxes of p(s) and p(t) grow with the drift of dead
//! reckoning, but their difference does not: `p(t) - p(s) = Σ_{u=s}^{t-1}
//! D(u)` exactly (the Euler chain), so `p(t) - p(s) ∈ Δ = (Σ D(u)) ∩ (P(t) -
//! P(s))` ([`ChainSums`]), a box as small as a few steps of odometry error. In the frame
//! of p(s) (x ↦ x - p(s)), A(i) is the annulus (or sector) around the exact
//! point 0 and A(j) the one around Δ, each cut by its detection box minus
//! P(s). Two shapes in one frame are disjoint by the tests of
//! [`super::shape`] (annulus tests on the distance interval |Δ|; bisection
//! when a bearing is known). Pairs are tried for each detection and the
//! next `max_ahead` detections in step order.
//!
//! # Soundness
//!
//! A translation keeps disjointness. The true p(t) - p(s) is in the sum of
//! the displacement boxes (each true displacement is in its box; interval
//! sums are rounded outwards) and in P(t) - P(s); the true landmarks minus
//! the true p(s) are in the translated shapes. So a disjointness proved in
//! the frame is a proof about the true landmarks.
//!
//! # Complexity
//!
//! O(k · max_ahead · d) shape tests (bisection capped), each with an
//! O(d) relative displacement from [`ChainSums`].

use super::chain_sums::ChainSums;
use super::shape::{disjoint_paved, Shape, Sighting, MAX_DIM};
use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// Pieces allowed to the bisection test when a bearing is known.
const PAVED_BUDGET: usize = 8;

/// Appends to `out` the pairs (i, j), i < j in input order, proved to see
/// distinct landmarks by their shapes in the frame of the earlier step
/// (module doc). `order` lists the detections by step; `sums` gives the
/// relative displacements, `pos` the position boxes ((N+1)·dim), `det` the
/// detection boxes, `heading_at` the heading at each detection's step.
#[allow(clippy::too_many_arguments)]
pub fn relative_pairs(
    dets: &[Sighting],
    order: &[usize],
    dim: usize,
    sums: &ChainSums,
    pos: &[Interval],
    det: &[IntervalBox],
    heading_at: &[Interval],
    max_ahead: usize,
    out: &mut Vec<(u32, u32)>,
) {
    relative_pairs_where(
        dets,
        order,
        dim,
        sums,
        (pos, det, heading_at),
        max_ahead,
        &mut |_, _| true,
        out,
    );
}

/// [`relative_pairs`] on the pairs (i, j) for which `wanted(i, j)` holds
/// (the others are not tested, and give no pair): the same pairs as
/// [`relative_pairs`] among the wanted ones, the same shape tests.
/// `(pos, det, heading_at)` as in [`relative_pairs`].
#[allow(clippy::too_many_arguments)]
pub fn relative_pairs_where(
    dets: &[Sighting],
    order: &[usize],
    dim: usize,
    sums: &ChainSums,
    (pos, det, heading_at): (&[Interval], &[IntervalBox], &[Interval]),
    max_ahead: usize,
    wanted: &mut dyn FnMut(usize, usize) -> bool,
    out: &mut Vec<(u32, u32)>,
) {
    let pbox = |t: usize| &pos[t * dim..(t + 1) * dim];
    for (oi, &i) in order.iter().enumerate() {
        let ahead = &order[oi + 1..order.len().min(oi + 1 + max_ahead)];
        if !ahead.iter().any(|&j| wanted(i, j)) {
            // No pair wanted: the shape of i is not built.
            continue;
        }
        let s = dets[i].step;
        let origin = pbox(s);
        let mut cut_i = [Interval::ZERO; MAX_DIM];
        for a in 0..dim {
            cut_i[a] = det[i][a] - origin[a];
        }
        let mut shape_i = Shape::new(
            IntervalBox::new(&[Interval::ZERO; MAX_DIM][..dim]),
            dets[i].range,
            dets[i].bearing.map(|b| (heading_at[i], b)),
            IntervalBox::new(&cut_i[..dim]),
        );
        // The cut may shrink to the shape's contracted hull (it holds the
        // shape): the tests below then start from it.
        shape_i.cut = shape_i.hull();
        if shape_i.is_empty() {
            continue;
        }
        for &j in ahead {
            if !wanted(i, j) {
                continue;
            }
            let t = dets[j].step;
            let target = pbox(t);
            let mut delta = sums.delta(s, t);
            let mut cut_j = [Interval::ZERO; MAX_DIM];
            for a in 0..dim {
                delta[a] = delta[a].intersect(target[a] - origin[a]);
                cut_j[a] = det[j][a] - origin[a];
            }
            let mut shape_j = Shape::new(
                IntervalBox::new(&delta[..dim]),
                dets[j].range,
                dets[j].bearing.map(|b| (heading_at[j], b)),
                IntervalBox::new(&cut_j[..dim]),
            );
            shape_j.cut = shape_j.hull();
            // Sectors: bisection, only while the relative position is known
            // better than the ranges (else the cones overlap anyway).
            let known =
                (0..dim).all(|a| delta[a].width() < shape_i.range.hi().min(shape_j.range.hi()));
            let apart = shape_i.disjoint(&shape_j)
                || ((shape_i.bearing.is_some() || shape_j.bearing.is_some())
                    && known
                    && disjoint_paved(&shape_i, &shape_j, PAVED_BUDGET));
            if apart {
                out.push((i.min(j) as u32, i.max(j) as u32));
            }
        }
    }
}
