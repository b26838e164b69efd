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

/// Forward sweep from step `from`: `p(i+1) ∩= p(i) + D(i)` for i = from..,
/// stopping at the first step whose bounds move by at most `tol` (with
/// `tol = 0`: do not move at all). `pos` has (N+1)·dim entries, `disp` N·dim.
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
    // The box of the current step is carried in registers.
    let mut cur = [Interval::EMPTY; 3];
    let big = dim > 3;
    if !big {
        cur[..dim].copy_from_slice(&pos[from * dim..(from + 1) * dim]);
    }
    let mut visited = 0;
    for i in from..steps {
        let base = (i + 1) * dim;
        let mut moved = 0.0f64;
        let mut changed = false;
        for a in 0..dim {
            let c = if big { pos[i * dim + a] } else { cur[a] };
            let old = pos[base + a];
            let new = old.intersect(c + disp[i * dim + a]);
            if new != old {
                if new.is_empty() {
                    return Sweep::Empty(i + 1);
                }
                changed = true;
                if tol > 0.0 {
                    moved = moved.max(shrinkage(old, new));
                }
                pos[base + a] = new;
            }
            if !big {
                cur[a] = new;
            }
        }
        visited += 1;
        if !changed || moved <= tol && tol > 0.0 {
            break;
        }
    }
    Sweep::Done(visited)
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
    let mut next = [Interval::EMPTY; 3];
    let big = dim > 3;
    if !big {
        next[..dim].copy_from_slice(&pos[from * dim..(from + 1) * dim]);
    }
    let mut visited = 0;
    for i in (0..from).rev() {
        let base = i * dim;
        let mut moved = 0.0f64;
        let mut changed = false;
        for a in 0..dim {
            let nx = if big { pos[base + dim + a] } else { next[a] };
            let old = pos[base + a];
            let new = old.intersect(nx - disp[base + a]);
            if new != old {
                if new.is_empty() {
                    return Sweep::Empty(i);
                }
                changed = true;
                if tol > 0.0 {
                    moved = moved.max(shrinkage(old, new));
                }
                pos[base + a] = new;
            }
            if !big {
                next[a] = new;
            }
        }
        visited += 1;
        if !changed || moved <= tol && tol > 0.0 {
            break;
        }
    }
    Sweep::Done(visited)
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
