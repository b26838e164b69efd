//! The state of one propagation by rounds ([`super::rounds`]): the
//! domains, what was proved, what is left to sweep, the counters, and the
//! progress reports. The passes ([`super::passes`]), the detections'
//! contraction inside them ([`super::detections`]) and the rounds
//! ([`super::rounds`]) are its methods, one file each.

use crate::nvector::Contractor;
use crate::slam::association::odometry2d::scan_map::ScanMap;
use crate::slam::association::odometry2d::scan_pose_step::ScanPoseMemo;
use crate::slam::association::odometry2d::sequential::SeparationGrid;
use crate::slam::association::ShapesState;
use crate::slam::mission::Mission;
use crate::slam::model::{operator_groups, Model};
use crate::slam::types::{width_sum, Association, Progress, SolveOptions, WorkEstimate};
use crate::union_find::Uf;
use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};

/// Why propagation ended before its fixpoint: the one way out of every
/// step of a round.
pub(super) enum Halt {
    /// A domain became empty; the reason names the constraint and variable.
    Infeasible(String),
    /// `max_rounds` reached or cancelled (the boxes are still sound).
    Stopped,
}

/// Which way a pass runs along the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Direction {
    Forward,
    Backward,
}

/// The state of one propagation: the domains, what was proved, what is
/// left to sweep, and the counters.
pub(super) struct Propagation<'a> {
    pub(super) mission: &'a Mission,
    pub(super) options: &'a SolveOptions,
    pub(super) model: Model,
    /// Detections proved to see one landmark.
    pub(super) matching: Uf,
    pub(super) tol: f64,
    pub(super) round: u32,
    pub(super) contractions: u64,
    /// Detections sorted by (step, index).
    pub(super) order: Vec<usize>,
    /// The distinct detection steps, ascending; the detections at
    /// `steps[s]` are `order[starts[s]..starts[s + 1]]`.
    pub(super) steps: Vec<usize>,
    pub(super) starts: Vec<usize>,
    /// Per distinct step: its detections moved p(step) by more than the
    /// tolerance in a backward pass and the change is not yet swept forward
    /// (`unswept[0]`), or in a forward pass and not yet swept backward
    /// (`unswept[1]`).
    pub(super) unswept: [Vec<bool>; 2],
    /// Per detection: its box or position moved by more than the tolerance
    /// in this round.
    pub(super) moving: Vec<bool>,
    pub(super) progress: &'a mut dyn FnMut(&Progress),
    pub(super) cancel: &'a AtomicBool,
    /// The last report (diameters, moving count, fraction so far).
    pub(super) report: Progress,
    /// The fraction's estimate (see [`WorkEstimate`]).
    pub(super) work: WorkEstimate,
    /// Detection shapes (modes `shapes` and `best`).
    pub(super) shapes: Option<ShapesState>,
    /// With a sensor offset: the mission with each detection restated from
    /// p ([`Mission::seen_from_p`]), which the shapes reasoning reads
    /// (it knows no offset).
    pub(super) shapes_mission: Option<Mission>,
    /// The minimum separation inside the passes ([`SeparationGrid`]),
    /// rebuilt at the start of each pass; None when the rule is off.
    pub(super) grid: Option<SeparationGrid>,
    /// The closed-world map of the pass ([`ScanMap`]), with the grid.
    pub(super) scan_map: Option<ScanMap>,
    /// What the scan pose left at each step ([`ScanPoseMemo`]).
    pub(super) pose_memo: ScanPoseMemo,
}

impl<'a> Propagation<'a> {
    pub(super) fn new(
        mission: &'a Mission,
        options: &'a SolveOptions,
        progress: &'a mut dyn FnMut(&Progress),
        cancel: &'a AtomicBool,
    ) -> Propagation<'a> {
        let model = Model::new(mission);
        // odometry2d's D(i) follow the headings; the others' are fixed
        // (Model::refresh_displacements).
        let fixed_displacements = model.odometry.is_none();
        let k = mission.detections.len();
        let mut matching = Uf::new(k);
        // Operator matching: detections of one landmark share one variable.
        for g in operator_groups(mission) {
            for &j in &g[1..] {
                matching.union(g[0], j);
            }
        }
        let mut order: Vec<usize> = (0..k).collect();
        let dets = &mission.detections;
        crate::sort::sort_indices_by(&mut order, |a, b| dets[a].step.cmp(&dets[b].step));
        let mut steps = Vec::new();
        let mut starts = Vec::new();
        for (x, &j) in order.iter().enumerate() {
            let t = mission.detections[j].step;
            if steps.last() != Some(&t) {
                steps.push(t);
                starts.push(x);
            }
        }
        starts.push(k);
        let unswept = [vec![false; steps.len()], vec![false; steps.len()]];
        Propagation {
            mission,
            options,
            model,
            matching,
            tol: options.tolerance.max(0.0),
            round: 0,
            contractions: 0,
            order,
            steps,
            starts,
            unswept,
            moving: vec![false; k],
            progress,
            cancel,
            report: Progress {
                detections: k,
                moving: k,
                ..Progress::default()
            },
            work: WorkEstimate::new(k),
            shapes: matches!(
                options.association,
                Association::NVector(Contractor::Best | Contractor::Shapes)
            )
            .then(|| {
                let mut state = ShapesState::new(k);
                state.fixed_displacements = fixed_displacements;
                state.options.threads = options.threads;
                state.options.frames.threads = options.threads;
                state
            }),
            shapes_mission: match mission.seen_from_p() {
                Cow::Owned(seen) => Some(seen),
                Cow::Borrowed(_) => None,
            },
            grid: None,
            scan_map: None,
            pose_memo: ScanPoseMemo::default(),
        }
    }

    /// Reports progress within a round and checks for cancellation.
    pub(super) fn tell(&mut self, pass: &'static str, detections_done: usize) -> Result<(), Halt> {
        // The share of this round done: each pass visits every detection.
        let k = self.mission.detections.len().max(1) as f64;
        let share = match pass {
            "forward" => detections_done as f64 / (2.0 * k),
            "backward" => 0.5 + detections_done as f64 / (2.0 * k),
            _ => 1.0,
        };
        self.report.fraction = self.report.fraction.max(self.work.within(share));
        self.report.round = self.round;
        self.report.pass = pass;
        self.report.detections_done = detections_done;
        (self.progress)(&self.report);
        if self.cancel.load(Ordering::Relaxed) {
            return Err(Halt::Stopped);
        }
        Ok(())
    }

    /// Reports the end of a round: the new diameter, the detections still
    /// moving, and a new estimate of the work left ([`WorkEstimate`]).
    pub(super) fn end_round(&mut self, moving: usize) {
        // The change below which nothing counts as moving: the tolerance
        // on each bound of the moving detections' positions and boxes.
        let floor = self.tol * (4 * self.model.dim * moving) as f64;
        let k = self.mission.detections.len();
        let f = self
            .work
            .end_round_converging(k, moving, width_sum(&self.model), floor);
        let max_d = self.model.max_trajectory_diameter();
        self.report.max_trajectory_diameter = max_d;
        self.report.moving = moving;
        self.report.detections_done = self.mission.detections.len();
        self.report.round = self.round;
        self.report.pass = "round";
        self.report.fraction = self.report.fraction.max(f);
        (self.progress)(&self.report);
    }
}

pub(super) fn pass_name(dir: Direction) -> &'static str {
    match dir {
        Direction::Forward => "forward",
        Direction::Backward => "backward",
    }
}
