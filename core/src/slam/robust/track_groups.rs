//! Tracks that survive false detections: groups of detections proved to
//! see one landmark in every reading that keeps them, for odometry2d
//! missions with `max_outliers` = q > 0 and a minimum separation
//! (docs/outliers.md, "Tracks with false detections").
//!
//! # Constraint
//!
//! A *reading* drops at most q detections (docs/formats.md); among the
//! detections not proved false (the *live* ones) at most `budget` = q -
//! |proved false| are dropped. A kept detection sees a real landmark
//! within its measured intervals. Distinct landmarks are at least s apart.
//!
//! # Math
//!
//! - **Direct pairs.** The track test ([`crate::slam::association::odometry2d::tracks`]) proves
//!   from the odometry and the two measurements alone that the landmarks of
//!   a and b are less than s apart: in every reading that keeps both, they
//!   see one landmark. Nothing else is read, so no other detection's drop
//!   can undo it.
//! - **Valid group.** A set G such that every two members see one landmark
//!   in every reading that keeps both. Then in every reading the kept
//!   members of G see one landmark L(G), which lies in the box of each kept
//!   member: in all but at most `budget` of the members' boxes, that is in
//!   their q-relaxed intersection; and with at least `budget + 1` live
//!   members every reading keeps one, so L(G) exists in every reading.
//! - **Merging two valid groups A and B** with the direct pairs E between
//!   them. Take x in A, y in B kept by a reading that drops a set D (at most
//!   `budget` detections, neither x nor y). It is enough that some pair (a,
//!   b) of E has both ends kept: then x, a see one landmark (A valid, or x =
//!   a), a, b one (direct), b, y one (B valid). The union is valid when
//!   (R1) E holds `budget + 1` pairwise disjoint pairs (a matching): each
//!   detection of D ends at most one of them; or (R2) every member x of one
//!   side is directly paired with every member of the other side or with at
//!   least `budget + 1` of them: x is kept, so a pair (x, b) with b outside
//!   D remains (or (x, y) itself).
//!
//! Chains of direct pairs are not enough: a, b, c with a~b and b~c prove
//! nothing of a and c in a reading that drops b. A landmark seen in
//! consecutive scans, each detection paired with its last `budget + 1`
//! predecessors, becomes one group through R2, one detection at a time.
//!
//! # Soundness
//!
//! The direct pairs are the track test's ([`gap_below`]: outward-rounded,
//! the relative pose enclosed from the odometry alone). The merges follow
//! from the two rules above, whose proofs hold for any D of at most `budget`
//! detections; a detection proved false (in every reading's D) takes no
//! part. Missing a pair or a merge only proves less. Tested against brute
//! force over every drop set on random pair graphs, and on simulated woods
//! missions with planted false detections of every kind
//! (`core/tests/slam/robust/track_groups.rs`).
//!
//! # Complexity
//!
//! The pair tests of the track rule: O(S · W) relative-pose steps and
//! O(k · c · M) gap tests (S detection steps, W the window, c detections
//! per step, M the later steps compared), a pair inside one group skipped.
//! Each merge test costs O(m · c · M) finds for the m members of the
//! smaller group, O(k · c · M) memory for the pairs.
//!
//! [`gap_below`]: crate::odometry::relative::gap_below

use crate::odometry::chain::OdometryChain;
use crate::slam::association::odometry2d::tracks::{StepRuns, TrackOptions};
use crate::slam::mission::Mission;
use crate::union_find::Uf;

/// The larger side is tested by R2 too when it has at most this many
/// members (the cost of a merge test stays proportional to the smaller
/// group otherwise).
const SMALL_SIDE: usize = 64;

/// Valid groups built from direct pairs (module doc): each call of
/// [`ValidGroups::pair`] records a direct pair and merges the two groups
/// when R1 or R2 holds.
#[derive(Debug, Clone)]
pub struct ValidGroups {
    uf: Uf,
    /// Members of each group, by root.
    members: Vec<Vec<usize>>,
    /// Direct pairs, both ways.
    adj: Vec<Vec<usize>>,
    live: Vec<bool>,
    /// `budget + 1`: the pairs a merge needs (saturating).
    need: usize,
}

impl ValidGroups {
    /// Singletons over `live.len()` detections, with `budget` drops among
    /// the live ones.
    pub fn new(live: &[bool], budget: usize) -> ValidGroups {
        let k = live.len();
        ValidGroups {
            uf: Uf::new(k),
            members: (0..k).map(|j| vec![j]).collect(),
            adj: vec![Vec::new(); k],
            live: live.to_vec(),
            need: budget.saturating_add(1),
        }
    }

    /// Whether a and b are already in one group.
    pub fn same(&mut self, a: usize, b: usize) -> bool {
        self.uf.find(a) == self.uf.find(b)
    }

    /// Records the direct pair (a, b) (module doc) and merges their groups
    /// when a rule allows; whether they are now one group. A pair with a
    /// detection that is not live is ignored.
    pub fn pair(&mut self, a: usize, b: usize) -> bool {
        if a == b || !self.live[a] || !self.live[b] {
            return a == b;
        }
        if self.same(a, b) {
            return true;
        }
        if !self.adj[a].contains(&b) {
            self.adj[a].push(b);
            self.adj[b].push(a);
        }
        let (ra, rb) = (self.uf.find(a), self.uf.find(b));
        if !self.joins(ra, rb) {
            return false;
        }
        let root = self.uf.union(ra, rb);
        let other = if root == ra { rb } else { ra };
        let moved = core::mem::take(&mut self.members[other]);
        self.members[root].extend(moved);
        true
    }

    /// R1 or R2 for the groups of roots `ra` and `rb`.
    fn joins(&mut self, ra: usize, rb: usize) -> bool {
        let (s, t) = if self.members[ra].len() <= self.members[rb].len() {
            (ra, rb)
        } else {
            (rb, ra)
        };
        self.each_reaches(s, t)
            || (self.members[t].len() <= SMALL_SIDE && self.each_reaches(t, s))
            || self.matching_reaches(s, t)
    }

    /// How many distinct members of group `t` are directly paired with x.
    fn paired_in(&mut self, x: usize, t: usize) -> usize {
        let mut c = 0;
        for i in 0..self.adj[x].len() {
            let y = self.adj[x][i];
            c += usize::from(self.uf.find(y) == t);
        }
        c
    }

    /// R2: every member of `s` is paired with all of `t` or with at least
    /// `need` of its members.
    fn each_reaches(&mut self, s: usize, t: usize) -> bool {
        let size_t = self.members[t].len();
        for i in 0..self.members[s].len() {
            let x = self.members[s][i];
            let c = self.paired_in(x, t);
            if c < size_t && c < self.need {
                return false;
            }
        }
        true
    }

    /// R1: a greedy matching of the pairs between `s` and `t` reaches
    /// `need` pairs (a maximal matching; a larger one only proves more).
    fn matching_reaches(&mut self, s: usize, t: usize) -> bool {
        let mut used: Vec<usize> = Vec::new();
        for i in 0..self.members[s].len() {
            let x = self.members[s][i];
            for n in 0..self.adj[x].len() {
                let y = self.adj[x][n];
                if self.uf.find(y) == t && !used.contains(&y) {
                    used.push(y);
                    if used.len() >= self.need {
                        return true;
                    }
                    break;
                }
            }
        }
        false
    }

    /// The groups of at least two members, each sorted, by smallest member.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        let mut out: Vec<Vec<usize>> = self
            .members
            .iter()
            .filter(|g| g.len() >= 2)
            .map(|g| {
                let mut g = g.clone();
                crate::sort::sort_usize(&mut g);
                g
            })
            .collect();
        crate::sort::sort_ord(&mut out);
        out
    }
}

/// The valid groups of the track pairs of an odometry2d mission (module
/// doc), over the `live` detections with `budget` drops among them. Empty
/// without a positive separation.
pub fn robust_track_groups(
    mission: &Mission,
    chain: &OdometryChain,
    live: &[bool],
    budget: usize,
    options: TrackOptions,
) -> Vec<Vec<usize>> {
    if live.len() != mission.detections.len() {
        return Vec::new();
    }
    let Some(steps) = StepRuns::new(mission) else {
        return Vec::new();
    };
    let mut g = ValidGroups::new(live, budget);
    steps.for_each_pair(chain, options, &mut |a, b, proved| {
        if live[a] && live[b] && !g.same(a, b) && proved() {
            g.pair(a, b);
        }
    });
    g.groups()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// Whether x and y stay connected by pairs between kept detections in
    /// every reading that drops at most `budget` others (every subset
    /// tried).
    fn connected_in_every_reading(
        k: usize,
        pairs: &[(usize, usize)],
        x: usize,
        y: usize,
        budget: usize,
    ) -> bool {
        for mask in 0u32..(1 << k) {
            if mask.count_ones() as usize > budget || mask & (1 << x) != 0 || mask & (1 << y) != 0 {
                continue;
            }
            let mut uf = Uf::new(k);
            for &(a, b) in pairs {
                if mask & (1 << a) == 0 && mask & (1 << b) == 0 {
                    uf.union(a, b);
                }
            }
            if uf.find(x) != uf.find(y) {
                return false;
            }
        }
        true
    }

    /// Random pair graphs on up to 9 detections, every budget up to 3: two
    /// members of a group stay joined by kept pairs in every reading (brute
    /// force over the drop sets), which is what makes a group valid.
    #[test]
    fn every_group_survives_every_drop_set() {
        let mut rng = Lcg::new(7);
        let mut merged = 0;
        for case in 0..3000 {
            let k = 2 + (rng.bits() % 8) as usize;
            let budget = (rng.bits() % 4) as usize;
            let density = 0.2 + 0.7 * rng.unit();
            let mut pairs = Vec::new();
            for a in 0..k {
                for b in a + 1..k {
                    if rng.unit() < density {
                        pairs.push((a, b));
                    }
                }
            }
            for i in (1..pairs.len()).rev() {
                pairs.swap(i, (rng.bits() % (i as u64 + 1)) as usize);
            }
            let live = vec![true; k];
            let mut g = ValidGroups::new(&live, budget);
            for &(a, b) in &pairs {
                g.pair(a, b);
            }
            for grp in g.groups() {
                merged += grp.len() - 1;
                for (i, &x) in grp.iter().enumerate() {
                    for &y in &grp[i + 1..] {
                        assert!(
                            connected_in_every_reading(k, &pairs, x, y, budget),
                            "case {case}: {x} and {y} grouped, budget {budget}, pairs {pairs:?}"
                        );
                    }
                }
            }
        }
        assert!(merged > 3000, "the rules merged almost nothing: {merged}");
    }

    /// A track: each detection paired with its `budget + 1` predecessors
    /// becomes one group; with `budget` predecessors only, it does not.
    #[test]
    fn a_track_paired_with_enough_predecessors_is_one_group() {
        for budget in 0..5usize {
            for lag in [budget + 1, budget] {
                let k = 40;
                let mut g = ValidGroups::new(&vec![true; k], budget);
                for b in 1..k {
                    for a in b.saturating_sub(lag)..b {
                        g.pair(a, b);
                    }
                }
                let groups = g.groups();
                let whole = groups.len() == 1 && groups[0].len() == k;
                if lag == budget + 1 {
                    assert!(whole, "budget {budget}: {groups:?}");
                } else if budget > 0 {
                    assert!(!whole, "budget {budget}, lag {lag}: {groups:?}");
                }
            }
        }
    }

    /// A detection that is not live takes no part.
    #[test]
    fn dead_detections_join_nothing() {
        let mut g = ValidGroups::new(&[true, false, true], 0);
        assert!(!g.pair(0, 1));
        assert!(g.pair(0, 2));
        assert_eq!(g.groups(), vec![vec![0, 2]]);
    }
}
