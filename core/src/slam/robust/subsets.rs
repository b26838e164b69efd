//! Consensus over subsets: detections proved false, and the trajectory
//! enclosed, by solving the ordinary (q = 0) propagation on subsets of the
//! detections of which every reading keeps at least one whole
//! (`max_outliers` = q > 0, small q; docs/outliers.md, "Consensus over
//! subsets").
//!
//! # Constraint
//!
//! A *reading* drops at most q detections (docs/formats.md). A detection
//! is *proved false* when no reading keeps it; every box must enclose
//! every solution of every reading.
//!
//! # Math
//!
//! 1. *Relaxation.* For a set S of detections, the mission `stripped(S)`
//!    whose detections outside S lose every constraint (range [0, +inf],
//!    no bearing, region, label or scan; [`crate::slam::robust::kept::stripped`]), with
//!    q = 0, is a relaxation of every reading that keeps all of S: a
//!    solution of such a reading is one of it (a stripped detection takes
//!    the landmark of any kept one). So the ordinary propagator, with the
//!    requested association, encloses every solution of every reading
//!    keeping S, and when it proves `stripped(S)` infeasible, no reading
//!    keeps all of S. What is propagated is the mission of S's detections
//!    only ([`crate::slam::robust::kept::kept_only`]), a relaxation of `stripped(S)`
//!    (its boxes enclose those of `stripped(S)`, its infeasibility proves
//!    `stripped(S)`'s): the stripped detections' unbounded shapes cost
//!    the shapes reasoning most of its time (measured: a 60-step
//!    odometry2d mission of 143 detections, q = 1, `best`, 27 s in
//!    `contract_distance` under the witness step, `perf`).
//! 2. *A family that every reading keeps one of.* The detections are dealt
//!    in time order into b blocks; the family is the C(b, q) sets S(E) =
//!    every detection outside the blocks E, for every set E of q blocks. A
//!    reading drops at most q detections, which lie in at most q blocks E:
//!    it keeps S(E) whole. Hence every solution of every reading is a
//!    solution of some feasible `stripped(S(E))` (step 1): the positions
//!    (and, odometry2d, the headings) lie in the hull of the feasible
//!    sets' boxes, and when no set is feasible, the mission has no
//!    reading at all.
//! 3. *Proved false.* A detection j kept by a reading lies, with the whole
//!    of some feasible S(E), in that reading; if j is in S(E), the solve
//!    of step 1 already holds j. So j can only be proved false when every
//!    feasible set leaves its block out; then j is proved false when, for
//!    every feasible S(E), `stripped(S(E) ∪ {j})` is proved infeasible
//!    (step 1: no reading keeps S(E) and j).
//!
//! The robust rounds ([`crate::slam::robust`]) take the proved false
//! detections (each lowers the budget of the others) and the positions;
//! when the proved false detections account for q, every other detection
//! is kept in every reading ([`crate::slam::robust::kept`]) and the ordinary
//! propagation on them gives the matching.
//!
//! b is the largest block count with C(b, q) <= [`MAX_SETS`] and b <= k;
//! the rule runs only when the sets keep at least half of the detections
//! ((b - q) / b >= 1/2: q <= 3 in practice); otherwise each set holds too
//! few detections to prove anything and nothing is done.
//!
//! # Soundness
//!
//! Steps 1-3 follow from the semantics of `max_outliers` and from the
//! soundness of the ordinary propagator (an infeasible verdict is a proof,
//! a stopped one is treated as feasible); hulls of boxes are exact.
//! Tested by planting up to q false detections of every kind
//! (`core/tests/slam/robust/subsets.rs`): no true detection is ever proved
//! false, no true position is lost.
//!
//! # Complexity
//!
//! Skipped when (N + k) times the most propagations exceeds [`MAX_WORK`]
//! (about 390,000 steps and detections).
//! At most [`MAX_SETS`] + [`MAX_TESTS`] ordinary propagations of the
//! mission (each costs what a run with q = 0 costs), O(C(b, q) · N · d)
//! memory for nothing more than one hull at a time: O(N · d + k).

use crate::interval::Interval;
use crate::slam::mission::Mission;
use crate::slam::propagate::rounds::rounds;
use crate::slam::robust::kept::kept_only;
use crate::slam::types::{Progress, SolveOptions, SolveStatus};
use std::sync::atomic::AtomicBool;

/// Most sets S(E) of the family (ordinary propagations of step 2).
pub const MAX_SETS: u64 = 32;

/// Most propagations of step 3 (detections tested against feasible sets).
pub const MAX_TESTS: usize = 96;

/// Most (steps + detections) x propagations the rule may spend: up to
/// [`MAX_SETS`] + [`MAX_TESTS`] ordinary propagations of the whole mission
/// are affordable on missions of a few hundred thousand steps (the paper
/// scenario's 10,000 take a fraction of a second each), not on the
/// format's 2,000,000 (128 solves of those would take minutes): above
/// this, the rule is skipped (it claims nothing, which is sound).
pub const MAX_WORK: u64 = 50_000_000;

/// Whether the rule's propagations fit [`MAX_WORK`].
pub fn within_work(steps: usize, detections: usize) -> bool {
    let solves = MAX_SETS + MAX_TESTS as u64;
    (steps as u64)
        .saturating_add(detections as u64)
        .saturating_mul(solves)
        <= MAX_WORK
}

/// What [`consensus`] proves.
#[derive(Debug, Clone, PartialEq)]
pub enum Consensus {
    /// q too large for the family (or nothing to do): nothing is claimed.
    Skipped,
    /// No set of the family is feasible: no reading exists (the reason).
    Infeasible(String),
    /// The proof: per detection, proved false; the hull of the feasible
    /// sets' position boxes ((N + 1) · d intervals); the propagations run
    /// and their contractions.
    Proved {
        /// Per detection: no reading keeps it.
        proved_false: Vec<bool>,
        /// Encloses every position of every reading.
        positions: Vec<Interval>,
        /// odometry2d: encloses every heading th(0..=N) of every reading
        /// (the hull of the feasible sets' headings, as the positions);
        /// empty for the other models.
        headings: Vec<Interval>,
        /// Ordinary propagations run.
        solves: usize,
        /// Their contractions.
        contractions: u64,
    },
}

/// C(b, q), saturating above `MAX_SETS` (exact below it).
fn binomial_capped(b: u64, q: u64) -> u64 {
    let q = q.min(b - q.min(b));
    let mut c: u64 = 1;
    for i in 0..q {
        // c · (b - i) / (i + 1) is exact (a binomial coefficient).
        c = c.saturating_mul(b - i) / (i + 1);
        if c > MAX_SETS {
            return MAX_SETS + 1;
        }
    }
    c
}

/// The block count b of the module doc, or `None` when the rule does not
/// apply (q = 0, or the sets would keep less than half the detections).
pub fn block_count(q: usize, k: usize) -> Option<usize> {
    if q == 0 || k <= q {
        return None;
    }
    // b grows from q + 1 while C(b, q) stays within the cap (C grows with
    // b; for q = 1 the cap bounds b by MAX_SETS).
    let mut b = q + 1;
    while b < k && binomial_capped(b as u64 + 1, q as u64) <= MAX_SETS {
        b += 1;
    }
    (binomial_capped(b as u64, q as u64) <= MAX_SETS && 2 * (b - q) >= b).then_some(b)
}

/// The next q-subset of 0..b in lexicographic order (`None` after the last).
fn next_combination(c: &mut [usize], b: usize) -> Option<()> {
    let q = c.len();
    let i = (0..q).rev().find(|&i| c[i] < b - q + i)?;
    c[i] += 1;
    for t in i + 1..q {
        c[t] = c[t - 1] + 1;
    }
    Some(())
}

/// The ordinary propagation of `kept_only(keep)` (a relaxation of
/// `stripped(keep)`: module doc, step 1).
fn solve_kept(
    mission: &Mission,
    keep: &[bool],
    options: &SolveOptions,
    cancel: &AtomicBool,
) -> (SolveStatus, (Vec<Interval>, Vec<Interval>), u64) {
    let sub = kept_only(mission, keep);
    let s = rounds(&sub, options, &mut |_: &Progress| {}, cancel);
    (s.status, (s.model.pos, s.model.heading), s.contractions)
}

/// The hull of two lists of intervals, element-wise (`None`: the first).
fn hull_of(h: Option<Vec<Interval>>, x: Vec<Interval>) -> Vec<Interval> {
    match h {
        None => x,
        Some(h) => h.iter().zip(&x).map(|(a, p)| a.hull(*p)).collect(),
    }
}

/// Consensus over subsets (module doc) for a mission with `max_outliers`
/// = q (at most k). `Skipped` when the rule does not apply.
pub fn consensus(
    mission: &Mission,
    q: usize,
    options: &SolveOptions,
    cancel: &AtomicBool,
) -> Consensus {
    consensus_told(mission, q, options, cancel, &mut |_| {})
}

/// [`consensus`], telling `tell` after each propagation the share of its
/// most propagations ([`MAX_SETS`] + [`MAX_TESTS`] at most) run so far, a
/// number in (0, 1] that never decreases (for a job's progress: on a
/// long mission the rule runs for minutes).
pub fn consensus_told(
    mission: &Mission,
    q: usize,
    options: &SolveOptions,
    cancel: &AtomicBool,
    tell: &mut dyn FnMut(f64),
) -> Consensus {
    let k = mission.detections.len();
    if !within_work(mission.steps, k) {
        return Consensus::Skipped;
    }
    let Some(b) = block_count(q, k) else {
        return Consensus::Skipped;
    };
    // Blocks dealt in time order (ties by index).
    let mut order: Vec<usize> = (0..k).collect();
    let dets = &mission.detections;
    crate::sort::sort_indices_by(&mut order, |x, y| dets[x].step.cmp(&dets[y].step));
    let mut block = vec![0usize; k];
    for (rank, &j) in order.iter().enumerate() {
        block[j] = rank % b;
    }
    let most = (binomial_capped(b as u64, q as u64) as usize + MAX_TESTS) as f64;
    let mut told = |solves: usize| tell((solves as f64 / most).min(1.0));
    let mut excluded: Vec<usize> = (0..q).collect();
    let mut feasible: Vec<Vec<bool>> = Vec::new();
    let mut positions: Option<Vec<Interval>> = None;
    let mut headings: Option<Vec<Interval>> = None;
    let (mut solves, mut contractions) = (0usize, 0u64);
    loop {
        let keep: Vec<bool> = block.iter().map(|bl| !excluded.contains(bl)).collect();
        let (status, (pos, heading), c) = solve_kept(mission, &keep, options, cancel);
        solves += 1;
        contractions += c;
        told(solves);
        if !matches!(status, SolveStatus::Infeasible(_)) {
            positions = Some(hull_of(positions, pos));
            headings = Some(hull_of(headings, heading));
            feasible.push(keep);
        }
        if next_combination(&mut excluded, b).is_none() {
            break;
        }
    }
    let Some(positions) = positions else {
        return Consensus::Infeasible(format!(
            "the detections dealt into {b} blocks in time order: the mission without any {q} of the blocks is infeasible, so no choice of at most {q} false detections is consistent"
        ));
    };
    let proved_false = prove_false(
        mission,
        &feasible,
        options,
        cancel,
        (&mut solves, &mut contractions),
        &mut told,
    );
    Consensus::Proved {
        proved_false,
        positions,
        headings: headings.unwrap_or_default(),
        solves,
        contractions,
    }
}

/// Step 3 of the module doc with the ordinary propagation as the test
/// ([`search_false`]).
fn prove_false(
    mission: &Mission,
    feasible: &[Vec<bool>],
    options: &SolveOptions,
    cancel: &AtomicBool,
    (solves, contractions): (&mut usize, &mut u64),
    told: &mut dyn FnMut(usize),
) -> Vec<bool> {
    search_false(feasible, MAX_TESTS, &mut |keep: &[bool]| {
        let (status, _, c) = solve_kept(mission, keep, options, cancel);
        *solves += 1;
        *contractions += c;
        told(*solves);
        matches!(status, SolveStatus::Infeasible(_))
    })
}

/// Step 3 of the module doc: the detections left out of every feasible
/// set, each proved false when `infeasible(set ∪ {j})` holds for every
/// feasible set (at most `cap` calls of `infeasible`, which proves a set
/// of detections infeasible or answers false).
///
/// The candidates (often a quarter of the detections or more, and a few
/// false among them) are searched by halving against the first feasible
/// set F: a run of candidates whose union with F is not proved infeasible
/// is not searched further (one test for the whole run); an infeasible
/// run is halved, and when its first half is not proved infeasible the
/// second half's own test is skipped (the run's conflict lies in it or
/// across the halves). Only single-candidate tests, `F ∪ {j}` proved
/// infeasible, prove anything, and each such j is then tested against
/// the other feasible sets. The halving only orders the work: a
/// candidate it does not reach is not claimed, which is sound. With f
/// candidates refutable alone among c, about 2 f log2(c) tests instead of
/// up to c.
pub fn search_false(
    feasible: &[Vec<bool>],
    cap: usize,
    infeasible: &mut dyn FnMut(&[bool]) -> bool,
) -> Vec<bool> {
    let k = feasible.first().map_or(0, Vec::len);
    let mut proved_false = vec![false; k];
    let Some(first) = feasible.first() else {
        return proved_false;
    };
    let candidates: Vec<usize> = (0..k).filter(|&j| feasible.iter().all(|s| !s[j])).collect();
    let mut tests = 0usize;
    let mut test = |set: &[bool], add: &[usize]| -> Option<bool> {
        if tests == cap {
            return None;
        }
        tests += 1;
        let mut keep = set.to_vec();
        for &j in add {
            keep[j] = true;
        }
        Some(infeasible(&keep))
    };
    // Runs of candidates still to search: (run, its infeasibility with F
    // inferred (its test skipped), it is a first half whose sibling lies
    // just below it on the stack).
    let mut runs: Vec<(&[usize], bool, bool)> = vec![(&candidates[..], false, false)];
    let mut found: Vec<usize> = Vec::new();
    while let Some((run, inferred, first_half)) = runs.pop() {
        if run.is_empty() {
            continue;
        }
        if !(inferred && run.len() > 1) {
            let Some(bad) = test(first, run) else {
                break;
            };
            if !bad {
                // The parent's conflict then lies in the sibling (or across).
                if first_half {
                    if let Some(sibling) = runs.last_mut() {
                        sibling.1 = true;
                    }
                }
                continue;
            }
            if run.len() == 1 {
                found.push(run[0]);
                continue;
            }
        }
        let (a, b) = run.split_at(run.len() / 2);
        runs.push((b, false, false));
        runs.push((a, false, true));
    }
    'found: for j in found {
        for set in &feasible[1..] {
            match test(set, &[j]) {
                Some(true) => {}
                Some(false) => continue 'found,
                None => break 'found,
            }
        }
        proved_false[j] = true;
    }
    proved_false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper scenario's missions fit the work cap; the format's
    /// largest (2,000,000 steps, which `huge_fields` runs with q = 3) and
    /// overflowing sizes do not.
    #[test]
    fn the_work_cap() {
        assert!(within_work(10_000, 300));
        assert!(within_work(300_000, 50_000));
        assert!(!within_work(2_000_000, 0));
        assert!(!within_work(usize::MAX, usize::MAX));
    }

    #[test]
    fn block_counts_and_combinations() {
        assert_eq!(block_count(0, 50), None);
        assert_eq!(block_count(1, 50), Some(32));
        assert_eq!(block_count(1, 5), Some(5));
        assert_eq!(block_count(2, 50), Some(8));
        assert_eq!(block_count(3, 50), Some(6));
        assert_eq!(block_count(4, 50), None);
        assert_eq!(block_count(3, 3), None);
        assert_eq!(block_count(usize::MAX / 2, usize::MAX), None);
        // Every q-subset of 0..b once, in order.
        let mut c = vec![0, 1];
        let mut seen = vec![c.clone()];
        while next_combination(&mut c, 5).is_some() {
            seen.push(c.clone());
        }
        assert_eq!(seen.len(), 10);
        assert!(seen.windows(2).all(|w| w[0] < w[1]));
    }

    /// The search with an oracle: a set is infeasible when it keeps a
    /// planted false detection. Every planted one among 1,000 candidates
    /// is found within the cap (tested one by one in index order, the
    /// first 96 candidates alone would take it all), every claim was
    /// proved by its own single-candidate tests, against every feasible
    /// set, and with the cap at 0 nothing is claimed.
    #[test]
    fn halving_finds_the_false_candidates_within_the_cap() {
        let k = 4000;
        for planted in [vec![3999], vec![1200, 3998], vec![7, 8, 2001], vec![]] {
            // Two feasible sets, each keeping the detections j % 4 == 0
            // or 1 (resp. 0 or 2): the candidates are j % 4 == 3.
            let feasible: Vec<Vec<bool>> = [1, 2]
                .iter()
                .map(|&r| (0..k).map(|j| j % 4 == 0 || j % 4 == r).collect())
                .collect();
            let planted: Vec<usize> = planted.iter().map(|&j| j - j % 4 + 3).collect();
            let mut singles = std::collections::BTreeMap::new();
            let mut oracle = |keep: &[bool]| {
                let bad = planted.iter().any(|&j| keep[j]);
                if keep.iter().filter(|&&x| x).count() == 2001 {
                    let j = (0..k).find(|&j| j % 4 == 3 && keep[j]).unwrap();
                    *singles.entry(j).or_insert(0) += usize::from(bad);
                }
                bad
            };
            let found = search_false(&feasible, MAX_TESTS, &mut oracle);
            for (j, &f) in found.iter().enumerate() {
                assert_eq!(f, planted.contains(&j), "{planted:?}: {j}");
                if f {
                    assert_eq!(singles.get(&j), Some(&2), "{j}: proved alone, both sets");
                }
            }
            let none = search_false(&feasible, 0, &mut |_| true);
            assert!(none.iter().all(|&f| !f));
        }
    }
}
