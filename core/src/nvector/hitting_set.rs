//! The `exact` contractor of atmost_nvector(n, {d(1)..d(k)}): the minimum
//! hitting set of the boxes and exact bound consistency, by branch and bound
//! (exponential; k <= 40). The reference the polynomial contractors are
//! measured against (Chabert, Jaulin, Lorca, CP 2009, section 4: computing
//! the minimum number of distinct vectors is NP-hard).
//!
//! # Math
//!
//! A solution chooses at most n points (the distinct vectors) such that
//! every box holds one of them: a *hitting set*. Boxes have Helly number 2,
//! so a set of boxes has a common point iff they pairwise meet, and the
//! boxes a point hits, `B(v)`, are maximal when `v` is the lower corner of a
//! non-empty intersection of boxes: each coordinate of that corner is some
//! box's lower bound. The *candidate cliques* are the maximal sets `B(v)`
//! over the grid of lower bounds, represented as bit masks (k <= 40 < 64).
//! The minimum hitting set of a set `U` of boxes is the minimum cover of `U`
//! by candidate cliques, found by branching on the cliques that hold the
//! lowest uncovered box, with memoisation.
//!
//! Bound consistency: box i can take value v iff v ∈ box_i and the boxes
//! not holding v can be hit by n - 1 more points: `cover(U \ B(v)) <= n - 1`.
//! Feasibility is monotone in `B(v)`, and on each axis `B(v)` only changes
//! at box bounds, where it is largest (a bound point belongs to both the
//! pieces around it), so the extreme feasible coordinate on axis a is a box
//! bound: the new lower bound of box i on axis a is the smallest bound value
//! e in box_i\[a\] for which some v with v\[a\] = e is feasible, the other
//! coordinates of v ranging over the box bounds inside box_i (and likewise
//! from above). An unbounded side stays unbounded when the piece beyond the
//! outermost bound is feasible.
//!
//! # Soundness
//!
//! Exact enumeration: a value is removed only when no hitting set of size
//! <= n through it exists. No arithmetic on bounds (representatives of open
//! pieces beyond the outermost bound are only used to test membership).
//!
//! # Complexity
//!
//! Exponential in the worst case (set cover); candidate cliques O(k^d · k),
//! bound consistency O(d k (2k)^(d-1)) feasibility tests, each a memoised
//! cover search.
//!
//! # Bounded work
//!
//! Every grid point visited (candidate cliques, feasibility tests) and every
//! node of the cover search counts one *node* against [`Limits::node_budget`];
//! the caller's cancellation flag ([`Limits::cancel`], for a deadline) is
//! read every [`CANCEL_EVERY`] nodes. When either runs out, the search
//! stops with a [`WorkLimit`] error instead of an answer: no box is
//! changed by an unfinished search (the caller's boxes keep what the
//! polynomial passes proved, which is sound). A node costs O(k) to
//! O(k · d) (a grid point tests every box), so the budget bounds the time
//! at about budget · k · d operations and the memo at budget entries.

use crate::ibox::IntervalBox;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// Largest k the exact contractor accepts.
pub const MAX_K: usize = 40;

/// The default [`Limits::node_budget`]: 16 million nodes, 1.3 to 3 s of
/// search on the worst cases measured (40 boxes in 8-D, n = 6, which
/// would otherwise run for minutes; release build, docs/contract.md), while
/// the paper-like instances of `nvector bench --only exact` need a few
/// hundred nodes (350 at k = 40 in 2-D) and 40 boxes in 4-D with n = 8
/// about 15 million.
pub const DEFAULT_NODE_BUDGET: u64 = 16_000_000;

/// How many nodes pass between two reads of the cancellation flag.
pub const CANCEL_EVERY: u64 = 4096;

/// Elementary operations (mask comparisons) worth one node: a grid point
/// tests every box on every axis, k · d <= 40 · 8 comparisons.
const OPS_PER_NODE: u64 = 256;

/// Most memoised covers kept: past this the memo starts over (the answers
/// stay exact, only time is lost), so memory stays near 70 MB whatever the
/// budget.
const MEMO_CAP: usize = 1 << 21;

/// Distinct masks kept while the grid is enumerated are deduplicated when
/// the list doubles past this size, so memory follows the distinct masks,
/// not the grid.
const MASKS_DEDUP: usize = 1 << 20;

/// Sorts and deduplicates `masks` when it has grown past `*limit`; the next
/// limit is twice what is left.
fn dedup_when_large(masks: &mut Vec<u64>, limit: &mut usize) {
    if masks.len() >= *limit {
        crate::sort::natural(masks);
        masks.dedup();
        *limit = (2 * masks.len()).max(MASKS_DEDUP);
    }
}

/// Most fixpoint rounds (each round is one pass over the axes and, for
/// `independent`, one witness pass); a round that changes nothing stops.
/// Reaching it with work pending sets
/// [`crate::nvector::Outcome::stopped_early`]. Here, with [`Limits`], so
/// that this module needs nothing of its parent.
pub const MAX_ROUNDS: u32 = 64;

/// Limits on the work of one atmost_nvector contraction
/// ([`crate::nvector::atmost_nvector_with`]): the exact contractor's search
/// and the fixpoint's rounds.
#[derive(Debug, Clone, Copy)]
pub struct Limits<'a> {
    /// Most nodes of the exact contractor (grid points visited plus
    /// cover-search nodes); default [`DEFAULT_NODE_BUDGET`].
    pub node_budget: u64,
    /// Read every [`CANCEL_EVERY`] nodes of the exact contractor; `true`
    /// stops the search (the caller sets it at its deadline, or to cancel).
    pub cancel: Option<&'a AtomicBool>,
    /// Most fixpoint rounds (default [`crate::nvector::MAX_ROUNDS`]);
    /// reaching it with work pending is reported, not an error
    /// ([`crate::nvector::Outcome::stopped_early`]).
    pub max_rounds: u32,
}

impl Default for Limits<'_> {
    fn default() -> Self {
        Limits {
            node_budget: DEFAULT_NODE_BUDGET,
            cancel: None,
            max_rounds: MAX_ROUNDS,
        }
    }
}

/// Why the exact contractor stopped before an answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkLimit {
    /// The node budget (the value) ran out.
    NodeBudget(u64),
    /// The caller's cancellation flag was set (a deadline or a cancel).
    Cancelled,
}

impl std::fmt::Display for WorkLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WorkLimit::NodeBudget(b) => write!(
                f,
                "the exact contractor ran out of its work budget ({b} search nodes) before \
                 an answer: the boxes overlap in too many ways for an exact search; use \
                 fewer boxes or axes, or a polynomial contractor (best)"
            ),
            WorkLimit::Cancelled => write!(
                f,
                "the exact contractor was stopped by its time limit before an answer; use \
                 fewer boxes or axes, or a polynomial contractor (best)"
            ),
        }
    }
}

impl std::error::Error for WorkLimit {}

/// The work left: nodes, and when to read the cancellation flag next.
struct Work<'a> {
    budget: u64,
    used: u64,
    next_check: u64,
    cancel: Option<&'a AtomicBool>,
}

impl<'a> Work<'a> {
    fn new(limits: &Limits<'a>) -> Work<'a> {
        Work {
            budget: limits.node_budget,
            used: 0,
            next_check: CANCEL_EVERY,
            cancel: limits.cancel,
        }
    }

    /// Counts one node.
    #[inline]
    fn tick(&mut self) -> Result<(), WorkLimit> {
        self.charge(1)
    }

    /// Counts `nodes` nodes (work worth that many grid points).
    #[inline]
    fn charge(&mut self, nodes: u64) -> Result<(), WorkLimit> {
        self.used += nodes;
        if self.used > self.budget {
            return Err(WorkLimit::NodeBudget(self.budget));
        }
        if self.used >= self.next_check {
            self.next_check += CANCEL_EVERY;
            if self.cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return Err(WorkLimit::Cancelled);
            }
        }
        Ok(())
    }
}

/// Exact minimum cover search over candidate cliques.
pub struct HittingSet<'a> {
    boxes: &'a [IntervalBox],
    cliques: Vec<u64>,
    /// For each box, the candidate cliques holding it.
    by_box: Vec<Vec<usize>>,
    memo: HashMap<u64, usize>,
    work: Work<'a>,
}

fn mask_of(boxes: &[IntervalBox], v: &[f64]) -> u64 {
    let mut m = 0u64;
    for (i, b) in boxes.iter().enumerate() {
        if b.contains(v) {
            m |= 1 << i;
        }
    }
    m
}

/// The distinct finite bound values of all boxes on one axis, sorted.
fn axis_bounds(boxes: &[IntervalBox], axis: usize, lower_only: bool) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::with_capacity(2 * boxes.len());
    for b in boxes {
        let x = b[axis];
        if x.lo().is_finite() {
            v.push(x.lo());
        }
        if !lower_only && x.hi().is_finite() {
            v.push(x.hi());
        }
    }
    crate::sort::floats(&mut v);
    v.dedup();
    if v.is_empty() {
        // Every box is unbounded on this axis both ways... or only above:
        // any value works as a representative.
        let his = boxes
            .iter()
            .map(|b| b[axis].hi())
            .fold(f64::INFINITY, f64::min);
        v.push(if his.is_finite() { his } else { 0.0 });
    }
    v
}

/// Calls `f` on every point of the grid `axes[0] × axes[1] × ...`, one
/// node of `work` each.
fn for_each_grid_point(
    axes: &[Vec<f64>],
    work: &mut Work,
    f: &mut dyn FnMut(&[f64]),
) -> Result<(), WorkLimit> {
    let d = axes.len();
    let mut idx = vec![0usize; d];
    let mut v: Vec<f64> = axes.iter().map(|a| a[0]).collect();
    loop {
        work.tick()?;
        f(&v);
        let mut a = 0;
        loop {
            if a == d {
                return Ok(());
            }
            idx[a] += 1;
            if idx[a] < axes[a].len() {
                v[a] = axes[a][idx[a]];
                break;
            }
            idx[a] = 0;
            v[a] = axes[a][0];
            a += 1;
        }
    }
}

impl<'a> HittingSet<'a> {
    /// Prepares the candidate cliques of `boxes` (non-empty, k <= 40), with
    /// the default [`Limits`] (no cancellation flag).
    pub fn new(boxes: &'a [IntervalBox]) -> Result<HittingSet<'a>, WorkLimit> {
        HittingSet::with_limits(boxes, &Limits::default())
    }

    /// Prepares the candidate cliques of `boxes` (non-empty, k <= 40); the
    /// work of this and of every later search counts against `limits`.
    pub fn with_limits(
        boxes: &'a [IntervalBox],
        limits: &Limits<'a>,
    ) -> Result<HittingSet<'a>, WorkLimit> {
        let mut work = Work::new(limits);
        let k = boxes.len();
        assert!(k <= MAX_K);
        let d = boxes.first().map_or(0, |b| b.dim());
        // The lower corner of an intersection is a grid point of lower
        // bounds, unless a box is unbounded below on that axis: then the
        // intersection may reach -inf there and its upper end (an upper
        // bound) is used instead, so all bounds enter the grid.
        let axes: Vec<Vec<f64>> = (0..d)
            .map(|a| {
                let unbounded_below = boxes.iter().any(|b| b[a].lo() == f64::NEG_INFINITY);
                axis_bounds(boxes, a, !unbounded_below)
            })
            .collect();
        let mut masks: Vec<u64> = Vec::new();
        let mut limit = MASKS_DEDUP;
        if d > 0 {
            for_each_grid_point(&axes, &mut work, &mut |v| {
                let m = mask_of(boxes, v);
                if m != 0 {
                    masks.push(m);
                    dedup_when_large(&mut masks, &mut limit);
                }
            })?;
        }
        // Every box holds its own lower corner only when bounded below; an
        // unbounded box is still hit by the corner grid? Not always: add
        // each box's own representative point to be complete.
        for b in boxes {
            let v: Vec<f64> = b
                .axes()
                .iter()
                .map(|x| representative(x.lo(), x.hi()))
                .collect();
            let m = mask_of(boxes, &v);
            if m != 0 {
                masks.push(m);
            }
        }
        crate::sort::natural(&mut masks);
        masks.dedup();
        // Keep maximal masks only.
        let mut cliques: Vec<u64> = Vec::new();
        by_size_desc(&mut masks);
        for m in masks {
            work.charge(1 + cliques.len() as u64 / OPS_PER_NODE)?;
            if !cliques.iter().any(|&c| c & m == m) {
                cliques.push(m);
            }
        }
        let mut by_box = vec![Vec::new(); k];
        for (ci, &c) in cliques.iter().enumerate() {
            for (i, list) in by_box.iter_mut().enumerate() {
                if c & (1 << i) != 0 {
                    list.push(ci);
                }
            }
        }
        Ok(HittingSet {
            boxes,
            cliques,
            by_box,
            memo: HashMap::new(),
            work,
        })
    }

    /// Nodes used so far (grid points and cover-search nodes).
    pub fn nodes(&self) -> u64 {
        self.work.used
    }

    /// All boxes, as a mask.
    pub fn all(&self) -> u64 {
        if self.boxes.len() == 64 {
            u64::MAX
        } else {
            (1u64 << self.boxes.len()) - 1
        }
    }

    /// The minimum number of points hitting every box of `u`.
    pub fn min_cover(&mut self, u: u64) -> Result<usize, WorkLimit> {
        if u == 0 {
            return Ok(0);
        }
        if let Some(&r) = self.memo.get(&u) {
            return Ok(r);
        }
        self.work.tick()?;
        if self.memo.len() >= MEMO_CAP {
            self.memo.clear();
        }
        // Branch on the uncovered box with the fewest candidate cliques.
        let mut best_box = u.trailing_zeros() as usize;
        let mut best_count = usize::MAX;
        let mut rest = u;
        while rest != 0 {
            let i = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let c = self.by_box[i].len();
            if c < best_count {
                best_count = c;
                best_box = i;
            }
        }
        let mut best = usize::MAX;
        let options: Vec<u64> = {
            let mut o: Vec<u64> = self.by_box[best_box]
                .iter()
                .map(|&ci| self.cliques[ci] & u)
                .collect();
            crate::sort::natural(&mut o);
            o.dedup();
            // Drop options dominated by another (subset of it within u).
            let (raw, len) = (self.by_box[best_box].len() as u64, o.len() as u64);
            self.work.charge((raw + len * len) / OPS_PER_NODE)?;
            let all = o.clone();
            o.retain(|&m| !all.iter().any(|&x| x != m && x & m == m));
            o
        };
        for m in options {
            let r = 1 + self.min_cover(u & !m)?;
            best = best.min(r);
            if best == 1 {
                break;
            }
        }
        self.memo.insert(u, best);
        Ok(best)
    }

    /// Whether box `i` can take a value `v` with `v[axis] = e`, i.e. some
    /// `v ∈ box_i` on the bound grid with `cover(U \ B(v)) <= n - 1`.
    fn feasible_at(
        &mut self,
        n: usize,
        i: usize,
        axis: usize,
        e: f64,
        grid: &[Vec<f64>],
    ) -> Result<bool, WorkLimit> {
        let all = self.all();
        let mut axes: Vec<Vec<f64>> = grid.to_vec();
        axes[axis] = vec![e];
        let boxes = self.boxes;
        let mut masks = Vec::new();
        let mut limit = MASKS_DEDUP;
        for_each_grid_point(&axes, &mut self.work, &mut |v| {
            if boxes[i].contains(v) {
                masks.push(mask_of(boxes, v));
                dedup_when_large(&mut masks, &mut limit);
            }
        })?;
        crate::sort::natural(&mut masks);
        masks.dedup();
        by_size_desc(&mut masks);
        for m in masks {
            if self.min_cover(all & !m)? < n {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Exact bound consistency: the hull of the values box `i` takes over
    /// all solutions with at most `n` distinct vectors (empty if none).
    pub fn consistent_box(&mut self, n: usize, i: usize) -> Result<IntervalBox, WorkLimit> {
        let b = self.boxes[i].clone();
        let d = b.dim();
        // Grid of candidate coordinates inside box_i, per axis: all bounds
        // within it, plus representatives of the unbounded pieces.
        let grid: Vec<Vec<f64>> = (0..d)
            .map(|a| {
                let x = b[a];
                let mut g: Vec<f64> = axis_bounds(self.boxes, a, false)
                    .into_iter()
                    .filter(|&e| x.contains(e))
                    .collect();
                if g.is_empty() {
                    g.push(representative(x.lo(), x.hi()));
                }
                g
            })
            .collect();
        let mut out = b.clone();
        for a in 0..d {
            let cands = &grid[a];
            let mut lo_pos = None;
            for (j, &e) in cands.iter().enumerate() {
                if self.feasible_at(n, i, a, e, &grid)? {
                    lo_pos = Some(j);
                    break;
                }
            }
            let Some(lo_pos) = lo_pos else {
                return Ok(IntervalBox::empty(d));
            };
            let mut hi_pos = lo_pos;
            for j in (lo_pos + 1..cands.len()).rev() {
                if self.feasible_at(n, i, a, cands[j], &grid)? {
                    hi_pos = j;
                    break;
                }
            }
            let mut lo = cands[lo_pos];
            let mut hi = cands[hi_pos];
            // Unbounded sides: test a point beyond the outermost bound (any
            // point of the open piece beyond it: the next float, so that
            // huge bounds work too; `c - 1` is `c` for c = 1e308).
            if b[a].lo() == f64::NEG_INFINITY && lo_pos == 0 {
                let beyond = cands[0].next_down();
                if beyond < cands[0] && self.feasible_at(n, i, a, beyond, &grid)? {
                    lo = f64::NEG_INFINITY;
                }
            }
            if b[a].hi() == f64::INFINITY && hi_pos == cands.len() - 1 {
                let last = cands[cands.len() - 1];
                let beyond = last.next_up();
                if beyond > last && self.feasible_at(n, i, a, beyond, &grid)? {
                    hi = f64::INFINITY;
                }
            }
            out[a] = crate::interval::Interval::new(lo, hi);
        }
        Ok(out)
    }
}

/// A point of `[lo, hi]` (finite when possible).
fn representative(lo: f64, hi: f64) -> f64 {
    match (lo.is_finite(), hi.is_finite()) {
        (true, _) => lo,
        (false, true) => hi,
        (false, false) => 0.0,
    }
}

/// Masks by decreasing size, ties by value (distinct masks: one order).
fn by_size_desc(masks: &mut [u64]) {
    let key = |m: u64| (std::cmp::Reverse(m.count_ones()), m);
    crate::sort::sort_u64_by(masks, &mut |a, b| key(a).cmp(&key(b)));
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::interval::Interval;

    fn b2(x0: f64, x1: f64, y0: f64, y1: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x0, x1), Interval::new(y0, y1)])
    }

    #[test]
    fn gccat_example_needs_two_vectors() {
        let boxes = vec![
            b2(1.0, 6.0, 2.0, 6.0),
            b2(3.0, 5.0, 6.0, 9.0),
            b2(4.0, 10.0, 1.0, 4.0),
            b2(5.0, 9.0, 3.0, 7.0),
            b2(9.0, 11.0, 0.0, 5.0),
        ];
        let mut h = HittingSet::new(&boxes).unwrap();
        let all = h.all();
        assert_eq!(h.min_cover(all), Ok(2));
    }

    #[test]
    fn exact_bounds_of_two_clusters() {
        // n = 1: the single vector is in all three boxes: [1,2]x[1,2].
        let boxes = vec![
            b2(0.0, 2.0, 0.0, 2.0),
            b2(1.0, 3.0, 1.0, 3.0),
            b2(0.0, 5.0, 0.0, 5.0),
        ];
        let mut h = HittingSet::new(&boxes).unwrap();
        for i in 0..3 {
            assert_eq!(h.consistent_box(1, i), Ok(b2(1.0, 2.0, 1.0, 2.0)));
        }
    }

    /// A worst case measured when the work budget was set: 40 overlapping boxes in 8-D (integer
    /// bounds, centres in [0, 10], sides 4 to 8), n = 6. Without a budget the
    /// grid of lower bounds alone (about 15^8 points) takes minutes.
    pub(crate) fn worst_case() -> Vec<IntervalBox> {
        let mut rng = crate::test_rng::Lcg::new(12);
        (0..40)
            .map(|_| {
                let axes: Vec<Interval> = (0..8)
                    .map(|_| {
                        let c = (rng.unit() * 10.0).round();
                        let a = (4.0 + rng.unit() * 4.0).round();
                        let b = (4.0 + rng.unit() * 4.0).round();
                        Interval::new(c - a, c + b)
                    })
                    .collect();
                IntervalBox::new(&axes)
            })
            .collect()
    }

    #[test]
    fn the_worst_case_answers_the_budget_error() {
        let boxes = worst_case();
        let limits = Limits {
            node_budget: 20_000,
            ..Limits::default()
        };
        let r = HittingSet::with_limits(&boxes, &limits).map(|_| ());
        assert_eq!(r, Err(WorkLimit::NodeBudget(20_000)));
        let message = WorkLimit::NodeBudget(20_000).to_string();
        assert!(
            message.contains("work budget (20000 search nodes)"),
            "{message}"
        );
    }

    #[test]
    fn the_cancellation_flag_stops_the_search() {
        let boxes = worst_case();
        let cancel = AtomicBool::new(true);
        let limits = Limits {
            cancel: Some(&cancel),
            ..Limits::default()
        };
        let r = HittingSet::with_limits(&boxes, &limits).map(|_| ());
        assert_eq!(r, Err(WorkLimit::Cancelled));
        assert!(WorkLimit::Cancelled.to_string().contains("time limit"));
    }

    #[test]
    fn the_budget_counts_every_search() {
        // The GCCAT example needs a few dozen nodes: it finishes within 100
        // and not within 5; the cover search after `new` counts too.
        let boxes = vec![
            b2(1.0, 6.0, 2.0, 6.0),
            b2(3.0, 5.0, 6.0, 9.0),
            b2(4.0, 10.0, 1.0, 4.0),
            b2(5.0, 9.0, 3.0, 7.0),
            b2(9.0, 11.0, 0.0, 5.0),
        ];
        let small = Limits {
            node_budget: 5,
            ..Limits::default()
        };
        assert!(HittingSet::with_limits(&boxes, &small).is_err());
        let mut h = HittingSet::with_limits(&boxes, &Limits::default()).unwrap();
        let all = h.all();
        let before = h.nodes();
        assert_eq!(h.min_cover(all), Ok(2));
        assert!(h.nodes() > before && h.nodes() < 100, "{}", h.nodes());
        let exact = Limits {
            node_budget: h.nodes(),
            ..Limits::default()
        };
        let mut h = HittingSet::with_limits(&boxes, &exact).unwrap();
        assert_eq!(h.min_cover(all), Ok(2));
        let tight = Limits {
            node_budget: exact.node_budget - 1,
            ..Limits::default()
        };
        let mut h = HittingSet::with_limits(&boxes, &tight).unwrap();
        assert_eq!(
            h.min_cover(all),
            Err(WorkLimit::NodeBudget(tight.node_budget))
        );
    }

    /// Regression (found by the signed-zero / overflowing-range property
    /// test): the point tested beyond the outermost bound of an unbounded
    /// side was `c - 1`, which is `c` for c = 1e308; the side was never
    /// tested, and n = 1 over the one box [-inf, 1e308] became
    /// [1e308, 1e308], losing every other value.
    #[test]
    fn regression_unbounded_side_beyond_a_huge_bound() {
        let b1 = |lo: f64, hi: f64| IntervalBox::new(&[Interval::new(lo, hi)]);
        for (lo, hi) in [
            (f64::NEG_INFINITY, 1e308),
            (-1e308, f64::INFINITY),
            (f64::NEG_INFINITY, -f64::MAX),
            (f64::MAX, f64::INFINITY),
        ] {
            let boxes = vec![b1(lo, hi)];
            let mut h = HittingSet::new(&boxes).unwrap();
            assert_eq!(h.consistent_box(1, 0), Ok(boxes[0].clone()), "[{lo}, {hi}]");
        }
    }

    /// Regression (found by the planted-solution property test): with boxes
    /// unbounded below, the clique {0, 1} meets only at x <= 0, whose lower
    /// corner is -inf; the candidate grid missed it, the exact contractor
    /// thought 3 vectors were needed through x = 5 and cut the planted
    /// point of box 2.
    #[test]
    fn regression_unbounded_below_cliques_are_found() {
        let boxes = vec![
            b2(f64::NEG_INFINITY, 3.0, 0.0, 0.0),
            b2(f64::NEG_INFINITY, 0.0, -1.0, 0.0),
            b2(f64::NEG_INFINITY, 5.0, 0.0, 0.0),
            b2(3.0, 5.0, 0.0, 0.0),
        ];
        let mut h = HittingSet::new(&boxes).unwrap();
        assert_eq!(h.min_cover(0b0011), Ok(1));
        assert!(h.consistent_box(2, 2).unwrap().contains(&[5.0, 0.0]));
    }
}
