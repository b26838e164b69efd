//! The detections contracted inside the passes: when a pass reaches a
//! detection step, each of its detections contracts p(step) and d(j)
//! (Distance, Bearing), or with a sensor offset or an odometry2d heading
//! p(step), th(step) and d(j) together, with the odometry2d association
//! evidence of the pass ([`crate::slam::association::odometry2d`]: the
//! scan pose, the minimum separation, the scan map, the pairs' headings).
//!
//! Soundness: each is a sound contractor (see each file); a box read
//! during a pass holds its landmark at every moment.

use super::propagation::{Halt, Propagation};
use crate::contractors::bearing::contract_bearing;
use crate::contractors::distance::contract_distance;
use crate::contractors::motion_chain::shrinkage;
use crate::interval::Interval;
use crate::odometry::angle::heading_moved;
use crate::odometry::pair_heading::{contract_pair_heading, Seen};
use crate::slam::association::odometry2d::scan_pose_step::scan_pose_step;
use crate::slam::association::odometry2d::sequential::SeparationGrid;
use crate::slam::types::Association;

impl Propagation<'_> {
    /// Contracts the detections at the `s`-th distinct step (Distance,
    /// Bearing) and marks those that moved. Returns whether p(step) moved
    /// by more than the tolerance.
    pub(super) fn contract_detections(&mut self, s: usize) -> Result<bool, Halt> {
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
    /// odometry2d heading ([`crate::slam::model::Model::contract_offset_detection`]): p(step),
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
    pub(super) fn sequential_separation(&self) -> Option<SeparationGrid> {
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
    /// onto the pass's map ([`crate::slam::association::odometry2d::scan_map::ScanMap::settle`]); whether a union was made.
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
        Ok(heading_moved(before, h) > self.tol)
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
                p_moved = p_moved.max(heading_moved(h, m.heading[t]));
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
}
