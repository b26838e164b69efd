//! The association step of a round ([`crate::slam::propagate::rounds`]):
//! ties the detection variables together. Proved groups (the operator's,
//! then those atmost_nvector proved) share one variable: their boxes are
//! intersected. Then atmost_nvector(n) with the chosen contractor
//! contracts every detection box and proves new groups, the detection
//! shapes (the steps of this module's parent) run, and the minimum
//! separation ([`super::odometry2d::separation`]) merges groups too narrow
//! to be two landmarks. A detection whose box moves by more than the
//! tolerance is marked moving; the passes of the next round carry its
//! change to p(step) and along the chain.
//!
//! Further association contractors belong here: one that shrinks a
//! position p(steps[s]) must set `unswept[0][s]` and `unswept[1][s]` so
//! the next passes sweep from it.
//!
//! Soundness: each step is a sound contractor (see each file), and a group
//! is proved once and stays proved.

use super::odometry2d::separation::separation_unions;
use super::{Chain, Domains, ShapesState};
use crate::contractors::motion_chain::{shrinkage, sweep_forward, Sweep};
use crate::interval::Interval;
use crate::nvector::{atmost_nvector, Status};
use crate::odometry::chain::OdometryChain;
use crate::slam::mission::Mission;
use crate::slam::model::Model;
use crate::slam::types::{Association, SolveOptions};
use crate::union_find::Uf;

/// What the association step reads and changes of a round's state.
pub struct AssociationStep<'a> {
    /// The mission.
    pub mission: &'a Mission,
    /// The solve options (the association contractor).
    pub options: &'a SolveOptions,
    /// The domains.
    pub model: &'a mut Model,
    /// Detections proved to see one landmark.
    pub matching: &'a mut Uf,
    /// The tolerance.
    pub tol: f64,
    /// The contraction counter.
    pub contractions: &'a mut u64,
    /// Per detection: its box or position moved by more than the tolerance
    /// in this round.
    pub moving: &'a mut [bool],
    /// Detection shapes (modes `shapes` and `best`).
    pub shapes: Option<&'a mut ShapesState>,
    /// With a sensor offset: the mission restated from p
    /// ([`Mission::seen_from_p`]), which the shapes read.
    pub shapes_mission: Option<&'a Mission>,
    /// Detections sorted by (step, index).
    pub order: &'a [usize],
    /// The distinct detection steps, ascending.
    pub steps: &'a [usize],
    /// The detections at `steps[s]` are `order[starts[s]..starts[s + 1]]`.
    pub starts: &'a [usize],
    /// Per distinct step, whether it is left to sweep forward (`[0]`) and
    /// backward (`[1]`).
    pub unswept: &'a mut [Vec<bool>; 2],
}

impl AssociationStep<'_> {
    /// The step (module doc); Err: the mission is infeasible (the reason).
    pub fn run(&mut self) -> Result<(), String> {
        self.associate_groups()?;
        self.separation_step()
    }

    /// The minimum separation (`landmark_min_separation`): groups whose
    /// boxes fit in a set of diameter below it are one landmark
    /// ([`separation_unions`]); the detections of a union count as moving,
    /// so that the next round intersects their boxes. Not for `none` (the
    /// basic model uses the operator's fields only).
    fn separation_step(&mut self) -> Result<(), String> {
        let s = self.mission.landmark_min_separation;
        if self.options.association == Association::None || s <= 0.0 {
            return Ok(());
        }
        let unions = separation_unions(&self.model.det, self.matching, s)?;
        *self.contractions += 1;
        for (a, b) in unions {
            self.moving[a] = true;
            self.moving[b] = true;
        }
        Ok(())
    }

    /// The groups and atmost_nvector part of [`AssociationStep::run`].
    fn associate_groups(&mut self) -> Result<(), String> {
        let dim = self.model.dim;
        let groups = self.matching.groups();
        for g in &groups {
            let mut common = self.model.det[g[0]].clone();
            for &j in &g[1..] {
                common.intersect_with(&self.model.det[j]);
            }
            if common.is_empty() {
                return Err(format!(
                    "landmark of detections {g:?}: their boxes have no common point (a wrong matching?)"
                ));
            }
            for &j in g {
                let m = (0..dim)
                    .map(|a| shrinkage(self.model.det[j][a], common[a]))
                    .fold(0.0, f64::max);
                if m > self.tol {
                    self.moving[j] = true;
                }
                self.model.det[j] = common.clone();
            }
            *self.contractions += 1;
        }
        let (Association::NVector(mode), Some(nl)) =
            (self.options.association, self.mission.landmark_count)
        else {
            return Ok(());
        };
        if self.model.det.is_empty() {
            return Ok(());
        }
        let snapshot = self.model.det.clone();
        let out = match atmost_nvector(nl, &mut self.model.det, mode) {
            Ok(out) => out,
            // Not a proof of infeasibility: `exact` out of its work budget
            // (k > 40 or its node budget) proves nothing this round, so the
            // boxes go back to what they were and the round goes on.
            Err(_) => {
                self.model.det = snapshot;
                return self.shapes_step(nl);
            }
        };
        *self.contractions += 1;
        if let Status::Infeasible { reason } = out.status {
            return Err(format!(
                "atmost_nvector({nl}) over the detections: {reason}"
            ));
        }
        for g in &out.groups {
            for &j in &g[1..] {
                self.matching.union(g[0], j);
            }
        }
        for (j, (a, b)) in snapshot.iter().zip(&self.model.det).enumerate() {
            let m = (0..dim).map(|x| shrinkage(a[x], b[x])).fold(0.0, f64::max);
            if m > self.tol {
                self.moving[j] = true;
            }
        }
        self.shapes_step(nl)
    }

    /// Detection shapes ([`crate::shapes`]): landmark regions of the
    /// groups, distinct pairs, witnesses and branch contraction. A position
    /// it shrinks is flagged for the next passes' sweeps.
    fn shapes_step(&mut self, n: usize) -> Result<(), String> {
        let Some(state) = self.shapes.as_mut() else {
            return Ok(());
        };
        let groups = self.matching.groups();
        // odometry2d: the shapes read th(step) and D(i) of the current
        // headings.
        self.model.refresh_headings_at(self.mission);
        self.model.refresh_displacements();
        let Model {
            dim,
            pos,
            det,
            disp,
            heading_at,
            heading,
            odometry,
            ..
        } = &mut *self.model;
        let mut chain = ShapesChain {
            disp,
            dim: *dim,
            tol: self.tol,
            steps: self.steps,
            unswept: &mut *self.unswept,
            swept: 0,
            odometry: odometry.as_ref().map(|c| (c, heading)),
        };
        let domains = Domains {
            dim: *dim,
            pos,
            det,
            heading_at,
            disp,
        };
        let q = self.mission.max_outliers;
        let out = state.contract(
            self.shapes_mission.unwrap_or(self.mission),
            domains,
            &groups,
            Some(n),
            q,
            self.tol,
            &mut chain,
        );
        *self.contractions += out.contractions + chain.swept;
        if let Some(reason) = out.infeasible {
            return Err(reason);
        }
        for &(a, b) in &out.unions {
            self.matching.union(a, b);
        }
        for &j in &out.moved_detections {
            self.moving[j] = true;
        }
        // A position the round shrank (a registration, a branch) is flagged
        // for the next passes' sweeps; its detections count as moving, so
        // that the round loop goes on to sweep it (otherwise a run could end
        // "consistent" with positions the registration shrank left
        // unswept).
        for s in 0..self.steps.len() {
            if self.unswept[0][s] || self.unswept[1][s] {
                for &j in &self.order[self.starts[s]..self.starts[s + 1]] {
                    self.moving[j] = true;
                }
            }
        }
        Ok(())
    }
}

/// The motion chain as the shapes contractor sees it: forward sweeps on
/// request, changed positions flagged for the next passes.
struct ShapesChain<'a> {
    disp: &'a [Interval],
    dim: usize,
    tol: f64,
    steps: &'a [usize],
    unswept: &'a mut [Vec<bool>; 2],
    swept: u64,
    /// odometry2d: the chain and th(0..=N), swept with the positions.
    odometry: Option<(&'a OdometryChain, &'a mut Vec<Interval>)>,
}

impl Chain for ShapesChain<'_> {
    fn sweep_forward(
        &mut self,
        pos: &mut [Interval],
        from: usize,
        to: usize,
    ) -> Result<bool, String> {
        let dim = self.dim;
        let outcome = match &mut self.odometry {
            Some((chain, heading)) => chain.sweep_forward_flat(pos, heading, from, to, self.tol),
            None => {
                let end = &mut pos[..(to + 1) * dim];
                sweep_forward(end, &self.disp[..to * dim], dim, from, self.tol)
            }
        };
        match outcome {
            Sweep::Done(visited) => {
                self.swept += visited as u64;
                Ok(visited == to - from)
            }
            Sweep::Empty(s) => Err(format!(
                "motion chain: the position of step {s} is empty (propagating a landmark region from step {from})"
            )),
        }
    }

    fn changed(&mut self, step: usize) {
        if let Ok(s) = self.steps.binary_search(&step) {
            self.unswept[0][s] = true;
            self.unswept[1][s] = true;
        }
    }
}
