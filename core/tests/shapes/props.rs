//! Soundness of the detection-shape contractors (core/src/shapes/) on
//! planted solutions: true landmarks, true positions inside their boxes,
//! ranges and bearings holding the truth, in ring, random and line layouts,
//! 2-D and 3-D. No contractor may lose a true point, group two detections
//! of different landmarks, or call a consistent instance infeasible.
//! The truth sits on the boundary: displacements and ranges are the
//! interval differences and distances of the true points (no margin),
//! boxes often have the truth as a bound; tangent and coincident shapes
//! (ranges of exactly 0, touching centre boxes) are generated on purpose.
//!
//! `PROPTEST_CASES` sets the number of cases; seeds and persisted
//! failures: tests/common/mod.rs (`config`).

// Axes and detections index several parallel arrays at once.
#![allow(clippy::needless_range_loop)]

use nvector_core::contractors::motion_chain::{sweep_backward, sweep_forward, Sweep};
use nvector_core::shapes::branch::branch;
use nvector_core::shapes::chain_sums::ChainSums;
use nvector_core::shapes::distinct::{Distinct, Uf};
use nvector_core::shapes::region::Paving;
use nvector_core::shapes::relative_pairs::relative_pairs;
use nvector_core::shapes::shape::{disjoint_paved, distance_between, Shape};
use nvector_core::shapes::witnesses::{find_witnesses, Item};
use nvector_core::slam::association::{sightings, Chain, Domains, ShapesState};
use nvector_core::slam::mission::Mission;
use nvector_core::{Interval, IntervalBox};
use proptest::prelude::*;
use serde_json::json;

use crate::common;
use common::planted::bearing_enclosure;
use common::world::{random_world, Planted, World};
use common::Rng;
use nvector_core::slam::simulate::Layout;

/// An interval holding the exact float `x` (a true position, landmark or
/// heading), `below` and `above` it: no margin, the truth is at a bound
/// when a side is 0 (`x - below` rounds to nearest, but stays <= x).
fn around(x: f64, below: f64, above: f64) -> Interval {
    Interval::new(x - below, x + above)
}

/// The enclosure `x` of a derived true value (computed with the project's
/// outward-rounded operations, so the truth is within an ulp of a bound),
/// widened by `below` and `above`.
fn widen(x: Interval, below: f64, above: f64) -> Interval {
    Interval::new(x.lo() - below, x.hi() + above)
}

/// A point box.
fn points(x: &[f64]) -> Vec<Interval> {
    x.iter().map(|&c| Interval::point(c)).collect()
}

fn planted(seed: u64, dim: usize, layout: Layout, bearings: bool) -> Planted {
    let mut rng = Rng::new(seed);
    let World {
        landmarks,
        truth_pos,
        headings,
    } = random_world(&mut rng, dim, layout, 150);
    let (n, steps) = (landmarks.len(), headings.len());
    let odo = rng.range(0.0, 0.3);
    let mut disp = Vec::with_capacity(steps * dim);
    for i in 0..steps {
        for a in 0..dim {
            // The interval difference of the true positions: the true
            // displacement is within an ulp of its bounds.
            let d = Interval::point(truth_pos[i + 1][a]) - Interval::point(truth_pos[i][a]);
            disp.push(widen(d, rng.slack(0.5, odo), rng.slack(0.5, odo)));
        }
    }
    let mut pos = vec![Interval::ENTIRE; (steps + 1) * dim];
    for a in 0..dim {
        pos[a] = around(0.0, rng.slack(0.5, 0.5), rng.slack(0.5, 0.5));
    }
    sweep_forward(&mut pos, &disp, dim, 0, 0.0);
    // Detections: some steps see one landmark (random, or the nearest).
    let range_err = rng.range(0.05, 4.0);
    let bearing_err = rng.range(0.01, 0.5);
    let mut dets = Vec::new();
    let mut det = Vec::new();
    let mut heading_at = Vec::new();
    let mut matching = Vec::new();
    let region = rng.unit() < 0.3;
    for t in 1..=steps {
        if rng.unit() > 0.35 {
            continue;
        }
        let l = rng.below(n);
        let (p, lm) = (&truth_pos[t], &landmarks[l]);
        // The interval distance between the true points.
        let dist = distance_between(&points(p), &points(lm));
        let r = widen(dist, rng.slack(0.5, range_err), rng.slack(0.5, range_err));
        let r = r.intersect(Interval::new(0.0, f64::INFINITY));
        let hd = headings[(t).min(steps - 1)];
        let h_int = around(hd, rng.slack(0.5, 0.05), rng.slack(0.5, 0.05));
        let mut d = json!({"step": t, "range": [r.lo(), r.hi()]});
        if bearings {
            let b = widen(
                bearing_enclosure(p, lm, hd),
                rng.slack(0.5, bearing_err),
                rng.slack(0.5, bearing_err),
            );
            d["bearing"] = json!([b.lo(), b.hi()]);
        }
        let mut b = IntervalBox::entire(dim);
        if region {
            for a in 0..dim {
                b[a] = around(lm[a], rng.slack(0.3, 20.0), rng.slack(0.3, 20.0));
            }
        }
        if dim == 3 {
            b[2] = b[2].intersect(around(lm[2], rng.slack(0.3, 1.0), rng.slack(0.3, 1.0)));
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
    let mission = Mission::from_value(&json!({
        "format": "nvector-mission/1",
        "model": model,
        "dt": 1.0,
        "steps": steps,
        "initial_position": vec![[0.0, 0.0]; dim],
        "inputs": inputs,
        "detections": dets,
        "landmark_count": n,
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

trait PlantedShape {
    fn shape(&self, j: usize) -> Shape;
}

impl PlantedShape for Planted {
    fn shape(&self, j: usize) -> Shape {
        let d = &self.mission.detections[j];
        let t = d.step;
        Shape::new(
            IntervalBox::new(&self.pos[t * self.dim..(t + 1) * self.dim]),
            d.range,
            d.bearing.map(|b| (self.heading_at[j], b)),
            self.det[j].clone(),
        )
    }
}

/// The chain for the round: sweeps at once, both ways, to the end.
struct Sweeps<'a> {
    disp: &'a [Interval],
    dim: usize,
    failed: Option<String>,
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

    fn changed(&mut self, _step: usize) {}
}

impl Sweeps<'_> {
    fn settle(&mut self, pos: &mut [Interval], steps: &[usize]) {
        for &t in steps {
            for s in [
                sweep_forward(pos, self.disp, self.dim, t, 1e-9),
                sweep_backward(pos, self.disp, self.dim, t, 1e-9),
            ] {
                if let Sweep::Empty(s) = s {
                    self.failed = Some(format!("chain emptied at {s}"));
                }
            }
        }
    }
}

fn layout(i: u8) -> Layout {
    [Layout::Line, Layout::Ring, Layout::Random][i as usize % 3]
}

proptest! {
    #![proptest_config(common::config(600))]

    /// The shapes round, iterated with the detections' own constraints as
    /// a propagator would: the truth stays inside, groups are true, no
    /// infeasibility.
    #[test]
    fn rounds_keep_the_planted_solution(seed in any::<u64>(), three in any::<bool>(), lay in 0u8..3, bearings in any::<bool>()) {
        let dim = if three { 3 } else { 2 };
        let mut inst = planted(seed, dim, layout(lay), bearings);
        let k = inst.mission.detections.len();
        let n = inst.mission.landmark_count;
        let mut state = ShapesState::new(k);
        state.options.max_boxes = 64;
        state.options.frames.max_boxes = 24;
        let mut uf = Uf::new(k);
        for _ in 0..4 {
            let groups = uf.groups();
            inst.own_constraints(&groups).map_err(TestCaseError::fail)?;
            inst.truth_inside().map_err(TestCaseError::fail)?;
            let Planted { pos, disp, det, heading_at, mission, .. } = &mut inst;
            let mut chain = Sweeps { disp, dim, failed: None };
            let out = state.contract(
                mission,
                Domains { dim, pos, det, heading_at, disp },
                &groups,
                n,
                0,
                1e-9,
                &mut chain,
            );
            let steps: Vec<usize> = mission.detections.iter().map(|d| d.step).collect();
            chain.settle(pos, &steps);
            prop_assert!(chain.failed.is_none(), "seed {seed}: {:?}", chain.failed);
            prop_assert!(out.infeasible.is_none(), "seed {seed}: {:?}", out.infeasible);
            for (a, b) in out.unions {
                prop_assert_eq!(inst.matching[a], inst.matching[b], "seed {} grouped {} and {}", seed, a, b);
                uf.union(a, b);
            }
            inst.truth_inside().map_err(|e| TestCaseError::fail(format!("seed {seed}: {e}")))?;
        }
    }

    /// Pairwise tests against the truth: two shapes holding one true
    /// landmark are never "disjoint"; a box holding a detection's true
    /// landmark always meets its shape, and its piece keeps the true
    /// (position, landmark); relative pairs are always true pairs.
    #[test]
    fn shape_tests_keep_the_truth(seed in any::<u64>(), three in any::<bool>(), lay in 0u8..3, bearings in any::<bool>()) {
        let dim = if three { 3 } else { 2 };
        let inst = planted(seed, dim, layout(lay), bearings);
        let k = inst.mission.detections.len();
        let shapes: Vec<Shape> = (0..k).map(|j| inst.shape(j)).collect();
        let mut rng = Rng::new(seed ^ 0xABCD);
        for j in 0..k {
            let l = &inst.landmarks[inst.matching[j]];
            let t = inst.mission.detections[j].step;
            let mut b = IntervalBox::point(l);
            for a in 0..dim {
                b[a] = around(l[a], rng.slack(0.3, 3.0), rng.slack(0.3, 3.0));
            }
            let piece = shapes[j].contract_piece(b.axes());
            prop_assert!(piece.is_some(), "seed {seed}: det {j} misses a box holding its landmark");
            let piece = piece.expect("some");
            for a in 0..dim {
                prop_assert!(piece.d[a].contains(l[a]) && piece.p[a].contains(inst.truth_pos[t][a]), "seed {seed}: piece of {j} lost the truth");
            }
            prop_assert!(shapes[j].hull().contains(l));
            for i in 0..j {
                if inst.matching[i] == inst.matching[j] {
                    prop_assert!(!shapes[i].disjoint(&shapes[j]), "seed {seed}: {i} {j} same landmark, called disjoint");
                    prop_assert!(!disjoint_paved(&shapes[i], &shapes[j], 64), "seed {seed}: {i} {j} same landmark, paved disjoint");
                }
            }
        }
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by_key(|&j| (inst.mission.detections[j].step, j));
        let sums = ChainSums::new(&inst.disp, dim);
        let mut pairs = Vec::new();
        relative_pairs(&sightings(&inst.mission), &order, dim, &sums, &inst.pos, &inst.det, &inst.heading_at, 64, &mut pairs);
        for (a, b) in pairs {
            prop_assert_ne!(inst.matching[a as usize], inst.matching[b as usize], "seed {} relative pair {} {}", seed, a, b);
        }
        // Relative displacements hold the true ones.
        for _ in 0..20 {
            let (s, t) = (rng.below(inst.truth_pos.len()), rng.below(inst.truth_pos.len()));
            let d = sums.delta(s, t);
            for a in 0..dim {
                prop_assert!(d[a].contains(inst.truth_pos[t][a] - inst.truth_pos[s][a]), "seed {seed}: delta({s}, {t})");
            }
        }
    }

    /// Landmark regions and branches: a group's paving keeps its true
    /// landmark; a branch against the true regions keeps the truth and
    /// the true region; witnesses never number more than the landmarks.
    #[test]
    fn regions_and_branches_keep_the_truth(seed in any::<u64>(), three in any::<bool>(), lay in 0u8..3, bearings in any::<bool>()) {
        let dim = if three { 3 } else { 2 };
        let inst = planted(seed, dim, layout(lay), bearings);
        let k = inst.mission.detections.len();
        let n = inst.landmarks.len();
        let shapes: Vec<Shape> = (0..k).map(|j| inst.shape(j)).collect();
        let mut regions: Vec<Paving> = Vec::new();
        for l in 0..n {
            let members: Vec<&Shape> = (0..k).filter(|&j| inst.matching[j] == l).map(|j| &shapes[j]).collect();
            let mut p = match members.first() {
                Some(s) => Paving::from_box(&s.hull()),
                None => Paving::from_box(&IntervalBox::point(&inst.landmarks[l])),
            };
            for s in &members {
                p.cut(s);
            }
            p.refine(&members, 0.0, 64);
            prop_assert!(p.contains(&inst.landmarks[l]), "seed {seed}: region {l} lost its landmark");
            regions.push(p);
        }
        let refs: Vec<&Paving> = regions.iter().collect();
        for j in 0..k {
            let br = branch(&shapes[j], &refs);
            let l = inst.matching[j];
            let t = inst.mission.detections[j].step;
            prop_assert!(br.surviving.contains(&l), "seed {seed}: det {j} lost its region");
            prop_assert!(br.d.contains(&inst.landmarks[l]) && br.p.contains(&inst.truth_pos[t]), "seed {seed}: branch of {j} lost the truth");
        }
        let items: Vec<Item> = shapes.iter().map(Item::Shape).chain(regions.iter().map(Item::Region)).collect();
        let sizes: Vec<(u8, f64)> = items.iter().map(|i| i.size()).collect();
        let w = find_witnesses(&sizes, &mut |a, b| items[a].disjoint(&items[b]), n + 1, &[], 10_000);
        prop_assert!(w.len() <= n, "seed {seed}: {} witnesses for {n} landmarks", w.len());
    }

    /// The clique rule on true distinct pairs never groups two landmarks
    /// and never calls them infeasible.
    #[test]
    fn the_clique_rule_keeps_the_truth(seed in any::<u64>(), n in 1usize..6, k in 1usize..60, density in 0.05..1.0f64) {
        let mut rng = Rng::new(seed);
        let truth: Vec<usize> = (0..k).map(|_| rng.below(n)).collect();
        let mut d = Distinct::default();
        for a in 0..k {
            for b in a + 1..k {
                if truth[a] != truth[b] && rng.unit() < density {
                    d.add([(a as u32, b as u32)]);
                }
            }
        }
        let mut uf = Uf::new(k);
        // Some true groups to start from.
        for _ in 0..k / 4 {
            let (a, b) = (rng.below(k), rng.below(k));
            if truth[a] == truth[b] {
                uf.union(a, b);
            }
        }
        let u = d.infer(&mut uf, n, 100_000);
        prop_assert!(u.is_ok(), "seed {seed}: {:?}", u);
        for g in uf.groups() {
            for &j in &g {
                prop_assert_eq!(truth[j], truth[g[0]], "seed {}", seed);
            }
        }
    }
}

/// A box holding `p`: each side at `p` (degenerate or touching) or up to
/// `w` away, zero widths often.
fn box_holding(rng: &mut Rng, p: &[f64], w: f64) -> IntervalBox {
    let axes: Vec<Interval> = p
        .iter()
        .map(|&c| around(c, rng.slack(0.5, w), rng.slack(0.5, w)))
        .collect();
    IntervalBox::new(&axes)
}

/// The integer square root of `d2` when it is the square of an integer.
fn exact_root(d2: f64) -> Option<f64> {
    let r = libm::sqrt(d2).round();
    (r * r == d2).then_some(r)
}

proptest! {
    #![proptest_config(common::config(2000))]

    /// Two detections of one landmark L at the boundary: the robot boxes
    /// hold the true positions (often at a bound, often degenerate, often
    /// touching), the ranges hold the true distances exactly on their
    /// bounds (an exact point when the distance is an integer, `[0, 0]`
    /// when the robot is on L; else the interval distance between the point
    /// boxes), coordinates on a 3-point integer grid so that coincident
    /// points and tangent shapes are frequent, 2-D and 3-D, sometimes a
    /// bearing, cuts unbounded or boxes with L on a bound. The two shapes
    /// share L: never "disjoint" (annulus tests or paving), each meets L's
    /// point box, keeps the truth in its piece, and a region cut by both
    /// keeps L.
    #[test]
    fn shapes_of_one_landmark_on_the_boundary_meet(seed in any::<u64>(), three in any::<bool>()) {
        let dim = if three { 3 } else { 2 };
        let mut rng = Rng::new(seed);
        let grid = |rng: &mut Rng| -> Vec<f64> { (0..dim).map(|_| rng.below(3) as f64).collect() };
        let l = grid(&mut rng);
        let shapes: Vec<(Shape, Vec<f64>)> = (0..2)
            .map(|_| {
                let p = if rng.chance(0.35) { l.clone() } else { grid(&mut rng) };
                let d2: f64 = (0..dim).map(|a| (p[a] - l[a]) * (p[a] - l[a])).sum();
                let range = match exact_root(d2) {
                    Some(r) if rng.chance(0.6) => Interval::point(r),
                    _ => widen(distance_between(&points(&p), &points(&l)), 0.0, rng.slack(0.6, 0.5)),
                };
                let range = Interval::new(range.lo().max(0.0), range.hi());
                let bearing = (dim == 2 && rng.chance(0.3)).then(|| {
                    let h = rng.range(-3.0, 3.0);
                    (Interval::point(h), bearing_enclosure(&p, &l, h))
                });
                let cut = if rng.chance(0.5) { IntervalBox::entire(dim) } else { box_holding(&mut rng, &l, 2.0) };
                (Shape::new(box_holding(&mut rng, &p, 1.0), range, bearing, cut), p)
            })
            .collect();
        let (a, b) = (&shapes[0].0, &shapes[1].0);
        prop_assert!(!a.disjoint(b) && !b.disjoint(a), "seed {seed}: one landmark's shapes called disjoint: {:?} {:?}", a, b);
        prop_assert!(!disjoint_paved(a, b, 64), "seed {seed}: one landmark's shapes paved disjoint: {:?} {:?}", a, b);
        prop_assert!(!Item::Shape(a).disjoint(&Item::Shape(b)));
        for (s, p) in &shapes {
            let piece = s.contract_piece(&points(&l));
            prop_assert!(piece.is_some(), "seed {seed}: {:?} misses its landmark {:?}", s, l);
            let piece = piece.expect("some");
            for x in 0..dim {
                prop_assert!(piece.p[x].contains(p[x]) && piece.d[x].contains(l[x]), "seed {seed}: piece {:?} lost the truth", piece);
            }
        }
        let mut region = Paving::from_box(&a.hull());
        region.cut(b);
        region.refine(&[a, b], 0.0, 32);
        prop_assert!(region.contains(&l), "seed {seed}: the region of {:?} and {:?} lost {:?}", a, b, l);
    }
}

/// Tangent and coincident shapes: the robot on the landmark (range exactly
/// [0, 0]) from two boxes that only touch, or coincide; a range [0, 5]
/// around a point and a range [5, 5] around another point 10 m away... and
/// exact tangency of zero-width annuli at a common point. None is disjoint.
#[test]
fn tangent_and_coincident_shapes_are_not_disjoint() {
    let b = |x: (f64, f64), y: (f64, f64)| {
        IntervalBox::new(&[Interval::new(x.0, x.1), Interval::new(y.0, y.1)])
    };
    let shape = |c: IntervalBox, r: (f64, f64)| {
        Shape::new(c, Interval::new(r.0, r.1), None, IntervalBox::entire(2))
    };
    let cases = [
        // Range 0 from boxes touching at (1, 0): the landmark is there.
        (
            shape(b((0.0, 1.0), (0.0, 0.0)), (0.0, 0.0)),
            shape(b((1.0, 2.0), (0.0, 0.0)), (0.0, 0.0)),
        ),
        // Range 0 from the same point.
        (
            shape(b((3.0, 3.0), (4.0, 4.0)), (0.0, 0.0)),
            shape(b((3.0, 3.0), (4.0, 4.0)), (0.0, 0.0)),
        ),
        // Range 0 from a box, a disc of radius 5 from a point of it.
        (
            shape(b((0.0, 1.0), (0.0, 1.0)), (0.0, 0.0)),
            shape(b((1.0, 1.0), (1.0, 1.0)), (0.0, 5.0)),
        ),
        // Circles of radius 5 around (0, 0) and (6, 8), tangent at (3, 4).
        (
            shape(b((0.0, 0.0), (0.0, 0.0)), (5.0, 5.0)),
            shape(b((6.0, 6.0), (8.0, 8.0)), (5.0, 5.0)),
        ),
        // A circle of radius 5 inside one of radius 10, tangent at (3, 4).
        (
            shape(b((0.0, 0.0), (0.0, 0.0)), (5.0, 5.0)),
            shape(b((-3.0, -3.0), (-4.0, -4.0)), (10.0, 10.0)),
        ),
    ];
    for (i, (s, t)) in cases.iter().enumerate() {
        assert!(!s.disjoint(t) && !t.disjoint(s), "case {i}: {s:?} {t:?}");
        assert!(!disjoint_paved(s, t, 64), "case {i}");
    }
}

/// The chain sums of displacements whose sums are exact in f64 (quarter
/// metres) are those sums, unwidened: `Interval::add` is tightest, so the
/// enclosure of p(t) - p(s) is exactly `[Σ lo, Σ hi]`.
#[test]
fn exact_chain_sums_are_not_widened() {
    let mut rng = Rng::new(7);
    let n = 300;
    let disp: Vec<Interval> = (0..n * 2)
        .map(|_| {
            let c = (rng.range(-40.0, 40.0) * 4.0).round() / 4.0;
            let w = rng.below(3) as f64 * 0.25;
            Interval::new(c - w, c + w)
        })
        .collect();
    let sums = ChainSums::new(&disp, 2);
    for (s, t) in [
        (0, 300),
        (5, 70),
        (64, 128),
        (200, 3),
        (299, 300),
        (63, 65),
        (7, 7),
    ] {
        let d = sums.delta(s, t);
        let (from, to) = (s.min(t), s.max(t));
        for a in 0..2 {
            let lo: f64 = (from..to).map(|u| disp[u * 2 + a].lo()).sum();
            let hi: f64 = (from..to).map(|u| disp[u * 2 + a].hi()).sum();
            let want = if s <= t {
                Interval::new(lo, hi)
            } else {
                Interval::new(-hi, -lo)
            };
            assert_eq!(d[a], want, "delta({s}, {t}) axis {a}");
        }
    }
}
