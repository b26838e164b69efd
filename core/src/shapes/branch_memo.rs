//! Branch contraction with a memo per region: [`branch`](super::branch::branch)
//! of a detection against regions of which most did not change since its
//! last branch (natively only: the browser's build runs the plain one).
//!
//! # Constraint
//!
//! The constraint of [`super::branch`]: detection j's landmark is in one
//! of the regions R(1..m).
//!
//! # Math
//!
//! The branch's hull is the hull over the regions of each region's own
//! hull of surviving pieces, and region i survives when one of its pieces
//! does: both depend only on the shape and on R(i). So each region's part
//! ([`super::branch`]'s extreme-boxes-first pass on R(i) alone) is kept
//! with the shape it was computed for and the version of R(i) it read,
//! and reused while both are the same; the parts are then joined in the
//! regions' order. A version names one content of a region: the caller
//! gives a region a new version whenever its boxes may differ (see
//! [`BranchMemo`]).
//!
//! # Soundness
//!
//! A reused part was computed from the same shape (every bit of its
//! centre, range, bearing and cut) and the same region boxes, by the same
//! deterministic code, so it is the part a new computation would give:
//! nothing is reused that the inputs do not fully determine, and a version
//! the caller failed to renew could only come from a region it did not
//! change. The joined hull is the same set as the plain branch's (a hull
//! of the same pieces), so the same bits except where +0 and -0 meet; a
//! hull with a zero bound is made again by the plain branch's every-box
//! pass, as the plain branch does.
//!
//! # Complexity
//!
//! O(s) to compare the shape's s = O(d) bits, then the plain branch's
//! work for the regions whose version changed only (without the skips
//! across regions: each region's pass skips the boxes its own hull holds).

use super::branch::{branches, every_box, extremes_first, Branches};
use super::region::Paving;
use super::shape::{DetectionShape, Piece, Shape};
use crate::interval::Interval;

/// What one detection's last branch read and found, per region (module
/// doc): the bits of its shape, and per region the version it read, the
/// hull of its surviving pieces and whether it survived.
#[derive(Debug, Clone, Default)]
pub struct BranchMemo {
    shape: Vec<u64>,
    parts: Vec<(u64, Option<Piece>, bool)>,
}

/// Every bit of what a branch reads of `s`: centre, range, bearing, cut.
fn shape_bits(s: &Shape) -> Vec<u64> {
    let mut out = Vec::with_capacity(4 * s.dim() + 6);
    let mut push = |x: Interval| {
        out.push(x.lo().to_bits());
        out.push(x.hi().to_bits());
    };
    s.centre.axes().iter().for_each(|&x| push(x));
    push(s.range);
    if let Some((h, b)) = s.bearing {
        push(h);
        push(b);
    }
    s.cut.axes().iter().for_each(|&x| push(x));
    out.push(s.bearing.is_some() as u64);
    out
}

/// [`super::branch::branch`] of `shape` against `regions`, region i at
/// version `versions[i]`, reusing the parts `memo` holds for the same
/// shape and versions, and leaving this call's parts in it (module doc).
pub fn branch_memo(
    shape: &Shape,
    regions: &[&Paving],
    versions: &[u64],
    memo: &mut BranchMemo,
) -> Branches {
    let key = shape_bits(shape);
    let same_shape = memo.shape == key;
    let mut parts = Vec::with_capacity(regions.len());
    for (i, (r, &v)) in regions.iter().zip(versions).enumerate() {
        let kept = memo.parts.get(i).filter(|p| same_shape && p.0 == v);
        parts.push(match kept {
            Some(&p) => p,
            None => {
                let (hull, surviving) = extremes_first(shape, &[*r]);
                (v, hull, !surviving.is_empty())
            }
        });
    }
    let mut hull: Option<Piece> = None;
    let mut surviving = Vec::new();
    for (i, &(_, part, hit)) in parts.iter().enumerate() {
        if let Some(piece) = part {
            hull = Some(hull.map_or(piece, |acc| Shape::hull_pieces(&acc, &piece)));
        }
        if hit {
            surviving.push(i);
        }
    }
    *memo = BranchMemo { shape: key, parts };
    if hull.as_ref().is_some_and(|h| shape.zero_bound(h)) {
        (hull, surviving) = every_box(shape, regions);
    }
    branches(shape, hull, surviving)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ibox::IntervalBox;
    use crate::rng::Rng;
    use crate::shapes::branch::branch;

    fn bits(b: &Branches) -> (Vec<u64>, Vec<usize>) {
        let v =
            b.p.axes()
                .iter()
                .chain(b.d.axes())
                .flat_map(|x| [x.lo().to_bits(), x.hi().to_bits()])
                .collect();
        (v, b.surviving.clone())
    }

    fn boxed(rng: &mut Rng, dim: usize, scale: f64, w: f64) -> IntervalBox {
        let v: Vec<Interval> = (0..dim)
            .map(|_| {
                let c = match rng.next_u64() % 8 {
                    0 => 0.0,
                    1 => -0.0,
                    _ => rng.sym(scale),
                };
                Interval::new(c - w * rng.unit(), c + w * rng.unit())
            })
            .collect();
        IntervalBox::new(&v)
    }

    /// Over sequences of branches of one detection whose shape and regions
    /// change at random (a changed region gets a new version; a repeated
    /// shape or region keeps its bits), the memo gives the plain branch's
    /// bits every time, and reuses parts often enough to mean something.
    /// Zero bounds, huge and unbounded boxes included.
    #[test]
    fn the_memo_gives_the_plain_branch_bits() {
        let mut rng = Rng::new(41);
        let mut reused = 0usize;
        for case in 0..400 {
            let dim = 2 + (case % 4 == 0) as usize;
            let scale = [1.0, 10.0, 1e6][case % 3];
            let mut regions: Vec<Paving> = (0..1 + case % 4)
                .map(|_| {
                    let w = scale * (0.1 + rng.unit());
                    let mut p = Paving::from_box(&boxed(&mut rng, dim, scale, w));
                    p.refine::<Shape>(&[], 0.0, 4 + (rng.next_u64() % 40) as usize);
                    p
                })
                .collect();
            let mut versions: Vec<u64> = (0..regions.len() as u64).collect();
            let mut next = versions.len() as u64;
            let mut memo = BranchMemo::default();
            let mut shape = Shape::new(
                boxed(&mut rng, dim, scale, scale),
                Interval::new(0.0, scale * 2.0 * rng.unit()),
                None,
                IntervalBox::entire(dim),
            );
            for step in 0..8 {
                match rng.next_u64() % 4 {
                    0 => {
                        let i = (rng.next_u64() as usize) % regions.len();
                        let w = scale * (0.05 + rng.unit());
                        let cut = boxed(&mut rng, dim, scale, w);
                        regions[i].intersect(&Paving::from_box(&cut), 64);
                        versions[i] = next;
                        next += 1;
                    }
                    1 => {
                        let bearing = (step % 2 == 0).then(|| {
                            let b = rng.sym(3.2);
                            (Interval::new(-0.1, 0.1), Interval::new(b, b + rng.unit()))
                        });
                        let r = scale * rng.unit();
                        let range = if case % 9 == 0 {
                            Interval::new(r, f64::INFINITY)
                        } else {
                            Interval::new(r, r + scale * 0.3 * rng.unit())
                        };
                        shape = Shape::new(shape.centre.clone(), range, bearing, shape.cut.clone());
                    }
                    _ => reused += memo.parts.len() * (memo.shape == shape_bits(&shape)) as usize,
                }
                let refs: Vec<&Paving> = regions.iter().collect();
                let want = branch(&shape, &refs);
                let got = branch_memo(&shape, &refs, &versions, &mut memo);
                assert_eq!(bits(&got), bits(&want), "case {case} step {step}");
            }
        }
        assert!(reused > 1000, "{reused}");
    }
}
