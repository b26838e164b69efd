//! Soundness of the detection-shape contractors (core/src/shapes/) on
//! planted solutions: true landmarks, true positions inside their boxes,
//! ranges and bearings holding the truth, in ring, random and line layouts,
//! 2-D and 3-D. No contractor may lose a true point, group two detections
//! of different landmarks, or call a consistent instance infeasible.
//!
//! `PROPTEST_CASES` sets the number of cases; seeds and persisted
//! failures: tests/common/mod.rs (`config`).

// Axes and detections index several parallel arrays at once.
#![allow(clippy::needless_range_loop)]

use nvector_core::shapes::branch::branch;
use nvector_core::shapes::chain_sums::ChainSums;
use nvector_core::shapes::distinct::{Distinct, Uf};
use nvector_core::shapes::region::Paving;
use nvector_core::shapes::relative::relative_pairs;
use nvector_core::shapes::shape::{disjoint_paved, Shape};
use nvector_core::shapes::witnesses::{find_witnesses, Item};
use nvector_core::shapes::{Chain, Domains, ShapesState};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::motion_chain::{sweep_backward, sweep_forward, Sweep};
use nvector_core::{Interval, IntervalBox};
use proptest::prelude::*;
use serde_json::json;

mod common;
use common::Rng;

/// Margin covering the f64 rounding of the instance generator itself.
const MARGIN: f64 = 1e-9;

fn around(x: f64, below: f64, above: f64) -> Interval {
    Interval::new(x - below - MARGIN, x + above + MARGIN)
}

/// A planted instance: the domains, the mission (detections) and the truth.
struct Planted {
    dim: usize,
    mission: Mission,
    pos: Vec<Interval>,
    disp: Vec<Interval>,
    det: Vec<IntervalBox>,
    heading_at: Vec<Interval>,
    truth_pos: Vec<Vec<f64>>,
    landmarks: Vec<Vec<f64>>,
    matching: Vec<usize>,
}

#[derive(Debug, Clone, Copy)]
enum Layout {
    Line,
    Ring,
    Random,
}

fn planted(seed: u64, dim: usize, layout: Layout, bearings: bool) -> Planted {
    let mut rng = Rng::new(seed);
    let n = 1 + rng.below(5);
    let spread = rng.range(5.0, 40.0);
    let landmarks: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut l = match layout {
                Layout::Line => vec![
                    spread * (i as f64 - n as f64 / 2.0) / n as f64 * 2.0,
                    if i % 2 == 0 { 5.0 } else { -5.0 } + rng.range(-1.0, 1.0),
                ],
                Layout::Ring => {
                    let a = i as f64 / n as f64 * std::f64::consts::TAU + rng.range(-0.3, 0.3);
                    vec![spread * libm::cos(a), spread * libm::sin(a)]
                }
                Layout::Random => vec![rng.range(-spread, spread), rng.range(-spread, spread)],
            };
            if dim == 3 {
                l.push(rng.range(-20.0, -5.0));
            }
            l
        })
        .collect();
    // A random walk: steps up to 2 m, the heading turning slowly.
    let steps = 20 + rng.below(150);
    let mut truth_pos = vec![vec![0.0; dim]];
    let mut headings = Vec::with_capacity(steps);
    let mut h = rng.range(-3.0, 3.0);
    for _ in 0..steps {
        h += rng.range(-0.4, 0.4);
        let v = rng.range(0.0, 2.0);
        let last = truth_pos.last().expect("one").clone();
        let mut p = vec![last[0] + v * libm::cos(h), last[1] + v * libm::sin(h)];
        if dim == 3 {
            p.push(last[2] + rng.range(-0.2, 0.2));
        }
        truth_pos.push(p);
        headings.push(h);
    }
    let odo = rng.range(0.0, 0.3);
    let mut disp = Vec::with_capacity(steps * dim);
    for i in 0..steps {
        for a in 0..dim {
            let d = truth_pos[i + 1][a] - truth_pos[i][a];
            disp.push(around(d, rng.range(0.0, odo), rng.range(0.0, odo)));
        }
    }
    let mut pos = vec![Interval::ENTIRE; (steps + 1) * dim];
    for a in 0..dim {
        pos[a] = around(0.0, rng.range(0.0, 0.5), rng.range(0.0, 0.5));
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
        let dist = (0..dim).map(|a| (lm[a] - p[a]).powi(2)).sum::<f64>().sqrt();
        let r = around(dist, rng.range(0.0, range_err), rng.range(0.0, range_err));
        let r = r.intersect(Interval::new(0.0, f64::INFINITY));
        let hd = headings[(t).min(steps - 1)];
        let h_int = around(hd, rng.range(0.0, 0.05), rng.range(0.0, 0.05));
        let mut d = json!({"step": t, "range": [r.lo(), r.hi()]});
        if bearings {
            let beta = libm::atan2(lm[1] - p[1], lm[0] - p[0]) - hd;
            let b = around(
                beta,
                rng.range(0.0, bearing_err),
                rng.range(0.0, bearing_err),
            );
            d["bearing"] = json!([b.lo(), b.hi()]);
        }
        let mut b = IntervalBox::entire(dim);
        if region {
            for a in 0..dim {
                b[a] = around(lm[a], rng.range(0.0, 20.0), rng.range(0.0, 20.0));
            }
        }
        if dim == 3 {
            b[2] = b[2].intersect(around(lm[2], rng.range(0.0, 1.0), rng.range(0.0, 1.0)));
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

impl Planted {
    fn truth_inside(&self) -> Result<(), String> {
        for (t, p) in self.truth_pos.iter().enumerate() {
            for a in 0..self.dim {
                if !self.pos[t * self.dim + a].contains(p[a]) {
                    return Err(format!(
                        "p({t}) lost: {:?} not in {:?}",
                        p,
                        &self.pos[t * self.dim..(t + 1) * self.dim]
                    ));
                }
            }
        }
        for (j, b) in self.det.iter().enumerate() {
            if !b.contains(&self.landmarks[self.matching[j]]) {
                return Err(format!("d({j}) lost"));
            }
        }
        Ok(())
    }

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

    /// The propagator's part, as in a round: each detection's own
    /// constraints, sweeps; then the groups' boxes intersected.
    fn own_constraints(&mut self, groups: &[Vec<usize>]) -> Result<(), String> {
        let dim = self.dim;
        for (j, d) in self.mission.detections.iter().enumerate() {
            let t = d.step;
            let p = &mut self.pos[t * dim..(t + 1) * dim];
            let mut r = d.range;
            let ok =
                nvector_core::slam::distance::contract_distance(p, self.det[j].axes_mut(), &mut r)
                    && d.bearing.is_none_or(|b| {
                        nvector_core::slam::bearing::contract_bearing(
                            p,
                            self.det[j].axes_mut(),
                            self.heading_at[j],
                            b,
                            r,
                        )
                    });
            if !ok {
                return Err(format!("detection {j} emptied"));
            }
            for s in [
                sweep_forward(&mut self.pos, &self.disp, dim, t, 1e-9),
                sweep_backward(&mut self.pos, &self.disp, dim, t, 1e-9),
            ] {
                if let Sweep::Empty(s) = s {
                    return Err(format!("chain emptied at {s}"));
                }
            }
        }
        for g in groups {
            let mut c = self.det[g[0]].clone();
            for &j in &g[1..] {
                c.intersect_with(&self.det[j]);
            }
            for &j in g {
                self.det[j] = c.clone();
            }
        }
        Ok(())
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
                b[a] = around(l[a], rng.range(0.0, 3.0), rng.range(0.0, 3.0));
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
        relative_pairs(&inst.mission, &order, dim, &sums, &inst.pos, &inst.det, &inst.heading_at, 64, &mut pairs);
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
