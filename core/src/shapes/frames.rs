//! Local frames: the landmark region of a proved group in the frame of one
//! of its steps, where dead-reckoning drift cancels, and the distinct pairs
//! it proves (docs/design.md, "Detection shapes").
//!
//! # Constraint
//!
//! A group H (detections proved to see one landmark L) and a detection x
//! (or another group): if no possible position of L is in x's shape (the
//! other group's region), x does not see L.
//!
//! # Math
//!
//! Frame of step s: x ↦ x - p(s). `p(t) - p(s)` lies in `Δ(s, t)`, the sum
//! of the displacement boxes between the two steps ([`ChainSums`]); it
//! does not carry the drift of the absolute boxes P(s), P(t). A group's
//! members are split, in step order, into pieces spanning at most
//! `piece_steps` steps; each piece takes the frame of its middle member's
//! step s and the region `L - p(s) ∈ ∩_j A_s(j)`, with A_s(j) the shape of
//! member j around Δ(s, t_j), kept as a [`Paving`] (from the hull of the
//! thinnest member's shape, cut by every member of the piece, bisected to
//! `max_boxes`). Where the absolute region is a ring, this one is often one
//! or two small blobs. Then, within `max_gap` steps of a piece:
//! - a detection x whose shape around Δ(s, t_x) misses the piece's paving
//!   is distinct from the group;
//! - two pieces of different groups, at steps s and s', are distinct when
//!   the first paving misses the second translated by Δ(s, s') (boxes plus
//!   an interval box).
//!
//! # Soundness
//!
//! The true p(t) - p(s) is in Δ(s, t) (see [`ChainSums`]), the true landmark
//! minus the true p(s) is in every member's relative shape, and a paving
//! keeps every point of the intersection ([`super::region`]); translating
//! by the true p(s) maps everything back, keeping disjointness.
//!
//! # Complexity
//!
//! Pieces are cached by group and rebuilt when the group changes:
//! O(m · members · d) each (m <= `max_boxes`). Tests: O(m d) per detection
//! and nearby piece, O(m^2 d) per pair of nearby pieces, each done once
//! (the answers depend on the pieces and the measurements alone).

use super::chain_sums::ChainSums;
use super::region::Paving;
use super::shape::{Shape, Sighting, MAX_DIM};
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::union_find::Uf;

/// Tuning of the local frames.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameOptions {
    /// Most steps spanned by the members of one piece.
    pub piece_steps: usize,
    /// Most steps between a piece and what it is tested against.
    pub max_gap: usize,
    /// Most boxes of a piece's paving.
    pub max_boxes: usize,
    /// Members whose shapes cut the halves of a bisection (the thinnest).
    pub refine_shapes: usize,
    /// Least steps between the frames of two pieces of one chunk.
    pub anchor_gap: usize,
    /// Threads for the pieces' building and tests ([`crate::par::map`]);
    /// the same answers for any count.
    pub threads: usize,
}

impl Default for FrameOptions {
    fn default() -> Self {
        FrameOptions {
            piece_steps: 600,
            max_gap: 600,
            max_boxes: 48,
            refine_shapes: 12,
            anchor_gap: 150,
            threads: 1,
        }
    }
}

/// One piece of a group: its frame's step, a member, its paving.
#[derive(Debug, Clone)]
struct Piece {
    step: usize,
    member: usize,
    /// Unique among the pieces these frames ever built (a piece never
    /// changes: a memo keyed on it stays valid while the id is seen).
    id: u64,
    region: Paving,
    /// Whether its pairs were found already (a piece depends on its
    /// group's members and the displacement sums alone, and so do the
    /// relative shapes it is tested against: the answers do not change).
    tested: bool,
}

/// Pieces of the groups, cached across rounds.
#[derive(Debug, Clone, Default)]
pub struct Frames {
    /// By group root: (member count when built, pieces).
    cache: Vec<Option<(usize, Vec<Piece>)>>,
    /// The id of the next piece built.
    next_id: u64,
}

/// The shape of detection j in the frame of step s (cut by nothing: the
/// piece regions are cached, so they depend on the group alone).
fn relative_shape(
    dets: &[Sighting],
    sums: &ChainSums,
    heading_at: &[Interval],
    dim: usize,
    s: usize,
    j: usize,
) -> Shape {
    let d = &dets[j];
    let centre = sums.delta(s, d.step);
    Shape::new(
        IntervalBox::new(&centre[..dim]),
        d.range,
        d.bearing.map(|b| (heading_at[j], b)),
        IntervalBox::entire(dim),
    )
}

impl Frames {
    /// The cached pieces of a group (found at any member): each a step s
    /// and a paving of `L - p(s)`.
    pub fn pieces(&self, group: &[usize]) -> Vec<(usize, &Paving)> {
        group
            .iter()
            .filter_map(|&j| self.cache.get(j)?.as_ref())
            .flat_map(|(_, pieces)| pieces.iter().map(|p| (p.step, &p.region)))
            .collect()
    }

    /// Every cached piece: a member of its group, its step s, its id
    /// (unique among the pieces these frames ever built) and its paving of
    /// `L - p(s)`.
    pub fn every_piece(&self) -> Vec<(usize, usize, u64, &Paving)> {
        self.cache
            .iter()
            .flatten()
            .flat_map(|(_, pieces)| pieces.iter().map(|p| (p.member, p.step, p.id, &p.region)))
            .collect()
    }

    /// Appends to `out` the distinct pairs the frames prove (module doc).
    /// `order`: detections by step. Returns the work done (pieces
    /// contracted); Err: a piece whose region is empty (infeasible).
    #[allow(clippy::too_many_arguments)]
    pub fn pairs(
        &mut self,
        dets: &[Sighting],
        order: &[usize],
        dim: usize,
        sums: &ChainSums,
        heading_at: &[Interval],
        uf: &mut Uf,
        opts: &FrameOptions,
        out: &mut Vec<(u32, u32)>,
    ) -> Result<u64, String> {
        let view = View {
            dets,
            sums,
            heading_at,
            dim,
        };
        let mut work = self.rebuild(&view, uf, opts)?;
        // Every piece, by step: (step, root, index).
        let mut all: Vec<(usize, usize, usize)> = Vec::new();
        for (root, c) in self.cache.iter().enumerate() {
            if let Some((_, pieces)) = c {
                for (i, p) in pieces.iter().enumerate() {
                    all.push((p.step, root, i));
                }
            }
        }
        crate::sort::sort_ord(&mut all);
        work += self.detections_against_pieces(&view, order, &all, uf, opts, out);
        work += self.pieces_against_pieces(&view, &all, opts, out);
        for (_, pieces) in self.cache.iter_mut().flatten() {
            for p in pieces {
                p.tested = true;
            }
        }
        Ok(work)
    }

    /// The pieces of every group, (re)built as [`Frames::pairs`] does, but
    /// no pair tested (the pieces stay untested): for a round that needs
    /// the pieces and none of their pairs. The work done; Err as
    /// [`Frames::pairs`].
    pub fn build(
        &mut self,
        dets: &[Sighting],
        dim: usize,
        sums: &ChainSums,
        heading_at: &[Interval],
        uf: &mut Uf,
        opts: &FrameOptions,
    ) -> Result<u64, String> {
        let view = View {
            dets,
            sums,
            heading_at,
            dim,
        };
        self.rebuild(&view, uf, opts)
    }

    /// The pieces of every group, (re)built when the group changed (its
    /// size); the work done. The groups to rebuild are built on
    /// `opts.threads` threads (each reads only the detections, the sums
    /// and the headings), then taken in the groups' order: the same ids,
    /// the same first error, as one after the other.
    fn rebuild(&mut self, v: &View, uf: &mut Uf, opts: &FrameOptions) -> Result<u64, String> {
        let k = v.dets.len();
        if self.cache.len() != k {
            self.cache = vec![None; k];
        }
        let mut work = 0u64;
        let groups = uf.groups();
        // Natively, the stale groups' pieces are built first, on the
        // threads; the browser's build makes them in the loop below.
        #[cfg(not(target_arch = "wasm32"))]
        let cached = |g: &[usize]| {
            g.iter().any(|&j| {
                self.cache[j]
                    .as_ref()
                    .is_some_and(|(len, _)| *len == g.len())
            })
        };
        #[cfg(not(target_arch = "wasm32"))]
        let stale: Vec<&Vec<usize>> = groups.iter().filter(|g| !cached(g)).collect();
        #[cfg(not(target_arch = "wasm32"))]
        let mut built =
            crate::par::map(opts.threads, &stale, |g| group_pieces(v, g, opts)).into_iter();
        let mut fresh: Vec<Option<(usize, Vec<Piece>)>> = vec![None; k];
        for g in &groups {
            let root = g[0];
            let cached = g
                .iter()
                .find_map(|&j| self.cache[j].take().filter(|(len, _)| *len == g.len()));
            let pieces = match cached {
                Some((_, p)) => p,
                None => {
                    #[cfg(not(target_arch = "wasm32"))]
                    let (pieces, w) = built.next().expect("one build per stale group");
                    #[cfg(target_arch = "wasm32")]
                    let (pieces, w) = group_pieces(v, g, opts);
                    work += w;
                    let mut pieces = pieces?;
                    for p in &mut pieces {
                        p.id = self.next_id;
                        self.next_id += 1;
                    }
                    pieces
                }
            };
            fresh[root] = Some((g.len(), pieces));
        }
        self.cache = fresh;
        Ok(work)
    }

    /// Detections (by step, `order`) against the untested pieces of other
    /// groups within `max_gap` steps; the work done. The detections are
    /// cut into runs tested on `opts.threads` threads (each test reads
    /// only the pieces and the detection), their pairs appended in the
    /// runs' order: the pairs of one pass over `order`.
    fn detections_against_pieces(
        &self,
        v: &View,
        order: &[usize],
        all: &[(usize, usize, usize)],
        uf: &mut Uf,
        opts: &FrameOptions,
        out: &mut Vec<(u32, u32)>,
    ) -> u64 {
        let roots: Vec<usize> = order.iter().map(|&x| uf.find(x)).collect();
        // One run with one thread, and always in the browser's build.
        if cfg!(target_arch = "wasm32") || opts.threads <= 1 {
            return self.detections_run(v, (order, &roots), all, opts, out);
        }
        split_runs(order.len(), opts.threads, out, |(a, b), pairs| {
            self.detections_run(v, (&order[a..b], &roots[a..b]), all, opts, pairs)
        })
    }

    /// [`Frames::detections_against_pieces`] for a run of `order` with the
    /// roots of its detections.
    fn detections_run(
        &self,
        v: &View,
        (order, roots): (&[usize], &[usize]),
        all: &[(usize, usize, usize)],
        opts: &FrameOptions,
        out: &mut Vec<(u32, u32)>,
    ) -> u64 {
        let mut work = 0u64;
        let mut lo = 0;
        for (&x, &rx) in order.iter().zip(roots) {
            let t = v.dets[x].step;
            while lo < all.len() && all[lo].0 + opts.max_gap < t {
                lo += 1;
            }
            for &(s, root, i) in all[lo..].iter().take_while(|e| e.0 <= t + opts.max_gap) {
                if root == rx {
                    continue;
                }
                let p = &self.cache[root].as_ref().expect("cached").1[i];
                if p.tested {
                    continue;
                }
                let shape = relative_shape(v.dets, v.sums, v.heading_at, v.dim, s, x);
                work += p.region.boxes().len() as u64;
                // An empty relative shape (an empty displacement between
                // the steps) proves no distinct pair.
                if !shape.is_empty() && !p.region.meets_shape(&shape) {
                    out.push((x as u32, p.member as u32));
                }
            }
        }
        work
    }

    /// Pieces against the nearby pieces of other groups (one of the two
    /// untested); the work done. Runs of `all` are tested on
    /// `opts.threads` threads, their pairs appended in the runs' order.
    fn pieces_against_pieces(
        &self,
        v: &View,
        all: &[(usize, usize, usize)],
        opts: &FrameOptions,
        out: &mut Vec<(u32, u32)>,
    ) -> u64 {
        if cfg!(target_arch = "wasm32") || opts.threads <= 1 {
            return self.pieces_run(v, all, (0, all.len()), opts, out);
        }
        split_runs(all.len(), opts.threads, out, |(a, b), pairs| {
            self.pieces_run(v, all, (a, b), opts, pairs)
        })
    }

    /// [`Frames::pieces_against_pieces`] for the pieces `all[a..b]`, each
    /// against those after it in `all`.
    fn pieces_run(
        &self,
        v: &View,
        all: &[(usize, usize, usize)],
        (from, to): (usize, usize),
        opts: &FrameOptions,
        out: &mut Vec<(u32, u32)>,
    ) -> u64 {
        let mut work = 0u64;
        for (a, &(s, ra, ia)) in all.iter().enumerate().take(to).skip(from) {
            for &(s2, rb, ib) in all[a + 1..].iter().take_while(|e| e.0 <= s + opts.max_gap) {
                if ra == rb {
                    continue;
                }
                let pa = &self.cache[ra].as_ref().expect("cached").1[ia];
                let pb = &self.cache[rb].as_ref().expect("cached").1[ib];
                if pa.tested && pb.tested {
                    continue;
                }
                let delta = v.sums.delta(s, s2);
                work += (pa.region.boxes().len() * pb.region.boxes().len()) as u64;
                if !meets_translated(&pa.region, &pb.region, &delta[..v.dim]) {
                    out.push((pa.member as u32, pb.member as u32));
                }
            }
        }
        work
    }
}

/// `0..len` cut into runs of about equal length, in order: one with one
/// thread, four per thread with more (the tests' costs vary along a
/// mission).
fn runs(len: usize, threads: usize) -> Vec<(usize, usize)> {
    let parts = if threads > 1 { threads * 4 } else { 1 };
    let size = len.div_ceil(parts).max(1);
    (0..len)
        .step_by(size)
        .map(|a| (a, (a + size).min(len)))
        .collect()
}

/// `work` over the runs of `0..len` on `threads` threads: each run's pairs
/// appended to `out` in run order (the order one thread gives), the work
/// counts summed.
fn split_runs<F>(len: usize, threads: usize, out: &mut Vec<(u32, u32)>, work: F) -> u64
where
    F: Fn((usize, usize), &mut Vec<(u32, u32)>) -> u64 + Sync,
{
    let parts = crate::par::map(threads, &runs(len, threads), |&run| {
        let mut pairs = Vec::new();
        let w = work(run, &mut pairs);
        (w, pairs)
    });
    let mut total = 0u64;
    for (w, pairs) in parts {
        total += w;
        out.extend(pairs);
    }
    total
}

/// What the pieces are built and tested from: the detections, the chain's
/// sums, the headings at the detections, the dimension.
struct View<'a> {
    dets: &'a [Sighting],
    sums: &'a ChainSums<'a>,
    heading_at: &'a [Interval],
    dim: usize,
}

/// The pieces of group `g`, its members sorted by step and cut into
/// chunks of at most `piece_steps` steps, with the work done (ids left 0).
fn group_pieces(v: &View, g: &[usize], opts: &FrameOptions) -> (Result<Vec<Piece>, String>, u64) {
    let dets = v.dets;
    let mut members = g.to_vec();
    crate::sort::sort_indices_by(&mut members, |a, b| dets[a].step.cmp(&dets[b].step));
    let mut work = 0u64;
    let mut pieces: Vec<Piece> = Vec::new();
    for chunk in members.chunk_by(|&a, &b| dets[b].step - dets[a].step <= opts.piece_steps) {
        match build_pieces(dets, v.sums, v.heading_at, v.dim, chunk, opts, &mut work) {
            Ok(p) => pieces.extend(p),
            Err(e) => return (Err(e), work),
        }
    }
    (Ok(pieces), work)
}

/// The pieces of one chunk of a group's members (sorted by step).
#[allow(clippy::too_many_arguments)]
fn build_pieces(
    dets: &[Sighting],
    sums: &ChainSums,
    heading_at: &[Interval],
    dim: usize,
    chunk: &[usize],
    opts: &FrameOptions,
    work: &mut u64,
) -> Result<Vec<Piece>, String> {
    if chunk.len() < 2 {
        return Ok(Vec::new());
    }
    // Anchors: members at least `anchor_gap` steps apart (the middle one
    // when the chunk is shorter), each the frame of one piece.
    let mut anchors: Vec<usize> = Vec::new();
    for &j in chunk {
        let far = anchors
            .last()
            .is_none_or(|&a| dets[j].step >= dets[a].step + opts.anchor_gap.max(1));
        if far {
            anchors.push(j);
        }
    }
    if anchors.len() == 1 {
        anchors[0] = chunk[chunk.len() / 2];
    }
    let mut pieces = Vec::with_capacity(anchors.len());
    for anchor in anchors {
        let s = dets[anchor].step;
        let shapes: Vec<Shape> = chunk
            .iter()
            .map(|&j| relative_shape(dets, sums, heading_at, dim, s, j))
            .collect();
        let mut by_thickness: Vec<&Shape> = shapes.iter().collect();
        // Ties in slice order (the references point into one slice, so their
        // addresses follow the indices): the order of a stable sort.
        crate::sort::sort_by(&mut by_thickness, |a, b| {
            a.thickness()
                .total_cmp(&b.thickness())
                .then_with(|| std::ptr::from_ref::<Shape>(*a).cmp(&std::ptr::from_ref::<Shape>(*b)))
        });
        let mut region = Paving::from_box(&by_thickness[0].hull());
        for sh in &by_thickness[1..] {
            region.cut(sh);
        }
        by_thickness.truncate(opts.refine_shapes);
        region.refine(&by_thickness, 0.0, opts.max_boxes);
        for sh in &shapes {
            region.cut(sh);
        }
        *work += (region.boxes().len() * shapes.len()) as u64;
        if region.is_empty() {
            return Err(format!(
                "landmark of detections {chunk:?}: their shapes, taken relative to the position of step {s}, have no common point"
            ));
        }
        pieces.push(Piece {
            step: s,
            member: anchor,
            id: 0,
            region,
            tested: false,
        });
    }
    Ok(pieces)
}

/// Whether `a` may meet `b` translated by `delta` (`false` is a proof; an
/// empty `delta`, from an empty displacement, proves nothing here).
fn meets_translated(a: &Paving, b: &Paving, delta: &[Interval]) -> bool {
    if delta.iter().any(|x| x.is_empty()) {
        return true;
    }
    let dim = delta.len();
    let shifted: Vec<IntervalBox> = b
        .boxes()
        .iter()
        .map(|x| {
            let mut axes = [Interval::ZERO; MAX_DIM];
            for i in 0..dim {
                axes[i] = x[i] + delta[i];
            }
            IntervalBox::new(&axes[..dim])
        })
        .collect();
    let shifted = Paving::from_boxes(dim, shifted);
    a.meets(&shifted)
}
