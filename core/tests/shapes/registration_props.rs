//! Soundness of the registration contractor (core/src/shapes/registration.rs)
//! on planted solutions: true landmarks inside their witness regions, the
//! true position inside its box, each local group's true relative landmark
//! (the interval difference of the true points, no margin) inside one of
//! its pieces' boxes, often on a bound, groups proved distinct only when their
//! landmarks differ. The true position must stay in the contracted box and
//! each group's true landmark among its candidates, whatever the tuning.
//! Tightness where the doc promises pruning: positions that only a map
//! sending two groups proved distinct to one witness admits are removed.
//!
//! `PROPTEST_CASES` sets the number of cases; seeds and persisted
//! failures: tests/common/mod.rs (`config`).

use nvector_core::shapes::registration::{register, LocalGroup, RegisterOptions};
use nvector_core::{Interval, IntervalBox};
use proptest::prelude::*;

use crate::common;
use common::Rng;

/// A box holding the true values enclosed by `x` (when `exact`; else a
/// decoy anywhere near them), each side at the enclosure (the truth within
/// an ulp of a bound: no margin) or up to `w` beyond it; both sides at it
/// on some axes now and then.
fn box_around(rng: &mut Rng, x: &[Interval], w: f64, exact: bool) -> IntervalBox {
    let axes: Vec<Interval> = x
        .iter()
        .map(|&c| {
            let (lo, hi) = if rng.unit() < 0.1 {
                (0.0, 0.0)
            } else {
                (rng.slack(0.3, w), rng.slack(0.3, w))
            };
            let c = if exact {
                c
            } else {
                Interval::point(c.mid() + rng.range(-3.0 * w, 3.0 * w))
            };
            // c.lo() - lo rounds to nearest, but never above c.lo().
            Interval::new(c.lo() - lo, c.hi() + hi)
        })
        .collect();
    IntervalBox::new(&axes)
}

/// Point intervals.
fn points(x: &[f64]) -> Vec<Interval> {
    x.iter().map(|&c| Interval::point(c)).collect()
}

/// `k` boxes, one of which holds the values enclosed by `x`, in random
/// order.
fn paving_holding(rng: &mut Rng, x: &[Interval], w: f64, k: usize) -> Vec<IntervalBox> {
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
                paving_holding(&mut rng, &points(l), w, k)
            })
            .collect();
        // Each group sees a landmark; pieces hold L - p.
        let truth: Vec<usize> = (0..g).map(|_| rng.below(n)).collect();
        let groups: Vec<LocalGroup> = truth
            .iter()
            .map(|&a| {
                // The interval difference L - p of the true points.
                let rel: Vec<Interval> = (0..dim).map(|x| Interval::point(landmarks[a][x]) - Interval::point(p_true[x])).collect();
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
        let p = box_around(&mut rng, &points(&p_true), scale, true);
        let opts = RegisterOptions { max_boxes, min_width, coarse, map_budget };
        let reg = register(&p, &witnesses, &groups, &|a, b| known[a][b], &opts);
        prop_assert!(reg.p.contains(&p_true), "seed {seed}: true p {:?} lost, result {:?}", p_true, reg.p);
        for (i, &a) in truth.iter().enumerate() {
            prop_assert!(reg.reach[i] & (1 << a) != 0, "seed {seed}: group {i} lost its landmark {a}: {:b}", reg.reach[i]);
        }
    }
}

/// Two landmarks at (0, 0) and (10, 0); the robot at (5, 5). Group 0 sees
/// the first at (-5, -5) in the robot's frame, but its piece also holds a
/// box at (5, -5); group 1 sees the second at (5, -5). The groups are
/// proved distinct. Sending both to the first landmark would place the
/// robot at (-5, 5) (both through the box at (5, -5)), and both to the
/// second at (5, 5): only the injectivity of the map on distinct groups
/// rules these out, and the registration must: the robot within a
/// bisection width of (5, 5), each group its own witness. Without the
/// distinct pair, (-5, 5) is admissible and must be kept, and either
/// group may see either landmark.
#[test]
fn injectivity_prunes_a_shared_witness() {
    let b2 = |x: (f64, f64), y: (f64, f64)| {
        IntervalBox::new(&[Interval::new(x.0, x.1), Interval::new(y.0, y.1)])
    };
    let witnesses = vec![
        vec![b2((-0.1, 0.1), (-0.1, 0.1))],
        vec![b2((9.9, 10.1), (-0.1, 0.1))],
    ];
    let groups = vec![
        LocalGroup {
            pieces: vec![vec![
                b2((-5.1, -4.9), (-5.1, -4.9)),
                b2((4.9, 5.1), (-5.1, -4.9)),
            ]],
            fixed: None,
        },
        LocalGroup {
            pieces: vec![vec![b2((4.9, 5.1), (-5.1, -4.9))]],
            fixed: None,
        },
    ];
    let p = b2((-30.0, 30.0), (-30.0, 30.0));
    let opts = RegisterOptions::default();
    let reg = register(&p, &witnesses, &groups, &|a, b| a != b, &opts);
    assert!(reg.p.contains(&[5.0, 5.0]), "{:?}", reg.p);
    assert!(
        reg.p[0].lo() > -5.0 + 1.0,
        "the shared witness is not pruned: {:?}",
        reg.p
    );
    assert_eq!(reg.reach, vec![0b01, 0b10]);
    let loose = register(&p, &witnesses, &groups, &|_, _| false, &opts);
    assert!(
        loose.p.contains(&[5.0, 5.0]) && loose.p.contains(&[-5.0, 5.0]),
        "{loose:?}"
    );
    assert_eq!(loose.reach, vec![0b11, 0b11]);
}

proptest! {
    #![proptest_config(common::config(500))]

    /// The case above, planted at random (2-D and 3-D, landmarks anywhere at
    /// least 8 m apart, local boxes the interval differences of the true
    /// points widened a little, extra unseen witnesses): with the two groups
    /// proved distinct, every position that only a map sending both to one
    /// witness admits is pruned; the truth is kept.
    #[test]
    fn injectivity_prunes_positions_only_shared_witnesses_allow(
        seed in any::<u64>(),
        three in any::<bool>(),
        n in 2usize..5,
    ) {
        let dim = if three { 3 } else { 2 };
        let mut rng = Rng::new(seed);
        let point = |rng: &mut Rng| -> Vec<f64> { (0..dim).map(|_| rng.range(-20.0, 20.0)).collect() };
        let mut landmarks: Vec<Vec<f64>> = Vec::new();
        while landmarks.len() < n {
            let l = point(&mut rng);
            if landmarks.iter().all(|m| (0..dim).map(|a| (m[a] - l[a]) * (m[a] - l[a])).sum::<f64>() > 64.0) {
                landmarks.push(l);
            }
        }
        let p_true = point(&mut rng);
        let w = rng.slack(0.5, 0.1);
        let bx = |c: &[Interval], w: f64| -> IntervalBox {
            let axes: Vec<Interval> = c.iter().map(|x| Interval::new(x.lo() - w, x.hi() + w)).collect();
            IntervalBox::new(&axes)
        };
        // Relative positions L - p: interval differences of the points.
        let rel = |l: &[f64]| -> Vec<Interval> { (0..dim).map(|a| Interval::point(l[a]) - Interval::point(p_true[a])).collect() };
        let witnesses: Vec<Vec<IntervalBox>> = landmarks.iter().map(|l| vec![bx(&points(l), w)]).collect();
        let (r0, r1) = (bx(&rel(&landmarks[0]), w), bx(&rel(&landmarks[1]), w));
        let groups = vec![
            LocalGroup { pieces: vec![vec![r0, r1.clone()]], fixed: None },
            LocalGroup { pieces: vec![vec![r1]], fixed: None },
        ];
        let p = IntervalBox::new(&vec![Interval::new(-70.0, 70.0); dim]);
        let opts = RegisterOptions { max_boxes: 4096, min_width: 0.25, ..RegisterOptions::default() };
        let reg = register(&p, &witnesses, &groups, &|a, b| a != b, &opts);
        prop_assert!(reg.p.contains(&p_true), "seed {seed}: the truth {:?} lost: {:?}", p_true, reg.p);
        prop_assert!(reg.reach[0] & 1 != 0 && reg.reach[1] & 2 != 0, "seed {seed}: {:?}", reg.reach);
        // The injective maps: g0 to y through its true box (y = 0 is the
        // truth) and g1 to z != y. The first box of g0 meets only at
        // W_y - r0 = p + W_y - W_0, the second g1's at p + W_z - W_1; both
        // within a few widths of one point only when W_y - W_0 = W_z - W_1,
        // false for distinct points 8 m apart unless y = 0, z = 1. Through
        // its decoy box g0 gives p + W_y - W_1, equal to g1's only for
        // y = z. So the truth is the only admissible position, and each
        // phantom p + W_x - W_1 (x != 1) of a shared witness x must be out.
        for x in (0..n).filter(|&x| x != 1) {
            let phantom: Vec<f64> = (0..dim).map(|a| p_true[a] + landmarks[x][a] - landmarks[1][a]).collect();
            prop_assert!(!reg.p.contains(&phantom), "seed {seed}: phantom {:?} of witness {x} kept: {:?} (truth {:?})", phantom, reg.p, p_true);
        }
    }
}
