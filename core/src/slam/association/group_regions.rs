//! Step 1 of a shapes round: each proved group's landmark region (a
//! [`Paving`]), cut by its local-frame pieces and by its members' shapes,
//! refined, and each member contracted by [`branch`] against it.
//!
//! Constraint: the members of a group see one landmark L, so L lies in
//! every member's shape and in P(s) + (L - p(s)) for every local piece.
//! Soundness: each cut and refinement keeps every point of the shapes'
//! intersection ([`crate::shapes::region`]); an empty region proves the
//! group infeasible. Complexity: O(c · m · d) for c members whose centre
//! changed, m <= `max_boxes` boxes; a member whose inputs did not change
//! since its last branch is skipped ([`super::BranchKey`]).

use super::round::Round;
use super::state::ShapesState;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::shapes::branch::branch;
use crate::shapes::region::Paving;
use crate::shapes::shape::Shape;

impl ShapesState {
    /// Step 1: regions of the groups, and their members contracted.
    pub(super) fn group_regions(&mut self, round: &mut Round) -> Result<(), String> {
        for g in round.uf.groups() {
            // The incremental schedule: a group none of whose inputs moved since its last
            // step 1 (the same members, positions, boxes, pieces and
            // region, bit for bit) is not cut, refined and branched again.
            let seen = (!self.full_work).then(|| self.group_signature(&g, round));
            if seen.is_some() && seen == self.group_seen[g[0]] {
                continue;
            }
            self.group_region(&g, round)?;
            if !self.full_work {
                self.group_seen[g[0]] = Some(self.group_signature(&g, round));
            }
        }
        Ok(())
    }

    /// The bits of what step 1 reads of group `g`: its members, their
    /// p(step) and d(j), its local pieces (step and box count), and the
    /// region it holds (hull and box count). O(|g| · d + pieces).
    fn group_signature(&self, g: &[usize], round: &Round) -> Vec<u64> {
        let dim = round.dom.dim;
        let mut sig = Vec::with_capacity(g.len() * (1 + 4 * dim) + 8);
        let push = |x: Interval, sig: &mut Vec<u64>| {
            sig.push(x.lo().to_bits());
            sig.push(x.hi().to_bits());
        };
        for &j in g {
            sig.push(j as u64);
            let t = round.step_of(j);
            for a in 0..dim {
                push(round.dom.pos[t * dim + a], &mut sig);
                push(round.dom.det[j][a], &mut sig);
            }
        }
        for (step, rel) in self.frames.pieces(g) {
            sig.push(step as u64);
            sig.push(rel.boxes().len() as u64);
        }
        sig.push(u64::MAX);
        for &j in g {
            if let Some(r) = &self.regions[j] {
                sig.push(j as u64);
                sig.push(r.boxes().len() as u64);
                for a in 0..r.hull_ref().dim() {
                    push(r.hull_ref()[a], &mut sig);
                }
            }
        }
        sig
    }

    /// Step 1 for one group `g`.
    fn group_region(&mut self, g: &[usize], round: &mut Round) -> Result<(), String> {
        let mut region = self.region_to_cut(g, round);
        let shapes: Vec<Shape> = g.iter().map(|&j| round.shape_of(j)).collect();
        self.cut_by_members(g, &shapes, &mut region, round);
        if region.is_empty() {
            return Err(format!(
                "landmark of detections {g:?}: their shapes (ranges and bearings around their positions) have no common point"
            ));
        }
        self.branch_members(g, &shapes, &region, round)?;
        self.regions[g[0]] = Some(region);
        Ok(())
    }

    /// The region of group `g` before this round's cuts: the regions its
    /// members hold, intersected (else the common box of its members), cut
    /// by its local-frame pieces: L ∈ P(s) + (L - p(s)).
    fn region_to_cut(&mut self, g: &[usize], round: &mut Round) -> Paving {
        let max_boxes = self.options.max_boxes;
        let dom = &round.dom;
        let mut region = match self.gather(g, max_boxes) {
            Some(r) => r,
            None => {
                let mut common = dom.det[g[0]].clone();
                for &j in &g[1..] {
                    common.intersect_with(&dom.det[j]);
                }
                for &j in g {
                    self.cut_with[j] = None;
                }
                Paving::from_box(&common)
            }
        };
        for (step, rel) in self.frames.pieces(g) {
            let origin = &dom.pos[step * dom.dim..(step + 1) * dom.dim];
            let shifted: Vec<IntervalBox> = rel
                .boxes()
                .iter()
                .map(|b| {
                    let axes: Vec<Interval> = (0..dom.dim).map(|a| b[a] + origin[a]).collect();
                    IntervalBox::new(&axes)
                })
                .collect();
            region.intersect(&Paving::from_boxes(dom.dim, shifted), max_boxes);
            round.out.contractions += region.boxes().len() as u64;
        }
        region
    }

    /// Cuts `region` by the shapes of the members whose centre box changed
    /// since they last cut it, then refines it by the thinnest shapes.
    fn cut_by_members(
        &mut self,
        g: &[usize],
        shapes: &[Shape],
        region: &mut Paving,
        round: &mut Round,
    ) {
        for (s, &j) in shapes.iter().zip(g) {
            if self.cut_with[j].as_ref() != Some(&s.centre) {
                region.cut(s);
                round.out.contractions += region.boxes().len() as u64;
                self.cut_with[j] = Some(s.centre.clone());
            }
        }
        let mut by_thickness: Vec<&Shape> = shapes.iter().collect();
        // Ties in slice order (the references point into one slice, so their
        // addresses follow the indices): the order of a stable sort.
        crate::sort::sort_by(&mut by_thickness, |a, b| {
            a.thickness()
                .total_cmp(&b.thickness())
                .then_with(|| std::ptr::from_ref::<Shape>(*a).cmp(&std::ptr::from_ref::<Shape>(*b)))
        });
        by_thickness.truncate(self.options.refine_shapes);
        region.refine(
            &by_thickness,
            self.options.resolution,
            self.options.max_boxes,
        );
    }

    /// Contracts each member of `g` by [`branch`] against its group's
    /// region, unless what the branch would read did not change.
    fn branch_members(
        &mut self,
        g: &[usize],
        shapes: &[Shape],
        region: &Paving,
        round: &mut Round,
    ) -> Result<(), String> {
        let hull = region.hull();
        for (s, &j) in shapes.iter().zip(g) {
            let key = (
                s.centre.clone(),
                s.cut.clone(),
                hull.clone(),
                region.boxes().len(),
            );
            if self.branched[j].as_ref() == Some(&key) {
                continue;
            }
            let br = branch(s, &[region]);
            round.out.contractions += region.boxes().len() as u64;
            round.apply(j, &br)?;
            // The key of what the next round will read.
            let t = round.step_of(j);
            self.branched[j] = Some((round.position(t), round.dom.det[j].clone(), key.2, key.3));
        }
        Ok(())
    }

    /// Takes the regions stored at the members of `g` and intersects them.
    fn gather(&mut self, g: &[usize], max_boxes: usize) -> Option<Paving> {
        let mut region: Option<Paving> = None;
        for &j in g {
            if let Some(p) = self.regions[j].take() {
                region = Some(match region {
                    None => p,
                    Some(mut r) => {
                        r.intersect(&p, max_boxes);
                        r
                    }
                });
            }
        }
        region
    }
}
