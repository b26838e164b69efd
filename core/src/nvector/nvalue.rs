//! `AtMostNValue` on intervals: bound consistency of
//! atmost_nvalue(n, {x_1..x_k}) — "the k real variables take at most n
//! distinct values" — with x_i in closed intervals (Beldiceanu, "Pruning
//! for the minimum constraint family and for the number of distinct values
//! constraint family", CP 2001; Chabert, Jaulin, Lorca, CP 2009, section 3).
//!
//! # Math
//!
//! - *Left greedy.* Visit the intervals by increasing upper bound; keep the
//!   last point placed `p` (initially none); an interval with `lo > p` is
//!   not stabbed, so place a new point at its upper bound. This is the
//!   classical minimum stabbing of intervals: it places the minimum number
//!   `m` of points, `p_1 < ... < p_m`, each as late as possible.
//! - *Right greedy.* The mirror image (decreasing lower bounds, new point at
//!   the lower bound) gives `q_1 < ... < q_m`, each as early as possible.
//! - `m > n`: no assignment uses at most n values: infeasible.
//!   `m < n`: every value of every domain extends to a solution (give it its
//!   own value, stab the rest with m points): nothing to prune.
//! - `m = n`: every solution uses exactly n values `v_1 < ... < v_n` and
//!   `q_j <= v_j <= p_j`. (Proof of `v_j <= p_j`: the interval I that created
//!   `p_j` has `lo(I) > p_{j-1} >= v_{j-1}`, by induction, so it is stabbed by
//!   some `v_i` with `i >= j`, hence `v_j <= v_i <= hi(I) = p_j`; mirror
//!   argument for `q_j`.) So the *kernels* `K_j = [q_j, p_j]` hold every value
//!   a solution uses, and each domain can be replaced by
//!   `hull(x ∩ (K_1 ∪ ... ∪ K_n))`.
//! - A domain that meets exactly one kernel `K_j` must take `v_j` in every
//!   solution: the domains meeting only `K_j` form *group j*; they are all
//!   equal, so each becomes their common intersection (with `K_j`), and
//!   `K_j` shrinks to it.
//!
//! # Soundness
//!
//! Only the two facts above are used: every value taken lies in some kernel,
//! and a domain meeting one kernel takes that kernel's value. Comparisons are
//! exact on f64 bounds (no arithmetic), so no rounding is involved.
//!
//! # Complexity
//!
//! Two sorts, by a radix sort of 32-bit monotone images of the bounds
//! ([`crate::radix`]), O(k) unless many bounds are closer than their range
//! / 2^32 (then O(k log k)); the greedies compare images and read exact
//! bounds only on equal images; the pruning pass locates each domain among
//! the sorted kernels through a table over the images and a short scan
//! (a binary search when the scan is long), O(k + n) on spread-out
//! kernels, O(k log n) at worst. Buffers are reused
//! through [`NValueScratch`].

use crate::interval::Interval;
use crate::radix::{fix_runs, sort_bits, sort_indices, sort_items, KeyImage, RadixScratch};

const INDEX: u64 = 0xFFFF_FFFF;

/// Reusable buffers for [`atmost_nvalue`] (no allocation after warm-up).
#[derive(Debug, Default, Clone)]
pub struct NValueScratch {
    order: Vec<u32>,
    radix: RadixScratch,
    items: Vec<u64>,
    lo_image: Vec<u32>,
    hi_image: Vec<u32>,
    table: Vec<u32>,
    latest: Vec<f64>,
    earliest: Vec<f64>,
    /// Kernels of the last call (valid when it returned `Kernels`).
    pub kernels: Vec<Interval>,
    /// For each domain, the kernel of its group, or `u32::MAX` when it meets
    /// several kernels (valid when the last call returned `Kernels`).
    pub group_of: Vec<u32>,
}

/// What atmost_nvalue proved on one set of intervals.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NValue {
    /// More than n values are needed (`m` = the minimum).
    Infeasible {
        /// Minimum number of distinct values.
        m: usize,
    },
    /// `m < n`: nothing can be pruned.
    Slack {
        /// Minimum number of distinct values.
        m: usize,
    },
    /// `m = n`: kernels and groups were computed (see [`NValueScratch`]),
    /// and the domains were contracted; `changed` says whether any moved.
    Kernels {
        /// Whether a domain was contracted.
        changed: bool,
    },
}

/// The minimum number of distinct values of the intervals (left greedy),
/// without pruning. Empty intervals are not allowed. O(k log k).
pub fn min_values(domains: &[Interval], scratch: &mut NValueScratch) -> usize {
    let order = &mut scratch.order;
    sort_indices(
        domains.len(),
        |i| domains[i].hi(),
        order,
        &mut scratch.radix,
    );
    left_greedy(domains, order, None)
}

/// Left greedy over `order` (sorted by upper bound): number of points, and
/// the points themselves pushed to `points` when given.
fn left_greedy(domains: &[Interval], order: &[u32], mut points: Option<&mut Vec<f64>>) -> usize {
    let mut m = 0;
    let mut p = f64::NEG_INFINITY;
    let mut placed = false;
    for &i in order {
        let (lo, hi) = (domains[i as usize].lo(), domains[i as usize].hi());
        if !placed || lo > p {
            p = hi;
            placed = true;
            m += 1;
            if let Some(pts) = points.as_deref_mut() {
                pts.push(hi);
            }
            if p == f64::INFINITY {
                // Every later interval has hi = +inf and is stabbed by a
                // large enough point: one more point covers them all.
                break;
            }
        }
    }
    m
}

/// Contracts `domains` under atmost_nvalue(n): see the module documentation.
/// `domains` must be non-empty intervals. On `Kernels`, `scratch.kernels`
/// and `scratch.group_of` describe the groups.
pub fn atmost_nvalue(n: usize, domains: &mut [Interval], scratch: &mut NValueScratch) -> NValue {
    let k = domains.len();
    let NValueScratch {
        order: _,
        radix,
        items,
        lo_image,
        hi_image,
        table,
        latest,
        earliest,
        kernels,
        group_of,
    } = scratch;
    // One monotone 32-bit image for all bounds: the sorts order the images
    // and the greedies compare them, reading an exact bound only when two
    // images are equal (image(x) < image(y) implies x < y).
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in domains.iter() {
        for b in [x.lo(), x.hi()] {
            if b.is_finite() {
                lo = lo.min(b);
                hi = hi.max(b);
            }
        }
    }
    let image = KeyImage::over(lo, hi);
    let bits = sort_bits(k);
    lo_image.clear();
    hi_image.clear();
    items.clear();
    for (i, x) in domains.iter().enumerate() {
        let (a, b) = (image.image(x.lo()), image.image(x.hi()));
        lo_image.push(a);
        hi_image.push(b);
        items.push((b as u64) << 32 | i as u64);
    }
    // Left greedy, by increasing upper bound: latest points.
    sort_items(items, bits, radix);
    fix_runs(items, bits, |a, b| {
        domains[a].hi().total_cmp(&domains[b].hi()).then(a.cmp(&b))
    });
    kernels.clear();
    latest.clear();
    let (mut p, mut p_image, mut placed) = (f64::NEG_INFINITY, 0u32, false);
    for &item in items.iter() {
        let i = (item & INDEX) as usize;
        let l = lo_image[i];
        if !placed || l > p_image || l == p_image && domains[i].lo() > p {
            p = domains[i].hi();
            p_image = (item >> 32) as u32;
            placed = true;
            latest.push(p);
            if p == f64::INFINITY {
                // Every later interval has hi = +inf and is stabbed by a
                // large enough point: one more point covers them all.
                break;
            }
        }
    }
    let m = latest.len();
    if m > n {
        return NValue::Infeasible { m };
    }
    if m < n {
        return NValue::Slack { m };
    }
    earliest_points(domains, lo_image, hi_image, items, bits, radix, earliest);
    debug_assert_eq!(earliest.len(), m, "both greedies find the minimum");
    earliest.reverse();
    for j in 0..m.min(earliest.len()) {
        kernels.push(Interval::new(earliest[j], latest[j]));
    }
    let changed = contract_to_kernels(domains, &image, lo_image, kernels, table, group_of);
    NValue::Kernels { changed }
}

/// The right greedy, by decreasing lower bound: the earliest points, into
/// `earliest` (in decreasing order).
#[allow(clippy::too_many_arguments)]
fn earliest_points(
    domains: &[Interval],
    lo_image: &[u32],
    hi_image: &[u32],
    items: &mut Vec<u64>,
    bits: u32,
    radix: &mut RadixScratch,
    earliest: &mut Vec<f64>,
) {
    items.clear();
    items.extend(
        lo_image
            .iter()
            .enumerate()
            .map(|(i, &a)| ((!a) as u64) << 32 | i as u64),
    );
    sort_items(items, bits, radix);
    fix_runs(items, bits, |a, b| {
        domains[b].lo().total_cmp(&domains[a].lo()).then(a.cmp(&b))
    });
    let (mut q, mut q_image, mut placed) = (f64::INFINITY, 0u32, false);
    earliest.clear();
    for &item in items.iter() {
        let i = (item & INDEX) as usize;
        let h = hi_image[i];
        if !placed || h < q_image || h == q_image && domains[i].hi() < q {
            q = domains[i].lo();
            q_image = !((item >> 32) as u32);
            placed = true;
            earliest.push(q);
            if q == f64::NEG_INFINITY {
                break;
            }
        }
    }
}

/// Contracts each domain to the hull of its intersections with the
/// (sorted, disjoint) kernels; a domain meeting exactly one kernel is in
/// its group (`group_of`), and every group's members become their common
/// intersection with its kernel (`kernels` is left holding those
/// intersections). Returns whether a domain moved.
fn contract_to_kernels(
    domains: &mut [Interval],
    image: &KeyImage,
    lo_image: &[u32],
    kernels: &mut [Interval],
    table: &mut Vec<u32>,
    group_of: &mut Vec<u32>,
) -> bool {
    let k = domains.len();
    // Each domain: hull of its intersections with the kernels; group when it
    // meets exactly one. Kernels are sorted and disjoint, so the kernels a
    // domain meets form a contiguous run; its first kernel (the first whose
    // upper bound is >= x.lo) is found from a table over the images: the
    // kernels before table[b] have upper bounds of image below every image
    // of bucket b, hence below x.lo; a short scan finishes.
    let buckets_log = (4 * kernels.len())
        .next_power_of_two()
        .trailing_zeros()
        .min(16);
    let shift = 32 - buckets_log;
    table.clear();
    let mut j = 0;
    for b in 0..1u64 << buckets_log {
        let start = b << shift;
        while j < kernels.len() && (image.image(kernels[j].hi()) as u64) < start {
            j += 1;
        }
        table.push(j as u32);
    }
    group_of.clear();
    group_of.resize(k, u32::MAX);
    let mut changed = false;
    for (i, x) in domains.iter_mut().enumerate() {
        let mut first = table[(lo_image[i] as u64 >> shift) as usize] as usize;
        first += run_length(&kernels[first..], |kj| kj.hi() < x.lo());
        let last = first + run_length(&kernels[first..], |kj| kj.lo() <= x.hi());
        if first == last {
            // Cannot happen for a correct greedy (every domain is stabbed by
            // some p_j in K_j); treat as a proof of emptiness to stay total.
            *x = Interval::EMPTY;
            changed = true;
            continue;
        }
        let lo = x.intersect(kernels[first]).lo();
        let hi = x.intersect(kernels[last - 1]).hi();
        let y = Interval::new(lo, hi);
        if y != *x {
            *x = y;
            changed = true;
        }
        if last - first == 1 {
            group_of[i] = first as u32;
        }
    }
    // Groups: every member takes v_j, so all become their common
    // intersection with K_j.
    let common = kernels;
    for (i, x) in domains.iter().enumerate() {
        let g = group_of[i];
        if g != u32::MAX {
            common[g as usize] = common[g as usize].intersect(*x);
        }
    }
    for (i, x) in domains.iter_mut().enumerate() {
        let g = group_of[i];
        if g != u32::MAX {
            let c = common[g as usize];
            if c != *x {
                *x = c;
                changed = true;
            }
        }
    }
    changed
}

/// The length of the prefix of `kernels` where `pred` holds (`pred` true
/// then false along the slice): a short scan, then a binary search when the
/// prefix is long, so the worst case stays O(log n).
#[inline]
fn run_length(kernels: &[Interval], pred: impl Fn(&Interval) -> bool) -> usize {
    const SCAN: usize = 4;
    for (j, kj) in kernels.iter().take(SCAN).enumerate() {
        if !pred(kj) {
            return j;
        }
    }
    if kernels.len() <= SCAN {
        return kernels.len();
    }
    SCAN + kernels[SCAN..].partition_point(pred)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(lo: f64, hi: f64) -> Interval {
        Interval::new(lo, hi)
    }

    #[test]
    fn two_clusters_are_grouped() {
        // [0,2] [1,3] need one value in [1,2]; [5,6] another.
        let mut d = vec![iv(0.0, 2.0), iv(1.0, 3.0), iv(5.0, 6.0)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Kernels { changed: true }
        );
        assert_eq!(d, vec![iv(1.0, 2.0), iv(1.0, 2.0), iv(5.0, 6.0)]);
        assert_eq!(s.group_of, vec![0, 0, 1]);
    }

    #[test]
    fn infeasible_and_slack() {
        let mut d = vec![iv(0.0, 1.0), iv(2.0, 3.0), iv(4.0, 5.0)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Infeasible { m: 3 }
        );
        assert_eq!(atmost_nvalue(4, &mut d, &mut s), NValue::Slack { m: 3 });
    }

    #[test]
    fn touching_intervals_share_a_value() {
        let mut d = vec![iv(0.0, 1.0), iv(1.0, 2.0)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(1, &mut d, &mut s),
            NValue::Kernels { changed: true }
        );
        assert_eq!(d, vec![iv(1.0, 1.0), iv(1.0, 1.0)]);
    }

    #[test]
    fn straddling_domain_is_hulled_not_grouped() {
        // Kernels [0,1] and [9,10]; [0.5, 9.5] meets both: it keeps [0.5, 9.5]
        // (hull of the two pieces) and is in no group.
        let mut d = vec![iv(0.0, 1.0), iv(9.0, 10.0), iv(0.5, 9.5), iv(-5.0, 20.0)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Kernels { changed: true }
        );
        assert_eq!(d[2], iv(0.5, 9.5));
        assert_eq!(d[3], iv(0.0, 10.0));
        assert_eq!(s.group_of[2], u32::MAX);
    }

    #[test]
    fn unbounded_domains() {
        let mut d = vec![iv(f64::NEG_INFINITY, 1.0), iv(0.0, f64::INFINITY)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(1, &mut d, &mut s),
            NValue::Kernels { changed: true }
        );
        assert_eq!(d, vec![iv(0.0, 1.0), iv(0.0, 1.0)]);
    }

    /// Regression: with every finite bound equal up to its sign
    /// (-0 and +0) the range of the bound images is 0, the images fell back
    /// to the f64 total order, which puts -0 below +0, and the greedy placed
    /// a second point for [0, 0] after [-0, -0]: n = 1 answered infeasible
    /// though 0 is a solution.
    #[test]
    fn regression_signed_zeros_at_equal_bounds_are_one_value() {
        for (a, b) in [(-0.0, 0.0), (0.0, -0.0)] {
            let mut d = vec![iv(a, a), iv(b, b), iv(-0.0, 0.0)];
            let mut s = NValueScratch::default();
            assert_eq!(min_values(&d, &mut s), 1);
            let r = atmost_nvalue(1, &mut d, &mut s);
            assert!(matches!(r, NValue::Kernels { .. }), "{r:?}");
            assert!(d.iter().all(|x| x.contains(0.0)), "{d:?}");
            assert_eq!(s.group_of, vec![0, 0, 0]);
        }
    }

    /// Regression: with finite bounds spread over more than
    /// f64::MAX the images fell back to the total order; kernel 0 =
    /// [-1e308, -0] then had an image below the table bucket of the lower
    /// bound +0 of [0, 1e308], the lookup skipped kernel 0, and the box was
    /// pruned to [1e308, 1e308] and grouped with the third, though
    /// (0, 0, 1e308) is a solution.
    #[test]
    fn regression_signed_zeros_with_an_overflowing_range() {
        let mut d = vec![iv(-1e308, -0.0), iv(0.0, 1e308), iv(1e308, 1e308)];
        let mut s = NValueScratch::default();
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Kernels { changed: false }
        );
        assert_eq!(d[1], iv(0.0, 1e308));
        assert!(d[1].contains(0.0) && d[1].contains(1e308));
        assert_eq!(s.group_of, vec![0, u32::MAX, 1]);
        // The mirror image, and -0 / +0 swapped.
        let mut d = vec![iv(-1e308, -1e308), iv(-1e308, -0.0), iv(0.0, 1e308)];
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Kernels { changed: false }
        );
        assert_eq!(s.group_of, vec![0, u32::MAX, 1]);
        let mut d = vec![iv(-1e308, 0.0), iv(-0.0, 1e308), iv(1e308, 1e308)];
        assert_eq!(
            atmost_nvalue(2, &mut d, &mut s),
            NValue::Kernels { changed: false }
        );
        assert_eq!(s.group_of, vec![0, u32::MAX, 1]);
    }

    /// The textbook version: comparison sorts, the kernels each domain meets
    /// by a linear scan. The image-based one must give the same bits.
    fn reference(n: usize, domains: &mut [Interval]) -> (NValue, Vec<u32>) {
        let mut by_hi: Vec<Interval> = domains.to_vec();
        by_hi.sort_by(|x, y| x.hi().total_cmp(&y.hi()));
        let mut latest: Vec<f64> = Vec::new();
        for x in &by_hi {
            if latest.last().is_none_or(|&p| x.lo() > p) {
                latest.push(x.hi());
            }
        }
        let m = latest.len();
        if m > n {
            return (NValue::Infeasible { m }, Vec::new());
        }
        if m < n {
            return (NValue::Slack { m }, Vec::new());
        }
        let mut by_lo: Vec<Interval> = domains.to_vec();
        by_lo.sort_by(|x, y| y.lo().total_cmp(&x.lo()));
        let mut earliest: Vec<f64> = Vec::new();
        for x in &by_lo {
            if earliest.last().is_none_or(|&q| x.hi() < q) {
                earliest.push(x.lo());
            }
        }
        earliest.reverse();
        let kernels: Vec<Interval> = (0..m).map(|j| iv(earliest[j], latest[j])).collect();
        let mut group_of = vec![u32::MAX; domains.len()];
        let mut changed = false;
        for (i, x) in domains.iter_mut().enumerate() {
            let met: Vec<usize> = (0..m)
                .filter(|&j| !x.intersect(kernels[j]).is_empty())
                .collect();
            let y = iv(
                x.intersect(kernels[met[0]]).lo(),
                x.intersect(kernels[*met.last().unwrap()]).hi(),
            );
            changed |= y != *x;
            *x = y;
            if met.len() == 1 {
                group_of[i] = met[0] as u32;
            }
        }
        let mut common = kernels.clone();
        for (i, x) in domains.iter().enumerate() {
            if group_of[i] != u32::MAX {
                common[group_of[i] as usize] = common[group_of[i] as usize].intersect(*x);
            }
        }
        for (i, x) in domains.iter_mut().enumerate() {
            if group_of[i] != u32::MAX {
                changed |= common[group_of[i] as usize] != *x;
                *x = common[group_of[i] as usize];
            }
        }
        (NValue::Kernels { changed }, group_of)
    }

    /// The same bounds as real numbers: -0 and +0 are one value (the
    /// textbook version assigns every contracted domain, the tested one only
    /// those that changed, so a zero bound may keep its sign in one and not
    /// in the other; `Interval`'s `==` compares bounds as reals).
    fn assert_same_bits(got: &[Interval], want: &[Interval], what: &str) {
        assert_eq!(got, want, "{what}");
    }

    /// Signed zeros where every finite bound is ±0 (a range of 0) or where
    /// ±1e308 bounds overflow the range: as the textbook version, which
    /// compares bounds as real numbers (-0 = +0).
    #[test]
    fn same_bits_as_the_textbook_version_with_signed_zeros() {
        let mut rng = crate::test_rng::Lcg::new(0x0000);
        let zeros = [-0.0, 0.0];
        for case in 0..400 {
            let k = 1 + case % 9;
            let overflow = case % 2 == 1;
            let pick = |r: u64| match r % if overflow { 5 } else { 3 } {
                0 | 1 => zeros[(r / 8 % 2) as usize],
                2 => {
                    if (r / 8).is_multiple_of(3) {
                        f64::INFINITY
                    } else {
                        f64::NEG_INFINITY
                    }
                }
                3 => 1e308,
                _ => -1e308,
            };
            let domains: Vec<Interval> = (0..k)
                .map(|_| {
                    let (a, b) = (pick(rng.bits()), pick(rng.bits()));
                    let x = iv(a.min(b), a.max(b));
                    if x.is_empty() {
                        iv(a, a)
                    } else {
                        x
                    }
                })
                .filter(|x| !x.is_empty())
                .collect();
            if domains.is_empty() {
                continue;
            }
            let m = min_values(&domains, &mut NValueScratch::default());
            for n in [m.saturating_sub(1).max(1), m, m + 1] {
                let mut want = domains.clone();
                let (r_want, g_want) = reference(n, &mut want);
                let mut got = domains.clone();
                let mut scratch = NValueScratch::default();
                let r = atmost_nvalue(n, &mut got, &mut scratch);
                assert_eq!(r, r_want, "case {case} n {n}: {domains:?}");
                if let NValue::Kernels { .. } = r {
                    assert_same_bits(&got, &want, &format!("case {case} n {n}: {domains:?}"));
                    assert_eq!(scratch.group_of, g_want, "case {case} n {n}: {domains:?}");
                }
            }
        }
    }

    /// Same results as the textbook version, on spread-out bounds, on
    /// bounds closer than their range / 2^32 (equal images everywhere: an
    /// outlier stretches the range), with ties, infinities and signed zeros.
    #[test]
    fn same_bits_as_the_textbook_version() {
        let mut rng = crate::test_rng::Lcg::new(0x2001);
        let mut next = || rng.unit();
        for case in 0..64 {
            // The last cases are large enough for the 24-bit radix path.
            let k = if case >= 60 {
                140_000
            } else {
                [5, 50, 1500, 3000][case % 4]
            };
            let clusters = 1 + case % 9;
            let unit = match case % 3 {
                0 => 1.0,
                1 => 1e-12, // with the outlier below: equal images
                _ => 0.25,  // dyadic: ties and touching bounds
            };
            let mut domains: Vec<Interval> = (0..k)
                .map(|i| {
                    let c = (i % clusters) as f64 * 10.0 * unit;
                    let (a, b) = (next() * 4.0 * unit, next() * 4.0 * unit);
                    if unit == 0.25 {
                        iv(c - (a * 4.0).floor() * 0.25, c + (b * 4.0).floor() * 0.25)
                    } else {
                        iv(c - a, c + b)
                    }
                })
                .collect();
            match if case >= 60 { 0 } else { case % 5 } {
                0 => domains.push(iv(1e6, 1e6)),
                1 => domains.push(iv(f64::NEG_INFINITY, 0.0)),
                2 => domains.push(iv(-0.0, f64::INFINITY)),
                3 => domains.push(iv(-1e300, 1e300)),
                _ => domains.push(iv(0.0, 0.0)),
            }
            let m = min_values(&domains, &mut NValueScratch::default());
            for n in [m.saturating_sub(1).max(1), m, m + 1] {
                let mut want = domains.clone();
                let (r_want, g_want) = reference(n, &mut want);
                let mut got = domains.clone();
                let mut scratch = NValueScratch::default();
                let r = atmost_nvalue(n, &mut got, &mut scratch);
                assert_eq!(r, r_want, "case {case} n {n}");
                if let NValue::Kernels { .. } = r {
                    assert_same_bits(&got, &want, &format!("case {case} n {n}"));
                    assert_eq!(scratch.group_of, g_want, "case {case} n {n}");
                }
            }
        }
    }

    /// Large inputs take the radix path of the sorts: planted values
    /// survive, and the minimum matches a comparison-sort greedy.
    #[test]
    fn large_planted_instances_keep_their_values() {
        let mut rng = crate::test_rng::Lcg::new(0x5eed);
        let mut next = || rng.unit();
        for case in 0..20 {
            let n = 1 + case % 7;
            let k = 1500 + case * 300;
            let points: Vec<f64> = (0..n).map(|j| j as f64 * 3.0 + next()).collect();
            let planted: Vec<f64> = (0..k).map(|i| points[i % n]).collect();
            let mut domains: Vec<Interval> = planted
                .iter()
                .map(|&v| {
                    let (a, b) = (next() * 4.0, next() * 4.0);
                    if case % 3 == 0 {
                        iv(v - (a * 8.0).floor() / 8.0, v + (b * 8.0).floor() / 8.0)
                    } else {
                        iv(v - a, v + b)
                    }
                })
                .collect();
            let mut by_hi: Vec<Interval> = domains.clone();
            by_hi.sort_by(|x, y| x.hi().total_cmp(&y.hi()));
            let mut m = 0;
            let mut p = f64::NEG_INFINITY;
            for x in &by_hi {
                if m == 0 || x.lo() > p {
                    p = x.hi();
                    m += 1;
                }
            }
            let mut scratch = NValueScratch::default();
            assert_eq!(min_values(&domains, &mut scratch), m, "case {case}");
            let r = atmost_nvalue(n, &mut domains, &mut scratch);
            assert!(!matches!(r, NValue::Infeasible { .. }), "case {case}");
            for (x, &v) in domains.iter().zip(&planted) {
                assert!(x.contains(v), "case {case}: {v} lost from {x:?}");
            }
        }
    }
}
