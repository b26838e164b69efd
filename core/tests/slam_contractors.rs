//! Soundness of the SLAM contractors: a planted solution (true positions,
//! landmark, inputs drawn inside their intervals) survives every
//! contraction. Case count: `NVECTOR_PROPTEST_CASES` (default 3000).

// The planted solutions are computed with the platform's f64 maths on purpose:
// an oracle independent of the libm-based code under test.
#![allow(clippy::disallowed_methods)]

use nvector_core::slam::bearing::contract_bearing;
use nvector_core::slam::distance::contract_distance;
use nvector_core::slam::motion_chain::{
    auv_displacement, sweep_backward, sweep_forward, unicycle_displacement, Sweep,
};
use nvector_core::Interval;
use proptest::prelude::*;

fn config() -> ProptestConfig {
    let cases = std::env::var("NVECTOR_PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000u32);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
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

fn exact_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn distance_keeps_the_planted_points(
        d in 2usize..=3,
        pa in proptest::collection::vec(-50.0..50.0f64, 3),
        pb in proptest::collection::vec(-50.0..50.0f64, 3),
        slack in prop_oneof![Just(0.0), 0.0..1.0f64],
        seed in proptest::collection::vec((0u8..5, 0.0..5.0f64, 0.0..5.0f64), 6),
    ) {
        let (pa, pb) = (&pa[..d], &pb[..d]);
        let dist = exact_distance(pa, pb);
        // The range holds the true distance: enclose the f64 computation
        // generously (relative 1e-12), plus a random slack.
        let r0 = Interval::new(dist * (1.0 - 1e-12) - slack, dist * (1.0 + 1e-12) + slack);
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
        prop_assert!(ok, "planted solution declared infeasible");
        for i in 0..d {
            prop_assert!(a[i].contains(pa[i]) && b[i].contains(pb[i]), "lost the planted point: a {:?} b {:?}", a, b);
        }
        prop_assert!(r.contains(dist) || r0.contains(dist) && r.is_subset(r0));
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
