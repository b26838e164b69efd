//! Steps 3 and 4 of a shapes round: the witnesses (n + 1 pairwise
//! disjoint or proved-distinct items prove infeasibility; n give the n
//! landmark regions) and the branch contraction of every other group and
//! detection against those n regions ([`Witnesses`]).
//!
//! Constraint: atmost_nvector(n) with n pairwise-distinct witnesses: every
//! other landmark is one of theirs. Soundness: the witness regions are
//! sound enclosures of distinct landmarks; a detection's branch keeps the
//! hull of every region its shape meets ([`branch`]), so a lone survivor
//! proves the matching and a missed region a distinct pair.
//! Complexity: O(k log k + 64² + k n) for the search, O(k · n · m · d) at
//! most for the branches (m boxes per region).

use super::pairs::roots;
use super::round::Round;
#[cfg(not(target_arch = "wasm32"))]
use super::state::RegionVersions;
use super::state::{CrossDeferred, ShapesState};
#[cfg(target_arch = "wasm32")]
use crate::shapes::branch::branch;
#[cfg(not(target_arch = "wasm32"))]
use crate::shapes::branch_memo::branch_memo;
use crate::shapes::chain_sums::ChainSums;
use crate::shapes::region::Paving;
use crate::shapes::shape::Shape;
use crate::shapes::witnesses::{find_witnesses, Item};

/// The n witness slots of a round: each slot's region (taken out of the
/// state while the detections are read) and the root of its group, with
/// the distinct pairs found on the way.
pub(super) struct Witnesses {
    /// The landmark region of each slot.
    pub regions: Vec<Paving>,
    /// The root of each slot's group.
    pub slot_root: Vec<usize>,
    /// Pairs (detection or group root, slot root) proved distinct.
    pub pairs: Vec<(u32, u32)>,
    /// Natively: the version of each slot's region, for the branches'
    /// memos ([`RegionVersions`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub versions: RegionVersions,
}

impl Witnesses {
    /// The region of slot `i`, to be changed (natively, it takes a new
    /// version first: [`RegionVersions`]).
    pub fn region_mut(&mut self, i: usize) -> &mut Paving {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let v = &mut self.versions;
            v.last += 1;
            v.slot[i] = v.last;
        }
        &mut self.regions[i]
    }

    /// Group `r` (with its region, when it has one) sees the landmark of
    /// witness `i`: the groups are united and the witness region
    /// intersected with the group's. Err: the two regions have no common
    /// point.
    pub fn join(
        &mut self,
        i: usize,
        r: usize,
        region: Option<Paving>,
        round: &mut Round,
        max_boxes: usize,
    ) -> Result<(), String> {
        if let Some(region) = region {
            self.region_mut(i).intersect(&region, max_boxes);
        }
        round.out.unions.push((self.slot_root[i], r));
        round.out.moved = true;
        round.out.moved_detections.push(r);
        self.slot_root[i] = round.uf.union(self.slot_root[i], r);
        if self.regions[i].is_empty() {
            return Err(format!(
                "landmark of groups {} and {r}: their regions have no common point",
                self.slot_root[i]
            ));
        }
        Ok(())
    }
}

impl ShapesState {
    /// Step 3: the witnesses. Err: more than n (infeasible); None: fewer
    /// than n (no branch this round); else the n witness regions, taken
    /// out of the state until [`ShapesState::restore`].
    /// `order` and `sums` serve the pairs between groups left undone by
    /// [`ShapesState::distinct_pairs`], looked for when fewer than n
    /// witnesses are found without them while the groups number n.
    pub(super) fn witness_regions(
        &mut self,
        round: &mut Round,
        n: usize,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<Option<Witnesses>, String> {
        let mut chosen = self.choose_witnesses(round, n)?;
        if chosen.len() < n
            && self.cross_deferred != CrossDeferred::default()
            && roots(&mut round.uf) >= n
            && self.deferred_pairs(round, order, sums)?
        {
            chosen = self.choose_witnesses(round, n)?;
        }
        round.out.contractions += 1;
        if chosen.len() > n {
            let mut named: Vec<usize> = chosen.clone();
            crate::sort::sort_usize(&mut named);
            return Err(format!(
                "detections {named:?} (with their groups): {} pairwise-disjoint shapes or proved-distinct groups, so at least {} distinct landmarks, more than landmark_count {n}",
                chosen.len(),
                chosen.len()
            ));
        }
        if chosen.len() < n {
            return Ok(None);
        }
        self.witnesses = chosen.clone();
        Ok(Some(self.take_witness_regions(round, chosen)))
    }

    /// Puts the witness regions back at their groups' roots and keeps the
    /// distinct pairs found.
    pub(super) fn restore(&mut self, w: Witnesses) {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let mut versions = w.versions;
            versions.end(&w.regions);
            self.region_versions = versions;
        }
        for (p, r) in w.regions.into_iter().zip(w.slot_root) {
            self.regions[r] = Some(p);
        }
        self.distinct.add(w.pairs);
    }

    /// Up to n + 1 pairwise disjoint or proved-distinct items (one per
    /// group: its region; one per ungrouped detection: its shape), seeded
    /// with the last round's witnesses; the roots of their groups.
    fn choose_witnesses(&mut self, round: &mut Round, n: usize) -> Result<Vec<usize>, String> {
        let k = round.mission.detections.len();
        let graph = self.distinct.graph(&mut round.uf)?;
        let mut roots: Vec<usize> = Vec::new();
        let mut size = vec![0usize; k];
        for j in 0..k {
            let r = round.uf.find(j);
            size[r] += 1;
        }
        let mut singles: Vec<Shape> = Vec::new();
        for (j, &count) in size.iter().enumerate() {
            if round.uf.find(j) == j {
                roots.push(j);
                if count == 1 {
                    singles.push(round.shape_of(j));
                }
            }
        }
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
            let r = round.uf.find(w);
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
        let w = find_witnesses(&sizes, &mut apart, n + 1, &seed, self.options.node_budget);
        Ok(w.into_iter().map(|i| item_root[i]).collect())
    }

    /// The n witness regions, taken out of the state (a singleton's region
    /// is its shape, paved).
    fn take_witness_regions(&mut self, round: &Round, chosen: Vec<usize>) -> Witnesses {
        let mut regions: Vec<Paving> = Vec::with_capacity(chosen.len());
        for &r in &chosen {
            let p = match self.regions[r].take() {
                Some(p) => p,
                None => {
                    let s = round.shape_of(r);
                    let mut p = Paving::from_box(&s.hull());
                    p.refine(&[&s], self.options.resolution, self.options.max_boxes);
                    self.cut_with[r] = Some(s.centre.clone());
                    p
                }
            };
            regions.push(p);
        }
        #[cfg(not(target_arch = "wasm32"))]
        let versions = {
            let mut v = std::mem::take(&mut self.region_versions);
            v.start(&regions);
            v
        };
        Witnesses {
            regions,
            slot_root: chosen,
            pairs: Vec::new(),
            #[cfg(not(target_arch = "wasm32"))]
            versions,
        }
    }

    /// Groups first: a group's region is at most the region of each
    /// member's shape, so it meets fewer witnesses. A group whose region
    /// meets one witness joins it; the witnesses it misses are distinct.
    pub(super) fn groups_on_witnesses(
        &mut self,
        round: &mut Round,
        w: &mut Witnesses,
    ) -> Result<(), String> {
        let k = round.mission.detections.len();
        let n = w.regions.len();
        for r in 0..k {
            if round.uf.find(r) != r || w.slot_root.contains(&r) {
                continue;
            }
            let Some(region) = self.regions[r].as_ref() else {
                continue;
            };
            let meets: Vec<usize> = (0..n).filter(|&i| w.regions[i].meets(region)).collect();
            round.out.contractions += n as u64;
            for (i, &root) in w.slot_root.iter().enumerate() {
                if !meets.contains(&i) {
                    w.pairs.push((r as u32, root as u32));
                }
            }
            match meets[..] {
                [] => {
                    let g: Vec<usize> = (0..k).filter(|&j| round.uf.find(j) == r).collect();
                    return Err(format!(
                        "landmark of detections {g:?}: its region meets none of the {n} landmark regions of the pairwise-distinct groups {:?}",
                        w.slot_root
                    ));
                }
                [i] => {
                    let region = self.regions[r].take();
                    w.join(i, r, region, round, self.options.max_boxes)?;
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Every detection in no witness group, in step order, contracted by
    /// [`branch`] against the n regions (a sequential filter: a lone
    /// survivor joins its witness, whose region is cut by the detection's
    /// shape at once); the chain swept forward to each detection's step
    /// before it is read. The last live change is left to the caller's
    /// passes ([`super::Chain::changed`]).
    pub(super) fn detections_on_witnesses(
        &mut self,
        round: &mut Round,
        w: &mut Witnesses,
        order: &[usize],
    ) -> Result<(), String> {
        let mut result = Ok(());
        // The step from which a forward change of the chain may be alive.
        let mut alive: Option<usize> = None;
        for &j in order {
            let t = round.step_of(j);
            if w.slot_root.contains(&round.uf.find(j)) {
                continue;
            }
            if let Some(from) = alive.filter(|&f| f < t) {
                match round.chain.sweep_forward(round.dom.pos, from, t) {
                    Ok(true) => alive = Some(t),
                    Ok(false) => alive = None,
                    Err(e) => {
                        result = Err(e);
                        break;
                    }
                }
            }
            match self.detection_on_witnesses(round, w, j) {
                Ok(true) => alive = Some(t),
                Ok(false) => {}
                Err(e) => {
                    result = Err(e);
                    break;
                }
            }
        }
        if let Some(step) = alive {
            round.chain.changed(step);
        }
        result
    }

    /// Detection `j` against the n witness regions; whether p(step) moved.
    fn detection_on_witnesses(
        &mut self,
        round: &mut Round,
        w: &mut Witnesses,
        j: usize,
    ) -> Result<bool, String> {
        let n = w.regions.len();
        let rj = round.uf.find(j);
        let s = round.shape_of(j);
        let br = {
            let refs: Vec<&Paving> = w.regions.iter().collect();
            // Natively, each region's part of j's last branch is reused
            // while j's shape and that region are the same (the same
            // bits as `branch`: crate::shapes::branch_memo).
            #[cfg(not(target_arch = "wasm32"))]
            let br = branch_memo(&s, &refs, &w.versions.slot, &mut self.branch_memos[j]);
            #[cfg(target_arch = "wasm32")]
            let br = branch(&s, &refs);
            br
        };
        round.out.contractions += w
            .regions
            .iter()
            .map(|p| p.boxes().len() as u64)
            .sum::<u64>();
        if br.surviving.is_empty() {
            return Err(format!(
                "detection {j} (step {}): its shape meets none of the {n} landmark regions of the pairwise-disjoint witnesses {:?}",
                round.step_of(j),
                w.slot_root
            ));
        }
        for (i, &r) in w.slot_root.iter().enumerate() {
            if !br.surviving.contains(&i) {
                w.pairs.push((j as u32, r as u32));
            }
        }
        if let [i] = br.surviving[..] {
            // j (and its group) sees the landmark of witness i.
            round.out.unions.push((w.slot_root[i], j));
            round.out.moved = true;
            round.out.moved_detections.push(j);
            if let Some(p) = self.regions[rj].take() {
                w.region_mut(i).intersect(&p, self.options.max_boxes);
            }
            w.slot_root[i] = round.uf.union(w.slot_root[i], j);
            w.region_mut(i).cut(&s);
            self.cut_with[j] = Some(s.centre.clone());
            round.out.contractions += w.regions[i].boxes().len() as u64;
            if w.regions[i].is_empty() {
                return Err(format!(
                    "landmark of detection {j} and witness group {}: no common point",
                    w.slot_root[i]
                ));
            }
        }
        round.apply(j, &br)
    }
}
