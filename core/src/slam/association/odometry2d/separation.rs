//! The minimum separation as association evidence (`landmark_min_separation`,
//! formats.md), for robots without a heading sensor (odometry2d).
//!
//! # Constraint
//!
//! Distinct landmarks are at least s apart: for two detections a and b,
//! `l(a) != l(b)` implies `|l(a) - l(b)| >= s`.
//!
//! # Math
//!
//! Each group g (detections proved to see one landmark, singletons
//! included) has its landmark in the intersection B(g) of its members'
//! boxes. When no point of B(g) is s or more from a point of B(h) (an
//! upper bound of the largest cross distance, [`farthest_above`], below
//! s; it was the hull's diameter, which also counts the distances inside
//! each box), the two landmarks are less than s apart, so they are not distinct: g
//! and h see the same landmark (a union). Groups are swept in the order of
//! their boxes' lower x bound; a group is compared with the groups still
//! "active" (whose box reaches within s in x of its own), at most
//! [`MAX_ACTIVE`] of them (the most recent); a merged group's box is the
//! intersection of the two.
//!
//! # Soundness
//!
//! Each box holds its group's true landmark (the boxes are sound
//! enclosures and the groups proved), so the true landmarks, one in each
//! box, are at most the largest cross distance apart; it is bounded from above
//! with outward rounding (`Interval` arithmetic), so "below s" is proved.
//! The landmarks of a union are equal, hence in the intersection of the
//! boxes; an empty intersection proves the mission infeasible. Comparing
//! fewer pairs (the window, [`MAX_ACTIVE`]) only finds fewer unions. The
//! rule needs every detection to see a real landmark: the rounds that run
//! it are those of `max_outliers` = 0 (the robust propagation never does).
//!
//! # Complexity
//!
//! O(k) for the group boxes, O(G log G) for the sort of the G groups whose
//! box is narrower than s, O(G · [`MAX_ACTIVE`]) for the sweep. Memory
//! O(k).

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::union_find::Uf;

/// Most active groups a group is compared with.
pub const MAX_ACTIVE: usize = 256;

/// An upper bound of the Euclidean diameter of `b` (infinity when
/// unbounded; `b` not empty).
pub(crate) fn diameter_above(b: &IntervalBox) -> f64 {
    let mut acc = Interval::ZERO;
    for x in b.axes() {
        if !x.is_bounded() {
            return f64::INFINITY;
        }
        let w = Interval::point(x.hi()) - Interval::point(x.lo());
        acc = acc + w.sqr();
    }
    acc.sqrt().hi()
}

/// An upper bound of the largest distance between a point of `a` and a
/// point of `b` (infinity when unbounded; neither empty): per axis the
/// magnitude of `a - b`, outward rounded. Below s, the landmarks held by
/// the two boxes are less than s apart, whatever the boxes' own widths
/// (the hull's diameter also counts the distances inside each box: a 1 m
/// box around a 0.4 m box has a hull of 1.4 m but no two points of the
/// two boxes more than 1 m apart).
pub(crate) fn farthest_above(a: &IntervalBox, b: &IntervalBox) -> f64 {
    let mut acc = Interval::ZERO;
    for (x, y) in a.axes().iter().zip(b.axes()) {
        let d = *x - *y;
        if !d.is_bounded() {
            return f64::INFINITY;
        }
        acc = acc + Interval::point(d.mag()).sqr();
    }
    acc.sqrt().hi()
}

/// The unions the separation `s` proves between the groups of `uf` over
/// the detection boxes `det` (they are applied to `uf` too). Err: two
/// groups proved to be one landmark have disjoint boxes (the mission is
/// infeasible; the reason names them).
pub fn separation_unions(
    det: &[IntervalBox],
    uf: &mut Uf,
    s: f64,
) -> Result<Vec<(usize, usize)>, String> {
    let mut unions = Vec::new();
    if s.is_nan() || s <= 0.0 || det.is_empty() {
        return Ok(unions);
    }
    let k = det.len();
    let mut group: Vec<Option<IntervalBox>> = vec![None; k];
    for (j, b) in det.iter().enumerate() {
        let r = uf.find(j);
        match &mut group[r] {
            Some(g) => {
                g.intersect_with(b);
            }
            slot => *slot = Some(b.clone()),
        }
    }
    let mut narrow: Vec<(usize, IntervalBox)> = group
        .into_iter()
        .enumerate()
        .filter_map(|(r, b)| {
            let b = b?;
            (!b.is_empty() && diameter_above(&b) < s).then_some((r, b))
        })
        .collect();
    crate::sort::sort_by(&mut narrow, |a, b| {
        a.1[0].lo().total_cmp(&b.1[0].lo()).then(a.0.cmp(&b.0))
    });
    let mut active: Vec<(usize, IntervalBox)> = Vec::new();
    for (r, b) in narrow {
        // Groups whose box ends more than s before this one starts in x
        // can meet no later box within s (later boxes start further on).
        active.retain(|(_, a)| a[0].hi() + s >= b[0].lo());
        let from = active.len().saturating_sub(MAX_ACTIVE);
        let mut merged: Option<usize> = None;
        for x in from..active.len() {
            let (ar, a) = &active[x];
            if farthest_above(a, &b) >= s {
                continue;
            }
            let (ar, a) = (*ar, a.clone());
            let common = a.intersect(&b);
            if common.is_empty() {
                return Err(format!(
                    "landmark_min_separation: detections {ar} and {r} (with their groups) are closer than {s} so one landmark, but their boxes have no common point"
                ));
            }
            uf.union(ar, r);
            unions.push((ar, r));
            match merged {
                None => {
                    active[x].1 = common;
                    merged = Some(x);
                }
                Some(m) => {
                    let c = active[m].1.intersect(&common);
                    if c.is_empty() {
                        return Err(format!(
                            "landmark_min_separation: detection {r} is one landmark with two groups whose boxes have no common point"
                        ));
                    }
                    active[m].1 = c;
                }
            }
        }
        if merged.is_none() {
            active.push((r, b));
        }
    }
    Ok(unions)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bx(x: f64, y: f64, r: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::centered(x, r), Interval::centered(y, r)])
    }

    #[test]
    fn close_boxes_merge_far_ones_do_not() {
        // s = 1: (0, 0) and (0.3, 0.2), 0.2 wide each way, merge (hull
        // diameter about 0.92); (2, 0) stays alone; a wide box never
        // merges.
        let det = vec![
            bx(0.0, 0.0, 0.2),
            bx(2.0, 0.0, 0.1),
            bx(0.3, 0.2, 0.2),
            bx(0.1, 0.1, 5.0),
        ];
        let mut uf = Uf::new(4);
        let u = separation_unions(&det, &mut uf, 1.0).unwrap();
        assert_eq!(u.len(), 1);
        assert_eq!(uf.find(0), uf.find(2));
        assert_ne!(uf.find(0), uf.find(1));
        assert_ne!(uf.find(0), uf.find(3));
        // s = 0: nothing.
        let mut uf = Uf::new(4);
        assert!(separation_unions(&det, &mut uf, 0.0).unwrap().is_empty());
        // Two disjoint boxes closer than s: one landmark in no common
        // point, infeasible.
        let det = vec![bx(0.0, 0.0, 0.1), bx(0.3, 0.2, 0.1)];
        let mut uf = Uf::new(2);
        let e = separation_unions(&det, &mut uf, 1.0).unwrap_err();
        assert!(e.contains("no common point"), "{e}");
    }

    /// Planted landmarks at least s apart, detection boxes around the true
    /// landmark of random widths: every union joins detections of one true
    /// landmark, and never an Err.
    #[test]
    fn planted_landmarks_only_merge_truly_equal_ones() {
        let mut rng = crate::test_rng::Lcg::new(20);
        let mut unit = move || (rng.bits() % 1_000_000) as f64 / 1_000_000.0;
        for case in 0..2000 {
            let s = 0.1 + unit() * 3.0;
            let n = 1 + (unit() * 12.0) as usize;
            let mut lms: Vec<[f64; 2]> = Vec::new();
            while lms.len() < n {
                let c = [unit() * 20.0 - 10.0, unit() * 20.0 - 10.0];
                if lms
                    .iter()
                    .all(|l| libm::hypot(l[0] - c[0], l[1] - c[1]) >= s)
                {
                    lms.push(c);
                }
                if unit() < 0.01 {
                    break;
                }
            }
            let k = 1 + (unit() * 60.0) as usize;
            let mut truth = Vec::new();
            let det: Vec<IntervalBox> = (0..k)
                .map(|_| {
                    let l = (unit() * lms.len() as f64) as usize % lms.len();
                    truth.push(l);
                    let w = unit() * s * 1.2;
                    let (ox, oy) = (unit() * w, unit() * w);
                    IntervalBox::new(&[
                        Interval::new(lms[l][0] - ox, lms[l][0] - ox + w),
                        Interval::new(lms[l][1] - oy, lms[l][1] - oy + w),
                    ])
                })
                .collect();
            let mut uf = Uf::new(k);
            separation_unions(&det, &mut uf, s).unwrap();
            for a in 0..k {
                for b in 0..k {
                    if uf.find(a) == uf.find(b) {
                        assert_eq!(truth[a], truth[b], "case {case}: {a} {b}");
                    }
                }
            }
        }
    }
}
