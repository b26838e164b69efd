//! The scan pose: the detections of one step share one position
//! and one heading, so they are contracted together over pieces of the
//! heading, which keeps the correlation between the heading and the
//! position that the detections' separate contractions lose.
//!
//! # Constraint
//!
//! For every detection j at the step (range r_j, bearing b_j, landmark
//! l_j, sensor offset o in the body frame):
//! `l_j = p + R(th) o + r_j (cos(th + b_j), sin(th + b_j))`.
//!
//! # Math
//!
//! The heading's interval Th is cut into K pieces Th_k (adjacent pieces
//! share their float bound, so they cover Th). For a piece, the world
//! vector from p to l_j lies in the box
//! `V_jk = R(Th_k) o + r_j (cos(Th_k + b_j), sin(Th_k + b_j))` (interval
//! arithmetic), so `p ∈ P_k = P ∩ ⋂_j (D_j - V_jk)`; a piece whose P_k is
//! empty holds no solution. Then `th ∈` the hull of the pieces left,
//! `p ∈` the hull of their P_k, and `l_j ∈ D_j ∩` the hull of the
//! `P_k + V_jk`. With a landmark box D_a of a mapped landmark (0.4 m) and
//! a heading 0.7 rad wide, P_k is about as wide as D_a plus a's
//! measurement error, and the landmark of an unmatched detection b of the
//! same step is read in P_k + V_bk: about 1.1 m on Lost in the Woods
//! where the separate contractions give 2-3 m (P + V(Th)).
//!
//! # Soundness
//!
//! The true heading lies in some piece Th_k (the pieces cover Th); for it
//! the true world vectors lie in the V_jk (outward-rounded interval
//! evaluations over the piece and the measurement intervals) and the true
//! landmarks in the D_j, so the true position is in P_k, the true
//! landmarks in `P_k + V_jk`, and the piece survives. Every detection must
//! see a real landmark (the rounds call it with `max_outliers` = 0). The
//! heading is a real number (never wrapped): cos and sin of a piece are
//! enclosed whatever its magnitude.
//!
//! # Complexity
//!
//! O(K c) interval operations (four trig enclosures per piece and
//! detection) for c detections; no allocation beyond O(c).

use crate::interval::Interval;

/// One detection of the step: its measurement and its landmark box.
#[derive(Debug, Clone, Copy)]
pub struct PoseReading {
    /// r, the range (clamped to r >= 0).
    pub range: Interval,
    /// b, the bearing.
    pub bearing: Interval,
    /// The landmark box, contracted in place.
    pub landmark: [Interval; 2],
}

/// What the contraction proved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseOutcome {
    /// The domains hold what is left (possibly unchanged).
    Contracted,
    /// No piece of the heading fits every detection: infeasible.
    Empty,
}

/// The world vector from p to the landmark of `r` under the heading piece
/// `th` (module doc).
fn world_vector(th: Interval, offset: [f64; 2], r: &PoseReading) -> [Interval; 2] {
    let (c, s) = (th.cos(), th.sin());
    let (ox, oy) = (Interval::point(offset[0]), Interval::point(offset[1]));
    let range = r.range.intersect(Interval::new(0.0, f64::INFINITY));
    let a = th + r.bearing;
    [
        c * ox - s * oy + range * a.cos(),
        s * ox + c * oy + range * a.sin(),
    ]
}

/// The hull of two boxes (either may be empty).
fn hull2(a: [Interval; 2], b: [Interval; 2]) -> [Interval; 2] {
    [a[0].hull(b[0]), a[1].hull(b[1])]
}

/// Contracts the position `p`, the heading and the readings' landmark
/// boxes by the joint constraint over `pieces` heading pieces (module
/// doc). Nothing is done with fewer than 2 pieces, an unbounded heading
/// or an empty domain.
pub fn contract_scan_pose(
    p: &mut [Interval; 2],
    heading: &mut Interval,
    offset: [f64; 2],
    reads: &mut [PoseReading],
    pieces: usize,
) -> PoseOutcome {
    let th = *heading;
    if pieces < 2 || reads.is_empty() || !th.is_bounded() || th.is_empty() {
        return PoseOutcome::Contracted;
    }
    // The pieces' bounds: lo, then non-decreasing values in [lo, hi], then
    // hi, so the pieces cover th whatever the rounding. The width may
    // overflow to +inf (then the inner bounds are hi); k = 0 is lo itself
    // (inf · 0 would be NaN).
    let (lo, w) = (th.lo(), th.hi() - th.lo());
    let bound = |k: usize| -> f64 {
        match k {
            0 => lo,
            k if k == pieces => th.hi(),
            k => (lo + w * (k as f64) / (pieces as f64)).clamp(lo, th.hi()),
        }
    };
    let mut vs = vec![[Interval::EMPTY; 2]; reads.len()];
    let mut th_hull = Interval::EMPTY;
    let mut p_hull = [Interval::EMPTY; 2];
    let mut d_hull = vec![[Interval::EMPTY; 2]; reads.len()];
    for k in 0..pieces {
        let piece = Interval::new(bound(k), bound(k + 1));
        let mut pk = *p;
        for (r, v) in reads.iter().zip(vs.iter_mut()) {
            *v = world_vector(piece, offset, r);
            pk[0] = pk[0].intersect(r.landmark[0] - v[0]);
            pk[1] = pk[1].intersect(r.landmark[1] - v[1]);
        }
        if pk[0].is_empty() || pk[1].is_empty() {
            continue;
        }
        th_hull = th_hull.hull(piece);
        p_hull = hull2(p_hull, pk);
        for ((r, v), d) in reads.iter().zip(&vs).zip(d_hull.iter_mut()) {
            let dk = [
                (pk[0] + v[0]).intersect(r.landmark[0]),
                (pk[1] + v[1]).intersect(r.landmark[1]),
            ];
            *d = hull2(*d, dk);
        }
    }
    if th_hull.is_empty() {
        return PoseOutcome::Empty;
    }
    *heading = th.intersect(th_hull);
    p[0] = p[0].intersect(p_hull[0]);
    p[1] = p[1].intersect(p_hull[1]);
    for (r, d) in reads.iter_mut().zip(d_hull) {
        r.landmark = d;
    }
    if heading.is_empty() || p[0].is_empty() || p[1].is_empty() {
        return PoseOutcome::Empty;
    }
    PoseOutcome::Contracted
}
