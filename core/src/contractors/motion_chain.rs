//! `MotionChain`: the Euler steps p(i+1) = p(i) + D(i), i = 0..N-1, with the
//! displacement boxes D(i) computed once from the input intervals.
//!
//! # Math
//!
//! Forward: `p(i+1) ∩= p(i) + D(i)`; backward: `p(i) ∩= p(i+1) - D(i)`.
//! Displacements: unicycle2d `D = dt·speed·(cos h, sin h) + [-e, e]`;
//! auv3d `D = dt·R(roll, pitch, yaw)·v + [-e, e]` with R the Z-Y-X Euler
//! rotation (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`), in interval arithmetic.
//!
//! # Soundness
//!
//! The true displacement lies in D(i) (interval extension of the model with
//! outward rounding), so the true p(i+1) lies in p(i) + D(i) and the true
//! p(i) in p(i+1) - D(i).
//!
//! # Complexity
//!
//! O(d) per step; a sweep stops as soon as a step moves no bound by more
//! than the tolerance (what lies beyond it would only be contracted by that
//! same small amount), so propagation from a detection costs the length of
//! the stretch it really tightens. Positions and displacements are flat
//! arrays (step-major): no allocation in sweeps.

use crate::interval::{pred, succ, Interval};

/// The displacement of one unicycle2d step.
pub fn unicycle_displacement(
    dt: f64,
    speed: Interval,
    heading: Interval,
    error: f64,
) -> [Interval; 2] {
    let v = speed.scale(dt);
    let e = Interval::new(-error, error);
    let (c, s) = heading.cos_sin();
    [v * c + e, v * s + e]
}

/// The displacement of one auv3d step: `dt · R(roll, pitch, yaw) · v + e`.
pub fn auv_displacement(
    dt: f64,
    roll: Interval,
    pitch: Interval,
    yaw: Interval,
    v: [Interval; 3],
    error: f64,
) -> [Interval; 3] {
    let (cf, sf) = (roll.cos(), roll.sin());
    let (ct, st) = (pitch.cos(), pitch.sin());
    let (cp, sp) = (yaw.cos(), yaw.sin());
    let r = [
        [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
        [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
        [-st, ct * sf, ct * cf],
    ];
    let e = Interval::new(-error, error);
    let mut out = [Interval::ZERO; 3];
    for (o, row) in out.iter_mut().zip(&r) {
        let w = row[0] * v[0] + row[1] * v[1] + row[2] * v[2];
        *o = w.scale(dt) + e;
    }
    out
}

/// How far the bounds of `new` moved inside `old` (0 when equal; +inf when
/// an infinite bound became finite).
#[inline]
pub fn shrinkage(old: Interval, new: Interval) -> f64 {
    if new.is_empty() {
        return f64::INFINITY;
    }
    let dl = new.lo() - old.lo();
    let dh = old.hi() - new.hi();
    let dl = if dl.is_nan() { 0.0 } else { dl };
    let dh = if dh.is_nan() { 0.0 } else { dh };
    dl.max(dh)
}

/// Outcome of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Stopped after visiting this many steps.
    Done(usize),
    /// The position of this step became empty.
    Empty(usize),
}

/// One step of a sweep in dimension `D`: `p ∩= q ⊕ d` where `⊕` is `+`
/// (forward) or `-` (backward), each bound rounded one ulp outwards by a
/// few integer operations (`pred`/`succ`; a NaN they give for an infinite
/// sum loses to the old bound, as the infinity would). Returns `None` when
/// `p` becomes empty, else whether it changed and by how much its bounds
/// moved (0 unless `MEASURE`).
#[inline(always)]
fn step<const D: usize, const FORWARD: bool, const MEASURE: bool>(
    p: &mut [Interval],
    q: &[Interval; D],
    d: &[Interval],
) -> Option<(bool, f64)> {
    let mut changed = false;
    let mut bad = false;
    let mut moved = 0.0f64;
    let mut new = [Interval::EMPTY; D];
    for a in 0..D {
        let (old, q, d) = (p[a], q[a], d[a]);
        // An empty displacement empties the step (checked off the chain of
        // dependent bounds).
        bad |= d.is_empty();
        // With q and d not empty no sum is NaN (no inf - inf).
        let (lo, hi) = if FORWARD {
            (pred(q.lo() + d.lo()), succ(q.hi() + d.hi()))
        } else {
            (pred(q.lo() - d.hi()), succ(q.hi() - d.lo()))
        };
        // These comparisons keep the old bound when the new one is NaN.
        let lo = if lo > old.lo() { lo } else { old.lo() };
        let hi = if hi < old.hi() { hi } else { old.hi() };
        bad |= lo > hi;
        changed |= lo != old.lo() || hi != old.hi();
        if MEASURE {
            let dl = lo - old.lo();
            let dh = old.hi() - hi;
            let dl = if dl.is_nan() { 0.0 } else { dl };
            let dh = if dh.is_nan() { 0.0 } else { dh };
            moved = moved.max(dl).max(dh);
        }
        // lo <= hi when not `bad`; lo < +inf and hi > -inf as the old bounds
        // are and pred/succ never give those.
        new[a] = Interval::new_unchecked(lo, hi);
    }
    if bad {
        return None;
    }
    if changed {
        p.copy_from_slice(&new);
    }
    Some((changed, moved))
}

/// Forward sweep in dimension `D` over steps `from..steps`.
fn forward<const D: usize, const MEASURE: bool>(
    pos: &mut [Interval],
    disp: &[Interval],
    from: usize,
    steps: usize,
    tol: f64,
) -> Sweep {
    let mut cur = [Interval::EMPTY; D];
    cur.copy_from_slice(&pos[from * D..(from + 1) * D]);
    let next = pos[(from + 1) * D..(steps + 1) * D].chunks_exact_mut(D);
    let ds = disp[from * D..steps * D].chunks_exact(D);
    for (visited, (p, d)) in next.zip(ds).enumerate() {
        let Some((changed, moved)) = step::<D, true, MEASURE>(p, &cur, d) else {
            return Sweep::Empty(from + visited + 1);
        };
        cur.copy_from_slice(p);
        if !changed || MEASURE && moved <= tol {
            return Sweep::Done(visited + 1);
        }
    }
    Sweep::Done(steps - from)
}

/// Backward sweep in dimension `D` over steps `from-1` down to 0.
fn backward<const D: usize, const MEASURE: bool>(
    pos: &mut [Interval],
    disp: &[Interval],
    from: usize,
    tol: f64,
) -> Sweep {
    let mut next = [Interval::EMPTY; D];
    next.copy_from_slice(&pos[from * D..(from + 1) * D]);
    let ps = pos[..from * D].chunks_exact_mut(D).rev();
    let ds = disp[..from * D].chunks_exact(D).rev();
    for (visited, (p, d)) in ps.zip(ds).enumerate() {
        let Some((changed, moved)) = step::<D, false, MEASURE>(p, &next, d) else {
            return Sweep::Empty(from - visited - 1);
        };
        next.copy_from_slice(p);
        if !changed || MEASURE && moved <= tol {
            return Sweep::Done(visited + 1);
        }
    }
    Sweep::Done(from)
}

/// Forward sweep from step `from`: `p(i+1) ∩= p(i) + D(i)` for i = from..,
/// stopping at the first step whose bounds move by at most `tol` (with
/// `tol = 0`: do not move at all). `pos` has (N+1)·dim entries, `disp` N·dim;
/// `dim` is 1, 2 or 3.
pub fn sweep_forward(
    pos: &mut [Interval],
    disp: &[Interval],
    dim: usize,
    from: usize,
    tol: f64,
) -> Sweep {
    let steps = (disp.len() / dim).min((pos.len() / dim).saturating_sub(1));
    if from >= steps {
        return Sweep::Done(0);
    }
    match (dim, tol > 0.0) {
        (1, false) => forward::<1, false>(pos, disp, from, steps, tol),
        (2, false) => forward::<2, false>(pos, disp, from, steps, tol),
        (3, false) => forward::<3, false>(pos, disp, from, steps, tol),
        (1, true) => forward::<1, true>(pos, disp, from, steps, tol),
        (2, true) => forward::<2, true>(pos, disp, from, steps, tol),
        (3, true) => forward::<3, true>(pos, disp, from, steps, tol),
        _ => panic!("sweep_forward: dimension {dim} is not 1, 2 or 3"),
    }
}

/// Backward sweep from step `from` down: `p(i) ∩= p(i+1) - D(i)` for
/// i = from-1 down to 0, with the same stopping rule.
pub fn sweep_backward(
    pos: &mut [Interval],
    disp: &[Interval],
    dim: usize,
    from: usize,
    tol: f64,
) -> Sweep {
    let from = from
        .min(disp.len() / dim)
        .min((pos.len() / dim).saturating_sub(1));
    if from == 0 {
        return Sweep::Done(0);
    }
    match (dim, tol > 0.0) {
        (1, false) => backward::<1, false>(pos, disp, from, tol),
        (2, false) => backward::<2, false>(pos, disp, from, tol),
        (3, false) => backward::<3, false>(pos, disp, from, tol),
        (1, true) => backward::<1, true>(pos, disp, from, tol),
        (2, true) => backward::<2, true>(pos, disp, from, tol),
        (3, true) => backward::<3, true>(pos, disp, from, tol),
        _ => panic!("sweep_backward: dimension {dim} is not 1, 2 or 3"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_then_backward_on_a_straight_line() {
        // p0 = 0, three steps of [1, 1.1]; p3 known to be [3, 3.05].
        let dim = 1;
        let disp = vec![Interval::new(1.0, 1.1); 3];
        let mut pos = vec![
            Interval::ZERO,
            Interval::ENTIRE,
            Interval::ENTIRE,
            Interval::new(3.0, 3.05),
        ];
        assert_eq!(sweep_forward(&mut pos, &disp, dim, 0, 0.0), Sweep::Done(3));
        assert!(pos[2].contains(2.0) && pos[2].contains(2.2));
        sweep_backward(&mut pos, &disp, dim, 3, 0.0);
        // p2 in p3 - [1, 1.1] = [1.9, 2.05], and in [2, 2.2]: [2, 2.05].
        assert!(pos[2].lo() >= 1.999 && pos[2].hi() <= 2.051, "{:?}", pos[2]);
    }

    #[test]
    fn contradiction_is_reported() {
        let disp = vec![Interval::new(1.0, 1.1)];
        let mut pos = vec![Interval::ZERO, Interval::new(5.0, 6.0)];
        assert_eq!(sweep_forward(&mut pos, &disp, 1, 0, 0.0), Sweep::Empty(1));
    }

    /// The sweeps give the same bits as the plain formulation with
    /// `Interval` operations (outward sums, intersection), and stop at the
    /// same steps, on random chains with unknown, degenerate, zero and
    /// unbounded positions, in 1 to 3 dimensions, with and without a
    /// tolerance.
    #[test]
    fn same_bits_as_plain_interval_operations() {
        fn plain(
            pos: &mut [Interval],
            disp: &[Interval],
            dim: usize,
            from: usize,
            tol: f64,
            forward: bool,
        ) -> Sweep {
            let steps = disp.len() / dim;
            let order: Vec<usize> = if forward {
                (from..steps).collect()
            } else {
                (0..from).rev().collect()
            };
            for (visited, i) in order.into_iter().enumerate() {
                let (src, dst) = if forward { (i, i + 1) } else { (i + 1, i) };
                let mut changed = false;
                let mut moved = 0.0f64;
                let mut new = Vec::new();
                for a in 0..dim {
                    let (q, d, old) = (pos[src * dim + a], disp[i * dim + a], pos[dst * dim + a]);
                    let c = if forward {
                        q.add_outward(d)
                    } else {
                        q.sub_outward(d)
                    };
                    let n = old.intersect(c);
                    if n.is_empty() {
                        return Sweep::Empty(dst);
                    }
                    changed |= n != old;
                    moved = moved.max(shrinkage(old, n));
                    new.push(n);
                }
                pos[dst * dim..(dst + 1) * dim].copy_from_slice(&new);
                if !changed || tol > 0.0 && moved <= tol {
                    return Sweep::Done(visited + 1);
                }
            }
            Sweep::Done(if forward { steps - from } else { from })
        }
        let mut rng = crate::test_rng::Lcg::new(0xBEEF);
        let mut next = || rng.bits();
        for case in 0..3000 {
            let dim = 1 + case % 3;
            let steps = 1 + (next() % 30) as usize;
            let value = |next: &mut dyn FnMut() -> u64| match next() % 8 {
                0 => 0.0,
                1 => -0.0,
                2 => (next() % 9) as f64 * 0.25 - 1.0,
                3 => f64::from_bits(next() % 5),
                _ => (next() % 1000) as f64 * 1e-3 - 0.5,
            };
            let disp: Vec<Interval> = (0..steps * dim)
                .map(|_| {
                    let (a, b) = (value(&mut next), value(&mut next));
                    Interval::new(a.min(b), a.max(b))
                })
                .collect();
            let pos: Vec<Interval> = (0..(steps + 1) * dim)
                .map(|_| match next() % 6 {
                    0 | 1 => Interval::ENTIRE,
                    2 => Interval::new(f64::NEG_INFINITY, value(&mut next)),
                    3 => Interval::new(value(&mut next) - 3.0, f64::INFINITY),
                    _ => {
                        let c = value(&mut next) * (next() % 40) as f64;
                        Interval::new(c - 5.0, c + 5.0)
                    }
                })
                .collect();
            let tol = [0.0, 1e-3, 0.1][case % 3];
            let from = (next() as usize) % (steps + 1);
            for forward in [true, false] {
                let (mut a, mut b) = (pos.clone(), pos.clone());
                let got = if forward {
                    sweep_forward(&mut a, &disp, dim, from, tol)
                } else {
                    sweep_backward(&mut a, &disp, dim, from, tol)
                };
                let want = plain(&mut b, &disp, dim, from, tol, forward);
                assert_eq!(got, want, "case {case} forward {forward}");
                if let Sweep::Done(_) = want {
                    assert_eq!(a, b, "case {case} forward {forward}");
                }
            }
        }
    }
}
