//! Shape witnesses: pairwise-disjoint detection shapes (or landmark
//! regions) prove distinct landmarks (docs/design.md, "Detection shapes").
//!
//! # Math
//!
//! Each item is a set known to hold one landmark: a detection's shape
//! ([`Shape`]) or a proved group's region ([`Paving`]). If t items are
//! pairwise disjoint, their landmarks are pairwise distinct, so the
//! detections see at least t landmarks: t > n is infeasible (the items are
//! named), and t = n means the landmarks are exactly those of the t items
//! (branch contraction then applies, see [`super::branch`]).
//!
//! # Finding them
//!
//! A largest set of pairwise-disjoint items is a maximum clique of the
//! disjointness graph (NP-hard). Exact search on a pool: the caller's seed
//! (last round's witnesses) and the best-ranked items (proved groups'
//! regions by area, then the thinnest shapes), at most 64, whose
//! disjointness graph (bit sets) is searched by branch and bound (bound:
//! chosen + candidates left) with a node budget, stopping at the wanted
//! size. Then a greedy pass over every other item, thinnest first, adds
//! each item disjoint from all chosen. Any set found is sound: each pair is
//! proved disjoint by a sound test.
//!
//! # Complexity
//!
//! O(k log k) to order, 64^2 pair tests for the pool, the node budget for
//! the clique search, O(k · want) pair tests for the greedy pass. Pair
//! tests: O(d) for two shapes, O(m d) for a shape and an m-box region,
//! O(m m') for two regions.

use super::region::Paving;
use super::shape::{disjoint_paved, DetectionShape, Shape};

/// A set holding one landmark (or emitter): a shape of any
/// [`DetectionShape`] type ([`Shape`] by default) or a region.
#[derive(Debug)]
pub enum Item<'a, S: DetectionShape = Shape> {
    /// A detection's shape.
    Shape(&'a S),
    /// A proved group's region.
    Region(&'a Paving),
}

/// Most items in the exact search's pool (one u64 bit set per item).
pub const POOL: usize = 64;

/// Pieces allowed to [`disjoint_paved`] when a pair is worth paving (a
/// shape with a bearing, a pulse's shell).
const PAVED_BUDGET: usize = 32;

impl<S: DetectionShape> Clone for Item<'_, S> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<S: DetectionShape> Copy for Item<'_, S> {}

impl<S: DetectionShape> Item<'_, S> {
    /// Whether the item holds no point (then it is no witness of
    /// anything).
    pub fn is_empty(&self) -> bool {
        match self {
            Item::Shape(s) => s.is_empty(),
            Item::Region(r) => r.is_empty(),
        }
    }

    /// A rank key, smaller is more telling: regions of proved groups
    /// first (by the total area, or volume, of their boxes), then shapes
    /// (by their thickness).
    pub fn size(&self) -> (u8, f64) {
        match self {
            Item::Region(r) => (0, r.boxes().iter().map(|b| b.volume()).sum()),
            Item::Shape(s) => (1, s.thickness()),
        }
    }

    /// A proof that the two items share no point (`false`: not proved).
    /// An empty item proves nothing (see [`Shape::disjoint`]).
    pub fn disjoint(&self, other: &Item<S>) -> bool {
        if self.is_empty() || other.is_empty() {
            return false;
        }
        match (self, other) {
            (Item::Shape(a), Item::Shape(b)) => {
                a.disjoint_quick(b) || (a.worth_paving(b) && disjoint_paved(*a, *b, PAVED_BUDGET))
            }
            (Item::Shape(s), Item::Region(r)) | (Item::Region(r), Item::Shape(s)) => {
                !r.meets_shape(*s)
            }
            (Item::Region(a), Item::Region(b)) => !a.meets(b),
        }
    }
}

/// Finds up to `want` pairwise-disjoint items (module doc) among `sizes.len()`
/// (ranked by `sizes`, smallest first)
/// items, `disjoint(a, b)` proving two of them disjoint (or distinct);
/// `seed` lists items to try first. Returns their indices, in the order
/// found.
pub fn find_witnesses(
    sizes: &[(u8, f64)],
    disjoint: &mut dyn FnMut(usize, usize) -> bool,
    want: usize,
    seed: &[usize],
    node_budget: usize,
) -> Vec<usize> {
    let k = sizes.len();
    if k == 0 || want == 0 {
        return Vec::new();
    }
    let mut order: Vec<usize> = (0..k).collect();
    crate::sort::sort_indices_by(&mut order, |a, b| {
        (sizes[a].0.cmp(&sizes[b].0)).then(sizes[a].1.total_cmp(&sizes[b].1))
    });
    let mut pool: Vec<usize> = Vec::with_capacity(POOL);
    let mut in_pool = vec![false; k];
    for &i in seed.iter().chain(order.iter()) {
        if pool.len() == POOL {
            break;
        }
        if i < k && !in_pool[i] {
            in_pool[i] = true;
            pool.push(i);
        }
    }
    let m = pool.len();
    let mut adj = vec![0u64; m];
    for a in 0..m {
        for b in a + 1..m {
            if disjoint(pool[a], pool[b]) {
                adj[a] |= 1 << b;
                adj[b] |= 1 << a;
            }
        }
    }
    let all = if m == 64 { u64::MAX } else { (1u64 << m) - 1 };
    let mut search = Clique {
        adj: &adj,
        want,
        best: 0,
        best_len: 0,
        nodes: 0,
        budget: node_budget,
    };
    search.expand(0, 0, all);
    let mut chosen: Vec<usize> = (0..m)
        .filter(|&b| search.best >> b & 1 == 1)
        .map(|b| pool[b])
        .collect();
    if chosen.len() < want {
        let mut taken = vec![false; k];
        for &c in &chosen {
            taken[c] = true;
        }
        for &i in &order {
            if taken[i] {
                continue;
            }
            if chosen.iter().all(|&c| disjoint(c, i)) {
                chosen.push(i);
                if chosen.len() >= want {
                    break;
                }
            }
        }
    }
    chosen
}

/// Branch and bound for a clique of the disjointness graph.
struct Clique<'a> {
    adj: &'a [u64],
    want: usize,
    best: u64,
    best_len: usize,
    nodes: usize,
    budget: usize,
}

impl Clique<'_> {
    /// Extends the clique `r` (size `len`) by candidates `p` (each adjacent
    /// to all of r).
    fn expand(&mut self, r: u64, len: usize, mut p: u64) {
        self.nodes += 1;
        if len > self.best_len {
            self.best = r;
            self.best_len = len;
        }
        while p != 0 {
            if self.best_len >= self.want
                || self.nodes >= self.budget
                || len + p.count_ones() as usize <= self.best_len
            {
                return;
            }
            let v = p.trailing_zeros() as usize;
            p &= !(1u64 << v);
            self.expand(r | 1 << v, len + 1, p & self.adj[v]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ibox::IntervalBox;
    use crate::interval::Interval;

    fn ring(r0: f64, r1: f64) -> Shape {
        Shape::new(
            IntervalBox::new(&[Interval::new(-0.1, 0.1), Interval::new(-0.1, 0.1)]),
            Interval::new(r0, r1),
            None,
            IntervalBox::entire(2),
        )
    }

    #[test]
    fn nested_rings_are_found_and_pairwise_disjoint() {
        // Rings [5k, 5k+2] around one point are pairwise disjoint; crossing
        // wide rings [0, 30] are not.
        let mut shapes: Vec<Shape> = (0..4)
            .map(|i| ring(5.0 * i as f64, 5.0 * i as f64 + 2.0))
            .collect();
        shapes.extend((0..10).map(|_| ring(0.0, 30.0)));
        let items: Vec<Item> = shapes.iter().map(Item::Shape).collect();
        let sizes: Vec<(u8, f64)> = items.iter().map(|i| i.size()).collect();
        let w = find_witnesses(
            &sizes,
            &mut |a, b| items[a].disjoint(&items[b]),
            5,
            &[],
            10_000,
        );
        assert_eq!(w.len(), 4);
        for (a, &i) in w.iter().enumerate() {
            for &j in &w[a + 1..] {
                assert!(items[i].disjoint(&items[j]));
            }
        }
    }

    /// An empty shape or region is no witness: it is disjoint from nothing
    /// (its emptiness is a proof of infeasibility, not of distinct
    /// landmarks).
    #[test]
    fn empty_items_prove_nothing() {
        let a = ring(5.0, 6.0);
        let mut empty = ring(20.0, 21.0);
        assert!(Item::Shape(&a).disjoint(&Item::Shape(&empty)));
        empty.centre = IntervalBox::empty(2);
        let none = Paving::from_box(&IntervalBox::empty(2));
        let far = Paving::from_box(&IntervalBox::new(&[
            Interval::new(50.0, 51.0),
            Interval::new(50.0, 51.0),
        ]));
        for (x, y) in [
            (Item::Shape(&a), Item::Shape(&empty)),
            (Item::Shape(&a), Item::Region(&none)),
            (Item::Region(&far), Item::Region(&none)),
            (Item::Region(&far), Item::Shape(&empty)),
        ] {
            assert!(!x.disjoint(&y) && !y.disjoint(&x));
        }
        assert!(Item::Shape(&a).disjoint(&Item::Region(&far)));
    }
}
