//! Step 5 of a shapes round: registration of the groups' local frames on
//! the n witness regions ([`register`]). At the steps of the groups'
//! pieces (one every `register_every` steps), the pieces within
//! `register_gap` steps, moved to the frame of that step, must fit the n
//! witness regions under a map that gives distinct groups distinct
//! witnesses: p(step) shrinks to the positions where such a map exists,
//! and a group left with one witness over every registration joins it (the
//! witnesses it cannot be are distinct pairs).
//!
//! Soundness: [`register`] keeps every position at which the true
//! landmarks fit (crate::shapes::registration); an answer is carried over
//! from an earlier round only while its inputs are close ([`RegKey`]).
//! Complexity: O(a · G · n · c² · B · d) (a registration steps, at most G
//! = `register_groups` groups each, pavings coarsened to c boxes, B paving
//! boxes of p(step)).

use super::round::Round;
use super::state::{CoarsePieces, RegKey, ShapesOptions, ShapesState};
use super::witness_step::Witnesses;
use crate::contractors::motion_chain::shrinkage;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::chain_sums::ChainSums;
use crate::shapes::region::Paving;
use crate::shapes::registration::{
    coarsen_piece, register_on, CoarseWitnesses, LocalGroup, Registration,
};

/// What a round's registrations read (the tuning, the distinct graph, the
/// coarsened witness regions), the cache of earlier answers by step, and what they
/// gather: per group root, the mask of the witnesses it may see.
struct Registrations<'a> {
    options: &'a ShapesOptions,
    graph: crate::shapes::distinct::Graph,
    /// The witness regions, coarsened once for the round's registrations.
    witnesses: CoarseWitnesses,
    cache: &'a mut Vec<(usize, RegKey, Vec<u64>)>,
    /// The pieces moved to a registration step and coarsened in the last
    /// round, by (step, piece id), with the displacement sum that moved
    /// them ([`Registrations::piece_at`]); taken from as this round reads
    /// them.
    old_pieces: CoarsePieces,
    /// Those this round read, kept for the next.
    new_pieces: CoarsePieces,
    reach: Vec<u64>,
}

/// A piece of a group's region in a local frame: (step, group root, piece
/// id, paving).
type Piece<'a> = (usize, usize, u64, &'a Paving);

/// The groups of one registration: their roots, their pieces (indices into
/// the window), their witness slots.
type Local = (Vec<usize>, Vec<Vec<usize>>, Vec<Option<usize>>);

impl Registrations<'_> {
    /// The groups whose pieces lie in `window` (the witness groups first,
    /// then those with the most pieces, when more than `register_groups`).
    fn local_groups(&self, round: &mut Round, window: &[Piece], slot_root: &[usize]) -> Local {
        let (mut roots, mut members, mut fixed): Local = Default::default();
        for (x, &(_, root, _, _)) in window.iter().enumerate() {
            let gi = match roots.iter().position(|&r| r == root) {
                Some(gi) => gi,
                None => {
                    roots.push(root);
                    members.push(Vec::new());
                    fixed.push(slot_root.iter().position(|&w| round.uf.find(w) == root));
                    roots.len() - 1
                }
            };
            members[gi].push(x);
        }
        if roots.len() > self.options.register_groups {
            // The witness groups first, then the most pieces.
            let mut idx: Vec<usize> = (0..roots.len()).collect();
            // (`roots` are distinct: one order whatever the sort.)
            crate::sort::sort_indices_by(&mut idx, |a, b| {
                let key = |i: usize| (fixed[i].is_none(), usize::MAX - members[i].len(), roots[i]);
                key(a).cmp(&key(b))
            });
            idx.truncate(self.options.register_groups);
            crate::sort::sort_usize(&mut idx);
            roots = idx.iter().map(|&i| roots[i]).collect();
            members = idx.iter().map(|&i| members[i].clone()).collect();
            fixed = idx.iter().map(|&i| fixed[i]).collect();
        }
        (roots, members, fixed)
    }

    /// The boxes of `piece` moved to the frame of step `s` and coarsened as
    /// [`register_on`] would coarsen them (`coarsen_piece`): taken from the
    /// last round when that moved the same piece by a displacement sum of
    /// the same bits (the same input, so the same boxes), else computed.
    fn piece_at(
        &mut self,
        s: usize,
        piece: &Piece,
        sums: &ChainSums,
        dim: usize,
    ) -> Vec<IntervalBox> {
        let &(t, _, id, region) = piece;
        let delta = sums.delta(s, t);
        let same = |d: &[Interval]| {
            d.iter().zip(&delta[..dim]).all(|(a, b)| {
                a.lo().to_bits() == b.lo().to_bits() && a.hi().to_bits() == b.hi().to_bits()
            })
        };
        let coarse = match self.old_pieces.remove(&(s, id)) {
            Some((d, coarse)) if same(&d) => coarse,
            _ => {
                let shifted: Vec<IntervalBox> = region
                    .boxes()
                    .iter()
                    .map(|b| {
                        let axes: Vec<Interval> = (0..dim).map(|x| b[x] + delta[x]).collect();
                        IntervalBox::new(&axes)
                    })
                    .collect();
                coarsen_piece(&shifted, dim, self.options.register.coarse)
            }
        };
        self.new_pieces
            .insert((s, id), (delta[..dim].to_vec(), coarse.clone()));
        coarse
    }

    /// The registration at step `s` of the local groups (roots, pieces
    /// and slots `local`, pieces in `window`) on the witness regions, up to
    /// [`register_on`]: `None` when the cache holds an answer whose inputs
    /// are close (its masks are then taken), else what to register.
    fn prepare_at(
        &mut self,
        round: &mut Round,
        s: usize,
        (window, sums): (&[Piece], &ChainSums),
        (roots, members, fixed): Local,
        w: &Witnesses,
    ) -> Option<Job> {
        let dim = round.dom.dim;
        let p = round.position(s);
        let key = RegKey {
            p: p.clone(),
            roots: roots.clone(),
            slots: w.slot_root.clone(),
            fixed: fixed.clone(),
            pieces: members.iter().map(Vec::len).sum(),
            witnesses: w.regions.iter().map(|r| r.hull()).collect(),
        };
        let slot = self.cache.binary_search_by_key(&s, |e| e.0);
        if let Some((_, old, old_reach)) = slot.ok().map(|i| &self.cache[i]) {
            if old.close(&key, self.options.register_slack, &mut round.uf) {
                for (&root, &r) in roots.iter().zip(old_reach) {
                    self.reach[root] &= r;
                }
                return None;
            }
        }
        let groups: Vec<LocalGroup> = members
            .iter()
            .zip(fixed)
            .map(|(m, fixed)| LocalGroup {
                pieces: m
                    .iter()
                    .map(|&x| self.piece_at(s, &window[x], sums, dim))
                    .collect(),
                fixed,
            })
            .collect();
        Some(Job {
            s,
            p,
            roots,
            groups,
            key,
        })
    }

    /// [`register_on`] for `job`: reads only the job, the witnesses, the
    /// distinct graph and the tuning (so jobs may run on any thread).
    fn register_job(&self, job: &Job) -> Registration {
        let (graph, roots) = (&self.graph, &job.roots);
        let distinct =
            |g: usize, h: usize| graph[roots[g]].binary_search(&(roots[h] as u32)).is_ok();
        register_on(
            &job.p,
            &self.witnesses,
            &job.groups,
            &distinct,
            &self.options.register,
        )
    }

    /// A registration's answer applied: p(s) shrunk, the masks taken, the
    /// cache updated. Err: no placement on the `n` witness regions
    /// (infeasible).
    fn finish(
        &mut self,
        round: &mut Round,
        (job, reg): (Job, Registration),
        n: usize,
    ) -> Result<(), String> {
        let (dim, s) = (round.dom.dim, job.s);
        round.out.contractions += reg.work;
        if reg.p.is_empty() {
            return Err(format!(
                "step {s}: the landmarks of groups {:?}, seen from p({s}), fit no placement on the {n} landmark regions",
                job.roots
            ));
        }
        let mut moved = 0.0f64;
        for x in 0..dim {
            let before = round.dom.pos[s * dim + x];
            let after = before.intersect(reg.p[x]);
            moved = moved.max(shrinkage(before, after));
            round.dom.pos[s * dim + x] = after;
        }
        if moved > round.tol {
            round.out.moved = true;
            round.chain.changed(s);
        }
        for (&root, &r) in job.roots.iter().zip(&reg.reach) {
            self.reach[root] &= r;
        }
        let key = RegKey {
            p: round.position(s),
            ..job.key
        };
        match self.cache.binary_search_by_key(&s, |e| e.0) {
            Ok(i) => self.cache[i] = (s, key, reg.reach),
            Err(i) => self.cache.insert(i, (s, key, reg.reach)),
        }
        Ok(())
    }
}

/// One registration to do: its step, p(s), the roots of its groups, their
/// pieces and slots, and the cache key of its inputs.
struct Job {
    s: usize,
    p: IntervalBox,
    roots: Vec<usize>,
    groups: Vec<LocalGroup>,
    key: RegKey,
}

impl ShapesState {
    /// Step 5 (module doc): registration of the local frames on the
    /// witness regions at the steps of the groups' pieces.
    pub(super) fn register_anchors(
        &mut self,
        round: &mut Round,
        sums: &ChainSums,
        w: &mut Witnesses,
    ) -> Result<(), String> {
        let mut regs = Registrations {
            options: &self.options,
            graph: self.distinct.graph(&mut round.uf)?,
            witnesses: CoarseWitnesses::new(
                &w.regions
                    .iter()
                    .map(|r| r.boxes().to_vec())
                    .collect::<Vec<_>>(),
                round.dom.dim,
                self.options.register.coarse,
            ),
            cache: &mut self.registered,
            old_pieces: std::mem::take(&mut self.coarse_pieces),
            new_pieces: CoarsePieces::new(),
            reach: vec![u64::MAX; round.mission.detections.len()],
        };
        // Pieces by step: (step, root, paving).
        let mut pieces: Vec<Piece> = self
            .frames
            .every_piece()
            .into_iter()
            .map(|(member, step, id, region)| (step, round.uf.find(member), id, region))
            .collect();
        // (Piece ids are unique: a total key, one order whatever the sort.)
        crate::sort::total_by_key(&mut pieces, |&(step, root, id, _)| (step, root, id));
        let (gap, every) = (regs.options.register_gap, regs.options.register_every);
        let mut last_anchor: Option<usize> = None;
        let mut lo = 0;
        #[cfg(not(target_arch = "wasm32"))]
        let mut jobs: Vec<Job> = Vec::new();
        for a in 0..pieces.len() {
            let s = pieces[a].0;
            if last_anchor.is_some_and(|l| s < l + every) {
                continue;
            }
            last_anchor = Some(s);
            while pieces[lo].0 + gap < s {
                lo += 1;
            }
            let hi = lo + pieces[lo..].iter().take_while(|e| e.0 <= s + gap).count();
            let window = &pieces[lo..hi];
            let local = regs.local_groups(round, window, &w.slot_root);
            let job = regs.prepare_at(round, s, (window, sums), local, w);
            #[cfg(not(target_arch = "wasm32"))]
            jobs.extend(job);
            // The browser's build registers at once, one after the other.
            #[cfg(target_arch = "wasm32")]
            if let Some(job) = job {
                let reg = regs.register_job(&job);
                regs.finish(round, (job, reg), w.regions.len())?;
            }
        }
        // The registrations are independent (each reads and shrinks only
        // p(s) of its own step, reads the pieces, the witnesses and the
        // graph, none of which they change, and the masks are gathered by
        // `&`): computed on any threads, applied in step order, as one
        // after the other would be.
        #[cfg(not(target_arch = "wasm32"))]
        {
            let threads = regs.options.threads;
            let done = crate::par::map(threads, &jobs, |job| regs.register_job(job));
            for answer in jobs.into_iter().zip(done) {
                regs.finish(round, answer, w.regions.len())?;
            }
        }
        let reach = regs.reach;
        self.coarse_pieces = regs.new_pieces;
        self.join_by_reach(round, w, &reach)
    }

    /// Groups left with one witness join it; the others are distinct from
    /// the witnesses they cannot be. Err: a group that fits none.
    fn join_by_reach(
        &mut self,
        round: &mut Round,
        w: &mut Witnesses,
        reach: &[u64],
    ) -> Result<(), String> {
        let n = w.regions.len();
        for (root, &r) in reach.iter().enumerate() {
            if r == u64::MAX || round.uf.find(root) != root {
                continue;
            }
            if w.slot_root.iter().any(|&x| round.uf.find(x) == root) {
                continue;
            }
            if r == 0 {
                return Err(format!(
                    "landmark of group {root}: seen from the steps around it, it fits none of the {n} landmark regions"
                ));
            }
            for (i, &x) in w.slot_root.iter().enumerate() {
                if r & (1 << i) == 0 {
                    w.pairs.push((root as u32, x as u32));
                }
            }
            if r.count_ones() == 1 {
                let region = self.regions[root].take();
                let i = r.trailing_zeros() as usize;
                w.join(i, root, region, round, self.options.max_boxes)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::union_find::Uf;

    /// The registration's cache names witnesses by slot: an answer is
    /// carried over only while each slot holds the same landmark (its
    /// witness in one group with the old one), even when the regions look
    /// alike (here both unbounded, as after an unbounded step).
    #[test]
    fn a_cached_registration_needs_the_same_landmark_in_each_slot() {
        let entire = IntervalBox::entire(2);
        let key = |slots: Vec<usize>| RegKey {
            p: entire.clone(),
            roots: vec![4],
            slots,
            fixed: vec![None],
            pieces: 1,
            witnesses: vec![entire.clone(), entire.clone()],
        };
        let mut uf = Uf::new(6);
        let old = key(vec![0, 1]);
        assert!(old.close(&key(vec![0, 1]), 0.02, &mut uf));
        // The witnesses swapped slots: the masks would name the wrong ones.
        assert!(!old.close(&key(vec![1, 0]), 0.02, &mut uf));
        // Another detection of the same landmark stands for it.
        assert!(!old.close(&key(vec![0, 2]), 0.02, &mut uf));
        uf.union(1, 2);
        assert!(old.close(&key(vec![0, 2]), 0.02, &mut uf));
    }
}
