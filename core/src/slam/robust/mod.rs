//! Robust propagation for missions with false detections
//! (`max_outliers` = q > 0).
//!
//! # Constraint
//!
//! The solution set is the union, over every set F of at most q dropped
//! detections, of the solutions of the mission without F. Every position box
//! must hold every position of every such sub-mission; the box of d(j) must
//! hold every value d(j) takes in the sub-missions that keep j. With q = 0
//! this module is not used (the ordinary propagator is exact for it).
//!
//! # Math
//!
//! - The motion chain, the initial and final positions hold in every
//!   sub-mission: the usual sweeps `p(i+1) ∩= p(i) + D(i)`,
//!   `p(i) ∩= p(i+1) - D(i)`.
//! - A detection j holds only where j is kept. From the current boxes it
//!   gives an *evidence* box `M(j)` for p(t_j): p(t_j) contracted by the
//!   distance (and bearing) constraint towards d(j), where d(j) is j's own
//!   box intersected with its landmark box. In a sub-mission keeping j,
//!   `p(t_j) ∈ M(j)`, and along the chain, for t >= t_j,
//!   `p(t) >= M(j).lo + Σ_{s=t_j}^{t-1} D(s).lo` (and the three mirror
//!   bounds). Evidence is never applied directly: a sub-mission drops at most
//!   q of the detections, so p(t) lies in the *q-relaxed intersection* of
//!   the evidence (the points lying in all but at most q of the sets): on
//!   each axis, its lower bound is at least the (q+1)-th largest of the
//!   evidence lower bounds, its upper bound at most the (q+1)-th smallest
//!   upper bound. The forward pass applies this to the evidence of
//!   detections at or before t; the backward pass to the evidence on both
//!   sides (the forward keys of the detections strictly before t are
//!   recorded by the forward pass, those at or after t are its own: no
//!   detection counts twice).
//! - Keys: the sums of displacement bounds are carried as running interval
//!   sums `S(t) ∋ Σ_{s<t} D(s).lo` (outward-rounded), so an evidence lower
//!   bound at t is `M.lo - S(t_j) + S(t) >= down(M.lo - S(t_j).hi) +
//!   S(t).lo`: the key `down(M.lo - S(t_j).hi)` does not depend on t, and
//!   the (q+1) largest keys are kept in a small sorted list: O(log q) per
//!   detection, O(1) per step. An unbounded displacement voids the evidence
//!   behind it (the list is cleared and the sums restart).
//! - Landmarks: detections with the same operator `landmark` share one
//!   landmark L. In a sub-mission keeping j, L lies in the own box of every
//!   kept member, that is in all but at most q of the members' boxes: per
//!   axis, the q-relaxed intersection of the members' boxes holds L, and
//!   d(j) lies in it and in j's own box.
//! - Proved false: when j's own constraints (range, bearing, region) have no
//!   solution within the current box of p(t_j), j is dropped in every
//!   feasible sub-mission; it gives no evidence, its box becomes empty, and
//!   the budget left for the others is q minus the number proved false
//!   (below zero: the mission is infeasible).
//! - atmost_nvector is not applied in these rounds: its contractors reason
//!   on every detection (a false one would make their groups unsound).
//! - `matching` (see [`super::kept`]): dropping a detection only removes
//!   constraints, so unless every reading (set of at most q detections
//!   taken as false) holds exactly q detections, any detection, labelled or
//!   not, is false in some reading, and no group is proved. At the fixpoint
//!   the detections proved false and the pairs with one label and disjoint
//!   boxes (one of each is false) are counted; when they account for q,
//!   every other detection is kept in every reading, and the ordinary
//!   propagation (with the requested association) on the mission cut to
//!   them is sound: its groups are reported, its boxes intersected in.
//!   Otherwise `matching` is empty. q >= k reads as q = k (no allocation is
//!   sized by q itself).
//!
//! # Soundness
//!
//! Every box computed encloses, by induction over the passes, every
//! solution of every sub-mission with at most q dropped detections: the
//! chain sweeps use constraints that hold in all of them; an evidence box is
//! computed from enclosures by sound contractors, so it holds p(t_j) in each
//! sub-mission keeping j; in a sub-mission, at most q (or the budget left)
//! of the listed evidences are dropped, so the true bound is at least the
//! largest kept one, hence at least the (q+1)-th largest overall. Every
//! rounding of a key or a bound goes outward (`pred`/`succ` after each
//! rounded operation, sums through `Interval::add`).
//!
//! # Complexity
//!
//! With q capped at k, a round is O(N·d·q + k·d·q) time (two passes over the chain, one
//! contraction per detection, sorted lists of q+1 keys per axis and bound,
//! merged at each step of the backward pass) and O(N·d + k·q·d) memory
//! beyond the model (recorded sums and key snapshots; past 2^24 keys the
//! merge is given up and the one-sided bounds stay).

use super::association::tracks::TrackOptions;
use super::kept::{kept_with_conflicts, refine, sure_groups, Accounted};
use super::mission::Mission;
use super::model::{operator_groups, Model};
use super::robust_conflicts::{pack, Packing};
use super::robust_heading::{cut_headings, robust_heading};
pub use super::robust_regions::relaxed_intersection;
use super::robust_regions::{regions_with, Regions};
use super::robust_subsets::{consensus_told, Consensus};
use super::robust_tracks::robust_track_groups;
use super::types::{OutlierTally, Progress, Solution, SolveOptions, SolveStatus, WorkEstimate};
use crate::contractors::bearing::contract_bearing;
use crate::contractors::distance::contract_distance;
use crate::contractors::motion_chain::shrinkage;
use crate::ibox::IntervalBox;
use crate::interval::{pred, succ, Interval};
use std::sync::atomic::{AtomicBool, Ordering};

/// The (m+1) largest values seen (or smallest, mirrored by the caller):
/// a sorted list, largest first.
#[derive(Debug, Clone, Default)]
struct TopKeys {
    keep: usize,
    keys: Vec<f64>,
}

impl TopKeys {
    fn new(keep: usize) -> TopKeys {
        TopKeys {
            keep,
            keys: Vec::with_capacity(keep + 1),
        }
    }

    /// Adds a key (NaN never comes in: callers map it to -inf first).
    fn push(&mut self, key: f64) {
        if self.keys.len() == self.keep && self.keys.last().is_some_and(|&m| key <= m) {
            return;
        }
        let at = self.keys.partition_point(|&k| k >= key);
        self.keys.insert(at, key);
        self.keys.truncate(self.keep);
    }
}

/// A lower bound of the real `a + b` (a NaN from `inf - inf` is -inf:
/// no information).
#[inline]
fn add_lo(a: f64, b: f64) -> f64 {
    let s = pred(a + b);
    if s.is_nan() {
        f64::NEG_INFINITY
    } else {
        s
    }
}

/// An upper bound of the real `a + b` (NaN is +inf).
#[inline]
fn add_hi(a: f64, b: f64) -> f64 {
    let s = succ(a + b);
    if s.is_nan() {
        f64::INFINITY
    } else {
        s
    }
}

/// Running interval sums of the lower and upper displacement bounds of one
/// axis, with the evidence keys relative to them.
struct Side {
    /// Encloses the exact sum of the displacement lower bounds so far.
    sum_lo: Interval,
    /// Encloses the exact sum of the displacement upper bounds so far.
    sum_hi: Interval,
    /// Keys of evidence lower bounds (the q+1 largest).
    lower: TopKeys,
    /// Negated keys of evidence upper bounds (the q+1 largest, i.e. the
    /// q+1 smallest upper bounds).
    upper: TopKeys,
}

impl Side {
    fn new(keep: usize) -> Side {
        Side {
            sum_lo: Interval::ZERO,
            sum_hi: Interval::ZERO,
            lower: TopKeys::new(keep),
            upper: TopKeys::new(keep),
        }
    }
}

/// Per-detection state of a round.
struct Evidence {
    /// Proved false (dropped in every feasible sub-mission).
    proved_false: Vec<bool>,
    /// The evidence box of p(t_j) (empty: none).
    boxes: Vec<IntervalBox>,
}

/// What the relaxed passes read of each detection: whether it is proved
/// false, and its evidence box (one axis per state axis of the chain).
type Votes<'a> = (&'a [bool], &'a [IntervalBox]);

/// A chain the relaxed passes run along: N + 1 states of `dim` intervals,
/// `x(t+1) = x(t) + D(t)`. The positions over the displacements, or
/// (odometry2d, [`super::robust_heading`]) the headings over the turns.
struct Track<'a> {
    dim: usize,
    /// N.
    steps: usize,
    /// The states, (N+1)·dim, step-major.
    state: &'a mut [Interval],
    /// The increments D(t), N·dim, step-major.
    step: &'a [Interval],
}

/// The relaxed passes along `track`, forward then backward, with the
/// `keep`-th best evidence of `ev` (proved false, evidence boxes; `budget`
/// + 1 kept); the largest move, or `Err(step)` when a state becomes empty.
fn relaxed_passes(
    mission: &Mission,
    track: &mut Track,
    order: &[usize],
    ev: Votes,
    keep: usize,
) -> Result<f64, usize> {
    let mut moved = 0.0f64;
    let mut record = Some(Record::default());
    for forward in [true, false] {
        let m = relaxed_pass(mission, track, order, ev, keep, forward, &mut record)?;
        moved = moved.max(m);
    }
    Ok(moved)
}

/// Contracts (copies of) p(t_j) and d(j) by j's own constraints. Returns
/// `None` when they have no solution.
fn own(
    mission: &Mission,
    model: &Model,
    j: usize,
    d: &IntervalBox,
) -> Option<(IntervalBox, IntervalBox)> {
    let det = &mission.detections[j];
    let mut p = model.position(det.step);
    let mut d = d.clone();
    let mut range = det.range;
    let ok = contract_distance(p.axes_mut(), d.axes_mut(), &mut range)
        && det.bearing.is_none_or(|b| {
            contract_bearing(p.axes_mut(), d.axes_mut(), model.heading_at[j], b, range)
        });
    (ok && !p.is_empty() && !d.is_empty()).then_some((p, d))
}

/// Evidence of every detection from the current boxes; shrinks the
/// detection boxes. `Err` names why the mission is infeasible.
fn gather(
    mission: &Mission,
    model: &mut Model,
    prior: &[IntervalBox],
    (groups, operator): (&[Vec<usize>], bool),
    q: usize,
    ev: &mut Evidence,
) -> Result<usize, String> {
    let k = mission.detections.len();
    let dim = model.dim;
    let mut own_box = own_boxes(mission, model, prior, ev);
    let false_count = ev.proved_false.iter().filter(|&&f| f).count();
    if false_count <= q && !operator {
        let budget = q - false_count;
        let held = group_landmarks(groups, &own_box, &ev.proved_false, budget, dim);
        region_cut(mission, model, budget, ev, &mut own_box, &held)?;
    }
    let false_count = ev.proved_false.iter().filter(|&&f| f).count();
    if false_count > q {
        let list: Vec<usize> = (0..k).filter(|&j| ev.proved_false[j]).collect();
        return Err(format!(
            "{false_count} detections {list:?} cannot reach any landmark position, more than max_outliers = {q}"
        ));
    }
    let budget = q - false_count;
    // Landmark boxes of the groups (the operator's, or the tracks'),
    // q-relaxed.
    let mut landmark_of: Vec<Option<IntervalBox>> = vec![None; k];
    for g in groups {
        let members: Vec<&IntervalBox> = g
            .iter()
            .filter(|&&j| !ev.proved_false[j])
            .map(|&j| &own_box[j])
            .collect();
        let l = relaxed_intersection(&members, budget, dim);
        if l.is_empty() {
            return Err(format!(
                "landmark of detections {g:?}: their boxes have no common point even with {budget} of them dropped"
            ));
        }
        for &j in g {
            landmark_of[j] = Some(l.clone());
        }
    }
    evidence_boxes(mission, model, ev, own_box, &landmark_of);
    Ok(budget)
}

/// Without operator labels: the landmark regions proved whichever
/// detections are false ([`super::robust_regions`]); each detection's own
/// box shrinks to the hull of its own constraints within each region, and
/// one that meets no region is proved false. `Err`: a region is empty.
fn region_cut(
    mission: &Mission,
    model: &Model,
    budget: usize,
    ev: &mut Evidence,
    own_box: &mut [IntervalBox],
    held: &[IntervalBox],
) -> Result<(), String> {
    let Some(n) = mission.landmark_count else {
        return Ok(());
    };
    let live: Vec<bool> = ev.proved_false.iter().map(|&f| !f).collect();
    let rs = match regions_with(own_box, &live, budget, n, held) {
        Regions::Unknown => return Ok(()),
        Regions::Infeasible(reason) => return Err(reason),
        Regions::Proved(rs) => rs,
    };
    for (j, d) in own_box.iter_mut().enumerate() {
        if ev.proved_false[j] {
            continue;
        }
        let mut hull = IntervalBox::empty(model.dim);
        for r in &rs {
            if !r.meets(d) {
                continue;
            }
            if let Some((_, cut)) = own(mission, model, j, &d.intersect(r)) {
                hull = hull.hull(&cut);
            }
        }
        if hull.is_empty() {
            ev.proved_false[j] = true;
        }
        *d = hull;
    }
    Ok(())
}

/// The boxes proved to hold a landmark in every reading from valid groups
/// ([`super::robust_tracks`]) of at least `budget + 1` live members: every
/// reading keeps one of them, and their common landmark lies in the boxes
/// of all kept members, so in the q-relaxed intersection of their own
/// boxes. O(k log k · d).
fn group_landmarks(
    groups: &[Vec<usize>],
    own_box: &[IntervalBox],
    proved_false: &[bool],
    budget: usize,
    dim: usize,
) -> Vec<IntervalBox> {
    groups
        .iter()
        .filter_map(|g| {
            let members: Vec<&IntervalBox> = g
                .iter()
                .filter(|&&j| !proved_false[j])
                .map(|&j| &own_box[j])
                .collect();
            (members.len() > budget).then(|| relaxed_intersection(&members, budget, dim))
        })
        .filter(|b| !b.is_empty())
        .collect()
}

/// Each detection's own box: its prior box and current box contracted by
/// its own constraints (empty, and proved false, when they have no
/// solution).
fn own_boxes(
    mission: &Mission,
    model: &Model,
    prior: &[IntervalBox],
    ev: &mut Evidence,
) -> Vec<IntervalBox> {
    let (k, dim) = (mission.detections.len(), model.dim);
    let mut own_box: Vec<IntervalBox> = Vec::with_capacity(k);
    #[allow(clippy::needless_range_loop)] // parallel per-detection arrays
    for j in 0..k {
        if ev.proved_false[j] {
            own_box.push(IntervalBox::empty(dim));
            continue;
        }
        let start = prior[j].intersect(&model.det[j]);
        match own(mission, model, j, &start) {
            Some((_, d)) => own_box.push(d),
            None => {
                ev.proved_false[j] = true;
                own_box.push(IntervalBox::empty(dim));
            }
        }
    }
    own_box
}

/// The evidence boxes of p(t_j) and the detections' final boxes: each own
/// box cut by its group's landmark box and contracted again.
fn evidence_boxes(
    mission: &Mission,
    model: &mut Model,
    ev: &mut Evidence,
    own_box: Vec<IntervalBox>,
    landmark_of: &[Option<IntervalBox>],
) {
    let dim = model.dim;
    for (j, mut d) in own_box.into_iter().enumerate() {
        if ev.proved_false[j] {
            ev.boxes[j] = IntervalBox::empty(dim);
            model.det[j].set_empty();
            continue;
        }
        if let Some(l) = &landmark_of[j] {
            d.intersect_with(l);
        }
        match own(mission, model, j, &d) {
            Some((p, d)) => {
                ev.boxes[j] = p;
                model.det[j] = d;
            }
            None => {
                // In every sub-mission keeping j, d(j) lies in its own box
                // and in the landmark box (relaxed with the budget left,
                // a superset of the one with a smaller budget): no point
                // satisfies j, so j is dropped in every feasible
                // sub-mission. The count is checked next round.
                ev.proved_false[j] = true;
                ev.boxes[j] = IntervalBox::empty(dim);
                model.det[j].set_empty();
            }
        }
    }
}

/// What the forward pass leaves for the backward one, so that the backward
/// pass can take the (q+1)-th best evidence among the detections on *both*
/// sides of each step: the forward running sums at each step, and the
/// forward keys of the detections strictly before it (a detection at step
/// t is in the backward lists at t: none is counted twice).
#[derive(Default)]
struct Record {
    /// (N+1)·dim forward sides' sums (lower, upper displacement bounds).
    sums: Vec<(Interval, Interval)>,
    /// Per step: the snapshot of the forward keys of earlier detections.
    at: Vec<u32>,
    /// Snapshots: per axis, (lower keys, negated upper keys), sorted
    /// largest first.
    lists: Vec<Vec<[Vec<f64>; 2]>>,
}

/// No forward keys.
const NO_KEYS: [Vec<f64>; 2] = [Vec::new(), Vec::new()];

/// Most keys kept in snapshots before the merge is given up (the one-sided
/// bounds stay, sound and looser).
const RECORD_KEYS: usize = 1 << 24;

/// The lower bound of p at a step from a lower key, with the running sums
/// (lower, upper displacement bounds) of the pass at that step.
fn lower_at(sums: (Interval, Interval), key: f64, forward: bool) -> f64 {
    if forward {
        add_lo(key, sums.0.lo())
    } else {
        add_lo(key, -sums.1.hi())
    }
}

/// The upper bound of p at a step from a negated upper key (see
/// [`lower_at`]).
fn upper_at(sums: (Interval, Interval), neg_key: f64, forward: bool) -> f64 {
    if forward {
        add_hi(-neg_key, sums.1.hi())
    } else {
        add_hi(-neg_key, -sums.0.lo())
    }
}

/// The m-th largest of `f(a_i)` and `g(b_j)` over two lists sorted largest
/// first, `f` and `g` non-decreasing (so each mapped list stays sorted).
fn kth_merged(
    a: &[f64],
    f: impl Fn(f64) -> f64,
    b: &[f64],
    g: impl Fn(f64) -> f64,
    m: usize,
) -> Option<f64> {
    if a.len() + b.len() < m {
        return None;
    }
    let (mut i, mut j) = (0, 0);
    let mut last = f64::NEG_INFINITY;
    for _ in 0..m {
        let x = a.get(i).map(|&k| f(k));
        let y = b.get(j).map(|&k| g(k));
        last = match (x, y) {
            (Some(x), Some(y)) if x >= y => {
                i += 1;
                x
            }
            (_, Some(y)) => {
                j += 1;
                y
            }
            (Some(x), None) => {
                i += 1;
                x
            }
            (None, None) => return None,
        };
    }
    Some(last)
}

/// Which way a relaxed pass runs along the chain: every place where the
/// two passes differ is one method here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Way {
    Forward,
    Backward,
}

impl Way {
    fn forward(self) -> bool {
        self == Way::Forward
    }

    /// The `x`-th step the pass visits, of 0..=n.
    fn step(self, x: usize, n: usize) -> usize {
        match self {
            Way::Forward => x,
            Way::Backward => n - x,
        }
    }

    /// The chain step carried into step `t`, and its (from, to) ends.
    fn link(self, t: usize, n: usize) -> Option<(usize, usize, usize)> {
        match self {
            Way::Forward => t.checked_sub(1).map(|s| (s, s, s + 1)),
            Way::Backward => (t < n).then_some((t, t + 1, t)),
        }
    }

    /// p(to) from p(from) over the displacement `d`.
    fn carry(self, q: Interval, d: Interval) -> Interval {
        match self {
            Way::Forward => q + d,
            Way::Backward => q - d,
        }
    }

    /// The keys of an evidence box's axis `m` on `side`. Forward: p(t') >=
    /// M.lo + S(t') - S(t_j), S the sum of lower displacement bounds;
    /// backward: p(t') >= M.lo - (V(t') - V(t_j)), V the suffix sum of
    /// upper bounds. Mirror for the upper bound of p.
    fn keys(self, m: Interval, side: &Side) -> (f64, f64) {
        match self {
            Way::Forward => (
                add_lo(m.lo(), -side.sum_lo.hi()),
                add_hi(m.hi(), -side.sum_hi.lo()),
            ),
            Way::Backward => (
                add_lo(m.lo(), side.sum_hi.lo()),
                add_hi(m.hi(), side.sum_lo.hi()),
            ),
        }
    }
}

/// The detections of a pass in its order: `order` (by step) walked from
/// its start (forward) or its end (backward) along with the steps.
struct Cursor<'a> {
    order: &'a [usize],
    next: usize,
    way: Way,
}

impl Cursor<'_> {
    /// The next detection of the pass if it is at step `t`.
    fn at(&mut self, mission: &Mission, t: usize) -> Option<usize> {
        let (i, after) = match self.way {
            Way::Forward => (self.next, self.next + 1),
            Way::Backward => (self.next.checked_sub(1)?, self.next - 1),
        };
        let j = *self.order.get(i)?;
        (mission.detections[j].step == t).then(|| {
            self.next = after;
            j
        })
    }
}

/// The keys of every side, for the record.
fn snapshot(sides: &[Side]) -> Vec<[Vec<f64>; 2]> {
    sides
        .iter()
        .map(|s| [s.lower.keys.clone(), s.upper.keys.clone()])
        .collect()
}

/// One relaxed pass over the chain (forward or backward), applying the
/// chain step and the q-relaxed evidence bounds. The forward pass fills
/// `record` (when given); the backward pass merges it. Returns the largest
/// move, or `Err(step)` when a position becomes empty.
fn relaxed_pass(
    mission: &Mission,
    track: &mut Track,
    order: &[usize],
    (proved_false, boxes): Votes,
    keep: usize,
    forward: bool,
    record: &mut Option<Record>,
) -> Result<f64, usize> {
    let way = if forward { Way::Forward } else { Way::Backward };
    let (dim, n) = (track.dim, track.steps);
    let mut sides: Vec<Side> = (0..dim).map(|_| Side::new(keep)).collect();
    let mut moved = 0.0f64;
    if way.forward() {
        if let Some(r) = record.as_mut() {
            *r = Record::default();
            r.lists.push(snapshot(&sides));
        }
    }
    let mut cursor = Cursor {
        order,
        next: if way.forward() { 0 } else { order.len() },
        way,
    };
    for x in 0..=n {
        let t = way.step(x, n);
        let changed_lists = match way.link(t, n) {
            Some(link) => chain_step(track, &mut sides, link, way, keep)?,
            None => false,
        };
        if way.forward() {
            if let Some(r) = record.as_mut() {
                if changed_lists {
                    r.lists.push(snapshot(&sides));
                }
                // The keys of detections before t, and the sums at t.
                r.at.push((r.lists.len() - 1) as u32);
                r.sums.extend(sides.iter().map(|s| (s.sum_lo, s.sum_hi)));
            }
        }
        // Evidence of the detections at step t joins the lists.
        let mut joined = false;
        while let Some(j) = cursor.at(mission, t) {
            let m = &boxes[j];
            if proved_false[j] || m.is_empty() {
                continue;
            }
            joined = true;
            for (a, side) in sides.iter_mut().enumerate() {
                let (key_lo, key_hi) = way.keys(m[a], side);
                side.lower.push(key_lo);
                side.upper.push(-key_hi);
            }
        }
        if way.forward() && joined {
            if let Some(r) = record.as_mut() {
                r.lists.push(snapshot(&sides));
                if r.lists.len() * dim * 2 * keep > RECORD_KEYS {
                    *record = None;
                }
            }
        }
        let m = relaxed_bounds(track, &sides, t, record.as_ref(), way, keep)?;
        moved = moved.max(m);
    }
    Ok(moved)
}

/// The chain step `(s, from, to)` of a relaxed pass: p(to) ∩= p(from) ± D(s),
/// and the running sums of the sides over D(s) (a side restarts when D(s)
/// is unbounded). Returns whether a side restarted; `Err(to)` when p(to)
/// becomes empty.
fn chain_step(
    track: &mut Track,
    sides: &mut [Side],
    (s, from, to): (usize, usize, usize),
    way: Way,
    keep: usize,
) -> Result<bool, usize> {
    let dim = track.dim;
    let mut changed_lists = false;
    for (a, side) in sides.iter_mut().enumerate() {
        let d = track.step[s * dim + a];
        if !d.lo().is_finite() || !d.hi().is_finite() {
            *side = Side::new(keep);
            changed_lists = true;
            continue;
        }
        side.sum_lo = side.sum_lo + Interval::point(d.lo());
        side.sum_hi = side.sum_hi + Interval::point(d.hi());
    }
    for a in 0..dim {
        let q = track.state[from * dim + a];
        let d = track.step[s * dim + a];
        let old = track.state[to * dim + a];
        let new = old.intersect(way.carry(q, d));
        if new.is_empty() {
            return Err(to);
        }
        track.state[to * dim + a] = new;
    }
    Ok(changed_lists)
}

/// The q-relaxed bounds of p(t) from the sides' keys (backward: merged
/// with the forward keys of the detections before t, at the forward sums
/// of step t, from `record`). Returns the largest move; `Err(t)` when p(t)
/// becomes empty.
fn relaxed_bounds(
    track: &mut Track,
    sides: &[Side],
    t: usize,
    record: Option<&Record>,
    way: Way,
    keep: usize,
) -> Result<f64, usize> {
    let dim = track.dim;
    let forward = way.forward();
    let mut moved = 0.0f64;
    for (a, side) in sides.iter().enumerate() {
        let old = track.state[t * dim + a];
        let (mut lo, mut hi) = (old.lo(), old.hi());
        let own = (side.sum_lo, side.sum_hi);
        let (keys, fwd): (&[Vec<f64>; 2], Option<(Interval, Interval)>) = match (record, way) {
            (Some(r), Way::Backward) => (&r.lists[r.at[t] as usize][a], Some(r.sums[t * dim + a])),
            _ => (&NO_KEYS, None),
        };
        let f_lo = |k: f64| fwd.map_or(f64::NEG_INFINITY, |f| lower_at(f, k, true));
        let f_hi = |k: f64| -fwd.map_or(f64::INFINITY, |f| upper_at(f, k, true));
        if let Some(b) = kth_merged(
            &side.lower.keys,
            |k| lower_at(own, k, forward),
            &keys[0],
            f_lo,
            keep,
        ) {
            lo = lo.max(b);
        }
        if let Some(b) = kth_merged(
            &side.upper.keys,
            |k| -upper_at(own, k, forward),
            &keys[1],
            f_hi,
            keep,
        ) {
            hi = hi.min(-b);
        }
        let new = Interval::new(lo, hi);
        if new.is_empty() {
            return Err(t);
        }
        moved = moved.max(shrinkage(old, new));
        track.state[t * dim + a] = new;
    }
    Ok(moved)
}

/// Solves a mission with `max_outliers` = q > 0 (see the module doc): the
/// robust rounds to their fixpoint, then what is proved of the detections
/// kept in every reading ([`super::kept`]): `matching` holds only groups
/// proved whichever detections are false.
pub fn solve_robust(
    mission: &Mission,
    q: usize,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    // The robust rounds know no sensor offset: they read the detections
    // restated from p (sound, see `Mission::seen_from_position`). The
    // ordinary propagations (consensus over subsets, conflict packing, the
    // refinement) read the mission as given: they know the offset, and the
    // restated detections are wider (measured on the woods scenario with
    // 2 false detections: a subset solved at 8.3 m instead of 0.8 m).
    let given = mission;
    let seen = mission.seen_from_p();
    let mission = &*seen;
    let k = mission.detections.len();
    // At most k detections can be dropped: q >= k reads as q = k. (q is an
    // input number, up to u32::MAX, that the mission's size does not bound:
    // nothing below may be sized by it before this cap.)
    let q = q.min(k);
    let mut model = Model::new(mission);
    model.max_outliers = q;
    if let Err(reason) = model.dead_reckoning(mission.final_position.is_some()) {
        return infeasible(model, reason, 0, 0);
    }
    let mut r = Robust::new((mission, given), q, options, model);
    let proof = loop {
        if r.round >= options.max_rounds || cancel.load(Ordering::Relaxed) {
            return r.stopped();
        }
        match r.round_step(progress, cancel) {
            Ok(None) => {}
            Ok(Some(proof)) => break proof,
            Err(reason) => return r.infeasible(reason),
        }
    };
    let proof = match proof {
        Err(reason) => return r.infeasible(reason),
        Ok(Accounted::Open(open)) => return r.finish(SolveStatus::Consistent, Vec::new(), open),
        Ok(Accounted::Kept(p)) => p,
    };
    if r.round >= options.max_rounds {
        let matching = sure_groups(&r.groups, &proof.sure);
        return r.finish(SolveStatus::Consistent, matching, 0);
    }
    let tally = OutlierTally {
        proved_false: proof.proved_false.len(),
        open: 0,
    };
    let mut model = r.model;
    let refined = refine(
        given,
        &mut model,
        &proof,
        options,
        (r.round, r.fraction.min(0.99)),
        progress,
        cancel,
    );
    let (rounds, contractions) = (
        r.round + refined.rounds,
        r.contractions + refined.contractions,
    );
    match refined.status {
        SolveStatus::Infeasible(reason) => infeasible(model, reason, rounds, contractions),
        status => finish(
            model,
            status,
            refined.matching,
            (rounds, contractions),
            tally,
        ),
    }
}

/// An infeasible mission's solution.
fn infeasible(model: Model, reason: String, rounds: u32, contractions: u64) -> Solution {
    Solution {
        status: SolveStatus::Infeasible(reason),
        matching: Vec::new(),
        rounds,
        contractions,
        model,
        outliers: None,
    }
}

/// The state of the robust rounds of one mission (see the module doc).
struct Robust<'a> {
    /// The mission the robust rounds read (the detections seen from p).
    mission: &'a Mission,
    /// The mission as given, for the ordinary propagations.
    given: &'a Mission,
    options: &'a SolveOptions,
    /// Most false detections (at most k).
    q: usize,
    model: Model,
    /// The detection boxes before any round.
    prior: Vec<IntervalBox>,
    /// The operator's groups, or without labels the valid track groups
    /// ([`super::robust_tracks`], odometry2d).
    groups: Vec<Vec<usize>>,
    /// The groups are the operator's.
    operator: bool,
    /// The budget the track groups were built with (they are rebuilt when
    /// more detections are proved false).
    tracks_budget: Option<usize>,
    /// Detections sorted by (step, index).
    order: Vec<usize>,
    ev: Evidence,
    contractions: u64,
    round: u32,
    work: WorkEstimate,
    fraction: f64,
    initial_max_trajectory_diameter: f64,
    /// Consensus over subsets has run (it runs at most once).
    consensus_done: bool,
    /// Pairwise disjoint conflicts of the conflict packing, each holding
    /// one drop of every reading ([`super::robust_conflicts`]).
    conflicts: Vec<Vec<usize>>,
}

impl<'a> Robust<'a> {
    /// After dead reckoning.
    fn new(
        (mission, given): (&'a Mission, &'a Mission),
        q: usize,
        options: &'a SolveOptions,
        model: Model,
    ) -> Robust<'a> {
        let k = mission.detections.len();
        let dim = model.dim;
        let mut order: Vec<usize> = (0..k).collect();
        let dets = &mission.detections;
        crate::sort::sort_indices_by(&mut order, |a, b| dets[a].step.cmp(&dets[b].step));
        let groups = operator_groups(mission);
        Robust {
            mission,
            given,
            options,
            q,
            prior: model.det.clone(),
            operator: !groups.is_empty(),
            tracks_budget: None,
            groups,
            order,
            ev: Evidence {
                proved_false: vec![false; k],
                boxes: vec![IntervalBox::empty(dim); k],
            },
            contractions: 0,
            round: 0,
            work: WorkEstimate::new(k),
            fraction: 0.0,
            initial_max_trajectory_diameter: model.trajectory_diameters().0,
            consensus_done: false,
            conflicts: Vec::new(),
            model,
        }
    }

    /// Consensus over subsets ([`super::robust_subsets`], small q): the
    /// detections proved false and the positions cut to the hull. Returns
    /// how many detections and positions it changed (more rounds follow
    /// when any); `Err`: no reading exists.
    ///
    /// While it runs (28 propagations of three quarters of the mission for
    /// q = 2: minutes on a long mission) the job's progress goes on:
    /// `"association"` reports after each propagation, the fraction moving
    /// over half of what is left below 0.99.
    fn consensus(
        &mut self,
        progress: &mut dyn FnMut(&Progress),
        cancel: &AtomicBool,
    ) -> Result<usize, String> {
        let k = self.mission.detections.len();
        let mut report = Progress {
            round: self.round,
            max_trajectory_diameter: self.model.trajectory_diameters().0,
            fraction: self.fraction,
            pass: "association",
            detections: k,
            detections_done: 0,
            moving: k,
            initial_max_trajectory_diameter: self.initial_max_trajectory_diameter,
        };
        let start = self.fraction.min(0.99);
        let mut tell = |share: f64| {
            report.fraction = report.fraction.max(start + (0.99 - start) * 0.5 * share);
            report.detections_done = (k as f64 * share) as usize;
            progress(&report);
        };
        let told = consensus_told(self.given, self.q, self.options, cancel, &mut tell);
        self.fraction = self.fraction.max(report.fraction);
        let (proved_false, positions, headings, contractions) = match told {
            Consensus::Skipped => return self.packing(cancel),
            Consensus::Infeasible(reason) => return Err(reason),
            Consensus::Proved {
                proved_false,
                positions,
                headings,
                contractions,
                ..
            } => (proved_false, positions, headings, contractions),
        };
        self.contractions += contractions;
        let turned = cut_headings(self.mission, &mut self.model, &headings)?;
        Ok(turned + self.apply(&proved_false, &positions)?)
    }

    /// Conflict packing ([`super::robust_conflicts`], any q): where
    /// consensus over subsets does not apply. As [`Self::consensus`].
    fn packing(&mut self, cancel: &AtomicBool) -> Result<usize, String> {
        let (proved_false, positions, conflicts, contractions) = match pack(
            self.given,
            self.q,
            &self.ev.proved_false,
            &self.order,
            self.options,
            cancel,
        ) {
            Packing::Skipped => return Ok(0),
            Packing::Infeasible(reason) => return Err(reason),
            Packing::Proved {
                proved_false,
                conflicts,
                positions,
                contractions,
                ..
            } => (proved_false, positions, conflicts, contractions),
        };
        self.contractions += contractions;
        let mut changed = conflicts.len();
        self.conflicts = conflicts;
        let positions = positions.unwrap_or_else(|| self.model.pos.clone());
        changed += self.apply(&proved_false, &positions)?;
        Ok(changed)
    }

    /// Marks the detections `proved_false` and cuts the positions to
    /// `positions` (both enclosing every reading); how many changed.
    fn apply(&mut self, proved_false: &[bool], positions: &[Interval]) -> Result<usize, String> {
        let mut changed = 0;
        for (j, &f) in proved_false.iter().enumerate() {
            if f && !self.ev.proved_false[j] {
                changed += 1;
                self.ev.proved_false[j] = true;
                self.model.det[j].set_empty();
            }
        }
        let dim = self.model.dim;
        for (i, (p, h)) in self.model.pos.iter_mut().zip(positions).enumerate() {
            let cut = p.intersect(*h);
            changed += usize::from(cut != *p);
            *p = cut;
            if p.is_empty() {
                return Err(format!(
                    "the position of step {} is empty: no choice of at most {} false detections is consistent",
                    i / dim,
                    self.q
                ));
            }
        }
        Ok(changed)
    }

    fn infeasible(self, reason: String) -> Solution {
        infeasible(self.model, reason, self.round, self.contractions)
    }

    /// The solution with the boxes as they are; `open`: the drops of q
    /// left unaccounted for.
    fn finish(self, status: SolveStatus, matching: Vec<Vec<usize>>, open: usize) -> Solution {
        let tally = OutlierTally {
            proved_false: self.ev.proved_false.iter().filter(|&&f| f).count(),
            open,
        };
        finish(
            self.model,
            status,
            matching,
            (self.round, self.contractions),
            tally,
        )
    }

    /// Stopped (`max_rounds` or cancelled): the boxes are sound, and so is
    /// what they prove.
    fn stopped(self) -> Solution {
        match self.kept_now() {
            Err(reason) => self.infeasible(reason),
            Ok(Accounted::Open(open)) => self.finish(SolveStatus::Stopped, Vec::new(), open),
            Ok(Accounted::Kept(p)) => {
                let matching = sure_groups(&self.groups, &p.sure);
                self.finish(SolveStatus::Stopped, matching, 0)
            }
        }
    }

    /// What the current boxes prove of the detections kept in every
    /// reading ([`kept`]).
    fn kept_now(&self) -> Result<Accounted, String> {
        kept_with_conflicts(
            &self.model.det,
            &self.ev.proved_false,
            &self.conflicts,
            &self.groups,
            self.q,
            self.mission.landmark_count,
        )
    }

    /// One robust round: the evidence gathered, a relaxed pass each way,
    /// the progress told. Ok(Some): the fixpoint, with what the boxes prove
    /// of the detections kept in every reading; Err: infeasible.
    fn round_step(
        &mut self,
        progress: &mut dyn FnMut(&Progress),
        cancel: &AtomicBool,
    ) -> Result<Option<Result<Accounted, String>>, String> {
        let k = self.mission.detections.len();
        let tol = self.options.tolerance.max(0.0);
        self.round += 1;
        let det_before = self.model.det.clone();
        self.track_groups();
        let budget = gather(
            self.mission,
            &mut self.model,
            &self.prior,
            (&self.groups, self.operator),
            self.q,
            &mut self.ev,
        )?;
        self.contractions += 2 * k as u64;
        let mut moved = self.passes(budget)?;
        let mut moving = 0;
        for (a, b) in det_before.iter().zip(&self.model.det) {
            if b.is_empty() {
                continue;
            }
            let mut m = 0.0f64;
            for x in 0..self.model.dim {
                if !a[x].is_empty() {
                    m = m.max(shrinkage(a[x], b[x]));
                }
            }
            moved = moved.max(m);
            moving += usize::from(m > tol);
        }
        if moved > tol {
            // A move of the chain alone still means another round.
            moving = moving.max(1);
        } else {
            moving = 0;
        }
        // At the fixpoint: what the boxes prove of the detections kept in
        // every reading, and whether the refinement on them follows (then
        // this is not the end of the work yet).
        let mut proof = (moved <= tol).then(|| self.kept_now());
        // Consensus over subsets runs once, at the first fixpoint that
        // proves nothing kept (it costs ordinary propagations; the cheap
        // rules and their reasons come first); what it changes is this
        // round's move.
        if matches!(proof, Some(Ok(Accounted::Open(_)))) && !self.consensus_done {
            self.consensus_done = true;
            let changed = self.consensus(progress, cancel)?;
            if changed > 0 {
                (moving, proof) = (changed, None);
            }
        }
        let (max_d, _) = self.model.trajectory_diameters();
        self.fraction = self.fraction.max(self.work.end_round(moving));
        let refines =
            matches!(proof, Some(Ok(Accounted::Kept(_)))) && self.round < self.options.max_rounds;
        progress(&Progress {
            round: self.round,
            max_trajectory_diameter: max_d,
            fraction: if refines {
                self.fraction.min(0.99)
            } else {
                self.fraction
            },
            pass: "round",
            detections: k,
            detections_done: k,
            moving,
            initial_max_trajectory_diameter: self.initial_max_trajectory_diameter,
        });
        Ok(proof)
    }

    /// Without operator labels, on odometry2d: the valid track groups for
    /// the current budget ([`robust_track_groups`]), rebuilt when the
    /// budget fell since they were built (a smaller budget merges more).
    fn track_groups(&mut self) {
        let Some(chain) = self.model.odometry.as_ref() else {
            return;
        };
        let false_count = self.ev.proved_false.iter().filter(|&&f| f).count();
        let budget = self.q.saturating_sub(false_count);
        if self.operator || self.tracks_budget.is_some_and(|b| b <= budget) {
            return;
        }
        let live: Vec<bool> = self.ev.proved_false.iter().map(|&f| !f).collect();
        self.groups =
            robust_track_groups(self.mission, chain, &live, budget, TrackOptions::default());
        self.tracks_budget = Some(budget);
    }

    /// The relaxed passes of a round, forward then backward, with the
    /// (q+1)-th best evidence (`budget` + 1 kept); the largest move.
    fn passes(&mut self, budget: usize) -> Result<f64, String> {
        // odometry2d: the headings first, and the displacements from them
        // ([`super::robust_heading`]), with the same passes on a chain of
        // dimension 1.
        let (mission, order, ev) = (self.mission, &self.order, &self.ev);
        let mut pass =
            |state: &mut [Interval], step: &[Interval], boxes: Vec<IntervalBox>, keep| {
                let mut track = Track {
                    dim: 1,
                    steps: step.len(),
                    state,
                    step,
                };
                relaxed_passes(mission, &mut track, order, (&ev.proved_false, &boxes), keep)
            };
        let turned = robust_heading(mission, &mut self.model, &ev.boxes, budget, &mut pass)?;
        let model = &mut self.model;
        let mut track = Track {
            dim: model.dim,
            steps: model.steps,
            state: &mut model.pos,
            step: &model.disp,
        };
        let votes = (&self.ev.proved_false[..], &self.ev.boxes[..]);
        let moved = relaxed_passes(self.mission, &mut track, &self.order, votes, budget + 1)
            .map_err(|t| {
                format!(
                    "the position of step {t} is empty: no choice of at most {} false detections is consistent",
                    self.q
                )
            })?;
        self.contractions += 2 * self.model.steps as u64;
        Ok(moved.max(turned))
    }
}

/// The solution, its groups proved (members kept in every reading), so
/// that a group's landmark box is the plain intersection of its members'
/// boxes: `max_outliers` of the model is 0 from here on.
fn finish(
    mut model: Model,
    status: SolveStatus,
    matching: Vec<Vec<usize>>,
    (rounds, contractions): (u32, u64),
    tally: OutlierTally,
) -> Solution {
    model.max_outliers = 0;
    Solution {
        status,
        matching,
        rounds,
        contractions,
        model,
        outliers: Some(tally),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    #[test]
    fn top_keys_and_the_merge_match_a_sort() {
        let mut rng = Lcg::new(7);
        for _ in 0..2000 {
            let m = 1 + (rng.bits() % 6) as usize;
            let (na, nb) = ((rng.bits() % 9) as usize, (rng.bits() % 9) as usize);
            let draw = |rng: &mut Lcg| (rng.bits() % 41) as f64 - 20.0;
            let a: Vec<f64> = (0..na).map(|_| draw(&mut rng)).collect();
            let b: Vec<f64> = (0..nb).map(|_| draw(&mut rng)).collect();
            let (mut ta, mut tb) = (TopKeys::new(m), TopKeys::new(m));
            a.iter().for_each(|&x| ta.push(x));
            b.iter().for_each(|&x| tb.push(x));
            // Offsets: a shifted by 0.5, b by -1.25 (exact in binary).
            let got = kth_merged(&ta.keys, |k| k + 0.5, &tb.keys, |k| k - 1.25, m);
            let mut all: Vec<f64> = a
                .iter()
                .map(|k| k + 0.5)
                .chain(b.iter().map(|k| k - 1.25))
                .collect();
            all.sort_by(|x, y| y.total_cmp(x));
            assert_eq!(got, all.get(m - 1).copied(), "{a:?} {b:?} m {m}");
        }
    }

    #[test]
    fn relaxed_intersection_holds_every_point_in_all_but_q_boxes() {
        let mut rng = Lcg::new(3);
        for _ in 0..2000 {
            let count = 1 + (rng.bits() % 6) as usize;
            let q = (rng.bits() % 3) as usize;
            let boxes: Vec<IntervalBox> = (0..count)
                .map(|_| {
                    let lo = (rng.bits() % 10) as f64;
                    let w = (rng.bits() % 6) as f64;
                    IntervalBox::new(&[Interval::new(lo, lo + w)])
                })
                .collect();
            let refs: Vec<&IntervalBox> = boxes.iter().collect();
            let r = relaxed_intersection(&refs, q, 1);
            for x in 0..=32 {
                let x = x as f64 * 0.5;
                let inside = boxes.iter().filter(|b| b[0].contains(x)).count();
                if inside + q >= count {
                    assert!(r[0].contains(x), "{x} in {inside} of {count}, q {q}: {r:?}");
                }
            }
        }
    }
}
