//! The `independent` contractor of atmost_nvector(n, {d(1)..d(k)}): pairwise
//! disjoint boxes as witnesses of distinct vectors, in full dimension
//! (docs/design.md; it lifts the independent-set reasoning of integer
//! atmost_nvalue propagators — Gecode's `nvalues`; Fages and Lapègue,
//! "Filtering AtMostNValue with difference constraints", AIJ 2014 — to
//! boxes).
//!
//! # Math
//!
//! Let `S = {s_1..s_t}` be boxes that are pairwise disjoint (an independent
//! set of the intersection graph). In any solution each `s_i` holds the value
//! of its own variable, and no vector lies in two of them, so the solution
//! uses at least `t` distinct vectors:
//! - `t > n`: infeasible.
//! - `t = n`: the n distinct vectors are exactly `w_1 ∈ s_1, ..., w_n ∈ s_n`,
//!   and every variable takes one of them. A box `x` therefore holds a value
//!   of `∪_i (x ∩ s_i)` and becomes `hull(∪_i (x ∩ s_i))`; a box meeting a
//!   single witness `s_i` takes `w_i`: it is grouped with `s_i`, and the
//!   group is intersected (this also shrinks the witness).
//!
//! Unlike per-axis reasoning this uses the true d-dimensional geometry: two
//! landmarks that overlap on every axis projection are still separated when
//! their boxes are disjoint (the weakness the paper points at in Fig. 9).
//!
//! # Finding S
//!
//! Maximum independent sets are NP-hard; any independent set is sound. We
//! seed with the boxes that create the left-greedy points on each axis
//! (they are pairwise disjoint on that axis: each one starts after the
//! previous one ends) and with the empty set, then extend each seed by the
//! remaining boxes from the smallest diameter up, keeping a box when it is
//! disjoint from all chosen ones, and stop past n. The largest set wins.
//!
//! # Soundness
//!
//! Only the two facts above; intersections and hulls compare f64 bounds
//! exactly, no arithmetic is done.
//!
//! # Complexity
//!
//! O(d k log k) for the seeds and the size order, O((d + 1) k n d) for the
//! extensions (each candidate is compared with at most n + 1 chosen boxes),
//! O(k n d) for the contraction.

use crate::ibox::IntervalBox;

/// Reusable buffers for [`find_independent`].
#[derive(Debug, Default, Clone)]
pub struct IndependentScratch {
    order: Vec<usize>,
    by_size: Vec<usize>,
    chosen: Vec<u32>,
    best: Vec<u32>,
}

/// Finds pairwise-disjoint boxes (at most `n + 1`: enough to prove
/// infeasibility). Returns their indices, sorted.
pub fn find_independent(
    n: usize,
    boxes: &[IntervalBox],
    scratch: &mut IndependentScratch,
) -> Vec<u32> {
    let k = boxes.len();
    if k == 0 {
        return Vec::new();
    }
    let dim = boxes[0].dim();
    let IndependentScratch {
        order,
        by_size,
        chosen,
        best,
    } = scratch;
    by_size.clear();
    by_size.extend(0..k);
    crate::sort::sort_indices_by(by_size, |a, b| {
        boxes[a].diameter().total_cmp(&boxes[b].diameter())
    });
    best.clear();
    for seed_axis in 0..=dim {
        chosen.clear();
        if seed_axis < dim {
            // Left greedy on this axis: the boxes creating points are
            // pairwise disjoint on the axis.
            order.clear();
            order.extend(0..k);
            crate::sort::sort_indices_by(order, |a, b| {
                boxes[a][seed_axis]
                    .hi()
                    .total_cmp(&boxes[b][seed_axis].hi())
            });
            let mut p = f64::NEG_INFINITY;
            let mut placed = false;
            for &i in order.iter() {
                let (hi, i) = (boxes[i][seed_axis].hi(), i as u32);
                if !placed || boxes[i as usize][seed_axis].lo() > p {
                    p = hi;
                    placed = true;
                    chosen.push(i);
                    if chosen.len() > n || p == f64::INFINITY {
                        break;
                    }
                }
            }
        }
        if chosen.len() <= n {
            for &i in by_size.iter() {
                let (b, i) = (&boxes[i], i as u32);
                if chosen.contains(&i) || chosen.iter().any(|&j| boxes[j as usize].meets(b)) {
                    continue;
                }
                chosen.push(i);
                if chosen.len() > n {
                    break;
                }
            }
        }
        if chosen.len() > best.len() {
            std::mem::swap(best, chosen);
            if best.len() > n {
                break;
            }
        }
    }
    let mut out = best.clone();
    crate::sort::natural(&mut out);
    out
}

/// Contracts every box to the hull of its intersections with the `n`
/// witnesses (pairwise disjoint boxes, `witnesses.len() == n`), and returns
/// for each box the witness it alone meets (`u32::MAX` when several; a box
/// meeting none is emptied). Witness boxes themselves are left as they are.
/// Returns whether a box changed.
pub fn contract_with_witnesses(
    boxes: &mut [IntervalBox],
    witnesses: &[u32],
    sole_witness: &mut Vec<u32>,
) -> bool {
    let wboxes: Vec<IntervalBox> = witnesses
        .iter()
        .map(|&w| boxes[w as usize].clone())
        .collect();
    sole_witness.clear();
    sole_witness.resize(boxes.len(), u32::MAX);
    let mut changed = false;
    for (i, x) in boxes.iter_mut().enumerate() {
        let mut hull: Option<IntervalBox> = None;
        let mut met = 0usize;
        let mut which = u32::MAX;
        for (wi, s) in wboxes.iter().enumerate() {
            if x.meets(s) {
                let piece = x.intersect(s);
                hull = Some(match hull {
                    None => piece,
                    Some(h) => h.hull(&piece),
                });
                met += 1;
                which = witnesses[wi];
            }
        }
        match hull {
            None => {
                if !x.is_empty() {
                    x.set_empty();
                    changed = true;
                }
            }
            Some(h) => {
                if h != *x {
                    *x = h;
                    changed = true;
                }
                if met == 1 {
                    sole_witness[i] = which;
                }
            }
        }
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;

    fn b2(x0: f64, x1: f64, y0: f64, y1: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x0, x1), Interval::new(y0, y1)])
    }

    #[test]
    fn diagonal_boxes_are_independent_though_projections_overlap() {
        // Two boxes overlapping on both projections but disjoint in 2-D.
        let boxes = vec![
            b2(0.0, 2.0, 0.0, 1.0),
            b2(1.0, 3.0, 1.5, 3.0),
            b2(0.0, 1.0, 1.5, 2.0),
        ];
        let mut s = IndependentScratch::default();
        let ind = find_independent(5, &boxes, &mut s);
        assert!(ind.len() >= 2);
        for (a, &i) in ind.iter().enumerate() {
            for &j in &ind[a + 1..] {
                assert!(!boxes[i as usize].meets(&boxes[j as usize]));
            }
        }
    }

    #[test]
    fn witnesses_contract_and_group() {
        // Witnesses 0 and 1; box 2 meets both (hulled), box 3 meets only 0.
        let mut boxes = vec![
            b2(0.0, 1.0, 0.0, 1.0),
            b2(5.0, 6.0, 5.0, 6.0),
            b2(0.5, 5.5, 0.5, 5.5),
            b2(-3.0, 0.5, -3.0, 0.5),
        ];
        let mut sole = Vec::new();
        assert!(contract_with_witnesses(&mut boxes, &[0, 1], &mut sole));
        assert_eq!(boxes[2], b2(0.5, 5.5, 0.5, 5.5));
        assert_eq!(boxes[3], b2(0.0, 0.5, 0.0, 0.5));
        assert_eq!(sole, vec![0, 1, u32::MAX, 0]);
    }
}
