//! The passes of a round along the motion chain ([`super::rounds`],
//! "Sweeping only what changed"): a sweep starts where a change starts and
//! runs while it moves a bound by more than the tolerance, stopping at each
//! detection step it reaches to contract the detections there
//! ([`super::detections`]).

use super::propagation::{pass_name, Direction, Halt, Propagation};
use crate::contractors::motion_chain::{sweep_backward, sweep_forward, Sweep};
use crate::slam::association::odometry2d::scan_map::ScanMap;

impl Propagation<'_> {
    /// One pass along the chain in direction `dir`: sweeps from every
    /// pending change while it stays above the tolerance, contracting each
    /// detection when the pass reaches its step (see the module doc).
    pub(super) fn pass(&mut self, dir: Direction) -> Result<(), Halt> {
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
}
