//! Registration of a local map on the landmark regions: the robot position
//! at one step is where the landmarks seen around it, in its own frame, fit
//! the n landmark regions (docs/design.md, "Detection shapes"; docs/shapes.md).
//!
//! # Constraint
//!
//! At most n landmarks and n pairwise-distinct witness groups with regions
//! W(1..n) (so every landmark is one witness's, [`super::witnesses`]); for
//! groups g near a step s, their landmark in the frame of s,
//! `L(g) - p(s) ∈ R(g)` (the local-frame pavings of [`super::frames`],
//! moved to the frame of s with the displacement sums, [`ChainSums`](super::chain_sums::ChainSums));
//! pairs of groups proved distinct ([`super::distinct`]).
//!
//! # Math
//!
//! Each group's landmark is one witness's, and groups proved distinct are
//! different witnesses', so for some map a from the groups to 1..n that is
//! injective on distinct pairs (and fixed for the witness groups),
//! `p(s) ∈ ∩_g (W(a(g)) - R(g))`, with `W - R` the set of differences
//! `w - r` (for paved W and R: the union of the boxes `B_w - B_r`). The set
//! of such p(s) within P(s) is paved ([`register`]): a box S of p(s) is
//! dropped when no admissible map a has S meeting `W(a(g)) - R(g)` for
//! every g; the others are bisected (widest axis, breadth first) down to a
//! width or a box count. P(s) becomes the hull of the boxes kept, and each
//! group's candidates are the witnesses some admissible map of some kept
//! box gives it. This uses what a single range cannot: the shape of the
//! local constellation (where the landmarks are relative to each other
//! and to the robot), matched against the global one.
//!
//! # Soundness
//!
//! The true p(s) lies in P(s) and the true map (each group to the witness
//! of its landmark) is admissible: distinct groups see distinct landmarks,
//! and a witness group sees its own. For each g the true landmark lies in
//! W(a(g)) and `L - p(s)` in R(g), so p(s) is the difference of a point of
//! a box of W(a(g)) and a point of a box of R(g), which lies in that pair's
//! difference box (outward-rounded interval subtraction). So the box
//! holding the true p(s) meets every set of the true map and is kept, and
//! the true witness is among each group's candidates. Coarsening a paving
//! (replacing boxes by their hulls) only adds points.
//!
//! # Complexity
//!
//! O(g · n · m_W · m_R · d) to build the difference boxes (pavings coarsened
//! to m boxes), then for each of at most `max_boxes` paving boxes
//! O(g · n · m_W · m_R · d) tests and a search over the admissible maps
//! bounded by `map_budget` nodes (beyond it, every test-passing witness
//! stays a candidate).

use super::shape::MAX_DIM;
use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// A group near the registration step: its local pieces (boxes of
/// `L - p(s)`, each piece a paving in the frame of s) and its witness when
/// it is one of the witness groups.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalGroup {
    /// Pieces, each a list of boxes in the frame of s.
    pub pieces: Vec<Vec<IntervalBox>>,
    /// The witness index when the group is a witness group.
    pub fixed: Option<usize>,
}

/// What a registration found.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    /// Hull of the kept boxes of p(s) (empty: no admissible position).
    pub p: IntervalBox,
    /// Per group: bit i set when witness i may be its landmark.
    pub reach: Vec<u64>,
    /// Box tests done.
    pub work: u64,
}

/// Tuning of [`register`].
#[derive(Debug, Clone, PartialEq)]
pub struct RegisterOptions {
    /// Most boxes of p(s) in the paving.
    pub max_boxes: usize,
    /// Boxes this narrow (on every axis) are not bisected.
    pub min_width: f64,
    /// Most boxes kept of each coarsened paving.
    pub coarse: usize,
    /// Node budget of the map search in one box.
    pub map_budget: usize,
}

impl Default for RegisterOptions {
    fn default() -> Self {
        RegisterOptions {
            max_boxes: 256,
            min_width: 0.5,
            coarse: 12,
            map_budget: 2_000,
        }
    }
}

type Axes = [Interval; MAX_DIM];

fn to_axes(b: &IntervalBox) -> Axes {
    let mut a = [Interval::ZERO; MAX_DIM];
    a[..b.dim()].copy_from_slice(b.axes());
    a
}

fn meets(a: &Axes, b: &Axes, dim: usize) -> bool {
    (0..dim).all(|x| a[x].meets(b[x]))
}

/// The hull of the p(s) within `p` that the constraint of the module doc
/// allows, and each group's candidate witnesses (`witnesses`: the boxes of
/// W(1..n); `distinct(g, h)`: groups g and h are proved to see distinct
/// landmarks; a group's `fixed` witness is below n). With more than 64
/// witnesses (beyond the candidate masks) nothing is contracted.
pub fn register(
    p: &IntervalBox,
    witnesses: &[Vec<IntervalBox>],
    groups: &[LocalGroup],
    distinct: &dyn Fn(usize, usize) -> bool,
    opts: &RegisterOptions,
) -> Registration {
    let coarse = CoarseWitnesses::new(witnesses, p.dim(), opts.coarse);
    register_on(p, &coarse, groups, distinct, opts)
}

/// The witness regions W(1..n) coarsened to `coarse` boxes each, as
/// [`register`] reads them: built once for the many registrations of a
/// round that share the witnesses ([`register_on`]; the same boxes, bit
/// for bit, as `register` builds each time).
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseWitnesses {
    boxes: Vec<Vec<Axes>>,
}

impl CoarseWitnesses {
    /// `witnesses` (boxes of dimension `dim`) coarsened to `coarse` boxes
    /// each. O(n · m² · d) for m boxes per witness.
    pub fn new(witnesses: &[Vec<IntervalBox>], dim: usize, coarse: usize) -> CoarseWitnesses {
        CoarseWitnesses {
            boxes: witnesses
                .iter()
                .map(|b| coarsen(b.iter().map(to_axes).collect(), dim, coarse))
                .collect(),
        }
    }
}

/// [`register`] on witnesses coarsened beforehand (with `opts.coarse` and
/// the dimension of `p`).
pub fn register_on(
    p: &IntervalBox,
    witnesses: &CoarseWitnesses,
    groups: &[LocalGroup],
    distinct: &dyn Fn(usize, usize) -> bool,
    opts: &RegisterOptions,
) -> Registration {
    let dim = p.dim();
    let n = witnesses.boxes.len();
    if n > 64 {
        return Registration {
            p: p.clone(),
            reach: vec![u64::MAX; groups.len()],
            work: 0,
        };
    }
    debug_assert!(groups.iter().all(|g| g.fixed.is_none_or(|f| f < n)));
    let mut out = Registration {
        p: IntervalBox::empty(dim),
        reach: vec![0; groups.len()],
        work: 0,
    };
    if p.is_empty() {
        return out;
    }
    let diff = differences(&witnesses.boxes, groups, dim, opts.coarse);
    let all = if n >= 64 { u64::MAX } else { (1u64 << n) - 1 };
    let masks = |s: &Axes, work: &mut u64| candidate_masks(&diff, s, all, dim, work);
    // Breadth first: a list read from `head` on, halves appended.
    let mut queue = vec![to_axes(p)];
    let mut head = 0;
    let mut kept: usize = 0;
    let mut assign = vec![usize::MAX; groups.len()];
    while head < queue.len() {
        let s = queue[head];
        head += 1;
        let Some(m) = masks(&s, &mut out.work) else {
            continue;
        };
        let mut reach = vec![0u64; groups.len()];
        let mut nodes = 0usize;
        let complete = maps(
            &m,
            distinct,
            0,
            &mut assign,
            &mut reach,
            &mut nodes,
            opts.map_budget,
        );
        if !complete {
            reach.clone_from(&m);
        } else if reach.contains(&0) {
            // No admissible map: the box holds no admissible p(s).
            continue;
        }
        let (widest, w) = widest(&s, dim);
        if w > opts.min_width && kept + (queue.len() - head) + 2 <= opts.max_boxes && w.is_finite()
        {
            queue.extend(halves(&s, widest));
            continue;
        }
        kept += 1;
        let sb = IntervalBox::new(&s[..dim]);
        out.p = if out.p.is_empty() {
            sb
        } else {
            out.p.hull(&sb)
        };
        for (r, x) in out.reach.iter_mut().zip(&reach) {
            *r |= x;
        }
    }
    out
}

/// The difference boxes of one group, piece and witness: for each box of
/// the coarsened W(i), the hull of its differences with the boxes of the
/// coarsened piece, then those differences (`block` = 1 + their count, a
/// box S meets one of them only if it meets their hull).
type Diffs = (usize, Vec<Axes>);

/// The difference boxes W(i) - R(g, piece) (`w`: the coarsened W, R
/// coarsened here to `coarse` boxes): `diff[g][piece][i]` (empty for a witness other than a group's
/// fixed one).
fn differences(
    w: &[Vec<Axes>],
    groups: &[LocalGroup],
    dim: usize,
    coarse: usize,
) -> Vec<Vec<Vec<Diffs>>> {
    let n = w.len();
    groups
        .iter()
        .map(|g| {
            g.pieces
                .iter()
                .map(|piece| {
                    let r = coarsen(piece.iter().map(to_axes).collect(), dim, coarse);
                    let block = 1 + r.len();
                    (0..n)
                        .map(|i| {
                            if g.fixed.is_some_and(|f| f != i) {
                                return (block, Vec::new());
                            }
                            let mut boxes = Vec::with_capacity(w[i].len() * block);
                            for wb in &w[i] {
                                let at = boxes.len();
                                boxes.push([Interval::EMPTY; MAX_DIM]);
                                for rb in &r {
                                    let mut d = [Interval::ZERO; MAX_DIM];
                                    for x in 0..dim {
                                        d[x] = wb[x].sub(rb[x]);
                                    }
                                    boxes.push(d);
                                }
                                boxes[at] = boxes[at + 1..]
                                    .iter()
                                    .fold(boxes[at], |h, d| hull2(&h, d, dim));
                            }
                            (block, boxes)
                        })
                        .collect()
                })
                .collect()
        })
        .collect()
}

/// The candidate masks of one box S of p(s) (bit i: witness i may be the
/// group's landmark, for every piece), from the masks `all`; None when
/// some group has none. Adds the difference boxes read to `work`.
fn candidate_masks(
    diff: &[Vec<Vec<Diffs>>],
    s: &Axes,
    all: u64,
    dim: usize,
    work: &mut u64,
) -> Option<Vec<u64>> {
    let mut m = Vec::with_capacity(diff.len());
    for g in diff {
        let mut mask = all;
        for piece in g {
            let mut pm = 0u64;
            for (i, (block, boxes)) in piece.iter().enumerate() {
                if mask & (1 << i) == 0 {
                    continue;
                }
                // A box outside a block's hull misses the whole block: the
                // same answer as testing every difference box.
                let hit = boxes.chunks(*block).any(|c| {
                    *work += 1;
                    meets(s, &c[0], dim) && {
                        *work += c.len() as u64 - 1;
                        c[1..].iter().any(|b| meets(s, b, dim))
                    }
                });
                if hit {
                    pm |= 1 << i;
                }
            }
            mask &= pm;
            if mask == 0 {
                return None;
            }
        }
        m.push(mask);
    }
    Some(m)
}

/// The widest axis of `s` (the last of equally wide ones, as `max_by`
/// picks) and its width.
fn widest(s: &Axes, dim: usize) -> (usize, f64) {
    let a = (0..dim)
        .max_by(|&a, &b| s[a].width().total_cmp(&s[b].width()))
        .unwrap_or(0);
    (a, s[a].width())
}

/// `s` cut in two at the midpoint of `axis`.
fn halves(s: &Axes, axis: usize) -> [Axes; 2] {
    let mid = s[axis].mid();
    let (mut a, mut b) = (*s, *s);
    a[axis] = Interval::new(s[axis].lo(), mid);
    b[axis] = Interval::new(mid, s[axis].hi());
    [a, b]
}

/// Depth-first search of the admissible maps (module doc) given each
/// group's candidate mask; ORs every complete map into `reach`. Returns
/// false when the node budget ran out (then `reach` is partial).
fn maps(
    masks: &[u64],
    distinct: &dyn Fn(usize, usize) -> bool,
    g: usize,
    assign: &mut [usize],
    reach: &mut [u64],
    nodes: &mut usize,
    budget: usize,
) -> bool {
    if g == masks.len() {
        for (r, &a) in reach.iter_mut().zip(assign.iter()) {
            *r |= 1 << a;
        }
        return true;
    }
    let mut m = masks[g];
    while m != 0 {
        let i = m.trailing_zeros() as usize;
        m &= m - 1;
        *nodes += 1;
        if *nodes > budget {
            return false;
        }
        if (0..g).any(|h| assign[h] == i && distinct(g, h)) {
            continue;
        }
        assign[g] = i;
        if !maps(masks, distinct, g + 1, assign, reach, nodes, budget) {
            return false;
        }
    }
    assign[g] = usize::MAX;
    true
}

/// `boxes` (of dimension `dim`) coarsened to at most `coarse` boxes, as
/// [`register_on`] coarsens each piece of a [`LocalGroup`]: the same boxes,
/// bit for bit, and a piece given already coarsened is read unchanged, so
/// a caller may coarsen a piece once and keep it. O(m² · d).
pub fn coarsen_piece(boxes: &[IntervalBox], dim: usize, coarse: usize) -> Vec<IntervalBox> {
    coarsen(boxes.iter().map(to_axes).collect(), dim, coarse)
        .iter()
        .map(|a| IntervalBox::new(&a[..dim]))
        .collect()
}

/// Half-perimeter of a box (its first `dim` axes).
fn size(h: &Axes, dim: usize) -> f64 {
    h[..dim].iter().map(|x| x.width()).sum()
}

fn hull2(a: &Axes, b: &Axes, dim: usize) -> Axes {
    let mut h = *a;
    for x in 0..dim {
        h[x] = a[x].hull(b[x]);
    }
    h
}

/// `set` reduced to at most `max` boxes whose union holds the union of
/// `set` (boxes inside another dropped, then neighbours along the widest
/// axis replaced by their hulls, cheapest first).
fn coarsen(mut set: Vec<Axes>, dim: usize, max: usize) -> Vec<Axes> {
    merge(&mut set, dim, max);
    set
}

/// Reduces `set` to at most `max` boxes keeping their union's points.
fn merge(set: &mut Vec<Axes>, dim: usize, max: usize) {
    let max = max.max(1);
    if set.len() <= max {
        return;
    }
    // Drop boxes inside another (the first of two equal ones is kept).
    let inside = |a: &Axes, b: &Axes| (0..dim).all(|x| a[x].is_subset(b[x]));
    let mut keep = vec![true; set.len()];
    for i in 0..set.len() {
        for j in 0..set.len() {
            if i != j && keep[j] && inside(&set[i], &set[j]) && (j < i || !inside(&set[j], &set[i]))
            {
                keep[i] = false;
                break;
            }
        }
    }
    let mut i = 0;
    set.retain(|_| {
        i += 1;
        keep[i - 1]
    });
    if set.len() <= max {
        return;
    }
    // Order along the widest axis of the whole union, then merge the
    // cheapest neighbours.
    let all = set.iter().skip(1).fold(set[0], |a, b| hull2(&a, b, dim));
    let axis = (0..dim)
        .max_by(|&a, &b| all[a].width().total_cmp(&all[b].width()))
        .unwrap_or(0);
    crate::sort::sort_by(set, |a, b| {
        a[axis]
            .mid()
            .total_cmp(&b[axis].mid())
            .then_with(|| a[axis].lo().total_cmp(&b[axis].lo()))
            .then_with(|| a[axis].hi().total_cmp(&b[axis].hi()))
            .then_with(|| {
                // Ties broken on every axis: the order, and so the merge,
                // depends on the boxes alone.
                (0..dim)
                    .map(|x| {
                        a[x].lo()
                            .total_cmp(&b[x].lo())
                            .then(a[x].hi().total_cmp(&b[x].hi()))
                    })
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            })
    });
    merge_neighbours(set, dim, max);
}

/// Merges the cheapest neighbours of `set` (in its order) into their hull
/// until at most `max` boxes are left: the cost of a merge is the growth
/// of the half-perimeter over the larger box's; the first of equal costs
/// goes first. The cost of each box with the next is kept as the merges
/// go (only the two next to a merge change): the same costs, so the same
/// merges, as computing them all again before each merge. O(m²) for m
/// boxes.
fn merge_neighbours(set: &mut Vec<Axes>, dim: usize, max: usize) {
    if set.len() <= max.max(1) {
        return;
    }
    let cost = |set: &[Axes], i: usize| {
        let h = hull2(&set[i], &set[i + 1], dim);
        size(&h, dim) - size(&set[i], dim).max(size(&set[i + 1], dim))
    };
    let mut costs: Vec<f64> = (0..set.len() - 1).map(|i| cost(set, i)).collect();
    while set.len() > max {
        let mut best = (f64::INFINITY, 0);
        for (i, &c) in costs.iter().enumerate() {
            if c < best.0 {
                best = (c, i);
            }
        }
        let i = best.1;
        set[i] = hull2(&set[i], &set[i + 1], dim);
        set.remove(i + 1);
        costs.remove(i);
        if i > 0 {
            costs[i - 1] = cost(set, i - 1);
        }
        if i + 1 < set.len() {
            costs[i] = cost(set, i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b2(x: (f64, f64), y: (f64, f64)) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x.0, x.1), Interval::new(y.0, y.1)])
    }

    /// Two landmarks at (0, 0) and (10, 0); the robot at (5, 5) sees them
    /// at (-5, -5) and (5, -5) in its frame (two groups proved distinct).
    /// Placing the local pair on the regions leaves p within a bisection
    /// width of [4, 6]², and the swapped map (p near (15, 5) for one group,
    /// near (-5, 5) for the other) has no common point: each group gets its
    /// own witness.
    /// The merges of [`merge_neighbours`] (costs kept between merges) are
    /// those of computing every neighbour's cost again before each merge
    /// (the loop it replaced), bit for bit, on random sets with
    /// many equal costs (boxes on a grid); and a piece coarsened by
    /// [`coarsen_piece`] is read unchanged when coarsened again.
    #[test]
    fn kept_merge_costs_give_the_merges_of_the_full_scan() {
        fn full_scan(set: &mut Vec<Axes>, dim: usize, max: usize) {
            while set.len() > max {
                let mut best = (f64::INFINITY, 0);
                for i in 0..set.len() - 1 {
                    let h = hull2(&set[i], &set[i + 1], dim);
                    let cost = size(&h, dim) - size(&set[i], dim).max(size(&set[i + 1], dim));
                    if cost < best.0 {
                        best = (cost, i);
                    }
                }
                let i = best.1;
                set[i] = hull2(&set[i], &set[i + 1], dim);
                set.remove(i + 1);
            }
        }
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        for case in 0..400 {
            let (dim, count, max) = (2 + case % 2, 1 + next(60) as usize, 1 + next(14) as usize);
            let set: Vec<Axes> = (0..count)
                .map(|_| {
                    let mut a = [Interval::ZERO; MAX_DIM];
                    for x in a.iter_mut().take(dim) {
                        let lo = next(20) as f64 * 0.5 - 5.0;
                        *x = Interval::new(lo, lo + next(6) as f64 * 0.25);
                    }
                    a
                })
                .collect();
            let (mut kept, mut full) = (set.clone(), set.clone());
            merge_neighbours(&mut kept, dim, max);
            full_scan(&mut full, dim, max);
            let bits = |v: &[Axes]| -> Vec<u64> {
                v.iter()
                    .flat_map(|a| a.iter().flat_map(|x| [x.lo().to_bits(), x.hi().to_bits()]))
                    .collect()
            };
            assert_eq!(bits(&kept), bits(&full), "case {case}");
            let boxes: Vec<IntervalBox> = set.iter().map(|a| IntervalBox::new(&a[..dim])).collect();
            let once = coarsen_piece(&boxes, dim, max);
            assert!(once.len() <= max, "case {case}");
            assert_eq!(coarsen_piece(&once, dim, max), once, "case {case}");
        }
    }

    /// The hull before each block of difference boxes only skips blocks
    /// that no box of them meets: the masks are those of testing every
    /// difference box, on random witnesses, pieces and boxes of p(s).
    #[test]
    fn block_hulls_give_the_masks_of_every_difference_box() {
        let mut rng = crate::rng::Rng::new(1806);
        let mut b = || {
            let lo = rng.unit() * 20.0 - 10.0;
            Interval::new(lo, lo + rng.unit() * 3.0)
        };
        for case in 0..300 {
            let w: Vec<Vec<Axes>> = (0..3)
                .map(|_| {
                    (0..1 + case % 5)
                        .map(|_| to_axes(&IntervalBox::new(&[b(), b()])))
                        .collect()
                })
                .collect();
            let groups: Vec<LocalGroup> = (0..2)
                .map(|g| LocalGroup {
                    pieces: (0..2)
                        .map(|_| {
                            (0..1 + case % 7)
                                .map(|_| IntervalBox::new(&[b(), b()]))
                                .collect()
                        })
                        .collect(),
                    fixed: (g == 1 && case % 2 == 0).then_some(2),
                })
                .collect();
            let diff = differences(&w, &groups, 2, 4);
            for _ in 0..20 {
                let s = to_axes(&IntervalBox::new(&[b(), b()]));
                let every: Option<Vec<u64>> = diff
                    .iter()
                    .map(|g| {
                        let mask = g.iter().fold(7u64, |mask, piece| {
                            let mut pm = 0;
                            for (i, (block, boxes)) in piece.iter().enumerate() {
                                let hit = boxes
                                    .chunks(*block)
                                    .any(|c| c[1..].iter().any(|d| meets(&s, d, 2)));
                                if hit {
                                    pm |= 1 << i;
                                }
                            }
                            mask & pm
                        });
                        (mask != 0).then_some(mask)
                    })
                    .collect();
                assert_eq!(
                    candidate_masks(&diff, &s, 7, 2, &mut 0),
                    every,
                    "case {case}"
                );
            }
        }
    }

    #[test]
    fn a_local_pair_places_the_robot_and_names_the_landmarks() {
        let witnesses = vec![
            vec![b2((-0.5, 0.5), (-0.5, 0.5))],
            vec![b2((9.5, 10.5), (-0.5, 0.5))],
        ];
        let groups = vec![
            LocalGroup {
                pieces: vec![vec![b2((-5.5, -4.5), (-5.5, -4.5))]],
                fixed: None,
            },
            LocalGroup {
                pieces: vec![vec![b2((4.5, 5.5), (-5.5, -4.5))]],
                fixed: None,
            },
        ];
        let p = b2((-20.0, 20.0), (-20.0, 20.0));
        let opts = RegisterOptions::default();
        let reg = register(&p, &witnesses, &groups, &|_, _| true, &opts);
        assert_eq!(reg.reach, vec![0b01, 0b10]);
        for a in 0..2 {
            assert!(reg.p[a].lo() >= 4.0 - opts.min_width && reg.p[a].hi() <= 6.0 + opts.min_width);
            assert!(reg.p[a].contains(5.0));
        }
        // Without the distinct pair the maps sending both groups to one
        // landmark are tried too: each needs p near two different points
        // ((5, 5) and (-5, 5), or (15, 5) and (5, 5)), so the answer is the
        // same.
        let reg = register(&p, &witnesses, &groups, &|_, _| false, &opts);
        assert_eq!(reg.reach, vec![0b01, 0b10]);
        assert!(reg.p[0].contains(5.0) && reg.p[1].contains(5.0));
    }

    /// Beyond 64 witnesses (the width of the candidate masks) nothing is
    /// contracted and every witness stays a candidate.
    #[test]
    fn more_than_64_witnesses_contract_nothing() {
        let witnesses: Vec<Vec<IntervalBox>> = (0..65)
            .map(|i| vec![b2((i as f64, i as f64 + 0.5), (0.0, 0.5))])
            .collect();
        let groups = vec![LocalGroup {
            pieces: vec![vec![b2((-0.5, 0.5), (-0.5, 0.5))]],
            fixed: None,
        }];
        let p = b2((-100.0, 100.0), (-100.0, 100.0));
        let reg = register(
            &p,
            &witnesses,
            &groups,
            &|_, _| true,
            &RegisterOptions::default(),
        );
        assert_eq!((reg.p, reg.reach), (p, vec![u64::MAX]));
    }

    /// A group that is a witness group keeps its witness; a position box
    /// the constellation cannot fit is emptied.
    #[test]
    fn no_placement_empties_the_position() {
        let witnesses = vec![vec![b2((-0.5, 0.5), (-0.5, 0.5))]];
        let groups = vec![LocalGroup {
            pieces: vec![vec![b2((-5.5, -4.5), (-5.5, -4.5))]],
            fixed: Some(0),
        }];
        let at = |p: IntervalBox| {
            register(
                &p,
                &witnesses,
                &groups,
                &|_, _| true,
                &RegisterOptions::default(),
            )
        };
        // p would have to be within [4, 6]².
        assert!(at(b2((10.0, 20.0), (10.0, 20.0))).p.is_empty());
        let reg = at(b2((0.0, 20.0), (0.0, 20.0)));
        assert!(!reg.p.is_empty() && reg.p[0].contains(5.0));
        assert_eq!(reg.reach, vec![1]);
    }
}
