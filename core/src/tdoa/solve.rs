//! The TDOA pipeline: per-pulse readings ([`super::readings`]), the
//! operator's matching, and atmost_nvector over the pulses' positions
//! ([`crate::nvector`]), in rounds to a fixpoint.
//!
//! # Constraint
//!
//! Every arrival, cut and operator label of the problem, and, with
//! `emitter_count` = n, atmost_nvector(n, {x_1..x_K}) (static emitters).
//!
//! # Math
//!
//! A round: (1) each pulse's box becomes the hull of its readings' pavings
//! (with q = 0 one reading, every arrival); (2) pulses of one operator id
//! and of one proved group get the intersection of their positions; (3)
//! atmost_nvector contracts the positions and proves groups, merged across
//! rounds with a union-find. Rounds stop when no box shrinks by more than
//! [`super::pulse::SHRINK`] of its width, or at `max_rounds`.
//!
//! # Soundness
//!
//! Each step keeps every solution of every reading (docs/outliers.md): the
//! readings' hull encloses them; an operator label and a proved group are
//! equalities that hold in every reading (the boxes enclose every reading's
//! positions, so a group proved on them holds in each); atmost_nvector
//! holds in every reading, as no reading drops a pulse.
//!
//! # Complexity
//!
//! Per round, K pavings (times the readings with q > 0) and one
//! atmost_nvector contraction of K boxes of dimension 3.

use super::arrival::PulseVars;
use super::problem::TdoaProblem;
use super::readings::{hull, least_drops};
use super::shell_step::ShellStep;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::nvector::{atmost_nvector, Contractor, Status};
use crate::union_find::Uf;

/// How to solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TdoaOptions {
    /// The atmost_nvector contractor (`None`: no nvector, the operator's
    /// matching only).
    pub mode: Option<Contractor>,
    /// Bisections of each pulse's paving.
    pub budget: usize,
    /// Most rounds.
    pub max_rounds: usize,
}

impl Default for TdoaOptions {
    fn default() -> Self {
        TdoaOptions {
            mode: Some(Contractor::Best),
            budget: super::pulse::DEFAULT_BUDGET,
            max_rounds: 8,
        }
    }
}

/// What a solve proved.
#[derive(Debug, Clone, PartialEq)]
pub struct TdoaSolution {
    /// Per pulse, its emitter's position and its emission time.
    pub vars: Vec<PulseVars>,
    /// Groups of pulses proved to share an emitter (size >= 2), each
    /// sorted, by smallest index.
    pub groups: Vec<Vec<usize>>,
    /// `Some(reason)` when the problem is proved infeasible.
    pub infeasible: Option<String>,
    /// Rounds run.
    pub rounds: usize,
    /// Whether `max_rounds` or the caller (`go_on`: a time limit) ended the
    /// rounds while they still shrank the boxes: no fixpoint, the boxes
    /// are sound but not the fixpoint's (status `"stopped"`).
    pub stopped: bool,
}

struct Run<'a> {
    p: &'a TdoaProblem,
    o: TdoaOptions,
    vars: Vec<PulseVars>,
    /// Per pulse, the range of its arrivals a sub-problem may drop.
    drops: Vec<(usize, usize)>,
    uf: Uf,
}

fn total_width(v: &[PulseVars]) -> f64 {
    v.iter()
        .flat_map(|p| p.x.iter().chain([&p.tau]))
        .map(|a| a.width().min(1e290))
        .sum()
}

impl Run<'_> {
    /// The rounds to their fixpoint (a round shrinks no box by more than
    /// [`super::pulse::SHRINK`] of the total width), to an empty box, to
    /// `max_rounds` or until `go_on` says stop: (rounds run, the reason of
    /// an infeasibility, whether the rounds stopped before the fixpoint).
    fn rounds(&mut self, go_on: &mut dyn FnMut(usize) -> bool) -> (usize, Option<String>, bool) {
        let mut rounds = 0;
        let mut infeasible = None;
        // Until a round shrinks nothing more (the fixpoint), a cap or the
        // caller stops the rounds early.
        let mut stopped = true;
        while rounds < self.o.max_rounds.max(1) {
            if rounds > 0 && !go_on(rounds) {
                break;
            }
            rounds += 1;
            let before = total_width(&self.vars);
            let step = self
                .readings()
                .and_then(|_| self.share())
                .and_then(|_| self.nvector())
                .and_then(|_| self.share())
                .and_then(|_| self.shells())
                .and_then(|_| self.share());
            if let Err(e) = step {
                infeasible = Some(e);
                stopped = false;
                break;
            }
            let after = total_width(&self.vars);
            // NaN (unbounded widths) ends the rounds too.
            let shrank = before - after > super::pulse::SHRINK * before;
            if !shrank {
                stopped = false;
                break;
            }
        }
        (rounds, infeasible, stopped)
    }

    /// Step 1: every pulse's box becomes the hull of its readings.
    fn readings(&mut self) -> Result<(), String> {
        let q = self.p.max_outliers;
        let k = self.p.pulses.len();
        let mut least = vec![0usize; k];
        if q > 0 {
            for (j, d) in least.iter_mut().enumerate() {
                *d = least_drops(self.p, j, self.vars[j], q, self.o.budget).ok_or_else(|| {
                    format!("pulses[{j}]: no reading dropping at most {q} arrivals")
                })?;
            }
        }
        let spent: usize = least.iter().sum();
        if spent > q {
            return Err(format!(
                "at least {spent} arrivals must be false, max_outliers = {q}"
            ));
        }
        for (j, &d) in least.iter().enumerate() {
            let hi = q - (spent - d);
            self.drops[j] = (d, hi);
            self.vars[j] = hull(self.p, j, self.vars[j], d, hi, self.o.budget)
                .ok_or_else(|| format!("pulses[{j}]: its arrivals cannot hold together"))?;
        }
        Ok(())
    }

    /// Step 2: intersect the positions of each group (operator ids and
    /// proved groups, all in the union-find).
    fn share(&mut self) -> Result<(), String> {
        for g in self.uf.groups() {
            let mut x = [Interval::ENTIRE; 3];
            for &j in &g {
                for (a, b) in x.iter_mut().zip(self.vars[j].x) {
                    *a = a.intersect(b);
                }
            }
            if x.iter().any(|a| a.is_empty()) {
                return Err(format!(
                    "pulses {g:?} share an emitter but their positions do not meet"
                ));
            }
            for &j in &g {
                self.vars[j].x = x;
            }
        }
        Ok(())
    }

    /// Step 3: atmost_nvector over the positions.
    fn nvector(&mut self) -> Result<(), String> {
        let (Some(mode), Some(n)) = (self.o.mode, self.p.emitter_count) else {
            return Ok(());
        };
        let mut boxes: Vec<IntervalBox> =
            self.vars.iter().map(|v| IntervalBox::new(&v.x)).collect();
        let out = atmost_nvector(n, &mut boxes, mode).map_err(|e| e.to_string())?;
        if let Status::Infeasible { reason } = out.status {
            return Err(reason);
        }
        for (v, b) in self.vars.iter_mut().zip(&boxes) {
            v.x.copy_from_slice(b.axes());
        }
        for g in out.groups.iter().filter(|g| g.len() > 1) {
            for w in g.windows(2) {
                self.uf.union(w[0], w[1]);
            }
        }
        Ok(())
    }

    /// Step 4 (`best`, `shapes`): the pulses' hyperbolic shells as
    /// detection shapes (regions, witnesses, branch contraction).
    fn shells(&mut self) -> Result<(), String> {
        let (Some(Contractor::Best | Contractor::Shapes), Some(n)) =
            (self.o.mode, self.p.emitter_count)
        else {
            return Ok(());
        };
        ShellStep {
            problem: self.p,
            emitter_count: n,
            vars: &mut self.vars,
            drops: &self.drops,
            uf: &mut self.uf,
        }
        .run()
    }
}

/// Solves `p`: boxes of every pulse's emitter and emission time, the
/// groups proved, or a proof of infeasibility.
pub fn solve_tdoa(p: &TdoaProblem, o: &TdoaOptions) -> TdoaSolution {
    solve_tdoa_with(p, o, &mut |_| true)
}

/// [`solve_tdoa`], asking `go_on(rounds done)` before every round after
/// the first: `false` stops the rounds there (a time limit, a
/// cancellation). The boxes after any whole round enclose every solution
/// (each round only contracts sound enclosures), so a solution stopped
/// early is sound, only wider.
pub fn solve_tdoa_with(
    p: &TdoaProblem,
    o: &TdoaOptions,
    go_on: &mut dyn FnMut(usize) -> bool,
) -> TdoaSolution {
    let k = p.pulses.len();
    let start = PulseVars {
        x: [Interval::ENTIRE; 3],
        tau: Interval::ENTIRE,
    };
    let mut run = Run {
        p,
        o: *o,
        vars: vec![start; k],
        drops: vec![(0, 0); k],
        uf: Uf::new(k),
    };
    // The first pulse of each operator id (a map: ids go up to
    // emitter_count, which the input's size does not bound).
    let mut first = std::collections::BTreeMap::new();
    for (j, pulse) in p.pulses.iter().enumerate() {
        if let Some(e) = pulse.emitter {
            let f = *first.entry(e).or_insert(j);
            if f != j {
                run.uf.union(f, j);
            }
        }
    }
    let (rounds, infeasible, stopped) = run.rounds(go_on);
    let groups = if infeasible.is_some() {
        run.vars.iter_mut().for_each(|v| {
            *v = PulseVars {
                x: [Interval::EMPTY; 3],
                tau: Interval::EMPTY,
            }
        });
        Vec::new()
    } else {
        run.uf
            .groups()
            .into_iter()
            .filter(|g| g.len() > 1)
            .collect()
    };
    TdoaSolution {
        vars: run.vars,
        groups,
        infeasible,
        rounds,
        stopped,
    }
}
