//! Relative displacements along the motion chain: an enclosure of
//! `p(t) - p(s)` for any two steps, without the drift of the absolute
//! boxes.
//!
//! # Math
//!
//! The Euler chain gives `p(t) - p(s) = Σ_{u=s}^{t-1} D_true(u)` with each
//! true displacement in its box D(u) = [lo_u, hi_u] (per axis), so
//! `p(t) - p(s) ∈ [Σ lo_u, Σ hi_u]`. The sums of lower (upper) bounds are
//! kept as prefix sums every `BLOCK` steps, each an outward-rounded interval
//! enclosing the exact real prefix sum; a query adds the steps between the
//! block boundary and the step, so
//! `Σ_{s}^{t-1} lo_u ∈ L(t) - L(s)` (interval difference) and its lower
//! bound is a sound lower bound (likewise for the upper bounds).
//!
//! Unbounded and huge bounds. A displacement may have an infinite bound (a
//! speed of `1e308 ± 1e308` is [0, +inf]; an error bound of f64::MAX
//! overflows when added): a lower bound below `-BIG` is counted as -inf and
//! an upper bound above `BIG` as +inf, in counts kept beside the finite
//! sums; a window whose count grows has that side infinite, and the other
//! windows keep their finite sums. A lower bound above `BIG` and an upper
//! bound below `-BIG` are replaced by 0 (a lower bound may only go down, an
//! upper bound only up). So the finite sums stay below `N · BIG` in
//! magnitude (no overflow for any N below 2^500) and hold no huge term: one
//! huge step leaves the windows that do not contain it as tight as before
//! (a huge term in the prefix sums would round every later window to its
//! own ulp). An
//! empty displacement (no motion is possible: the chain is infeasible) is
//! counted too, and a window containing one is empty.
//!
//! # Soundness
//!
//! Every finite sum is an interval enclosure of the exact real sum
//! (outward rounding) of bounds that are at most the true lower bounds (at
//! least the true upper bounds); an infinite side holds everything. The
//! true displacement sum lies between the exact sums of the bounds.
//!
//! # Complexity
//!
//! O(N d) to build, memory O(N d / BLOCK), O(BLOCK · d) per query.

use super::shape::MAX_DIM;
use crate::interval::Interval;

/// Steps between stored prefix sums.
const BLOCK: usize = 64;

/// Displacement bounds beyond this magnitude (2^500) are taken as infinite
/// (or as 0, see the module doc): a sum of fewer than 2^500 bounds below it
/// cannot overflow.
const BIG: f64 = 3.273_390_607_896_142e150;

/// The sums of the bounds of the displacements before one step, on one
/// axis (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Prefix {
    /// Enclosure of the sum of the lower bounds that are above `-BIG`
    /// (0 for those above `BIG`).
    lo: Interval,
    /// Enclosure of the sum of the upper bounds that are below `BIG`
    /// (0 for those below `-BIG`).
    hi: Interval,
    /// Lower bounds below `-BIG` (taken as -inf).
    lo_inf: usize,
    /// Upper bounds above `BIG` (taken as +inf).
    hi_inf: usize,
    /// Empty displacements.
    empty: usize,
}

impl Prefix {
    const ZERO: Prefix = Prefix {
        lo: Interval::ZERO,
        hi: Interval::ZERO,
        lo_inf: 0,
        hi_inf: 0,
        empty: 0,
    };

    /// Adds the bounds of one displacement `d`.
    #[inline]
    fn add(&mut self, d: Interval) {
        if d.is_empty() {
            self.empty += 1;
            return;
        }
        if d.lo() < -BIG {
            self.lo_inf += 1;
        } else {
            let lo = if d.lo() > BIG { 0.0 } else { d.lo() };
            self.lo = self.lo + Interval::point(lo);
        }
        if d.hi() > BIG {
            self.hi_inf += 1;
        } else {
            let hi = if d.hi() < -BIG { 0.0 } else { d.hi() };
            self.hi = self.hi + Interval::point(hi);
        }
    }

    /// An enclosure of the displacement sum between the steps of `self`
    /// and of `later` (a prefix at a later step).
    #[inline]
    fn window(&self, later: &Prefix) -> Interval {
        if later.empty > self.empty {
            return Interval::EMPTY;
        }
        let lo = if later.lo_inf > self.lo_inf {
            f64::NEG_INFINITY
        } else {
            (later.lo - self.lo).lo()
        };
        let hi = if later.hi_inf > self.hi_inf {
            f64::INFINITY
        } else {
            (later.hi - self.hi).hi()
        };
        Interval::new(lo, hi)
    }
}

/// Prefix sums of the displacement bounds (module doc).
#[derive(Debug, Clone)]
pub struct ChainSums<'a> {
    dim: usize,
    disp: &'a [Interval],
    /// Per block boundary b·BLOCK and axis: the sums of the bounds of the
    /// displacements before it.
    blocks: Vec<Prefix>,
    /// Steps whose prefix sums are kept too (sorted), and those sums.
    marks: Vec<usize>,
    mark_sums: Vec<Prefix>,
}

impl<'a> ChainSums<'a> {
    /// Prefix sums of `disp` (N·dim displacement boxes).
    pub fn new(disp: &'a [Interval], dim: usize) -> ChainSums<'a> {
        let n = disp.len() / dim.max(1);
        let mut blocks = Vec::with_capacity((n / BLOCK + 1) * dim);
        let mut sums = [Prefix::ZERO; MAX_DIM];
        for u in 0..=n {
            if u % BLOCK == 0 {
                blocks.extend_from_slice(&sums[..dim]);
            }
            if u < n {
                for (a, s) in sums.iter_mut().enumerate().take(dim) {
                    s.add(disp[u * dim + a]);
                }
            }
        }
        ChainSums {
            dim,
            disp,
            blocks,
            marks: Vec::new(),
            mark_sums: Vec::new(),
        }
    }

    /// Also keeps the prefix sums at `steps` (the detection steps), so that
    /// a query between two of them costs O(d). O(|steps| · BLOCK · d).
    pub fn with_steps(mut self, steps: &[usize]) -> ChainSums<'a> {
        let mut marks = steps.to_vec();
        crate::sort::sort_usize(&mut marks);
        marks.dedup();
        let mut sums = Vec::with_capacity(marks.len() * self.dim);
        for &t in &marks {
            for a in 0..self.dim {
                sums.push(self.walk(t, a));
            }
        }
        self.marks = marks;
        self.mark_sums = sums;
        self
    }

    /// The sums of the bounds before step `t` on axis `a`.
    fn prefix(&self, t: usize, a: usize) -> Prefix {
        if let Ok(i) = self.marks.binary_search(&t) {
            return self.mark_sums[i * self.dim + a];
        }
        self.walk(t, a)
    }

    /// [`ChainSums::prefix`] from the block boundary below `t`.
    fn walk(&self, t: usize, a: usize) -> Prefix {
        let dim = self.dim;
        let b = t / BLOCK;
        let mut p = self.blocks[b * dim + a];
        for u in b * BLOCK..t {
            p.add(self.disp[u * dim + a]);
        }
        p
    }

    /// The sums without the displacements they were read from, to be
    /// [`StoredSums::attach`]ed to the same displacements later (a
    /// propagation whose displacements do not change keeps them across
    /// rounds instead of building them again: O(N d) each round).
    pub fn store(self) -> StoredSums {
        StoredSums {
            dim: self.dim,
            len: self.disp.len(),
            blocks: self.blocks,
            marks: self.marks,
            mark_sums: self.mark_sums,
        }
    }

    /// An enclosure of p(t) - p(s) on each axis (first `dim` entries):
    /// unbounded on a side where a displacement between the steps is;
    /// empty only when a displacement between them is empty.
    pub fn delta(&self, s: usize, t: usize) -> [Interval; MAX_DIM] {
        let mut out = [Interval::ZERO; MAX_DIM];
        if s == t {
            return out;
        }
        let (from, to) = (s.min(t), s.max(t));
        for (a, o) in out.iter_mut().enumerate().take(self.dim) {
            let forward = self.prefix(from, a).window(&self.prefix(to, a));
            *o = if s < t { forward } else { -forward };
        }
        out
    }
}

/// A [`ChainSums`] without its displacements ([`ChainSums::store`]).
#[derive(Debug, Clone)]
pub struct StoredSums {
    dim: usize,
    len: usize,
    blocks: Vec<Prefix>,
    marks: Vec<usize>,
    mark_sums: Vec<Prefix>,
}

impl StoredSums {
    /// The sums again, reading `disp`, which must hold the very
    /// displacements (bit for bit) they were built from: the caller's
    /// promise (the queries then give the same bits as a fresh
    /// [`ChainSums::new`] with the same steps). None when `disp` or `dim`
    /// is not of the stored size (a different chain).
    pub fn attach(self, disp: &[Interval], dim: usize) -> Option<ChainSums<'_>> {
        (disp.len() == self.len && dim == self.dim).then_some(ChainSums {
            dim,
            disp,
            blocks: self.blocks,
            marks: self.marks,
            mark_sums: self.mark_sums,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_encloses_the_exact_sums_of_bounds() {
        use num_rational::BigRational;
        let rat = |x: f64| BigRational::from_float(x).expect("finite");
        let mut rng = crate::test_rng::Lcg::new(7);
        let n = 300;
        let disp: Vec<Interval> = (0..n * 2)
            .map(|_| {
                let c = (rng.unit() * 2.0 - 1.0) * 1e3;
                let w = rng.unit() * 0.1;
                Interval::new(c - w, c + w)
            })
            .collect();
        let sums = ChainSums::new(&disp, 2);
        for (s, t) in [
            (0, 0),
            (0, 300),
            (5, 70),
            (64, 128),
            (200, 3),
            (299, 300),
            (63, 65),
        ] {
            let d = sums.delta(s, t);
            let (from, to) = (s.min(t), s.max(t));
            for a in 0..2 {
                let (mut lo, mut hi) = (rat(0.0), rat(0.0));
                for u in from..to {
                    lo += rat(disp[u * 2 + a].lo());
                    hi += rat(disp[u * 2 + a].hi());
                }
                let (lo, hi) = if s <= t { (lo, hi) } else { (-hi, -lo) };
                assert!(rat(d[a].lo()) <= lo && hi <= rat(d[a].hi()), "{s} {t} {a}");
                // Tight: within a few ulps of the exact sums.
                let slack = rat(1e-9);
                assert!(lo - rat(d[a].lo()) < slack.clone() && rat(d[a].hi()) - hi < slack);
            }
        }
    }

    /// Regression: one displacement with an infinite bound (a speed of
    /// 1e308 ± 1e308 is [0, +inf]) made every later prefix sum empty, so
    /// every window across it was empty and every pair of detections across
    /// it "disjoint". Windows containing an unbounded, huge or overflowing
    /// step are unbounded on that side (never empty), and the windows that
    /// do not contain it keep the exact sums, tight.
    #[test]
    fn issue_19_unbounded_steps_give_unbounded_windows_not_empty_ones() {
        use num_rational::BigRational;
        let rat = |x: f64| BigRational::from_float(x).expect("finite");
        let n = 400;
        let mut disp = vec![Interval::new(0.9, 1.1); n];
        disp[10] = Interval::new(0.0, f64::INFINITY);
        disp[100] = Interval::new(f64::NEG_INFINITY, f64::INFINITY);
        disp[200] = Interval::new(-f64::MAX, f64::MAX);
        disp[250] = Interval::new(1e300, f64::MAX);
        disp[300] = Interval::new(-1e200, -1e160);
        let sums = ChainSums::new(&disp, 1).with_steps(&[5, 150, 399]);
        let d = |s: usize, t: usize| sums.delta(s, t)[0];
        assert!(
            d(0, 10).lo() > 8.9 && d(0, 10).hi() < 11.1,
            "{:?}",
            d(0, 10)
        );
        assert!(!d(5, 20).is_empty());
        assert_eq!(d(5, 20).hi(), f64::INFINITY);
        assert!(d(5, 20).lo() > 0.0, "{:?}", d(5, 20));
        assert_eq!(d(20, 5).lo(), f64::NEG_INFINITY);
        assert_eq!(d(50, 150), Interval::ENTIRE);
        assert_eq!(d(150, 50), Interval::ENTIRE);
        assert_eq!(d(199, 201), Interval::ENTIRE);
        // Above BIG: a lower bound is taken as 0, the upper one as +inf.
        // (0 up to the rounding of the prefix sums around it).
        let w = d(250, 251);
        assert!(
            w.lo() <= 0.0 && w.lo() > -1e-9 && w.hi() == f64::INFINITY,
            "{w:?}"
        );
        // Below -BIG: the lower bound as -inf, the upper one as 0.
        let w = d(300, 301);
        assert!(
            w.lo() == f64::NEG_INFINITY && w.hi() >= 0.0 && w.hi() < 1e-9,
            "{w:?}"
        );
        // Windows between the huge steps: the exact sums, tight.
        for (s, t) in [
            (11, 99),
            (101, 199),
            (201, 249),
            (301, 399),
            (0, 10),
            (260, 299),
        ] {
            for (a, b) in [(s, t), (t, s)] {
                let w = d(a, b);
                let (mut lo, mut hi) = (rat(0.0), rat(0.0));
                for x in &disp[s..t] {
                    lo += rat(x.lo());
                    hi += rat(x.hi());
                }
                let (lo, hi) = if a < b { (lo, hi) } else { (-hi, -lo) };
                assert!(rat(w.lo()) <= lo && hi <= rat(w.hi()), "{a} {b} {w:?}");
                let slack = rat(1e-9);
                assert!(
                    lo - rat(w.lo()) < slack.clone() && rat(w.hi()) - hi < slack,
                    "{a} {b}"
                );
            }
        }
        // An empty displacement (an infeasible chain) empties its windows
        // alone.
        let mut disp = vec![Interval::new(0.9, 1.1); 100];
        disp[40] = Interval::EMPTY;
        let sums = ChainSums::new(&disp, 1);
        assert!(sums.delta(30, 50)[0].is_empty());
        assert!(!sums.delta(41, 99)[0].is_empty() && !sums.delta(0, 40)[0].is_empty());
    }

    /// Sums kept across rounds answer, once attached to the
    /// same displacements, with the bits of freshly built ones; attached
    /// to a chain of another size or dimension they are refused.
    #[test]
    fn stored_sums_attached_again_answer_like_fresh_ones() {
        let disp: Vec<Interval> = (0..400)
            .map(|i| Interval::new(i as f64 * 0.013 - 1.0, i as f64 * 0.007 + 0.5))
            .collect();
        let steps = [3, 70, 150, 199];
        let fresh = ChainSums::new(&disp, 2).with_steps(&steps);
        let stored = ChainSums::new(&disp, 2).with_steps(&steps).store();
        assert!(stored.clone().attach(&disp[..398], 2).is_none());
        assert!(stored.clone().attach(&disp[..399], 3).is_none());
        let again = stored.attach(&disp, 2).expect("the same chain");
        let bits = |d: [Interval; MAX_DIM]| d.map(|x| (x.lo().to_bits(), x.hi().to_bits()));
        for (s, t) in [(0, 200), (3, 199), (70, 5), (150, 151), (64, 128), (199, 0)] {
            assert_eq!(bits(fresh.delta(s, t)), bits(again.delta(s, t)), "{s} {t}");
        }
    }
}
