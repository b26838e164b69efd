//! The physics-guided propagator of the paper's section 6: a fixpoint over
//! the motion chain, the detection constraints and the association
//! constraint.
//!
//! # Rounds
//!
//! A round is a set-membership smoother over the chain followed by the
//! association step:
//! 1. a **forward pass**, step 0 to N: the chain is swept forward
//!    (`p(i+1) ∩= p(i) + D(i)`) and each detection's constraints (Distance,
//!    Bearing; its region and depth bound d(j) from the start) contract
//!    p(step) and d(j) when the pass reaches its step, so later detections
//!    see what earlier ones proved;
//! 2. a **backward pass**, N down to 0, the same with `p(i) ∩= p(i+1) -
//!    D(i)`;
//! 3. the **association step** ([`AssociationStep`]): detections
//!    proved to see one landmark (the operator's `landmark` fields, then
//!    the groups atmost_nvector proves) share one variable (their boxes are
//!    intersected), and atmost_nvector(n) contracts all detection boxes.
//!
//! Rounds repeat until no detection box, position at a detection or group
//! box moves by more than the tolerance, or `max_rounds`.
//!
//! # Sweeping only what changed
//!
//! A pass does not sweep the whole chain: a sweep starts where a change
//! starts (a detection that moved p(step) by more than the tolerance, in
//! this pass or, for the other direction, in the last pass) and runs while
//! it moves a bound by more than the tolerance; it stops at each detection
//! step it reaches to apply the detection, then goes on if the change is
//! still alive. Stretches nothing reached are jumped over. This is enough:
//! a backward sweep leaves the chain forward-consistent (if `p(i)` takes
//! its bound from `p(i+1) - D(i)`, then `p(i) + D(i)` holds `p(i+1)`), and
//! a forward sweep leaves it backward-consistent, so outside the pending
//! starts each direction has nothing to do.
//!
//! # Fixpoint
//!
//! Every operation is one of the sound contractors of this module's
//! neighbours, so the order in which they run does not change the greatest
//! common fixpoint they converge to; the tolerance leaves a slack of the
//! order of the tolerance per bound, as a sweep stops once its change falls
//! below it. The test `core/tests/slam/propagate/same_fixpoint.rs` compares the boxes,
//! statuses and matchings with the previous algorithm (each detection swept
//! on its own, kept there as a reference) on random missions.
//!
//! # Complexity
//!
//! A round costs O(N·d + k) for the passes (each stretch between two
//! detection steps is swept at most once per pass; usually far less, as
//! later rounds only touch what the association step changed), plus the
//! association (O(k log k) for the polynomial contractors). Memory: the
//! model's O(N·d + k), plus O(k) for the detection order and flags; no
//! allocation per step.
//!
//! The previous propagator swept forward and backward from each detection
//! that moved its position, to wherever the change died out: O(N) per
//! detection, O(N·k) per round (18.8 s and 1.4·10^9 contractions for 10^6
//! steps and 4,767 detections; BENCHMARKS.md has the new figures).
//!
//! Soundness: every step is a sound contractor (see each file), so the true
//! trajectory and landmarks stay inside.

use super::propagation::{Direction, Halt, Propagation};
use crate::slam::association::odometry2d::tracks::{track_unions, TrackOptions};
use crate::slam::association::step::AssociationStep;
use crate::slam::mission::Mission;
use crate::slam::types::{Association, Progress, Solution, SolveOptions, SolveStatus};
use std::sync::atomic::{AtomicBool, Ordering};

impl Propagation<'_> {
    /// Dead reckoning, then rounds to the fixpoint.
    fn run(&mut self) -> Result<(), Halt> {
        self.dead_reckoning()?;
        self.tracks();
        let d0 = self.model.max_trajectory_diameter();
        self.report.initial_max_trajectory_diameter = d0;
        self.report.max_trajectory_diameter = d0;
        loop {
            if self.round >= self.options.max_rounds || self.cancel.load(Ordering::Relaxed) {
                return Err(Halt::Stopped);
            }
            self.round += 1;
            self.moving.fill(false);
            self.drift()?;
            self.pass(Direction::Forward)?;
            self.pass(Direction::Backward)?;
            self.tell("association", 0)?;
            self.associate()?;
            let moving = self.moving.iter().filter(|&&m| m).count();
            self.end_round(moving);
            if moving == 0 {
                return Ok(());
            }
        }
    }

    /// odometry2d with a minimum separation: the detections the relative
    /// evidence proves to see one landmark ([`track_unions`]) share one
    /// variable from the first pass on. Not for `none` (the basic model
    /// uses the operator's fields only) nor with false detections.
    fn tracks(&mut self) {
        let Some(chain) = &self.model.odometry else {
            return;
        };
        if self.options.association == Association::None || self.mission.max_outliers > 0 {
            return;
        }
        let u = track_unions(
            self.mission,
            chain,
            &mut self.matching,
            TrackOptions::default(),
        );
        self.contractions += u.len() as u64;
    }

    /// odometry2d with `heading_drift`: the windows over the headings, and
    /// the chain swept from every heading they moved
    /// ([`OdometryChain::drift_flat`]), once per round (O(N) per window).
    fn drift(&mut self) -> Result<(), Halt> {
        let Some(chain) = &self.model.odometry else {
            return Ok(());
        };
        let (pos, heading) = (&mut self.model.pos, &mut self.model.heading);
        match chain.drift_flat(pos, heading, self.tol) {
            Ok(work) => {
                self.contractions += work as u64;
                Ok(())
            }
            Err(e) => Err(Halt::Infeasible(format!(
                "heading_drift: the heading or position of step {} is empty",
                e.step
            ))),
        }
    }

    /// p(0..=N) from the initial position forward, and back from the final
    /// position when known (tolerance 0: every step).
    fn dead_reckoning(&mut self) -> Result<(), Halt> {
        let to_final = self.mission.final_position.is_some();
        self.model
            .dead_reckoning(to_final)
            .map_err(Halt::Infeasible)?;
        self.contractions += 2 * self.model.steps as u64;
        Ok(())
    }

    /// The association step of a round ([`AssociationStep`]): proved
    /// groups share one variable, atmost_nvector(n) contracts every
    /// detection box, then the shapes and the minimum separation. A
    /// detection whose box moves by more than the tolerance is marked
    /// moving; the passes of the next round carry its change to p(step)
    /// and along the chain.
    fn associate(&mut self) -> Result<(), Halt> {
        AssociationStep {
            mission: self.mission,
            options: self.options,
            model: &mut self.model,
            matching: &mut self.matching,
            tol: self.tol,
            contractions: &mut self.contractions,
            moving: &mut self.moving,
            shapes: self.shapes.as_mut(),
            shapes_mission: self.shapes_mission.as_ref(),
            order: &self.order,
            steps: &self.steps,
            starts: &self.starts,
            unswept: &mut self.unswept,
        }
        .run()
        .map_err(Halt::Infeasible)
    }
}

/// The rounds of this module from dead reckoning to the fixpoint (or a
/// halt), for a mission without false detections (`max_outliers` 0; the
/// robust propagation of [`crate::slam::robust`] handles the others).
pub fn rounds(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    run_rounds(mission, options, false, progress, cancel)
}

/// [`rounds`] with the shapes' full work in every round (every group's
/// step 1 even when none of its inputs moved, the distinct pairs of the
/// detection shapes even when the operator named every landmark:
/// `ShapesState::full_work`), the schedule before the incremental one. The tests
/// compare [`rounds`] with it: every box of `rounds` must lie in this
/// one's, its groups hold this one's.
#[doc(hidden)]
pub fn rounds_full_shapes(
    mission: &Mission,
    options: &SolveOptions,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    run_rounds(mission, options, true, progress, cancel)
}

/// [`rounds`], with `full_work` for the shapes state (above).
fn run_rounds(
    mission: &Mission,
    options: &SolveOptions,
    full_work: bool,
    progress: &mut dyn FnMut(&Progress),
    cancel: &AtomicBool,
) -> Solution {
    debug_assert_eq!(mission.max_outliers, 0);
    let mut p = Propagation::new(mission, options, progress, cancel);
    if let Some(state) = p.shapes.as_mut() {
        state.full_work = full_work;
    }
    let status = match p.run() {
        Ok(()) => SolveStatus::Consistent,
        Err(Halt::Infeasible(reason)) => SolveStatus::Infeasible(reason),
        Err(Halt::Stopped) => SolveStatus::Stopped,
    };
    let matching = p.matching.groups();
    if let Some(state) = &p.shapes {
        let mut regions = vec![None; mission.detections.len()];
        for g in &matching {
            regions[g[0]] = state.region_of(g).map(|r| r.boxes().to_vec());
        }
        p.model.landmark_regions = regions;
    }
    Solution {
        status,
        matching,
        rounds: p.round,
        contractions: p.contractions,
        model: p.model,
        outliers: None,
    }
}
