//! The minimum separation inside the passes (odometry2d): each detection is
//! compared with the groups' landmark boxes as the pass reaches it, a
//! sequential filter, so that a landmark seen again joins its group (and
//! contracts the pose) in the same pass rather than at the end of the
//! round ([`super::separation`]).
//!
//! # Constraint
//!
//! Distinct landmarks are at least s apart (`landmark_min_separation`):
//! `l(a) != l(b)` implies `|l(a) - l(b)| >= s`; every detection sees a
//! real landmark (`max_outliers` = 0).
//!
//! # Math
//!
//! When the pass reaches detection j, its group's box B (held at the
//! group's root, the intersection of what the group's members proved so
//! far) is compared with the boxes G of the groups held in a grid of
//! cells of side s (each group under the cell of its box's centre when it
//! was entered). When no point of B is s or more from a point of G
//! ([`super::separation::farthest_above`] below s) the two landmarks are less than s apart, so they are one: a union, and
//! the merged group's box is B ∩ G. Only groups whose centre was within
//! two cells of B's centre are compared (a group whose points are all
//! within s of B's has its centre within s of B's). B itself may be up to
//! 2 s wide (a wider box has points 2 s apart, at least s from any G).
//!
//! # Soundness
//!
//! The argument of [`super::separation`]: every box holds its group's true
//! landmark at every moment of the pass (each contraction keeps every
//! solution), so the two landmarks, one in each box, are less than the
//! largest cross distance apart; it is bounded from above with outward
//! rounding, so "below s" is proved, and with it one landmark (when both
//! groups see real landmarks). Its point is then in B ∩ G; an empty
//! intersection proves the mission infeasible. A grid entry left behind by
//! a moved centre or a merged group only makes the rule miss unions
//! (entries are read through the union-find's current roots).
//!
//! # Complexity
//!
//! O(1) expected per grid lookup (25 per detection) and O(c) box tests
//! per detection, c the groups entered in the 25 cells around it (bounded
//! by the packing of
//! boxes narrower than s, at most a few tens when the groups are distinct
//! landmarks; a cell's list holds one entry per group, [`compact`], so a
//! landmark seen n times costs one test, not n); memory O(G).

use super::separation::{diameter_above, farthest_above};
use crate::ibox::IntervalBox;
use crate::union_find::Uf;
use std::collections::HashMap;

/// Groups narrower than s, by the grid cell of their box's centre.
#[derive(Debug, Clone, Default)]
pub struct SeparationGrid {
    s: f64,
    /// Per cell ([`cell_key`]), the index of its list in `lists` (a map
    /// of the key type the clique rule's memo uses: no second map's code
    /// in the browser's build; it is only looked up, never walked).
    cells: HashMap<u64, usize>,
    /// The cells' lists of entered detections, in their order of entry.
    lists: Vec<Vec<usize>>,
    /// Per detection: entered in the grid (as a representative).
    entered: Vec<bool>,
    /// Whether the lists are compacted ([`compact`]): always, but for the
    /// test that compares the grid with and without it.
    #[cfg(test)]
    compacts: bool,
}

/// The cell of `x` (the centre of a bounded box) for a side `s`.
fn cell(x: f64, s: f64) -> i64 {
    // Bounded boxes narrower than s: x / s is finite; the cast saturates
    // for huge coordinates (those only miss unions).
    libm::floor(x / s) as i64
}

/// The key of cell (x, y): both indices clamped to 32 bits, side by side.
/// One key per cell within 2^31 cells of the origin; the cells beyond
/// share keys, which only adds groups to compare (every union is still
/// proved by its box test).
fn cell_key(x: i64, y: i64) -> u64 {
    let c = |v: i64| v.clamp(i32::MIN as i64, i32::MAX as i64) as i32 as u32 as u64;
    (c(x) << 32) | c(y)
}

impl SeparationGrid {
    /// An empty grid for `k` detections and separation `s` (None: the
    /// rule does not apply, s <= 0 or NaN).
    pub fn new(k: usize, s: f64) -> Option<SeparationGrid> {
        (s > 0.0 && s.is_finite()).then(|| SeparationGrid {
            s,
            cells: HashMap::new(),
            lists: Vec::new(),
            entered: vec![false; k],
            #[cfg(test)]
            compacts: true,
        })
    }

    /// Whether the lists are compacted (always outside the tests).
    fn compacts(&self) -> bool {
        #[cfg(test)]
        return self.compacts;
        #[cfg(not(test))]
        true
    }

    /// The cell of the centre of `b` (None: not a 2-D box narrower than s).
    fn key(&self, b: &IntervalBox) -> Option<(i64, i64)> {
        self.key_within(b, self.s)
    }

    /// The cell of the centre of `b` (None: not a 2-D box narrower than
    /// `w`, w <= 2 s: the cell index stays finite for bounded boxes).
    fn key_within(&self, b: &IntervalBox, w: f64) -> Option<(i64, i64)> {
        if b.dim() != 2 || b.is_empty() || diameter_above(b) >= w {
            return None;
        }
        Some((cell(b[0].mid(), self.s), cell(b[1].mid(), self.s)))
    }

    /// Detection j's group (box `det[root]`) compared with the grid's
    /// groups (module doc); the unions are applied to `uf` and `det` (the
    /// merged root holds the intersection) and returned. Err: two groups
    /// proved to be one landmark have disjoint boxes.
    pub fn merge(
        &mut self,
        det: &mut [IntervalBox],
        uf: &mut Uf,
        j: usize,
    ) -> Result<Vec<(usize, usize)>, String> {
        let mut unions = Vec::new();
        let mut root = uf.find(j);
        let Some((cx, cy)) = self.key_within(&det[root], 2.0 * self.s) else {
            return Ok(unions);
        };
        let mut seen: Vec<usize> = Vec::new();
        let compacts = self.compacts();
        for x in cx.saturating_sub(2)..=cx.saturating_add(2) {
            for y in cy.saturating_sub(2)..=cy.saturating_add(2) {
                let Some(&at) = self.cells.get(&cell_key(x, y)) else {
                    continue;
                };
                let list = &mut self.lists[at];
                if compacts {
                    compact(list, uf);
                }
                for &e in list.iter() {
                    let r = uf.find(e);
                    if r == root || seen.contains(&r) {
                        continue;
                    }
                    seen.push(r);
                    let (b, g) = (&det[root], &det[r]);
                    if g.is_empty() || farthest_above(b, g) >= self.s {
                        continue;
                    }
                    let common = b.intersect(g);
                    if common.is_empty() {
                        return Err(format!(
                            "landmark_min_separation: detections {e} and {j} (with their groups) are closer than {} so one landmark, but their boxes have no common point",
                            self.s
                        ));
                    }
                    let nr = uf.union(root, r);
                    det[root] = common.clone();
                    det[r] = common;
                    unions.push((e, j));
                    root = nr;
                }
            }
        }
        if !self.entered[j] {
            if let Some(k) = self.key(&det[root]) {
                self.entered[j] = true;
                // j is entered in cell k once (as before); when an entry
                // of k already has j's root, j would be shadowed there for
                // good (see [`compact`]), so it is not pushed.
                let next = self.lists.len();
                let at = *self.cells.entry(cell_key(k.0, k.1)).or_insert(next);
                if at == next {
                    self.lists.push(Vec::new());
                }
                let list = &mut self.lists[at];
                if !compacts || !list.iter().any(|&e| uf.find(e) == root) {
                    list.push(j);
                }
            }
        }
        Ok(unions)
    }
}

/// Drops from a cell's list every entry whose group's root is already the
/// root of an earlier entry of the list; the rest keep their order.
///
/// The same unions in the same order: [`SeparationGrid::merge`] reads a
/// list in order and skips an entry whose root is the current group's or
/// one it has already compared. Groups only merge, so two entries that
/// share a root now share it for good; when the walk reaches the later one
/// the earlier one was reached first and either compared (its root is in
/// `seen`, or merged into the current group) or skipped for the same two
/// reasons, so the later one is skipped too, whatever unions happen in
/// between (a union merges only the current group with a compared one;
/// roots are smallest members, untouched by path compression). The error
/// and the unions name the entry compared, the earlier one, which stays.
///
/// O(n · c) for n entries and c distinct roots in the list; each entry is
/// dropped at most once, so the lists stay at about the groups in a cell
/// (without it a cell's list grows with every detection of its landmark:
/// O(n) per read for a landmark seen n times).
fn compact(list: &mut Vec<usize>, uf: &mut Uf) {
    let mut kept = 0;
    for i in 0..list.len() {
        let (e, r) = (list[i], uf.find(list[i]));
        if !list[..kept].iter().any(|&x| uf.find(x) == r) {
            list[kept] = e;
            kept += 1;
        }
    }
    list.truncate(kept);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;

    fn square(x: f64, y: f64, w: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x, x + w), Interval::new(y, y + w)])
    }

    /// Two boxes of one landmark (hull 0.5 wide) merge; a box 1.2 away
    /// (hull diameter above s = 1) does not; the merged root holds the
    /// intersection.
    #[test]
    fn near_boxes_merge_and_far_ones_do_not() {
        let mut det = vec![
            square(0.0, 0.0, 0.4),
            square(0.1, 0.1, 0.4),
            square(1.2, 0.0, 0.4),
        ];
        let mut uf = Uf::new(3);
        let mut g = SeparationGrid::new(3, 1.0).expect("a grid");
        assert!(g.merge(&mut det, &mut uf, 0).expect("no error").is_empty());
        assert_eq!(
            g.merge(&mut det, &mut uf, 1).expect("no error"),
            vec![(0, 1)]
        );
        let r = uf.find(0);
        assert_eq!(det[r], square(0.1, 0.1, 0.3));
        assert!(g.merge(&mut det, &mut uf, 2).expect("no error").is_empty());
        assert_ne!(uf.find(2), uf.find(0));
    }

    /// The grid with and without the compaction of its lists, on random
    /// detections of a few landmarks (boxes around them, some wider than
    /// s, some misplaced so that a proved union meets disjoint boxes): the
    /// same unions in the same order, the same errors, the same groups and
    /// boxes after every merge.
    #[test]
    fn compacted_lists_give_the_same_unions() {
        let mut rng = crate::rng::Rng::new(38);
        let (mut unions, mut errors, mut shorter) = (0usize, 0usize, 0usize);
        let len = |g: &SeparationGrid| g.lists.iter().map(Vec::len).sum::<usize>();
        for case in 0..400 {
            let k = 20 + case % 80;
            let s = 1.0;
            let marks: Vec<(f64, f64)> = (0..1 + case % 9)
                .map(|_| (rng.sym(6.0), rng.sym(6.0)))
                .collect();
            let mut det: Vec<IntervalBox> = (0..k)
                .map(|_| {
                    let (x, y) = marks[rng.next_u64() as usize % marks.len()];
                    let w = [0.05, 0.3, 0.9, 1.6][rng.next_u64() as usize % 4];
                    let off = if rng.next_u64().is_multiple_of(25) {
                        0.6
                    } else {
                        0.0
                    };
                    let (dx, dy) = (rng.sym(w * 0.5), rng.sym(w * 0.5));
                    square(x + dx - w * 0.5 + off, y + dy - w * 0.5, w)
                })
                .collect();
            let mut det2 = det.clone();
            let (mut uf, mut uf2) = (Uf::new(k), Uf::new(k));
            let mut g = SeparationGrid::new(k, s).expect("a grid");
            let mut plain = g.clone();
            plain.compacts = false;
            // Each detection reached by two passes, as the passes do.
            for j in (0..k).chain(0..k) {
                let a = g.merge(&mut det, &mut uf, j);
                let b = plain.merge(&mut det2, &mut uf2, j);
                assert_eq!(a, b, "case {case} detection {j}");
                match a {
                    Ok(u) => unions += u.len(),
                    Err(_) => {
                        errors += 1;
                        break;
                    }
                }
                assert_eq!(det, det2, "case {case} detection {j}");
                for i in 0..k {
                    assert_eq!(uf.find(i), uf2.find(i), "case {case}");
                }
            }
            shorter += (len(&g) < len(&plain)) as usize;
        }
        // The compaction is exercised: lists it made shorter.
        assert!(
            unions > 1000 && errors > 10 && shorter > 100,
            "{unions} unions, {errors} errors, {shorter} shorter"
        );
    }

    /// A box wider than s is never merged, nor entered.
    #[test]
    fn wide_boxes_prove_nothing() {
        let mut det = vec![square(0.0, 0.0, 0.4), square(0.0, 0.0, 1.5)];
        let mut uf = Uf::new(2);
        let mut g = SeparationGrid::new(2, 1.0).expect("a grid");
        assert!(g.merge(&mut det, &mut uf, 0).expect("no error").is_empty());
        assert!(g.merge(&mut det, &mut uf, 1).expect("no error").is_empty());
        assert!(SeparationGrid::new(2, 0.0).is_none());
        assert!(SeparationGrid::new(2, f64::NAN).is_none());
    }
}
