//! Unbounded and overflowing bounds, on planted solutions.
//!
//! One displacement with an infinite bound (a speed of 1e308 ± 1e308 is
//! [0, +inf]; a motion error of f64::MAX overflows when added) once made
//! the displacement sums of the shapes code empty, and with them every pair
//! of detections across it "distinct": wrong matchings reported as proved,
//! or "infeasible". Here every contractor, and the whole engine, meets
//! unbounded and overflowing steps, speeds, headings, errors and ranges:
//! ±inf bounds, 1e308 and f64::MAX error bounds, zero widths, huge
//! coordinates, and truths on the boundary of their intervals (planted
//! exactly where the f64 arithmetic allows it: Pythagorean triples scaled
//! by powers of two, positions whose differences are enclosed by the
//! project's own interval subtraction). The truth must survive and no
//! matching may be wrong.
//!
//! Deterministic: the seeds are fixed (`NVECTOR_UNBOUNDED_SEED` picks
//! another base seed; a failure prints the seed of its case), and
//! `NVECTOR_PROPTEST_CASES` scales the case counts.

// Axes and detections index several parallel arrays at once.
#![allow(clippy::needless_range_loop)]

use num_bigint::BigInt;
use num_rational::BigRational;
use nvector_core::contractors::bearing::contract_bearing;
use nvector_core::contractors::distance::contract_distance;
use nvector_core::contractors::motion_chain::{
    auv_displacement, sweep_backward, sweep_forward, unicycle_displacement, Sweep,
};
use nvector_core::nvector::Contractor;
use nvector_core::shapes::branch::branch;
use nvector_core::shapes::chain_sums::ChainSums;
use nvector_core::shapes::distinct::Uf;
use nvector_core::shapes::region::Paving;
use nvector_core::shapes::registration::{register, LocalGroup, RegisterOptions};
use nvector_core::shapes::shape::{disjoint_paved, distance_between, Shape};
use nvector_core::slam::association::{Chain, Domains, ShapesState};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::{score, SolveStatus};
use nvector_core::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::{Interval, IntervalBox};
use serde_json::{json, Value};
use std::sync::atomic::AtomicBool;

use crate::common;
use common::world::{random_world, Planted, World};
use common::Rng;

/// The base seed: fixed, so that a run is reproducible and a bug is caught
/// in every run or in none.
fn seed_base() -> u64 {
    std::env::var("NVECTOR_UNBOUNDED_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x0019_0019)
}

/// `default` cases, scaled by `NVECTOR_PROPTEST_CASES` (1000 = as is).
fn cases(default: usize) -> usize {
    std::env::var("NVECTOR_PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .map_or(default, |c| (default * c / 1000).max(1))
}

/// Runs `case` on the seeds of `count` cases; the message of a failure
/// names the seed.
fn each_case(count: usize, salt: u64, mut case: impl FnMut(&mut Rng, u64)) {
    let base = seed_base();
    for i in 0..count as u64 {
        let seed = base.wrapping_add(i).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt;
        case(&mut Rng::new(seed), seed);
    }
}

fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).expect("finite")
}

/// A finite f64 exactly, as an integer count of 2^-1074 (every f64 is
/// one): sums of these need no fraction reduction.
fn fixed(x: f64) -> BigInt {
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, exp - 1075)
    };
    let v = BigInt::from(m) << ((e + 1074) as usize);
    if bits >> 63 == 1 {
        -v
    } else {
        v
    }
}

/// Whether `x` (exact, in units of 2^-1074) lies in `i`, infinite bounds
/// included.
fn holds(i: Interval, x: &BigInt) -> bool {
    !i.is_empty()
        && (i.lo() == f64::NEG_INFINITY || fixed(i.lo()) <= *x)
        && (i.hi() == f64::INFINITY || *x <= fixed(i.hi()))
}

/// A value of a wild magnitude: zero, tiny, ordinary, an integer, huge,
/// near f64::MAX.
fn wild_value(rng: &mut Rng) -> f64 {
    match rng.below(9) {
        0 => 0.0,
        1 => rng.range(-1e-300, 1e-300),
        2 => (rng.below(41) as f64 - 20.0) * 0.5,
        3 => rng.range(-1e300, 1e300),
        4 => (rng.unit() * 2.0 - 1.0) * f64::MAX,
        _ => rng.range(-50.0, 50.0),
    }
}

/// An interval holding `inner` (the truth or an enclosure of it; not
/// empty): itself (the truth on the boundary, a zero width for a point),
/// half-lines and the whole line, an overflowing `centered` with a 1e308
/// or f64::MAX error, [-MAX, MAX], or widened by up to `w` on each side.
fn holding(rng: &mut Rng, inner: Interval, w: f64) -> Interval {
    let (lo, hi) = (inner.lo(), inner.hi());
    let wide = match rng.below(14) {
        0 => Interval::ENTIRE,
        1 => Interval::new(f64::NEG_INFINITY, hi),
        2 => Interval::new(lo, f64::INFINITY),
        3 => Interval::centered(inner.mid(), 1e308),
        4 => Interval::centered(inner.mid(), f64::MAX),
        5 => Interval::new(-f64::MAX, f64::MAX),
        6..=8 => inner,
        9 => Interval::new(lo, hi + rng.range(0.0, w)),
        10 => Interval::new(lo - rng.range(0.0, w), hi),
        _ => Interval::new(lo - rng.range(0.0, w), hi + rng.range(0.0, w)),
    };
    // `centered` and [-MAX, MAX] may miss an infinite side of `inner`.
    wide.hull(inner)
}

/// A bound as the mission format writes it.
fn bound(x: f64) -> Value {
    if x == f64::INFINITY {
        json!("inf")
    } else if x == f64::NEG_INFINITY {
        json!("-inf")
    } else {
        json!(x)
    }
}

// ----- relative displacements (shapes/chain_sums.rs) ------------------------

/// Sums of displacement boxes holding wild true displacements (some
/// unbounded, huge, overflowing, zero-width) always hold the exact sum of
/// the true displacements, on every window and in both directions, and are
/// never empty.
#[test]
fn chain_sums_hold_the_exact_sums_of_wild_steps() {
    each_case(cases(1500), 1, |rng, seed| {
        let dim = 1 + rng.below(3);
        let long = rng.unit() < 0.2;
        let steps = 1 + rng.below(if long { 400 } else { 90 });
        let huge_share = rng.unit() * 0.3;
        let mut truth = Vec::with_capacity(steps * dim);
        let mut disp = Vec::with_capacity(steps * dim);
        for _ in 0..steps * dim {
            let d = if rng.unit() < huge_share {
                wild_value(rng)
            } else {
                rng.range(-2.0, 2.0)
            };
            let w = [0.0, 1e-6, 0.5, 1e300][rng.below(4)];
            truth.push(d);
            disp.push(if rng.unit() < huge_share {
                holding(rng, Interval::point(d), w)
            } else {
                Interval::new(d - rng.range(0.0, 0.1), d + rng.range(0.0, 0.1))
            });
        }
        // Exact prefix sums of the true displacements.
        let mut prefix = vec![vec![BigInt::from(0); dim]];
        for u in 0..steps {
            let mut next = prefix[u].clone();
            for a in 0..dim {
                next[a] += fixed(truth[u * dim + a]);
            }
            prefix.push(next);
        }
        let marks: Vec<usize> = (0..rng.below(6)).map(|_| rng.below(steps + 1)).collect();
        let sums = ChainSums::new(&disp, dim).with_steps(&marks);
        for _ in 0..30 {
            let (s, t) = (rng.below(steps + 1), rng.below(steps + 1));
            let d = sums.delta(s, t);
            for a in 0..dim {
                let exact = &prefix[t][a] - &prefix[s][a];
                assert!(
                    holds(d[a], &exact),
                    "seed {seed}: delta({s}, {t})[{a}] = {:?} misses the true sum",
                    d[a]
                );
            }
        }
    });
}

// ----- the motion chain (slam/motion_chain.rs) -----------------------------

/// Sweeps over displacement boxes holding the exact differences of wild
/// true positions (huge coordinates whose differences overflow included)
/// keep every true position and never empty a position.
#[test]
fn sweeps_keep_wild_true_positions() {
    each_case(cases(2000), 2, |rng, seed| {
        let dim = 1 + rng.below(3);
        let steps = 1 + rng.below(60);
        let huge = rng.unit() < 0.3;
        let mut truth: Vec<f64> = (0..dim)
            .map(|_| {
                if huge {
                    wild_value(rng)
                } else {
                    rng.range(-100.0, 100.0)
                }
            })
            .collect();
        for i in 0..steps {
            for a in 0..dim {
                let last = truth[i * dim + a];
                let next = if huge && rng.unit() < 0.3 {
                    wild_value(rng)
                } else {
                    last + rng.range(-2.0, 2.0)
                };
                truth.push(if next.is_finite() { next } else { last });
            }
        }
        let wild_share = rng.unit() * 0.4;
        let disp: Vec<Interval> = (0..steps * dim)
            .map(|x| {
                // The exact difference, enclosed by the interval subtraction.
                let exact = Interval::point(truth[x + dim]) - Interval::point(truth[x]);
                if rng.unit() < wild_share {
                    holding(rng, exact, 1.0)
                } else {
                    Interval::new(
                        exact.lo() - rng.range(0.0, 0.2),
                        exact.hi() + rng.range(0.0, 0.2),
                    )
                }
            })
            .collect();
        let pos: Vec<Interval> = truth
            .iter()
            .enumerate()
            .map(|(x, &p)| {
                if x < dim || rng.unit() < 0.3 {
                    holding(rng, Interval::point(p), 3.0)
                } else {
                    Interval::ENTIRE
                }
            })
            .collect();
        let tol = [0.0, 1e-9, 1e-3][rng.below(3)];
        let mut pos = pos;
        for _ in 0..4 {
            let from = rng.below(steps + 1);
            let outcome = if rng.unit() < 0.5 {
                sweep_forward(&mut pos, &disp, dim, from, tol)
            } else {
                sweep_backward(&mut pos, &disp, dim, from, tol)
            };
            assert!(
                !matches!(outcome, Sweep::Empty(_)),
                "seed {seed}: {outcome:?}"
            );
            for (x, &p) in truth.iter().enumerate() {
                assert!(
                    pos[x].contains(p),
                    "seed {seed}: p({})[{}] = {p:e} lost: {:?}",
                    x / dim,
                    x % dim,
                    pos[x]
                );
            }
        }
    });
}

/// The displacement of wild inputs (speeds and headings with 1e308 and
/// f64::MAX errors, unbounded speeds, huge error bounds) holds the
/// displacement of the true inputs (an enclosure computed from point
/// intervals, which holds the true displacement), and is never empty.
#[test]
fn displacements_of_wild_inputs_hold_the_true_one() {
    each_case(cases(3000), 3, |rng, seed| {
        let dt = [1.0, 0.1, 1e-3, 1e3][rng.below(4)];
        let error = [0.0, 0.01, 1e300, 1e308, f64::MAX][rng.below(5)];
        let e_true = if error == 0.0 {
            0.0
        } else {
            rng.range(-1.0, 1.0) * error.min(1e300)
        };
        let pt = Interval::point;
        if rng.unit() < 0.5 {
            let (v, h) = (rng.range(-0.5, 3.0), rng.range(-10.0, 10.0));
            let speed = holding(rng, pt(v), 1.0);
            let heading = holding(rng, pt(h), 0.5);
            let d = unicycle_displacement(dt, speed, heading, error);
            let t = unicycle_displacement(dt, pt(v), pt(h), 0.0);
            for a in 0..2 {
                let t = t[a] + pt(e_true);
                assert!(
                    !d[a].is_empty() && t.is_subset(d[a]),
                    "seed {seed}: axis {a}: {:?} misses {t:?}",
                    d[a]
                );
            }
        } else {
            let angles: Vec<f64> = (0..3).map(|_| rng.range(-4.0, 4.0)).collect();
            let v: Vec<f64> = (0..3).map(|_| rng.range(-2.0, 2.0)).collect();
            let wide: Vec<Interval> = angles
                .iter()
                .chain(&v)
                .map(|&x| holding(rng, pt(x), 0.3))
                .collect();
            let d = auv_displacement(
                dt,
                wide[0],
                wide[1],
                wide[2],
                [wide[3], wide[4], wide[5]],
                error,
            );
            let t = auv_displacement(
                dt,
                pt(angles[0]),
                pt(angles[1]),
                pt(angles[2]),
                [pt(v[0]), pt(v[1]), pt(v[2])],
                0.0,
            );
            for a in 0..3 {
                let t = t[a] + pt(e_true);
                assert!(
                    !d[a].is_empty() && t.is_subset(d[a]),
                    "seed {seed}: axis {a}: {:?} misses {t:?}",
                    d[a]
                );
            }
        }
    });
}

// ----- exact planted geometry ----------------------------------------------

/// Integer offsets with an integer length: (offset, length).
const TRIPLES_2D: [([f64; 2], f64); 7] = [
    ([0.0, 0.0], 0.0),
    ([0.0, 1.0], 1.0),
    ([3.0, 4.0], 5.0),
    ([5.0, 12.0], 13.0),
    ([8.0, 15.0], 17.0),
    ([20.0, 21.0], 29.0),
    ([1.0, 0.0], 1.0),
];
const TRIPLES_3D: [([f64; 3], f64); 6] = [
    ([0.0, 0.0, 0.0], 0.0),
    ([0.0, 0.0, 1.0], 1.0),
    ([1.0, 2.0, 2.0], 3.0),
    ([2.0, 3.0, 6.0], 7.0),
    ([1.0, 4.0, 8.0], 9.0),
    ([4.0, 4.0, 7.0], 9.0),
];

/// A robot position p and a landmark l at the exact distance r (all exact
/// in f64, coordinates up to about 2^990): p = m·2^f, l = p + 2^e·t with
/// (t, |t|) an integer triple (signs and axes shuffled), e - f <= 40.
struct Exact {
    p: Vec<f64>,
    l: Vec<f64>,
    r: f64,
    /// Every coordinate is a multiple of 2^f.
    f: i32,
}

/// An integer offset t with its length, axes and signs shuffled.
fn triple(rng: &mut Rng, dim: usize) -> (Vec<f64>, f64) {
    let (t, len): (Vec<f64>, f64) = if dim == 2 {
        let (t, len) = TRIPLES_2D[rng.below(TRIPLES_2D.len())];
        (t.to_vec(), len)
    } else {
        let (t, len) = TRIPLES_3D[rng.below(TRIPLES_3D.len())];
        (t.to_vec(), len)
    };
    let mut t: Vec<f64> = t
        .iter()
        .map(|&x| if rng.unit() < 0.5 { -x } else { x })
        .collect();
    for i in (1..dim).rev() {
        t.swap(i, rng.below(i + 1));
    }
    (t, len)
}

/// Another robot position seeing the landmark of `x` at an exact distance:
/// `l - 2^e·t` with f <= e <= f + 30 (the coordinates of l are below
/// 2^45 · 2^f in magnitude, so the difference is exact).
fn another_view(rng: &mut Rng, x: &Exact, dim: usize) -> (Vec<f64>, f64) {
    let e = x.f + rng.below(31) as i32;
    let (t, len) = triple(rng, dim);
    let k = libm::ldexp(1.0, e);
    let p: Vec<f64> = (0..dim).map(|a| x.l[a] - t[a] * k).collect();
    assert!(
        (0..dim).all(|a| rat(p[a]) == rat(x.l[a]) - rat(t[a]) * rat(k)),
        "inexact view"
    );
    (p, len * k)
}

fn exact_pair(rng: &mut Rng, dim: usize, huge: bool) -> Exact {
    let e = if huge {
        rng.below(1000) as i32 - 60
    } else {
        rng.below(12) as i32 - 6
    };
    let f = e - rng.below(41) as i32;
    let scale = |k: i32| libm::ldexp(1.0, k);
    let (t, len) = triple(rng, dim);
    let p: Vec<f64> = (0..dim)
        .map(|_| (rng.below(1 << 20) as f64 - (1 << 19) as f64) * scale(f))
        .collect();
    let l: Vec<f64> = (0..dim).map(|a| p[a] + t[a] * scale(e)).collect();
    // Exact: both terms are multiples of 2^f below 2^53 · 2^f.
    assert!(
        (0..dim).all(|a| rat(l[a]) == rat(p[a]) + rat(t[a]) * rat(scale(e))),
        "inexact pair"
    );
    Exact {
        p,
        l,
        r: len * scale(e),
        f,
    }
}

fn boxes_holding(rng: &mut Rng, x: &[f64], w: f64) -> Vec<Interval> {
    x.iter()
        .map(|&c| holding(rng, Interval::point(c), w))
        .collect()
}

/// The distance contractor on exact truths (ranges equal to the true
/// distance, zero included, coordinates up to 2^990 whose squares
/// overflow) with unbounded and overflowing domains: the truth stays.
#[test]
fn distance_keeps_exact_truths_with_wild_domains() {
    each_case(cases(4000), 4, |rng, seed| {
        let dim = 2 + rng.below(2);
        let huge = rng.unit() < 0.3;
        let x = exact_pair(rng, dim, huge);
        let w = 1.0 + x.r;
        let mut p = boxes_holding(rng, &x.p, w);
        let mut l: Vec<Interval> = if rng.unit() < 0.3 {
            vec![Interval::ENTIRE; dim]
        } else {
            boxes_holding(rng, &x.l, w)
        };
        let mut r = holding(rng, Interval::point(x.r), w);
        let ok = contract_distance(&mut p, &mut l, &mut r);
        assert!(ok, "seed {seed}: emptied");
        assert!(r.contains(x.r), "seed {seed}: range {:e} lost: {r:?}", x.r);
        for a in 0..dim {
            assert!(
                p[a].contains(x.p[a]) && l[a].contains(x.l[a]),
                "seed {seed}: axis {a}: p {:?} / {:e}, l {:?} / {:e}",
                p[a],
                x.p[a],
                l[a],
                x.l[a]
            );
        }
    });
}

/// The bearing contractor with unbounded and overflowing headings,
/// bearings, ranges and boxes, on exact truths where the angle is exact
/// (the landmark straight ahead along the heading plus the bearing: cos 0
/// and sin 0 are exact) and on truths whose angle is enclosed by libm's
/// atan2 (within one ulp) widened by two ulps.
#[test]
fn bearing_keeps_truths_with_wild_domains() {
    each_case(cases(4000), 5, |rng, seed| {
        let dim = 2 + rng.below(2);
        let huge = rng.unit() < 0.3;
        let x = exact_pair(rng, dim, huge);
        let aligned = rng.unit() < 0.5;
        let (p_true, l_true, r_true, theta_true, beta) = if aligned {
            // l = p + (r, 0[, dz]) and θ + β = 0 exactly.
            let mut l = x.p.clone();
            l[0] += x.r;
            let exact = l[0] - x.r == x.p[0] && rat(l[0]) == rat(x.p[0]) + rat(x.r);
            if !exact || x.r == 0.0 {
                return;
            }
            let theta = rng.range(-7.0, 7.0);
            (x.p.clone(), l, x.r, theta, Interval::point(-theta))
        } else {
            let (dx, dy) = (x.l[0] - x.p[0], x.l[1] - x.p[1]);
            if dx == 0.0 && dy == 0.0 {
                return;
            }
            let phi = libm::atan2(dy, dx);
            let phi = Interval::new(phi.next_down().next_down(), phi.next_up().next_up());
            let theta = rng.range(-7.0, 7.0);
            (
                x.p.clone(),
                x.l.clone(),
                x.r,
                theta,
                phi - Interval::point(theta),
            )
        };
        let w = 1.0 + r_true;
        let mut p = boxes_holding(rng, &p_true, w);
        let mut l = boxes_holding(rng, &l_true, w);
        let heading = holding(rng, Interval::point(theta_true), 0.5);
        let bearing = holding(rng, beta, 0.5);
        let range = holding(rng, Interval::point(r_true), w);
        let ok = contract_bearing(&mut p, &mut l, heading, bearing, range);
        assert!(ok, "seed {seed}: emptied (aligned {aligned})");
        for a in 0..dim {
            assert!(
                p[a].contains(p_true[a]) && l[a].contains(l_true[a]),
                "seed {seed}: axis {a} (aligned {aligned}): p {:?} / {:e}, l {:?} / {:e}",
                p[a],
                p_true[a],
                l[a],
                l_true[a]
            );
        }
    });
}

// ----- shapes (shapes/shape.rs, region.rs, branch.rs) ----------------------

/// Two detections of one landmark from two exact positions, each shape
/// with a wild centre box, range and cut: never called disjoint (annulus
/// test or bisection); a box holding the landmark meets each shape and its
/// piece keeps the truth; a paving cut by both keeps the landmark, and a
/// branch against it keeps the truth.
#[test]
fn shapes_of_one_landmark_are_never_disjoint() {
    each_case(cases(3000), 6, |rng, seed| {
        let dim = 2 + rng.below(2);
        let huge = rng.unit() < 0.3;
        let a = exact_pair(rng, dim, huge);
        // A second position seeing the same landmark, exactly.
        let (p2, r2) = another_view(rng, &a, dim);
        let l = a.l.clone();
        let make = |rng: &mut Rng, p: &[f64], r: f64| {
            let w = 1.0 + r;
            let bearing = (dim == 2 && rng.unit() < 0.3).then(|| {
                (
                    Interval::ENTIRE,
                    holding(rng, Interval::new(-4.0, 4.0), 1.0),
                )
            });
            Shape::new(
                IntervalBox::new(&boxes_holding(rng, p, w)),
                holding(rng, Interval::point(r), w),
                bearing,
                if rng.unit() < 0.5 {
                    IntervalBox::entire(dim)
                } else {
                    IntervalBox::new(&boxes_holding(rng, &l, w))
                },
            )
        };
        let s1 = make(rng, &a.p, a.r);
        let s2 = make(rng, &p2, r2);
        assert!(
            !s1.disjoint(&s2) && !s2.disjoint(&s1),
            "seed {seed}: disjoint"
        );
        assert!(!disjoint_paved(&s1, &s2, 32), "seed {seed}: paved disjoint");
        let around = IntervalBox::new(&boxes_holding(rng, &l, 2.0));
        for (s, p) in [(&s1, &a.p), (&s2, &p2)] {
            let piece = s.contract_piece(around.axes());
            let piece = piece.unwrap_or_else(|| panic!("seed {seed}: a box holding l missed"));
            for i in 0..dim {
                assert!(
                    piece.d[i].contains(l[i]) && piece.p[i].contains(p[i]),
                    "seed {seed}: piece lost the truth"
                );
            }
            assert!(s.hull().contains(&l), "seed {seed}: hull");
        }
        let mut region = Paving::from_box(&s1.hull());
        region.cut(&s2);
        region.refine(&[&s1, &s2], 0.0, 32);
        assert!(region.contains(&l), "seed {seed}: region lost l");
        let br = branch(&s2, &[&region]);
        assert!(
            br.surviving == [0] && br.d.contains(&l) && br.p.contains(&p2),
            "seed {seed}: branch lost the truth"
        );
    });
}

// ----- registration (shapes/registration.rs) -------------------------------

/// The registration with wild witness boxes, pieces and position boxes
/// (unbounded, half-unbounded, overflowing, huge coordinates): the true
/// position stays and each group keeps its true landmark.
#[test]
fn registration_keeps_the_truth_with_wild_boxes() {
    each_case(cases(2000), 7, |rng, seed| {
        let dim = 2 + rng.below(2);
        let n = 1 + rng.below(5);
        let scale = if rng.unit() < 0.2 { 1e300 } else { 50.0 };
        let point =
            |rng: &mut Rng| -> Vec<f64> { (0..dim).map(|_| rng.range(-scale, scale)).collect() };
        let landmarks: Vec<Vec<f64>> = (0..n).map(|_| point(rng)).collect();
        let p_true = point(rng);
        let w = scale * rng.range(0.001, 0.2);
        let wild = |rng: &mut Rng, inner: Vec<Interval>| -> IntervalBox {
            let axes: Vec<Interval> = inner
                .into_iter()
                .map(|x| {
                    if rng.unit() < 0.3 {
                        holding(rng, x, w)
                    } else {
                        Interval::new(x.lo() - rng.range(0.0, w), x.hi() + rng.range(0.0, w))
                    }
                })
                .collect();
            IntervalBox::new(&axes)
        };
        let points =
            |x: &[f64]| -> Vec<Interval> { x.iter().map(|&c| Interval::point(c)).collect() };
        let witnesses: Vec<Vec<IntervalBox>> = landmarks
            .iter()
            .map(|l| {
                let mut boxes: Vec<IntervalBox> = (0..rng.below(3))
                    .map(|_| {
                        let elsewhere = point(rng);
                        wild(rng, points(&elsewhere))
                    })
                    .collect();
                let at = rng.below(boxes.len() + 1);
                boxes.insert(at, wild(rng, points(l)));
                boxes
            })
            .collect();
        let g = 1 + rng.below(6);
        let truth: Vec<usize> = (0..g).map(|_| rng.below(n)).collect();
        let groups: Vec<LocalGroup> = truth
            .iter()
            .map(|&a| {
                // L - p, enclosed by the interval subtraction.
                let rel: Vec<Interval> = (0..dim)
                    .map(|x| Interval::point(landmarks[a][x]) - Interval::point(p_true[x]))
                    .collect();
                let pieces = (0..1 + rng.below(2))
                    .map(|_| vec![wild(rng, rel.clone())])
                    .collect();
                LocalGroup {
                    pieces,
                    fixed: (rng.unit() < 0.3).then_some(a),
                }
            })
            .collect();
        let known: Vec<Vec<bool>> = (0..g)
            .map(|a| {
                (0..g)
                    .map(|b| truth[a] != truth[b] && rng.unit() < 0.5)
                    .collect()
            })
            .collect();
        let known = |a: usize, b: usize| known[a.min(b)][a.max(b)];
        let p = wild(rng, points(&p_true));
        let opts = RegisterOptions {
            max_boxes: 1 + rng.below(200),
            min_width: rng.range(0.0, 2.0),
            coarse: 1 + rng.below(12),
            map_budget: 1 + rng.below(2000),
        };
        let reg = register(&p, &witnesses, &groups, &known, &opts);
        assert!(
            reg.p.contains(&p_true),
            "seed {seed}: true p lost: {:?}",
            reg.p
        );
        for (i, &a) in truth.iter().enumerate() {
            assert!(
                reg.reach[i] & (1 << a) != 0,
                "seed {seed}: group {i} lost its landmark {a}"
            );
        }
    });
}

// ----- the shapes engine (shapes/round.rs, relative.rs, frames.rs) ---------

fn planted(rng: &mut Rng, dim: usize, layout: Layout, bearings: bool) -> Planted {
    let World {
        landmarks,
        truth_pos,
        headings,
    } = random_world(rng, dim, layout, 120);
    let (n, steps) = (landmarks.len(), headings.len());
    // Displacement boxes: the exact difference enclosed, widened by the
    // odometry error; a few unbounded or overflowing ones.
    let odo = rng.range(0.0, 0.3);
    let wild_steps = 1 + rng.below(3);
    let wild_at: Vec<usize> = (0..wild_steps).map(|_| rng.below(steps)).collect();
    let mut disp = Vec::with_capacity(steps * dim);
    for i in 0..steps {
        for a in 0..dim {
            let exact = Interval::point(truth_pos[i + 1][a]) - Interval::point(truth_pos[i][a]);
            disp.push(if wild_at.contains(&i) {
                match rng.below(5) {
                    0 => Interval::ENTIRE,
                    1 => Interval::new(exact.lo(), f64::INFINITY),
                    2 => Interval::new(f64::NEG_INFINITY, exact.hi()),
                    3 => exact.hull(Interval::centered(exact.mid(), f64::MAX)),
                    _ => exact.hull(Interval::centered(exact.mid(), 1e300)),
                }
            } else {
                Interval::new(
                    exact.lo() - rng.range(0.0, odo),
                    exact.hi() + rng.range(0.0, odo),
                )
            });
        }
    }
    let mut pos = vec![Interval::ENTIRE; (steps + 1) * dim];
    for a in 0..dim {
        pos[a] = Interval::new(-rng.range(0.0, 0.5), rng.range(0.0, 0.5));
    }
    sweep_forward(&mut pos, &disp, dim, 0, 0.0);
    let range_err = rng.range(0.0, 3.0);
    let bearing_err = rng.range(0.01, 0.5);
    let (mut dets, mut det, mut heading_at, mut matching) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for t in 0..=steps {
        if rng.unit() > 0.35 {
            continue;
        }
        let l = rng.below(n);
        let (p, lm) = (&truth_pos[t], &landmarks[l]);
        let points =
            |x: &[f64]| -> Vec<Interval> { x.iter().map(|&c| Interval::point(c)).collect() };
        // The true distance, enclosed; on the boundary of the range or not.
        let dist = distance_between(&points(p), &points(lm));
        let r = match rng.below(8) {
            0 => Interval::new(dist.lo(), f64::INFINITY),
            1 => Interval::new(0.0, f64::INFINITY),
            2 => Interval::new(0.0, dist.hi()),
            3 => dist.hull(Interval::centered(dist.mid(), 1e308)),
            4 => dist,
            _ => Interval::new(
                dist.lo() - rng.range(0.0, range_err),
                dist.hi() + rng.range(0.0, range_err),
            ),
        }
        .intersect(Interval::new(0.0, f64::INFINITY));
        let hd = headings[t.min(steps - 1)];
        let h_int = Interval::new(hd - rng.range(0.0, 0.05), hd + rng.range(0.0, 0.05));
        let mut d = json!({"step": t, "range": [bound(r.lo()), bound(r.hi())]});
        if bearings && (lm[0] != p[0] || lm[1] != p[1]) {
            let phi = libm::atan2(lm[1] - p[1], lm[0] - p[0]);
            let phi = Interval::new(phi.next_down().next_down(), phi.next_up().next_up());
            let beta = phi - Interval::point(hd);
            let b = if rng.unit() < 0.1 {
                beta.hull(Interval::centered(beta.mid(), 1e308))
            } else {
                Interval::new(
                    beta.lo() - rng.range(0.0, bearing_err),
                    beta.hi() + rng.range(0.0, bearing_err),
                )
            };
            d["bearing"] = json!([bound(b.lo()), bound(b.hi())]);
        }
        let mut b = IntervalBox::entire(dim);
        if dim == 3 {
            b[2] = Interval::new(lm[2] - rng.range(0.0, 1.0), lm[2] + rng.range(0.0, 1.0));
        }
        dets.push(d);
        det.push(b);
        heading_at.push(h_int);
        matching.push(l);
    }
    let (model, inputs) = if dim == 2 {
        (
            "unicycle2d",
            json!({"speed": {"value": vec![0.0; steps], "error": 0.0}, "heading": {"value": vec![0.0; steps], "error": 0.0}}),
        )
    } else {
        let z = json!({"value": vec![0.0; steps], "error": 0.0});
        (
            "auv3d",
            json!({"roll": z, "pitch": z, "yaw": z, "vx": z, "vy": z, "vz": z}),
        )
    };
    // n or more: "at most n" holds either way.
    let count = n + usize::from(rng.unit() < 0.2);
    let mission = Mission::from_value(&json!({
        "format": "nvector-mission/1",
        "model": model,
        "dt": 1.0,
        "steps": steps,
        "initial_position": vec![[0.0, 0.0]; dim],
        "inputs": inputs,
        "detections": dets,
        "landmark_count": count,
    }))
    .expect("valid mission");
    Planted {
        dim,
        mission,
        pos,
        disp,
        det,
        heading_at,
        truth_pos,
        landmarks,
        matching,
    }
}

/// The chain for the round: the sweeps it asks for, at once.
struct Sweeps<'a> {
    disp: &'a [Interval],
    dim: usize,
    changed: Vec<usize>,
}

impl Chain for Sweeps<'_> {
    fn sweep_forward(
        &mut self,
        pos: &mut [Interval],
        from: usize,
        to: usize,
    ) -> Result<bool, String> {
        let dim = self.dim;
        match sweep_forward(
            &mut pos[..(to + 1) * dim],
            &self.disp[..to * dim],
            dim,
            from,
            1e-9,
        ) {
            Sweep::Done(visited) => Ok(visited == to - from),
            Sweep::Empty(s) => Err(format!("chain emptied at {s}")),
        }
    }

    fn changed(&mut self, step: usize) {
        self.changed.push(step);
    }
}

/// Shapes rounds (regions, relative pairs, local frames, witnesses,
/// branches, registration) on planted missions with unbounded and
/// overflowing steps and ranges, in every layout, 2-D and 3-D, with and
/// without bearings: the truth stays, every union is true, nothing is
/// called infeasible.
#[test]
fn shapes_rounds_keep_the_truth_across_unbounded_steps() {
    let layouts = [Layout::Line, Layout::Ring, Layout::Random];
    each_case(cases(240), 8, |rng, seed| {
        let dim = 2 + rng.below(2);
        let layout = layouts[rng.below(3)];
        let bearings = rng.unit() < 0.5;
        let mut inst = planted(rng, dim, layout, bearings);
        let k = inst.mission.detections.len();
        let n = inst.mission.landmark_count;
        let mut state = ShapesState::new(k);
        state.options.max_boxes = 32;
        state.options.frames.max_boxes = 16;
        let mut uf = Uf::new(k);
        let why =
            |e: String| format!("seed {seed} ({layout:?}, {dim}-D, bearings {bearings}): {e}");
        for _ in 0..3 {
            let groups = uf.groups();
            inst.own_constraints(&groups).map_err(why).unwrap();
            inst.truth_inside().map_err(why).unwrap();
            let Planted {
                pos,
                disp,
                det,
                heading_at,
                mission,
                ..
            } = &mut inst;
            let mut chain = Sweeps {
                disp,
                dim,
                changed: Vec::new(),
            };
            let out = state.contract(
                mission,
                Domains {
                    dim,
                    pos,
                    det,
                    heading_at,
                    disp,
                },
                &groups,
                n,
                0,
                1e-9,
                &mut chain,
            );
            let changed = std::mem::take(&mut chain.changed);
            for t in changed {
                for s in [
                    sweep_forward(pos, disp, dim, t, 1e-9),
                    sweep_backward(pos, disp, dim, t, 1e-9),
                ] {
                    assert!(!matches!(s, Sweep::Empty(_)), "{}", why(format!("{s:?}")));
                }
            }
            assert!(
                out.infeasible.is_none(),
                "{}",
                why(format!("{:?}", out.infeasible))
            );
            for (a, b) in out.unions {
                assert_eq!(
                    inst.matching[a],
                    inst.matching[b],
                    "{}",
                    why(format!("grouped {a} and {b}"))
                );
                uf.union(a, b);
            }
            inst.truth_inside().map_err(why).unwrap();
        }
    });
}

// ----- the whole engine ----------------------------------------------------

/// Every association, `exact` included where it accepts the detections.
fn associations(k: usize) -> Vec<Association> {
    let mut v = vec![
        Association::None,
        Association::NVector(Contractor::Nvalue),
        Association::NVector(Contractor::Projection),
        Association::NVector(Contractor::Independent),
        Association::NVector(Contractor::Shapes),
        Association::NVector(Contractor::Best),
    ];
    if k <= 16 {
        v.push(Association::NVector(Contractor::Exact));
    }
    v
}

/// Makes a few steps of a simulated mission unbounded or overflowing, the
/// ways the mission format allows (every value keeps the truth): a speed of
/// `1e308 ± 1e308` ([0, +inf]) or `v ± 1e308`, a heading `± f64::MAX`, an
/// input sample of (-inf, inf), a motion error of f64::MAX, 1e308 or
/// 1e300, a range [lo, +inf] or [0, +inf].
fn make_wild(rng: &mut Rng, m: &mut Mission) -> String {
    let mut what = Vec::new();
    let n = m.steps;
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(n);
        match rng.below(7) {
            6 => {
                // A whole sample unbounded: "lo": "-inf", "hi": "inf".
                let channel = rng.below(m.inputs.len());
                m.inputs[channel][i] = Interval::ENTIRE;
                what.push(format!("an input at step {i} (-inf, inf)"));
            }
            0 => {
                let c = &mut m.inputs[if m.model.dim() == 2 { 0 } else { 3 }][i];
                *c = if c.lo() >= 0.0 {
                    c.hull(Interval::centered(1e308, 1e308))
                } else {
                    c.hull(Interval::centered(c.mid(), 1e308))
                };
                what.push(format!("speed[{i}] {c:?}"));
            }
            1 => {
                let c = &mut m.inputs[if m.model.dim() == 2 { 1 } else { 2 }][i];
                *c = c.hull(Interval::centered(c.mid(), f64::MAX));
                what.push(format!("heading[{i}] {c:?}"));
            }
            2 => {
                // Several consecutive steps, as a gap in the odometry.
                let e = [f64::MAX, 1e308, 1e300][rng.below(3)];
                let len = 1 + rng.below(30);
                for x in i..(i + len).min(n) {
                    m.motion_error[x] = m.motion_error[x].max(e);
                }
                what.push(format!("motion_error[{i}..+{len}] = {e:e}"));
            }
            3 => {
                m.motion_error[i] = f64::MAX;
                what.push(format!("motion_error[{i}] = MAX"));
            }
            _ => {
                if m.detections.is_empty() {
                    continue;
                }
                let j = rng.below(m.detections.len());
                let r = &mut m.detections[j].range;
                *r = if rng.unit() < 0.5 {
                    Interval::new(r.lo(), f64::INFINITY)
                } else {
                    Interval::new(0.0, f64::INFINITY)
                };
                what.push(format!("range[{j}] {r:?}"));
            }
        }
    }
    what.join(", ")
}

/// After a consistent run, the trajectory is a fixpoint of the motion
/// chain: a sweep with no tolerance from any step moves no bound by more
/// than a little above the tolerance (positions shrunk by the association
/// step and left unswept would move by much more).
fn chain_settled(s: &nvector_core::slam::result::Solution) -> Result<(), String> {
    let m = &s.model;
    let dim = m.dim;
    let mut pos = m.pos.clone();
    for from in 0..=m.steps {
        for forward in [true, false] {
            let out = if forward {
                sweep_forward(&mut pos, &m.disp, dim, from, 0.0)
            } else {
                sweep_backward(&mut pos, &m.disp, dim, from, 0.0)
            };
            if let Sweep::Empty(t) = out {
                return Err(format!("a sweep from {from} emptied p({t})"));
            }
        }
    }
    for (x, (a, b)) in m.pos.iter().zip(&pos).enumerate() {
        let moved = (b.lo() - a.lo()).max(a.hi() - b.hi());
        let slack = 1e-6 * (1.0 + a.mag().min(1e6));
        if moved > slack {
            return Err(format!(
                "p({})[{}] was not swept: {a:?} -> {b:?}",
                x / dim,
                x % dim
            ));
        }
    }
    Ok(())
}

/// The whole engine on simulated missions made wild (paper scenario in the
/// three layouts, with and without bearings; the 3-D AUV survey), every
/// association: consistent, the truth inside, no matching error, the
/// trajectory settled.
#[test]
fn the_engine_keeps_the_truth_across_unbounded_steps() {
    let layouts = [Layout::Line, Layout::Ring, Layout::Random];
    each_case(cases(100), 9, |rng, seed| {
        let auv = rng.unit() < 0.2;
        let mut o = SimulateOptions::new(
            if auv { Scenario::Auv } else { Scenario::Paper },
            rng.next(),
        );
        o.steps = Some(if auv {
            3000 + rng.below(5000)
        } else {
            1500 + rng.below(6500)
        });
        if !auv {
            o.layout = layouts[rng.below(3)];
            o.range_only = rng.unit() < 0.5;
            o.landmarks = Some(1 + rng.below(5));
            o.noise = rng.range(0.3, 2.0);
        }
        let mut m = Mission::from_value(&simulate(&o)).expect("valid");
        let what = make_wild(rng, &mut m);
        // Written as JSON and read back: the unbounded bounds survive
        // ("-inf" / "inf", not null).
        let m = Mission::from_value(&m.to_value()).expect("the wild mission, written back");
        let k = m.detections.len();
        for assoc in associations(k) {
            let options = SolveOptions {
                association: assoc,
                ..SolveOptions::default()
            };
            let s = solve_model(&m, &options, &mut |_| {}, &AtomicBool::new(false));
            let ctx = format!(
                "seed {seed} ({:?} {:?} range_only {}, {k} detections, {what}) {assoc:?}",
                o.scenario, o.layout, o.range_only
            );
            assert_eq!(s.status, SolveStatus::Consistent, "{ctx}");
            let (inside, errors, _) = score(&m, &s).expect("truth");
            assert!(inside, "{ctx}: truth lost");
            assert_eq!(errors, 0, "{ctx}: matching {:?}", s.matching);
            chain_settled(&s)
                .map_err(|e| format!("{ctx}: {e}"))
                .unwrap();
        }
    });
}

/// The three missions that found these faults, built in core (the CLI tests run them
/// through the binary): a 3-step, 2-landmark mission whose first step has
/// the unbounded speed and whose step 1 sees both landmarks at overlapping
/// ranges; 2 steps and one landmark across an unbounded step (and the same
/// with the operator's labels and an unbounded range); the paper scenario
/// (seed 3, 3,000 steps) with motion_error[1500] = f64::MAX.
#[test]
fn issue_19_missions_answer_consistently_under_every_contractor() {
    let three = json!({
        "format": "nvector-mission/1", "model": "unicycle2d", "dt": 1.0, "steps": 3,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [1e308, 1, 1], "error": [1e308, 0.01, 0.01]},
                   "heading": {"value": [0, 0, 0], "error": 0.01}},
        "detections": [{"step": 0, "range": [4.9, 5.1]}, {"step": 1, "range": [3.9, 4.6]},
                       {"step": 1, "range": [4.0, 4.7]}],
        "landmark_count": 2,
        "truth": {"positions": [[0, 0], [1, 0], [2, 0], [3, 0]], "landmarks": [[5, 0], [1, 4.5]],
                  "matching": [0, 0, 1]}
    });
    let two = json!({
        "format": "nvector-mission/1", "model": "unicycle2d", "dt": 1.0, "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [1e308, 1], "error": [1e308, 0.01]},
                   "heading": {"value": [0, 0], "error": 0.01}},
        "detections": [{"step": 0, "range": [4.9, 5.1]}, {"step": 2, "range": [4.0, 4.3]}],
        "landmark_count": 1,
        "truth": {"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[3, 4]], "matching": [0, 0]}
    });
    // The operator's group across the unbounded step, its second range
    // unbounded: p(2) keeps an infinite bound, which must not count as a
    // move in every round (the run must end consistent, not stopped).
    let half = json!({
        "format": "nvector-mission/1", "model": "unicycle2d", "dt": 1.0, "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {"speed": {"value": [1e308, 1], "error": [1e308, 0.01]},
                   "heading": {"value": [0, 0], "error": 0.01}},
        "detections": [{"step": 0, "range": [4.9, 5.1], "landmark": 0},
                       {"step": 2, "range": [4.0, "inf"], "landmark": 0}],
        "landmark_count": 1,
        "truth": {"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[3, 4]], "matching": [0, 0]}
    });
    let mut o = SimulateOptions::new(Scenario::Paper, 3);
    o.steps = Some(3000);
    let mut paper = simulate(&o);
    let e = paper["motion_error"].as_f64().expect("one number");
    let mut errors = vec![e; 3000];
    errors[1500] = f64::MAX;
    paper["motion_error"] = json!(errors);
    for (name, v) in [
        ("three", three),
        ("two", two),
        ("half", half),
        ("paper", paper),
    ] {
        let m = Mission::from_value(&v).expect("valid");
        for assoc in associations(m.detections.len()) {
            let options = SolveOptions {
                association: assoc,
                ..SolveOptions::default()
            };
            let s = solve_model(&m, &options, &mut |_| {}, &AtomicBool::new(false));
            assert_eq!(s.status, SolveStatus::Consistent, "{name} {assoc:?}");
            let (inside, errors, _) = score(&m, &s).expect("truth");
            assert!(inside && errors == 0, "{name} {assoc:?}: {:?}", s.matching);
        }
    }
}
