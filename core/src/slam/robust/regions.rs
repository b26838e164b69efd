//! Landmark regions that survive false detections: n pairwise disjoint
//! boxes, each proved to hold exactly one landmark in every solution of
//! every reading of a mission with `max_outliers` = q > 0, found without
//! the operator's labels (docs/outliers.md, "Regions without labels").
//!
//! # Constraint
//!
//! A *reading* drops at most q detections (docs/formats.md); the proved
//! false ones are dropped in every reading, so among the others (the *live*
//! ones) at most `budget` = q - |proved false| are dropped. Every kept
//! detection k sees one of the n landmarks, and in every solution of every
//! reading keeping k that landmark lies in k's box `d(k)` (the robust
//! propagation keeps that invariant, [`crate::slam::robust`]).
//!
//! # Math
//!
//! 1. *At least one landmark.* If at least `budget + 1` live detections
//!    have their boxes inside a box B, every reading keeps one of them, and
//!    its landmark lies in its box, so in B: every solution of every
//!    reading has a landmark in B. A box the caller proved to hold a
//!    landmark in every reading (`held`: a valid track group's,
//!    [`crate::slam::robust::track_groups`]) serves as such a B too.
//! 2. *Exactly one.* With n pairwise disjoint such boxes B(1..n) and n
//!    landmarks, each B(i) holds exactly one landmark, L(i), and every
//!    landmark is one of them.
//! 3. *The q-relaxed intersection.* A kept member k of B(i) (d(k) ⊂ B(i))
//!    sees a landmark in B(i), hence L(i): L(i) lies in the boxes of all
//!    kept members, that is in all but at most `budget` of the members'
//!    boxes, so in their q-relaxed intersection (per axis, the
//!    (budget+1)-th largest lower bound and the (budget+1)-th smallest upper
//!    bound). The region R(i) is B(i) cut by it.
//! 4. *Use* (in [`crate::slam::robust`]): every landmark lies in the union of
//!    the R(i). A kept detection j sees one of them, so d(j) shrinks to the
//!    hull, over the regions, of j's own constraints (distance, bearing)
//!    contracted within d(j) ∩ R(i) (the position box contracted only in a
//!    copy: a position must hold in readings that drop j too); when no
//!    region survives, j is false in every reading (*proved false*), which
//!    shrinks the budget of every later round. A false detection that
//!    reads a phantom (a range or bearing to no landmark) is proved false
//!    once its position box and the regions are narrow enough.
//!
//! The boxes B are a heuristic choice (any choice is sound, a bad one only
//! finds fewer than n of them, and then nothing is used): candidates are
//! the live boxes by increasing diameter; a candidate j grows to the hull
//! of its box and the `budget` narrowest other live boxes that meet it
//! (so `budget + 1` live boxes lie inside it), and it is kept when it
//! meets none of the boxes kept before. If the regions of step 2 cannot be
//! all found, nothing is claimed: a box B holding two true landmarks (two
//! close ones grown together) leaves fewer than n disjoint boxes, since
//! each of the n holds one of the n landmarks in the truth.
//!
//! # Soundness
//!
//! Steps 1-3 are consequences of the semantics of `max_outliers` and of
//! the boxes' invariant; the tests compare bounds (no rounding) and the
//! relaxed intersection picks bounds of the input boxes. The truth is a
//! solution of a reading, so a region never loses a true landmark, and a
//! true detection is never proved false: planted-solution property tests in
//! `core/tests/slam/robust/regions.rs` (false detections of every kind, huge
//! and unbounded boxes).
//!
//! # Complexity
//!
//! O(k log k · d) for the sort and relaxed intersections, plus
//! O(T · k · d) for T <= [`MAX_TRIES`] candidates grown and counted: linear
//! in the number k of detections. Memory O(k + n · d).

use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// Most candidates grown per call (each scans every detection once).
pub const MAX_TRIES: usize = 128;

/// The q-relaxed intersection of boxes (the points lying in all but at
/// most q of them), enclosed per axis: on each axis the (q+1)-th largest
/// lower bound and the (q+1)-th smallest upper bound (entire when there
/// are at most q boxes). Tightness: on each axis, exactly the q-relaxed
/// intersection of the projections (which encloses that of the boxes).
/// O(m log m · d).
pub fn relaxed_intersection(boxes: &[&IntervalBox], q: usize, dim: usize) -> IntervalBox {
    let mut out = IntervalBox::entire(dim);
    if boxes.len() <= q {
        return out;
    }
    let mut lo: Vec<f64> = Vec::with_capacity(boxes.len());
    let mut hi: Vec<f64> = Vec::with_capacity(boxes.len());
    for a in 0..dim {
        lo.clear();
        hi.clear();
        lo.extend(boxes.iter().map(|b| b[a].lo()));
        hi.extend(boxes.iter().map(|b| b[a].hi()));
        // One sort instantiation for both (and for the other f64 sorts):
        // ties are equal bits, so reversing the ascending order is the
        // descending one.
        crate::sort::floats(&mut lo);
        lo.reverse();
        crate::sort::floats(&mut hi);
        let (l, h) = (lo[q], hi[q]);
        out[a] = if l <= h {
            Interval::new(l, h)
        } else {
            Interval::EMPTY
        };
    }
    out
}

/// Pairwise disjoint boxes among `held` (bounded, of dimension `dim`),
/// narrowest first, at most n. O(h log h + h · n · d).
fn disjoint_held(held: &[IntervalBox], n: usize, dim: usize) -> Vec<IntervalBox> {
    let mut kept: Vec<IntervalBox> = Vec::with_capacity(n);
    let mut by_width: Vec<(f64, usize)> = held
        .iter()
        .enumerate()
        .map(|(i, b)| (b.diameter(), i))
        .filter(|&(w, i)| w.is_finite() && held[i].dim() == dim)
        .collect();
    crate::sort::sort_by(&mut by_width, |a, b| {
        a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
    });
    for &(_, i) in &by_width {
        if kept.len() == n {
            break;
        }
        if !kept.iter().any(|b| b.meets(&held[i])) {
            kept.push(held[i].clone());
        }
    }
    kept
}

/// What [`regions`] proves.
#[derive(Debug, Clone, PartialEq)]
pub enum Regions {
    /// Fewer than n disjoint boxes found: nothing is claimed.
    Unknown,
    /// R(1..n): each holds exactly one landmark in every solution of every
    /// reading, and every landmark is in one of them.
    Proved(Vec<IntervalBox>),
    /// A region is empty: no reading has a solution (the reason).
    Infeasible(String),
}

/// The n regions of the module doc from the detections' boxes `det`
/// (enclosing d(j) in every reading keeping j), `live[j]` (not proved
/// false), the budget of drops among the live ones and n.
pub fn regions(det: &[IntervalBox], live: &[bool], budget: usize, n: usize) -> Regions {
    regions_with(det, live, budget, n, &[])
}

/// [`regions`] with `held`: boxes already proved to hold a landmark in
/// every solution of every reading (a valid group's, [`crate::slam::robust::track_groups`]),
/// tried first as the boxes B of step 1, narrowest first, each kept when it
/// meets none kept before.
pub fn regions_with(
    det: &[IntervalBox],
    live: &[bool],
    budget: usize,
    n: usize,
    held: &[IntervalBox],
) -> Regions {
    let Some(dim) = det.first().map(IntervalBox::dim) else {
        return Regions::Unknown;
    };
    let usable = |j: usize| live[j] && !det[j].is_empty();
    let live_count = (0..det.len()).filter(|&j| usable(j)).count();
    // n groups of budget + 1 members each are needed (saturating: a huge
    // budget simply finds nothing).
    if n == 0 || live_count < n.saturating_mul(budget.saturating_add(1)) {
        return Regions::Unknown;
    }
    let mut cand: Vec<(f64, usize)> = (0..det.len())
        .filter(|&j| usable(j))
        .map(|j| (det[j].diameter(), j))
        .filter(|&(w, _)| w.is_finite())
        .collect();
    crate::sort::sort_by(&mut cand, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut kept = disjoint_held(held, n, dim);
    let mut tries = 0;
    for &(_, j) in &cand {
        if kept.len() == n || tries == MAX_TRIES {
            break;
        }
        if kept.iter().any(|b| b.meets(&det[j])) {
            continue;
        }
        tries += 1;
        // The budget narrowest other live boxes meeting d(j) (`cand` is
        // sorted by diameter).
        let near: Vec<usize> = cand
            .iter()
            .map(|&(_, k)| k)
            .filter(|&k| k != j && det[k].meets(&det[j]))
            .take(budget)
            .collect();
        if near.len() < budget {
            continue;
        }
        let b = near.iter().fold(det[j].clone(), |b, &k| b.hull(&det[k]));
        if !kept.iter().any(|c| c.meets(&b)) {
            kept.push(b);
        }
    }
    if kept.len() < n {
        return Regions::Unknown;
    }
    let mut out = Vec::with_capacity(n);
    for b in kept {
        let members: Vec<&IntervalBox> = (0..det.len())
            .filter(|&k| usable(k) && det[k].is_subset(&b))
            .map(|k| &det[k])
            .collect();
        let r = b.intersect(&relaxed_intersection(&members, budget, dim));
        if r.is_empty() {
            return Regions::Infeasible(format!(
                "{} detections lie in the box {b:?}, which holds exactly one landmark, but their boxes have no common point even with {budget} of them dropped",
                members.len()
            ));
        }
        out.push(r);
    }
    Regions::Proved(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(x: (f64, f64), y: (f64, f64)) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x.0, x.1), Interval::new(y.0, y.1)])
    }

    #[test]
    fn two_clusters_with_one_phantom_each_side() {
        // Landmarks at (0, 0) and (10, 0), three detections each, budget 1.
        let det = vec![
            b((-0.2, 0.1), (-0.1, 0.2)),
            b((-0.1, 0.2), (-0.2, 0.1)),
            b((-0.15, 0.15), (-0.15, 0.15)),
            b((9.9, 10.2), (-0.1, 0.2)),
            b((9.8, 10.1), (-0.2, 0.1)),
            b((9.85, 10.15), (-0.15, 0.15)),
            b((5.0, 5.2), (3.0, 3.2)),
        ];
        let live = vec![true; det.len()];
        match regions(&det, &live, 1, 2) {
            Regions::Proved(r) => {
                assert!(r.iter().any(|r| r.contains(&[0.0, 0.0])), "{r:?}");
                assert!(r.iter().any(|r| r.contains(&[10.0, 0.0])), "{r:?}");
                assert!(r.iter().all(|r| !r.contains(&[5.1, 3.1])), "{r:?}");
            }
            other => panic!("{other:?}"),
        }
        // Budget 3: four members per region needed, three are there.
        assert_eq!(regions(&det, &live, 3, 2), Regions::Unknown);
        // A huge budget finds nothing and allocates nothing by it.
        assert_eq!(regions(&det, &live, usize::MAX, 2), Regions::Unknown);
    }
}
