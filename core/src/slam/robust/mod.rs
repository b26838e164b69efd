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
//! - `matching` (see [`crate::slam::robust::kept`]): dropping a detection only removes
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

pub mod cliques;
pub mod conflicts;
pub mod heading;
pub mod hitting;
pub mod kept;
mod passes;
pub mod regions;
pub mod subsets;
pub mod track_groups;

use crate::contractors::motion_chain::shrinkage;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::slam::association::odometry2d::tracks::TrackOptions;
use crate::slam::mission::Mission;
use crate::slam::model::{operator_groups, Model};
use crate::slam::robust::conflicts::{pack, Packing};
use crate::slam::robust::heading::{cut_headings, robust_heading};
use crate::slam::robust::kept::{kept_with_conflicts, refine, sure_groups, Accounted};
pub use crate::slam::robust::regions::relaxed_intersection;
use crate::slam::robust::subsets::{consensus_told, Consensus};
use crate::slam::robust::track_groups::robust_track_groups;
use crate::slam::types::{
    OutlierTally, Progress, Solution, SolveOptions, SolveStatus, WorkEstimate,
};
use passes::{gather, relaxed_passes, Evidence, Track};
use std::sync::atomic::{AtomicBool, Ordering};

/// Solves a mission with `max_outliers` = q > 0 (see the module doc): the
/// robust rounds to their fixpoint, then what is proved of the detections
/// kept in every reading ([`crate::slam::robust::kept`]): `matching` holds only groups
/// proved whichever detections are false.
pub fn solve_robust(
    mission: &Mission,
    q: usize,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    // The robust rounds know no sensor offset: they read the detections
    // restated from p (sound, see `Mission::seen_from_p`). The
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
    /// ([`crate::slam::robust::track_groups`], odometry2d).
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
    /// one drop of every reading ([`crate::slam::robust::conflicts`]).
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

    /// Consensus over subsets ([`crate::slam::robust::subsets`], small q): the
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

    /// Conflict packing ([`crate::slam::robust::conflicts`], any q): where
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
        // ([`crate::slam::robust::heading`]), with the same passes on a chain of
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
