//! Conflict packing: disjoint conflicts found by the ordinary (q = 0)
//! propagation account for `max_outliers`, and detections proved false
//! against the rest (`max_outliers` = q > 0, any q; docs/outliers.md,
//! "Conflict packing"). Reiter's diagnosis (1987): conflict sets and
//! their hitting sets, the conflicts shrunk by a deletion filter.
//!
//! # Constraint
//!
//! A *reading* drops at most q detections (docs/formats.md); every box
//! must enclose every solution of every reading, and a detection is
//! *proved false* when no reading with a solution keeps it. Detections
//! already proved false (the set P) are dropped in every reading, so the
//! others see a budget b = q - |P|.
//!
//! # Math
//!
//! 1. *Relaxation* (as in [`crate::slam::robust::subsets`]): for a set S, the
//!    mission `stripped(S)` ([`crate::slam::robust::kept::stripped`]) with q = 0 is a
//!    relaxation of every reading keeping all of S; its ordinary
//!    propagation proving it infeasible proves that no reading with a
//!    solution keeps all of S. Such an S is a *conflict*.
//! 2. *Shrinking* (deletion filter, "progression"): from an infeasible set
//!    T in time order, C starts empty; while `stripped(C)` is not proved
//!    infeasible, bisect for the shortest prefix T[..=i] with C ∪ T[..=i]
//!    proved infeasible, add T[i] to C and keep T[..i]. The invariant
//!    (C ∪ T proved infeasible) holds; the result is a conflict because
//!    its own infeasibility is the loop's exit test, whatever the
//!    bisection found (propagation need not be monotone: only the final
//!    test is relied on).
//! 3. *Packing.* Greedily: R = every detection outside P; while
//!    `stripped(R)` is infeasible, shrink a conflict C(i) out of R and
//!    remove it from R. The conflicts are pairwise disjoint, and every
//!    reading with a solution drops at least one detection of each, so at
//!    least m = their count: m > b proves that no reading exists. When m =
//!    b, a reading drops exactly one detection of each conflict and
//!    nothing else: every detection of N' = R is kept in every reading
//!    (*certain*), and the propagation of `stripped(N')` encloses every
//!    position of every reading.
//! 4. *Resolution.* Let q' = b - m (drops not accounted for). A reading
//!    keeping a detection x of a conflict C(i) still drops one detection of
//!    C(i) \ {x} and of every other conflict, so at most q' of N': it keeps
//!    whole one set of the family F = {N'} when q' = 0, else N' dealt in
//!    time order into q' + 3 blocks, every set leaving q' blocks out
//!    (C(q' + 3, q') = 4, 10, 20 sets for q' = 1, 2, 3; none above 3).
//!    When `stripped(S ∪ {x})` is proved infeasible for every S of F, x is
//!    proved false: it leaves the budget (b - 1), C(i) is resolved (its
//!    other detections, no longer counted, rejoin N'), and the packing
//!    goes on from step 3 (N' grew, perhaps with false detections that
//!    make new conflicts), to a fixpoint. Conflicts plus proved false
//!    beyond the budget: no reading exists.
//!
//! 0. *Free conflicts* (ids hidden, `landmark_count` n): the
//!    (n + 1)-cliques of pairwise distinct detections
//!    ([`crate::slam::robust::cliques`]) are conflicts found without a
//!    propagation; what their hitting sets prove comes first, and when
//!    there are any the disjoint packing (steps 3-4) is not run: step 5
//!    starts from them. Every conflict test propagates the tested
//!    detections only ([`crate::slam::robust::kept::kept_only`], a relaxation of
//!    `stripped`).
//! 5. *Overlapping conflicts* (`State::hit`, when the packing does not
//!    account for the budget): conflicts may share detections; their
//!    minimum hitting set ([`crate::slam::robust::hitting`], exact) bounds every
//!    reading's drops, and a detection in every hitting set of at most b
//!    is proved false (docs/outliers.md, "Overlapping conflicts"). At
//!    most [`HIT_SOLVES`] propagations, within [`HIT_WORK`].
//!
//! What is returned: the detections proved false; the unresolved
//! conflicts, each holding one drop of every reading
//! ([`crate::slam::robust::kept::kept_with_conflicts`] counts them with P, their
//! members are not sure, so with P and them accounting for q every other
//! detection is sure and the refinement reports its groups); with m = b
//! the positions of `stripped(N')`.
//!
//! The packing stops (a work heuristic, sound whatever it says) when it
//! has run more than [`PATIENCE`] / (N + k) propagations and, with the conflicts
//! still to find as large as those found, N' would keep under a third of
//! the detections: too few to refute anything. Without free conflicts,
//! each conflict's shrinking keeps to its share of the propagations
//! left (`State::shrink_in_share`), and past it the packing and the
//! overlapping conflicts give up (another work heuristic).
//!
//! # Soundness
//!
//! Steps 1-4 rest only on the semantics of `max_outliers` and on the
//! soundness of the ordinary propagator's infeasible verdict (a stopped or
//! cancelled solve counts as feasible: it proves nothing). The conflicts
//! are pairwise disjoint by construction (each is shrunk out of what the
//! earlier ones left), which is what makes their count a lower bound of
//! every reading's drops. Tested by `core/tests/slam/robust/conflicts.rs`
//! (planted false detections of every kind, q the number planted and
//! more): no true detection proved false, no true position lost, no false
//! detection grouped; and a packing that counts overlapping conflicts as
//! disjoint is caught.
//!
//! # Complexity
//!
//! At most [`MAX_SOLVES`] ordinary propagations of the mission (a conflict
//! of c detections out of k costs about c (1 + log2 k) of them); skipped
//! when (N + k) · [`MAX_SOLVES`] exceeds [`MAX_WORK`], and what is found
//! before the cap is kept (conflicts proved are conflicts). Memory: a few
//! keep vectors, O(k), and one positions vector, O(N · d).

use crate::interval::Interval;
use crate::slam::mission::Mission;
use crate::slam::model::Model;
use crate::slam::propagate::rounds::rounds;
use crate::slam::robust::cliques::clique_conflicts;
use crate::slam::robust::hitting::{forced, hitting_set, minimum, Forced, Hit};
use crate::slam::robust::kept::kept_only;
use crate::slam::types::{Progress, SolveOptions, SolveStatus};
use std::sync::atomic::{AtomicBool, Ordering};

/// Most ordinary propagations the rule runs.
pub const MAX_SOLVES: usize = 600;

/// Most (steps + detections) x [`MAX_SOLVES`] the rule may spend: the
/// paper scenario's 10,000 steps and 50-73 detections fit (a propagation
/// takes some ms); CMU Plaza 1 (9,657 steps, 3,600 detections, whose
/// q = 0 propagation takes far longer) and the format's 2,000,000 steps
/// (`huge_fields`) do not and skip the rule.
pub const MAX_WORK: u64 = 7_000_000;

/// Whether the rule's propagations fit [`MAX_WORK`].
pub fn within_work(steps: usize, detections: usize) -> bool {
    fits(steps, detections, MAX_SOLVES, MAX_WORK)
}

/// Whether (steps + detections) x `solves` is at most `work`.
fn fits(steps: usize, detections: usize, solves: usize, work: u64) -> bool {
    (steps as u64)
        .saturating_add(detections as u64)
        .saturating_mul(solves as u64)
        <= work
}

/// What [`pack`] proves.
#[derive(Debug, Clone, PartialEq)]
pub enum Packing {
    /// Nothing to do (q = 0, over the work cap, or every detection
    /// together is not proved infeasible): nothing is claimed.
    Skipped,
    /// More disjoint conflicts than the budget: no reading exists.
    Infeasible(String),
    /// The proof (module doc).
    Proved {
        /// Per detection: proved false here (P not included).
        proved_false: Vec<bool>,
        /// Pairwise disjoint conflicts, disjoint from P and from the
        /// detections proved false here, each holding one drop of every
        /// reading.
        conflicts: Vec<Vec<usize>>,
        /// With m = b: encloses every position of every reading.
        positions: Option<Vec<Interval>>,
        /// Ordinary propagations run.
        solves: usize,
        /// Their contractions.
        contractions: u64,
    },
}

/// The ordinary propagations of one packing, counted against the cap.
struct Solver<'a> {
    /// Most propagations ([`MAX_SOLVES`], or [`HIT_SOLVES`] once the
    /// overlapping conflicts are searched).
    cap: usize,
    mission: &'a Mission,
    /// The job's options, with at most [`SUB_ROUNDS`] rounds.
    options: SolveOptions,
    cancel: &'a AtomicBool,
    solves: usize,
    contractions: u64,
}

impl Solver<'_> {
    /// `Some(infeasible)`, and the positions when feasible; `None` at the
    /// cap or once `cancel` is set (nothing proved: a cancelled
    /// propagation proves nothing infeasible, and each would still run its
    /// dead reckoning, so a cancelled packing went on for hundreds of them).
    fn solve(&mut self, keep: &[bool]) -> Option<(bool, Vec<Interval>)> {
        if self.solves >= self.cap || self.cancel.load(Ordering::Relaxed) {
            return None;
        }
        self.solves += 1;
        let sub = kept_only(self.mission, keep);
        let s = rounds(&sub, &self.options, &mut |_: &Progress| {}, self.cancel);
        self.contractions += s.contractions;
        Some((matches!(s.status, SolveStatus::Infeasible(_)), s.model.pos))
    }

    /// Whether the set `members` is proved infeasible (`None`: the cap).
    fn infeasible(&mut self, members: &[usize]) -> Option<bool> {
        let mut keep = vec![false; self.mission.detections.len()];
        for &j in members {
            keep[j] = true;
        }
        self.solve(&keep).map(|r| r.0)
    }

    /// Step 2 of the module doc: a conflict inside `t` (time order),
    /// whose union is proved infeasible. `None`: the cap was hit or the
    /// filter ran out of candidates (nothing proved).
    fn shrink(&mut self, t: &[usize]) -> Option<Vec<usize>> {
        let mut c: Vec<usize> = Vec::new();
        let mut t: Vec<usize> = t.to_vec();
        loop {
            if !c.is_empty() && self.infeasible(&c)? {
                return Some(c);
            }
            if t.is_empty() {
                return None;
            }
            // Invariant: c ∪ t proved infeasible; hi is an infeasible
            // prefix end, lo - 1 a feasible one (or none).
            let (mut lo, mut hi) = (0usize, t.len() - 1);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                let mut set = c.clone();
                set.extend_from_slice(&t[..=mid]);
                if self.infeasible(&set)? {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            c.push(t[hi]);
            t.truncate(hi);
        }
    }
}

/// (Steps + detections) x propagations the packing may spend before its
/// work heuristic ([`State::promising`]) may stop it: 150 propagations of
/// a 4,000-step mission, 60 of the paper scenario's 10,000; small
/// missions, cheap to pack, are packed whole.
pub const PATIENCE: u64 = 600_000;

/// Most unaccounted drops q' = b - m for which resolution runs (step 4:
/// the family of q'-block sets of N').
pub const MAX_OPEN: usize = 3;

/// Conflict packing (module doc) for a mission with `max_outliers` = q
/// (at most k) and the detections `proved_false` so far; `order`: the
/// detections in time order.
pub fn pack(
    mission: &Mission,
    q: usize,
    proved_false: &[bool],
    order: &[usize],
    options: &SolveOptions,
    cancel: &AtomicBool,
) -> Packing {
    let k = mission.detections.len();
    let p = proved_false.iter().filter(|&&f| f).count();
    if q == 0 || p >= q || !within_work(mission.steps, k) {
        return Packing::Skipped;
    }
    let mut st = State {
        s: Solver {
            cap: MAX_SOLVES,
            mission,
            options: SolveOptions {
                max_rounds: options.max_rounds.min(SUB_ROUNDS),
                ..options.clone()
            },
            cancel,
            solves: 0,
            contractions: 0,
        },
        rank: vec![0; k],
        rest: order
            .iter()
            .copied()
            .filter(|&j| !proved_false[j])
            .collect(),
        conflicts: Vec::new(),
        proved_false: vec![false; k],
        budget: q - p,
        positions: None,
        open: k - p,
        shares: false,
        gave_up: false,
    };
    for (r, &j) in order.iter().enumerate() {
        st.rank[j] = r;
    }
    // Step 0: the conflicts that cost no propagation (n + 1 detections
    // pairwise distinct), and what their hitting sets prove.
    let open: Vec<bool> = proved_false.iter().map(|&f| !f).collect();
    // The cliques read detections seen from p (the distinct pairs know no
    // sensor offset); the propagations read the mission as given.
    let seen = mission.seen_from_p();
    let mut free = clique_conflicts(&seen, &Model::new(&seen), &open, order);
    if let Err(reason) = st.free(&mut free) {
        return Packing::Infeasible(reason);
    }
    if let Err(reason) = st.stages(free, q, p) {
        return Packing::Infeasible(reason);
    }
    if st.conflicts.is_empty() && !st.proved_false.contains(&true) {
        return Packing::Skipped;
    }
    Packing::Proved {
        proved_false: st.proved_false,
        conflicts: st.conflicts,
        positions: st.positions,
        solves: st.s.solves,
        contractions: st.s.contractions,
    }
}

impl State<'_> {
    /// After the free conflicts: the disjoint packing (when there are no
    /// free conflicts or they leave nothing), the overlapping conflicts,
    /// and the disjoint packing of what they leave open. Err: no reading.
    fn stages(&mut self, free: Vec<Vec<usize>>, q: usize, p: usize) -> Result<(), String> {
        let (steps, k) = (self.s.mission.steps, self.proved_false.len());
        let had_free = !free.is_empty();
        // With free conflicts the disjoint packing is not needed first:
        // the overlapping conflicts start from them.
        if free.is_empty() || self.budget == 0 || !within_hit_work(steps, k) {
            self.shares = true;
            self.pack_and_resolve(q, p)?;
            self.shares = false;
        }
        if self.conflicts.len() < self.budget && within_hit_work(steps, k) && !self.gave_up {
            self.s.cap = HIT_SOLVES;
            self.hit(free)?;
            // What the overlapping conflicts left open: the disjoint
            // packing of the rest (its conflicts count one drop each in
            // `robust/kept.rs`), with a few more propagations of its own.
            if had_free && self.budget > 0 && self.conflicts.is_empty() {
                self.s.cap = self.s.cap.max(self.s.solves + FALLBACK_SOLVES);
                self.pack_and_resolve(q, p)?;
            }
        }
        Ok(())
    }
}

fn infeasible_reason(conflicts: &[Vec<usize>], q: usize, p: usize) -> String {
    format!(
        "the detection sets {conflicts:?} are each inconsistent (one detection of each is false) and pairwise disjoint, and {p} other detections or more are proved false: more than max_outliers = {q}"
    )
}

/// The packing's state: N' = `rest` (time order), the unresolved
/// conflicts, the detections proved false here, the budget b left.
struct State<'a> {
    s: Solver<'a>,
    /// Each detection's place in time order.
    rank: Vec<usize>,
    rest: Vec<usize>,
    conflicts: Vec<Vec<usize>>,
    proved_false: Vec<bool>,
    budget: usize,
    /// With m = b: the positions of `stripped(rest)`.
    positions: Option<Vec<Interval>>,
    /// How many detections the packing started with.
    open: usize,
    /// Whether each conflict's shrinking keeps to its share of the
    /// propagations left ([`State::shrink_in_share`]).
    shares: bool,
    /// A shrinking went past its share: the packing and the overlapping
    /// conflicts are not run further (they would find conflicts as large).
    gave_up: bool,
}

impl State<'_> {
    /// Steps 3 and 4 to a fixpoint (or the cap); Err: no reading exists.
    fn pack_and_resolve(&mut self, q: usize, p: usize) -> Result<(), String> {
        loop {
            match self.pack_rest() {
                Err(()) => return Err(infeasible_reason(&self.conflicts, q, p)),
                Ok(false) => return Ok(()),
                Ok(true) => {}
            }
            if !self.resolve_one()? {
                return Ok(());
            }
        }
    }

    /// Step 3: conflicts shrunk out of `rest` until it is feasible. Ok:
    /// whether the packing is complete (false: the cap); Err: more
    /// conflicts than the budget.
    fn pack_rest(&mut self) -> Result<bool, ()> {
        loop {
            let keep = self.keep_of(&self.rest);
            let Some((infeasible, pos)) = self.s.solve(&keep) else {
                return Ok(false);
            };
            if !infeasible {
                if self.conflicts.len() == self.budget {
                    self.positions = Some(pos);
                }
                return Ok(true);
            }
            let Some(c) = self.shrink_in_share() else {
                return Ok(false);
            };
            self.rest.retain(|j| !c.contains(j));
            self.conflicts.push(c);
            if self.conflicts.len() > self.budget {
                return Err(());
            }
            if !self.promising() {
                return Ok(false);
            }
        }
    }

    /// Step 2 on `rest`, within this conflict's share of the propagations
    /// left when [`State::shares`] is set (a work heuristic, sound
    /// whatever it does: stopping claims less). The packing proves
    /// something only once its conflicts leave at most [`MAX_OPEN`] drops
    /// open (step 4), so each of the `d = budget - MAX_OPEN - m` conflicts
    /// still needed may take `1 / d` of what is left; one that takes more
    /// means conflicts too large to be found in time (measured on the
    /// woods scenario, 300 steps, 10 phantoms: a first conflict of 52
    /// detections took the whole cap of 600 propagations, 75 s, for
    /// nothing), and the packing gives up.
    fn shrink_in_share(&mut self) -> Option<Vec<usize>> {
        let needed = self.budget.saturating_sub(MAX_OPEN + self.conflicts.len());
        if !self.shares || needed <= 1 {
            return self.s.shrink(&self.rest);
        }
        let cap = self.s.cap;
        let share = cap.saturating_sub(self.s.solves) / needed;
        self.s.cap = self.s.solves + share;
        let c = self.s.shrink(&self.rest);
        if c.is_none() && self.s.solves >= self.s.cap {
            self.gave_up = true;
        }
        self.s.cap = cap;
        c
    }

    /// A work heuristic (any answer is sound: stopping the packing only
    /// claims less): whether the packing has run at most [`PATIENCE`] /
    /// (N + k) propagations, or, with the conflicts still to find as large as the
    /// mean of those found, N' would keep at least a third of the
    /// detections it started with. Below that N' is too small
    /// to refute anything (measured on the paper scenario: conflicts of
    /// n + 1 = 5 detections, 10 of them in 54-63), and the packing would
    /// spend hundreds of propagations for nothing.
    fn promising(&self) -> bool {
        let found: usize = self.conflicts.iter().map(Vec::len).sum();
        let m = self.conflicts.len();
        let to_find = (self.budget - m).saturating_mul(found) / m.max(1);
        let size = (self.s.mission.steps as u64).saturating_add(self.proved_false.len() as u64);
        (self.s.solves as u64).saturating_mul(size) <= PATIENCE
            || self.rest.len().saturating_sub(to_find).saturating_mul(3) >= self.open
    }

    fn keep_of(&self, set: &[usize]) -> Vec<bool> {
        let mut keep = vec![false; self.proved_false.len()];
        for &j in set {
            keep[j] = true;
        }
        keep
    }

    /// Step 4: the family of sets of N' of which every reading keeping a
    /// detection of a conflict keeps one whole (at most q' = b - m of N'
    /// dropped): N' itself for q' = 0, else N' dealt in time order into
    /// q' + 3 blocks, every set leaving q' blocks out (C(q' + 3, q'): 4,
    /// 10 or 20 sets). `None`: q' > [`MAX_OPEN`].
    fn family(&self) -> Option<Vec<Vec<bool>>> {
        let open = self.budget - self.conflicts.len();
        if open == 0 {
            return Some(vec![self.keep_of(&self.rest)]);
        }
        if open > MAX_OPEN || self.rest.len() < open + 3 {
            return None;
        }
        let b = open + 3;
        let mut out = Vec::new();
        let mut excluded: Vec<usize> = (0..open).collect();
        loop {
            let mut keep = vec![false; self.proved_false.len()];
            for (r, &j) in self.rest.iter().enumerate() {
                keep[j] = !excluded.contains(&(r % b));
            }
            out.push(keep);
            let Some(i) = (0..open).rev().find(|&i| excluded[i] < b - open + i) else {
                return Some(out);
            };
            excluded[i] += 1;
            for t in i + 1..open {
                excluded[t] = excluded[t - 1] + 1;
            }
        }
    }

    /// Whether `x` is proved false: every set of the family plus x is
    /// proved infeasible (`None`: the cap).
    fn refuted(&mut self, family: &[Vec<bool>], x: usize) -> Option<bool> {
        for set in family {
            let mut keep = set.clone();
            keep[x] = true;
            if !self.s.solve(&keep)?.0 {
                return Some(false);
            }
        }
        Some(true)
    }

    /// Step 4: the first conflict with a detection proved false is
    /// resolved (its detections proved false leave the budget, the others
    /// rejoin N'). Ok: whether one was (false: none, or the cap); Err: no
    /// reading exists.
    fn resolve_one(&mut self) -> Result<bool, String> {
        let Some(family) = self.family() else {
            return Ok(false);
        };
        for i in 0..self.conflicts.len() {
            let mut refuted = Vec::new();
            for x in self.conflicts[i].clone() {
                match self.refuted(&family, x) {
                    None => return Ok(false),
                    Some(true) => refuted.push(x),
                    Some(false) => {}
                }
            }
            if refuted.is_empty() {
                continue;
            }
            let c = self.conflicts.remove(i);
            if refuted.len() > self.budget || self.conflicts.len() > self.budget - refuted.len() {
                return Err(format!(
                    "detections {refuted:?} of the inconsistent set {c:?} are each inconsistent with the detections that every choice of at most max_outliers false detections keeps, and the disjoint inconsistent sets {:?} hold one false detection each: more than max_outliers false detections",
                    self.conflicts
                ));
            }
            self.budget -= refuted.len();
            for &x in &refuted {
                self.proved_false[x] = true;
            }
            self.rest
                .extend(c.into_iter().filter(|j| !refuted.contains(j)));
            let rank = &self.rank;
            crate::sort::stable_by_key(&mut self.rest, |&j| rank[j]);
            self.positions = None;
            return Ok(true);
        }
        Ok(false)
    }
}

/// Most rounds of each propagation of a set (a propagation stopped there is
/// not proved infeasible, so it proves nothing: sound). On the paper
/// scenario with 10 false detections the sets proved infeasible take 1-33
/// rounds, except one run's (random layout, seed 7) 1,880; some feasible
/// sets crawl to the job's 10,000 rounds (77 million contractions, about
/// 1.5 s each): that run took 98 s of CPU, 68 propagations.
pub const SUB_ROUNDS: u32 = 200;

/// Most ordinary propagations once the overlapping conflicts are searched
/// (`State::hit`), the packing's included: with the free conflicts and
/// the propagations of the kept detections only, the paper scenario with
/// 10 false detections needs 20-400 (a few ms to 70 ms each: 200 left
/// 4 line runs of 10 unproved); 1,500 (qhit) let one run spend 108 s.
pub const HIT_SOLVES: usize = 400;

/// Propagations added for the disjoint packing that follows the
/// overlapping conflicts when they leave drops unaccounted for (K = 5,
/// ring, seed 9: 4 of 5 phantoms proved, the last one packed). Kept
/// small: on a busy machine K = 10, random, seed 6 took 8.4 s of CPU on
/// main and 10.8-12.2 s with 20-60 of these (same recall with each).
pub const FALLBACK_SOLVES: usize = 20;

/// Most (steps + detections) x [`HIT_SOLVES`] for the overlapping
/// conflicts: the paper scenario's 10,000 steps fit, CMU Plaza 1 and the
/// 2,000,000-step missions do not.
pub const HIT_WORK: u64 = 4_400_000;

/// Most branch-and-bound nodes of the hitting-set searches of one packing
/// ([`crate::slam::robust::hitting`]).
pub const HIT_NODES: u64 = 2_000_000;

/// Whether `State::hit`'s propagations fit [`HIT_WORK`].
pub fn within_hit_work(steps: usize, detections: usize) -> bool {
    fits(steps, detections, HIT_SOLVES, HIT_WORK)
}

impl State<'_> {
    /// The detections still open (neither proved false here nor before),
    /// in time order.
    fn pool(&self) -> Vec<usize> {
        let mut pool: Vec<usize> = self.rest.clone();
        pool.extend(self.conflicts.iter().flatten());
        let rank = &self.rank;
        crate::sort::stable_by_key(&mut pool, |&j| rank[j]);
        pool
    }

    /// Overlapping conflicts (docs/outliers.md, "Overlapping conflicts"):
    /// Reiter's loop grows a family F of conflicts, each shrunk out of the
    /// open detections minus a hitting set H of F, until a minimum H has b
    /// members (the budget; more: no reading). Then a member x of H is
    /// proved false when no set of at most b detections without x hits F:
    /// while one, H', exists and the open detections minus H' are
    /// infeasible, a conflict shrunk out of them joins F. x leaves the
    /// budget and the conflicts holding it leave F; on to a fixpoint. Err:
    /// no reading exists. The cap (solves or nodes) stops it with what is
    /// proved so far.
    fn hit(&mut self, free: Vec<Vec<usize>>) -> Result<(), String> {
        let mut family: Vec<Vec<usize>> = self.conflicts.clone();
        family.extend(free);
        let mut work = HIT_NODES;
        let no_reading = |b: usize, f: &[Vec<usize>]| {
            format!(
                "the inconsistent detection sets {f:?} cannot all be hit by {b} detections: more false detections than max_outliers allows"
            )
        };
        loop {
            let h = match minimum(&family, &[], self.budget, &mut work) {
                Hit::Found(h) => h,
                Hit::None => return Err(no_reading(self.budget, &family)),
                Hit::Unknown => return Ok(()),
            };
            if h.len() < self.budget {
                match self.grow(&mut family, &h) {
                    Some(true) => continue,
                    _ => return Ok(()),
                }
            }
            let mut proved = None;
            // The candidates: h, then the members of each hitting set H'
            // found consistent (the open detections outside it are not
            // proved infeasible): its drops are the likely false ones
            // (a heuristic: which x are tried decides only what is proved).
            let mut cands = h;
            let mut next = 0;
            while next < cands.len() {
                let x = cands[next];
                next += 1;
                let Some(refuted) = self.refute(&mut family, x, &mut work, &mut cands) else {
                    return Ok(());
                };
                if refuted {
                    proved = Some(x);
                    break;
                }
            }
            let Some(x) = proved else {
                return Ok(());
            };
            self.budget -= 1;
            self.proved_false[x] = true;
            family.retain(|c| !c.contains(&x));
            if let Some(i) = self.conflicts.iter().position(|c| c.contains(&x)) {
                let c = self.conflicts.remove(i);
                self.rest.extend(c.into_iter().filter(|&j| j != x));
            }
            self.rest.retain(|&j| j != x);
            let rank = &self.rank;
            crate::sort::stable_by_key(&mut self.rest, |&j| rank[j]);
            self.positions = None;
            if self.budget == 0 {
                let keep = self.keep_of(&self.pool());
                match self.s.solve(&keep) {
                    Some((true, _)) => return Err(no_reading(0, &family)),
                    Some((false, pos)) => self.positions = Some(pos),
                    None => {}
                }
                return Ok(());
            }
        }
    }

    /// Step 0: the detections that every hitting set of at most b of the
    /// free conflicts `family` holds are proved false (docs/outliers.md,
    /// "Overlapping conflicts", step 2), to a fixpoint; no propagation.
    /// Err: no set of at most b hits the family (no reading exists).
    fn free(&mut self, family: &mut Vec<Vec<usize>>) -> Result<(), String> {
        let mut work = HIT_NODES;
        while !family.is_empty() {
            let xs = match forced(family, self.budget, &mut work) {
                Forced::Members(xs) => xs,
                Forced::NoReading => {
                    return Err(format!(
                        "the sets of detections {family:?}, each pairwise proved to see distinct landmarks and one more than landmark_count, cannot all be hit by {} detections: more false detections than max_outliers allows",
                        self.budget
                    ))
                }
            };
            if xs.is_empty() {
                return Ok(());
            }
            // Each x is in every hitting set of at most b: all of them are
            // dropped by every reading (forced() checks |xs| <= b through
            // the minimum hitting sets, which hold them).
            self.budget -= xs.len();
            for &x in &xs {
                self.proved_false[x] = true;
            }
            family.retain(|c| !c.iter().any(|j| xs.contains(j)));
            self.rest.retain(|j| !xs.contains(j));
        }
        Ok(())
    }

    /// Whether `x` is proved false: no set of at most b detections without
    /// x hits `family`, which grows while the hitting sets found leave
    /// infeasible open detections. The members of a hitting set found
    /// consistent join `cands`. `None`: a cap.
    fn refute(
        &mut self,
        family: &mut Vec<Vec<usize>>,
        x: usize,
        work: &mut u64,
        cands: &mut Vec<usize>,
    ) -> Option<bool> {
        let mut ban = vec![false; self.proved_false.len()];
        ban[x] = true;
        loop {
            match hitting_set(family, &ban, self.budget, work) {
                Hit::None => return Some(true),
                Hit::Unknown => return None,
                Hit::Found(other) => {
                    if !self.grow(family, &other)? {
                        for y in other {
                            if !cands.contains(&y) {
                                cands.push(y);
                            }
                        }
                        return Some(false);
                    }
                }
            }
        }
    }

    /// One step of Reiter's loop: when the open detections outside the
    /// hitting set `h` are proved infeasible, a conflict shrunk out of them
    /// (unhit by `h`) joins `family`: `Some(true)`. `Some(false)`: they are
    /// not; `None`: the cap.
    fn grow(&mut self, family: &mut Vec<Vec<usize>>, h: &[usize]) -> Option<bool> {
        let mut t: Vec<usize> = self.pool().into_iter().filter(|j| !h.contains(j)).collect();
        // The filter keeps the earliest detections it can: start each
        // search elsewhere in time (a golden-ratio sequence), so that the
        // conflicts spread over the mission.
        let frac = (family.len() as u64).wrapping_mul(0x9E37_79B9) & 0xFFFF_FFFF;
        let turn = ((frac * t.len() as u64) >> 32) as usize;
        t.rotate_left(turn);
        if !self.s.infeasible(&t)? {
            return Some(false);
        }
        let c = self.s.shrink(&t)?;
        family.push(c);
        Some(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_work_cap() {
        assert!(within_work(10_000, 73));
        assert!(!within_work(9_657, 3_600));
        assert!(!within_work(2_000_000, 0));
        assert!(!within_work(usize::MAX, usize::MAX));
    }
}
