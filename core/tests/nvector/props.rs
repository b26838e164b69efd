//! Property tests of the atmost_nvector contractors.
//!
//! - Soundness: a planted solution (n points, each box drawn around one of
//!   them, degenerate, touching and nested boxes included) survives every
//!   mode, and no two boxes holding different planted points are grouped.
//! - `exact` against brute force on small integer instances: the minimum
//!   hitting set and every bound, computed by enumerating the half-integer
//!   grid (all corners are integers, so every cell of the arrangement has a
//!   grid point) — independent of the branch and bound under test.
//! - Ordering: exact ⊆ every mode ⊆ nvalue, independent ⊆ projection.
//! - Signed zeros and bounds spreading over f64::MAX keep planted solutions.
//! - `exact` under a node budget: the exact answer or a sound error.
//!
//! Case count: `PROPTEST_CASES` (default 3000); seeds and persisted
//! failures: tests/common/mod.rs (`config`).

// Index loops compare several parallel vectors of boxes: clearer as ranges.
#![allow(clippy::needless_range_loop)]

use nvector_core::nvector::contract::ContractError;
use nvector_core::nvector::hitting_set::{Limits, WorkLimit};
use nvector_core::nvector::{atmost_nvector, atmost_nvector_with, Contractor, Status};
use nvector_core::{Interval, IntervalBox};
use proptest::prelude::*;

use crate::common;

/// Default 3000 cases (`PROPTEST_CASES`), divided by `div` for the slower
/// properties.
fn config(div: u32) -> ProptestConfig {
    common::config_div(3000, div, 20)
}

const MODES: [Contractor; 5] = [
    Contractor::Nvalue,
    Contractor::Projection,
    Contractor::Independent,
    Contractor::Best,
    Contractor::Exact,
];

/// A planted instance: boxes, the planted point index of each box, the
/// points, and n.
#[derive(Debug, Clone)]
struct Planted {
    boxes: Vec<IntervalBox>,
    owner: Vec<usize>,
    points: Vec<Vec<f64>>,
    n: usize,
}

/// One side of a box around a coordinate: 0 (degenerate/touching), a small
/// integer, or a float.
fn side() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        (1u8..4).prop_map(f64::from),
        0.0..3.0f64,
        Just(f64::INFINITY)
    ]
}

fn planted(max_k: usize, integer: bool) -> impl Strategy<Value = Planted> {
    (1usize..=3, 1usize..=4, 1usize..=max_k, 0usize..=2).prop_flat_map(
        move |(d, npts, k, extra)| {
            let coord = if integer {
                (0i32..=6).prop_map(f64::from).boxed()
            } else {
                prop_oneof![(0i32..=6).prop_map(f64::from), 0.0..6.0f64].boxed()
            };
            let points = proptest::collection::vec(proptest::collection::vec(coord, d), npts);
            let sides = if integer {
                proptest::collection::vec(proptest::collection::vec((0u8..4, 0u8..4), d), k)
                    .prop_map(|v| {
                        v.into_iter()
                            .map(|b| {
                                b.into_iter()
                                    .map(|(a, c)| (f64::from(a), f64::from(c)))
                                    .collect::<Vec<_>>()
                            })
                            .collect::<Vec<_>>()
                    })
                    .boxed()
            } else {
                proptest::collection::vec(proptest::collection::vec((side(), side()), d), k).boxed()
            };
            let owners = proptest::collection::vec(0..npts, k);
            (points, sides, owners, Just(extra)).prop_map(|(points, sides, owner, extra)| {
                let boxes: Vec<IntervalBox> = owner
                    .iter()
                    .zip(&sides)
                    .map(|(&o, s)| {
                        let axes: Vec<Interval> = points[o]
                            .iter()
                            .zip(s)
                            .map(|(&c, &(a, b))| Interval::new(c - a, c + b))
                            .collect();
                        IntervalBox::new(&axes)
                    })
                    .collect();
                let mut used: Vec<&Vec<f64>> = owner.iter().map(|&o| &points[o]).collect();
                used.sort_by(|a, b| a.partial_cmp(b).unwrap());
                used.dedup();
                let n = used.len() + extra;
                Planted {
                    boxes,
                    owner,
                    points,
                    n,
                }
            })
        },
    )
}

fn check_sound(p: &Planted, mode: Contractor) -> Result<Vec<IntervalBox>, TestCaseError> {
    let mut boxes = p.boxes.clone();
    let out =
        atmost_nvector(p.n, &mut boxes, mode).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert!(
        !matches!(out.status, Status::Infeasible { .. }),
        "{mode:?} says infeasible: {:?} on {:?}",
        out.status,
        p
    );
    for (i, b) in boxes.iter().enumerate() {
        prop_assert!(
            b.contains(&p.points[p.owner[i]]),
            "{mode:?} lost the planted point of box {i}: {:?} -> {:?}",
            p,
            b
        );
        prop_assert!(b.is_subset(&p.boxes[i]), "{mode:?} grew box {i}");
    }
    for g in &out.groups {
        for &j in g {
            prop_assert!(
                p.points[p.owner[j]] == p.points[p.owner[g[0]]],
                "{mode:?} grouped boxes {} and {j} holding different planted points: {:?}",
                g[0],
                p
            );
        }
    }
    prop_assert!(out.min_distinct_lower <= out.min_distinct_upper);
    let mut used: Vec<&Vec<f64>> = p.owner.iter().map(|&o| &p.points[o]).collect();
    used.sort_by(|a, b| a.partial_cmp(b).unwrap());
    used.dedup();
    prop_assert!(
        out.min_distinct_lower <= used.len(),
        "lower bound {} above a planted solution of {}",
        out.min_distinct_lower,
        used.len()
    );
    Ok(boxes)
}

/// Brute force on the half-integer grid (integer corners only): the masks
/// of boxes each grid point hits.
struct Brute {
    grid: Vec<Vec<f64>>,
    masks: Vec<u64>,
}

impl Brute {
    fn new(boxes: &[IntervalBox]) -> Brute {
        let d = boxes[0].dim();
        let coords: Vec<f64> = (-8..=24).map(|i| f64::from(i) * 0.5).collect();
        let mut grid = vec![vec![]];
        for _ in 0..d {
            grid = grid
                .into_iter()
                .flat_map(|v: Vec<f64>| {
                    coords.iter().map(move |&c| {
                        let mut w = v.clone();
                        w.push(c);
                        w
                    })
                })
                .collect();
        }
        let masks = grid
            .iter()
            .map(|v| {
                boxes
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| b.contains(v))
                    .fold(0u64, |m, (i, _)| m | 1 << i)
            })
            .collect();
        Brute { grid, masks }
    }

    /// Can `u` be hit by at most `budget` grid points?
    fn coverable(&self, u: u64, budget: usize, distinct: &[u64]) -> bool {
        if u == 0 {
            return true;
        }
        if budget == 0 {
            return false;
        }
        let low = u & u.wrapping_neg();
        distinct
            .iter()
            .filter(|&&m| m & low != 0)
            .any(|&m| self.coverable(u & !m, budget - 1, distinct))
    }

    fn min_cover(&self, all: u64) -> usize {
        let distinct = self.distinct();
        (0..=64)
            .find(|&b| self.coverable(all, b, &distinct))
            .unwrap()
    }

    fn distinct(&self) -> Vec<u64> {
        let mut d = self.masks.clone();
        d.sort_unstable();
        d.dedup();
        d
    }
}

proptest! {
    #![proptest_config(config(1))]

    #[test]
    fn planted_solution_survives_polynomial_modes(p in planted(12, false)) {
        for mode in [Contractor::Nvalue, Contractor::Projection, Contractor::Independent, Contractor::Best] {
            check_sound(&p, mode)?;
        }
    }
}

proptest! {
    #![proptest_config(config(6))]

    #[test]
    fn planted_solution_survives_exact(p in planted(7, false)) {
        check_sound(&p, Contractor::Exact)?;
    }

    #[test]
    fn exact_matches_brute_force_and_bounds_the_others(p in planted(6, true), n_shift in 0usize..2) {
        // Also try n below the planted count: infeasible cases are checked
        // against brute force too.
        let n = p.n.saturating_sub(n_shift).max(1);
        let brute = Brute::new(&p.boxes);
        let k = p.boxes.len();
        let all = (1u64 << k) - 1;
        let mhs = brute.min_cover(all);
        let mut exact = p.boxes.clone();
        let out = atmost_nvector(n, &mut exact, Contractor::Exact).unwrap();
        if mhs > n {
            prop_assert!(matches!(out.status, Status::Infeasible { .. }), "brute force needs {mhs} > n = {n}, exact says {:?}", out.status);
            return Ok(());
        }
        prop_assert!(!matches!(out.status, Status::Infeasible { .. }), "exact infeasible but brute force covers with {mhs} <= {n}");
        prop_assert_eq!((out.min_distinct_lower, out.min_distinct_upper), (mhs, mhs));
        let distinct = brute.distinct();
        for i in 0..k {
            // Feasible grid values of box i: in box i, rest coverable by n-1.
            let mut hull: Option<IntervalBox> = None;
            for (v, &m) in brute.grid.iter().zip(&brute.masks) {
                if m & (1 << i) != 0 && brute.coverable(all & !m, n - 1, &distinct) {
                    let pt = IntervalBox::point(v);
                    hull = Some(match hull { None => pt, Some(h) => h.hull(&pt) });
                }
            }
            let hull = hull.expect("box i has a feasible value when the instance is feasible");
            prop_assert_eq!(&exact[i], &hull, "exact bound of box {} differs from brute force", i);
        }
        let mut results = Vec::new();
        for mode in MODES {
            let mut b = p.boxes.clone();
            let o = atmost_nvector(n, &mut b, mode).unwrap();
            prop_assert!(!matches!(o.status, Status::Infeasible { .. }), "{mode:?} infeasible on a feasible instance");
            prop_assert!(o.min_distinct_lower <= mhs && o.min_distinct_upper >= mhs, "{mode:?} bounds {:?} vs {mhs}", (o.min_distinct_lower, o.min_distinct_upper));
            results.push(b);
        }
        let [nvalue, projection, independent, best, exact2] = <[Vec<IntervalBox>; 5]>::try_from(results).unwrap();
        for i in 0..k {
            prop_assert!(exact2[i] == exact[i]);
            for (name, m) in [("projection", &projection), ("independent", &independent), ("best", &best)] {
                prop_assert!(exact[i].is_subset(&m[i]), "{} tighter than exact on box {}", name, i);
                prop_assert!(m[i].is_subset(&nvalue[i]), "{} looser than nvalue on box {}", name, i);
            }
            prop_assert!(independent[i].is_subset(&projection[i]), "independent looser than projection on box {}", i);
        }
    }
}

/// Regression: signed zeros are one value. With every finite
/// bound ±0 (a range of 0) or bounds spreading over more than f64::MAX, the
/// nvalue greedies keyed -0 below +0: n = 1 over [-0, -0], [0, 0] answered
/// infeasible, and n = 2 over [-1e308, -0], [0, 1e308], [1e308, 1e308]
/// pruned the second box to [1e308, 1e308] and grouped it with the third.
/// Every mode must keep the planted solutions (0, 0) and (0, 0, 1e308).
#[test]
fn regression_signed_zeros_are_one_value_in_every_mode() {
    let b = |lo: f64, hi: f64| IntervalBox::new(&[Interval::new(lo, hi)]);
    let cases: [(usize, Vec<IntervalBox>, Vec<f64>); 3] = [
        (1, vec![b(-0.0, -0.0), b(0.0, 0.0)], vec![0.0, 0.0]),
        (
            2,
            vec![b(-1e308, -0.0), b(0.0, 1e308), b(1e308, 1e308)],
            vec![0.0, 0.0, 1e308],
        ),
        (
            2,
            vec![b(-1e308, -1e308), b(-1e308, 0.0), b(-0.0, 1e308)],
            vec![-1e308, 0.0, 0.0],
        ),
    ];
    for (n, boxes, planted) in cases {
        for mode in MODES {
            let mut out = boxes.clone();
            let r = atmost_nvector(n, &mut out, mode).unwrap();
            assert!(
                !matches!(r.status, Status::Infeasible { .. }),
                "{mode:?} on {boxes:?}: {:?}",
                r.status
            );
            for (x, &v) in out.iter().zip(&planted) {
                assert!(
                    x.contains(&[v]),
                    "{mode:?} lost {v} from {boxes:?}: {out:?}"
                );
            }
            for g in &r.groups {
                for &j in g {
                    assert_eq!(planted[j], planted[g[0]], "{mode:?} grouped {g:?}");
                }
            }
        }
    }
}

/// A coordinate with signed zeros and huge magnitudes.
fn extreme_coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(-0.0),
        Just(1e308),
        Just(-1e308),
        (-3i32..=3).prop_map(f64::from),
    ]
}

/// A box side: 0 (degenerate), 1, 1e308 (the spread overflows) or +inf.
fn extreme_side() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(1.0), Just(1e308), Just(f64::INFINITY)]
}

/// Flips the sign of a zero bound when `flip` says so.
fn sign(x: f64, flip: bool) -> f64 {
    if x == 0.0 && flip {
        -x
    } else {
        x
    }
}

fn planted_extreme(max_k: usize) -> impl Strategy<Value = Planted> {
    (1usize..=2, 1usize..=3, 1usize..=max_k, 0usize..=1).prop_flat_map(
        move |(d, npts, k, extra)| {
            let points =
                proptest::collection::vec(proptest::collection::vec(extreme_coord(), d), npts);
            let sides = proptest::collection::vec(
                proptest::collection::vec(
                    (extreme_side(), extreme_side(), any::<bool>(), any::<bool>()),
                    d,
                ),
                k,
            );
            let owners = proptest::collection::vec(0..npts, k);
            (points, sides, owners, Just(extra)).prop_map(|(points, sides, owner, extra)| {
                let boxes: Vec<IntervalBox> = owner
                    .iter()
                    .zip(&sides)
                    .map(|(&o, s)| {
                        let axes: Vec<Interval> = points[o]
                            .iter()
                            .zip(s)
                            .map(|(&c, &(a, b, fa, fb))| {
                                // c - a and c + b round to nearest: widen
                                // to keep c inside (1e308 - 1 = 1e308).
                                let lo = if a == 0.0 { c } else { (c - a).min(c) };
                                let hi = if b == 0.0 { c } else { (c + b).max(c) };
                                Interval::new(sign(lo, fa), sign(hi, fb))
                            })
                            .collect();
                        IntervalBox::new(&axes)
                    })
                    .collect();
                let mut used: Vec<&Vec<f64>> = owner.iter().map(|&o| &points[o]).collect();
                used.sort_by(|a, b| a.partial_cmp(b).unwrap());
                used.dedup();
                let n = used.len() + extra;
                Planted {
                    boxes,
                    owner,
                    points,
                    n,
                }
            })
        },
    )
}

proptest! {
    #![proptest_config(config(3))]

    /// Planted solutions survive with signed zeros at equal ranges (every
    /// finite bound ±0) and with ranges over f64::MAX, in every mode.
    #[test]
    fn planted_solution_survives_signed_zeros_and_overflowing_ranges(p in planted_extreme(7)) {
        for mode in MODES {
            check_sound(&p, mode)?;
        }
    }
}

proptest! {
    #![proptest_config(config(6))]

    /// `exact` under a small node budget either finishes with the same
    /// boxes as without one, or answers the work-limit error with boxes
    /// that still hold the planted solution (what the polynomial passes
    /// proved) and enclose the exact answer.
    #[test]
    fn exact_under_a_budget_is_exact_or_a_sound_error(p in planted(7, false), budget in 0u64..3000) {
        let mut full = p.boxes.clone();
        let full_out = atmost_nvector(p.n, &mut full, Contractor::Exact).unwrap();
        let mut b = p.boxes.clone();
        let limits = Limits { node_budget: budget, ..Limits::default() };
        match atmost_nvector_with(p.n, &mut b, Contractor::Exact, &limits) {
            Ok(out) => {
                prop_assert_eq!(&b, &full);
                prop_assert_eq!(out, full_out);
            }
            Err(e) => {
                prop_assert_eq!(e, ContractError::Limit(WorkLimit::NodeBudget(budget)));
                for (i, x) in b.iter().enumerate() {
                    prop_assert!(x.contains(&p.points[p.owner[i]]), "box {} lost its planted point", i);
                    prop_assert!(full[i].is_subset(x) && x.is_subset(&p.boxes[i]));
                }
            }
        }
    }
}
