//! The shapes step of the TDOA rounds (`best`, `shapes`): the pulses'
//! hyperbolic shells ([`super::shell`]) through the shapes machinery —
//! emitter regions, witnesses, branch contraction ([`crate::shapes`]).
//!
//! # Constraint
//!
//! Each pulse's emitter position x_k lies in its shell S(k); the pulses of
//! a proved group share one emitter; atmost_nvector(n, {x_1..x_K}).
//!
//! # Math
//!
//! 1. **Regions.** A proved group G's emitter lies in `∩_{k ∈ G} S(k)`:
//!    a [`Paving`] of the group's box cut by its [`REGION_SHELLS`] thinnest
//!    members' shells and refined to [`REGION_BOXES`] boxes. The members'
//!    boxes are cut to the region's hull; an empty region is infeasible.
//! 2. **Witnesses.** Pairwise-disjoint items (regions, then the shells of
//!    pulses in no group, at most [`SHELL_POOL`] of them, thinnest first)
//!    are distinct emitters ([`find_witnesses`]): more than n is
//!    infeasible.
//! 3. **Branches.** With exactly n witnesses every emitter is one of
//!    theirs, so every other pulse's x lies in one of the n witness
//!    regions (a witness shell's region is its own paving):
//!    [`branch_pieces`] contracts (x, tau) to the hull of the surviving
//!    pieces; no survivor is infeasible; one survivor proves the pulse's
//!    emitter (a group with the witness).
//!
//! # Soundness
//!
//! Every step keeps every solution of every allowed sub-problem
//! (docs/outliers.md): a shell is the union over the pulse's readings
//! ([`super::shell`]), so a region encloses the group's emitter in every
//! sub-problem; disjoint items hold distinct emitters in each, so n of
//! them name all n emitters (atmost_nvector) and the true emitter of any
//! pulse lies in one witness region: the branch holding it survives
//! ([`crate::shapes::branch`]). A single survivor is the true emitter's.
//!
//! # Complexity
//!
//! Per call: G regions of at most [`REGION_BOXES`] boxes, each cut by at
//! most [`REGION_SHELLS`] shells; the witnesses' pair tests (box tests for
//! regions, paved shell tests for at most [`SHELL_POOL`] shells); K branch
//! contractions of one shell over at most n · [`REGION_BOXES`] boxes. A
//! shell test is a pulse fixpoint per reading.

use super::arrival::PulseVars;
use super::problem::TdoaProblem;
use super::shell::PulseShell;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::branch::branch_pieces;
use crate::shapes::region::Paving;
use crate::shapes::shape::DetectionShape;
use crate::shapes::witnesses::{find_witnesses, Item};
use crate::union_find::Uf;

/// Most boxes of a region's paving.
pub const REGION_BOXES: usize = 32;
/// Members' shells (the thinnest) cutting a region.
pub const REGION_SHELLS: usize = 4;
/// Most shells of ungrouped pulses offered as witnesses.
pub const SHELL_POOL: usize = 24;
/// Node budget of the witnesses' clique search.
const NODE_BUDGET: usize = 20_000;

/// The state the step reads and contracts.
pub struct ShellStep<'a> {
    /// The problem.
    pub problem: &'a TdoaProblem,
    /// n.
    pub emitter_count: usize,
    /// Per pulse, its boxes (contracted).
    pub vars: &'a mut [PulseVars],
    /// Per pulse, the range of its arrivals a sub-problem may drop.
    pub drops: &'a [(usize, usize)],
    /// Proved groups (joined).
    pub uf: &'a mut Uf,
}

/// A group's region (module doc, 1).
fn region(shells: &[PulseShell], g: &[usize]) -> Paving {
    let mut members: Vec<&PulseShell> = g.iter().map(|&j| &shells[j]).collect();
    crate::sort::sort_by(&mut members, |a, b| {
        a.thickness()
            .total_cmp(&b.thickness())
            .then(a.pulse().cmp(&b.pulse()))
    });
    let mut x = [Interval::ENTIRE; 3];
    for m in &members {
        for (a, b) in x.iter_mut().zip(m.vars().x) {
            *a = a.intersect(b);
        }
    }
    let mut r = Paving::from_box(&IntervalBox::new(&x));
    members.truncate(REGION_SHELLS);
    for s in &members {
        r.cut(*s);
    }
    r.refine(&members, 0.0, REGION_BOXES);
    r
}

impl ShellStep<'_> {
    /// Runs the step (module doc); `Err` names what proves the problem
    /// infeasible.
    pub fn run(&mut self) -> Result<(), String> {
        let (p, k) = (self.problem, self.vars.len());
        let shells: Vec<PulseShell> = (0..k)
            .map(|j| PulseShell::new(p, j, self.vars[j], self.drops[j].0, self.drops[j].1))
            .collect();
        let groups = self.uf.groups();
        let mut regions = Vec::with_capacity(groups.len());
        let mut grouped = vec![false; k];
        for g in &groups {
            let r = region(&shells, g);
            if r.is_empty() {
                return Err(format!(
                    "pulses {g:?} share an emitter but their shells do not meet"
                ));
            }
            let h = r.hull();
            for &j in g {
                grouped[j] = true;
                for (a, b) in self.vars[j].x.iter_mut().zip(h.axes()) {
                    *a = a.intersect(*b);
                }
            }
            regions.push(r);
        }
        let singles: Vec<usize> = (0..k).filter(|&j| !grouped[j]).collect();
        let chosen = self.witnesses(&shells, &regions, &singles);
        let n = self.emitter_count;
        // Witness i: a region (index < regions.len()) or a single's shell.
        let name = |i: usize| match i.checked_sub(regions.len()) {
            None => groups[i][0],
            Some(s) => singles[s],
        };
        if chosen.len() > n {
            let names: Vec<usize> = chosen.iter().map(|&i| name(i)).collect();
            return Err(format!(
                "pulses {names:?} (or their groups) are pairwise proved to come from \
                 distinct emitters: more than emitter_count = {n}"
            ));
        }
        if chosen.len() < n || n == 0 {
            return Ok(());
        }
        let pavings: Vec<Paving> = chosen
            .iter()
            .map(|&i| match i.checked_sub(regions.len()) {
                None => regions[i].clone(),
                Some(s) => shells[singles[s]].paving(0.0, REGION_BOXES),
            })
            .collect();
        let refs: Vec<&Paving> = pavings.iter().collect();
        let reps: Vec<usize> = chosen.iter().map(|&i| name(i)).collect();
        self.branches(&shells, &refs, &reps)
    }

    /// Up to n + 1 pairwise-disjoint items: regions first, then (when
    /// fewer than n) the thinnest singles' shells too.
    fn witnesses(
        &self,
        shells: &[PulseShell],
        regions: &[Paving],
        singles: &[usize],
    ) -> Vec<usize> {
        let want = self.emitter_count + 1;
        let mut items: Vec<Item<PulseShell>> = regions.iter().map(Item::Region).collect();
        let mut sizes: Vec<(u8, f64)> = items.iter().map(|i| i.size()).collect();
        let first = find_witnesses(
            &sizes,
            &mut |a, b| items[a].disjoint(&items[b]),
            want,
            &[],
            NODE_BUDGET,
        );
        if first.len() >= self.emitter_count || singles.is_empty() {
            return first;
        }
        // Positions in `singles`, thinnest shell first; only the first
        // SHELL_POOL are offered (item regions.len() + t is order[t]).
        let mut order: Vec<usize> = (0..singles.len()).collect();
        crate::sort::sort_by(&mut order, |&a, &b| {
            let (sa, sb) = (&shells[singles[a]], &shells[singles[b]]);
            sa.thickness().total_cmp(&sb.thickness()).then(a.cmp(&b))
        });
        order.truncate(SHELL_POOL);
        let mut idx: Vec<usize> = (0..regions.len()).collect();
        for &s in &order {
            let sh = &shells[singles[s]];
            items.push(Item::Shape(sh));
            sizes.push((1, sh.thickness()));
            idx.push(regions.len() + s);
        }
        let found = find_witnesses(
            &sizes,
            &mut |a, b| items[a].disjoint(&items[b]),
            want,
            &first,
            NODE_BUDGET,
        );
        found.into_iter().map(|i| idx[i]).collect()
    }

    /// Branch contraction of every pulse outside the witnesses onto their
    /// regions `refs` (witness i's representative pulse `reps[i]`).
    fn branches(
        &mut self,
        shells: &[PulseShell],
        refs: &[&Paving],
        reps: &[usize],
    ) -> Result<(), String> {
        let k = self.vars.len();
        let roots: Vec<usize> = reps.iter().map(|&r| self.uf.find(r)).collect();
        let witness_of: Vec<Option<usize>> = (0..k)
            .map(|j| {
                let rj = self.uf.find(j);
                roots.iter().position(|&r| r == rj)
            })
            .collect();
        for (j, w) in witness_of.iter().enumerate() {
            if w.is_some() {
                continue;
            }
            let (hull, surviving) = branch_pieces(&shells[j], refs);
            let Some(h) = hull else {
                return Err(format!(
                    "pulses[{j}]: its shell meets none of the {} emitters' regions proved distinct",
                    refs.len()
                ));
            };
            let v = &mut self.vars[j];
            for (a, b) in v.x.iter_mut().zip(h.x) {
                *a = a.intersect(b);
            }
            v.tau = v.tau.intersect(h.tau);
            if v.is_empty() {
                return Err(format!("pulses[{j}]: no emitter position is left"));
            }
            if let [i] = surviving[..] {
                self.uf.union(reps[i], j);
            }
        }
        Ok(())
    }
}
