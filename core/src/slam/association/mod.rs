//! The `shapes` contractor of a SLAM round: landmark regions of the proved
//! groups, shape witnesses and branch contraction, run over every
//! detection (docs/design.md, "Detection shapes").
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
//! 1. **Landmark regions.** Each group of size >= 2 keeps a [`Paving`](crate::shapes::region::Paving) of
//!    its landmark ([`crate::shapes::region`]): cut by every member's shape whose
//!    centre box changed since it last cut it, bisected down to a bounded
//!    count (halves cut by the thinnest members). Each member is then
//!    contracted by [`branch`](crate::shapes::branch::branch) against its group's region alone: d(j) and
//!    p(step) shrink to the hulls of the pieces.
//! 2. **Distinct pairs.** Detections at nearby steps whose shapes are
//!    disjoint in the frame of the earlier step ([`relative_pairs`](crate::shapes::relative_pairs::relative_pairs)) see
//!    distinct landmarks; so do a detection and a region its branch
//!    excluded (step 4). With n known, [`Distinct::infer`](crate::shapes::distinct::Distinct::infer) merges the
//!    common neighbours of every n-1 pairwise-distinct groups and proves
//!    infeasibility from n+1 of them. With at most n groups (every
//!    detection named by the operator, say) only the pairs inside a group
//!    are looked for at once, those between groups when the witness
//!    search needs them (`pairs.rs` gives why no box can change).
//! 3. **Witnesses.** Items are the groups' regions and the shapes of the
//!    detections in no group. [`find_witnesses`](crate::shapes::witnesses::find_witnesses) looks for n + 1 pairwise
//!    disjoint (or proved distinct) items: n + 1 is infeasible (the items'
//!    detections are named); n gives n regions R(1..n) (a singleton's
//!    region is its shape, paved) holding the n distinct landmarks, one
//!    each.
//! 4. **Branch contraction.** With n witnesses, every other detection j
//!    (in step order) is contracted by [`branch`](crate::shapes::branch::branch) against R(1..n): its
//!    landmark is one of the n. A single surviving region proves the
//!    matching: j (with its group) joins that witness's group, whose region
//!    is cut by j's shape at once, so later detections meet a smaller
//!    region (a sequential filter). A region that does not survive is a
//!    distinct pair.
//!
//! 5. **Registration** ([`crate::shapes::registration::register`]): at the steps of the groups' local
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
use crate::shapes::chain_sums::ChainSums;
use crate::union_find::Uf;
use round::Round;

mod group_regions;
pub mod odometry2d;
mod pairs;
mod registration_step;
mod round;
mod state;
pub mod step;
mod witness_step;

pub use round::sightings;
pub use state::{Chain, Domains, ShapesOptions, ShapesOutcome, ShapesState};

impl ShapesState {
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
        let k = mission.detections.len();
        if max_outliers > 0 || k == 0 {
            return ShapesOutcome::default();
        }
        if self.regions.len() != k {
            *self = ShapesState {
                options: self.options.clone(),
                fixed_displacements: self.fixed_displacements,
                full_work: self.full_work,
                ..ShapesState::new(k)
            };
        }
        let mut uf = Uf::new(k);
        for g in groups {
            for &j in &g[1..] {
                uf.union(g[0], j);
            }
        }
        let mut round = Round {
            mission,
            dom,
            uf,
            tol: tolerance,
            chain,
            out: ShapesOutcome::default(),
        };
        if let Err(reason) = self.steps(&mut round, n) {
            round.out.infeasible = Some(reason);
        }
        round.out
    }

    /// The steps of the module doc, in order; Err: the mission is
    /// infeasible (the reason).
    fn steps(&mut self, round: &mut Round, n: Option<usize>) -> Result<(), String> {
        self.group_regions(round)?;
        let Some(n) = n else {
            return Ok(());
        };
        let dets = &round.mission.detections;
        let mut order: Vec<usize> = (0..dets.len()).collect();
        crate::sort::sort_indices_by(&mut order, |a, b| dets[a].step.cmp(&dets[b].step));
        let (disp, dim) = (round.dom.disp, round.dom.dim);
        // Built once when the displacements do not change (the same bits:
        // the same displacements and detection steps).
        let kept = self.stored_sums.take().filter(|_| self.fixed_displacements);
        let sums = match kept.and_then(|s| s.attach(disp, dim)) {
            Some(sums) => sums,
            None => {
                let steps: Vec<usize> = dets.iter().map(|d| d.step).collect();
                ChainSums::new(disp, dim).with_steps(&steps)
            }
        };
        let result = self.steps_with_sums(round, n, &order, &sums);
        if self.fixed_displacements {
            self.stored_sums = Some(sums.store());
        }
        result
    }

    /// The steps of the module doc after the groups' regions, with the
    /// chain sums `sums`.
    fn steps_with_sums(
        &mut self,
        round: &mut Round,
        n: usize,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<(), String> {
        self.distinct_pairs(round, n, order, sums)?;
        if let Some(mut w) = self.witness_regions(round, n, order, sums)? {
            // An infeasible group ends the round at once (the witness
            // regions and the pairs found are dropped: the mission is
            // infeasible).
            self.groups_on_witnesses(round, &mut w)?;
            let mut result = self.detections_on_witnesses(round, &mut w, order);
            if result.is_ok() && self.options.registration && n <= 64 {
                result = self.register_anchors(round, sums, &mut w);
            }
            self.restore(w);
            result?;
        }
        self.infer(round, n)?;
        Ok(())
    }
}
