//! Free conflicts (`max_outliers` = q > 0, ids hidden, `landmark_count`
//! n): n + 1 detections pairwise proved to see distinct landmarks cannot
//! all be genuine (docs/outliers.md, "Conflicts from distinct pairs").
//!
//! # Constraint
//!
//! A *conflict* is a set of detections that no reading with a solution
//! keeps whole ([`crate::slam::robust::conflicts`]); the minimum hitting sets of
//! a family of conflicts bound every reading's drops
//! ([`crate::slam::robust::hitting`]).
//!
//! # Math
//!
//! 1. *Distinct pairs.* Two detections i, j at steps s <= t whose shapes
//!    are disjoint in the frame of p(s) ([`relative_pairs`]: the relative
//!    displacement p(t) - p(s) is the exact sum of the displacement boxes,
//!    no drift) cannot see one landmark in any reading keeping both.
//! 2. *Pigeonhole.* A reading keeping n + 1 detections that are pairwise
//!    distinct would need n + 1 landmarks; there are at most n. So every
//!    (n + 1)-clique of the distinct-pair graph is a conflict, found with
//!    no propagation at all.
//! 3. *Which cliques.* For each open detection x, cliques holding x whose
//!    other members are disjoint from those of x's earlier cliques (the
//!    most a hitting set without x must pay), at most [`PER_DETECTION`].
//!    Which cliques are kept is a heuristic: every clique is a conflict.
//!
//! # Soundness
//!
//! The boxes the pairs are tested in enclose every solution of every
//! reading keeping the detection (the caller passes the mission's initial
//! domains, [`Model::new`]; the displacement boxes and headings are
//! inputs, true in every reading), and a disjointness proved by [`relative_pairs`] is
//! outward rounded ([`crate::shapes::relative_pairs`]). Only detections with a
//! known heading and no sensor offset are tested (`plain_detections`);
//! detections proved false (empty boxes) take no part. Tested by
//! `core/tests/slam/robust/cliques.rs` (planted false detections of every
//! kind: no clique of true detections only, the truth stays inside).
//!
//! # Complexity
//!
//! O(k · [`MAX_AHEAD`]) shape tests for the pairs, then a depth-first
//! clique search of at most [`MAX_NODES`] nodes, each O(k) (a sorted
//! neighbour list merged); memory O(k · [`MAX_AHEAD`]).

use crate::shapes::chain_sums::ChainSums;
use crate::shapes::relative_pairs::relative_pairs;
use crate::shapes::shape::Sighting;
use crate::slam::mission::Mission;
use crate::slam::model::Model;

/// Detections ahead (time order) each one is tested against.
pub const MAX_AHEAD: usize = 96;

/// Most nodes of the clique search, over every detection.
pub const MAX_NODES: u64 = 200_000;

/// Most cliques kept per detection.
pub const PER_DETECTION: usize = 4;

/// Largest n + 1 searched (a clique of more is rarely complete, and the
/// search grows with its size).
pub const MAX_CLIQUE: usize = 9;

/// The (n + 1)-cliques of the distinct-pair graph among the `open`
/// detections (module doc), each sorted; `order`: the detections in time
/// order. Empty without `landmark_count`, with offset sensors or unknown
/// headings, or with n + 1 above [`MAX_CLIQUE`].
pub fn clique_conflicts(
    mission: &Mission,
    model: &Model,
    open: &[bool],
    order: &[usize],
) -> Vec<Vec<usize>> {
    clique_conflicts_with(mission, model, open, order, &Limits::default())
}

/// The work limits of [`clique_conflicts_with`] (any values are sound:
/// they decide only which cliques are found).
#[derive(Debug, Clone)]
pub struct Limits {
    /// Detections ahead (time order) each one is tested against.
    pub ahead: usize,
    /// Most cliques kept per detection.
    pub per_detection: usize,
    /// Most nodes of the search, over every detection.
    pub nodes: u64,
    /// Most nodes of the search from one detection.
    pub nodes_each: u64,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            ahead: MAX_AHEAD,
            per_detection: PER_DETECTION,
            nodes: MAX_NODES,
            nodes_each: MAX_NODES,
        }
    }
}

/// [`clique_conflicts`] with the given work limits.
pub fn clique_conflicts_with(
    mission: &Mission,
    model: &Model,
    open: &[bool],
    order: &[usize],
    limits: &Limits,
) -> Vec<Vec<usize>> {
    let Some(n) = mission.landmark_count else {
        return Vec::new();
    };
    if n == 0 || n + 1 > MAX_CLIQUE || !model.plain_detections() {
        return Vec::new();
    }
    let k = mission.detections.len();
    let live: Vec<usize> = order
        .iter()
        .copied()
        .filter(|&j| open[j] && !model.det[j].is_empty())
        .collect();
    let adj = distinct_graph(mission, model, &live, limits.ahead);
    let mut search = Search {
        adj: &adj,
        size: n + 1,
        nodes: 0,
    };
    let mut total = limits.nodes;
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    let mut used = vec![false; k];
    for &x in &live {
        if adj[x].len() < n {
            continue;
        }
        search.nodes = limits.nodes_each.min(total);
        let before = search.nodes;
        for &j in &adj[x] {
            used[j] = false;
        }
        for _ in 0..limits.per_detection {
            let cand: Vec<usize> = adj[x].iter().copied().filter(|&j| !used[j]).collect();
            let mut clique = vec![x];
            if !search.extend(&mut clique, &cand) {
                break;
            }
            for &j in &clique[1..] {
                used[j] = true;
            }
            crate::sort::natural(&mut clique);
            if seen.insert(clique.clone()) {
                out.push(clique);
            }
        }
        total -= before - search.nodes;
    }
    out
}

/// The distinct-pair graph among the `live` detections (time order):
/// sorted neighbour lists, indexed by detection (module doc, step 1).
fn distinct_graph(
    mission: &Mission,
    model: &Model,
    live: &[usize],
    ahead: usize,
) -> Vec<Vec<usize>> {
    let k = mission.detections.len();
    let sightings: Vec<Sighting> = mission
        .detections
        .iter()
        .map(|d| Sighting {
            step: d.step.min(model.steps),
            range: d.range,
            bearing: d.bearing,
        })
        .collect();
    let steps: Vec<usize> = sightings.iter().map(|s| s.step).collect();
    let sums = ChainSums::new(&model.disp, model.dim).with_steps(&steps);
    let mut pairs = Vec::new();
    relative_pairs(
        &sightings,
        live,
        model.dim,
        &sums,
        &model.pos,
        &model.det,
        &model.heading_at,
        ahead,
        &mut pairs,
    );
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); k];
    for &(a, b) in &pairs {
        adj[a as usize].push(b as usize);
        adj[b as usize].push(a as usize);
    }
    for row in &mut adj {
        crate::sort::natural(row);
        row.dedup();
    }
    adj
}

/// A depth-first search for one clique of `size` members.
struct Search<'a> {
    /// Sorted neighbour lists.
    adj: &'a [Vec<usize>],
    size: usize,
    /// Nodes left.
    nodes: u64,
}

impl Search<'_> {
    /// Extends `clique` (pairwise adjacent) by members of `cand` (sorted,
    /// each adjacent to every member) to `size`; whether it did (else
    /// `clique` is as given).
    fn extend(&mut self, clique: &mut Vec<usize>, cand: &[usize]) -> bool {
        if clique.len() == self.size {
            return true;
        }
        for (i, &v) in cand.iter().enumerate() {
            if clique.len() + cand.len() - i < self.size {
                return false;
            }
            let Some(left) = self.nodes.checked_sub(1) else {
                return false;
            };
            self.nodes = left;
            let next = meet(&cand[i + 1..], &self.adj[v]);
            clique.push(v);
            if self.extend(clique, &next) {
                return true;
            }
            clique.pop();
        }
        false
    }
}

/// The sorted intersection of two sorted lists.
fn meet(a: &[usize], b: &[usize]) -> Vec<usize> {
    let mut out = Vec::new();
    crate::sort::meet_sorted(a, b, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_search_finds_a_clique_only_where_there_is_one() {
        // A 4-cycle has no triangle; add a chord and it has two.
        let mut adj = vec![vec![1, 3], vec![0, 2], vec![1, 3], vec![0, 2]];
        let mut s = Search {
            adj: &adj,
            size: 3,
            nodes: 1000,
        };
        let mut c = vec![0];
        assert!(!s.extend(&mut c, &[1, 3]));
        assert_eq!(c, vec![0]);
        adj[0] = vec![1, 2, 3];
        adj[2] = vec![0, 1, 3];
        let mut s = Search {
            adj: &adj,
            size: 3,
            nodes: 1000,
        };
        let mut c = vec![0];
        assert!(s.extend(&mut c, &[1, 2, 3]));
        assert_eq!(c, vec![0, 1, 2]);
        assert_eq!(meet(&[1, 3, 5, 7], &[2, 3, 7, 9]), vec![3, 7]);
    }
}
