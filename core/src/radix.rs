//! Ordering indices by f64 keys in (typically) linear time, for the nvalue
//! greedies, where the sorts dominate the time. Keys are mapped to u64 so
//! that unsigned order is `f64::total_cmp` order ([`f64_key`]); see
//! [`sort_indices`] for the method. Deterministic: ties are broken by index.
//! O(k) time when keys are spread out, O(k log k) at worst; O(k) extra space
//! in reused buffers.

/// The u64 whose unsigned order is the `total_cmp` order of `x`, except
/// that -0 and +0 get one key (that of +0): for non-NaN `x` and `y`,
/// `f64_key(x) < f64_key(y)` iff `x < y` as real numbers.
///
/// Signed zeros are one value in core, and this is where it is enforced.
/// Everywhere else bounds are compared with IEEE operators, for which
/// -0 = +0; the keys and the images built on them ([`KeyImage`]) are the
/// one place where a bound's bit pattern decided an outcome: callers read
/// `image(x) < image(y)` as `x < y`, and the total order's -0 < +0 made the
/// nvalue greedies place a second point for [0, 0] after [-0, -0] and skip
/// a kernel ending at -0 when looking up a lower bound +0.
/// Canonicalizing here (one addition: `-0 + 0 = +0` and `x + 0 = x`
/// otherwise) fixes every user of the keys at once and costs nothing in the
/// interval arithmetic; canonicalizing at the boundary of `Interval` instead
/// would put a test on every bound of every operation (negation alone turns
/// [0, 1] into [-1, -0]) for the benefit of these few comparisons. Sorts by
/// `total_cmp` elsewhere (ties among ±0 in either order) stay correct since
/// what follows them compares real values.
#[inline]
pub fn f64_key(x: f64) -> u64 {
    let b = (x + 0.0).to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | (1 << 63)
    }
}

/// Reusable buffers of [`sort_indices`].
#[derive(Debug, Default, Clone)]
pub struct RadixScratch {
    items: Vec<u64>,
    tmp: Vec<u64>,
    counts: Vec<u32>,
}

/// A monotone map of f64 keys to 32 bits: fixed point over the keys' finite
/// range when that range is finite and not empty, else the high 32 bits of
/// [`f64_key`]. Monotone (non-decreasing) in the real order because
/// subtraction, multiplication by a positive constant (rounded to nearest)
/// and the saturating conversion to an integer all are (and give -0 and +0
/// one image: `-0 - lo = +0 - lo`), as is `f64_key`, which identifies the
/// zeros. Hence, for any keys `x`, `y` in its domain: `image(x) < image(y)`
/// implies `x < y` as real numbers; only equal images leave the order open.
#[derive(Debug, Clone, Copy)]
pub struct KeyImage {
    lo: f64,
    scale: f64,
    fixed: bool,
}

impl KeyImage {
    /// The map for keys whose finite ones lie in `[lo, hi]` (`lo > hi`:
    /// no finite key).
    pub fn over(lo: f64, hi: f64) -> KeyImage {
        let range = hi - lo;
        let fixed = range.is_finite() && range > 0.0;
        let scale = if fixed { 4_294_967_295.0 / range } else { 0.0 };
        KeyImage { lo, scale, fixed }
    }

    /// The image of `x` (not NaN).
    #[inline]
    pub fn image(&self, x: f64) -> u32 {
        if self.fixed {
            (((x - self.lo) * self.scale) as u64).min(u32::MAX as u64) as u32
        } else {
            (f64_key(x) >> 32) as u32
        }
    }
}

/// How many high bits of the 32-bit image [`sort_items`] orders by for `k`
/// items: all 32 (three passes of 11 bits) up to 2^17 items; beyond, the
/// high 24 (two passes of 12 bits: the counters stay in the L1 cache, and
/// [`fix_runs`] orders the few items whose high 24 bits tie by their full
/// image first).
pub fn sort_bits(k: usize) -> u32 {
    if k >= 1 << 17 {
        24
    } else {
        32
    }
}

/// Sorts items `image << 32 | index` by the high `bits` bits of the image
/// ([`sort_bits`]), ties in index order (for `bits = 32`: by the whole
/// u64). Stable LSD passes (a comparison sort below 1024 items); passes
/// where every item has the same digit are skipped.
pub fn sort_items(items: &mut Vec<u64>, bits: u32, scratch: &mut RadixScratch) {
    let k = items.len();
    if k < 1024 {
        crate::sort::total_by_key(items, |&it| (it >> (64 - bits), it & 0xFFFF_FFFF));
        return;
    }
    let RadixScratch { tmp, counts, .. } = scratch;
    let passes = bits.div_ceil(12);
    let digit = bits.div_ceil(passes);
    let buckets = 1usize << digit;
    let mask = buckets - 1;
    let shifts: Vec<u32> = (0..passes).map(|p| 64 - bits + p * digit).collect();
    counts.clear();
    counts.resize(buckets * shifts.len(), 0);
    for &item in items.iter() {
        for (p, &shift) in shifts.iter().enumerate() {
            counts[p * buckets + (((item >> shift) as usize) & mask)] += 1;
        }
    }
    tmp.clear();
    tmp.resize(k, 0);
    for (p, &shift) in shifts.iter().enumerate() {
        let c = &mut counts[p * buckets..(p + 1) * buckets];
        if c.iter().any(|&n| n as usize == k) {
            continue; // every item has the same digit here
        }
        let mut sum = 0u32;
        for n in c.iter_mut() {
            let here = *n;
            *n = sum;
            sum += here;
        }
        for &item in items.iter() {
            let d = ((item >> shift) as usize) & mask;
            tmp[c[d] as usize] = item;
            c[d] += 1;
        }
        std::mem::swap(items, tmp);
    }
}

/// Within each run of items whose high `bits` image bits are equal
/// (adjacent after [`sort_items`] with the same `bits`), orders the items
/// by full image, then by `cmp` of their indices.
pub fn fix_runs(items: &mut [u64], bits: u32, cmp: impl Fn(usize, usize) -> std::cmp::Ordering) {
    let k = items.len();
    let shift = 64 - bits;
    let by = |a: &u64, b: &u64| {
        (a >> 32)
            .cmp(&(b >> 32))
            .then_with(|| cmp((a & 0xFFFF_FFFF) as usize, (b & 0xFFFF_FFFF) as usize))
    };
    let mut start = 0;
    while start < k {
        let high = items[start] >> shift;
        let mut end = start + 1;
        while end < k && items[end] >> shift == high {
            end += 1;
        }
        if end - start > 1 {
            // Runs of equal keys (boxes of one group, contracted alike) are
            // already in index order: check before sorting.
            let run = &mut items[start..end];
            if !run.is_sorted_by(|a, b| by(a, b).is_le()) {
                // One sort instantiation for every caller (wasm size).
                crate::sort::sort_u64_by(run, &mut |a, b| by(&a, &b));
            }
        }
        start = end;
    }
}

/// The indices `0..k` ordered by increasing `key(i)` (`f64::total_cmp`
/// order, ties by index), into `out`. Keys must not be NaN.
///
/// Each item is packed in one u64: a 32-bit monotone image of its key
/// ([`KeyImage`] over the keys' finite range) above its index, sorted by
/// [`sort_items`] on its high [`sort_bits`] bits. Only items with equal
/// sorted bits can be out of order, and they are adjacent: each such run is
/// then sorted by full image and key ([`fix_runs`]). Runs longer than one
/// are rare unless keys are equal or closer than their range / 2^bits; the
/// run sort (a comparison sort) keeps the worst case at O(k log k).
pub fn sort_indices(
    k: usize,
    key: impl Fn(usize) -> f64,
    out: &mut Vec<u32>,
    scratch: &mut RadixScratch,
) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..k {
        let x = key(i);
        if x.is_finite() {
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    let image = KeyImage::over(lo, hi);
    let mut items = std::mem::take(&mut scratch.items);
    items.clear();
    items.extend((0..k).map(|i| (image.image(key(i)) as u64) << 32 | i as u64));
    let bits = sort_bits(k);
    sort_items(&mut items, bits, scratch);
    fix_runs(&mut items, bits, |a, b| {
        key(a).total_cmp(&key(b)).then(a.cmp(&b))
    });
    out.clear();
    out.extend(items.iter().map(|&it| (it & 0xFFFF_FFFF) as u32));
    scratch.items = items;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(values: &[f64]) {
        let mut out = Vec::new();
        sort_indices(
            values.len(),
            |i| values[i],
            &mut out,
            &mut RadixScratch::default(),
        );
        let mut want: Vec<(f64, u32)> = values
            .iter()
            .enumerate()
            .map(|(i, &x)| (x, i as u32))
            .collect();
        want.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let got: Vec<(f64, u32)> = out.iter().map(|&i| (values[i as usize], i)).collect();
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g.1, w.1, "{g:?} vs {w:?}");
        }
    }

    #[test]
    fn key_order_is_the_real_order() {
        let xs = [
            f64::NEG_INFINITY,
            -1e308,
            -1.0,
            -f64::MIN_POSITIVE,
            0.0,
            f64::MIN_POSITIVE,
            1.0,
            1e308,
            f64::INFINITY,
        ];
        for w in xs.windows(2) {
            assert!(f64_key(w[0]) < f64_key(w[1]), "{} < {}", w[0], w[1]);
        }
    }

    /// Regression: -0 and +0 had different keys (the total
    /// order), so an image could claim -0 < +0 (see `f64_key`).
    #[test]
    fn regression_signed_zeros_have_one_key_and_one_image() {
        assert_eq!(f64_key(-0.0), f64_key(0.0));
        assert!(f64_key(-f64::MIN_POSITIVE) < f64_key(-0.0));
        assert!(f64_key(0.0) < f64_key(f64::MIN_POSITIVE));
        for (lo, hi) in [
            (0.0, 0.0),      // equal bounds: no fixed point
            (-0.0, 0.0),     // equal up to the sign
            (-1e308, 1e308), // overflowing range
            (-1.0, 1.0),     // fixed point
            (-0.0, 1e-300),
            (f64::INFINITY, f64::NEG_INFINITY), // no finite key
        ] {
            let image = KeyImage::over(lo, hi);
            assert_eq!(image.image(-0.0), image.image(0.0), "over [{lo}, {hi}]");
        }
    }

    /// `image(x) < image(y)` implies `x < y` on keys with signed zeros,
    /// at equal and overflowing ranges.
    #[test]
    fn images_are_monotone_with_signed_zeros() {
        let keys = [
            f64::NEG_INFINITY,
            -1e308,
            -1.0,
            -0.0,
            0.0,
            1.0,
            1e308,
            f64::INFINITY,
        ];
        for (lo, hi) in [
            (-0.0, 0.0),
            (0.0, -0.0),
            (-1e308, 1e308),
            (-1.0, 1.0),
            (-1e308, 0.0),
        ] {
            let image = KeyImage::over(lo, hi);
            for &x in &keys {
                for &y in &keys {
                    if image.image(x) < image.image(y) {
                        assert!(x < y, "image({x}) < image({y}) over [{lo}, {hi}]");
                    }
                }
            }
        }
    }

    #[test]
    fn sorts_like_a_stable_comparison_sort() {
        let mut rng = crate::test_rng::Lcg::new(0x2009);
        let mut next = || rng.bits();
        for &k in &[0usize, 1, 5, 300, 1023, 1024, 5000, 70_000, 140_000] {
            let v: Vec<f64> = (0..k)
                .map(|i| match next() % 7 {
                    0 => (next() % 10) as f64, // many ties
                    1 => -((next() % 1000) as f64) * 1e-3,
                    2 => {
                        f64::from_bits(next() << 11).abs().min(1e300)
                            * if i % 2 == 0 { 1.0 } else { -1.0 }
                    }
                    3 => f64::INFINITY,
                    4 => -0.0,
                    5 => 1.0 + (next() % 1000) as f64 * f64::EPSILON, // equal high bits
                    _ => (next() as f64) * 1e-10 - 5e5,
                })
                .collect();
            check(&v);
        }
    }
}
