//! Closed intervals of `f64` with outward rounding.
//!
//! Every operation returns an enclosure of the exact real result: each bound
//! computed with a rounded floating-point operation is moved one ulp outwards
//! (`f64::next_down` for lower bounds, `f64::next_up` for upper bounds), which
//! is sound whatever the rounding mode of the platform (wasm32 cannot set it)
//! because IEEE-754 basic operations are correctly rounded, hence within one
//! ulp. Transcendental functions come from `libm` (within one ulp in practice)
//! and are widened by two ulps and clamped to their mathematical range.
//!
//! The empty interval is a value (`lo = +inf, hi = -inf`); a NaN bound is
//! never produced. Unbounded intervals use infinite bounds; `[+inf, +inf]`
//! and `[-inf, -inf]` are not intervals (real numbers only) and constructors
//! turn them into the empty interval.

// Inherent `add`, `mul`, ... are kept beside the operator traits so that
// interval code can be written in method-chain form.
#![allow(clippy::should_implement_trait)]

use std::fmt;

/// A closed interval `[lo, hi]` of real numbers, possibly unbounded, or empty.
///
/// Invariant: either `lo <= hi`, `lo < +inf`, `hi > -inf` and neither is NaN,
/// or the interval is empty (`lo = +inf`, `hi = -inf`).
#[derive(Clone, Copy, PartialEq)]
pub struct Interval {
    lo: f64,
    hi: f64,
}

#[inline]
fn down(x: f64) -> f64 {
    x.next_down()
}

#[inline]
fn up(x: f64) -> f64 {
    x.next_up()
}

/// `x.next_down()` for non-NaN `x` in a few integer operations, except
/// that `-inf` gives NaN (callers take `max` with a real bound, which
/// ignores it, as it would ignore `-inf`). For hot loops.
#[inline]
pub(crate) fn pred(x: f64) -> f64 {
    let b = x.to_bits() as i64;
    let b = if b == 0 { i64::MIN } else { b }; // +0 as -0
    f64::from_bits((if b > 0 { b - 1 } else { b + 1 }) as u64)
}

/// `x.next_up()` for non-NaN `x`, except that `+inf` gives NaN (see
/// [`pred`]).
#[inline]
pub(crate) fn succ(x: f64) -> f64 {
    let b = x.to_bits() as i64;
    let b = if b == i64::MIN { 0 } else { b }; // -0 as +0
    f64::from_bits((if b >= 0 { b + 1 } else { b - 1 }) as u64)
}

/// Error of the rounded sum `s = fl(a + b)`: `a + b = s + err` exactly
/// (Knuth's TwoSum), valid when `s` is finite.
#[inline]
fn two_sum_err(a: f64, b: f64, s: f64) -> f64 {
    let bb = s - a;
    (a - (s - bb)) + (b - bb)
}

/// A lower bound of the exact `a + b`: the rounded sum when it is exact or
/// rounded down, one ulp lower otherwise.
#[inline]
fn add_down(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s.is_finite() && two_sum_err(a, b, s) >= 0.0 {
        s
    } else {
        down(s)
    }
}

/// An upper bound of the exact `a + b` (see [`add_down`]).
#[inline]
fn add_up(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s.is_finite() && two_sum_err(a, b, s) <= 0.0 {
        s
    } else {
        up(s)
    }
}

/// `a / b` for `b >= 0` (`b = 0` standing for 0+, `b` may be +inf) when
/// it is an exact limit: an infinite `a` stays, `0 / b` and `a / +inf` are 0,
/// `a / 0+` is the infinity of `a`'s sign. `None` when it must be rounded.
#[inline]
fn div_limit(a: f64, b: f64) -> Option<f64> {
    if a.is_infinite() {
        Some(a)
    } else if a == 0.0 || b == f64::INFINITY {
        Some(0.0)
    } else if b == 0.0 {
        Some(f64::INFINITY.copysign(a))
    } else {
        None
    }
}

/// `a / b` rounded down, for `b >= 0` (see [`div_limit`]): the exact limit,
/// else the rounded quotient moved one ulp down.
#[inline]
fn div_down(a: f64, b: f64) -> f64 {
    div_limit(a, b).unwrap_or_else(|| down(a / b))
}

/// `a / b` rounded up, for `b >= 0` (see [`div_down`]).
#[inline]
fn div_up(a: f64, b: f64) -> f64 {
    div_limit(a, b).unwrap_or_else(|| up(a / b))
}

/// `a * b` with `0 * inf = 0` (the product of bounds of intervals, where a
/// zero bound times an infinite one contributes 0 to the hull).
#[inline]
fn mul0(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        a * b
    }
}

impl Interval {
    /// The empty interval.
    pub const EMPTY: Interval = Interval {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
    /// The whole real line `(-inf, +inf)`.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };
    /// `[0, 0]`.
    pub const ZERO: Interval = Interval { lo: 0.0, hi: 0.0 };

    /// `[lo, hi]`; empty when `lo > hi`, when a bound is NaN, or when the
    /// interval would hold no real number (`[inf, inf]`).
    /// Tightness: exact.
    #[inline]
    pub fn new(lo: f64, hi: f64) -> Interval {
        if lo <= hi && lo < f64::INFINITY && hi > f64::NEG_INFINITY {
            Interval { lo, hi }
        } else {
            Interval::EMPTY
        }
    }

    /// `[lo, hi]` for bounds known to satisfy the invariant (`lo <= hi`,
    /// `lo < +inf`, `hi > -inf`, no NaN), without checking them.
    #[inline]
    pub(crate) const fn new_unchecked(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    /// The degenerate interval `[x, x]` (empty for a non-finite `x`).
    #[inline]
    pub fn point(x: f64) -> Interval {
        Interval::new(x, x)
    }

    /// `[x - r, x + r]` rounded outwards, for `r >= 0` (a measurement with a
    /// symmetric error bound). Tightness: within one ulp per bound.
    #[inline]
    pub fn centered(x: f64, r: f64) -> Interval {
        if r.is_nan() || r < 0.0 {
            return Interval::EMPTY;
        }
        if r == 0.0 {
            return Interval::point(x);
        }
        Interval::new(add_down(x, -r), add_up(x, r))
    }

    /// Lower bound (`+inf` when empty).
    #[inline]
    pub fn lo(self) -> f64 {
        self.lo
    }

    /// Upper bound (`-inf` when empty).
    #[inline]
    pub fn hi(self) -> f64 {
        self.hi
    }

    /// Whether the interval holds no real number.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.lo > self.hi
    }

    /// Whether both bounds are finite (the empty interval is bounded).
    #[inline]
    pub fn is_bounded(self) -> bool {
        self.is_empty() || (self.lo.is_finite() && self.hi.is_finite())
    }

    /// Whether `x` lies in the interval.
    #[inline]
    pub fn contains(self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// Whether `self` is a subset of `other` (the empty set is a subset of all).
    #[inline]
    pub fn is_subset(self, other: Interval) -> bool {
        self.is_empty() || (other.lo <= self.lo && self.hi <= other.hi)
    }

    /// Whether the two intervals share a point.
    #[inline]
    pub fn meets(self, other: Interval) -> bool {
        self.lo.max(other.lo) <= self.hi.min(other.hi)
    }

    /// Intersection. Tightness: exact.
    ///
    /// Only `lo <= hi` is checked: with both operands intervals (or empty),
    /// the other tests of [`Interval::new`] follow from it (a `+inf` lower
    /// bound or a `-inf` upper one comes from an empty operand, whose other
    /// bound then fails `lo <= hi`; max and min of non-NaN bounds are not
    /// NaN), so the result is the same.
    #[inline]
    pub fn intersect(self, other: Interval) -> Interval {
        let (lo, hi) = (self.lo.max(other.lo), self.hi.min(other.hi));
        if lo <= hi {
            Interval::new_unchecked(lo, hi)
        } else {
            Interval::EMPTY
        }
    }

    /// Interval hull of the union. Tightness: exact.
    #[inline]
    pub fn hull(self, other: Interval) -> Interval {
        if self.is_empty() {
            return other;
        }
        if other.is_empty() {
            return self;
        }
        Interval {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    /// Width `hi - lo`, rounded up; 0 for the empty interval, `+inf` when
    /// unbounded. An upper bound of the exact width.
    #[inline]
    pub fn width(self) -> f64 {
        if self.is_empty() || self.lo == self.hi {
            0.0
        } else {
            add_up(self.hi, -self.lo)
        }
    }

    /// A point of the interval near its middle (0 for the entire line, a
    /// finite point for a half-line, NaN only for the empty interval).
    #[inline]
    pub fn mid(self) -> f64 {
        if self.is_empty() {
            return f64::NAN;
        }
        match (self.lo.is_finite(), self.hi.is_finite()) {
            (true, true) => {
                let m = self.lo * 0.5 + self.hi * 0.5;
                m.clamp(self.lo, self.hi)
            }
            (false, false) => 0.0,
            (true, false) => if self.lo >= 0.0 {
                self.lo * 2.0 + 1.0
            } else {
                0.0
            }
            .min(f64::MAX),
            (false, true) => if self.hi <= 0.0 {
                self.hi * 2.0 - 1.0
            } else {
                0.0
            }
            .max(f64::MIN),
        }
    }

    /// Magnitude `max |x|` over the interval (0 when empty).
    #[inline]
    pub fn mag(self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            self.lo.abs().max(self.hi.abs())
        }
    }

    /// Negation. Tightness: exact.
    #[inline]
    pub fn neg(self) -> Interval {
        if self.is_empty() {
            self
        } else {
            Interval {
                lo: -self.hi,
                hi: -self.lo,
            }
        }
    }

    /// Absolute value `{|x|}`. Tightness: exact.
    #[inline]
    pub fn abs(self) -> Interval {
        if self.is_empty() || self.lo >= 0.0 {
            self
        } else if self.hi <= 0.0 {
            self.neg()
        } else {
            Interval {
                lo: 0.0,
                hi: (-self.lo).max(self.hi),
            }
        }
    }

    /// Sum. Tightness: tightest (a bound moves one ulp out only when the
    /// rounded sum is inexact on the wrong side, detected by TwoSum).
    ///
    /// The bounds need no check: of two intervals, the lower bounds are
    /// below `+inf` and the upper ones above `-inf`, so no sum is NaN;
    /// `add_down` rounds an exact sum down (an overflow to `+inf` down to
    /// `f64::MAX`) and `add_up` up, so `lo <= hi`, `lo < +inf` and
    /// `hi > -inf` hold.
    #[inline]
    pub fn add(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() {
            return Interval::EMPTY;
        }
        Interval::new_unchecked(add_down(self.lo, other.lo), add_up(self.hi, other.hi))
    }

    /// Difference. Tightness: tightest (see [`Interval::add`]; `-other`
    /// is an interval, so the bounds need no check either).
    #[inline]
    pub fn sub(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() {
            return Interval::EMPTY;
        }
        Interval::new_unchecked(add_down(self.lo, -other.hi), add_up(self.hi, -other.lo))
    }

    /// Sum widened unconditionally by one ulp per bound: an enclosure like
    /// [`Interval::add`] (the rounded sum is within one ulp of the exact one),
    /// at most one ulp looser per bound, and branch-free, for hot loops that
    /// add millions of intervals (the motion sweeps).
    #[inline]
    pub fn add_outward(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() {
            return Interval::EMPTY;
        }
        Interval::new(down(self.lo + other.lo), up(self.hi + other.hi))
    }

    /// Difference widened unconditionally by one ulp per bound (see
    /// [`Interval::add_outward`]).
    #[inline]
    pub fn sub_outward(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() {
            return Interval::EMPTY;
        }
        Interval::new(down(self.lo - other.hi), up(self.hi - other.lo))
    }

    /// Product. Tightness: within one ulp per bound.
    #[inline]
    pub fn mul(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() {
            return Interval::EMPTY;
        }
        let p = [
            mul0(self.lo, other.lo),
            mul0(self.lo, other.hi),
            mul0(self.hi, other.lo),
            mul0(self.hi, other.hi),
        ];
        let lo = p[0].min(p[1]).min(p[2]).min(p[3]);
        let hi = p[0].max(p[1]).max(p[2]).max(p[3]);
        Interval::new(down(lo), up(hi))
    }

    /// Product by a scalar. Tightness: within one ulp per bound.
    #[inline]
    pub fn scale(self, k: f64) -> Interval {
        self.mul(Interval::point(k))
    }

    /// Quotient `{x / y : x in self, y in other, y != 0}`, enclosed in one
    /// interval (the hull of the two pieces when `other` straddles 0).
    /// Each bound is one quotient of a bound of `self` by a bound of
    /// `other`, chosen by the signs, rounded once: tightness within one ulp
    /// per bound (checked against inari's tightest enclosures).
    pub fn div(self, other: Interval) -> Interval {
        if self.is_empty() || other.is_empty() || (other.lo == 0.0 && other.hi == 0.0) {
            return Interval::EMPTY;
        }
        if other.lo >= 0.0 {
            return self.div_positive(other);
        }
        if other.hi <= 0.0 {
            // x / y = (-x) / (-y), with -y > 0 or -y = [0, h].
            return self.neg().div_positive(other.neg());
        }
        // 0 inside other.
        if self.lo == 0.0 && self.hi == 0.0 {
            Interval::ZERO
        } else {
            Interval::ENTIRE
        }
    }

    /// `self / y` for `y = [l, h]` with `l > 0`, or `y = [0, h]` with
    /// `h > 0` (then the quotient is over (0, h]).
    fn div_positive(self, y: Interval) -> Interval {
        let lo = if self.lo >= 0.0 {
            div_down(self.lo, y.hi)
        } else {
            div_down(self.lo, y.lo)
        };
        let hi = if self.hi <= 0.0 {
            div_up(self.hi, y.hi)
        } else {
            div_up(self.hi, y.lo)
        };
        Interval::new(lo, hi)
    }

    /// Reciprocal `1 / x` for an interval not containing 0 (empty or entire
    /// otherwise, see [`Interval::div`]). Tightness: within one ulp per bound.
    #[inline]
    pub fn recip(self) -> Interval {
        if self.is_empty() {
            return self;
        }
        if self.lo > 0.0 || self.hi < 0.0 {
            let lo = if self.hi.is_infinite() {
                0.0
            } else {
                down(1.0 / self.hi)
            };
            let hi = if self.lo.is_infinite() {
                0.0
            } else {
                up(1.0 / self.lo)
            };
            return Interval::new(lo, hi);
        }
        Interval::point(1.0).div(self)
    }

    /// Square `{x^2}`. Tightness: within one ulp per bound.
    #[inline]
    pub fn sqr(self) -> Interval {
        if self.is_empty() {
            return self;
        }
        let a = self.abs();
        let lo = if a.lo == 0.0 {
            0.0
        } else {
            down(a.lo * a.lo).max(0.0)
        };
        Interval::new(lo, up(a.hi * a.hi))
    }

    /// Square root of the non-negative part (empty when `self < 0`).
    /// Tightness: within one ulp per bound.
    #[inline]
    pub fn sqrt(self) -> Interval {
        let x = self.intersect(Interval::new(0.0, f64::INFINITY));
        if x.is_empty() {
            return x;
        }
        let lo = if x.lo == 0.0 {
            0.0
        } else {
            down(libm::sqrt(x.lo)).max(0.0)
        };
        Interval::new(lo, up(libm::sqrt(x.hi)))
    }

    /// Cosine. Tightness: within three ulps per bound, or `[-1, 1]`.
    pub fn cos(self) -> Interval {
        if self.is_empty() {
            return self;
        }
        // cos reaches +1 at 2k*pi and -1 at (2k+1)*pi.
        trig(self, libm::cos, 0.0)
    }

    /// `(self.cos(), self.sin())`, the same bits, each bound's cosine and
    /// sine made by one `libm::sincos` (one argument reduction for both).
    /// `sincos` runs the kernels of `sin` and `cos` on the same reduced
    /// argument, so it gives their bits, except below 2^-26 in magnitude,
    /// where `sin` returns x and `sincos` its kernel: such bounds take
    /// `sin` and `cos` themselves. The browser's build takes `cos` and
    /// `sin` (the same bits, without `sincos`'s code in its transfer).
    pub fn cos_sin(self) -> (Interval, Interval) {
        if cfg!(target_arch = "wasm32") {
            return (self.cos(), self.sin());
        }
        if self.is_empty() {
            return (self, self);
        }
        if !trig_in_range(self) {
            return (TRIG_FULL, TRIG_FULL);
        }
        let both = |x: f64| {
            if libm::fabs(x) < 1e-7 {
                (libm::sin(x), libm::cos(x))
            } else {
                libm::sincos(x)
            }
        };
        let ((s_lo, c_lo), (s_hi, c_hi)) = (both(self.lo), both(self.hi));
        (
            trig_bounds(self, c_lo, c_hi, 0.0),
            trig_bounds(self, s_lo, s_hi, 0.5),
        )
    }

    /// Sine. Tightness: within three ulps per bound, or `[-1, 1]`.
    pub fn sin(self) -> Interval {
        if self.is_empty() {
            return self;
        }
        // sin reaches +1 at pi/2 + 2k*pi and -1 at -pi/2 + 2k*pi.
        trig(self, libm::sin, 0.5)
    }

    // ----- backward projections (HC4Revise) ---------------------------------

    /// Backward projection of `z = x + y`: returns the contracted `(x, y)`,
    /// `x ∩ (z - y)` and `y ∩ (z - x)`. Sound: any `(x, y)` with `x + y` in
    /// `z` is kept. Tightness: within one ulp per bound.
    #[inline]
    pub fn add_rev(z: Interval, x: Interval, y: Interval) -> (Interval, Interval) {
        let x2 = x.intersect(z.sub(y));
        let y2 = y.intersect(z.sub(x2));
        (x2, y2)
    }

    /// Backward projection of `z = x - y`: contracted `(x, y)`.
    #[inline]
    pub fn sub_rev(z: Interval, x: Interval, y: Interval) -> (Interval, Interval) {
        let x2 = x.intersect(z.add(y));
        let y2 = y.intersect(x2.sub(z));
        (x2, y2)
    }

    /// Backward projection of `z = x * y`: contracted `(x, y)`, using the
    /// relational division (only when the divisor does not hold 0, which
    /// keeps it a single interval; otherwise the factor is kept).
    pub fn mul_rev(z: Interval, x: Interval, y: Interval) -> (Interval, Interval) {
        if z.is_empty() || x.is_empty() || y.is_empty() {
            return (Interval::EMPTY, Interval::EMPTY);
        }
        let x2 = if y.contains(0.0) {
            if z.contains(0.0) {
                x
            } else {
                // y must be non-zero; x = z / y over y\{0} (hull of two parts).
                x.intersect(z.div(y))
            }
        } else {
            x.intersect(z.div(y))
        };
        let y2 = if x2.contains(0.0) {
            if z.contains(0.0) {
                y
            } else {
                y.intersect(z.div(x2))
            }
        } else {
            y.intersect(z.div(x2))
        };
        if x2.is_empty() || y2.is_empty() {
            return (Interval::EMPTY, Interval::EMPTY);
        }
        (x2, y2)
    }

    /// Backward projection of `z = x^2`: contracted `x`, the hull of
    /// `x ∩ [sqrt z]` and `x ∩ [-sqrt z]`. Sound and, up to rounding, the
    /// tightest single interval.
    #[inline]
    pub fn sqr_rev(z: Interval, x: Interval) -> Interval {
        let r = z.sqrt();
        if r.is_empty() {
            return Interval::EMPTY;
        }
        x.intersect(r).hull(x.intersect(r.neg()))
    }
}

/// Sound enclosure of `f(x)` for `f` = sin or cos; `phase` = 0 for cos
/// (maxima at 2k*pi), 0.5 for sin (maxima at (2k + 1/2)*pi).
fn trig(x: Interval, f: fn(f64) -> f64, phase: f64) -> Interval {
    if !trig_in_range(x) {
        return TRIG_FULL;
    }
    trig_bounds(x, f(x.lo), f(x.hi), phase)
}

/// [-1, 1].
const TRIG_FULL: Interval = Interval { lo: -1.0, hi: 1.0 };

/// Whether [`trig`] searches the extrema of `x` (else it answers [-1, 1]).
/// Beyond this, libm's argument reduction is still exact, but we keep the
/// extremum search in a range where k*pi is well separated in f64.
fn trig_in_range(x: Interval) -> bool {
    x.lo.is_finite() && x.hi.is_finite() && x.hi - x.lo < 6.0 && x.mag() <= 1e8
}

/// [`trig`] given `a = f(x.lo)` and `b = f(x.hi)`, for `x` in range
/// ([`trig_in_range`]).
fn trig_bounds(x: Interval, a: f64, b: f64, phase: f64) -> Interval {
    let mut lo = down(down(down(a.min(b))));
    let mut hi = up(up(up(a.max(b))));
    // Extrema: f = +1 at (2k + phase)*pi, f = -1 at (2k + 1 + phase)*pi.
    // Positions t = x/pi - phase; an integer t in [t_lo, t_hi] is an
    // extremum (even: max, odd: min). The search range is widened by a
    // relative slack larger than any rounding error of x/pi, so an extremum
    // can only be included wrongly (loosening), never missed.
    let inv_pi = 1.0 / std::f64::consts::PI;
    let slack = 1e-12 * (1.0 + x.mag());
    let t_lo = (x.lo * inv_pi - phase - slack).ceil();
    let t_hi = (x.hi * inv_pi - phase + slack).floor();
    let mut t = t_lo;
    while t <= t_hi {
        if (t as i64).rem_euclid(2) == 0 {
            hi = 1.0;
        } else {
            lo = -1.0;
        }
        t += 1.0;
        if t - t_lo > 4.0 {
            break;
        }
    }
    Interval::new(lo.max(-1.0), hi.min(1.0))
}

impl Default for Interval {
    fn default() -> Self {
        Interval::ENTIRE
    }
}

impl fmt::Debug for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            write!(f, "[empty]")
        } else {
            write!(f, "[{:?}, {:?}]", self.lo, self.hi)
        }
    }
}

impl fmt::Display for Interval {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_empty() {
            write!(f, "empty")
        } else {
            write!(f, "[{}, {}]", Bound(self.lo), Bound(self.hi))
        }
    }
}

/// A bound in a message: as `f64`'s Display (shortest round-trip digits),
/// but with an exponent beyond 1e15 and below 1e-6, where Display writes
/// every digit (1e308 was 309 characters).
struct Bound(f64);

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x.is_finite() && x != 0.0 && !(1e-6..1e15).contains(&x.abs()) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

macro_rules! bin_op {
    ($tr:ident, $m:ident, $f:ident) => {
        impl std::ops::$tr for Interval {
            type Output = Interval;
            #[inline]
            fn $m(self, rhs: Interval) -> Interval {
                Interval::$f(self, rhs)
            }
        }
    };
}
bin_op!(Add, add, add);
bin_op!(Sub, sub, sub);
bin_op!(Mul, mul, mul);
bin_op!(Div, div, div);

impl std::ops::Neg for Interval {
    type Output = Interval;
    #[inline]
    fn neg(self) -> Interval {
        Interval::neg(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `cos_sin` gives the bits of `cos` and `sin` on narrow and wide
    /// intervals, bounds near 0 (on both sides of 2^-26 and 2^-27·√2), near
    /// the kernels' limit π/4, around multiples of π/2, large, unbounded
    /// and empty.
    #[test]
    fn cos_sin_is_cos_and_sin_bit_for_bit() {
        let bits = |x: Interval| (x.lo().to_bits(), x.hi().to_bits());
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut points = vec![
            0.0,
            -0.0,
            1e-300,
            1.4e-8,
            1.5e-8,
            1.05e-8,
            1e-7,
            std::f64::consts::FRAC_PI_4,
            0.79,
        ];
        for k in -8..=8 {
            points.push(k as f64 * std::f64::consts::FRAC_PI_2);
        }
        for _ in 0..200_000 {
            let scale = [1e-9, 1e-7, 1.0, 10.0, 1e6][(next() * 5.0) as usize % 5];
            points.push((next() * 2.0 - 1.0) * scale);
        }
        let mut cases = vec![Interval::ENTIRE, Interval::EMPTY, Interval::new(0.0, 1e9)];
        for w in points.windows(2) {
            let x = w[0];
            cases.push(Interval::point(x));
            cases.push(Interval::new(x, x + 0.2 * next()));
            cases.push(Interval::new(x.min(w[1]), x.max(w[1])));
            cases.push(Interval::new(-x.abs(), x.abs()));
        }
        for x in cases {
            let (c, s) = x.cos_sin();
            assert_eq!(bits(c), bits(x.cos()), "cos {x:?}");
            assert_eq!(bits(s), bits(x.sin()), "sin {x:?}");
        }
    }

    /// Messages name intervals: huge and tiny bounds with an exponent (1e308
    /// was written with all its 309 digits), others as before.
    #[test]
    fn display_is_short_at_the_extremes() {
        assert_eq!(Interval::new(0.5, 2.0).to_string(), "[0.5, 2]");
        assert_eq!(Interval::new(4.9, 5.3).to_string(), "[4.9, 5.3]");
        assert_eq!(
            Interval::new(1e308, f64::INFINITY).to_string(),
            "[1e308, inf]"
        );
        assert_eq!(
            Interval::new(-1.7e308, -1e15).to_string(),
            "[-1.7e308, -1e15]"
        );
        assert_eq!(Interval::new(-1e-7, 0.0).to_string(), "[-1e-7, 0]");
        assert_eq!(
            Interval::new(123456.0, 1e14).to_string(),
            "[123456, 100000000000000]"
        );
        assert_eq!(Interval::EMPTY.to_string(), "empty");
    }

    #[test]
    fn constructors_reject_non_intervals() {
        assert!(Interval::new(2.0, 1.0).is_empty());
        assert!(Interval::new(f64::NAN, 1.0).is_empty());
        assert!(Interval::new(f64::INFINITY, f64::INFINITY).is_empty());
        assert!(!Interval::new(f64::NEG_INFINITY, f64::INFINITY).is_empty());
    }

    #[test]
    fn add_rounds_outwards() {
        let x = Interval::point(0.1) + Interval::point(0.2);
        assert!(x.lo() < 0.30000000000000004 && x.hi() >= 0.30000000000000004);
        assert!(x.lo() <= 0.3);
    }

    #[test]
    fn mul_zero_times_infinity() {
        let x = Interval::new(0.0, 1.0) * Interval::new(2.0, f64::INFINITY);
        assert_eq!(x.lo(), 0.0f64.next_down());
        assert_eq!(x.hi(), f64::INFINITY);
        assert!(!x.is_empty());
    }

    #[test]
    fn div_by_interval_touching_zero() {
        let x = Interval::new(1.0, 2.0) / Interval::new(0.0, 4.0);
        assert!(x.contains(0.25) && x.contains(1e300) && !x.contains(0.2));
        let y = Interval::new(1.0, 2.0) / Interval::new(-4.0, 0.0);
        assert!(y.contains(-0.25) && y.contains(-1e300) && !y.contains(-0.2));
        assert!((Interval::new(1.0, 2.0) / Interval::ZERO).is_empty());
        assert_eq!(
            Interval::new(1.0, 2.0) / Interval::new(-1.0, 1.0),
            Interval::ENTIRE
        );
    }

    #[test]
    fn cos_finds_extrema() {
        let c = Interval::new(-0.1, 0.1).cos();
        assert_eq!(c.hi(), 1.0);
        let c = Interval::new(3.0, 3.2).cos();
        assert_eq!(c.lo(), -1.0);
        let s = Interval::new(1.5, 1.6).sin();
        assert_eq!(s.hi(), 1.0);
        let s = Interval::new(0.1, 0.2).sin();
        assert!(s.contains(libm::sin(0.1)) && s.contains(libm::sin(0.2)) && s.hi() < 0.3);
    }

    #[test]
    fn sqr_rev_keeps_both_signs() {
        let x = Interval::sqr_rev(Interval::new(4.0, 9.0), Interval::new(-10.0, 10.0));
        assert!(x.contains(-3.0) && x.contains(3.0) && x.contains(-2.0));
        let x = Interval::sqr_rev(Interval::new(4.0, 9.0), Interval::new(0.0, 10.0));
        assert!(x.lo() > 1.99 && x.hi() < 3.01);
        assert!(Interval::sqr_rev(Interval::new(-2.0, -1.0), Interval::ENTIRE).is_empty());
    }

    #[test]
    fn pred_and_succ_are_next_down_and_next_up() {
        let mut xs = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::from_bits(1),
            -f64::from_bits(1),
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1.0,
            -1.0,
        ];
        let mut seed = 7u64;
        for _ in 0..100_000 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = f64::from_bits(seed);
            if !x.is_nan() {
                xs.push(x);
            }
        }
        for x in xs {
            let (p, s) = (pred(x), succ(x));
            if x == f64::NEG_INFINITY {
                assert!(p.is_nan());
            } else {
                assert_eq!(p.to_bits(), x.next_down().to_bits(), "pred({x:e})");
            }
            if x == f64::INFINITY {
                assert!(s.is_nan());
            } else {
                assert_eq!(s.to_bits(), x.next_up().to_bits(), "succ({x:e})");
            }
        }
    }
}
