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
//! 3. the **association step** (`Propagation::associate`): detections
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
//! below it. The test `propagation_same_fixpoint.rs` compares the boxes,
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

use super::association::scan_map::ScanMap;
use super::association::scan_pose::{scan_pose_step, ScanPoseMemo};
use super::association::separation::separation_unions;
use super::association::sequential::SeparationGrid;
use super::association::tracks::{track_unions, TrackOptions};
use super::association::{Chain, Domains, ShapesState};
use super::mission::Mission;
use super::model::{operator_groups, Model};
use super::types::{Association, Progress, Solution, SolveOptions, SolveStatus, WorkEstimate};
use crate::contractors::bearing::contract_bearing;
use crate::contractors::distance::contract_distance;
use crate::contractors::motion_chain::{shrinkage, sweep_backward, sweep_forward, Sweep};
use crate::interval::Interval;
use crate::nvector::{atmost_nvector, Contractor, Status};
use crate::odometry::chain::OdometryChain;
use crate::odometry::pair_heading::{contract_pair_heading, Seen};
use crate::union_find::Uf;
use std::sync::atomic::{AtomicBool, Ordering};

/// Why propagation ended before its fixpoint: the one way out of every
/// step of a round.
enum Halt {
    /// A domain became empty; the reason names the constraint and variable.
    Infeasible(String),
    /// `max_rounds` reached or cancelled (the boxes are still sound).
    Stopped,
}

/// Which way a pass runs along the chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Direction {
    Forward,
    Backward,
}

/// The state of one propagation: the domains, what was proved, what is
/// left to sweep, and the counters.
struct Propagation<'a> {
    mission: &'a Mission,
    options: &'a SolveOptions,
    model: Model,
    /// Detections proved to see one landmark.
    matching: Uf,
    tol: f64,
    round: u32,
    contractions: u64,
    /// Detections sorted by (step, index).
    order: Vec<usize>,
    /// The distinct detection steps, ascending; the detections at
    /// `steps[s]` are `order[starts[s]..starts[s + 1]]`.
    steps: Vec<usize>,
    starts: Vec<usize>,
    /// Per distinct step: its detections moved p(step) by more than the
    /// tolerance in a backward pass and the change is not yet swept forward
    /// (`unswept[0]`), or in a forward pass and not yet swept backward
    /// (`unswept[1]`).
    unswept: [Vec<bool>; 2],
    /// Per detection: its box or position moved by more than the tolerance
    /// in this round.
    moving: Vec<bool>,
    progress: &'a mut dyn FnMut(&Progress),
    cancel: &'a AtomicBool,
    /// The last report (diameters, moving count, fraction so far).
    report: Progress,
    /// The fraction's estimate (see [`WorkEstimate`]).
    work: WorkEstimate,
    /// Detection shapes (modes `shapes` and `best`).
    shapes: Option<ShapesState>,
    /// With a sensor offset: the mission with each detection restated from
    /// p ([`Mission::seen_from_position`]), which the shapes reasoning reads
    /// (it knows no offset).
    shapes_mission: Option<Mission>,
    /// The minimum separation inside the passes ([`SeparationGrid`]),
    /// rebuilt at the start of each pass; None when the rule is off.
    grid: Option<SeparationGrid>,
    /// The closed-world map of the pass ([`ScanMap`]), with the grid.
    scan_map: Option<ScanMap>,
    /// What the scan pose left at each step ([`ScanPoseMemo`]).
    pose_memo: ScanPoseMemo,
}

impl<'a> Propagation<'a> {
    fn new(
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
                state
            }),
            shapes_mission: mission
                .sensor_offset
                .is_some_and(|o| o != [0.0, 0.0])
                .then(|| mission.seen_from_position()),
            grid: None,
            scan_map: None,
            pose_memo: ScanPoseMemo::default(),
        }
    }

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

    /// One pass along the chain in direction `dir`: sweeps from every
    /// pending change while it stays above the tolerance, contracting each
    /// detection when the pass reaches its step (see the module doc).
    fn pass(&mut self, dir: Direction) -> Result<(), Halt> {
        let count = self.steps.len();
        let (this_way, other_way) = match dir {
            Direction::Forward => (0, 1),
            Direction::Backward => (1, 0),
        };
        let stride = count.div_ceil(32).max(1);
        self.grid = self.sequential_separation();
        self.scan_map = self.grid.as_ref().and_then(|_| {
            let n = self.mission.landmark_count?;
            ScanMap::new(self.mission, &self.model.det, &mut self.matching, n)
        });
        // Where a change still propagates from, and the detection that
        // started it (named if the chain empties).
        let mut alive: Option<(usize, usize)> = None;
        for x in 0..count {
            let s = match dir {
                Direction::Forward => x,
                Direction::Backward => count - 1 - x,
            };
            let t = self.steps[s];
            if let Some((from, origin)) = alive {
                alive = self.sweep(from, t, dir, origin)?.then_some((t, origin));
            }
            let moved_position = self.contract_detections(s)?;
            if moved_position {
                self.unswept[other_way][s] = true;
            }
            if std::mem::take(&mut self.unswept[this_way][s]) || moved_position {
                alive = Some((t, self.order[self.starts[s]]));
            }
            if (x + 1) % stride == 0 {
                let done = match dir {
                    Direction::Forward => self.starts[s + 1],
                    Direction::Backward => self.order.len() - self.starts[s],
                };
                self.tell(pass_name(dir), done)?;
            }
        }
        if let Some((from, origin)) = alive {
            let end = match dir {
                Direction::Forward => self.model.steps,
                Direction::Backward => 0,
            };
            self.sweep(from, end, dir, origin)?;
        }
        Ok(())
    }

    /// Sweeps the chain from step `from` towards step `to` while the change
    /// stays above the tolerance; `origin` is the detection whose change it
    /// carries. Returns whether the change is still alive at `to`.
    fn sweep(
        &mut self,
        from: usize,
        to: usize,
        dir: Direction,
        origin: usize,
    ) -> Result<bool, Halt> {
        let dim = self.model.dim;
        if let Some(chain) = &self.model.odometry {
            let (pos, heading) = (&mut self.model.pos, &mut self.model.heading);
            let outcome = match dir {
                Direction::Forward => chain.sweep_forward_flat(pos, heading, from, to, self.tol),
                Direction::Backward => chain.sweep_backward_flat(pos, heading, from, to, self.tol),
            };
            return self.swept(outcome, from, to, 0, origin);
        }
        let (pos, disp) = (&mut self.model.pos, &self.model.disp);
        let (outcome, offset) = match dir {
            Direction::Forward => (
                sweep_forward(
                    &mut pos[..(to + 1) * dim],
                    &disp[..to * dim],
                    dim,
                    from,
                    self.tol,
                ),
                0,
            ),
            Direction::Backward => (
                sweep_backward(
                    &mut pos[to * dim..],
                    &disp[to * dim..],
                    dim,
                    from - to,
                    self.tol,
                ),
                to,
            ),
        };
        self.swept(outcome, from, to, offset, origin)
    }

    /// The outcome of a sweep from `from` to `to` (`offset`: the first
    /// state of the slice swept) as [`Propagation::sweep`] returns it.
    fn swept(
        &mut self,
        outcome: Sweep,
        from: usize,
        to: usize,
        offset: usize,
        origin: usize,
    ) -> Result<bool, Halt> {
        match outcome {
            Sweep::Done(visited) => {
                self.contractions += visited as u64;
                Ok(visited == from.abs_diff(to))
            }
            Sweep::Empty(s) => {
                let t = self.mission.detections[origin].step;
                Err(Halt::Infeasible(format!(
                    "motion chain: the position of step {} is empty (propagating detection {origin} at step {t})",
                    s + offset
                )))
            }
        }
    }

    /// Contracts the detections at the `s`-th distinct step (Distance,
    /// Bearing) and marks those that moved. Returns whether p(step) moved
    /// by more than the tolerance.
    fn contract_detections(&mut self, s: usize) -> Result<bool, Halt> {
        let t = self.steps[s];
        let dim = self.model.dim;
        let mut moved_position = false;
        if !self.model.plain_detections() {
            return self.contract_offset_detections(s);
        }
        for x in self.starts[s]..self.starts[s + 1] {
            let j = self.order[x];
            let det = &self.mission.detections[j];
            let p = &mut self.model.pos[t * dim..(t + 1) * dim];
            let d = &mut self.model.det[j];
            let mut before = [Interval::EMPTY; 3];
            before[..dim].copy_from_slice(p);
            let mut d_before = [Interval::EMPTY; 3];
            d_before[..dim].copy_from_slice(d.axes());
            let mut range = det.range;
            let ok = contract_distance(p, d.axes_mut(), &mut range)
                && det.bearing.is_none_or(|b| {
                    contract_bearing(p, d.axes_mut(), self.model.heading_at[j], b, range)
                });
            self.contractions += 1;
            if !ok || d.is_empty() {
                d.set_empty();
                return Err(Halt::Infeasible(format!(
                    "detection {j} (step {t}): range {} cannot reach any landmark position",
                    det.range
                )));
            }
            let p_moved = (0..dim)
                .map(|a| shrinkage(before[a], p[a]))
                .fold(0.0, f64::max);
            let d_moved = (0..dim)
                .map(|a| shrinkage(d_before[a], d[a]))
                .fold(0.0, f64::max);
            if p_moved > self.tol {
                moved_position = true;
            }
            if p_moved > self.tol || d_moved > self.tol {
                self.moving[j] = true;
            }
        }
        Ok(moved_position)
    }

    /// [`Propagation::contract_detections`] for a sensor offset or an
    /// odometry2d heading ([`Model::contract_offset_detection`]): p(step),
    /// th(step) and d(j). Returns whether p(step) or th(step) moved by more
    /// than the tolerance (both are swept along the chain).
    fn contract_offset_detections(&mut self, s: usize) -> Result<bool, Halt> {
        let moved = self.offset_detections_once(s)? | self.scan_pose(s)?;
        let merged = self.separate_in_pass(s)? | self.scan_map_in_pass(s)?;
        if !self.pair_headings(s)? && !merged {
            return Ok(moved);
        }
        self.offset_detections_once(s)?;
        if merged {
            self.pair_headings(s)?;
            self.offset_detections_once(s)?;
        }
        Ok(true)
    }

    /// The step's detections, p and th contracted together
    /// ([`scan_pose_step`]), with the rounds' condition of the grid.
    fn scan_pose(&mut self, s: usize) -> Result<bool, Halt> {
        if self.grid.is_none() {
            return Ok(false);
        }
        let at = &self.order[self.starts[s]..self.starts[s + 1]];
        let (moved, pose) = scan_pose_step(
            self.mission,
            &mut self.model,
            &mut self.matching,
            &mut self.pose_memo,
            at,
            self.steps[s],
            self.tol,
        )
        .map_err(Halt::Infeasible)?;
        self.contractions += 1;
        moved.iter().for_each(|&j| self.moving[j] = true);
        Ok(pose)
    }

    /// The grid of [`SeparationGrid`] for a pass: odometry2d with a
    /// minimum separation, an association contractor and no false
    /// detections (the rounds' own condition); else None.
    fn sequential_separation(&self) -> Option<SeparationGrid> {
        if self.model.odometry.is_none()
            || self.options.association == Association::None
            || self.mission.max_outliers > 0
        {
            return None;
        }
        SeparationGrid::new(
            self.mission.detections.len(),
            self.mission.landmark_min_separation,
        )
    }

    /// The detections at the `s`-th distinct step compared with the
    /// groups' boxes so far ([`SeparationGrid::merge`]); whether a union
    /// was made (its detections count as moving).
    fn separate_in_pass(&mut self, s: usize) -> Result<bool, Halt> {
        let Some(grid) = self.grid.as_mut() else {
            return Ok(false);
        };
        let mut merged = false;
        for x in self.starts[s]..self.starts[s + 1] {
            let j = self.order[x];
            let unions = grid
                .merge(&mut self.model.det, &mut self.matching, j)
                .map_err(Halt::Infeasible)?;
            self.contractions += 1;
            for (a, b) in unions {
                self.moving[a] = true;
                self.moving[b] = true;
                merged = true;
            }
        }
        Ok(merged)
    }

    /// The detections at the `s`-th distinct step, scan by scan, matched
    /// onto the pass's map ([`ScanMap::settle`]); whether a union was made.
    fn scan_map_in_pass(&mut self, s: usize) -> Result<bool, Halt> {
        let Some(map) = self.scan_map.as_ref() else {
            return Ok(false);
        };
        let mut at: Vec<usize> = self.order[self.starts[s]..self.starts[s + 1]].to_vec();
        let dets = &self.mission.detections;
        crate::sort::stable_by_key(&mut at, |&j| (dets[j].scan, j));
        let mut merged = false;
        for scan in at.chunk_by(|&a, &b| dets[a].scan.is_some() && dets[a].scan == dets[b].scan) {
            let unions = map
                .settle(self.mission, &self.model.det, &mut self.matching, scan)
                .map_err(Halt::Infeasible)?;
            self.contractions += 1;
            for (a, b) in unions {
                let root = self.matching.union(a, b);
                let common = self.model.det[a].intersect(&self.model.det[b]);
                if common.is_empty() {
                    return Err(Halt::Infeasible(format!(
                        "detection {a}: its box and its scan-matched group's (detection {b}) have no common point"
                    )));
                }
                for j in [a, b, root] {
                    self.model.det[j] = common.clone();
                    self.moving[j] = true;
                }
                merged = true;
            }
        }
        Ok(merged)
    }

    /// odometry2d: th(step) contracted by every pair of the step's
    /// detections ([`contract_pair_heading`]); whether it moved by more
    /// than the tolerance. O(c²) for c detections at the step.
    fn pair_headings(&mut self, s: usize) -> Result<bool, Halt> {
        let t = self.steps[s];
        let range = self.starts[s]..self.starts[s + 1];
        if self.model.odometry.is_none() || range.len() < 2 {
            return Ok(false);
        }
        let seen: Vec<Seen> = self.order[range]
            .iter()
            .map(|&j| {
                let d = &self.mission.detections[j];
                Seen {
                    landmark: [self.model.det[j][0], self.model.det[j][1]],
                    range: d.range,
                    bearing: d.bearing,
                }
            })
            .collect();
        let before = self.model.heading[t];
        let mut h = before;
        for (x, a) in seen.iter().enumerate() {
            for b in &seen[x + 1..] {
                h = contract_pair_heading(h, a, b);
            }
        }
        self.contractions += (seen.len() * (seen.len() - 1) / 2) as u64;
        if h.is_empty() {
            return Err(Halt::Infeasible(format!(
                "heading of step {t}: no heading turns the constellation of its detections onto their landmark boxes"
            )));
        }
        self.model.heading[t] = h;
        Ok(shrinkage(before, h) > self.tol)
    }

    /// One contraction of each detection at the `s`-th distinct step
    /// (see [`Propagation::contract_offset_detections`]).
    fn offset_detections_once(&mut self, s: usize) -> Result<bool, Halt> {
        let t = self.steps[s];
        let mut moved_position = false;
        for x in self.starts[s]..self.starts[s + 1] {
            let j = self.order[x];
            let root = self.matching.find(j);
            let m = &mut self.model;
            let d_before = [m.det[j][0], m.det[j][1]];
            if root != j {
                // A sequential filter: the group's landmark box so far
                // (held at its root) bounds this member's before it is read.
                let (lo, hi) = m.det.split_at_mut(j.max(root));
                let (a, b) = if root < j {
                    (&lo[root], &mut hi[0])
                } else {
                    (&hi[0], &mut lo[j])
                };
                b.intersect_with(a);
            }
            let before = (m.pos[2 * t], m.pos[2 * t + 1], m.heading.get(t).copied());
            let ok = m.contract_offset_detection(self.mission, j);
            self.contractions += 1;
            if !ok || m.det[j].is_empty() {
                m.det[j].set_empty();
                return Err(Halt::Infeasible(format!(
                    "detection {j} (step {t}): range {} cannot reach any landmark position",
                    self.mission.detections[j].range
                )));
            }
            let mut p_moved =
                shrinkage(before.0, m.pos[2 * t]).max(shrinkage(before.1, m.pos[2 * t + 1]));
            if let Some(h) = before.2 {
                p_moved = p_moved.max(shrinkage(h, m.heading[t]));
            }
            let d_moved =
                shrinkage(d_before[0], m.det[j][0]).max(shrinkage(d_before[1], m.det[j][1]));
            if root != j {
                let r_before = [m.det[root][0], m.det[root][1]];
                let dj = m.det[j].clone();
                m.det[root].intersect_with(&dj);
                if m.det[root].is_empty() {
                    return Err(Halt::Infeasible(format!(
                        "landmark of detection {j} (step {t}) and its group (detection {root}): their boxes have no common point"
                    )));
                }
                let r_moved = shrinkage(r_before[0], m.det[root][0])
                    .max(shrinkage(r_before[1], m.det[root][1]));
                if r_moved > self.tol {
                    self.moving[root] = true;
                }
            }
            if p_moved > self.tol {
                moved_position = true;
            }
            if p_moved > self.tol || d_moved > self.tol {
                self.moving[j] = true;
            }
        }
        Ok(moved_position)
    }

    /// The association step of a round: ties the detection variables
    /// together. Proved groups (the operator's, then those atmost_nvector
    /// proved) share one variable: their boxes are intersected. Then
    /// atmost_nvector(n) with the chosen contractor contracts every
    /// detection box and proves new groups. A detection whose box moves by
    /// more than the tolerance is marked moving; the passes of the next
    /// round carry its change to p(step) and along the chain.
    ///
    /// Further association contractors (detection shapes, robust handling
    /// of false detections) belong here: one that shrinks a position
    /// p(steps[s]) must set `unswept[0][s]` and `unswept[1][s]` so the
    /// next passes sweep from it.
    fn associate(&mut self) -> Result<(), Halt> {
        self.associate_groups()?;
        self.separation_step()
    }

    /// The minimum separation (`landmark_min_separation`): groups whose
    /// boxes fit in a set of diameter below it are one landmark
    /// ([`separation_unions`]); the detections of a union count as moving,
    /// so that the next round intersects their boxes. Not for `none` (the
    /// basic model uses the operator's fields only).
    fn separation_step(&mut self) -> Result<(), Halt> {
        let s = self.mission.landmark_min_separation;
        if self.options.association == Association::None || s <= 0.0 {
            return Ok(());
        }
        let unions =
            separation_unions(&self.model.det, &mut self.matching, s).map_err(Halt::Infeasible)?;
        self.contractions += 1;
        for (a, b) in unions {
            self.moving[a] = true;
            self.moving[b] = true;
        }
        Ok(())
    }

    /// The groups and atmost_nvector part of [`Propagation::associate`].
    fn associate_groups(&mut self) -> Result<(), Halt> {
        let dim = self.model.dim;
        let groups = self.matching.groups();
        for g in &groups {
            let mut common = self.model.det[g[0]].clone();
            for &j in &g[1..] {
                common.intersect_with(&self.model.det[j]);
            }
            if common.is_empty() {
                return Err(Halt::Infeasible(format!(
                    "landmark of detections {g:?}: their boxes have no common point (a wrong matching?)"
                )));
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
            self.contractions += 1;
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
        self.contractions += 1;
        if let Status::Infeasible { reason } = out.status {
            return Err(Halt::Infeasible(format!(
                "atmost_nvector({nl}) over the detections: {reason}"
            )));
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
    fn shapes_step(&mut self, n: usize) -> Result<(), Halt> {
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
        } = &mut self.model;
        let mut chain = ShapesChain {
            disp,
            dim: *dim,
            tol: self.tol,
            steps: &self.steps,
            unswept: &mut self.unswept,
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
            self.shapes_mission.as_ref().unwrap_or(self.mission),
            domains,
            &groups,
            Some(n),
            q,
            self.tol,
            &mut chain,
        );
        self.contractions += out.contractions + chain.swept;
        if let Some(reason) = out.infeasible {
            return Err(Halt::Infeasible(reason));
        }
        for &(a, b) in &out.unions {
            self.matching.union(a, b);
        }
        for &j in &out.moved_detections {
            self.moving[j] = true;
        }
        // A position the round shrank (a registration, a branch) is flagged
        // for the next passes' sweeps; its detections count as moving, so
        // that the round loop goes on to sweep it (issue 19: a run could end
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

    /// Reports progress within a round and checks for cancellation.
    fn tell(&mut self, pass: &'static str, detections_done: usize) -> Result<(), Halt> {
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
    fn end_round(&mut self, moving: usize) {
        let f = self.work.end_round(moving);
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

fn pass_name(dir: Direction) -> &'static str {
    match dir {
        Direction::Forward => "forward",
        Direction::Backward => "backward",
    }
}

/// The rounds of this module from dead reckoning to the fixpoint (or a
/// halt), for a mission without false detections (`max_outliers` 0; the
/// robust propagation of [`super::outliers`] handles the others).
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
/// `ShapesState::full_work`), the schedule before issue 18. The tests
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
