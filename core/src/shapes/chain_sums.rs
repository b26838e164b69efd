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
//! # Soundness
//!
//! Every sum is an interval enclosure of the exact real sum (outward
//! rounding); the true displacement sum lies between the exact sums of the
//! bounds.
//!
//! # Complexity
//!
//! O(N d) to build, memory O(N d / BLOCK), O(BLOCK · d) per query.

use super::shape::MAX_DIM;
use crate::interval::Interval;

/// Steps between stored prefix sums.
const BLOCK: usize = 64;

/// Prefix sums of the displacement bounds (module doc).
#[derive(Debug, Clone)]
pub struct ChainSums<'a> {
    dim: usize,
    disp: &'a [Interval],
    /// Per block boundary b·BLOCK and axis: enclosures of Σ_{u<b·BLOCK}
    /// lo_u and Σ hi_u.
    lo: Vec<Interval>,
    hi: Vec<Interval>,
    /// Steps whose prefix sums are kept too (sorted), and those sums.
    marks: Vec<usize>,
    mark_lo: Vec<Interval>,
    mark_hi: Vec<Interval>,
}

impl<'a> ChainSums<'a> {
    /// Prefix sums of `disp` (N·dim displacement boxes).
    pub fn new(disp: &'a [Interval], dim: usize) -> ChainSums<'a> {
        let n = disp.len() / dim.max(1);
        let blocks = n / BLOCK + 1;
        let mut lo = Vec::with_capacity(blocks * dim);
        let mut hi = Vec::with_capacity(blocks * dim);
        let mut sl = [Interval::ZERO; MAX_DIM];
        let mut sh = [Interval::ZERO; MAX_DIM];
        for u in 0..=n {
            if u % BLOCK == 0 {
                lo.extend_from_slice(&sl[..dim]);
                hi.extend_from_slice(&sh[..dim]);
            }
            if u < n {
                for a in 0..dim {
                    let d = disp[u * dim + a];
                    sl[a] = sl[a] + Interval::point(d.lo());
                    sh[a] = sh[a] + Interval::point(d.hi());
                }
            }
        }
        ChainSums {
            dim,
            disp,
            lo,
            hi,
            marks: Vec::new(),
            mark_lo: Vec::new(),
            mark_hi: Vec::new(),
        }
    }

    /// Also keeps the prefix sums at `steps` (the detection steps), so that
    /// a query between two of them costs O(d). O(|steps| · BLOCK · d).
    pub fn with_steps(mut self, steps: &[usize]) -> ChainSums<'a> {
        let mut marks = steps.to_vec();
        marks.sort_unstable();
        marks.dedup();
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for &t in &marks {
            for a in 0..self.dim {
                let (l, h) = self.walk(t, a);
                lo.push(l);
                hi.push(h);
            }
        }
        self.marks = marks;
        self.mark_lo = lo;
        self.mark_hi = hi;
        self
    }

    /// Enclosures of Σ_{u<t} lo_u and Σ_{u<t} hi_u on axis `a`.
    fn prefix(&self, t: usize, a: usize) -> (Interval, Interval) {
        if let Ok(i) = self.marks.binary_search(&t) {
            let x = i * self.dim + a;
            return (self.mark_lo[x], self.mark_hi[x]);
        }
        self.walk(t, a)
    }

    /// [`ChainSums::prefix`] from the block boundary below `t`.
    fn walk(&self, t: usize, a: usize) -> (Interval, Interval) {
        let dim = self.dim;
        let b = t / BLOCK;
        let (mut l, mut h) = (self.lo[b * dim + a], self.hi[b * dim + a]);
        for u in b * BLOCK..t {
            let d = self.disp[u * dim + a];
            l = l + Interval::point(d.lo());
            h = h + Interval::point(d.hi());
        }
        (l, h)
    }

    /// An enclosure of p(t) - p(s) on each axis (first `dim` entries);
    /// empty when a displacement is empty.
    pub fn delta(&self, s: usize, t: usize) -> [Interval; MAX_DIM] {
        let mut out = [Interval::ZERO; MAX_DIM];
        if s == t {
            return out;
        }
        let (from, to) = (s.min(t), s.max(t));
        for (a, o) in out.iter_mut().enumerate().take(self.dim) {
            let (l1, h1) = self.prefix(from, a);
            let (l2, h2) = self.prefix(to, a);
            let forward = Interval::new((l2 - l1).lo(), (h2 - h1).hi());
            *o = if s < t { forward } else { -forward };
        }
        out
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
}
