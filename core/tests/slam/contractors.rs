//! Soundness of the SLAM contractors: a planted solution (true positions,
//! landmark, inputs drawn inside their intervals) survives every
//! contraction. Case count: `PROPTEST_CASES` (default 3000); seeds and
//! persisted failures: tests/common/mod.rs (`config`).

// The planted solutions are computed with the platform's f64 maths on purpose:
// an oracle independent of the libm-based code under test.
#![allow(clippy::disallowed_methods)]

use num_bigint::BigInt;
use num_rational::BigRational;
use nvector_core::contractors::bearing::contract_bearing;
use nvector_core::contractors::distance::contract_distance;
use nvector_core::contractors::motion_chain::{
    auv_displacement, sweep_backward, sweep_forward, unicycle_displacement, Sweep,
};
use nvector_core::shapes::shape::distance_between;
use nvector_core::Interval;
use proptest::prelude::*;

use crate::common;
use common::planted::bearing_enclosure;
use common::{enclose, holds, rat, taylor};

/// A coordinate: a small integer (exact distances, coincidences) or any
/// float.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![(-6i32..=6).prop_map(f64::from), -50.0..50.0f64]
}

/// The integer square root of `v` when `v` is the square of an integer.
fn integer_sqrt(v: &BigRational) -> Option<f64> {
    use num_traits::ToPrimitive;
    if !v.is_integer() {
        return None;
    }
    let n = v.to_integer();
    let r = n.sqrt();
    (&r * &r == n).then(|| r.to_f64().expect("small"))
}

/// Whether `r` (with `lo >= 0`) holds the square root of `sq >= 0`:
/// `lo^2 <= sq <= hi^2`, exactly.
fn holds_root(r: Interval, sq: &BigRational) -> bool {
    !r.is_empty()
        && (r.lo() <= 0.0 || rat(r.lo()) * rat(r.lo()) <= *sq)
        && (r.hi() == f64::INFINITY || *sq <= rat(r.hi()) * rat(r.hi()))
}

fn config() -> ProptestConfig {
    common::config(3000)
}

/// An interval around `x`: degenerate, touching (x at a bound), or wide,
/// sometimes unbounded.
fn around(x: f64) -> impl Strategy<Value = Interval> {
    (0u8..5, 0.0..5.0f64, 0.0..5.0f64).prop_map(move |(kind, a, b)| match kind {
        0 => Interval::point(x),
        1 => Interval::new(x, x + b),
        2 => Interval::new(x - a, x),
        3 => Interval::ENTIRE,
        _ => Interval::new(x - a, x + b),
    })
}

proptest! {
    #![proptest_config(config())]

    /// The range is the interval distance between the two true points
    /// (the project's own outward-rounded operations: the true distance is
    /// within an ulp of a bound), an exact point when the distance is an
    /// integer (coincident points: exactly [0, 0]), or that widened by a
    /// slack; boxes hold the points, often at a bound. The contracted
    /// range must still hold the exact distance (checked on its square
    /// with rationals), and the boxes the points.
    #[test]
    fn distance_keeps_the_planted_points(
        d in 1usize..=3,
        pa in proptest::collection::vec(coordinate(), 3),
        pb in proptest::collection::vec(coordinate(), 3),
        same in 0usize..4,
        exact_range in any::<bool>(),
        slack in prop_oneof![Just(0.0), 0.0..1.0f64],
        seed in proptest::collection::vec((0u8..5, 0.0..5.0f64, 0.0..5.0f64), 6),
    ) {
        // Points sharing `same` axes (all of them: coincident points).
        let pa = &pa[..d];
        let pb: Vec<f64> = (0..d).map(|i| if i < same { pa[i] } else { pb[i] }).collect();
        let exact_sq: BigRational = (0..d).map(|i| (rat(pa[i]) - rat(pb[i])) * (rat(pa[i]) - rat(pb[i]))).sum();
        let boxes = |p: &[f64]| -> Vec<Interval> { p.iter().map(|&x| Interval::point(x)).collect() };
        let enclosure = distance_between(&boxes(pa), &boxes(&pb));
        let root = integer_sqrt(&exact_sq);
        let r0 = match root {
            Some(k) if exact_range => Interval::point(k),
            _ => Interval::new((enclosure.lo() - slack).max(0.0), enclosure.hi() + slack),
        };
        prop_assert!(holds_root(r0, &exact_sq), "planted range {:?} misses the distance", r0);
        let mk = |x: f64, (kind, a, b): (u8, f64, f64)| match kind {
            0 => Interval::point(x),
            1 => Interval::new(x, x + b),
            2 => Interval::new(x - a, x),
            3 => Interval::ENTIRE,
            _ => Interval::new(x - a, x + b),
        };
        let mut a: Vec<Interval> = pa.iter().zip(&seed).map(|(&x, &s)| mk(x, s)).collect();
        let mut b: Vec<Interval> = pb.iter().zip(&seed[3..]).map(|(&x, &s)| mk(x, s)).collect();
        let mut r = r0;
        let ok = contract_distance(&mut a, &mut b, &mut r);
        prop_assert!(ok, "planted solution declared infeasible: {:?} {:?} {:?}", a, b, r0);
        for i in 0..d {
            prop_assert!(a[i].contains(pa[i]) && b[i].contains(pb[i]), "lost the planted point: a {:?} b {:?}", a, b);
        }
        prop_assert!(r.is_subset(r0), "the range grew: {:?} -> {:?}", r0, r);
        prop_assert!(holds_root(r, &exact_sq), "the range {:?} lost the distance sqrt({})", r, exact_sq);
    }

    /// Bearing on a truth at the boundary: the robot p and the landmark d
    /// are exact points (integers half of the time, sometimes coincident
    /// horizontally), the range their interval distance, the bearing
    /// libm's atan2 widened by a few ulps minus the heading (outward), each
    /// perhaps widened by a slack; p and d start in bounded boxes with the
    /// truth at a bound, or unbounded; 2-D and 3-D (slant range, d_z in a
    /// bounded box). Both points must survive.
    #[test]
    fn bearing_keeps_a_truth_on_the_boundary(
        three in any::<bool>(),
        p in proptest::collection::vec(coordinate(), 3),
        l in proptest::collection::vec(coordinate(), 3),
        same_xy in 0usize..5,
        theta in prop_oneof![Just(0.0), -4.0..4.0f64],
        w in prop_oneof![Just(0.0), 0.0..0.2f64],
        sides in proptest::collection::vec((0u8..4, 0.0..3.0f64), 12),
    ) {
        let dim = if three { 3 } else { 2 };
        let p = &p[..dim];
        // Now and then the landmark right above/below the robot (or on it).
        let l: Vec<f64> = (0..dim).map(|i| if same_xy == 0 && i < 2 { p[i] } else { l[i] }).collect();
        let pts = |x: &[f64]| -> Vec<Interval> { x.iter().map(|&c| Interval::point(c)).collect() };
        let range = distance_between(&pts(p), &pts(&l));
        let range = Interval::new((range.lo() - w).max(0.0), range.hi() + w);
        let bearing = bearing_enclosure(p, &l, theta);
        let bearing = Interval::new(bearing.lo() - w, bearing.hi());
        let heading = Interval::new(theta, theta + w);
        let side = |x: f64, (kind, s): (u8, f64)| match kind {
            0 => Interval::new(x, x + s),
            1 => Interval::new(x - s, x),
            2 => Interval::point(x),
            _ => Interval::ENTIRE,
        };
        let mut pb: Vec<Interval> = (0..dim).map(|i| side(p[i], sides[i])).collect();
        let mut db: Vec<Interval> = (0..dim).map(|i| side(l[i], sides[3 + i])).collect();
        let ok = contract_bearing(&mut pb, &mut db, heading, bearing, range);
        prop_assert!(ok, "planted bearing declared infeasible: p {:?} d {:?} range {:?} bearing {:?}", pb, db, range, bearing);
        for i in 0..dim {
            prop_assert!(pb[i].contains(p[i]) && db[i].contains(l[i]),
                "lost the truth p {:?} d {:?}: {:?} {:?} (range {:?}, bearing {:?})", p, l, pb, db, range, bearing);
        }
    }

    #[test]
    fn bearing_keeps_the_planted_points(
        px in -50.0..50.0f64, py in -50.0..50.0f64, pz in -5.0..5.0f64,
        theta in -4.0..4.0f64, beta in -3.2..3.2f64, rho in 0.0..60.0f64, dz in -10.0..10.0f64,
        three_d in any::<bool>(),
        w in 0.0..0.2f64,
        box_kind in 0u8..5,
    ) {
        // Landmark from the model, computed in f64; the intervals for θ, β
        // are widened by 1e-9 to cover the rounding of that computation.
        let phi = theta + beta;
        let dx = px + rho * phi.cos();
        let dy = py + rho * phi.sin();
        let (mut p, mut d, range): (Vec<Interval>, Vec<Interval>, Interval) = if three_d {
            let r = (rho * rho + dz * dz).sqrt();
            (vec![Interval::point(px), Interval::point(py), Interval::point(pz)],
             vec![Interval::ENTIRE, Interval::ENTIRE, Interval::point(pz + dz)],
             Interval::new(r * (1.0 - 1e-9) - w, r * (1.0 + 1e-9) + w))
        } else {
            (vec![Interval::point(px), Interval::point(py)], vec![Interval::ENTIRE, Interval::ENTIRE],
             Interval::new(rho * (1.0 - 1e-9) - w, rho * (1.0 + 1e-9) + w))
        };
        if box_kind == 1 {
            p[0] = Interval::new(px - w, px + w);
            p[1] = Interval::new(py - 1.0, py + w);
        }
        let heading = Interval::new(theta - 1e-9 - w, theta + 1e-9);
        let bearing = Interval::new(beta - 1e-9, beta + 1e-9 + w);
        prop_assert!(contract_bearing(&mut p, &mut d, heading, bearing, range));
        // The true landmark is within 1e-6 of the f64 one.
        prop_assert!(d[0].lo() <= dx + 1e-6 && dx - 1e-6 <= d[0].hi(), "d_x {:?} vs {}", d[0], dx);
        prop_assert!(d[1].lo() <= dy + 1e-6 && dy - 1e-6 <= d[1].hi(), "d_y {:?} vs {}", d[1], dy);
        prop_assert!(p[0].contains(px) && p[1].contains(py));
    }

    #[test]
    fn motion_chain_keeps_the_planted_trajectory(
        steps in 1usize..40,
        speeds in proptest::collection::vec(-1.0..3.0f64, 40),
        headings in proptest::collection::vec(-7.0..7.0f64, 40),
        err in prop_oneof![Just(0.0), 0.0..0.1f64],
        known_end in any::<bool>(),
        tol in prop_oneof![Just(0.0), Just(1e-9), Just(1e-3)],
    ) {
        // True trajectory integrated in f64 with the error absorbed by the
        // interval half-width 1e-9 around each input.
        let dt = 0.1;
        let mut truth = vec![[0.0f64, 0.0]];
        let mut disp = Vec::new();
        for i in 0..steps {
            let (v, h) = (speeds[i], headings[i]);
            let last = truth[i];
            truth.push([last[0] + dt * v * h.cos(), last[1] + dt * v * h.sin()]);
            let [dx, dy] = unicycle_displacement(dt, Interval::new(v - 1e-9, v + 1e-9), Interval::new(h - 1e-9, h + 1e-9), err + 1e-12);
            disp.push(dx);
            disp.push(dy);
        }
        let mut pos = vec![Interval::ENTIRE; 2 * (steps + 1)];
        pos[0] = Interval::point(0.0);
        pos[1] = Interval::point(0.0);
        if known_end {
            let t = truth[steps];
            pos[2 * steps] = Interval::new(t[0] - 0.01, t[0] + 0.01);
            pos[2 * steps + 1] = Interval::new(t[1] - 0.01, t[1] + 0.01);
        }
        prop_assert!(matches!(sweep_forward(&mut pos, &disp, 2, 0, tol), Sweep::Done(_)));
        prop_assert!(matches!(sweep_backward(&mut pos, &disp, 2, steps, tol), Sweep::Done(_)));
        for (i, t) in truth.iter().enumerate() {
            prop_assert!(pos[2 * i].contains(t[0]) && pos[2 * i + 1].contains(t[1]), "step {} lost: {:?} vs {:?}", i, &pos[2 * i..2 * i + 2], t);
        }
    }

    #[test]
    fn auv_displacement_holds_the_true_one(
        roll in -0.5..0.5f64, pitch in -0.5..0.5f64, yaw in -7.0..7.0f64,
        v in proptest::collection::vec(-2.0..2.0f64, 3),
        w in 0.0..0.05f64,
    ) {
        let (cf, sf, ct, st, cp, sp) = (roll.cos(), roll.sin(), pitch.cos(), pitch.sin(), yaw.cos(), yaw.sin());
        let r = [
            [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
            [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
            [-st, ct * sf, ct * cf],
        ];
        let dt = 0.1;
        let around = |x: f64| Interval::new(x - 1e-9 - w, x + 1e-9);
        let d = auv_displacement(dt, around(roll), around(pitch), around(yaw), [around(v[0]), around(v[1]), around(v[2])], 0.0);
        for a in 0..3 {
            let truth = dt * (r[a][0] * v[0] + r[a][1] * v[1] + r[a][2] * v[2]);
            prop_assert!(d[a].lo() <= truth + 1e-12 && truth - 1e-12 <= d[a].hi(), "axis {}: {:?} vs {}", a, d[a], truth);
        }
    }
}

proptest! {
    // Exact rationals and Taylor series: slower, fewer cases.
    #![proptest_config(common::config_div(3000, 12, 50))]

    /// The motion chain in 1, 2 and 3 dimensions on a truth that is not a
    /// float: positions k/den (den 3, 7 or 10), each displacement and the
    /// start the tightest f64 enclosure of the exact rational (a true value
    /// strictly inside an ulp-wide interval), the end known or not. After
    /// a forward and a backward sweep every position must hold its exact
    /// rational: a bound rounded to nearest instead of outwards is lost.
    #[test]
    fn motion_chain_keeps_a_rational_truth(
        dim in 1usize..=3,
        steps in 1usize..60,
        den in prop_oneof![Just(3i64), Just(7i64), Just(10i64)],
        start in proptest::collection::vec(-3000i64..3000, 3),
        moves in proptest::collection::vec(-40i64..40, 180),
        known_end in any::<bool>(),
        tol in prop_oneof![Just(0.0), Just(1e-9)],
    ) {
        let q = |k: i64| BigRational::new(BigInt::from(k), BigInt::from(den));
        let mut truth: Vec<Vec<i64>> = vec![start[..dim].to_vec()];
        for i in 0..steps {
            let last = truth[i].clone();
            truth.push((0..dim).map(|a| last[a] + moves[i * 3 + a]).collect());
        }
        let mut disp = Vec::with_capacity(steps * dim);
        for w in truth.windows(2) {
            for (next, last) in w[1].iter().zip(&w[0]) {
                disp.push(enclose(&q(next - last)));
            }
        }
        let mut pos = vec![Interval::ENTIRE; dim * (steps + 1)];
        for a in 0..dim {
            pos[a] = enclose(&q(truth[0][a]));
            if known_end {
                pos[steps * dim + a] = enclose(&q(truth[steps][a]));
            }
        }
        prop_assert!(matches!(sweep_forward(&mut pos, &disp, dim, 0, tol), Sweep::Done(_)));
        prop_assert!(matches!(sweep_backward(&mut pos, &disp, dim, steps, tol), Sweep::Done(_)));
        for (i, t) in truth.iter().enumerate() {
            for a in 0..dim {
                prop_assert!(holds(pos[i * dim + a], &q(t[a])), "step {} axis {}: {:?} lost {}/{}", i, a, pos[i * dim + a], t[a], den);
            }
        }
    }

    /// The displacement of a unicycle step at the boundary of its error:
    /// speed and heading exact points, the true displacement
    /// `dt·v·(cos h, sin h) + (ex, ey)` with each error -e, 0 or +e
    /// exactly, cos and sin enclosed by a rigorous Taylor series. The
    /// interval displacement must hold it.
    #[test]
    fn unicycle_displacement_holds_the_truth_at_its_error_bound(
        v in prop_oneof![Just(0.0), -3.0..3.0f64],
        h in prop_oneof![Just(0.0), -7.0..7.0f64],
        e in prop_oneof![Just(0.0), 0.0..0.5f64],
        ex in -1i32..=1,
        ey in -1i32..=1,
        dt in prop_oneof![Just(1.0), Just(0.1), 0.01..1.0f64],
    ) {
        let d = unicycle_displacement(dt, Interval::point(v), Interval::point(h), e);
        let scale = rat(dt) * rat(v);
        for (axis, cosine, sign) in [(0, true, ex), (1, false, ey)] {
            let (lo, hi) = taylor(&rat(h), cosine);
            let (a, b) = (&scale * &lo, &scale * &hi);
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            let err = rat(e) * BigRational::from_integer(BigInt::from(sign));
            prop_assert!(rat(d[axis].lo()) <= &a + &err && &b + &err <= rat(d[axis].hi()),
                "axis {}: {:?} misses dt v {} + {:?}", axis, d[axis], if cosine { "cos h" } else { "sin h" }, err);
        }
    }
}

#[test]
fn around_strategy_is_used() {
    // Keeps the helper strategy compiled and checked: it always holds x.
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    for _ in 0..100 {
        let x = around(1.5).new_tree(&mut runner).unwrap().current();
        assert!(x.contains(1.5));
    }
}
