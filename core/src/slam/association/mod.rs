//! The `shapes` contractor of a SLAM round: landmark regions of the proved
//! groups, shape witnesses and branch contraction, run over every
//! detection (DESIGN.md, "Detection shapes").
//!
//! # Constraint
//!
//! The detection constraints (range, bearing, region, depth: the shapes of
//! [`crate::shapes::shape`]) with atmost_nvector(n, {d(1)..d(k)}) and the proved
//! groups (detections known to see one landmark).
//!
//! # Math
//!
//! A round, given the current boxes of p(0..=N) and d(1..k):
//! 1. **Landmark regions.** Each group of size >= 2 keeps a [`Paving`] of
//!    its landmark ([`crate::shapes::region`]): cut by every member's shape whose
//!    centre box changed since it last cut it, bisected down to a bounded
//!    count (halves cut by the thinnest members). Each member is then
//!    contracted by [`branch`] against its group's region alone: d(j) and
//!    p(step) shrink to the hulls of the pieces.
//! 2. **Distinct pairs.** Detections at nearby steps whose shapes are
//!    disjoint in the frame of the earlier step ([`relative_pairs`]) see
//!    distinct landmarks; so do a detection and a region its branch
//!    excluded (step 4). With n known, [`Distinct::infer`] merges the
//!    common neighbours of every n-1 pairwise-distinct groups and proves
//!    infeasibility from n+1 of them.
//! 3. **Witnesses.** Items are the groups' regions and the shapes of the
//!    detections in no group. [`find_witnesses`] looks for n + 1 pairwise
//!    disjoint (or proved distinct) items: n + 1 is infeasible (the items'
//!    detections are named); n gives n regions R(1..n) (a singleton's
//!    region is its shape, paved) holding the n distinct landmarks, one
//!    each.
//! 4. **Branch contraction.** With n witnesses, every other detection j
//!    (in step order) is contracted by [`branch`] against R(1..n): its
//!    landmark is one of the n. A single surviving region proves the
//!    matching: j (with its group) joins that witness's group, whose region
//!    is cut by j's shape at once, so later detections meet a smaller
//!    region (a sequential filter). A region that does not survive is a
//!    distinct pair.
//!
//! 5. **Registration** ([`register`]): at the steps of the groups' local
//!    pieces (one every `register_every` steps), the pieces within
//!    `register_gap` steps, moved to the frame of that step, must fit the
//!    n witness regions under a map that gives distinct groups distinct
//!    witnesses: p(step) shrinks to the positions where such a map exists,
//!    and a group left with one witness over every registration joins it
//!    (the others are distinct pairs).
//!
//! Whenever p(step) shrinks by more than the tolerance the caller's
//! [`Chain`] is told (its own passes sweep the change along the motion
//! chain in both directions later); in step 4, the change is also swept
//! forward to each next detection's step before that detection is read,
//! so that the filter sees it.
//!
//! # Soundness
//!
//! Each step is one of the sound contractors of this module's files; a
//! group is proved once and stays proved (contractions keep every
//! solution, so a proof made on smaller boxes holds for the input boxes).
//! Regions are sound enclosures of their group's landmark at every moment,
//! so they stay sound as groups merge (intersection of two enclosures of
//! one point) and as boxes shrink.
//!
//! With false detections allowed (`max_outliers` q > 0) the argument needs
//! n + q witnesses and must not contract the witnesses themselves; this
//! round does nothing when q > 0 (soundness first; see docs/shapes.md).
//!
//! # Complexity
//!
//! Per round: O(c · m d) for the region cuts (c changed members, m <=
//! `max_boxes` boxes per region), O(k n m d) at most for the branches (a
//! region whose hull the shape misses costs O(d)), O(k log k + 64^2 + k n)
//! for the witness search, and for the registration O(a · G · n · c² · B · d)
//! (a registration steps, at most G = `register_groups` groups each, pavings
//! coarsened to c boxes, B paving boxes of p(step)). Memory O(k + g · m)
//! for g groups.

use super::mission::Mission;
use crate::contractors::motion_chain::shrinkage;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::branch::{branch, Branches};
use crate::shapes::chain_sums::ChainSums;
use crate::shapes::distinct::{Distinct, Uf};
use crate::shapes::frames::{FrameOptions, Frames};
use crate::shapes::region::Paving;
use crate::shapes::registration::{register, LocalGroup, RegisterOptions};
use crate::shapes::relative::relative_pairs;
use crate::shapes::shape::{Shape, Sighting};
use crate::shapes::witnesses::{find_witnesses, Item};

/// Tuning of the shapes round.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapesOptions {
    /// Most boxes in one region's paving.
    pub max_boxes: usize,
    /// Boxes narrower than this are not bisected further (metres).
    pub resolution: f64,
    /// Most members whose shapes cut the halves of a bisection (the
    /// thinnest ones).
    pub refine_shapes: usize,
    /// Node budget of the exact witness search.
    pub node_budget: usize,
    /// Detections after each one (in step order) tried for a relative
    /// distinct pair.
    pub max_ahead: usize,
    /// Node budget of each pass of the clique rule.
    pub clique_budget: usize,
    /// Local frames ([`crate::shapes::frames`]).
    pub frames: FrameOptions,
    /// Most frame/inference passes in one round.
    pub frame_passes: usize,
    /// Whether the local frames are registered on the witness regions.
    pub registration: bool,
    /// Steps around a registration step whose pieces are used.
    pub register_gap: usize,
    /// Least steps between two registration steps.
    pub register_every: usize,
    /// Most groups in one registration.
    pub register_groups: usize,
    /// A registration step is done again when its position box or a
    /// witness region shrank by more than this fraction of its width since
    /// the last time (or the groups around it changed).
    pub register_slack: f64,
    /// Tuning of each registration.
    pub register: RegisterOptions,
}

impl Default for ShapesOptions {
    fn default() -> Self {
        ShapesOptions {
            max_boxes: 64,
            resolution: 0.0,
            refine_shapes: 16,
            node_budget: 20_000,
            max_ahead: 64,
            clique_budget: 200_000,
            frames: FrameOptions::default(),
            frame_passes: 3,
            registration: true,
            register_gap: 300,
            register_every: 50,
            register_groups: 8,
            register_slack: 0.02,
            register: RegisterOptions::default(),
        }
    }
}

/// A member's position box, detection box, its region's hull and box count.
type BranchKey = (IntervalBox, IntervalBox, IntervalBox, usize);

/// The domains a round reads and contracts.
#[derive(Debug)]
pub struct Domains<'a> {
    /// Dimension of positions (2 or 3).
    pub dim: usize,
    /// Position domains, (N+1)·dim, step-major.
    pub pos: &'a mut [Interval],
    /// Detection variables d(j).
    pub det: &'a mut [IntervalBox],
    /// Heading (or yaw) at each detection's step.
    pub heading_at: &'a [Interval],
    /// Displacement boxes D(i), N·dim, step-major.
    pub disp: &'a [Interval],
}

/// The motion chain as a round sees it (the propagator implements it).
pub trait Chain {
    /// Sweeps the change of p(`from`) forward to p(`to`) (`from < to`),
    /// while it moves a bound by more than the tolerance; returns whether
    /// it is still alive at `to`. Err: a position emptied (the reason).
    fn sweep_forward(
        &mut self,
        pos: &mut [Interval],
        from: usize,
        to: usize,
    ) -> Result<bool, String>;
    /// p(`step`) changed (a detection step): the caller sweeps it along
    /// the chain, both ways, later.
    fn changed(&mut self, step: usize);
}

/// What a round did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShapesOutcome {
    /// Pairs of detections proved to see the same landmark.
    pub unions: Vec<(usize, usize)>,
    /// Whether a bound moved by more than the tolerance or a group grew.
    pub moved: bool,
    /// Detections whose boxes (or whose p(step)) moved by more than the
    /// tolerance, or that joined a group.
    pub moved_detections: Vec<usize>,
    /// Contractor calls (pieces contracted).
    pub contractions: u64,
    /// Why the mission is infeasible, when it was proved.
    pub infeasible: Option<String>,
}

/// State kept across rounds: the regions of the groups and the last
/// witnesses.
#[derive(Debug, Clone, Default)]
pub struct ShapesState {
    /// Tuning.
    pub options: ShapesOptions,
    /// Region of each group, stored at one member (the root).
    regions: Vec<Option<Paving>>,
    /// The centre box with which each detection last cut its group's
    /// region (`None`: never).
    cut_with: Vec<Option<IntervalBox>>,
    /// What each group member's last branch against its region read: its
    /// position box, its detection box, the region's hull and box count
    /// (the branch is skipped while they stay the same: it would give the
    /// same pieces).
    branched: Vec<Option<BranchKey>>,
    /// One detection of each of the last witnesses.
    witnesses: Vec<usize>,
    /// Detection pairs proved distinct.
    distinct: Distinct,
    /// Group regions in local frames.
    frames: Frames,
    /// Whether the relative pairs were computed (once: they rest on the
    /// displacement boxes and the measurements, which do not change).
    relative_done: bool,
    /// What each registration step last read, and the candidates it gave.
    /// By step, in step order.
    registered: Vec<(usize, RegKey, Vec<u64>)>,
}

/// The inputs of one registration (see [`RegKey::close`]).
#[derive(Debug, Clone)]
struct RegKey {
    p: IntervalBox,
    roots: Vec<usize>,
    /// A detection of each witness slot's group.
    slots: Vec<usize>,
    fixed: Vec<Option<usize>>,
    pieces: usize,
    witnesses: Vec<IntervalBox>,
}

impl RegKey {
    /// Whether a registration that read `self` can stand for one reading
    /// `new`: the same groups and pieces, each witness slot holding the
    /// same landmark (its witness in one group of `uf` with the old one's:
    /// the candidate masks name witnesses by slot, so a mask is only
    /// carried over while slot i is the same landmark in both rounds), and
    /// the position box and the witness regions' hulls shrunk by at most
    /// the fraction `slack` of their widths on every axis since. Its answer
    /// holds (it was sound for larger boxes, and says which landmarks the
    /// groups may see); a registration on the smaller boxes could only be
    /// tighter, by little.
    fn close(&self, new: &RegKey, slack: f64, uf: &mut Uf) -> bool {
        let near = |a: &IntervalBox, b: &IntervalBox| {
            a.dim() == b.dim()
                && (0..a.dim()).all(|x| {
                    let (wa, wb) = (a[x].width(), b[x].width());
                    wb >= wa * (1.0 - slack) && b[x].is_subset(a[x])
                })
        };
        self.roots == new.roots
            && self.slots.len() == new.slots.len()
            && self
                .slots
                .iter()
                .zip(&new.slots)
                .all(|(&a, &b)| uf.find(a) == uf.find(b))
            && self.fixed == new.fixed
            && self.pieces == new.pieces
            && self.witnesses.len() == new.witnesses.len()
            && near(&self.p, &new.p)
            && self
                .witnesses
                .iter()
                .zip(&new.witnesses)
                .all(|(a, b)| near(a, b))
    }
}

/// What the pure shapes need of the mission's detections.
pub fn sightings(mission: &Mission) -> Vec<Sighting> {
    mission
        .detections
        .iter()
        .map(|d| Sighting {
            step: d.step,
            range: d.range,
            bearing: d.bearing,
        })
        .collect()
}

fn shape_of(mission: &Mission, dom: &Domains, j: usize) -> Shape {
    let det = &mission.detections[j];
    let dim = dom.dim;
    let t = det.step;
    Shape::new(
        IntervalBox::new(&dom.pos[t * dim..(t + 1) * dim]),
        det.range,
        det.bearing.map(|b| (dom.heading_at[j], b)),
        dom.det[j].clone(),
    )
}

impl ShapesState {
    /// A state for `k` detections.
    pub fn new(k: usize) -> ShapesState {
        ShapesState {
            options: ShapesOptions::default(),
            regions: vec![None; k],
            cut_with: vec![None; k],
            branched: vec![None; k],
            witnesses: Vec::new(),
            distinct: Distinct::default(),
            frames: Frames::default(),
            relative_done: false,
            registered: Vec::new(),
        }
    }

    /// The region of a group (any member may hold it), when one was built.
    pub fn region_of(&self, group: &[usize]) -> Option<&Paving> {
        group.iter().find_map(|&j| self.regions.get(j)?.as_ref())
    }

    /// One round (module doc). `groups`: the proved groups (size >= 2);
    /// `n`: the landmark count when known; `max_outliers`: q (the round
    /// does nothing when q > 0); `chain` propagates shrunk positions.
    #[allow(clippy::too_many_arguments)]
    pub fn contract(
        &mut self,
        mission: &Mission,
        dom: Domains,
        groups: &[Vec<usize>],
        n: Option<usize>,
        max_outliers: usize,
        tolerance: f64,
        chain: &mut dyn Chain,
    ) -> ShapesOutcome {
        let mut out = ShapesOutcome::default();
        let k = mission.detections.len();
        if max_outliers > 0 || k == 0 {
            return out;
        }
        if self.regions.len() != k {
            *self = ShapesState {
                options: self.options.clone(),
                ..ShapesState::new(k)
            };
        }
        let mut dom = dom;
        let mut uf = Uf::new(k);
        for g in groups {
            for &j in &g[1..] {
                uf.union(g[0], j);
            }
        }
        if let Err(reason) =
            self.group_regions(mission, &mut dom, &mut uf, tolerance, chain, &mut out)
        {
            out.infeasible = Some(reason);
            return out;
        }
        let Some(n) = n else {
            return out;
        };
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_unstable_by_key(|&j| (mission.detections[j].step, j));
        let steps: Vec<usize> = mission.detections.iter().map(|d| d.step).collect();
        let sightings = sightings(mission);
        let sums = ChainSums::new(dom.disp, dom.dim).with_steps(&steps);
        if !self.relative_done {
            self.relative_done = true;
            let mut pairs = Vec::new();
            relative_pairs(
                &sightings,
                &order,
                dom.dim,
                &sums,
                dom.pos,
                dom.det,
                dom.heading_at,
                self.options.max_ahead,
                &mut pairs,
            );
            out.contractions += pairs.len() as u64;
            self.distinct.add(pairs);
        }
        for pass in 0..self.options.frame_passes.max(1) {
            if pass > 0 {
                let mut pairs = Vec::new();
                match self.frames.pairs(
                    &sightings,
                    &order,
                    dom.dim,
                    &sums,
                    dom.heading_at,
                    &mut uf,
                    &self.options.frames,
                    &mut pairs,
                ) {
                    Ok(work) => out.contractions += work,
                    Err(reason) => {
                        out.infeasible = Some(reason);
                        return out;
                    }
                }
                self.distinct.add(pairs);
            }
            match self.distinct.infer(&mut uf, n, self.options.clique_budget) {
                Ok(u) => {
                    let done = u.is_empty() && pass > 0;
                    out.moved |= !u.is_empty();
                    out.moved_detections
                        .extend(u.iter().flat_map(|&(a, b)| [a, b]));
                    out.unions.extend(u);
                    if done {
                        break;
                    }
                }
                Err(reason) => {
                    out.infeasible = Some(reason);
                    return out;
                }
            }
        }
        if let Err(reason) = self.witness_branches(
            mission, &mut dom, &mut uf, n, &order, &sums, tolerance, chain, &mut out,
        ) {
            out.infeasible = Some(reason);
            return out;
        }
        match self.distinct.infer(&mut uf, n, self.options.clique_budget) {
            Ok(u) => {
                out.moved |= !u.is_empty();
                out.moved_detections
                    .extend(u.iter().flat_map(|&(a, b)| [a, b]));
                out.unions.extend(u);
            }
            Err(reason) => out.infeasible = Some(reason),
        }
        out
    }

    /// Step 1: regions of the groups, and their members contracted.
    fn group_regions(
        &mut self,
        mission: &Mission,
        dom: &mut Domains,
        uf: &mut Uf,
        tol: f64,
        chain: &mut dyn Chain,
        out: &mut ShapesOutcome,
    ) -> Result<(), String> {
        let opts = self.options.clone();
        for g in uf.groups() {
            let root = g[0];
            let region = self.gather(&g, dom, opts.max_boxes);
            let mut region = match region {
                Some(r) => r,
                None => {
                    let mut common = dom.det[root].clone();
                    for &j in &g[1..] {
                        common.intersect_with(&dom.det[j]);
                    }
                    for &j in &g {
                        self.cut_with[j] = None;
                    }
                    Paving::from_box(&common)
                }
            };
            // L ∈ P(s) + (L - p(s)) for each local-frame piece of the group.
            for (step, rel) in self.frames.pieces(&g) {
                let origin = &dom.pos[step * dom.dim..(step + 1) * dom.dim];
                let shifted: Vec<IntervalBox> = rel
                    .boxes()
                    .iter()
                    .map(|b| {
                        let axes: Vec<Interval> = (0..dom.dim).map(|a| b[a] + origin[a]).collect();
                        IntervalBox::new(&axes)
                    })
                    .collect();
                region.intersect(&Paving::from_boxes(dom.dim, shifted), opts.max_boxes);
                out.contractions += region.boxes().len() as u64;
            }
            let shapes: Vec<Shape> = g.iter().map(|&j| shape_of(mission, dom, j)).collect();
            for (s, &j) in shapes.iter().zip(&g) {
                if self.cut_with[j].as_ref() != Some(&s.centre) {
                    region.cut(s);
                    out.contractions += region.boxes().len() as u64;
                    self.cut_with[j] = Some(s.centre.clone());
                }
            }
            let mut by_thickness: Vec<&Shape> = shapes.iter().collect();
            // Ties in slice order (the references point into one slice, so their
            // addresses follow the indices): the order of a stable sort.
            by_thickness.sort_unstable_by(|a, b| {
                a.thickness().total_cmp(&b.thickness()).then_with(|| {
                    std::ptr::from_ref::<Shape>(*a).cmp(&std::ptr::from_ref::<Shape>(*b))
                })
            });
            by_thickness.truncate(opts.refine_shapes);
            region.refine(&by_thickness, opts.resolution, opts.max_boxes);
            if region.is_empty() {
                return Err(format!(
                    "landmark of detections {g:?}: their shapes (ranges and bearings around their positions) have no common point"
                ));
            }
            let hull = region.hull();
            for (s, &j) in shapes.iter().zip(&g) {
                let key = (
                    s.centre.clone(),
                    s.cut.clone(),
                    hull.clone(),
                    region.boxes().len(),
                );
                if self.branched[j].as_ref() == Some(&key) {
                    continue;
                }
                let br = branch(s, &[&region]);
                out.contractions += region.boxes().len() as u64;
                apply(mission, dom, j, &br, tol, chain, out)?;
                // The key of what the next round will read.
                let t = mission.detections[j].step;
                let dim = dom.dim;
                self.branched[j] = Some((
                    IntervalBox::new(&dom.pos[t * dim..(t + 1) * dim]),
                    dom.det[j].clone(),
                    key.2,
                    key.3,
                ));
            }
            self.regions[root] = Some(region);
        }
        Ok(())
    }

    /// Takes the regions stored at the members of `g` and intersects them.
    fn gather(&mut self, g: &[usize], _dom: &Domains, max_boxes: usize) -> Option<Paving> {
        let mut region: Option<Paving> = None;
        for &j in g {
            if let Some(p) = self.regions[j].take() {
                region = Some(match region {
                    None => p,
                    Some(mut r) => {
                        r.intersect(&p, max_boxes);
                        r
                    }
                });
            }
        }
        region
    }

    /// Steps 2 and 3: witnesses and branch contraction.
    #[allow(clippy::too_many_arguments)]
    fn witness_branches(
        &mut self,
        mission: &Mission,
        dom: &mut Domains,
        uf: &mut Uf,
        n: usize,
        order: &[usize],
        sums: &ChainSums,
        tol: f64,
        chain: &mut dyn Chain,
        out: &mut ShapesOutcome,
    ) -> Result<(), String> {
        let k = mission.detections.len();
        let graph = self.distinct.graph(uf)?;
        let opts = self.options.clone();
        // Items: one per group (its region) and per ungrouped detection.
        let mut roots: Vec<usize> = Vec::new();
        let mut size = vec![0usize; k];
        for j in 0..k {
            let r = uf.find(j);
            size[r] += 1;
        }
        let mut singles: Vec<Shape> = Vec::new();
        for (j, &count) in size.iter().enumerate() {
            if uf.find(j) == j {
                roots.push(j);
                if count == 1 {
                    singles.push(shape_of(mission, dom, j));
                }
            }
        }
        let chosen: Vec<usize> = {
            let mut items: Vec<Item> = Vec::with_capacity(roots.len());
            let mut item_root: Vec<usize> = Vec::with_capacity(roots.len());
            let mut si = 0;
            for &r in &roots {
                if size[r] == 1 {
                    items.push(Item::Shape(&singles[si]));
                    si += 1;
                    item_root.push(r);
                } else if let Some(p) = self.regions[r].as_ref() {
                    items.push(Item::Region(p));
                    item_root.push(r);
                }
            }
            let mut seed = Vec::new();
            for &w in &self.witnesses {
                let r = uf.find(w);
                if let Some(i) = item_root.iter().position(|&x| x == r) {
                    seed.push(i);
                }
            }
            let sizes: Vec<(u8, f64)> = items.iter().map(|i| i.size()).collect();
            let mut apart = |a: usize, b: usize| {
                graph[item_root[a]]
                    .binary_search(&(item_root[b] as u32))
                    .is_ok()
                    || items[a].disjoint(&items[b])
            };
            let w = find_witnesses(&sizes, &mut apart, n + 1, &seed, opts.node_budget);
            w.into_iter().map(|i| item_root[i]).collect()
        };
        out.contractions += 1;
        if chosen.len() > n {
            let mut named: Vec<usize> = chosen.clone();
            named.sort_unstable();
            return Err(format!(
                "detections {named:?} (with their groups): {} pairwise-disjoint shapes or proved-distinct groups, so at least {} distinct landmarks, more than landmark_count {n}",
                chosen.len(),
                chosen.len()
            ));
        }
        if chosen.len() < n {
            return Ok(());
        }
        self.witnesses = chosen.clone();
        // The n regions, taken out while the detections are read.
        let mut wregions: Vec<Paving> = Vec::with_capacity(n);
        for &r in &chosen {
            let p = match self.regions[r].take() {
                Some(p) => p,
                None => {
                    let s = shape_of(mission, dom, r);
                    let mut p = Paving::from_box(&s.hull());
                    p.refine(&[&s], opts.resolution, opts.max_boxes);
                    self.cut_with[r] = Some(s.centre.clone());
                    p
                }
            };
            wregions.push(p);
        }
        let mut slot_root: Vec<usize> = chosen.clone();
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        // Groups first: a group's region is at most the region of each
        // member's shape, so it meets fewer witnesses.
        for r in 0..k {
            if uf.find(r) != r || slot_root.contains(&r) {
                continue;
            }
            let Some(region) = self.regions[r].as_ref() else {
                continue;
            };
            let meets: Vec<usize> = (0..n).filter(|&i| wregions[i].meets(region)).collect();
            out.contractions += n as u64;
            for (i, &w) in slot_root.iter().enumerate() {
                if !meets.contains(&i) {
                    pairs.push((r as u32, w as u32));
                }
            }
            match meets[..] {
                [] => {
                    let g: Vec<usize> = (0..k).filter(|&j| uf.find(j) == r).collect();
                    return Err(format!(
                        "landmark of detections {g:?}: its region meets none of the {n} landmark regions of the pairwise-distinct groups {slot_root:?}"
                    ));
                }
                [i] => {
                    let region = self.regions[r].take();
                    join_witness(
                        wregions.as_mut_slice(),
                        &mut slot_root,
                        i,
                        r,
                        region,
                        uf,
                        out,
                        opts.max_boxes,
                    )?;
                }
                _ => {}
            }
        }
        let mut result = Ok(());
        // The step from which a forward change of the chain may be alive.
        let mut alive: Option<usize> = None;
        for &j in order {
            let rj = uf.find(j);
            if slot_root.contains(&rj) {
                continue;
            }
            let t = mission.detections[j].step;
            if let Some(from) = alive.filter(|&f| f < t) {
                match chain.sweep_forward(dom.pos, from, t) {
                    Ok(true) => alive = Some(t),
                    Ok(false) => alive = None,
                    Err(e) => {
                        result = Err(e);
                        break;
                    }
                }
            }
            let s = shape_of(mission, dom, j);
            let br = {
                let refs: Vec<&Paving> = wregions.iter().collect();
                branch(&s, &refs)
            };
            out.contractions += wregions.iter().map(|p| p.boxes().len() as u64).sum::<u64>();
            if br.surviving.is_empty() {
                result = Err(format!(
                    "detection {j} (step {}): its shape meets none of the {n} landmark regions of the pairwise-disjoint witnesses {:?}",
                    mission.detections[j].step, slot_root
                ));
                break;
            }
            for (i, &r) in slot_root.iter().enumerate() {
                if !br.surviving.contains(&i) {
                    pairs.push((j as u32, r as u32));
                }
            }
            if let [i] = br.surviving[..] {
                // j (and its group) sees the landmark of witness i.
                out.unions.push((slot_root[i], j));
                out.moved = true;
                out.moved_detections.push(j);
                if let Some(p) = self.regions[rj].take() {
                    wregions[i].intersect(&p, opts.max_boxes);
                }
                let new_root = uf.union(slot_root[i], j);
                slot_root[i] = new_root;
                wregions[i].cut(&s);
                self.cut_with[j] = Some(s.centre.clone());
                out.contractions += wregions[i].boxes().len() as u64;
                if wregions[i].is_empty() {
                    result = Err(format!(
                        "landmark of detection {j} and witness group {}: no common point",
                        slot_root[i]
                    ));
                    break;
                }
            }
            match apply(mission, dom, j, &br, tol, chain, out) {
                Ok(true) => alive = Some(t),
                Ok(false) => {}
                Err(e) => {
                    result = Err(e);
                    break;
                }
            }
        }
        if let Some(step) = alive {
            chain.changed(step);
        }
        if result.is_ok() && opts.registration && n <= 64 {
            result = self.register_anchors(
                mission,
                dom,
                uf,
                sums,
                &mut wregions,
                &mut slot_root,
                tol,
                chain,
                out,
                &mut pairs,
            );
        }
        for (p, r) in wregions.into_iter().zip(slot_root) {
            self.regions[r] = Some(p);
        }
        self.distinct.add(pairs);
        result
    }
}

impl ShapesState {
    /// Step 5: registration of the local frames on the witness regions
    /// ([`crate::shapes::registration`]) at the steps of the groups' pieces: p(s)
    /// shrinks, and a group left with one witness joins it.
    #[allow(clippy::too_many_arguments)]
    fn register_anchors(
        &mut self,
        mission: &Mission,
        dom: &mut Domains,
        uf: &mut Uf,
        sums: &ChainSums,
        wregions: &mut [Paving],
        slot_root: &mut [usize],
        tol: f64,
        chain: &mut dyn Chain,
        out: &mut ShapesOutcome,
        pairs: &mut Vec<(u32, u32)>,
    ) -> Result<(), String> {
        let dim = dom.dim;
        let n = wregions.len();
        let graph = self.distinct.graph(uf)?;
        let witness_boxes: Vec<Vec<IntervalBox>> =
            wregions.iter().map(|w| w.boxes().to_vec()).collect();
        // Pieces by step: (step, root, paving).
        let mut pieces: Vec<(usize, usize, &Paving)> = self
            .frames
            .every_piece()
            .into_iter()
            .map(|(member, step, region)| (step, uf.find(member), region))
            .collect();
        pieces.sort_unstable_by_key(|&(step, root, _)| (step, root));
        let gap = self.options.register_gap;
        let mut reach: Vec<u64> = vec![u64::MAX; mission.detections.len()];
        let mut last_anchor: Option<usize> = None;
        let mut lo = 0;
        for a in 0..pieces.len() {
            let s = pieces[a].0;
            if last_anchor.is_some_and(|l| s < l + self.options.register_every) {
                continue;
            }
            last_anchor = Some(s);
            while pieces[lo].0 + gap < s {
                lo += 1;
            }
            // Local groups around s, in the frame of s.
            let mut roots: Vec<usize> = Vec::new();
            let mut groups: Vec<LocalGroup> = Vec::new();
            for &(t, root, region) in pieces[lo..].iter().take_while(|e| e.0 <= s + gap) {
                let delta = sums.delta(s, t);
                let boxes: Vec<IntervalBox> = region
                    .boxes()
                    .iter()
                    .map(|b| {
                        let axes: Vec<Interval> = (0..dim).map(|x| b[x] + delta[x]).collect();
                        IntervalBox::new(&axes)
                    })
                    .collect();
                let gi = match roots.iter().position(|&r| r == root) {
                    Some(gi) => gi,
                    None => {
                        roots.push(root);
                        groups.push(LocalGroup {
                            pieces: Vec::new(),
                            fixed: slot_root.iter().position(|&w| uf.find(w) == root),
                        });
                        roots.len() - 1
                    }
                };
                groups[gi].pieces.push(boxes);
            }
            if groups.len() > self.options.register_groups {
                // The witness groups first, then the most pieces.
                let mut idx: Vec<usize> = (0..groups.len()).collect();
                idx.sort_unstable_by_key(|&i| {
                    (
                        groups[i].fixed.is_none(),
                        usize::MAX - groups[i].pieces.len(),
                        roots[i],
                    )
                });
                idx.truncate(self.options.register_groups);
                idx.sort_unstable();
                roots = idx.iter().map(|&i| roots[i]).collect();
                groups = idx.iter().map(|&i| groups[i].clone()).collect();
            }
            let distinct =
                |g: usize, h: usize| graph[roots[g]].binary_search(&(roots[h] as u32)).is_ok();
            let p = IntervalBox::new(&dom.pos[s * dim..(s + 1) * dim]);
            let key = RegKey {
                p: p.clone(),
                roots: roots.clone(),
                slots: slot_root.to_vec(),
                fixed: groups.iter().map(|g| g.fixed).collect(),
                pieces: groups.iter().map(|g| g.pieces.len()).sum(),
                witnesses: wregions.iter().map(|w| w.hull()).collect(),
            };
            let slot = self.registered.binary_search_by_key(&s, |e| e.0);
            if let Some((_, old, old_reach)) = slot.ok().map(|i| &self.registered[i]) {
                if old.close(&key, self.options.register_slack, uf) {
                    for (&root, &r) in roots.iter().zip(old_reach) {
                        reach[root] &= r;
                    }
                    continue;
                }
            }
            let reg = register(
                &p,
                &witness_boxes,
                &groups,
                &distinct,
                &self.options.register,
            );
            out.contractions += reg.work;
            if reg.p.is_empty() {
                return Err(format!(
                    "step {s}: the landmarks of groups {roots:?}, seen from p({s}), fit no placement on the {n} landmark regions"
                ));
            }
            let mut moved = 0.0f64;
            for x in 0..dim {
                let before = dom.pos[s * dim + x];
                let after = before.intersect(reg.p[x]);
                moved = moved.max(shrinkage(before, after));
                dom.pos[s * dim + x] = after;
            }
            if moved > tol {
                out.moved = true;
                chain.changed(s);
            }
            for (&root, &r) in roots.iter().zip(&reg.reach) {
                reach[root] &= r;
            }
            let key = RegKey {
                p: IntervalBox::new(&dom.pos[s * dim..(s + 1) * dim]),
                ..key
            };
            match slot {
                Ok(i) => self.registered[i] = (s, key, reg.reach),
                Err(i) => self.registered.insert(i, (s, key, reg.reach)),
            }
        }
        // Groups left with one witness join it; the others are distinct
        // from the witnesses they cannot be.
        for (root, &r) in reach.iter().enumerate() {
            if r == u64::MAX || uf.find(root) != root {
                continue;
            }
            if slot_root.iter().any(|&w| uf.find(w) == root) {
                continue;
            }
            if r == 0 {
                return Err(format!(
                    "landmark of group {root}: seen from the steps around it, it fits none of the {n} landmark regions"
                ));
            }
            for (i, &w) in slot_root.iter().enumerate() {
                if r & (1 << i) == 0 {
                    pairs.push((root as u32, w as u32));
                }
            }
            if r.count_ones() == 1 {
                let region = self.regions[root].take();
                let i = r.trailing_zeros() as usize;
                join_witness(
                    wregions,
                    slot_root,
                    i,
                    root,
                    region,
                    uf,
                    out,
                    self.options.max_boxes,
                )?;
            }
        }
        Ok(())
    }
}

/// Group `r` (with its region, when it has one) sees the landmark of
/// witness `i`: the groups are united and the witness region intersected
/// with the group's. Err: the two regions have no common point.
#[allow(clippy::too_many_arguments)]
fn join_witness(
    wregions: &mut [Paving],
    slot_root: &mut [usize],
    i: usize,
    r: usize,
    region: Option<Paving>,
    uf: &mut Uf,
    out: &mut ShapesOutcome,
    max_boxes: usize,
) -> Result<(), String> {
    if let Some(region) = region {
        wregions[i].intersect(&region, max_boxes);
    }
    out.unions.push((slot_root[i], r));
    out.moved = true;
    out.moved_detections.push(r);
    slot_root[i] = uf.union(slot_root[i], r);
    if wregions[i].is_empty() {
        return Err(format!(
            "landmark of groups {} and {r}: their regions have no common point",
            slot_root[i]
        ));
    }
    Ok(())
}

/// Intersects p(step) and d(j) with a branch result; tells the chain of a
/// shrunk position. Returns whether p(step) moved.
fn apply(
    mission: &Mission,
    dom: &mut Domains,
    j: usize,
    br: &Branches,
    tol: f64,
    chain: &mut dyn Chain,
    out: &mut ShapesOutcome,
) -> Result<bool, String> {
    let dim = dom.dim;
    let t = mission.detections[j].step;
    if br.p.is_empty() || br.d.is_empty() {
        return Err(format!(
            "detection {j} (step {t}): its shape meets no part of its landmark's region"
        ));
    }
    let mut p_moved = 0.0f64;
    let mut d_moved = false;
    for a in 0..dim {
        let before = dom.pos[t * dim + a];
        let after = before.intersect(br.p[a]);
        p_moved = p_moved.max(shrinkage(before, after));
        dom.pos[t * dim + a] = after;
        let before = dom.det[j][a];
        let after = before.intersect(br.d[a]);
        d_moved |= shrinkage(before, after) > tol;
        dom.det[j][a] = after;
    }
    if dom.det[j].is_empty() || dom.pos[t * dim..(t + 1) * dim].iter().any(|x| x.is_empty()) {
        return Err(format!(
            "detection {j} (step {t}): its shape meets no part of its landmark's region"
        ));
    }
    if p_moved > tol || d_moved {
        out.moved = true;
        out.moved_detections.push(j);
    }
    if p_moved > tol {
        chain.changed(t);
    }
    Ok(p_moved > tol)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoChain(Vec<usize>);

    impl Chain for NoChain {
        fn sweep_forward(
            &mut self,
            _pos: &mut [Interval],
            _from: usize,
            to: usize,
        ) -> Result<bool, String> {
            Ok(to == usize::MAX)
        }
        fn changed(&mut self, step: usize) {
            self.0.push(step);
        }
    }

    /// Issue 19: an infinite bound that a branch leaves unchanged counted
    /// as an infinite move (`-inf - -inf` is NaN, read as "moved"), so an
    /// unbounded position was reported moving in every round. It moves
    /// only when it becomes finite or a finite bound moves by more than the
    /// tolerance.
    #[test]
    fn issue_19_an_unchanged_infinite_bound_has_not_moved() {
        let mission = Mission::from_value(&serde_json::json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [1.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": [{"step": 1, "range": [1, 2]}]
        }))
        .expect("valid mission");
        let half = Interval::new(0.0, f64::INFINITY);
        let mut pos = vec![Interval::ZERO, Interval::ZERO, half, Interval::ENTIRE];
        let mut det = vec![IntervalBox::new(&[Interval::ENTIRE, half])];
        let heading_at = [Interval::ZERO];
        let disp = [Interval::ZERO; 2];
        let br = Branches {
            p: IntervalBox::new(&[half, Interval::ENTIRE]),
            d: IntervalBox::new(&[Interval::ENTIRE, half]),
            surviving: vec![0],
        };
        let mut chain = NoChain(Vec::new());
        let mut out = ShapesOutcome::default();
        let mut dom = Domains {
            dim: 2,
            pos: &mut pos,
            det: &mut det,
            heading_at: &heading_at,
            disp: &disp,
        };
        assert_eq!(
            apply(&mission, &mut dom, 0, &br, 1e-9, &mut chain, &mut out),
            Ok(false)
        );
        assert!(!out.moved && out.moved_detections.is_empty() && chain.0.is_empty());
        // An infinite bound becoming finite is a move.
        let br = Branches {
            p: IntervalBox::new(&[Interval::new(0.0, 5.0), Interval::ENTIRE]),
            ..br
        };
        assert_eq!(
            apply(&mission, &mut dom, 0, &br, 1e-9, &mut chain, &mut out),
            Ok(true)
        );
        assert!(out.moved && out.moved_detections == [0] && chain.0 == [1]);
    }

    /// The registration's cache names witnesses by slot: an answer is
    /// carried over only while each slot holds the same landmark (its
    /// witness in one group with the old one), even when the regions look
    /// alike (here both unbounded, as after an unbounded step).
    #[test]
    fn a_cached_registration_needs_the_same_landmark_in_each_slot() {
        let entire = IntervalBox::entire(2);
        let key = |slots: Vec<usize>| RegKey {
            p: entire.clone(),
            roots: vec![4],
            slots,
            fixed: vec![None],
            pieces: 1,
            witnesses: vec![entire.clone(), entire.clone()],
        };
        let mut uf = Uf::new(6);
        let old = key(vec![0, 1]);
        assert!(old.close(&key(vec![0, 1]), 0.02, &mut uf));
        // The witnesses swapped slots: the masks would name the wrong ones.
        assert!(!old.close(&key(vec![1, 0]), 0.02, &mut uf));
        // Another detection of the same landmark stands for it.
        assert!(!old.close(&key(vec![0, 2]), 0.02, &mut uf));
        uf.union(1, 2);
        assert!(old.close(&key(vec![0, 2]), 0.02, &mut uf));
    }
}
