//! Step 2 of a shapes round: distinct pairs. Detections at nearby steps
//! whose shapes are disjoint in the frame of the earlier step see distinct
//! landmarks ([`relative_pairs`], once: they rest on the displacements and
//! the measurements, which do not change), so do pieces of groups disjoint
//! in a local frame ([`crate::shapes::frames`]); with n known,
//! [`crate::shapes::distinct::Distinct::infer`] merges the common
//! neighbours of every n-1 pairwise-distinct groups and proves
//! infeasibility from n+1 of them.
//!
//! Soundness: each pair rests on disjoint sound enclosures (see those
//! modules). Complexity: O(k · `max_ahead`) shape tests once, then per pass
//! the frames' pieces and the clique rule within `clique_budget`.

use super::round::sightings;
use super::round::Round;
use super::state::ShapesState;
use crate::shapes::chain_sums::ChainSums;
use crate::shapes::relative::relative_pairs;

impl ShapesState {
    /// Step 2 (module doc): `order` lists the detections by step.
    pub(super) fn distinct_pairs(
        &mut self,
        round: &mut Round,
        n: usize,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<(), String> {
        let sightings = sightings(round.mission);
        let dom = &round.dom;
        if !self.relative_done {
            self.relative_done = true;
            let mut pairs = Vec::new();
            relative_pairs(
                &sightings,
                order,
                dom.dim,
                sums,
                dom.pos,
                dom.det,
                dom.heading_at,
                self.options.max_ahead,
                &mut pairs,
            );
            round.out.contractions += pairs.len() as u64;
            self.distinct.add(pairs);
        }
        for pass in 0..self.options.frame_passes.max(1) {
            if pass > 0 {
                let mut pairs = Vec::new();
                round.out.contractions += self.frames.pairs(
                    &sightings,
                    order,
                    round.dom.dim,
                    sums,
                    round.dom.heading_at,
                    &mut round.uf,
                    &self.options.frames,
                    &mut pairs,
                )?;
                self.distinct.add(pairs);
            }
            let merged = self.infer(round, n)?;
            if !merged && pass > 0 {
                break;
            }
        }
        Ok(())
    }

    /// The groups the distinct pairs force together (n known), added to
    /// the round's unions; whether there was one.
    pub(super) fn infer(&mut self, round: &mut Round, n: usize) -> Result<bool, String> {
        let u = self
            .distinct
            .infer(&mut round.uf, n, self.options.clique_budget)?;
        let merged = !u.is_empty();
        round.out.moved |= merged;
        round
            .out
            .moved_detections
            .extend(u.iter().flat_map(|&(a, b)| [a, b]));
        round.out.unions.extend(u);
        Ok(merged)
    }
}
