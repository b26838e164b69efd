//! Detection shapes: the set of landmark positions one detection allows
//! given the current box of its robot position (docs/design.md, "Detection
//! shapes").
//!
//! # The set
//!
//! Detection j at step t with range r (and bearing β relative to the
//! heading θ, when measured) allows the landmark positions
//!
//! `A(j) = {x ∈ C : ∃ p ∈ P, |x - p| ∈ r, [β: x - p points along θ + β]}`
//!
//! where P is the box of p(t) and C the box d(j) (which holds the detection's
//! region, depth and the mission's landmark region, and whatever the other
//! contractors proved). Without a bearing A(j) is an annulus (a spherical
//! shell in 3-D) around an uncertain centre; with one, an annular sector.
//! Its hull is the box d(j); the shape itself is much thinner, and two shapes
//! are often disjoint where their hulls overlap.
//!
//! # Tests (each sound: `false` for "meets" and `true` for "disjoint" are
//! proofs)
//!
//! - [`Shape::contract_piece`] / [`Shape::meets_box`]: the branch "landmark
//!   in box B": copies of P and B ∩ C contracted by the detection's own
//!   constraints ([`contract_distance`], then [`contract_bearing`](crate::contractors::bearing::contract_bearing) and
//!   [`contract_distance`] again when a bearing is known). The forward pass
//!   of the distance contractor evaluates `Σ (P_i - B_i)^2`, which is the
//!   exact range of the squared distance between the two boxes (the terms
//!   are separable), rounded outwards; B is excluded when that range misses
//!   r^2, or when the bearing cone from P misses B.
//! - [`Shape::disjoint`]: the hulls are disjoint, or, with
//!   `[dlo, dhi]` the interval of distances between points of the two centre
//!   boxes P and Q, `dlo > r1hi + r2hi` (each annulus lies within r_hi of
//!   its centre box, and the boxes are further apart than that), or
//!   `dhi + r1hi < r2lo` (every point of A(1) is within `r1hi + dhi` of every
//!   point of Q, so closer than r2lo to it: inside the hole of A(2)), or the
//!   symmetric case. The interval sums are rounded outwards.
//! - [`disjoint_paved`]: for sectors, whose cone the annulus test ignores:
//!   the common hull is bisected (bounded count) and every piece must be
//!   excluded by one of the two shapes.
//!
//! An empty shape (an empty centre, range or cut) is never called disjoint
//! from another: emptiness is a proof of infeasibility, reported where it
//! arises, never a proof of distinct landmarks.
//!
//! # The trait
//!
//! [`DetectionShape`] is what the rest of the shapes machinery (witnesses,
//! regions, branch contraction) needs of a shape: its bounds, the branch
//! "position in box B" ([`DetectionShape::contract_piece`]) with its
//! position part, and a quick disjointness test. [`Shape`] implements it,
//! and so does a TDOA pulse's hyperbolic shell
//! ([`crate::tdoa::shell::PulseShell`]); [`disjoint_paved`],
//! [`super::region::Paving`], [`super::branch`] and [`super::witnesses`] are
//! generic over it (monomorphized: no cost for the SLAM path).
//!
//! # Complexity
//!
//! O(d) per test, O(budget · d) for [`disjoint_paved`].

use crate::contractors::bearing::contract_bearing_trig;
use crate::contractors::distance::contract_distance;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use std::cell::OnceCell;

/// What the shapes need of one detection, and no more: its step, range
/// and bearing (the SLAM association step builds them from the mission's
/// detections, so that this module never sees a mission).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    /// Step of the robot position p(step).
    pub step: usize,
    /// Range to the landmark.
    pub range: Interval,
    /// Angle of the landmark relative to the heading (2-D) or yaw (3-D).
    pub bearing: Option<Interval>,
}

/// Most axes of a shape (missions are 2-D or 3-D).
pub const MAX_DIM: usize = 3;

/// The landmark set of one detection (see the module doc).
#[derive(Debug, Clone)]
pub struct Shape {
    /// P: the box of the robot position p(step).
    pub centre: IntervalBox,
    /// r: the range, intersected with [0, +inf).
    pub range: Interval,
    /// (θ, β): the heading (or yaw) at the step and the bearing, when a
    /// bearing is measured.
    pub bearing: Option<(Interval, Interval)>,
    /// C: a box known to hold the landmark (the detection variable d(j)).
    pub cut: IntervalBox,
    /// (φ, cos φ, sin φ) for φ = θ + β of `bearing`, made at the first
    /// contraction (a shape is contracted against every box of
    /// a paving, and the interval cosine and sine of φ were recomputed
    /// each time). Used only while θ + β gives the same bits as φ (a
    /// changed `bearing` recomputes them), so every contraction gives the
    /// same bits as without it.
    trig: OnceCell<(Interval, Interval, Interval)>,
    /// (r_hi, U) for the bound U of [`Shape::absorbs`], made at its first
    /// call; used only while the range's upper bound has the same bits.
    reach: OnceCell<(f64, f64)>,
}

/// Equal shapes: the same centre, range, bearing and cut (the cached
/// cosine, sine and reach are not part of the shape).
impl PartialEq for Shape {
    fn eq(&self, other: &Shape) -> bool {
        self.centre == other.centre
            && self.range == other.range
            && self.bearing == other.bearing
            && self.cut == other.cut
    }
}

/// One branch of a detection: the robot position and the landmark position
/// contracted under "landmark in a given box".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece {
    /// Contracted copy of P (first `dim` axes).
    pub p: [Interval; MAX_DIM],
    /// Contracted copy of the box ∩ C.
    pub d: [Interval; MAX_DIM],
}

/// A set known to hold one position (a landmark's, an emitter's), with
/// the sound tests the shapes machinery runs on it (module doc).
pub trait DetectionShape {
    /// One branch "position in box B": the position and the shape's own
    /// hidden variables (a robot position, an emission time), contracted.
    type Piece: Copy;

    /// Number of axes of the position.
    fn dim(&self) -> usize;

    /// Whether the shape is proved empty (then it proves no disjointness).
    fn is_empty(&self) -> bool;

    /// A box known to hold the shape (where pavings of it start).
    fn bounds(&self) -> &IntervalBox;

    /// The branch "position in `b`"; `None` is a proof that no point of
    /// the shape lies in `b`. Every solution with its position in `b` lies
    /// in the returned piece.
    fn contract_piece(&self, b: &[Interval]) -> Option<Self::Piece>;

    /// The position part of a piece (the first [`DetectionShape::dim`]
    /// axes).
    fn position(piece: &Self::Piece) -> [Interval; MAX_DIM];

    /// The hull of two pieces (the branch contraction keeps the hull of
    /// its survivors).
    fn hull_pieces(a: &Self::Piece, b: &Self::Piece) -> Self::Piece;

    /// A quick proof that the two shapes share no point (`false`: not
    /// proved).
    fn disjoint_quick(&self, other: &Self) -> bool;

    /// Whether [`disjoint_paved`] may prove what
    /// [`DetectionShape::disjoint_quick`] does not (worth its cost).
    fn worth_paving(&self, other: &Self) -> bool;

    /// A rank key, smaller is thinner (says more).
    fn thickness(&self) -> f64;

    /// Whether the shape may meet `b` (`false` is a proof that it does
    /// not).
    fn meets_box(&self, b: &[Interval]) -> bool {
        self.contract_piece(b).is_some()
    }

    /// A cheap proof that every point of `b` is a position the shape
    /// allows, none of `b`'s bounds a zero: then the position part of
    /// [`DetectionShape::contract_piece`] of `b` is `b`, bit for bit (a
    /// sound contraction keeps every solution, so it keeps all of `b`, and
    /// it never grows `b`; equal non-zero bounds have equal bits), and a
    /// paving's cut may leave `b` as it is. `false`: not known (the
    /// default).
    fn keeps(&self, _b: &[Interval]) -> bool {
        false
    }

    /// A cheap test that the hull of `acc` and the piece of `b` (when
    /// there is one) is `acc`, bit for bit, given `outer`, the piece of a
    /// box holding `b` (the contractions are inclusion-monotone, so it
    /// holds the piece of `b`): then the branch contraction need not
    /// contract `b` once its region is known to survive. `false`: not
    /// known (the default).
    fn absorbs(&self, _acc: &Self::Piece, _outer: &Self::Piece, _b: &[Interval]) -> bool {
        false
    }

    /// Whether [`DetectionShape::absorbs`] may answer `true` (then the
    /// branch contraction takes the boxes in another order).
    const ABSORBS: bool = false;

    /// Whether a bound of the piece is zero (of either sign).
    fn zero_bound(&self, _piece: &Self::Piece) -> bool {
        true
    }
}

impl DetectionShape for Shape {
    type Piece = Piece;

    fn dim(&self) -> usize {
        Shape::dim(self)
    }

    fn is_empty(&self) -> bool {
        Shape::is_empty(self)
    }

    fn bounds(&self) -> &IntervalBox {
        &self.cut
    }

    fn contract_piece(&self, b: &[Interval]) -> Option<Piece> {
        Shape::contract_piece(self, b)
    }

    fn position(piece: &Piece) -> [Interval; MAX_DIM] {
        piece.d
    }

    fn hull_pieces(a: &Piece, b: &Piece) -> Piece {
        let mut out = *a;
        for i in 0..MAX_DIM {
            out.p[i] = a.p[i].hull(b.p[i]);
            out.d[i] = a.d[i].hull(b.d[i]);
        }
        out
    }

    fn disjoint_quick(&self, other: &Shape) -> bool {
        Shape::disjoint(self, other)
    }

    /// Only a bearing's cone is missed by the annulus tests.
    fn worth_paving(&self, other: &Shape) -> bool {
        self.bearing.is_some() || other.bearing.is_some()
    }

    fn thickness(&self) -> f64 {
        Shape::thickness(self)
    }

    fn meets_box(&self, b: &[Interval]) -> bool {
        Shape::meets_box(self, b)
    }

    fn absorbs(&self, acc: &Piece, outer: &Piece, b: &[Interval]) -> bool {
        Shape::absorbs(self, acc, outer, b)
    }

    /// Natively only (the browser's build contracts every box, with the
    /// same bits).
    fn keeps(&self, b: &[Interval]) -> bool {
        cfg!(not(target_arch = "wasm32")) && Shape::keeps_box(self, b)
    }

    /// Natively only: the browser's build keeps the plain branch
    /// contraction (its transfer budget), with the same bits.
    const ABSORBS: bool = cfg!(not(target_arch = "wasm32"));

    fn zero_bound(&self, piece: &Piece) -> bool {
        let dim = self.dim();
        piece.p[..dim]
            .iter()
            .chain(&piece.d[..dim])
            .any(|x| x.lo() == 0.0 || x.hi() == 0.0)
    }
}

/// A reference to a shape is that shape (so that `&&Shape` from an
/// iterator over `&Shape`s works where a shape is asked for).
impl<T: DetectionShape> DetectionShape for &T {
    type Piece = T::Piece;

    fn dim(&self) -> usize {
        T::dim(self)
    }

    fn is_empty(&self) -> bool {
        T::is_empty(self)
    }

    fn bounds(&self) -> &IntervalBox {
        T::bounds(self)
    }

    fn contract_piece(&self, b: &[Interval]) -> Option<T::Piece> {
        T::contract_piece(self, b)
    }

    fn keeps(&self, b: &[Interval]) -> bool {
        T::keeps(self, b)
    }

    fn position(piece: &T::Piece) -> [Interval; MAX_DIM] {
        T::position(piece)
    }

    fn hull_pieces(a: &T::Piece, b: &T::Piece) -> T::Piece {
        T::hull_pieces(a, b)
    }

    fn disjoint_quick(&self, other: &Self) -> bool {
        T::disjoint_quick(self, other)
    }

    fn worth_paving(&self, other: &Self) -> bool {
        T::worth_paving(self, other)
    }

    fn thickness(&self) -> f64 {
        T::thickness(self)
    }

    fn meets_box(&self, b: &[Interval]) -> bool {
        T::meets_box(self, b)
    }

    fn absorbs(&self, acc: &T::Piece, outer: &T::Piece, b: &[Interval]) -> bool {
        T::absorbs(self, acc, outer, b)
    }

    const ABSORBS: bool = T::ABSORBS;

    fn zero_bound(&self, piece: &T::Piece) -> bool {
        T::zero_bound(self, piece)
    }
}

/// `up(sqrt(up(r^2)))`: a bound of every |p_i - d_i| that
/// [`contract_distance`] keeps under a range of upper bound `r` (the
/// bound of [`Shape::absorbs`], computed by the same operations).
fn reach(r: f64) -> f64 {
    Interval::new(0.0, r).sqr().sqrt().hi()
}

/// The interval of distances between a point of `p` and a point of `q`
/// (boxes of one dimension). Tightness: the exact range, rounded outwards
/// (the squared distance is a sum of separable squares).
pub fn distance_between(p: &[Interval], q: &[Interval]) -> Interval {
    let mut s = Interval::ZERO;
    for (a, b) in p.iter().zip(q) {
        s = s + (*a - *b).sqr();
    }
    s.sqrt()
}

impl Shape {
    /// A shape; `range` is cut to [0, +inf).
    pub fn new(
        centre: IntervalBox,
        range: Interval,
        bearing: Option<(Interval, Interval)>,
        cut: IntervalBox,
    ) -> Shape {
        debug_assert!(centre.dim() == cut.dim() && centre.dim() <= MAX_DIM);
        Shape {
            centre,
            range: range.intersect(Interval::new(0.0, f64::INFINITY)),
            bearing,
            cut,
            trig: OnceCell::new(),
            reach: OnceCell::new(),
        }
    }

    /// cos φ and sin φ of φ = θ + β: those made with the shape while φ has
    /// the same bits, else computed (the same bits either way).
    fn cos_sin(&self, heading: Interval, beta: Interval) -> (Interval, Interval) {
        let phi = heading + beta;
        let same = |a: Interval, b: Interval| {
            a.lo().to_bits() == b.lo().to_bits() && a.hi().to_bits() == b.hi().to_bits()
        };
        let &(made, c, s) = self.trig.get_or_init(|| (phi, phi.cos(), phi.sin()));
        if same(made, phi) {
            (c, s)
        } else {
            (phi.cos(), phi.sin())
        }
    }

    /// Number of axes.
    pub fn dim(&self) -> usize {
        self.centre.dim()
    }

    /// Whether the shape is proved empty (an empty centre, range or cut).
    pub fn is_empty(&self) -> bool {
        self.centre.is_empty() || self.range.is_empty() || self.cut.is_empty()
    }

    /// The branch "landmark in `b`": P and b ∩ C contracted by the
    /// detection's constraints; `None` when proved empty (then the shape
    /// does not meet `b`). Every (p, x) with p ∈ P, x ∈ b ∩ C satisfying the
    /// detection lies in the returned piece. O(d).
    pub fn contract_piece(&self, b: &[Interval]) -> Option<Piece> {
        let dim = self.dim();
        let mut piece = Piece {
            p: [Interval::ZERO; MAX_DIM],
            d: [Interval::ZERO; MAX_DIM],
        };
        for (a, x) in b.iter().enumerate().take(dim) {
            piece.p[a] = self.centre[a];
            piece.d[a] = x.intersect(self.cut[a]);
            if piece.d[a].is_empty() || piece.p[a].is_empty() {
                return None;
            }
        }
        let mut r = self.range;
        let (p, d) = (&mut piece.p[..dim], &mut piece.d[..dim]);
        if !contract_distance(p, d, &mut r) {
            return None;
        }
        if let Some((heading, bearing)) = self.bearing {
            let (c, s) = self.cos_sin(heading, bearing);
            if !contract_bearing_trig(p, d, c, s, r) || !contract_distance(p, d, &mut r) {
                return None;
            }
        }
        if p.iter().chain(d.iter()).any(|x| x.is_empty()) {
            return None;
        }
        Some(piece)
    }

    /// Whether the shape may meet `b` (`false` is a proof that it does not).
    pub fn meets_box(&self, b: &[Interval]) -> bool {
        (cfg!(not(target_arch = "wasm32")) && self.keeps_box(b)) || self.contract_piece(b).is_some()
    }

    /// Whether every point x of `b` is a position the shape allows, proved
    /// cheaply (no bearing; every bound of `b` and P non-zero and below
    /// 2^500 in magnitude;
    /// `false`: not known). Constraint: x in C and |x - p| in r for some p
    /// in P. Math: the distances from x to the points of the box P fill
    /// [dmin(x), dmax(x)] (P is connected); per axis a, x_a in [bl, bh],
    /// P_a = [pl, ph], dist(x_a, P_a) <= f_a = max(pl - bl, bh - ph, 0)
    /// and max(|x_a - pl|, |x_a - ph|) >= g_a = max(bl - pl, ph - bh,
    /// (ph - pl) / 2), so dmin(x)^2 <= Σ f_a^2 and dmax(x)^2 >= Σ g_a^2;
    /// Σ f_a^2 <= r_hi^2 and Σ g_a^2 >= r_lo^2 (each operation rounded
    /// outward: one ulp up or down of its rounded result) give
    /// dmin(x) <= r_hi and dmax(x) >= r_lo, so [dmin, dmax] meets r, and
    /// b ⊆ C. Sound: every x of b then satisfies the detection, so
    /// [`Shape::contract_piece`] keeps it ([`DetectionShape::keeps`]).
    /// O(d).
    pub fn keeps_box(&self, b: &[Interval]) -> bool {
        use crate::interval::{pred, succ};
        if self.bearing.is_some() || self.range.is_empty() || b.len() < self.dim() {
            return false;
        }
        // Bounds below 2^500 in magnitude: the differences and squares
        // below stay finite, so one ulp up (down) of each rounded result
        // bounds the exact one.
        let usable = |v: f64| v != 0.0 && v.abs() < 3.3e150;
        let (mut far, mut near) = (0.0f64, 0.0f64);
        for (a, x) in b.iter().enumerate().take(self.dim()) {
            let (p, c) = (self.centre[a], self.cut[a]);
            let (bl, bh, pl, ph) = (x.lo(), x.hi(), p.lo(), p.hi());
            if !(usable(bl) && usable(bh) && usable(pl) && usable(ph)) || bl > bh || pl > ph {
                return false;
            }
            if !(c.lo() <= bl && bh <= c.hi()) {
                return false;
            }
            let f = succ((pl - bl).max(bh - ph).max(0.0));
            let g = pred(bl - pl)
                .max(pred(ph - bh))
                .max(pred((ph - pl) * 0.5))
                .max(0.0);
            far = succ(far + succ(f * f));
            near = pred(near + pred(g * g)).max(0.0);
        }
        let (r_lo, r_hi) = (self.range.lo(), self.range.hi());
        far <= pred(r_hi * r_hi) && near >= succ(r_lo * r_lo)
    }

    /// Whether `acc` holds the piece of `b` so that their hull is `acc`
    /// bit for bit ([`DetectionShape::absorbs`]), without contracting:
    /// the piece lies in `outer` (the piece of a box holding `b`: every
    /// step of the contraction is inclusion-monotone), its landmark part
    /// in b ∩ C and its robot part in b ∩ C + [-U, U] with
    /// `U = up(sqrt(up(r_hi^2)))`, because every [`contract_distance`]
    /// ends the robot part with `p ∩= u + d`, where `|u| <= sqrt(s_i)`
    /// and `s_i <= r_hi^2`, both rounded up (the bearing step between
    /// them only shrinks p and d). A bound of `acc` equal to the piece's
    /// must not be a zero (the hull of +0 and -0 may keep either). O(d).
    pub fn absorbs(&self, acc: &Piece, outer: &Piece, b: &[Interval]) -> bool {
        let range_hi = self.range.hi();
        let &(made, u) = self.reach.get_or_init(|| (range_hi, reach(range_hi)));
        let u = if made.to_bits() == range_hi.to_bits() {
            u
        } else {
            reach(range_hi)
        };
        let reach = Interval::new(-u, u);
        // `a` holds `x`, and a bound of theirs equal in value has its bits.
        let holds = |a: Interval, x: Interval| {
            let lo = a.lo() < x.lo() || (a.lo() == x.lo() && a.lo() != 0.0);
            let hi = a.hi() > x.hi() || (a.hi() == x.hi() && a.hi() != 0.0);
            lo && hi
        };
        for (a, x) in b.iter().enumerate().take(self.dim()) {
            let d = x.intersect(self.cut[a]).intersect(outer.d[a]);
            if d.is_empty() {
                // No piece.
                return true;
            }
            if !holds(acc.d[a], d) {
                return false;
            }
            let p = outer.p[a].intersect(d + reach);
            if p.is_empty() {
                return true;
            }
            if !holds(acc.p[a], p) {
                return false;
            }
        }
        true
    }

    /// The hull of the shape as far as its contraction shows: C contracted
    /// by the detection's constraints (empty when proved empty).
    pub fn hull(&self) -> IntervalBox {
        let dim = self.dim();
        match self.contract_piece(self.cut.axes()) {
            Some(piece) => IntervalBox::new(&piece.d[..dim]),
            None => IntervalBox::empty(dim),
        }
    }

    /// A proof that the two shapes share no point (`false`: not proved).
    /// Hulls, then the annulus tests of the module doc. O(d).
    ///
    /// An empty shape proves nothing here (`false`): its emptiness says the
    /// mission is infeasible, which is for the caller to report as such,
    /// not to turn into "distinct landmarks" (an empty centre box
    /// from an unbounded displacement made every pair across it
    /// "disjoint").
    pub fn disjoint(&self, other: &Shape) -> bool {
        if self.is_empty() || other.is_empty() {
            return false;
        }
        if !self.cut.meets(&other.cut) {
            return true;
        }
        let dd = distance_between(self.centre.axes(), other.centre.axes());
        let (r1, r2) = (self.range, other.range);
        (r1 + r2).hi() < dd.lo() || (dd + r1).hi() < r2.lo() || (dd + r2).hi() < r1.lo()
    }

    /// A size to rank shapes by how much they say: the annulus thickness
    /// (range width plus the centre's diameter), capped by the hull's
    /// diameter; smaller is thinner.
    pub fn thickness(&self) -> f64 {
        let t = self.range.width() + self.centre.diameter();
        t.min(self.cut.diameter())
    }
}

/// A proof that shapes `a` and `b` are disjoint by bisection: the common
/// bounds are split (widest axis at its midpoint) and every piece must be
/// excluded by `a` or `b`. Gives up (returns `false`) after `budget`
/// pieces. Sound: a common point would lie in a piece neither shape
/// excludes. O(budget · d).
pub fn disjoint_paved<S: DetectionShape>(a: &S, b: &S, budget: usize) -> bool {
    if a.is_empty() || b.is_empty() {
        // Not a proof of disjointness (see [`Shape::disjoint`]).
        return false;
    }
    if a.disjoint_quick(b) {
        return true;
    }
    let start = a.bounds().intersect(b.bounds());
    if start.is_empty() {
        return true;
    }
    let dim = a.dim();
    let mut stack = vec![start];
    let mut seen = 0usize;
    while let Some(x) = stack.pop() {
        let (pa, pb) = match (a.contract_piece(x.axes()), b.contract_piece(x.axes())) {
            (Some(pa), Some(pb)) => (S::position(&pa), S::position(&pb)),
            _ => continue,
        };
        seen += 1;
        if seen > budget {
            return false;
        }
        // Both shapes meet x: continue on the part both contractions keep.
        let mut axes = [Interval::ZERO; MAX_DIM];
        for (i, x) in axes.iter_mut().enumerate().take(dim) {
            *x = pa[i].intersect(pb[i]);
            if x.is_empty() {
                break;
            }
        }
        let y = IntervalBox::new(&axes[..dim]);
        if y.is_empty() {
            continue;
        }
        let (l, r) = bisect(&y);
        stack.push(r);
        stack.push(l);
    }
    true
}

/// Splits a box at the midpoint of its widest axis (an unbounded axis is
/// split at a finite point). The two halves cover the box.
pub fn bisect(b: &IntervalBox) -> (IntervalBox, IntervalBox) {
    let mut axis = 0;
    let mut w = -1.0;
    for (i, x) in b.axes().iter().enumerate() {
        if x.width() > w {
            w = x.width();
            axis = i;
        }
    }
    let m = b[axis].mid();
    let (mut l, mut r) = (b.clone(), b.clone());
    l[axis] = Interval::new(b[axis].lo(), m);
    r[axis] = Interval::new(m, b[axis].hi());
    (l, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `keeps_box` answers `true` only for boxes every point of which the
    /// shape allows: the contraction then gives the box back bit for bit,
    /// and sampled points of the box are at an allowed distance from some
    /// point of P. It answers `true` often enough to matter (and `false`
    /// too). 2-D and 3-D, thin and thick annuli, wide and point centres.
    #[test]
    fn a_kept_box_is_what_the_contraction_gives_back() {
        let mut rng = crate::rng::Rng::new(7);
        let (mut kept, mut other) = (0usize, 0usize);
        for case in 0..20_000 {
            let dim = 2 + (case % 3 == 0) as usize;
            let scale = [1.0, 50.0, 1e4][case % 3];
            let iv = |c: f64, w: f64| Interval::new(c - w, c + w);
            let mut centre = Vec::new();
            let mut b = Vec::new();
            let r0 = scale * rng.unit();
            let r = Interval::new(r0, r0 + scale * rng.unit() * [0.05, 0.5, 2.0][case % 4 % 3]);
            for a in 0..dim {
                let c = rng.sym(scale);
                centre.push(iv(
                    c,
                    scale * 0.3 * rng.unit() * (case % 5 != 0) as u8 as f64,
                ));
                let dir = if a == 0 { r0 } else { rng.sym(r0 * 0.3) };
                b.push(iv(c + dir, scale * 0.2 * rng.unit()));
            }
            let cut = if case % 7 == 0 {
                IntervalBox::new(
                    &b.iter()
                        .map(|x| iv(x.mid(), x.width() * 0.4))
                        .collect::<Vec<_>>(),
                )
            } else {
                IntervalBox::entire(dim)
            };
            let s = Shape::new(IntervalBox::new(&centre), r, None, cut);
            if !s.keeps_box(&b) {
                other += 1;
                continue;
            }
            kept += 1;
            let piece = s.contract_piece(&b).expect("a kept box meets the shape");
            for (d, x) in piece.d.iter().zip(&b) {
                assert_eq!(d.lo().to_bits(), x.lo().to_bits(), "case {case}");
                assert_eq!(d.hi().to_bits(), x.hi().to_bits(), "case {case}");
            }
            for _ in 0..8 {
                let x: Vec<f64> = b.iter().map(|i| i.lo() + i.width() * rng.unit()).collect();
                let (mut dmin, mut dmax) = (0.0, 0.0);
                for a in 0..dim {
                    let (lo, hi) = (centre[a].lo(), centre[a].hi());
                    let near = (lo - x[a]).max(x[a] - hi).max(0.0);
                    let far = (x[a] - lo).abs().max((x[a] - hi).abs());
                    dmin += near * near;
                    dmax += far * far;
                }
                let eps = 1e-9 * scale;
                assert!(
                    dmin.sqrt() <= r.hi() + eps && dmax.sqrt() >= r.lo() - eps,
                    "case {case}"
                );
            }
        }
        assert!(kept > 1000 && other > 1000, "{kept} {other}");
    }

    /// `keeps_box` on adversarial bounds (zeros of both signs, subnormals,
    /// huge, MAX and infinite values, empty and reversed ranges): when it
    /// says `true`, the contraction gives the box back bit for bit and
    /// keeps every corner of it as a point box (a planted solution on the
    /// boundary); it never says `true` with an unusable bound.
    #[test]
    fn keeps_box_is_sound_on_extreme_values() {
        let specials = [
            0.0,
            -0.0,
            5e-324,
            -5e-324,
            1e-300,
            1.0,
            -1.0,
            3.0,
            -3.0,
            1e150,
            -1e150,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut rng = crate::rng::Rng::new(11);
        let pick = |rng: &mut crate::rng::Rng| {
            if rng.next_u64().is_multiple_of(3) {
                specials[rng.next_u64() as usize % specials.len()]
            } else {
                rng.sym(4.0)
            }
        };
        let (mut kept, mut cases) = (0usize, 0usize);
        for case in 0..30_000 {
            let dim = 2 + (case % 2);
            let iv = |rng: &mut crate::rng::Rng| {
                let (a, b) = (pick(rng), pick(rng));
                Interval::new(a.min(b), a.max(b))
            };
            let centre: Vec<Interval> = (0..dim).map(|_| iv(&mut rng)).collect();
            let b: Vec<Interval> = (0..dim).map(|_| iv(&mut rng)).collect();
            let r = iv(&mut rng);
            let cut = if case % 3 == 0 {
                IntervalBox::new(&(0..dim).map(|_| iv(&mut rng)).collect::<Vec<_>>())
            } else {
                IntervalBox::entire(dim)
            };
            let s = Shape::new(IntervalBox::new(&centre), r, None, cut);
            cases += 1;
            if !s.keeps_box(&b) {
                continue;
            }
            kept += 1;
            for x in &b {
                assert!(x.lo().is_finite() && x.hi().is_finite(), "case {case}");
                assert!(x.lo() != 0.0 && x.hi() != 0.0, "case {case}");
            }
            let piece = s.contract_piece(&b).expect("a kept box meets the shape");
            for (d, x) in piece.d.iter().zip(&b) {
                assert_eq!(d.lo().to_bits(), x.lo().to_bits(), "case {case}");
                assert_eq!(d.hi().to_bits(), x.hi().to_bits(), "case {case}");
            }
            for corner in 0..(1usize << dim) {
                let p: Vec<Interval> = (0..dim)
                    .map(|a| {
                        let v = if corner >> a & 1 == 0 {
                            b[a].lo()
                        } else {
                            b[a].hi()
                        };
                        Interval::new(v, v)
                    })
                    .collect();
                assert!(
                    s.contract_piece(&p).is_some(),
                    "case {case} corner {corner}"
                );
            }
        }
        assert!(kept > 100, "{kept} of {cases}");
    }

    fn b2(x0: f64, x1: f64, y0: f64, y1: f64) -> IntervalBox {
        IntervalBox::new(&[Interval::new(x0, x1), Interval::new(y0, y1)])
    }

    fn annulus(cx: f64, cy: f64, e: f64, r0: f64, r1: f64) -> Shape {
        Shape::new(
            b2(cx - e, cx + e, cy - e, cy + e),
            Interval::new(r0, r1),
            None,
            IntervalBox::entire(2),
        )
    }

    #[test]
    fn nested_annuli_are_disjoint_crossing_ones_are_not() {
        // Same centre ±0.5, radii [5, 6] and [8, 9]: the hole of the second
        // holds the first (6 + 1.42 < 8).
        assert!(annulus(0.0, 0.0, 0.5, 5.0, 6.0).disjoint(&annulus(0.0, 0.0, 0.5, 8.0, 9.0)));
        // Far apart.
        assert!(annulus(0.0, 0.0, 0.5, 5.0, 6.0).disjoint(&annulus(20.0, 0.0, 0.5, 5.0, 6.0)));
        // Crossing circles.
        assert!(!annulus(0.0, 0.0, 0.5, 5.0, 6.0).disjoint(&annulus(8.0, 0.0, 0.5, 5.0, 6.0)));
    }

    #[test]
    fn a_box_in_the_hole_is_excluded() {
        let a = annulus(0.0, 0.0, 0.1, 5.0, 6.0);
        assert!(!a.meets_box(b2(-1.0, 1.0, -1.0, 1.0).axes()));
        assert!(a.meets_box(b2(4.0, 7.0, -1.0, 1.0).axes()));
        assert!(!a.meets_box(b2(7.0, 8.0, 7.0, 8.0).axes()));
    }

    /// The cosine and sine kept with a shape stand for those of
    /// its bearing only: a bearing changed after a contraction gives the
    /// pieces of a shape made with the new bearing, and the same shape
    /// gives the same bits at every contraction.
    #[test]
    fn a_changed_bearing_is_not_read_with_the_old_cosine() {
        let port = Shape::new(
            b2(-0.1, 0.1, -0.1, 0.1),
            Interval::new(4.9, 5.1),
            Some((Interval::ZERO, Interval::new(1.4, 1.7))),
            IntervalBox::entire(2),
        );
        let all = IntervalBox::entire(2);
        let first = port.contract_piece(all.axes()).expect("meets");
        assert_eq!(port.contract_piece(all.axes()), Some(first));
        let mut turned = port.clone();
        turned.bearing = Some((Interval::ZERO, Interval::new(-1.7, -1.4)));
        let fresh = Shape::new(
            b2(-0.1, 0.1, -0.1, 0.1),
            Interval::new(4.9, 5.1),
            Some((Interval::ZERO, Interval::new(-1.7, -1.4))),
            IntervalBox::entire(2),
        );
        let piece = turned.contract_piece(all.axes()).expect("meets");
        assert_eq!(Some(piece), fresh.contract_piece(all.axes()));
        // Starboard: the landmark is south of the robot, not north.
        assert!(
            piece.d[1].hi() < 0.0 && first.d[1].lo() > 0.0,
            "{piece:?} {first:?}"
        );
    }

    #[test]
    fn sectors_on_opposite_sides_are_disjoint_by_bisection() {
        // Robot at the origin heading east; one landmark to port (β ≈ pi/2),
        // one to starboard, same range: the annuli coincide, the sectors
        // do not.
        let port = Shape::new(
            b2(-0.1, 0.1, -0.1, 0.1),
            Interval::new(4.9, 5.1),
            Some((Interval::ZERO, Interval::new(1.4, 1.7))),
            IntervalBox::entire(2),
        );
        let mut starboard = port.clone();
        starboard.bearing = Some((Interval::ZERO, Interval::new(-1.7, -1.4)));
        let (port, starboard) = (
            Shape {
                cut: port.hull(),
                ..port
            },
            Shape {
                cut: starboard.hull(),
                ..starboard
            },
        );
        assert!(!port.disjoint(&starboard) || !port.cut.meets(&starboard.cut));
        assert!(disjoint_paved(&port, &starboard, 64));
    }

    /// Regression: an empty centre box (an unbounded displacement made the
    /// displacement sums empty) made every pair "disjoint". An empty shape
    /// proves nothing; an unbounded centre box meets everything.
    #[test]
    fn issue_19_an_empty_or_unbounded_shape_proves_no_disjointness() {
        let far = annulus(100.0, 0.0, 0.5, 5.0, 6.0);
        let mut empty = annulus(0.0, 0.0, 0.5, 5.0, 6.0);
        assert!(empty.disjoint(&far));
        empty.centre = IntervalBox::empty(2);
        assert!(!empty.disjoint(&far) && !far.disjoint(&empty));
        assert!(!disjoint_paved(&empty, &far, 64) && !disjoint_paved(&far, &empty, 64));
        let mut cut = annulus(0.0, 0.0, 0.5, 5.0, 6.0);
        cut.cut = IntervalBox::empty(2);
        assert!(!cut.disjoint(&far) && !far.disjoint(&cut));
        let unbounded = Shape::new(
            IntervalBox::entire(2),
            Interval::new(5.0, 6.0),
            None,
            IntervalBox::entire(2),
        );
        assert!(!unbounded.disjoint(&far) && !far.disjoint(&unbounded));
        let huge = Shape::new(
            b2(-f64::MAX, f64::MAX, -f64::MAX, f64::MAX),
            Interval::new(0.0, f64::INFINITY),
            None,
            IntervalBox::entire(2),
        );
        assert!(!huge.disjoint(&far) && !disjoint_paved(&huge, &far, 64));
    }
}
