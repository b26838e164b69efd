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
            // Issue 18: with every landmark named by the operator, the
            // names say which detections see distinct landmarks; the
            // shapes' pairs (O(k · max_ahead) shape tests) are not sought.
            let named = !self.full_work && label_pairs(round.mission, n, &mut pairs);
            if !named {
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
            }
            scan_pairs(round.mission, n, &mut pairs)?;
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

/// When every detection carries the operator's `landmark` (an id below
/// n naming the landmark, formats.md) and at most [`MAX_LABELS_FOR_PAIRS`]
/// ids are used: one pair between the first detections of every two ids
/// (distinct ids name distinct landmarks; the groups carry the pairs to
/// their members), and true. Else nothing and false. O(k + ids²).
fn label_pairs(
    mission: &crate::slam::mission::Mission,
    n: usize,
    out: &mut Vec<(u32, u32)>,
) -> bool {
    let mut first: Vec<(usize, u32)> = Vec::new();
    for (j, d) in mission.detections.iter().enumerate() {
        let Some(l) = d.landmark.filter(|&l| l < n) else {
            return false;
        };
        if let Err(x) = first.binary_search_by_key(&l, |e| e.0) {
            if first.len() == MAX_LABELS_FOR_PAIRS {
                return false;
            }
            first.insert(x, (l, j as u32));
        }
    }
    for (x, a) in first.iter().enumerate() {
        for b in &first[x + 1..] {
            out.push((a.1.min(b.1), a.1.max(b.1)));
        }
    }
    true
}

/// Most operator ids whose pairs [`label_pairs`] lists.
const MAX_LABELS_FOR_PAIRS: usize = 64;

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
    by_scan.sort_unstable();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::mission::Mission;

    fn mission(labels: &[Option<usize>]) -> Mission {
        let detections: Vec<serde_json::Value> = labels
            .iter()
            .map(|l| match l {
                Some(l) => serde_json::json!({"step": 1, "range": [1, 2], "landmark": l}),
                None => serde_json::json!({"step": 1, "range": [1, 2]}),
            })
            .collect();
        Mission::from_value(&serde_json::json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "landmark_count": 3,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [1.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": detections
        }))
        .expect("valid mission")
    }

    /// Issue 18: with every landmark named, one pair between the first
    /// detections of every two names; with one detection unnamed, none
    /// (the shapes' pairs are sought instead).
    #[test]
    fn label_pairs_pair_the_names_only_when_every_detection_is_named() {
        let mut pairs = Vec::new();
        assert!(label_pairs(
            &mission(&[Some(2), Some(0), Some(2), Some(1)]),
            3,
            &mut pairs
        ));
        pairs.sort_unstable();
        assert_eq!(pairs, [(0, 1), (0, 3), (1, 3)]);
        let mut pairs = Vec::new();
        assert!(!label_pairs(
            &mission(&[Some(2), None, Some(0)]),
            3,
            &mut pairs
        ));
        assert!(pairs.is_empty());
    }
}
