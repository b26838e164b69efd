//! Soundness of the registration contractor (core/src/shapes/registration.rs)
//! on planted solutions: true landmarks inside their witness regions, the
//! true position inside its box, each local group's true relative landmark
//! inside one of its pieces' boxes, groups proved distinct only when their
//! landmarks differ. The true position must stay in the contracted box and
//! each group's true landmark among its candidates, whatever the tuning.
//!
//! `PROPTEST_CASES` sets the number of cases; seeds and persisted
//! failures: tests/common/mod.rs (`config`).

use nvector_core::shapes::registration::{register, LocalGroup, RegisterOptions};
use nvector_core::{Interval, IntervalBox};
use proptest::prelude::*;

mod common;
use common::Rng;

/// A box holding point `x` (or, when `x` is None, anywhere near `centre`),
/// half-widths up to `w`; a zero width on some axes now and then.
fn box_around(rng: &mut Rng, x: &[f64], w: f64, exact: bool) -> IntervalBox {
    let axes: Vec<Interval> = x
        .iter()
        .map(|&c| {
            let (lo, hi) = if rng.unit() < 0.1 {
                (0.0, 0.0)
            } else {
                (rng.range(0.0, w), rng.range(0.0, w))
            };
            let c = if exact {
                c
            } else {
                c + rng.range(-3.0 * w, 3.0 * w)
            };
            // Generator rounding: widen by a relative margin.
            let m = 1e-9 * (1.0 + c.abs());
            Interval::new(c - lo - m, c + hi + m)
        })
        .collect();
    IntervalBox::new(&axes)
}

/// `k` boxes, one of which holds `x`, in random order.
fn paving_holding(rng: &mut Rng, x: &[f64], w: f64, k: usize) -> Vec<IntervalBox> {
    let at = rng.below(k);
    (0..k).map(|i| box_around(rng, x, w, i == at)).collect()
}

proptest! {
    #![proptest_config(common::config(2000))]

    #[test]
    fn registration_keeps_the_planted_solution(
        seed in any::<u64>(),
        three in any::<bool>(),
        n in 1usize..7,
        g in 1usize..9,
        scale in 0.5..60.0f64,
        density in 0.0..1.0f64,
        max_boxes in 1usize..300,
        coarse in 1usize..20,
        map_budget in 1usize..3000,
        min_width in 0.0..5.0f64,
    ) {
        let dim = if three { 3 } else { 2 };
        let mut rng = Rng::new(seed);
        let point = |rng: &mut Rng| -> Vec<f64> { (0..dim).map(|_| rng.range(-scale, scale)).collect() };
        let landmarks: Vec<Vec<f64>> = (0..n).map(|_| point(&mut rng)).collect();
        let p_true = point(&mut rng);
        let w = scale * rng.range(0.01, 0.5);
        let witnesses: Vec<Vec<IntervalBox>> = landmarks
            .iter()
            .map(|l| {
                let k = 1 + rng.below(6);
                paving_holding(&mut rng, l, w, k)
            })
            .collect();
        // Each group sees a landmark; pieces hold L - p.
        let truth: Vec<usize> = (0..g).map(|_| rng.below(n)).collect();
        let groups: Vec<LocalGroup> = truth
            .iter()
            .map(|&a| {
                let rel: Vec<f64> = (0..dim).map(|x| landmarks[a][x] - p_true[x]).collect();
                let pieces = (0..1 + rng.below(3))
                    .map(|_| {
                        let k = 1 + rng.below(6);
                        paving_holding(&mut rng, &rel, w, k)
                    })
                    .collect();
                LocalGroup { pieces, fixed: (rng.unit() < 0.3).then_some(a) }
            })
            .collect();
        let distinct_pairs: Vec<Vec<bool>> = (0..g)
            .map(|a| (0..g).map(|b| truth[a] != truth[b]).collect())
            .collect();
        // Symmetric random subset of the true distinct pairs.
        let mut known = vec![vec![false; g]; g];
        for a in 0..g {
            for b in a + 1..g {
                if distinct_pairs[a][b] && rng.unit() < density {
                    known[a][b] = true;
                    known[b][a] = true;
                }
            }
        }
        let p = box_around(&mut rng, &p_true, scale, true);
        let opts = RegisterOptions { max_boxes, min_width, coarse, map_budget };
        let reg = register(&p, &witnesses, &groups, &|a, b| known[a][b], &opts);
        prop_assert!(reg.p.contains(&p_true), "seed {seed}: true p {:?} lost, result {:?}", p_true, reg.p);
        for (i, &a) in truth.iter().enumerate() {
            prop_assert!(reg.reach[i] & (1 << a) != 0, "seed {seed}: group {i} lost its landmark {a}: {:b}", reg.reach[i]);
        }
    }
}
