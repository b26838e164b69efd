//! Minimum hitting sets of a family of conflicts (`max_outliers` = q > 0;
//! docs/outliers.md, "Overlapping conflicts"): the exact decision "does a
//! set of at most s detections, none of them forbidden, meet every
//! conflict?", by branch and bound with a work cap.
//!
//! # Constraint
//!
//! A *conflict* is a set of detections that no reading with a solution
//! keeps whole ([`super::robust_conflicts`]). The detections D a reading
//! drops therefore meet (*hit*) every conflict, and D avoids every
//! detection proved kept in every reading (*forbidden* here).
//!
//! # Math
//!
//! Depth-first search: take the unhit conflict with the fewest allowed
//! members; a hitting set holds one of them, so branch on each in turn,
//! and after the branch on member e fails, forbid e in the later branches
//! (the branches then split the hitting sets: those holding e, those
//! without e holding the next, ...). Prune when the chosen members plus a
//! *lower bound* of what the unhit conflicts still need exceed s: the
//! count of unhit conflicts, greedily picked smallest first, whose allowed
//! members are pairwise disjoint (each needs its own member). An unhit
//! conflict with no allowed member cannot be hit: prune.
//!
//! # Soundness
//!
//! "None" is answered only when the search ran to its end: every pruning
//! uses a true lower bound (a greedy *cover* would be an upper bound and
//! may not prune), so no hitting set of size <= s is skipped. When the
//! work cap is hit the answer is "unknown", which callers read as "a
//! hitting set may exist" (nothing proved). Pure combinatorics: no
//! arithmetic on bounds.
//!
//! # Complexity
//!
//! Exponential in s in the worst case (set cover); each node costs
//! O(|F| · c) for conflicts of at most c members; at most `work` nodes.

/// The answer of [`hitting_set`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Hit {
    /// A hitting set of at most s allowed detections (sorted).
    Found(Vec<usize>),
    /// Proved: every hitting set avoiding the forbidden detections has
    /// more than s members.
    None,
    /// The work cap ran out: nothing proved.
    Unknown,
}

/// Whether a set of at most `s` detections outside `forbidden` (indexed
/// by detection; a detection past its end is allowed) meets every set of
/// `family` (module doc). `work`: nodes left, decremented.
pub fn hitting_set(family: &[Vec<usize>], forbidden: &[bool], s: usize, work: &mut u64) -> Hit {
    let k = family
        .iter()
        .flatten()
        .map(|&j| j + 1)
        .max()
        .unwrap_or(0)
        .max(forbidden.len());
    let mut banned = vec![false; k];
    banned[..forbidden.len()].copy_from_slice(forbidden);
    let mut chosen = vec![false; k];
    let mut picked = Vec::new();
    match search(family, &mut banned, &mut chosen, &mut picked, s, work) {
        Some(true) => {
            crate::sort::natural(&mut picked);
            Hit::Found(picked)
        }
        Some(false) => Hit::None,
        None => Hit::Unknown,
    }
}

/// The smallest hitting set avoiding `forbidden`, if one of at most `s`
/// members exists: `Found` (a minimum one), `None` (every one has more
/// than s), `Unknown` (the cap).
pub fn minimum(family: &[Vec<usize>], forbidden: &[bool], s: usize, work: &mut u64) -> Hit {
    for t in 0..=s {
        match hitting_set(family, forbidden, t, work) {
            Hit::None => {}
            other => return other,
        }
    }
    Hit::None
}

/// The branch and bound (module doc): `Some(true)` with `picked` a hitting
/// set, `Some(false)` none within `s`, `None` the cap.
fn search(
    family: &[Vec<usize>],
    banned: &mut [bool],
    chosen: &mut [bool],
    picked: &mut Vec<usize>,
    s: usize,
    work: &mut u64,
) -> Option<bool> {
    *work = work.checked_sub(1)?;
    let unhit: Vec<&Vec<usize>> = family
        .iter()
        .filter(|c| !c.iter().any(|&j| chosen[j]))
        .collect();
    if unhit.is_empty() {
        return Some(true);
    }
    let allowed = |c: &Vec<usize>| c.iter().filter(|&&j| !banned[j]).count();
    let mut order: Vec<(usize, usize)> = unhit
        .iter()
        .enumerate()
        .map(|(i, c)| (allowed(c), i))
        .collect();
    crate::sort::natural(&mut order);
    if order[0].0 == 0 || picked.len() >= s {
        return Some(false);
    }
    // Lower bound: unhit conflicts with pairwise disjoint allowed members.
    let mut used = vec![false; banned.len()];
    let mut bound = 0;
    for &(_, i) in &order {
        let c = unhit[i];
        if c.iter().all(|&j| banned[j] || !used[j]) {
            bound += 1;
            for &j in c {
                used[j] = true;
            }
        }
    }
    if picked.len() + bound > s {
        return Some(false);
    }
    let branch: Vec<usize> = unhit[order[0].1]
        .iter()
        .copied()
        .filter(|&j| !banned[j])
        .collect();
    let mut out = Some(false);
    let mut undo = Vec::new();
    for j in branch {
        chosen[j] = true;
        picked.push(j);
        let r = search(family, banned, chosen, picked, s, work);
        chosen[j] = false;
        if r != Some(false) {
            out = r;
            if r.is_none() {
                picked.pop();
            }
            break;
        }
        picked.pop();
        banned[j] = true;
        undo.push(j);
    }
    for j in undo {
        banned[j] = false;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// The minimum hitting set size by enumerating every subset (k <= 12).
    fn brute(family: &[Vec<usize>], forbidden: &[bool], k: usize) -> Option<usize> {
        (0u32..1 << k)
            .filter(|m| (0..k).all(|j| m & (1 << j) == 0 || !forbidden[j]))
            .filter(|m| family.iter().all(|c| c.iter().any(|&j| m & (1 << j) != 0)))
            .map(|m| m.count_ones() as usize)
            .min()
    }

    #[test]
    fn exact_against_enumeration() {
        let mut rng = Lcg::new(18);
        for _ in 0..3000 {
            let k = 1 + (rng.bits() % 12) as usize;
            let f = (rng.bits() % 9) as usize;
            let family: Vec<Vec<usize>> = (0..f)
                .map(|_| {
                    let mut c: Vec<usize> = (0..1 + rng.bits() % 5)
                        .map(|_| (rng.bits() % k as u64) as usize)
                        .collect();
                    c.sort_unstable();
                    c.dedup();
                    c
                })
                .collect();
            let forbidden: Vec<bool> = (0..k).map(|_| rng.bits().is_multiple_of(5)).collect();
            let want = brute(&family, &forbidden, k);
            for s in 0..=k {
                let mut work = u64::MAX;
                let got = hitting_set(&family, &forbidden, s, &mut work);
                match (want, &got) {
                    (Some(m), Hit::Found(h)) => {
                        assert!(m <= s && h.len() <= s, "{family:?} {s} {h:?}");
                        assert!(family.iter().all(|c| c.iter().any(|j| h.contains(j))));
                        assert!(h.iter().all(|&j| !forbidden[j]));
                    }
                    (Some(m), Hit::None) => assert!(m > s, "{family:?} {forbidden:?} s {s}"),
                    (None, Hit::None) => {}
                    _ => panic!("{family:?} {forbidden:?} s {s}: {got:?} against {want:?}"),
                }
            }
            let mut work = u64::MAX;
            match minimum(&family, &forbidden, k, &mut work) {
                Hit::Found(h) => assert_eq!(Some(h.len()), want),
                Hit::None => assert_eq!(want, None),
                Hit::Unknown => panic!("no cap"),
            }
        }
    }

    #[test]
    fn the_cap_proves_nothing() {
        let family: Vec<Vec<usize>> = (0..12).map(|i| vec![2 * i, 2 * i + 1]).collect();
        let mut work = 5;
        assert_eq!(hitting_set(&family, &[], 12, &mut work), Hit::Unknown);
        let mut work = u64::MAX;
        assert!(matches!(hitting_set(&family, &[], 12, &mut work), Hit::Found(h) if h.len() == 12));
        // The lower bound alone: 12 disjoint conflicts need 12.
        let mut work = 1;
        assert_eq!(hitting_set(&family, &[], 11, &mut work), Hit::None);
    }
}
