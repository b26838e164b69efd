//! Which detections are kept in every reading of a mission with false
//! detections (`max_outliers` = q > 0), and what is proved of them: the
//! `matching` of the robust propagation ([`crate::slam::robust`]).
//!
//! # Question
//!
//! A *reading* is a set F of at most q detections taken as false (no
//! landmark there, a measurement outside its bounds, or a wrong operator
//! label) such that the mission without F is consistent; the truth is one
//! reading. A group of `matching` claims that its members are true
//! detections of one landmark, so it may be reported only if, in every
//! reading, none of its members is in F and all of them see one landmark.
//!
//! # Math
//!
//! - Monotonicity: dropping a detection only removes constraints (its range,
//!   bearing, region and label), so when F is a reading and |F| < q, so is
//!   F ∪ {j} for every j. Hence, unless every reading has exactly q
//!   detections, every detection is false in some reading and no group is
//!   proved, whatever the labels say (any member may be the false one).
//! - Proved false (P, from the robust rounds): j's own constraints have no
//!   solution within enclosures of every reading keeping j, so j is in
//!   every reading.
//! - Conflict pairs: two detections with the same operator label whose
//!   boxes are disjoint cannot both be kept (a kept detection's label is
//!   right and its landmark lies in its box, which encloses d(j) in every
//!   reading keeping j): every reading holds one of them.
//! - With P and c pairwise disjoint conflict pairs (disjoint from P), every
//!   reading has at least |P| + c detections. If |P| + c > q there is no
//!   reading: the mission is infeasible. If |P| + c = q, every reading is P
//!   plus exactly one detection of each pair, so every other detection (the
//!   *sure* set S) is kept, with its label right, in every reading. If
//!   |P| + c < q, nothing is proved kept and `matching` is empty.
//! - Disjoint witnesses (with `landmark_count` n): m detections, outside
//!   P and the pairs, whose boxes are pairwise disjoint see m different
//!   landmarks when kept, so at most n of them are kept: every reading
//!   drops at least m - n of them. The pairs and these are disjoint sets,
//!   so every reading has at least |P| + c + (m - n) detections; when that
//!   is q, every reading is P, one of each pair and exactly m - n of the
//!   witnesses, and every other detection is sure (the witnesses are
//!   not). The witnesses are found greedily (the narrowest boxes first,
//!   each kept when it meets none kept before), up to n + (q - |P| - c) + 1
//!   of them (one more proves the mission infeasible).
//! - Refinement on S: the mission whose detections outside S are stripped
//!   of every constraint (range [0, +inf], no bearing, region, depth or
//!   label), with q = 0, is a relaxation of every reading: a solution of a
//!   reading is one of it (atmost_nvector too: at most n landmarks among the
//!   kept detections, hence among S, and a stripped detection may take the
//!   landmark of any of them). So the ordinary propagator, with the
//!   requested association, is sound on it: its boxes of the positions and
//!   of d(j), j in S, enclose those of every reading and are intersected
//!   with the robust ones; its groups cut to S are proved in every reading
//!   (kept, true, one landmark); its infeasibility proves the mission's.
//!
//! The conflict pairs are found per label group by a greedy sweep: on each
//! axis the largest lower bound and the smallest upper bound of the boxes
//! still in play; when they come from two boxes and do not meet, those two
//! boxes are disjoint: a pair, both out of play. When no axis gives one, the
//! boxes left meet pairwise on every axis, so no two of them are disjoint:
//! the set of pairs is maximal (not always maximum: fewer pairs than q - |P|
//! only proves less).
//!
//! # Soundness
//!
//! Each step above is a consequence of the semantics of `max_outliers`
//! (docs/formats.md) and of enclosures computed soundly; the comparisons
//! are exact (no rounding: the bounds are compared, not computed).
//!
//! # Complexity
//!
//! Conflict pairs: O(k log k · d) (sorting each group's bounds per axis,
//! then pointers that only move forward). The refinement is one ordinary
//! propagation (see [`crate::slam::propagate::rounds`]); O(N + k) memory for its copy of
//! the mission and its model.

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::slam::mission::{Detection, Mission};
use crate::slam::model::Model;
use crate::slam::propagate::rounds::rounds;
use crate::slam::types::{Progress, SolveOptions, SolveStatus};
use serde_json::Value;
use std::sync::atomic::AtomicBool;

/// What every reading of the mission holds ([`kept`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Kept {
    /// Per detection: kept (and true, its label right) in every reading.
    pub sure: Vec<bool>,
    /// Detections proved false (in every reading).
    pub proved_false: Vec<usize>,
    /// Disjoint pairs of which every reading drops exactly one.
    pub pairs: Vec<(usize, usize)>,
    /// Detections with pairwise disjoint boxes of which every reading
    /// drops exactly `witnesses.len() - n` (empty when not needed).
    pub witnesses: Vec<usize>,
    /// q.
    pub max_outliers: usize,
}

/// The detections kept in every reading (module doc), from boxes `det`
/// enclosing d(j) in every reading keeping j, the detections proved false,
/// the operator's label groups, q and the landmark count n (for the
/// disjoint witnesses). `Ok(None)`: none is proved kept (fewer than q
/// detections are proved to be in every reading). `Err`: no reading
/// exists; the reason names the detections.
pub fn kept(
    det: &[IntervalBox],
    proved_false: &[bool],
    groups: &[Vec<usize>],
    q: usize,
    n: Option<usize>,
) -> Result<Option<Kept>, String> {
    kept_with_conflicts(det, proved_false, &[], groups, q, n).map(Accounted::kept)
}

/// What the boxes prove of every reading's drops ([`kept_with_conflicts`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Accounted {
    /// The drops account for q: the detections kept in every reading.
    Kept(Kept),
    /// This many drops of q are accounted for by nothing proved: every
    /// detection is dropped by some reading (monotonicity), none is kept.
    Open(usize),
}

impl Accounted {
    /// The detections kept in every reading, if any is proved.
    pub fn kept(self) -> Option<Kept> {
        match self {
            Accounted::Kept(k) => Some(k),
            Accounted::Open(_) => None,
        }
    }
}

/// [`kept`], with `conflicts`: pairwise disjoint sets of detections of
/// which every reading drops at least one ([`crate::slam::robust::conflicts`]).
/// A conflict that holds a detection proved false is not counted (that
/// detection already is); the others count one drop each, like a pair,
/// and their members are not sure.
pub fn kept_with_conflicts(
    det: &[IntervalBox],
    proved_false: &[bool],
    conflicts: &[Vec<usize>],
    groups: &[Vec<usize>],
    q: usize,
    n: Option<usize>,
) -> Result<Accounted, String> {
    let dropped: Vec<usize> = (0..det.len()).filter(|&j| proved_false[j]).collect();
    let counted: Vec<&Vec<usize>> = conflicts
        .iter()
        .filter(|c| c.iter().all(|&j| !proved_false[j]))
        .collect();
    let mut in_conflict = vec![false; det.len()];
    for &j in counted.iter().copied().flatten() {
        in_conflict[j] = true;
    }
    let Some(budget) = q.checked_sub(dropped.len() + counted.len()) else {
        return Err(format!(
            "{} detections {dropped:?} cannot reach any landmark position and the disjoint sets {counted:?} hold one false detection each, more than max_outliers = {q}",
            dropped.len()
        ));
    };
    let mut pairs = Vec::new();
    for g in groups {
        let members: Vec<usize> = g
            .iter()
            .copied()
            .filter(|&j| !proved_false[j] && !in_conflict[j])
            .collect();
        disjoint_pairs(&members, det, budget + 1, &mut pairs);
        if pairs.len() > budget {
            break;
        }
    }
    if pairs.len() > budget {
        return Err(format!(
            "detections {dropped:?} are proved false and the pairs {pairs:?} have one operator label each but disjoint boxes (one of each pair is false): {} false detections, more than max_outliers = {q}",
            dropped.len() + pairs.len()
        ));
    }
    let mut sure: Vec<bool> = proved_false
        .iter()
        .zip(&in_conflict)
        .map(|(&f, &c)| !f && !c)
        .collect();
    for &(a, b) in &pairs {
        sure[a] = false;
        sure[b] = false;
    }
    let mut witnesses = Vec::new();
    if pairs.len() < budget {
        let (Some(n), left) = (n, budget - pairs.len()) else {
            return Ok(Accounted::Open(budget - pairs.len()));
        };
        witnesses = disjoint_witnesses(det, &sure, n.saturating_add(left).saturating_add(1));
        if witnesses.len().saturating_sub(n) > left {
            return Err(format!(
                "detections {dropped:?} are proved false, the pairs {pairs:?} hold one false detection each, and the {} detections {witnesses:?} have pairwise disjoint boxes ({} landmarks: all but {n} of them are false): more than max_outliers = {q}",
                witnesses.len(),
                n
            ));
        }
        let counted = witnesses.len().saturating_sub(n);
        if counted < left {
            return Ok(Accounted::Open(left - counted));
        }
        for &w in &witnesses {
            sure[w] = false;
        }
    }
    Ok(Accounted::Kept(Kept {
        sure,
        proved_false: dropped,
        pairs,
        witnesses,
        max_outliers: q,
    }))
}

/// Detections among `open` with pairwise disjoint boxes, a maximal set of
/// them found greedily (narrowest box first), at most `limit`. O(k log k +
/// k · limit · d).
fn disjoint_witnesses(det: &[IntervalBox], open: &[bool], limit: usize) -> Vec<usize> {
    let mut order: Vec<(f64, usize)> = (0..det.len())
        .filter(|&j| open[j] && !det[j].is_empty())
        .map(|j| (det[j].diameter(), j))
        .collect();
    crate::sort::stable_by(&mut order, |a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut out: Vec<usize> = Vec::new();
    for (_, j) in order {
        if out.len() >= limit {
            break;
        }
        if out.iter().all(|&w| !det[w].meets(&det[j])) {
            out.push(j);
        }
    }
    out
}

/// Adds to `out` pairwise disjoint pairs of members with disjoint boxes, a
/// maximal set of them (module doc), until `out` holds `limit` pairs.
fn disjoint_pairs(
    members: &[usize],
    det: &[IntervalBox],
    limit: usize,
    out: &mut Vec<(usize, usize)>,
) {
    let m = members.len();
    if m < 2 || out.len() >= limit {
        return;
    }
    let dim = det[members[0]].dim();
    let bx = |i: usize| &det[members[i]];
    // Per axis: the members' positions by lower bound, largest first, and
    // by upper bound, smallest first (ties by position: one order whatever
    // the sort).
    let mut by_lo: Vec<Vec<usize>> = Vec::with_capacity(dim);
    let mut by_hi: Vec<Vec<usize>> = Vec::with_capacity(dim);
    for a in 0..dim {
        let mut lo: Vec<usize> = (0..m).collect();
        crate::sort::sort_indices_by(&mut lo, |x, y| bx(y)[a].lo().total_cmp(&bx(x)[a].lo()));
        let mut hi: Vec<usize> = (0..m).collect();
        crate::sort::sort_indices_by(&mut hi, |x, y| bx(x)[a].hi().total_cmp(&bx(y)[a].hi()));
        by_lo.push(lo);
        by_hi.push(hi);
    }
    let mut in_play = vec![true; m];
    let mut at = vec![(0usize, 0usize); dim];
    while out.len() < limit {
        let mut found = None;
        for a in 0..dim {
            let (mut l, mut h) = at[a];
            while l < m && !in_play[by_lo[a][l]] {
                l += 1;
            }
            while h < m && !in_play[by_hi[a][h]] {
                h += 1;
            }
            at[a] = (l, h);
            if l == m || h == m {
                return;
            }
            let (x, y) = (by_lo[a][l], by_hi[a][h]);
            // The box with the largest lower bound lies wholly above the
            // one with the smallest upper bound on this axis.
            if x != y && bx(x)[a].lo() > bx(y)[a].hi() {
                found = Some((x, y));
                break;
            }
        }
        let Some((x, y)) = found else {
            return;
        };
        in_play[x] = false;
        in_play[y] = false;
        let (a, b) = (members[x], members[y]);
        out.push((a.min(b), a.max(b)));
    }
}

/// The operator's label groups cut to the detections kept in every
/// reading: groups of size >= 2, sorted, by smallest member.
pub fn sure_groups(groups: &[Vec<usize>], sure: &[bool]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = groups
        .iter()
        .map(|g| {
            let mut g: Vec<usize> = g.iter().copied().filter(|&j| sure[j]).collect();
            crate::sort::sort_usize(&mut g);
            g
        })
        .filter(|g| g.len() >= 2)
        .collect();
    crate::sort::sort_ord(&mut out);
    out
}

/// The mission of the detections in `keep` only (in their order; the
/// positions keep their steps), q = 0, without truth: a relaxation of
/// [`stripped`]`(mission, keep)`, whose solutions restricted to the kept
/// detections are its solutions (a stripped detection only adds a
/// variable d(j) bound to some landmark, at most n of them; removing it
/// removes constraints). So its infeasibility proves that of `stripped`,
/// and its position boxes enclose those of every solution of `stripped`.
/// It is what the conflict searches propagate: the stripped detections'
/// unbounded shapes cost the shapes reasoning most of its time
/// (measured: 61 % of a K = 10 paper packing in `contract_distance` under
/// the witness step's branches).
pub fn kept_only(mission: &Mission, keep: &[bool]) -> Mission {
    let mut sub = stripped(mission, keep);
    let mut j = 0;
    sub.detections.retain(|_| {
        j += 1;
        keep.get(j - 1).copied().unwrap_or(false)
    });
    sub.detection_count = sub.detections.len();
    sub
}

/// The mission with the detections outside `sure` stripped of every
/// constraint (same indices), without false detections or truth.
pub fn stripped(mission: &Mission, sure: &[bool]) -> Mission {
    let detections = mission
        .detections
        .iter()
        .zip(sure)
        .map(|(d, &s)| {
            if s {
                d.clone()
            } else {
                Detection {
                    step: d.step,
                    range: Interval::new(0.0, f64::INFINITY),
                    bearing: None,
                    region: None,
                    depth: None,
                    landmark: None,
                    scan: None,
                }
            }
        })
        .collect();
    Mission {
        name: mission.name.clone(),
        model: mission.model,
        dt: mission.dt,
        steps: mission.steps,
        detection_count: mission.detection_count,
        initial_position: mission.initial_position.clone(),
        final_position: mission.final_position.clone(),
        inputs: mission.inputs.clone(),
        motion_error: mission.motion_error.clone(),
        detections,
        landmark_count: mission.landmark_count,
        landmark_region: mission.landmark_region.clone(),
        max_outliers: 0,
        meta: Value::Null,
        truth: None,
        initial_heading: mission.initial_heading,
        final_heading: mission.final_heading,
        heading_error: mission.heading_error.clone(),
        heading_drift: mission.heading_drift.clone(),
        motion_drift: mission.motion_drift.clone(),
        sensor_offset: mission.sensor_offset,
        landmark_min_separation: mission.landmark_min_separation,
    }
}

/// What the refinement on the sure detections adds ([`refine`]).
pub struct Refined {
    /// Consistent, infeasible (the reason in the mission's numbering) or
    /// stopped.
    pub status: SolveStatus,
    /// Proved groups (size >= 2, members sure).
    pub matching: Vec<Vec<usize>>,
    /// Its rounds.
    pub rounds: u32,
    /// Its contractions.
    pub contractions: u64,
}

/// Runs the ordinary propagation on the mission cut to the sure detections
/// (module doc) and intersects its boxes into `model` (the robust ones).
/// `rounds_done`: the robust rounds before (progress continues their count,
/// the fraction rises from `fraction_done` to 1).
pub fn refine(
    mission: &Mission,
    model: &mut Model,
    kept: &Kept,
    options: &SolveOptions,
    (rounds_done, fraction_done): (u32, f64),
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Refined {
    let sub = stripped(mission, &kept.sure);
    let sub_options = SolveOptions {
        max_rounds: options.max_rounds.saturating_sub(rounds_done),
        ..options.clone()
    };
    let mut report = |p: &Progress| {
        let mut p = p.clone();
        p.round += rounds_done;
        p.fraction = fraction_done + (1.0 - fraction_done) * p.fraction;
        progress(&p);
    };
    // `stripped` sets max_outliers to 0: the plain rounds.
    let s = rounds(&sub, &sub_options, &mut report, cancel);
    let forced = || {
        format!(
            "with detections {:?} proved false, one of each pair {:?} and all but n of the disjoint witnesses {:?} (forced by max_outliers = {}), the other detections",
            kept.proved_false, kept.pairs, kept.witnesses, kept.max_outliers
        )
    };
    let mut out = Refined {
        status: s.status.clone(),
        matching: Vec::new(),
        rounds: s.rounds,
        contractions: s.contractions,
    };
    if let SolveStatus::Infeasible(r) = &s.status {
        out.status = SolveStatus::Infeasible(format!("{}: {r}", forced()));
        return out;
    }
    let dim = model.dim;
    for (i, (p, r)) in model.pos.iter_mut().zip(&s.model.pos).enumerate() {
        *p = p.intersect(*r);
        if p.is_empty() {
            out.status = SolveStatus::Infeasible(format!(
                "{} leave no position at step {}",
                forced(),
                i / dim
            ));
            return out;
        }
    }
    for (j, b) in model.det.iter_mut().enumerate() {
        if kept.sure[j] {
            b.intersect_with(&s.model.det[j]);
            if b.is_empty() {
                out.status = SolveStatus::Infeasible(format!(
                    "{} leave no landmark position for detection {j}",
                    forced()
                ));
                return out;
            }
        }
    }
    let regions = &s.model.landmark_regions;
    let mut landmark_regions = vec![None; mission.detections.len()];
    for g in &s.matching {
        let cut: Vec<usize> = g.iter().copied().filter(|&j| kept.sure[j]).collect();
        if cut.len() >= 2 {
            landmark_regions[cut[0]] = regions.get(g[0]).cloned().flatten();
            out.matching.push(cut);
        }
    }
    crate::sort::sort_ord(&mut out.matching);
    if !regions.is_empty() {
        model.landmark_regions = landmark_regions;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    fn boxes(v: &[(f64, f64)]) -> Vec<IntervalBox> {
        v.iter()
            .map(|&(lo, w)| IntervalBox::new(&[Interval::new(lo, lo + w)]))
            .collect()
    }

    #[test]
    fn disjoint_pairs_are_disjoint_and_maximal() {
        let mut rng = Lcg::new(11);
        for _ in 0..3000 {
            let m = (rng.bits() % 8) as usize;
            let dim = 1 + (rng.bits() % 2) as usize;
            let det: Vec<IntervalBox> = (0..m)
                .map(|_| {
                    let axes: Vec<Interval> = (0..dim)
                        .map(|_| {
                            let lo = (rng.bits() % 10) as f64;
                            Interval::new(lo, lo + (rng.bits() % 4) as f64)
                        })
                        .collect();
                    IntervalBox::new(&axes)
                })
                .collect();
            let members: Vec<usize> = (0..m).collect();
            let mut pairs = Vec::new();
            disjoint_pairs(&members, &det, usize::MAX, &mut pairs);
            let mut used = vec![false; m];
            for &(a, b) in &pairs {
                assert!(a < b && !used[a] && !used[b], "{pairs:?}");
                used[a] = true;
                used[b] = true;
                assert!(det[a].intersect(&det[b]).is_empty(), "{a} {b}");
            }
            // Maximal: the boxes left meet pairwise.
            for a in 0..m {
                for b in a + 1..m {
                    if !used[a] && !used[b] {
                        assert!(!det[a].intersect(&det[b]).is_empty(), "{det:?} {pairs:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn disjoint_witnesses_never_call_a_planted_false_detection_sure() {
        // n landmarks on a line, true boxes holding theirs, up to q false
        // boxes anywhere (some holding a landmark: they fit), no labels.
        let mut rng = Lcg::new(18);
        let mut sure_runs = 0;
        for _ in 0..5000 {
            let n = 1 + (rng.bits() % 4) as usize;
            let lm: Vec<f64> = (0..n).map(|_| (rng.bits() % 40) as f64).collect();
            let q = (rng.bits() % 4) as usize;
            let mut det = Vec::new();
            let mut fake = Vec::new();
            for &l in &lm {
                for _ in 0..1 + rng.bits() % 4 {
                    let (a, b) = ((rng.bits() % 3) as f64, (rng.bits() % 3) as f64);
                    det.push(IntervalBox::new(&[Interval::new(l - a, l + b)]));
                    fake.push(false);
                }
            }
            for _ in 0..rng.bits() % (q as u64 + 1) {
                let lo = (rng.bits() % 50) as f64 - 5.0;
                let w = match rng.bits() % 4 {
                    0 => f64::INFINITY,
                    _ => (rng.bits() % 3) as f64,
                };
                det.push(IntervalBox::new(&[Interval::new(lo, lo + w)]));
                fake.push(true);
            }
            let none = vec![false; det.len()];
            match kept(&det, &none, &[], q, Some(n)) {
                Err(e) => panic!("truth infeasible: {e} {lm:?} {det:?} {fake:?}"),
                Ok(None) => {}
                Ok(Some(k)) => {
                    sure_runs += usize::from(q > 0);
                    for (j, &f) in fake.iter().enumerate() {
                        assert!(!(f && k.sure[j]), "false {j} sure: {lm:?} {det:?} {k:?}");
                    }
                }
            }
        }
        assert!(sure_runs > 500, "{sure_runs}");
    }

    #[test]
    fn the_sure_set_needs_every_unit_of_q_accounted_for() {
        // Group {0, 1, 2}: box 2 is apart from 0 and 1; 3 is proved false.
        let det = boxes(&[(0.0, 1.0), (0.5, 1.0), (5.0, 1.0), (0.0, 1.0), (9.0, 1.0)]);
        let groups = vec![vec![0, 1, 2]];
        let falses = [false, false, false, true, false];
        // q = 1: 3 alone uses it up, and the pair (0 or 1, 2) is one more.
        assert!(kept(&det, &falses, &groups, 1, None)
            .unwrap_err()
            .contains("more than max_outliers = 1"));
        // q = 2: every reading is {3} and one of the pair.
        let k = kept(&det, &falses, &groups, 2, None).unwrap().unwrap();
        assert_eq!(k.proved_false, vec![3]);
        assert_eq!(k.pairs.len(), 1);
        assert!(k.pairs[0].1 == 2);
        let pair_low = k.pairs[0].0;
        let expect: Vec<bool> = (0..5).map(|j| j != 3 && j != 2 && j != pair_low).collect();
        assert_eq!(k.sure, expect);
        // q = 3: a reading may drop one more of anything: nothing is sure,
        // and one drop is open (q = 5: three).
        assert_eq!(kept(&det, &falses, &groups, 3, None).unwrap(), None);
        for (q, open) in [(3, 1), (5, 3)] {
            let a = kept_with_conflicts(&det, &falses, &[], &groups, q, None).unwrap();
            assert_eq!(a, Accounted::Open(open), "q = {q}");
        }
        // A conflict {0, 4} counts one drop more: q = 3 is accounted for.
        let a = kept_with_conflicts(&det, &falses, &[vec![0, 4]], &groups, 3, None).unwrap();
        assert!(matches!(a, Accounted::Kept(_)), "{a:?}");
        // Witnesses: the sure detections left (the pair's other member and
        // 4) have disjoint boxes. With n = 2 they count nothing (one drop
        // open); with n = 1 one drop: q = 3 is accounted for.
        let a = kept_with_conflicts(&det, &falses, &[], &groups, 3, Some(2)).unwrap();
        assert_eq!(a, Accounted::Open(1));
        let a = kept_with_conflicts(&det, &falses, &[], &groups, 3, Some(1)).unwrap();
        assert!(matches!(a, Accounted::Kept(_)), "{a:?}");
        // Groups cut to the sure set.
        let mut sure = vec![true; 5];
        sure[1] = false;
        assert_eq!(
            sure_groups(&[vec![2, 0, 1], vec![3, 4]], &sure),
            vec![vec![0, 2], vec![3, 4]]
        );
    }
}
