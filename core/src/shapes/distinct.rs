//! The distinctness graph: detections proved to see distinct landmarks, and
//! what at most n landmarks then force (docs/design.md, "Detection shapes").
//!
//! # Constraint
//!
//! atmost_nvector(n, {d(1)..d(k)}) with proved facts of two kinds: groups
//! (detections seeing one landmark, a union-find) and distinct pairs
//! (detections whose shapes are disjoint, see [`super::relative`] and
//! [`super::witnesses`]).
//!
//! # Math
//!
//! On the graph whose vertices are the groups and whose edges join groups
//! holding a distinct pair:
//! - an (n+1)-clique is n+1 pairwise-distinct landmarks: infeasible;
//! - an edge inside a group is a contradiction: infeasible;
//! - if C is an (n-1)-clique (n-1 pairwise-distinct landmarks), every
//!   common neighbour of C sees a landmark outside those n-1, and only one
//!   landmark is left: all common neighbours of C form one group. (This is
//!   "meets exactly one of n witnesses" with the witnesses' n-th landmark
//!   left implicit, so it needs n-1 distinct groups, not n.)
//!
//! The rule is applied to every (n-1)-clique found within a node budget,
//! the unions are applied, the graph is rebuilt, until nothing changes.
//!
//! # Soundness
//!
//! Only the three facts above, each a consequence of at most n landmarks
//! and of the proved facts; a union-find of proved equalities stays proved.
//!
//! # Complexity
//!
//! O(e log e) to build the group graph from e distinct pairs; the clique
//! enumeration is bounded by the node budget (for n = 4 it lists the
//! triangles, O(Σ deg^2) with sorted-list intersections); a few passes.

pub use crate::union_find::Uf;
use std::sync::Arc;

/// The group graph: per detection, the sorted roots of the groups proved
/// distinct from its group (empty for non-roots), `graph[r]`; shared, not
/// copied.
pub type Graph = Arc<GroupGraph>;

/// The lists of a [`Graph`] end to end (compressed rows): detection r's
/// list is `nbrs[start[r]..start[r + 1]]`. One u32 per detection and one
/// per neighbour, whatever the lists' history (a graph of 2^32 entries or
/// more is refused: [`Distinct::graph`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GroupGraph {
    start: Vec<u32>,
    nbrs: Vec<u32>,
}

impl GroupGraph {
    /// The graph of the given lists (each sorted, without repeats).
    pub fn from_lists(lists: &[Vec<u32>]) -> GroupGraph {
        let mut g = GroupGraph {
            start: Vec::with_capacity(lists.len() + 1),
            nbrs: Vec::with_capacity(lists.iter().map(Vec::len).sum()),
        };
        g.start.push(0);
        for l in lists {
            g.nbrs.extend_from_slice(l);
            g.start.push(g.nbrs.len() as u32);
        }
        g
    }

    /// Number of detections.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Whether there are no detections.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl std::ops::Index<usize> for GroupGraph {
    type Output = [u32];
    fn index(&self, r: usize) -> &[u32] {
        &self.nbrs[self.start[r] as usize..self.start[r + 1] as usize]
    }
}

/// Detection pairs proved distinct, accumulated over rounds.
#[derive(Debug, Clone, Default)]
pub struct Distinct {
    pairs: Vec<(u32, u32)>,
    sorted: usize,
    /// (pairs, groups) when the last inference changed nothing: the same
    /// facts give the same (empty) answer, so it is not run again.
    settled: Option<(usize, usize)>,
}

/// Most passes of [`Distinct::infer`].
const MAX_PASSES: usize = 32;

impl Distinct {
    /// Records pairs (i, j) proved to see distinct landmarks.
    pub fn add(&mut self, pairs: impl IntoIterator<Item = (u32, u32)>) {
        self.pairs
            .extend(pairs.into_iter().map(|(a, b)| (a.min(b), a.max(b))));
    }

    /// Number of distinct pairs known (after deduplication).
    pub fn len(&mut self) -> usize {
        self.normalize();
        self.pairs.len()
    }

    /// Whether no pair is known.
    pub fn is_empty(&mut self) -> bool {
        self.len() == 0
    }

    /// Sorts and deduplicates the pairs. `pairs[..sorted]` is kept sorted
    /// and without repeats, so only the pairs added since are sorted, then
    /// merged in place from the back (the buffer is the added pairs only):
    /// the same sorted set as sorting all. O(a log a + e) for a added
    /// pairs, e in all.
    fn normalize(&mut self) {
        if self.sorted == self.pairs.len() {
            return;
        }
        if cfg!(target_arch = "wasm32") {
            // The browser's build sorts them all (the same set, less code
            // in its transfer).
            crate::sort::natural(&mut self.pairs);
            self.pairs.dedup();
            self.sorted = self.pairs.len();
            return;
        }
        let n = self.sorted;
        let mut tail = self.pairs[n..].to_vec();
        crate::sort::natural(&mut tail);
        tail.dedup();
        self.pairs.truncate(n + tail.len());
        // Back merge: the largest remaining of the two runs goes to the
        // last free place; equal pairs are both kept, then dropped below.
        let (mut i, mut j, mut w) = (n, tail.len(), n + tail.len());
        while j > 0 {
            if i > 0 && self.pairs[i - 1] > tail[j - 1] {
                self.pairs[w - 1] = self.pairs[i - 1];
                i -= 1;
            } else {
                self.pairs[w - 1] = tail[j - 1];
                j -= 1;
            }
            w -= 1;
        }
        self.pairs.dedup();
        self.sorted = self.pairs.len();
    }

    /// The group graph: sorted neighbour roots per root (empty for
    /// non-roots), in compressed rows ([`GroupGraph`]: made at its exact
    /// size). Err: a pair inside one group. O(e log e + k).
    ///
    /// (A memo of the last graph, reused while the pairs and the roots are
    /// the same, saved 8 % of CMU Plaza 1's time but held the graph through
    /// the shapes step: 0.4 MB more at the woods scenario's peak.)
    pub fn graph(&mut self, uf: &mut Uf) -> Result<Graph, String> {
        self.normalize();
        let n = uf.len();
        let mut root_pair = |&(a, b): &(u32, u32)| {
            let (ra, rb) = (uf.find(a as usize), uf.find(b as usize));
            if ra == rb {
                return Err(format!(
                    "detections {a} and {b} are proved to see distinct landmarks (their shapes are disjoint) but also the same one"
                ));
            }
            Ok((ra, rb))
        };
        if self.pairs.len() > (u32::MAX / 2) as usize {
            return Err(format!(
                "{} detection pairs proved distinct: more than the group graph holds ({})",
                self.pairs.len(),
                u32::MAX / 2
            ));
        }
        // Compressed rows: the degrees, their prefix sums, the lists
        // filled, each sorted and deduplicated, then moved up end to end.
        let mut start = vec![0u32; n + 1];
        for p in &self.pairs {
            let (ra, rb) = root_pair(p)?;
            start[ra + 1] += 1;
            start[rb + 1] += 1;
        }
        for r in 0..n {
            start[r + 1] += start[r];
        }
        let mut fill = start.clone();
        let mut nbrs = vec![0u32; start[n] as usize];
        for p in &self.pairs {
            let (ra, rb) = root_pair(p)?;
            nbrs[fill[ra] as usize] = rb as u32;
            nbrs[fill[rb] as usize] = ra as u32;
            fill[ra] += 1;
            fill[rb] += 1;
        }
        drop(fill);
        let mut end = 0usize;
        for r in 0..n {
            let (from, to) = (start[r] as usize, start[r + 1] as usize);
            crate::sort::natural(&mut nbrs[from..to]);
            start[r] = end as u32;
            for i in from..to {
                if i == from || nbrs[i] != nbrs[i - 1] {
                    nbrs[end] = nbrs[i];
                    end += 1;
                }
            }
        }
        start[n] = end as u32;
        nbrs.truncate(end);
        nbrs.shrink_to_fit();
        Ok(Arc::new(GroupGraph { start, nbrs }))
    }

    /// Applies the rules of the module doc to a fixpoint; merges groups in
    /// `uf` and returns the unions made (pairs of detections). Err: an
    /// infeasibility, naming detections. `node_budget` bounds the clique
    /// enumeration of each pass.
    pub fn infer(
        &mut self,
        uf: &mut Uf,
        n: usize,
        node_budget: usize,
    ) -> Result<Vec<(usize, usize)>, String> {
        let mut unions = Vec::new();
        let k = uf.len();
        if k == 0 || n == 0 {
            return Ok(unions);
        }
        self.normalize();
        let key = (
            self.pairs.len(),
            (0..k).filter(|&i| uf.find(i) == i).count(),
        );
        if self.settled == Some(key) {
            return Ok(unions);
        }
        if n == 1 {
            for j in 1..k {
                if uf.find(j) != uf.find(0) {
                    uf.union(0, j);
                    unions.push((0, j));
                }
            }
            self.graph(uf)?;
            return Ok(unions);
        }
        for _ in 0..MAX_PASSES {
            let adj = self.graph(uf)?;
            let roots: Vec<u32> = (0..k as u32)
                .filter(|&r| !adj[r as usize].is_empty())
                .collect();
            let mut e = clique_pass(&adj, n - 1, node_budget, &roots);
            if let Some(reason) = e.infeasible {
                return Err(reason);
            }
            let mut changed = false;
            for &r in &roots {
                let m = e.merged.find(r as usize);
                if m != r as usize && uf.find(m) != uf.find(r as usize) {
                    uf.union(m, r as usize);
                    unions.push((m, r as usize));
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        self.graph(uf)?;
        if unions.is_empty() {
            self.settled = Some(key);
        }
        Ok(unions)
    }
}

/// One pass of the clique rule: the (`depth` = n-1)-cliques of the group
/// graph `adj` over `roots`, enumerated within `budget` nodes.
fn clique_pass<'a>(adj: &'a GroupGraph, depth: usize, budget: usize, roots: &[u32]) -> Enum<'a> {
    let k = adj.len();
    let mut e = Enum {
        adj,
        depth,
        nodes: 0,
        budget,
        merged: Uf::new(k),
        infeasible: None,
        common: Vec::new(),
        nexts: Vec::new(),
        commons: Vec::new(),
        mark: Vec::new(),
        epoch: 0,
        closed: Closed::default(),
    };
    // A clique holds at most n - 1 of the k roots: n itself is an input
    // number (up to u32::MAX) that k does not bound.
    let mut clique = Vec::with_capacity(depth.saturating_add(1).min(k));
    e.extend(&mut clique, roots);
    e
}

/// Enumeration of the (n-1)-cliques of the group graph.
struct Enum<'a> {
    adj: &'a GroupGraph,
    depth: usize,
    nodes: usize,
    budget: usize,
    /// The merges found so far, over the roots (a union-find: O(k) memory
    /// however many cliques close).
    merged: Uf,
    infeasible: Option<String>,
    common: Vec<u32>,
    /// Buffers of the candidate lists, by clique size (reused from node to
    /// node; grown with the recursion's depth, which k bounds, not n).
    nexts: Vec<Vec<u32>>,
    /// `commons[d]` (d >= 1): the common neighbours of the clique's first
    /// d + 1 roots, kept while they are on the clique, so that a full
    /// clique intersects one more list instead of all of its own.
    commons: Vec<Vec<u32>>,
    /// `mark[r] == epoch`: root r is a common neighbour of the clique
    /// being closed ([`Enum::mark_all`]; empty until first used).
    mark: Vec<u32>,
    epoch: u32,
    /// The common neighbour sets closed this pass with no edge inside and
    /// merged (measured: on the hidden 10^6-step paper mission 96 % of the
    /// closed sets repeat one closed before in the pass; the graph does not
    /// change during a pass, so the check finds no edge again and the
    /// merge is already made): skipped. At most [`MAX_CLOSED`] roots held.
    closed: Closed,
}

/// Most roots held by [`Enum::closed`] (a bound on its memory; beyond it
/// sets are checked again, as before).
const MAX_CLOSED: usize = 1 << 22;

/// Sets of roots, found by a 64-bit hash of their members and compared
/// whole (sets of one hash chained): a map of `u64` to `usize`, the one
/// the paper's contractor already uses, keeps the page's wasm small.
#[derive(Default)]
struct Closed {
    /// The last set stored under each hash.
    heads: std::collections::HashMap<u64, usize>,
    /// (the set stored before it under the same hash or `usize::MAX`, the set).
    sets: Vec<(usize, Vec<u32>)>,
    roots: usize,
}

impl Closed {
    fn hash(set: &[u32]) -> u64 {
        set.iter().fold(set.len() as u64, |h, &x| {
            (h ^ u64::from(x))
                .wrapping_mul(0x9e37_79b9_7f4a_7c15)
                .rotate_left(29)
        })
    }

    fn contains(&self, set: &[u32]) -> bool {
        let mut at = self
            .heads
            .get(&Self::hash(set))
            .copied()
            .unwrap_or(usize::MAX);
        while let Some((next, member)) = self.sets.get(at) {
            if member == set {
                return true;
            }
            at = *next;
        }
        false
    }

    /// Stores `set` while at most [`MAX_CLOSED`] roots are held.
    fn insert(&mut self, set: &[u32]) {
        if self.roots + set.len() > MAX_CLOSED {
            return;
        }
        self.roots += set.len();
        let next = self.heads.insert(Self::hash(set), self.sets.len());
        self.sets.push((next.unwrap_or(usize::MAX), set.to_vec()));
    }
}

/// `bufs[d]`, grown to hold it, taken out (put it back after use).
fn take_buf(bufs: &mut Vec<Vec<u32>>, d: usize) -> Vec<u32> {
    if bufs.len() <= d {
        bufs.resize_with(d + 1, Vec::new);
    }
    std::mem::take(&mut bufs[d])
}

impl Enum<'_> {
    /// `clique`: pairwise adjacent roots, increasing; `cands`: roots
    /// greater than its last, adjacent to all of it.
    fn extend(&mut self, clique: &mut Vec<u32>, cands: &[u32]) {
        if self.infeasible.is_some() || self.nodes >= self.budget {
            return;
        }
        self.nodes += 1;
        if clique.len() == self.depth {
            self.close(clique);
            return;
        }
        let d = clique.len();
        let mut next = take_buf(&mut self.nexts, d);
        for (i, &v) in cands.iter().enumerate() {
            if self.nodes >= self.budget || self.infeasible.is_some() {
                break;
            }
            crate::sort::meet_sorted(&cands[i + 1..], &self.adj[v as usize], &mut next);
            if d + 1 + next.len() < self.depth {
                continue;
            }
            clique.push(v);
            if d >= 1 && d + 1 < self.depth {
                // The common neighbours of the clique so far (see
                // `commons`); a full clique's are found in `close`.
                let mut common = take_buf(&mut self.commons, d);
                crate::sort::meet_sorted(
                    self.common_of(clique, d - 1),
                    &self.adj[v as usize],
                    &mut common,
                );
                self.commons[d] = common;
            }
            self.extend(clique, &next);
            clique.pop();
        }
        self.nexts[d] = next;
    }

    /// The common neighbours of `clique[..=d]`: the adjacency of its
    /// first root, or `commons[d]`.
    fn common_of(&self, clique: &[u32], d: usize) -> &[u32] {
        if d == 0 {
            &self.adj[clique[0] as usize]
        } else {
            &self.commons[d]
        }
    }

    /// Common neighbours of a full (n-1)-clique: one landmark.
    fn close(&mut self, clique: &[u32]) {
        let mut common = std::mem::take(&mut self.common);
        let last = clique.len() - 1;
        if last == 0 {
            common.clear();
            common.extend_from_slice(&self.adj[clique[0] as usize]);
        } else {
            crate::sort::meet_sorted(
                self.common_of(clique, last - 1),
                &self.adj[clique[last] as usize],
                &mut common,
            );
        }
        self.close_common(clique, &common);
        self.common = common;
    }

    /// Marks the members of `common` (a new epoch of `mark`).
    fn mark_all(&mut self, common: &[u32]) {
        if self.mark.len() != self.adj.len() {
            self.mark = vec![0; self.adj.len()];
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.mark.fill(0);
            self.epoch = 1;
        }
        for &c in common {
            self.mark[c as usize] = self.epoch;
        }
    }

    fn close_common(&mut self, clique: &[u32], common: &[u32]) {
        if common.len() < 2 || self.closed.contains(common) {
            return;
        }
        let adj = self.adj;
        let mut marked = false;
        for (i, &a) in common.iter().enumerate() {
            let na = &adj[a as usize];
            let rest = &common[i + 1..];
            // The first b of `rest` adjacent to a (both lists increasing):
            // by binary searches in a's list when `rest` is short, else by
            // a scan of a's list for the marked members of `common` (the
            // same b: the least member of `rest` in a's list).
            let found = if rest.len() * 8 <= na.len() {
                rest.iter().find(|b| na.binary_search(b).is_ok()).copied()
            } else {
                if !marked {
                    self.mark_all(common);
                    marked = true;
                }
                let from = na.partition_point(|&x| x <= a);
                na[from..]
                    .iter()
                    .find(|&&x| self.mark[x as usize] == self.epoch)
                    .copied()
            };
            if let Some(b) = found {
                let mut named: Vec<u32> = clique.to_vec();
                named.extend([a, b]);
                crate::sort::natural(&mut named);
                self.infeasible = Some(format!(
                    "detections {named:?} (with their groups): {} pairwise-distinct landmarks, more than landmark_count {}",
                    named.len(),
                    self.depth + 1
                ));
                return;
            }
        }
        for &x in &common[1..] {
            self.merged.union(common[0] as usize, x as usize);
        }
        self.closed.insert(common);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs added in batches (with repeats) and groups merged between
    /// them: the incrementally merged pairs give what a fresh set of the
    /// same pairs gives, and the compressed rows of the graph the plain
    /// lists of the groups' roots.
    #[test]
    fn the_merged_pairs_and_the_graph_match_a_fresh_build() {
        let mut rng = crate::rng::Rng::new(5);
        for case in 0..60 {
            let k = 8 + case * 3;
            let mut d = Distinct::default();
            let mut uf = Uf::new(k);
            let mut all = Vec::new();
            for _ in 0..12 {
                for _ in 0..(rng.next_u64() % 20) {
                    let (a, b) = (rng.next_u64() as usize % k, rng.next_u64() as usize % k);
                    if a != b && uf.find(a) != uf.find(b) {
                        all.push((a as u32, b as u32));
                        d.add([(a as u32, b as u32)]);
                    }
                }
                if rng.next_u64().is_multiple_of(3) {
                    let (a, b) = (rng.next_u64() as usize % k, rng.next_u64() as usize % k);
                    let mut fresh = Distinct::default();
                    fresh.add(all.iter().copied());
                    let mut u2 = uf.clone();
                    u2.union(a, b);
                    if fresh.graph(&mut u2).is_ok() {
                        uf.union(a, b);
                    }
                }
                let mut fresh = Distinct::default();
                fresh.add(all.iter().copied());
                fresh.normalize();
                d.normalize();
                assert_eq!(d.pairs, fresh.pairs, "case {case}");
                let want = fresh.graph(&mut uf);
                // The compressed rows against plain lists of the roots.
                let mut lists = vec![Vec::new(); k];
                for &(a, b) in &all {
                    let (ra, rb) = (uf.find(a as usize), uf.find(b as usize));
                    lists[ra].push(rb as u32);
                    lists[rb].push(ra as u32);
                }
                for l in &mut lists {
                    l.sort_unstable();
                    l.dedup();
                }
                let plain = GroupGraph::from_lists(&lists);
                assert_eq!(want.as_deref(), Ok(&plain), "case {case}");
                assert_eq!(plain.len(), k);
                assert_eq!(d.graph(&mut uf), want, "case {case}");
                // A second call: the same graph.
                assert_eq!(d.graph(&mut uf), want, "case {case}");
            }
        }
    }

    #[test]
    fn closed_sets_are_found_exactly_when_stored() {
        // Short sets over few roots: many repeats, prefixes and permuted
        // look-alikes, checked against a plain set.
        let mut rng = crate::test_rng::Lcg::new(7);
        let mut closed = Closed::default();
        let mut plain = std::collections::BTreeSet::new();
        for _ in 0..20_000 {
            let len = (rng.bits() % 5) as usize;
            let set: Vec<u32> = (0..len).map(|_| (rng.bits() % 6) as u32).collect();
            assert_eq!(closed.contains(&set), plain.contains(&set), "{set:?}");
            if rng.bits().is_multiple_of(2) {
                closed.insert(&set);
                plain.insert(set);
            }
        }
    }

    #[test]
    fn common_neighbours_of_a_triangle_merge_with_n_4() {
        // 0, 1, 2 pairwise distinct; 3 and 4 distinct from all three: with
        // n = 4 they see the fourth landmark.
        let mut d = Distinct::default();
        d.add([
            (0, 1),
            (0, 2),
            (1, 2),
            (0, 3),
            (1, 3),
            (2, 3),
            (0, 4),
            (1, 4),
            (2, 4),
        ]);
        let mut uf = Uf::new(6);
        let u = d.infer(&mut uf, 4, 1000).unwrap();
        assert_eq!(uf.find(4), 3);
        assert_eq!(u, vec![(3, 4)]);
        assert_eq!(uf.find(5), 5);
        // With n = 5 nothing follows.
        let mut uf = Uf::new(6);
        assert!(d.infer(&mut uf, 5, 1000).unwrap().is_empty());
    }

    /// The enumeration before the reused buffers (a new candidate list per
    /// node, a full clique's lists all intersected, the 5-clique check by
    /// binary searches): the reference of
    /// `the_clique_pass_matches_the_plain_enumeration`.
    struct Plain<'a> {
        adj: &'a [Vec<u32>],
        depth: usize,
        nodes: usize,
        budget: usize,
        merged: Uf,
        infeasible: Option<(Vec<u32>, u32, u32)>,
    }

    impl Plain<'_> {
        fn extend(&mut self, clique: &mut Vec<u32>, cands: &[u32]) {
            if self.infeasible.is_some() || self.nodes >= self.budget {
                return;
            }
            self.nodes += 1;
            if clique.len() == self.depth {
                let mut common = self.adj[clique[0] as usize].clone();
                for &c in &clique[1..] {
                    let mut out = Vec::new();
                    crate::sort::meet_sorted(&common, &self.adj[c as usize], &mut out);
                    common = out;
                }
                for (i, &a) in common.iter().enumerate() {
                    let na = &self.adj[a as usize];
                    if let Some(&b) = common[i + 1..].iter().find(|b| na.binary_search(b).is_ok()) {
                        self.infeasible = Some((clique.clone(), a, b));
                        return;
                    }
                }
                if common.len() >= 2 {
                    for &x in &common[1..] {
                        self.merged.union(common[0] as usize, x as usize);
                    }
                }
                return;
            }
            for (i, &v) in cands.iter().enumerate() {
                if self.nodes >= self.budget || self.infeasible.is_some() {
                    return;
                }
                let mut next = Vec::new();
                crate::sort::meet_sorted(&cands[i + 1..], &self.adj[v as usize], &mut next);
                if clique.len() + 1 + next.len() < self.depth {
                    continue;
                }
                clique.push(v);
                self.extend(clique, &next);
                clique.pop();
            }
        }
    }

    /// Random graphs (dense and sparse, hubs with long lists), n from 2 to
    /// 6, budgets that stop the search or not: the pass finds the same
    /// merges, the same node count and the same 5-clique (named the same)
    /// as the plain enumeration.
    #[test]
    fn the_clique_pass_matches_the_plain_enumeration() {
        let mut rng = crate::rng::Rng::new(18);
        let mut infeasible = 0;
        for case in 0..600 {
            let k = 5 + (rng.next_u64() % 60) as usize;
            let density = rng.unit() * if case % 3 == 0 { 0.9 } else { 0.4 };
            let hubs = (rng.next_u64() % 4) as usize;
            let mut adj = vec![Vec::new(); k];
            for a in 0..k {
                for b in a + 1..k {
                    let p = if a < hubs { 0.95 } else { density };
                    if rng.unit() < p {
                        adj[a].push(b as u32);
                        adj[b].push(a as u32);
                    }
                }
            }
            for l in &mut adj {
                crate::sort::natural(l);
            }
            let roots: Vec<u32> = (0..k as u32)
                .filter(|&r| !adj[r as usize].is_empty())
                .collect();
            let depth = 1 + (rng.next_u64() % 5) as usize;
            let budget = [10, 200, 100_000][case % 3];
            let g = GroupGraph::from_lists(&adj);
            let mut e = clique_pass(&g, depth, budget, &roots);
            let mut p = Plain {
                adj: &adj,
                depth,
                nodes: 0,
                budget,
                merged: Uf::new(k),
                infeasible: None,
            };
            p.extend(&mut Vec::new(), &roots);
            assert_eq!(e.nodes, p.nodes, "case {case}");
            match &p.infeasible {
                Some((clique, a, b)) => {
                    infeasible += 1;
                    let mut named = clique.clone();
                    named.extend([*a, *b]);
                    crate::sort::natural(&mut named);
                    let reason = e.infeasible.clone().expect("infeasible as the plain one");
                    assert!(
                        reason.contains(&format!("{named:?}")),
                        "case {case}: {reason}"
                    );
                }
                None => {
                    assert_eq!(e.infeasible, None, "case {case}");
                    for r in 0..k {
                        assert_eq!(e.merged.find(r), p.merged.find(r), "case {case} root {r}");
                    }
                }
            }
        }
        assert!(
            infeasible > 20 && infeasible < 580,
            "{infeasible} infeasible cases"
        );
    }

    #[test]
    fn five_pairwise_distinct_with_n_4_is_infeasible() {
        let mut d = Distinct::default();
        for a in 0..5u32 {
            for b in a + 1..5 {
                d.add([(a, b)]);
            }
        }
        let mut uf = Uf::new(5);
        let e = d.infer(&mut uf, 4, 1000).unwrap_err();
        assert!(e.contains("[0, 1, 2, 3, 4]"), "{e}");
    }
}
