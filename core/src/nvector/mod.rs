//! The nvector global constraint atmost_nvector(n, {d(1)..d(k)}) and its
//! contractors (Chabert, Jaulin, Lorca, CP 2009).
//!
//! [`atmost_nvector`] runs one of the contractors of [`Contractor`] to a fixpoint:
//! - `nvalue` ([`nvalue`]): atmost_nvalue on each axis projection (an
//!   axis needs at most n values when the vectors are at most n).
//! - `projection` (paper, section 5): when an axis needs exactly n values,
//!   the map from vectors to their values on that axis is a bijection, so the
//!   boxes of a group on that axis are equal *as vectors*: whole boxes are
//!   intersected. Iterated over the axes.
//! - `independent` ([`independent`]): pairwise-disjoint witnesses in full
//!   dimension, with `projection`.
//! - `exact` ([`hitting_set`]): exact bound consistency, k <= 40.
//! - `shapes`: in SLAM, `best` plus the detection shapes of
//!   [`crate::shapes`] (annuli and sectors instead of their hulls); on
//!   plain boxes there are no shapes, and it acts as `best`.
//!
//! Groups are proved equalities, merged across axes and rounds with a
//! union-find (equality is transitive and a sound contraction keeps every
//! solution, so a proof made at any round holds for the input boxes).

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::union_find::Uf;
use error::ContractError;
use hitting_set::Limits;
use independent::IndependentScratch;
use nvalue::{NValue, NValueScratch};

pub mod contract;
pub mod error;
pub mod hitting_set;
pub mod independent;
pub mod nvalue;

/// Which contractor enforces atmost_nvector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Contractor {
    /// atmost_nvalue on each axis projection independently (paper, section 5).
    Nvalue,
    /// `Nvalue` plus whole-box intersection of groups, to a fixpoint.
    Projection,
    /// `Projection` plus pairwise-disjoint witnesses in full dimension.
    Independent,
    /// Exact bound consistency (exponential, k <= 40).
    Exact,
    /// The strongest polynomial contractor.
    Best,
    /// Detection shapes (SLAM only, `crate::shapes`); on plain boxes, as
    /// `Best`.
    Shapes,
}

impl Contractor {
    /// Every contractor, in the order of the spec.
    pub const ALL: [Contractor; 6] = [
        Contractor::Nvalue,
        Contractor::Projection,
        Contractor::Independent,
        Contractor::Exact,
        Contractor::Shapes,
        Contractor::Best,
    ];

    /// Parses the spec's name (`"nvalue"`, `"projection"`, ...).
    pub fn parse(s: &str) -> Option<Contractor> {
        Some(match s {
            "nvalue" => Contractor::Nvalue,
            "projection" => Contractor::Projection,
            "independent" => Contractor::Independent,
            "exact" => Contractor::Exact,
            "best" => Contractor::Best,
            "shapes" => Contractor::Shapes,
            _ => return None,
        })
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Contractor::Nvalue => "nvalue",
            Contractor::Projection => "projection",
            Contractor::Independent => "independent",
            Contractor::Exact => "exact",
            Contractor::Best => "best",
            Contractor::Shapes => "shapes",
        }
    }
}

/// The OpenAPI schema of a contractor: its spec names (the `contractor`
/// of a contraction request).
#[cfg(feature = "openapi")]
impl utoipa::PartialSchema for Contractor {
    fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
        use utoipa::openapi::schema::{ObjectBuilder, Type};
        ObjectBuilder::new()
            .schema_type(Type::String)
            .enum_values(Some(Contractor::ALL.map(Contractor::name)))
            .description(Some(
                "A box contractor of atmost_nvector: nvalue (atmost_nvalue on each axis, \
                 the paper's naive one), projection (the paper's improved one), independent \
                 (pairwise-disjoint witnesses, with projection), exact (bound consistency; \
                 exponential, k <= 40, bounded work), shapes (the detection shapes in SLAM; \
                 on plain boxes, as best), best (the strongest polynomial one).",
            ))
            .into()
    }
}

#[cfg(feature = "openapi")]
impl utoipa::ToSchema for Contractor {}

/// What a contraction proved.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Some box shrank.
    Contracted,
    /// Nothing could be removed.
    Unchanged,
    /// The constraint has no solution in the boxes (they are all emptied).
    Infeasible {
        /// Why, e.g. "axis 0 needs at least 3 distinct values, n = 2".
        reason: String,
    },
}

/// Result of one atmost_nvector contraction.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Contracted, unchanged or infeasible.
    pub status: Status,
    /// Partition of the box indices into sets proved equal (singletons
    /// included), each sorted, listed by smallest index.
    pub groups: Vec<Vec<usize>>,
    /// Proved lower bound on the minimum number of distinct vectors.
    pub min_distinct_lower: usize,
    /// Size of a hitting set found (an upper bound of that minimum).
    pub min_distinct_upper: usize,
    /// Passes over the axes / fixpoint rounds.
    pub rounds: u32,
    /// The fixpoint stopped at its round cap ([`Limits::max_rounds`],
    /// default [`MAX_ROUNDS`]) with work pending: the boxes are sound but
    /// another round might contract them further.
    pub stopped_early: bool,
}

pub use hitting_set::MAX_ROUNDS;

/// The groups proved so far: the crate's one union-find
/// ([`crate::union_find::Uf`], smallest index as root) with the count of
/// unions done. The fixpoint reads the roots as `u32`, like its scratch
/// arrays (box indices below 2^32, as throughout this module).
struct Groups {
    uf: Uf,
    /// Unions done (0: every group is a singleton).
    merged: usize,
}

impl Groups {
    fn new(k: usize) -> Groups {
        Groups {
            uf: Uf::new(k),
            merged: 0,
        }
    }

    /// The root (smallest member) of each index's group, into `out`.
    fn roots_into(&mut self, out: &mut Vec<u32>) {
        out.clear();
        for i in 0..self.uf.len() as u32 {
            let r = self.find(i);
            out.push(r);
        }
    }

    fn find(&mut self, i: u32) -> u32 {
        self.uf.find(i as usize) as u32
    }

    /// Merges; returns whether the two were apart.
    fn union(&mut self, a: u32, b: u32) -> bool {
        if self.find(a) == self.find(b) {
            return false;
        }
        self.uf.union(a as usize, b as usize);
        self.merged += 1;
        true
    }

    /// The partition: sorted members, groups ordered by smallest index.
    fn partition(&mut self) -> Vec<Vec<usize>> {
        let k = self.uf.len();
        let mut slot = vec![usize::MAX; k];
        let mut out: Vec<Vec<usize>> = Vec::new();
        for i in 0..k {
            let r = self.uf.find(i);
            if slot[r] == usize::MAX {
                slot[r] = out.len();
                out.push(Vec::new());
            }
            out[slot[r]].push(i);
        }
        out
    }
}

/// Intersects the boxes of every group of size >= 2; returns whether any
/// box changed. Works axis by axis on flat bound arrays (no box clones).
/// Marks in `dirty` the axes on which a bound moved.
fn intersect_groups(
    boxes: &mut [IntervalBox],
    groups: &mut Groups,
    common: &mut Vec<Interval>,
    dirty: &mut [bool],
    axes: Option<usize>,
) -> bool {
    let k = boxes.len();
    let roots: Vec<u32> = (0..k as u32).map(|i| groups.find(i)).collect();
    if roots.iter().enumerate().all(|(i, &r)| r == i as u32) {
        return false;
    }
    let dim = boxes[0].dim();
    let mut changed = false;
    let (from, to) = axes.map_or((0, dim), |a| (a, a + 1));
    for axis in from..to {
        common.clear();
        common.resize(k, Interval::ENTIRE);
        for (b, &r) in boxes.iter().zip(&roots) {
            let c = &mut common[r as usize];
            *c = c.intersect(b[axis]);
        }
        for (b, &r) in boxes.iter_mut().zip(&roots) {
            let c = common[r as usize];
            if b[axis] != c {
                b[axis] = c;
                changed = true;
                dirty[axis] = true;
            }
        }
    }
    if changed {
        for b in boxes.iter_mut() {
            if b.is_empty() {
                b.set_empty();
            }
        }
    }
    changed
}

/// An upper bound of the minimum number of distinct vectors: the size of a
/// hitting set built greedily (each box joins the first cell it meets, the
/// cell shrinking to the intersection; a point of each cell hits its boxes).
/// The boxes are first copied, in order, to a flat array by a loop of
/// independent loads (the memory system overlaps them), so the greedy
/// itself reads sequentially. Only the boxes listed in `members` are used
/// (one per group when the groups' boxes are equal: a point hitting one
/// hits all). O(k log k + 8 k d).
fn greedy_hitting_set(boxes: &[IntervalBox], members: &[u32]) -> usize {
    let dim = boxes[0].dim();
    let mut order = Vec::new();
    crate::radix::sort_indices(
        members.len(),
        |i| boxes[members[i] as usize][0].hi(),
        &mut order,
        &mut crate::radix::RadixScratch::default(),
    );
    let mut sorted: Vec<Interval> = Vec::with_capacity(members.len() * dim);
    for &i in &order {
        sorted.extend_from_slice(boxes[members[i as usize] as usize].axes());
    }
    // Cells visited last are the likeliest to meet the next box (boxes come
    // by increasing upper bound on axis 0): only the 8 most recent are tried.
    let mut cells: Vec<Interval> = Vec::new();
    for b in sorted.chunks_exact(dim) {
        let start = cells.len().saturating_sub(8 * dim);
        let hit = cells[start..]
            .rchunks_exact_mut(dim)
            .find(|c| c.iter().zip(b).all(|(x, y)| x.meets(*y)));
        if let Some(c) = hit {
            for (x, y) in c.iter_mut().zip(b) {
                *x = x.intersect(*y);
            }
        } else {
            cells.extend_from_slice(b);
        }
    }
    cells.len() / dim
}

fn infeasible(boxes: &mut [IntervalBox], reason: String, lower: usize, rounds: u32) -> Outcome {
    let k = boxes.len();
    for b in boxes.iter_mut() {
        b.set_empty();
    }
    Outcome {
        status: Status::Infeasible { reason },
        groups: (0..k).map(|i| vec![i]).collect(),
        min_distinct_lower: lower,
        min_distinct_upper: k,
        rounds,
        stopped_early: false,
    }
}

/// Contracts `boxes` (all of one dimension) under atmost_nvector(n, boxes)
/// with the contractor `mode`, to a fixpoint. Never removes a vector tuple
/// satisfying the constraint. Errors: n = 0, boxes of different dimensions
/// or of dimension 0, `exact` with more than 40 boxes, and `exact` out of
/// its default work budget (as an `InputError` naming the limit; see
/// [`atmost_nvector_with`] for a distinct error and a cancellation flag).
pub fn atmost_nvector(
    n: usize,
    boxes: &mut [IntervalBox],
    mode: Contractor,
) -> Result<Outcome, InputError> {
    atmost_nvector_with(n, boxes, mode, &Limits::default()).map_err(InputError::from)
}

/// [`atmost_nvector`] with limits ([`Limits`]): the fixpoint's round cap,
/// and the work of `exact` (node budget and cancellation flag); out of the
/// latter, it answers [`ContractError::Limit`], the boxes holding what the
/// polynomial passes proved (sound, not exact).
pub fn atmost_nvector_with(
    n: usize,
    boxes: &mut [IntervalBox],
    mode: Contractor,
    limits: &Limits,
) -> Result<Outcome, ContractError> {
    contract(n, boxes, mode, true, limits)
}

/// The input checks of [`contract`]: an error for n = 0, boxes of
/// dimension 0 or of different dimensions, `exact` past its box limit.
fn check_input(n: usize, boxes: &[IntervalBox], mode: Contractor) -> Result<(), ContractError> {
    if n == 0 {
        return Err(InputError::new("n", "n must be at least 1").into());
    }
    let Some(first) = boxes.first() else {
        return Ok(());
    };
    let dim = first.dim();
    if dim == 0 {
        return Err(InputError::new("boxes[0]", "a box needs at least one axis").into());
    }
    if let Some(i) = boxes.iter().position(|b| b.dim() != dim) {
        return Err(InputError::new(
            format!("boxes[{i}]"),
            format!(
                "expected a box of dimension {dim} like boxes[0], found {} axes",
                boxes[i].dim()
            ),
        )
        .into());
    }
    let k = boxes.len();
    if mode == Contractor::Exact && k > hitting_set::MAX_K {
        return Err(InputError::new(
            "boxes",
            format!(
                "the exact contractor is exponential and accepts at most {} boxes, found {k}",
                hitting_set::MAX_K
            ),
        )
        .into());
    }
    Ok(())
}

/// [`atmost_nvector`], with the per-group atmost_nvalue passes allowed or
/// not (tests check both give the same bits): the fixpoint of the axis
/// passes and the witness pass ([`Run`]), then the exact stage.
fn contract(
    n: usize,
    boxes: &mut [IntervalBox],
    mode: Contractor,
    by_group_passes: bool,
    limits: &Limits,
) -> Result<Outcome, ContractError> {
    check_input(n, boxes, mode)?;
    if boxes.is_empty() {
        return Ok(Outcome {
            status: Status::Unchanged,
            groups: Vec::new(),
            min_distinct_lower: 0,
            min_distinct_upper: 0,
            rounds: 0,
            stopped_early: false,
        });
    }
    if let Some(i) = boxes.iter().position(|b| b.is_empty()) {
        return Ok(infeasible(boxes, format!("box {i} is empty"), 0, 0));
    }
    let mut run = Run::new(n, boxes, mode, by_group_passes);
    let mut stopped_early;
    loop {
        run.rounds += 1;
        for axis in 0..run.dim {
            if let Some(out) = run.axis_pass(axis) {
                return Ok(out);
            }
        }
        if run.with_witnesses && run.witness_dirty {
            if let Some(out) = run.witness_pass() {
                return Ok(out);
            }
        }
        let pending = run.dirty.iter().any(|&d| d) || (run.with_witnesses && run.witness_dirty);
        if !pending || run.rounds >= limits.max_rounds {
            stopped_early = pending;
            break;
        }
    }
    if !run.whole_boxes {
        if let Some(reason) = run.group_without_common_point() {
            let lower = run.lower;
            return Ok(run.infeasible(reason, lower));
        }
    }
    let mut upper = run.hitting_set_upper().max(run.lower);
    if mode == Contractor::Exact {
        if let Some(out) = run.exact(limits, &mut upper)? {
            return Ok(out);
        }
        // Exact bound consistency: no round left could contract further.
        stopped_early = false;
    }
    let status = if run.contracted {
        Status::Contracted
    } else {
        Status::Unchanged
    };
    Ok(Outcome {
        status,
        groups: run.groups.partition(),
        min_distinct_lower: run.lower.min(upper),
        min_distinct_upper: upper,
        rounds: run.rounds,
        stopped_early,
    })
}

/// The state of one contraction's fixpoint: the boxes, the groups proved
/// equal, the bounds on the minimum number of distinct vectors, which axes
/// and whether the witness pass have work pending, and the scratch space
/// the passes reuse.
struct Run<'a> {
    n: usize,
    boxes: &'a mut [IntervalBox],
    k: usize,
    dim: usize,
    by_group_passes: bool,
    /// Not `nvalue`: groups are intersected as whole boxes.
    whole_boxes: bool,
    /// `independent`, `best`, `shapes`, `exact`: the witness pass runs.
    with_witnesses: bool,
    /// Whether a box moved (contractions are monotone: a box that moved
    /// differs from its input).
    contracted: bool,
    groups: Groups,
    lower: usize,
    rounds: u32,
    /// Axes whose bounds moved since their last atmost_nvalue pass (the
    /// pass is idempotent: bound consistency).
    dirty: Vec<bool>,
    /// Whether anything moved since the last witness pass.
    witness_dirty: bool,
    nv: NValueScratch,
    ind: IndependentScratch,
    domains: Vec<Interval>,
    roots: Vec<u32>,
    reps: Vec<u32>,
    rep_slot: Vec<u32>,
    sole: Vec<u32>,
    common: Vec<Interval>,
}

impl<'a> Run<'a> {
    fn new(
        n: usize,
        boxes: &'a mut [IntervalBox],
        mode: Contractor,
        by_group_passes: bool,
    ) -> Run<'a> {
        let k = boxes.len();
        let dim = boxes[0].dim();
        Run {
            n,
            k,
            dim,
            boxes,
            by_group_passes,
            whole_boxes: mode != Contractor::Nvalue,
            with_witnesses: matches!(
                mode,
                Contractor::Independent | Contractor::Best | Contractor::Shapes | Contractor::Exact
            ),
            contracted: false,
            groups: Groups::new(k),
            lower: 1,
            rounds: 0,
            dirty: vec![true; dim],
            witness_dirty: true,
            nv: NValueScratch::default(),
            ind: IndependentScratch::default(),
            domains: Vec::with_capacity(k),
            roots: Vec::new(),
            reps: Vec::new(),
            rep_slot: Vec::new(),
            sole: Vec::new(),
            common: Vec::with_capacity(k),
        }
    }

    /// The boxes emptied, with `reason`: the infeasible outcome.
    fn infeasible(&mut self, reason: String, lower: usize) -> Outcome {
        infeasible(self.boxes, reason, lower, self.rounds)
    }

    /// `nvalue` proves groups (one kernel on an axis with n values) but
    /// does not intersect their boxes: a group whose members have no
    /// common point is a proof of infeasibility, which it would otherwise
    /// report as "unchanged" with that group (boxes proved to take one
    /// vector that they cannot share). The reason names the first member
    /// and the one that empties the common box. O(k d).
    fn group_without_common_point(&mut self) -> Option<String> {
        let k = self.boxes.len();
        let roots: Vec<u32> = (0..k as u32).map(|i| self.groups.find(i)).collect();
        if roots.iter().enumerate().all(|(i, &r)| r == i as u32) {
            return None;
        }
        let mut first = vec![u32::MAX; k];
        for axis in 0..self.dim {
            let mut common = vec![Interval::ENTIRE; k];
            for (i, (b, &r)) in self.boxes.iter().zip(&roots).enumerate() {
                let r = r as usize;
                if first[r] == u32::MAX {
                    first[r] = i as u32;
                }
                common[r] = common[r].intersect(b[axis]);
                if common[r].is_empty() {
                    return Some(format!(
                        "boxes {} and {i} are proved to take one vector, but their group has no common point on axis {axis}",
                        first[r]
                    ));
                }
            }
        }
        None
    }

    /// Fills `domains` with the boxes' intervals on `axis`: one per group
    /// when the pass may run on one member per group (returns true), else
    /// one per box.
    fn fill_domains(&mut self, axis: usize) -> bool {
        let k = self.k;
        // The boxes of a group are equal (intersected) in the whole-box
        // modes: atmost_nvalue over one representative per group gives
        // the same minimum, kernels and pruning as over all of them
        // (duplicates are stabbed by the same points and pruned alike),
        // at the cost of the number of groups. Checked, not assumed.
        self.domains.clear();
        let by_group = self.by_group_passes && self.whole_boxes && self.groups.merged > 0 && {
            self.groups.roots_into(&mut self.roots);
            let boxes = &*self.boxes;
            boxes
                .iter()
                .zip(&self.roots)
                .all(|(b, &r)| b[axis] == boxes[r as usize][axis])
        };
        if by_group {
            self.reps.clear();
            self.rep_slot.clear();
            self.rep_slot.resize(k, u32::MAX);
            for (i, &r) in self.roots.iter().enumerate() {
                if r == i as u32 {
                    self.rep_slot[i] = self.reps.len() as u32;
                    self.reps.push(r);
                }
            }
            let boxes = &*self.boxes;
            self.domains
                .extend(self.reps.iter().map(|&r| boxes[r as usize][axis]));
        } else {
            self.domains.extend(self.boxes.iter().map(|b| b[axis]));
        }
        by_group
    }

    /// The atmost_nvalue pass on `axis` when its bounds moved since the
    /// last one; then the groups intersected. `Some` when infeasible.
    fn axis_pass(&mut self, axis: usize) -> Option<Outcome> {
        if !self.dirty[axis] {
            return None;
        }
        self.dirty[axis] = false;
        let n = self.n;
        let by_group = self.fill_domains(axis);
        let mut grew = false;
        let mut moved = false;
        match nvalue::atmost_nvalue(n, &mut self.domains, &mut self.nv) {
            NValue::Infeasible { m } => {
                let reason = format!("axis {axis} needs at least {m} distinct values, n = {n}");
                return Some(self.infeasible(reason, m));
            }
            NValue::Slack { m } => self.lower = self.lower.max(m),
            NValue::Kernels { changed } => {
                self.lower = self.lower.max(n);
                if changed {
                    self.witness_dirty = true;
                    moved = true;
                    self.contracted = true;
                    if by_group {
                        for (b, &r) in self.boxes.iter_mut().zip(&self.roots) {
                            b[axis] = self.domains[self.rep_slot[r as usize] as usize];
                        }
                    } else {
                        for (b, &x) in self.boxes.iter_mut().zip(self.domains.iter()) {
                            b[axis] = x;
                        }
                    }
                }
                // Boxes meeting one kernel on this axis share its value,
                // hence (m = n) the same vector.
                let mut first_of = vec![u32::MAX; self.nv.kernels.len()];
                for (i, &g) in self.nv.group_of.iter().enumerate() {
                    if g == u32::MAX {
                        continue;
                    }
                    let i = if by_group { self.reps[i] as usize } else { i };
                    let f = &mut first_of[g as usize];
                    if *f == u32::MAX {
                        *f = i as u32;
                    } else {
                        grew |= self.groups.union(*f, i as u32);
                    }
                }
            }
        }
        // Members of a group are equal: intersect them on every axis
        // when groups grew, else only on this axis when it moved (the
        // other axes were intersected when the groups last changed), and
        // not at all when the pass ran on one member per group.
        let axes = if grew {
            Some(None)
        } else if moved && !by_group {
            Some(Some(axis))
        } else {
            None
        };
        if let (true, Some(axes)) = (self.whole_boxes, axes) {
            if intersect_groups(
                self.boxes,
                &mut self.groups,
                &mut self.common,
                &mut self.dirty,
                axes,
            ) {
                self.witness_dirty = true;
                self.contracted = true;
            }
        }
        if let Some(i) = self.boxes.iter().position(|b| b.is_empty()) {
            let reason = format!("box {i} emptied on axis {axis}: its group has no common vector");
            return Some(self.infeasible(reason, self.lower));
        }
        None
    }

    /// The witness pass: pairwise disjoint boxes are distinct vectors;
    /// with n of them, every box takes a witness's vector. `Some` when
    /// infeasible.
    fn witness_pass(&mut self) -> Option<Outcome> {
        let n = self.n;
        self.witness_dirty = false;
        let witnesses = independent::find_independent(n, self.boxes, &mut self.ind);
        self.lower = self.lower.max(witnesses.len());
        if witnesses.len() > n {
            let list: Vec<String> = witnesses.iter().map(|w| w.to_string()).collect();
            let reason = format!(
                "boxes {} are pairwise disjoint: at least {} distinct vectors, n = {n}",
                list.join(", "),
                witnesses.len()
            );
            return Some(self.infeasible(reason, witnesses.len()));
        }
        if witnesses.len() == n {
            let mut changed =
                independent::contract_with_witnesses(self.boxes, &witnesses, &mut self.sole);
            for (i, &w) in self.sole.iter().enumerate() {
                if w != u32::MAX {
                    self.groups.union(w, i as u32);
                }
            }
            if changed {
                self.dirty.iter_mut().for_each(|d| *d = true);
            }
            changed |= intersect_groups(
                self.boxes,
                &mut self.groups,
                &mut self.common,
                &mut self.dirty,
                None,
            );
            self.contracted |= changed;
            self.witness_dirty = changed;
            if let Some(i) = self.boxes.iter().position(|b| b.is_empty()) {
                let reason = format!("box {i} meets no witness of the {n} distinct vectors");
                return Some(self.infeasible(reason, self.lower));
            }
        }
        None
    }

    /// The size of a hitting set found greedily: over one member per group
    /// when every group's boxes are equal (always after `projection`),
    /// else over every box.
    fn hitting_set_upper(&mut self) -> usize {
        self.groups.roots_into(&mut self.roots);
        let boxes = &*self.boxes;
        let equal = boxes
            .iter()
            .zip(&self.roots)
            .all(|(b, &r)| *b == boxes[r as usize]);
        let roots = &self.roots;
        let members: Vec<u32> = if equal {
            (0..self.k as u32)
                .filter(|&i| roots[i as usize] == i)
                .collect()
        } else {
            (0..self.k as u32).collect()
        };
        greedy_hitting_set(boxes, &members)
    }

    /// The exact stage: the minimum hitting set and bound consistency,
    /// within `limits` (out of them, an error and no box changed). Sets
    /// both bounds to the minimum; `Some` when infeasible.
    fn exact(
        &mut self,
        limits: &Limits,
        upper: &mut usize,
    ) -> Result<Option<Outcome>, ContractError> {
        let (n, k) = (self.n, self.k);
        let snapshot = self.boxes.to_vec();
        let mut hs = hitting_set::HittingSet::with_limits(&snapshot, limits)?;
        let all = hs.all();
        let m = hs.min_cover(all)?;
        if m > n {
            let reason = format!(
                "the boxes need at least {m} distinct vectors (minimum hitting set), n = {n}"
            );
            return Ok(Some(self.infeasible(reason, m)));
        }
        self.lower = m;
        *upper = m;
        // All bounds first: out of budget midway, no box has changed.
        let exact: Vec<IntervalBox> = (0..k)
            .map(|i| hs.consistent_box(n, i))
            .collect::<Result<_, _>>()?;
        self.boxes.clone_from_slice(&exact);
        self.contracted |= self.boxes.iter().zip(&snapshot).any(|(a, b)| a != b);
        if let Some(i) = self.boxes.iter().position(|b| b.is_empty()) {
            let reason = format!("box {i} has no consistent value");
            return Ok(Some(self.infeasible(reason, self.lower)));
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b2(x0: f64, x1: f64, y0: f64, y1: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x0, x1), Interval::new(y0, y1)])
    }

    /// n = 2: axis 0 groups boxes 0 and 1, axis 1 groups 0 and 2, so the
    /// three take one vector, which boxes 1 and 2 (disjoint) cannot. The
    /// naive contractor reported "unchanged" with the group [0, 1, 2];
    /// every mode now proves it infeasible, and a group whose members meet
    /// is still reported as before.
    #[test]
    fn nvalue_groups_without_a_common_point_are_infeasible() {
        for mode in [Contractor::Nvalue, Contractor::Projection, Contractor::Best] {
            let mut boxes = vec![
                b2(0.0, 1.0, 0.0, 1.0),
                b2(0.0, 1.0, 2.0, 3.0),
                b2(2.0, 3.0, 0.0, 1.0),
            ];
            let out = atmost_nvector(2, &mut boxes, mode).unwrap();
            assert!(
                matches!(out.status, Status::Infeasible { .. }),
                "{mode:?}: {out:?}"
            );
            assert!(boxes.iter().all(|b| b.is_empty()), "{mode:?}");
        }
        // Boxes 0 and 1 meet: the same group, no contradiction.
        let mut boxes = vec![
            b2(0.0, 1.0, 0.0, 1.0),
            b2(0.5, 1.0, 0.0, 3.0),
            b2(2.0, 3.0, 2.0, 3.0),
        ];
        let out = atmost_nvector(2, &mut boxes, Contractor::Nvalue).unwrap();
        assert!(!matches!(out.status, Status::Infeasible { .. }), "{out:?}");
        assert_eq!(out.groups, vec![vec![0, 1], vec![2]]);
    }

    #[test]
    fn spec_example() {
        // The contract example of docs/formats.md.
        for mode in [
            Contractor::Nvalue,
            Contractor::Projection,
            Contractor::Independent,
            Contractor::Exact,
            Contractor::Best,
            Contractor::Shapes,
        ] {
            let mut boxes = vec![
                b2(0.0, 2.0, 0.0, 2.0),
                b2(1.0, 3.0, 1.0, 3.0),
                b2(5.0, 6.0, 5.0, 6.0),
            ];
            let out = atmost_nvector(2, &mut boxes, mode).unwrap();
            assert_eq!(out.status, Status::Contracted, "{mode:?}");
            assert_eq!(boxes[0], b2(1.0, 2.0, 1.0, 2.0));
            assert_eq!(boxes[1], b2(1.0, 2.0, 1.0, 2.0));
            assert_eq!(boxes[2], b2(5.0, 6.0, 5.0, 6.0));
            assert_eq!(out.groups, vec![vec![0, 1], vec![2]]);
            assert_eq!((out.min_distinct_lower, out.min_distinct_upper), (2, 2));
        }
    }

    /// The passes over one member per group change nothing but the time:
    /// same boxes, groups, bounds and status as passes over every box, on
    /// clustered instances (groups form), overlapping ones (straddlers)
    /// and infeasible ones.
    #[test]
    fn passes_over_groups_give_the_same_bits() {
        let mut rng = crate::test_rng::Lcg::new(0xC0FFEE);
        let mut next = || rng.unit();
        for case in 0..300 {
            let dim = 1 + case % 3;
            let clusters = 1 + case % 6;
            let k = 2 + (case * 7) % 40;
            let spread = [0.5, 3.0, 6.0][case % 3];
            let centres: Vec<Vec<f64>> = (0..clusters)
                .map(|j| (0..dim).map(|_| j as f64 * 10.0 * next()).collect())
                .collect();
            let boxes: Vec<IntervalBox> = (0..k)
                .map(|i| {
                    let c = &centres[i % clusters];
                    let axes: Vec<Interval> = c
                        .iter()
                        .map(|&x| {
                            let (a, b) = (
                                (next() * 4.0 * spread).floor() / 4.0,
                                (next() * 4.0 * spread).floor() / 4.0,
                            );
                            Interval::new(x - a, x + b)
                        })
                        .collect();
                    IntervalBox::new(&axes)
                })
                .collect();
            for n in [clusters.saturating_sub(1).max(1), clusters, clusters + 1] {
                for mode in [
                    Contractor::Projection,
                    Contractor::Independent,
                    Contractor::Best,
                ] {
                    let (mut a, mut b) = (boxes.clone(), boxes.clone());
                    let limits = Limits::default();
                    let fast = contract(n, &mut a, mode, true, &limits).unwrap();
                    let slow = contract(n, &mut b, mode, false, &limits).unwrap();
                    assert_eq!(a, b, "case {case} n {n} {mode:?}");
                    assert_eq!(fast.status, slow.status, "case {case} n {n} {mode:?}");
                    assert_eq!(fast.groups, slow.groups, "case {case} n {n} {mode:?}");
                    assert_eq!(
                        (fast.min_distinct_lower, fast.min_distinct_upper),
                        (slow.min_distinct_lower, slow.min_distinct_upper),
                        "case {case} n {n} {mode:?}"
                    );
                }
            }
        }
    }
}
