//! Minimum hitting sets of a family of conflicts (`max_outliers` = q > 0;
//! docs/outliers.md, "Overlapping conflicts"): the exact decision "does a
//! set of at most s detections, none of them forbidden, meet every
//! conflict?", by branch and bound with a work cap.
//!
//! # Constraint
//!
//! A *conflict* is a set of detections that no reading with a solution
//! keeps whole ([`crate::slam::robust::conflicts`]). The detections D a reading
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
//! O(|F| · c) for conflicts of at most c members (it visits every member
//! of the family, M in all). The work cap counts that cost: a node takes
//! 1 + M / [`MEMBERS_PER_NODE`] units of `work`, so a cap of W units
//! visits at most about W · [`MEMBERS_PER_NODE`] members, whatever the
//! family's size (families of fewer than [`MEMBERS_PER_NODE`] members
//! count one unit per node, as before). Counted per node only, a family
//! of 800 five-member cliques (200 false ranges on a 500-step paper
//! mission) ran the 2,000,000 nodes of a packing for minutes.

use crate::union_find::Uf;

/// Members of the family visited per unit of `work` (module doc,
/// "Complexity").
pub const MEMBERS_PER_NODE: u64 = 64;

/// The units of `work` one search node over `family` takes: 1 + M /
/// [`MEMBERS_PER_NODE`], M the members of the family.
pub fn node_charge(family: &[Vec<usize>]) -> u64 {
    let members: usize = family.iter().map(Vec::len).sum();
    1 + members as u64 / MEMBERS_PER_NODE
}

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
/// `family` (module doc). `work`: units left, decremented by
/// [`node_charge`] per node.
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
    let charge = node_charge(family);
    match search(
        family,
        &mut banned,
        &mut chosen,
        &mut picked,
        s,
        work,
        charge,
    ) {
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

/// The conflicts of `family` grouped into *components*: two conflicts are
/// in one component when a chain of conflicts sharing members joins them.
/// Each component as the sorted indices of its conflicts, the components
/// in the order of their first conflict. O(Σ|c| α) (union-find over the
/// members, indexed in a map: detection numbers size nothing).
pub fn components(family: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut uf = Uf::new(family.len());
    let mut owner = std::collections::BTreeMap::new();
    for (i, c) in family.iter().enumerate() {
        for &j in c {
            if let Some(&o) = owner.get(&j) {
                uf.union(o, i);
            } else {
                owner.insert(j, i);
            }
        }
    }
    let mut slot: Vec<Option<usize>> = vec![None; family.len()];
    let mut out: Vec<Vec<usize>> = Vec::new();
    for i in 0..family.len() {
        let r = uf.find(i);
        let at = *slot[r].get_or_insert_with(|| {
            out.push(Vec::new());
            out.len() - 1
        });
        out[at].push(i);
    }
    out
}

/// A true lower bound of the minimum hitting set size of `family`: the
/// count of conflicts, picked greedily smallest first, whose members are
/// pairwise disjoint (each needs its own member). An empty conflict
/// cannot be hit: `None`.
pub fn packing_bound(family: &[Vec<usize>]) -> Option<usize> {
    if family.iter().any(Vec::is_empty) {
        return None;
    }
    let mut order: Vec<(usize, usize)> = family
        .iter()
        .enumerate()
        .map(|(i, c)| (c.len(), i))
        .collect();
    crate::sort::natural(&mut order);
    let mut used = std::collections::BTreeSet::new();
    let mut bound = 0;
    for (_, i) in order {
        if family[i].iter().all(|j| !used.contains(j)) {
            bound += 1;
            used.extend(family[i].iter().copied());
        }
    }
    Some(bound)
}

/// What [`forced`] proves of a family of conflicts and a budget b.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Forced {
    /// No set of at most b detections hits every conflict.
    NoReading,
    /// Detections that every hitting set of at most b holds (sorted; the
    /// work cap may leave some out: what is listed is proved).
    Members(Vec<usize>),
}

/// The detections held by every hitting set of at most `b` of `family`,
/// decided component by component (docs/outliers.md, "Free conflicts on
/// large missions"): with D a hitting set, |D| is at least the sum over
/// the components of what each needs, since components share no member.
/// So x of component C is forced when no hitting set of C without x has
/// at most b minus the other components' lower bounds; a component whose
/// exact minimum the cap leaves unknown counts its packing bound (a true
/// lower bound) and proves nothing of its own members. `work`: search
/// nodes left, decremented; one pass (the caller iterates after removing
/// what is forced).
pub fn forced(family: &[Vec<usize>], b: usize, work: &mut u64) -> Forced {
    let comps = components(family);
    let mut fams: Vec<Vec<Vec<usize>>> = Vec::with_capacity(comps.len());
    // Per component: its lower bound, and a minimum hitting set if known.
    let mut lows: Vec<(usize, Option<Vec<usize>>)> = Vec::with_capacity(comps.len());
    for comp in &comps {
        let fam: Vec<Vec<usize>> = comp.iter().map(|&i| family[i].clone()).collect();
        let Some(low) = packing_bound(&fam) else {
            return Forced::NoReading;
        };
        if low > b {
            return Forced::NoReading;
        }
        let exact = match minimum(&fam, &[], b, work) {
            Hit::Found(h) => (h.len(), Some(h)),
            Hit::None => return Forced::NoReading,
            Hit::Unknown => (low, None),
        };
        lows.push(exact);
        fams.push(fam);
    }
    let total: usize = lows.iter().map(|l| l.0).sum();
    if total > b {
        return Forced::NoReading;
    }
    let mut out = Vec::new();
    for (fam, (low, h)) in fams.iter().zip(&lows) {
        let Some(h) = h else { continue };
        // What a hitting set of this component may cost within b.
        let room = b - (total - low);
        let mut ban = vec![false; h.iter().map(|&j| j + 1).max().unwrap_or(0)];
        for &x in h {
            ban[x] = true;
            if hitting_set(fam, &ban, room, work) == Hit::None {
                out.push(x);
            }
            ban[x] = false;
        }
    }
    crate::sort::natural(&mut out);
    Forced::Members(out)
}

/// The branch and bound (module doc): `Some(true)` with `picked` a hitting
/// set, `Some(false)` none within `s`, `None` the cap (each node takes
/// `charge` units of `work`: [`node_charge`]).
fn search(
    family: &[Vec<usize>],
    banned: &mut [bool],
    chosen: &mut [bool],
    picked: &mut Vec<usize>,
    s: usize,
    work: &mut u64,
    charge: u64,
) -> Option<bool> {
    *work = work.checked_sub(charge)?;
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
        let r = search(family, banned, chosen, picked, s, work, charge);
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

    /// The cap counts the members a node visits (module doc,
    /// "Complexity"): 1,000 five-member conflicts take 1 + 5,000 / 64 =
    /// 79 units per node, so 78 units do not pay for the root (Unknown)
    /// and 79 pay for it alone (s = 0 with a conflict to hit: None at the
    /// root). Counted one unit per node, 78 units ran the root and a
    /// family of 800 cliques (200 false ranges on a 500-step paper
    /// mission) spent minutes in 2,000,000 nodes. Families of fewer than
    /// 64 members still take one unit per node.
    #[test]
    fn the_cap_counts_member_visits() {
        let family: Vec<Vec<usize>> = (0..1000)
            .map(|i| (0..5).map(|j| 5 * i + j).collect())
            .collect();
        assert_eq!(node_charge(&family), 79);
        let mut work = 78;
        assert_eq!(hitting_set(&family, &[], 0, &mut work), Hit::Unknown);
        let mut work = 79;
        assert_eq!(hitting_set(&family, &[], 0, &mut work), Hit::None);
        assert_eq!(work, 0);
        assert_eq!(node_charge(&[vec![0, 1], vec![2]]), 1);
        assert_eq!(node_charge(&[(0..63).collect()]), 1);
        assert_eq!(node_charge(&[(0..64).collect()]), 2);
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

    /// Random families over k <= 12 detections, in several components
    /// (members drawn from one of a few disjoint pools, some shared).
    fn family_of(rng: &mut Lcg, k: usize) -> Vec<Vec<usize>> {
        let pools = 1 + (rng.bits() % 3) as usize;
        let f = (rng.bits() % 10) as usize;
        (0..f)
            .map(|_| {
                let pool = (rng.bits() % pools as u64) as usize;
                let mut c: Vec<usize> = (0..1 + rng.bits() % 4)
                    .map(|_| {
                        let j = (rng.bits() % k as u64) as usize;
                        // Mostly within the pool: j ≡ pool (mod pools).
                        if rng.bits().is_multiple_of(6) {
                            j
                        } else {
                            (j - j % pools + pool).min(k - 1)
                        }
                    })
                    .collect();
                c.sort_unstable();
                c.dedup();
                c
            })
            .collect()
    }

    #[test]
    fn forced_members_are_in_every_hitting_set_and_components_share_nothing() {
        let mut rng = Lcg::new(0x18f0);
        let mut claimed = 0;
        for _ in 0..4000 {
            let k = 1 + (rng.bits() % 12) as usize;
            let family = family_of(&mut rng, k);
            let comps = components(&family);
            let mut seen = vec![false; family.len()];
            for (a, ca) in comps.iter().enumerate() {
                for &i in ca {
                    assert!(!seen[i]);
                    seen[i] = true;
                }
                for cb in &comps[a + 1..] {
                    for &i in ca {
                        for &j in cb {
                            assert!(
                                !family[i].iter().any(|x| family[j].contains(x)),
                                "{family:?}: {comps:?}"
                            );
                        }
                    }
                }
            }
            assert!(seen.iter().all(|&s| s));
            let none = vec![false; k];
            let min = brute(&family, &none, k);
            if let Some(low) = packing_bound(&family) {
                assert!(Some(low) <= min, "{family:?}: bound {low} over {min:?}");
            }
            for b in 0..=k {
                let capped = rng.bits().is_multiple_of(4);
                let mut work = if capped { 3 } else { u64::MAX };
                match forced(&family, b, &mut work) {
                    Forced::NoReading => assert!(min.is_none_or(|m| m > b), "{family:?} b {b}"),
                    Forced::Members(xs) => {
                        // Under the cap "no reading" may go unseen.
                        assert!(
                            capped || min.is_some_and(|m| m <= b),
                            "{family:?} b {b}: {xs:?}"
                        );
                        for &x in &xs {
                            let mut ban = none.clone();
                            ban[x] = true;
                            let without = brute(&family, &ban, k);
                            assert!(
                                without.is_none_or(|m| m > b),
                                "{family:?} b {b}: {x} forced, yet a hitting set of {without:?} avoids it"
                            );
                            claimed += 1;
                        }
                    }
                }
            }
        }
        assert!(claimed > 500, "{claimed}");
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
