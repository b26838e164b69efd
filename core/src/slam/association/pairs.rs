//! Step 2 of a shapes round: distinct pairs. Detections at nearby steps
//! whose shapes are disjoint in the frame of the earlier step see distinct
//! landmarks ([`relative_pairs`], once: they rest on the displacements and
//! the measurements, which do not change), so do pieces of groups disjoint
//! in a local frame ([`crate::shapes::frames`]); with n known,
//! [`crate::shapes::distinct::Distinct::infer`] merges the common
//! neighbours of every n-1 pairwise-distinct groups and proves
//! infeasibility from n+1 of them.
//!
//! The mission's scans add pairs too ([`scan_pairs`], once): detections
//! of one scan see pairwise distinct landmarks (formats.md, `scan`).
//!
//! Soundness: each pair rests on disjoint sound enclosures (see those
//! modules), or on the scan's statement; a scan pair holds only when every
//! detection is real, and the shapes round runs only with `max_outliers`
//! = 0 (a false detection sees no landmark, so it is distinct from
//! nothing; with q > 0 the pairs would not hold and are never added). Complexity: O(k · `max_ahead`) shape tests once, then per pass
//! the frames' pieces and the clique rule within `clique_budget`.

use super::round::sightings;
use super::round::Round;
use super::state::ShapesState;
use crate::shapes::chain_sums::ChainSums;
use crate::shapes::relative_pairs::relative_pairs_where;
use crate::union_find::Uf;

impl ShapesState {
    /// Step 2 (module doc): `order` lists the detections by step.
    ///
    /// At most n groups (the incremental schedule; every detection named by the operator,
    /// say, or the groups complete): the pairs between different groups
    /// are then not looked for (the relative pairs of round 1 between
    /// different groups, the frames' tests), only those inside a group
    /// (each a proof of infeasibility). Why no box can change: with R <= n
    /// roots, the clique rule has nothing to merge (a merge needs an
    /// (n-1)-clique and two common neighbours, n + 1 roots) nor an
    /// (n+1)-clique to find; no group grows (step 3 finds at most R
    /// witnesses, so with R < n none; with R = n every root is a witness,
    /// steps 4-5 join nothing, and the registration fixes every group to
    /// its own slot, where its map search reads no pair); so the pairs
    /// between groups only serve the witness search's "apart", and
    /// [`ShapesState::witness_regions`] looks for them when it finds fewer
    /// than n witnesses with R = n, in this round (on the same domains:
    /// the same pairs as the full work's) or a later one.
    pub(super) fn distinct_pairs(
        &mut self,
        round: &mut Round,
        n: usize,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<(), String> {
        let few = !self.full_work && roots(&mut round.uf) <= n;
        if !self.relative_done {
            self.relative_done = true;
            self.cross_deferred.relative = few;
            let mut pairs = Vec::new();
            self.relative(round, order, sums, !few, &mut pairs);
            scan_pairs(round.mission, n, &mut pairs)?;
            round.out.contractions += pairs.len() as u64;
            self.distinct.add(pairs);
        }
        for pass in 0..self.options.frame_passes.max(1) {
            if pass > 0 {
                if few {
                    self.cross_deferred.frames = true;
                    round.out.contractions += self.frames.build(
                        &sightings(round.mission),
                        round.dom.dim,
                        sums,
                        round.dom.heading_at,
                        &mut round.uf,
                        &self.options.frames,
                    )?;
                } else {
                    self.frame_pairs(round, order, sums)?;
                }
            }
            let merged = self.infer(round, n)?;
            if !merged && pass > 0 {
                break;
            }
        }
        Ok(())
    }

    /// The pairs between different groups that [`Self::distinct_pairs`]
    /// left undone, looked for now; whether there were any.
    pub(super) fn deferred_pairs(
        &mut self,
        round: &mut Round,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<bool, String> {
        let undone = std::mem::take(&mut self.cross_deferred);
        if undone.relative {
            let mut pairs = Vec::new();
            self.relative(round, order, sums, true, &mut pairs);
            round.out.contractions += pairs.len() as u64;
            self.distinct.add(pairs);
        }
        if undone.frames {
            self.frame_pairs(round, order, sums)?;
        }
        Ok(undone.relative || undone.frames)
    }

    /// The relative pairs ([`relative_pairs_where`]): of every two
    /// detections with `cross`, else only of two in one group.
    fn relative(
        &self,
        round: &mut Round,
        order: &[usize],
        sums: &ChainSums,
        cross: bool,
        pairs: &mut Vec<(u32, u32)>,
    ) {
        let sightings = sightings(round.mission);
        let (dom, uf) = (&round.dom, &mut round.uf);
        // Two operator ids do not prove two landmarks distinct (the
        // model ties each id to a variable; atmost_nvector allows two
        // variables to coincide): the pairs come from the shapes only.
        relative_pairs_where(
            &sightings,
            order,
            dom.dim,
            sums,
            (dom.pos, dom.det, dom.heading_at),
            self.options.max_ahead,
            &mut |i, j| cross || uf.find(i) == uf.find(j),
            pairs,
        );
    }

    /// The frames' pieces and their pairs ([`crate::shapes::frames`]).
    fn frame_pairs(
        &mut self,
        round: &mut Round,
        order: &[usize],
        sums: &ChainSums,
    ) -> Result<(), String> {
        let mut pairs = Vec::new();
        round.out.contractions += self.frames.pairs(
            &sightings(round.mission),
            order,
            round.dom.dim,
            sums,
            round.dom.heading_at,
            &mut round.uf,
            &self.options.frames,
            &mut pairs,
        )?;
        self.distinct.add(pairs);
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

/// Scans larger than this add no pairs (their pairs grow as the square of
/// the scan's size; dropping evidence is sound).
const MAX_SCAN_FOR_PAIRS: usize = 64;

/// The distinct pairs of the mission's scans: every two detections of one
/// scan. Err: a scan holds more detections than there are landmarks (n),
/// which no matching can satisfy. O(k log k + the pairs), the pairs at
/// most k·`MAX_SCAN_FOR_PAIRS`/2.
pub(super) fn scan_pairs(
    mission: &crate::slam::mission::Mission,
    n: usize,
    out: &mut Vec<(u32, u32)>,
) -> Result<(), String> {
    let mut by_scan: Vec<(u64, u32)> = mission
        .detections
        .iter()
        .enumerate()
        .filter_map(|(j, d)| d.scan.map(|s| (s, j as u32)))
        .collect();
    crate::sort::sort_ord(&mut by_scan);
    for run in by_scan.chunk_by(|a, b| a.0 == b.0) {
        if run.len() > n {
            return Err(format!(
                "scan {} holds {} detections of pairwise distinct landmarks, more than landmark_count {n}",
                run[0].0,
                run.len()
            ));
        }
        if run.len() > MAX_SCAN_FOR_PAIRS {
            continue;
        }
        for (x, a) in run.iter().enumerate() {
            for b in &run[x + 1..] {
                out.push((a.1, b.1));
            }
        }
    }
    Ok(())
}

/// The number of groups (roots) of `uf`, singletons included. O(k).
pub(super) fn roots(uf: &mut Uf) -> usize {
    (0..uf.len()).filter(|&j| uf.find(j) == j).count()
}
