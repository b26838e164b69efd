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

use crate::interval::Interval;

/// The displacement of one unicycle2d step.
pub fn unicycle_displacement(
    dt: f64,
    speed: Interval,
    heading: Interval,
    error: f64,
) -> [Interval; 2] {
    let v = speed.scale(dt);
    let e = Interval::new(-error, error);
    [v * heading.cos() + e, v * heading.sin() + e]
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
/// (forward) or `-` (backward), each bound rounded one ulp outwards
/// (branch-free, see [`Interval::add_outward`]). Returns `None` when `p`
/// becomes empty, else whether it changed and by how much its bounds moved
/// (computed only when `measure`).
#[inline(always)]
fn step<const D: usize, const FORWARD: bool>(
    p: &mut [Interval],
    q: &[Interval; D],
    d: &[Interval],
    measure: bool,
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
        let (lo, hi) = if FORWARD {
            ((q.lo() + d.lo()).next_down(), (q.hi() + d.hi()).next_up())
        } else {
            ((q.lo() - d.hi()).next_down(), (q.hi() - d.lo()).next_up())
        };
        // `max`/`min` ignore a NaN operand (a non-empty q and d give none),
        // so neither bound is NaN.
        let (lo, hi) = (old.lo().max(lo), old.hi().min(hi));
        bad |= lo > hi;
        changed |= lo != old.lo() || hi != old.hi();
        if measure {
            let dl = lo - old.lo();
            let dh = old.hi() - hi;
            let dl = if dl.is_nan() { 0.0 } else { dl };
            let dh = if dh.is_nan() { 0.0 } else { dh };
            moved = moved.max(dl).max(dh);
        }
        new[a] = Interval::new(lo, hi);
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
fn forward<const D: usize>(
    pos: &mut [Interval],
    disp: &[Interval],
    from: usize,
    steps: usize,
    tol: f64,
) -> Sweep {
    let mut cur = [Interval::EMPTY; D];
    cur.copy_from_slice(&pos[from * D..(from + 1) * D]);
    let measure = tol > 0.0;
    let next = pos[(from + 1) * D..(steps + 1) * D].chunks_exact_mut(D);
    let ds = disp[from * D..steps * D].chunks_exact(D);
    for (visited, (p, d)) in next.zip(ds).enumerate() {
        let Some((changed, moved)) = step::<D, true>(p, &cur, d, measure) else {
            return Sweep::Empty(from + visited + 1);
        };
        cur.copy_from_slice(p);
        if !changed || measure && moved <= tol {
            return Sweep::Done(visited + 1);
        }
    }
    Sweep::Done(steps - from)
}

/// Backward sweep in dimension `D` over steps `from-1` down to 0.
fn backward<const D: usize>(
    pos: &mut [Interval],
    disp: &[Interval],
    from: usize,
    tol: f64,
) -> Sweep {
    let mut next = [Interval::EMPTY; D];
    next.copy_from_slice(&pos[from * D..(from + 1) * D]);
    let measure = tol > 0.0;
    let ps = pos[..from * D].chunks_exact_mut(D).rev();
    let ds = disp[..from * D].chunks_exact(D).rev();
    for (visited, (p, d)) in ps.zip(ds).enumerate() {
        let Some((changed, moved)) = step::<D, false>(p, &next, d, measure) else {
            return Sweep::Empty(from - visited - 1);
        };
        next.copy_from_slice(p);
        if !changed || measure && moved <= tol {
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
    match dim {
        1 => forward::<1>(pos, disp, from, steps, tol),
        2 => forward::<2>(pos, disp, from, steps, tol),
        3 => forward::<3>(pos, disp, from, steps, tol),
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
    match dim {
        1 => backward::<1>(pos, disp, from, tol),
        2 => backward::<2>(pos, disp, from, tol),
        3 => backward::<3>(pos, disp, from, tol),
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
}
