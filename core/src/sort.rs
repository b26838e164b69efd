//! One comparison sort for the whole crate, for the size of the page's
//! wasm: every `sort_by`/`sort_unstable_by` with its own closure is its own
//! copy of the standard library's sort (about 2.5 KB of wasm each, 28 of
//! them measured before this module). Here the sort itself is compiled once,
//! over positions with a `dyn` comparison; the generic wrappers only build
//! the positions and apply the permutation.
//!
//! The result is the one of a stable sort (ties in slice order), whatever
//! the algorithm underneath: the comparison is completed by the positions,
//! a total order on distinct items. So a call site that used a stable sort,
//! or an unstable one with a comparison that is total on distinguishable
//! items (every call site moved here breaks its ties), gets the same order
//! as before, bit for bit.
//!
//! Natively the one sort underneath is std's unstable sort (fast); in
//! wasm it is [`merge_sort`], a small stable merge sort (std's sort is
//! about 3 KB of wasm for each instance, and the wrappers' instances
//! share it). Since every comparison it sees is total, both give the
//! same order. The sorts kept on std's natively for speed (the radix
//! sort's fast path, the natural sorts of integers and f64, the stable
//! sorts of a few hot call sites) go through [`natural`], [`floats`],
//! [`stable_by`], [`stable_by_key`] and [`total_by_key`]: std's sort
//! natively, the shared sort in wasm, the same result either way (the
//! registration's pieces too, since their key ends with the piece's
//! unique id).
//!
//! Complexity: O(k log k) comparisons, each an indirect call, plus O(k)
//! extra space for the positions (the items are then permuted by swaps).

use std::cmp::Ordering;

/// Sorts positions `idx` by `cmp` (on the positions), ties by position.
/// Not generic, and never inlined: the one instantiation of the sort.
#[inline(never)]
pub fn sort_positions(idx: &mut [usize], cmp: &mut dyn FnMut(usize, usize) -> Ordering) {
    #[cfg(not(target_arch = "wasm32"))]
    idx.sort_unstable_by(|&a, &b| cmp(a, b).then(a.cmp(&b)));
    #[cfg(target_arch = "wasm32")]
    merge_sort(idx, &mut |a, b| cmp(a, b).then(a.cmp(&b)));
}

/// Up to this many items, [`merge_sort`] sorts by insertion.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
const SMALL: usize = 16;

/// A stable merge sort of `v` by `cmp`, bottom up (runs of 1, 2, 4, ...
/// merged into a buffer, the buffers swapped each pass; by insertion up to
/// [`SMALL`] items): small code for
/// the page's wasm, where it is the one sort under [`sort_positions`]
/// (natively, tested against std's). O(k log k) comparisons, O(k) extra
/// space.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
#[inline(never)]
fn merge_sort(v: &mut [usize], cmp: &mut dyn FnMut(usize, usize) -> Ordering) {
    let n = v.len();
    if n <= SMALL {
        // Short slices (most calls): insertion sort in place, no buffer.
        for i in 1..n {
            let mut j = i;
            while j > 0 && cmp(v[j], v[j - 1]) == Ordering::Less {
                v.swap(j, j - 1);
                j -= 1;
            }
        }
        return;
    }
    let mut from = v.to_vec();
    let mut to = vec![0; n];
    let mut width = 1;
    while width < n {
        let mut lo = 0;
        while lo < n {
            let mid = n.min(lo + width);
            let hi = n.min(mid + width);
            let (mut i, mut j) = (lo, mid);
            for slot in &mut to[lo..hi] {
                // The right run's item first only when strictly less: ties
                // keep their order (stable).
                if j < hi && (i == mid || cmp(from[j], from[i]) == Ordering::Less) {
                    *slot = from[j];
                    j += 1;
                } else {
                    *slot = from[i];
                    i += 1;
                }
            }
            lo = hi;
        }
        std::mem::swap(&mut from, &mut to);
        width *= 2;
    }
    v.copy_from_slice(&from);
}

/// Sorts indices (into data the comparison reads) by `cmp`, ties by
/// index value: what `idx.sort_unstable_by(|&a, &b| cmp(a, b).then(a.cmp(&b)))`
/// does, in place, without a copy.
pub fn sort_indices_by(idx: &mut [usize], mut cmp: impl FnMut(usize, usize) -> Ordering) {
    sort_positions(idx, &mut cmp);
}

/// A stable sort of `v` by `cmp` (what `slice::sort_by` does).
pub fn sort_by<T>(v: &mut [T], mut cmp: impl FnMut(&T, &T) -> Ordering) {
    let mut at: Vec<usize> = (0..v.len()).collect();
    let items: &[T] = v;
    sort_positions(&mut at, &mut |a, b| cmp(&items[a], &items[b]));
    permute(v, &at);
}

/// A stable sort of `v` by `key` (what `slice::sort_by_key` does).
pub fn sort_by_key<T, K: Ord>(v: &mut [T], mut key: impl FnMut(&T) -> K) {
    sort_by(v, |a, b| key(a).cmp(&key(b)));
}

/// `v.sort_unstable()`, the same result (equal items are alike), through
/// the shared sort: for the tuple and vector types sorted once or twice
/// per call, each of which would be its own copy of the sort.
pub fn sort_ord<T: Ord>(v: &mut [T]) {
    sort_by(v, T::cmp);
}

/// Puts `v[at[i]]` at `i` (`at` a permutation of the positions), by swaps:
/// no copy of the items.
fn permute<T>(v: &mut [T], at: &[usize]) {
    permute_by(at, &mut |i, j| v.swap(i, j));
}

/// The swaps that put the item at `at[i]` at `i`, made by `swap`: not
/// generic, one copy for every item type.
#[inline(never)]
fn permute_by(at: &[usize], swap: &mut dyn FnMut(usize, usize)) {
    // dest[j]: where the item now at j goes.
    let mut dest = vec![0; at.len()];
    for (i, &j) in at.iter().enumerate() {
        dest[j] = i;
    }
    for i in 0..at.len() {
        while dest[i] != i {
            let j = dest[i];
            swap(i, j);
            dest.swap(i, j);
        }
    }
}

/// Sorts u64 items by `cmp` (the radix sort's runs, the hitting set's
/// masks), through [`sort_positions`]. The comparison must be total on
/// distinct items (ties only between equal items) for the order to be the
/// one of `sort_unstable_by`.
#[inline(never)]
pub fn sort_u64_by(v: &mut [u64], cmp: &mut dyn FnMut(u64, u64) -> Ordering) {
    sort_by(v, |&a, &b| cmp(a, b));
}

/// `v.sort_unstable()` for indices, in place: [`sort_positions`] with every
/// comparison a tie, broken by value.
pub fn sort_usize(v: &mut [usize]) {
    sort_positions(v, &mut |_, _| Ordering::Equal);
}

/// `v.sort_unstable()` for items whose equal ones are alike (integers,
/// tuples and vectors of them): std's natively (speed), [`sort_ord`] in
/// wasm (size); the same result.
pub fn natural<T: Ord>(v: &mut [T]) {
    #[cfg(not(target_arch = "wasm32"))]
    v.sort_unstable();
    #[cfg(target_arch = "wasm32")]
    sort_ord(v);
}

/// `v.sort_unstable_by(f64::total_cmp)`: floats in total order (equal
/// only when the same bits); std's natively, the shared sort in wasm.
pub fn floats(v: &mut [f64]) {
    #[cfg(not(target_arch = "wasm32"))]
    v.sort_unstable_by(f64::total_cmp);
    #[cfg(target_arch = "wasm32")]
    sort_by(v, f64::total_cmp);
}

/// `v.sort_by(cmp)` (stable): std's natively, [`sort_by`] in wasm.
pub fn stable_by<T>(v: &mut [T], cmp: impl FnMut(&T, &T) -> Ordering) {
    #[cfg(not(target_arch = "wasm32"))]
    v.sort_by(cmp);
    #[cfg(target_arch = "wasm32")]
    sort_by(v, cmp);
}

/// `v.sort_by_key(key)` (stable): std's natively, [`sort_by`] in wasm.
pub fn stable_by_key<T, K: Ord>(v: &mut [T], key: impl FnMut(&T) -> K) {
    #[cfg(not(target_arch = "wasm32"))]
    v.sort_by_key(key);
    #[cfg(target_arch = "wasm32")]
    sort_by_key(v, key);
}

/// `v.sort_unstable_by_key(key)` for a key that differs between any two
/// distinguishable items (it ends with an index, say), so that the order
/// is the one of any sort: std's unstable sort natively, the shared sort
/// in wasm.
pub fn total_by_key<T, K: Ord>(v: &mut [T], key: impl FnMut(&T) -> K) {
    #[cfg(not(target_arch = "wasm32"))]
    v.sort_unstable_by_key(key);
    #[cfg(target_arch = "wasm32")]
    sort_by_key(v, key);
}

/// The items of both sorted lists `a` and `b` (increasing, no repeats),
/// in order, into `out` (cleared first): a merge, O(|a| + |b|).
pub fn meet_sorted<T: Ord + Copy>(a: &[T], b: &[T], out: &mut Vec<T>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            Ordering::Less => i += 1,
            Ordering::Greater => j += 1,
            Ordering::Equal => {
                out.push(a[i]);
                i += 1;
                j += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    #[test]
    fn same_order_as_the_standard_stable_sort() {
        let mut rng = Lcg::new(7);
        for case in 0..2000 {
            let k = (case % 40) as usize;
            // Few distinct keys: many ties, which must keep slice order.
            let v: Vec<(u32, usize)> = (0..k).map(|i| ((rng.bits() % 5) as u32, i)).collect();
            let mut want = v.clone();
            want.sort_by_key(|x| x.0);
            let mut got = v.clone();
            sort_by_key(&mut got, |x| x.0);
            assert_eq!(got, want, "case {case}");
            let mut idx: Vec<usize> = (0..k).rev().collect();
            let mut want_idx = idx.clone();
            want_idx.sort_by_key(|&i| (v[i].0, i));
            sort_indices_by(&mut idx, |a, b| v[a].0.cmp(&v[b].0));
            assert_eq!(idx, want_idx, "case {case}");
        }
    }

    #[test]
    fn sort_ord_and_u64_as_the_standard_sorts() {
        let mut rng = Lcg::new(11);
        for case in 0..2000 {
            let k = (case % 50) as usize;
            let v: Vec<(u64, Vec<usize>)> = (0..k)
                .map(|_| {
                    (
                        rng.bits() % 4,
                        vec![(rng.bits() % 3) as usize; (rng.bits() % 3) as usize],
                    )
                })
                .collect();
            let mut want = v.clone();
            want.sort_unstable();
            let mut got = v;
            sort_ord(&mut got);
            assert_eq!(got, want, "case {case}");
            let m: Vec<u64> = (0..k).map(|_| rng.bits() % 64).collect();
            let key = |x: u64| (std::cmp::Reverse(x.count_ones()), x);
            let mut want = m.clone();
            want.sort_unstable_by_key(|&x| key(x));
            let mut got = m;
            sort_u64_by(&mut got, &mut |a, b| key(a).cmp(&key(b)));
            assert_eq!(got, want, "case {case}");
            let u: Vec<usize> = (0..k).map(|_| (rng.bits() % 20) as usize).collect();
            let mut want = u.clone();
            want.sort_unstable();
            let mut got = u;
            sort_usize(&mut got);
            assert_eq!(got, want, "case {case}");
        }
    }

    /// The wasm sort (`merge_sort`), run natively: the order of std's
    /// stable sort, on every length up to 70 (odd runs at each pass) and
    /// many ties; with a total comparison, the order of std's unstable one.
    #[test]
    fn the_merge_sort_is_a_stable_sort() {
        let mut rng = Lcg::new(13);
        for case in 0..3000 {
            let k = case % 71;
            let keys: Vec<u64> = (0..k).map(|_| rng.bits() % 7).collect();
            let mut got: Vec<usize> = (0..k).collect();
            merge_sort(&mut got, &mut |a, b| keys[a].cmp(&keys[b]));
            let mut want: Vec<usize> = (0..k).collect();
            want.sort_by_key(|&i| keys[i]);
            assert_eq!(got, want, "case {case}");
            let mut got: Vec<usize> = (0..k).rev().collect();
            merge_sort(&mut got, &mut |a, b| keys[a].cmp(&keys[b]).then(a.cmp(&b)));
            let mut want: Vec<usize> = (0..k).collect();
            want.sort_unstable_by(|&a, &b| keys[a].cmp(&keys[b]).then(a.cmp(&b)));
            assert_eq!(got, want, "case {case}");
        }
    }

    /// The wrappers kept on std's natively give std's order (natively they
    /// are std's; this pins their contract for the wasm side too, through
    /// the shared sort's wrappers they call there).
    #[test]
    fn the_native_wrappers_match_the_shared_sort() {
        let mut rng = Lcg::new(17);
        for case in 0..1000 {
            let k = case % 40;
            let v: Vec<(u32, usize)> = (0..k).map(|i| ((rng.bits() % 4) as u32, i)).collect();
            let (mut a, mut b) = (v.clone(), v.clone());
            stable_by_key(&mut a, |x| x.0);
            sort_by_key(&mut b, |x| x.0);
            assert_eq!(a, b, "case {case}");
            let (mut a, mut b) = (v.clone(), v.clone());
            stable_by(&mut a, |x, y| y.0.cmp(&x.0));
            sort_by(&mut b, |x, y| y.0.cmp(&x.0));
            assert_eq!(a, b, "case {case}");
            let (mut a, mut b) = (v.clone(), v.clone());
            a.reverse();
            b.reverse();
            total_by_key(&mut a, |x| (x.0, x.1));
            sort_by_key(&mut b, |x| (x.0, x.1));
            assert_eq!(a, b, "case {case}");
            let w: Vec<u64> = (0..k).map(|_| rng.bits() % 9).collect();
            let (mut a, mut b) = (w.clone(), w);
            natural(&mut a);
            sort_ord(&mut b);
            assert_eq!(a, b, "case {case}");
            let f: Vec<f64> = (0..k).map(|_| (rng.bits() % 5) as f64 - 2.0).collect();
            let (mut a, mut b) = (f.clone(), f);
            floats(&mut a);
            sort_by(&mut b, f64::total_cmp);
            assert_eq!(
                a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                b.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                "case {case}"
            );
        }
    }

    #[test]
    fn floats_in_total_order_with_nan_and_signed_zeros() {
        let v = [
            3.0,
            f64::NAN,
            -0.0,
            0.0,
            f64::NEG_INFINITY,
            1e308,
            -f64::NAN,
            0.0,
        ];
        let mut want = v;
        want.sort_by(f64::total_cmp);
        let mut got = v;
        sort_by(&mut got, f64::total_cmp);
        assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits));
    }
}
