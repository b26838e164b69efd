//! Containment of every interval operation, checked against exact rational
//! arithmetic (num-rational over big integers): points are drawn inside the
//! input intervals, the exact real result is computed independently of the
//! floating-point code, and it must lie in the computed interval.
//!
//! Exact rationals are the oracle of containment for + - * / sqr sqrt (no
//! rounding at all) and a rigorous Taylor enclosure serves for sin and cos.
//! In a build with `-C target-cpu=haswell` the module `inari_reference`
//! also checks every arithmetic operation against inari's tightest
//! enclosures (containment and the promised tightness).
//!
//! Case count: `PROPTEST_CASES` (default 4000 per property); seeds and
//! persisted failures: tests/common/mod.rs (`config`).

use num_rational::BigRational;
use num_traits::{One, Signed};
use nvector_core::Interval;
use proptest::prelude::*;

mod common;
use common::{ceil_f64, floor_f64, holds, rat, taylor};

/// Default 4000 cases per property (`PROPTEST_CASES` changes it).
fn config() -> ProptestConfig {
    common::config(4000)
}

/// The trigonometric oracle sums big-rational Taylor series, about a
/// hundred times slower than the others: fewer cases for those.
fn trig_config() -> ProptestConfig {
    common::config_div(4000, 10, 50)
}

/// Finite f64 of every magnitude: small integers, ordinary values, tiny and
/// huge ones, near overflow, and signed zeros.
fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-20i32..20).prop_map(f64::from),
        -1e3..1e3f64,
        (-1.0..1.0f64, -300i32..300).prop_map(|(m, e)| m * libm::pow(10.0, f64::from(e))),
        (0.5..1.0f64).prop_map(|m| m * f64::MAX),
        (-1.0..-0.5f64).prop_map(|m| m * f64::MAX),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
    ]
}

/// A bounded interval with a point inside it.
fn interval_and_point() -> impl Strategy<Value = (Interval, f64)> {
    (finite(), finite(), 0.0..=1.0f64, 0u8..4).prop_map(|(a, b, t, pick)| {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        let x = match pick {
            0 => lo,
            1 => hi,
            _ => {
                let p = lo + t * (hi - lo);
                if p.is_finite() {
                    p.clamp(lo, hi)
                } else {
                    lo * (1.0 - t) + hi * t
                }
            }
        };
        let x = if x.is_finite() { x.clamp(lo, hi) } else { lo };
        (Interval::new(lo, hi), x)
    })
}

/// An interval, possibly unbounded on one or both sides, with a finite point.
fn any_interval_and_point() -> impl Strategy<Value = (Interval, f64)> {
    (interval_and_point(), 0u8..6).prop_map(|((x, p), open)| {
        let x = match open {
            0 => Interval::new(f64::NEG_INFINITY, x.hi()),
            1 => Interval::new(x.lo(), f64::INFINITY),
            2 => Interval::ENTIRE,
            _ => x,
        };
        (x, p)
    })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn add_contains((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        let z = x + y;
        prop_assert!(holds(z, &(rat(a) + rat(b))), "{:?} + {:?} = {:?} misses {} + {}", x, y, z, a, b);
    }

    /// `Interval::add` and `Interval::sub` are documented tightest: each
    /// bound is the nearest f64 on its side of the exact sum (difference)
    /// of the operands' bounds, so an exact sum comes back unwidened.
    #[test]
    fn add_and_sub_are_tightest((x, _a) in any_interval_and_point(), (y, _b) in any_interval_and_point()) {
        let inf = f64::INFINITY;
        let lo = |u: f64, v: f64| if u == -inf || v == -inf { -inf } else { floor_f64(&(rat(u) + rat(v))) };
        let hi = |u: f64, v: f64| if u == inf || v == inf { inf } else { ceil_f64(&(rat(u) + rat(v))) };
        let s = x + y;
        prop_assert!(s.lo() == lo(x.lo(), y.lo()) && s.hi() == hi(x.hi(), y.hi()),
            "{:?} + {:?} = {:?}, tightest [{:e}, {:e}]", x, y, s, lo(x.lo(), y.lo()), hi(x.hi(), y.hi()));
        let d = x - y;
        prop_assert!(d.lo() == lo(x.lo(), -y.hi()) && d.hi() == hi(x.hi(), -y.lo()),
            "{:?} - {:?} = {:?}, tightest [{:e}, {:e}]", x, y, d, lo(x.lo(), -y.hi()), hi(x.hi(), -y.lo()));
    }

    #[test]
    fn sub_contains((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        let z = x - y;
        prop_assert!(holds(z, &(rat(a) - rat(b))), "{:?} - {:?} = {:?}", x, y, z);
    }

    #[test]
    fn outward_add_and_sub_contain_and_enclose_the_tight_ones((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        let s = x.add_outward(y);
        prop_assert!(holds(s, &(rat(a) + rat(b))), "{:?} +out {:?} = {:?} misses {} + {}", x, y, s, a, b);
        prop_assert!((x + y).is_subset(s), "{:?} +out {:?} = {:?} is tighter than {:?}", x, y, s, x + y);
        let d = x.sub_outward(y);
        prop_assert!(holds(d, &(rat(a) - rat(b))), "{:?} -out {:?} = {:?} misses {} - {}", x, y, d, a, b);
        prop_assert!((x - y).is_subset(d), "{:?} -out {:?} = {:?} is tighter than {:?}", x, y, d, x - y);
    }

    #[test]
    fn mul_contains((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        let z = x * y;
        prop_assert!(holds(z, &(rat(a) * rat(b))), "{:?} * {:?} = {:?} misses {} * {}", x, y, z, a, b);
    }

    #[test]
    fn div_contains((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        prop_assume!(b != 0.0);
        let z = x / y;
        prop_assert!(holds(z, &(rat(a) / rat(b))), "{:?} / {:?} = {:?} misses {} / {}", x, y, z, a, b);
    }

    #[test]
    fn recip_contains((x, a) in any_interval_and_point()) {
        prop_assume!(a != 0.0);
        let z = x.recip();
        prop_assert!(holds(z, &(BigRational::one() / rat(a))), "1 / {:?} = {:?}", x, z);
    }

    #[test]
    fn sqr_contains((x, a) in any_interval_and_point()) {
        let z = x.sqr();
        prop_assert!(holds(z, &(rat(a) * rat(a))), "{:?}^2 = {:?}", x, z);
        prop_assert!(z.lo() >= 0.0);
    }

    #[test]
    fn sqrt_contains((x, a) in any_interval_and_point()) {
        let (x, a) = (x.abs(), a.abs());
        let z = x.sqrt();
        // sqrt(a) in [lo, hi] <=> lo^2 <= a <= hi^2 for 0 <= lo <= hi.
        prop_assert!(!z.is_empty() && z.lo() >= 0.0);
        prop_assert!(rat(z.lo()) * rat(z.lo()) <= rat(a), "sqrt {:?} = {:?}", x, z);
        prop_assert!(z.hi() == f64::INFINITY || rat(a) <= rat(z.hi()) * rat(z.hi()), "sqrt {:?} = {:?}", x, z);
    }

    /// `add`, `sub` and `intersect` build their results without the
    /// checks of `Interval::new`: the results are the ones it builds
    /// (empty operands included), and they keep the invariant.
    #[test]
    fn add_sub_intersect_need_no_check((x, _a) in any_interval_and_point(), (y, _b) in any_interval_and_point(), empty in 0u8..4) {
        let (x, y) = match empty {
            0 => (Interval::EMPTY, y),
            1 => (x, Interval::EMPTY),
            _ => (x, y),
        };
        let i = x.intersect(y);
        let want = Interval::new(x.lo().max(y.lo()), x.hi().min(y.hi()));
        prop_assert!(i.lo().to_bits() == want.lo().to_bits() && i.hi().to_bits() == want.hi().to_bits(), "{:?} & {:?} = {:?}", x, y, i);
        for z in [x + y, x - y, i] {
            let valid = z.lo() <= z.hi() && z.lo() < f64::INFINITY && z.hi() > f64::NEG_INFINITY;
            let empty = z.lo() == f64::INFINITY && z.hi() == f64::NEG_INFINITY;
            prop_assert!(valid || empty, "{:?} {:?}: {:?}", x, y, z);
            prop_assert!(Interval::new(z.lo(), z.hi()) == z || empty);
        }
    }

    #[test]
    fn neg_abs_hull_intersect((x, a) in any_interval_and_point(), (y, b) in any_interval_and_point()) {
        prop_assert!(holds(x.neg(), &-rat(a)));
        prop_assert!(holds(x.abs(), &rat(a).abs()));
        prop_assert!(holds(x.hull(y), &rat(a)) && holds(x.hull(y), &rat(b)));
        if y.contains(a) {
            prop_assert!(holds(x.intersect(y), &rat(a)));
        }
        prop_assert!(x.width() >= 0.0);
        if x.is_bounded() && x.width().is_finite() {
            prop_assert!(rat(x.width()) >= rat(x.hi()) - rat(x.lo()));
        }
        prop_assert!(x.contains(x.mid()));
    }

    #[test]
    fn add_rev_keeps_solutions((x, a) in interval_and_point(), (y, b) in interval_and_point(), s in 0.0..1.0f64) {
        // z: an interval holding the exact a + b, with some slack.
        let exact = Interval::point(a) + Interval::point(b);
        prop_assume!(exact.is_bounded());
        let z = Interval::new(exact.lo() - s, exact.hi() + s);
        prop_assume!(!z.is_empty());
        let (x2, y2) = Interval::add_rev(z, x, y);
        prop_assert!(x2.contains(a) && y2.contains(b), "add_rev({:?}, {:?}, {:?}) = {:?}, {:?}", z, x, y, x2, y2);
        let exact = Interval::point(a) - Interval::point(b);
        prop_assume!(exact.is_bounded());
        let (x3, y3) = Interval::sub_rev(exact, x, y);
        prop_assert!(x3.contains(a) && y3.contains(b));
    }

    #[test]
    fn mul_rev_keeps_solutions((x, a) in interval_and_point(), (y, b) in interval_and_point()) {
        let z = Interval::point(a) * Interval::point(b);
        prop_assume!(z.is_bounded());
        let (x2, y2) = Interval::mul_rev(z, x, y);
        prop_assert!(x2.contains(a) && y2.contains(b), "mul_rev({:?}, {:?}, {:?}) = {:?}, {:?}", z, x, y, x2, y2);
    }

    #[test]
    fn sqr_rev_keeps_solutions((x, a) in interval_and_point()) {
        let z = Interval::point(a).sqr();
        let x2 = Interval::sqr_rev(z, x);
        prop_assert!(x2.contains(a), "sqr_rev({:?}, {:?}) = {:?} loses {}", z, x, x2, a);
        prop_assert!(x2.is_subset(x));
    }

    #[test]
    fn centered_contains(c in finite(), r in 0.0..1e6f64) {
        let x = Interval::centered(c, r);
        let (rc, rr) = (rat(c), rat(r));
        if x.is_bounded() {
            prop_assert!(holds(x, &(&rc - &rr)) && holds(x, &(&rc + &rr)));
        }
    }
}

proptest! {
    #![proptest_config(trig_config())]

    #[test]
    fn sin_cos_contain(lo in -8.0..8.0f64, w in prop_oneof![Just(0.0), 0.0..1e-6f64, 0.0..4.0f64], t in 0.0..=1.0f64) {
        let hi = (lo + w).min(8.0);
        let x = Interval::new(lo, hi);
        let a = (lo + t * (hi - lo)).clamp(lo, hi);
        let ra = rat(a);
        for cosine in [false, true] {
            let z = if cosine { x.cos() } else { x.sin() };
            let (l, h) = taylor(&ra, cosine);
            prop_assert!(holds(z, &l) && holds(z, &h), "{} {:?} = {:?} misses the value at {}", if cosine { "cos" } else { "sin" }, x, z, a);
            prop_assert!(z.lo() >= -1.0 && z.hi() <= 1.0);
        }
    }

    #[test]
    fn sin_cos_extrema_near_multiples_of_half_pi(k in -5i32..5, d in -1e-12..1e-12f64) {
        // Intervals that end right next to an extremum: the extremum must be
        // included whenever it lies inside.
        let c = f64::from(k) * std::f64::consts::FRAC_PI_2 + d;
        let x = Interval::new(c - 1e-3, c + 1e-3);
        for cosine in [false, true] {
            let z = if cosine { x.cos() } else { x.sin() };
            for p in [x.lo(), c, x.hi()] {
                let (l, h) = taylor(&rat(p), cosine);
                prop_assert!(holds(z, &l) && holds(z, &h));
            }
        }
    }
}

#[test]
fn empty_propagates_and_is_never_nan() {
    let e = Interval::EMPTY;
    let x = Interval::new(1.0, 2.0);
    for z in [
        e + x,
        x - e,
        e * x,
        x / e,
        e.sqr(),
        e.sqrt(),
        e.sin(),
        e.cos(),
        e.abs(),
    ] {
        assert!(z.is_empty());
        assert!(!z.lo().is_nan() && !z.hi().is_nan());
    }
    // Zero times an unbounded interval is exactly zero-ish, never NaN.
    let z = Interval::ZERO * Interval::ENTIRE;
    assert!(z.contains(0.0) && !z.lo().is_nan() && z.is_bounded());
}

#[test]
fn overflow_goes_to_infinity_not_nan() {
    let big = Interval::new(f64::MAX, f64::MAX);
    let s = big + big;
    assert_eq!(s.hi(), f64::INFINITY);
    assert_eq!(s.lo(), f64::MAX);
    let p = big * big;
    assert!(p.hi() == f64::INFINITY && !p.lo().is_nan());
}

/// The same operations against inari (IEEE Std 1788.1, tightest enclosures
/// for these operations), an independent implementation that rounds with
/// the FPU's directed modes instead of next_down/next_up. inari needs
/// AVX2 and FMA, so this module exists only in a build with
/// `-C target-cpu=haswell` (`make test` runs it in `target/haswell`, see
/// the Makefile); inari's transcendental functions need GMP and MPFR built
/// from source (minutes on two cores), so sin and cos stay with the Taylor
/// oracle above and inari is built without its `gmp` feature.
///
/// For each operation: inari's result (the tightest f64 interval holding
/// the exact range) must lie inside ours (anything sound contains it), and
/// ours must lie inside inari's widened by the tightness our doc comments
/// promise (0 ulp for + and -, 1 ulp per bound for the others).
#[cfg(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
))]
mod inari_reference {
    use super::*;

    fn theirs(x: Interval) -> inari::Interval {
        if x.is_empty() {
            inari::Interval::EMPTY
        } else {
            inari::Interval::try_from((x.lo(), x.hi())).expect("a valid interval")
        }
    }

    /// `theirs ⊆ ours ⊆ theirs widened by `ulps` per bound`.
    fn agrees(ours: Interval, theirs: inari::Interval, ulps: u32) -> Result<(), String> {
        if theirs.is_empty() || ours.is_empty() {
            return if theirs.is_empty() && ours.is_empty() {
                Ok(())
            } else {
                Err(format!("ours {ours:?}, inari {theirs:?}"))
            };
        }
        let (lo, hi) = (theirs.inf(), theirs.sup());
        let (mut wlo, mut whi) = (lo, hi);
        for _ in 0..ulps {
            wlo = wlo.next_down();
            whi = whi.next_up();
        }
        let inside = ours.lo() <= lo && hi <= ours.hi();
        let tight = wlo <= ours.lo() && ours.hi() <= whi;
        if inside && tight {
            Ok(())
        } else {
            Err(format!(
                "ours {ours:?}, inari [{lo:e}, {hi:e}]: {}",
                if inside {
                    "looser than promised"
                } else {
                    "misses part of the tightest enclosure"
                }
            ))
        }
    }

    proptest! {
        #![proptest_config(config())]

        #[test]
        fn binary_operations_agree_with_inari((x, _a) in any_interval_and_point(), (y, _b) in any_interval_and_point()) {
            let (p, q) = (theirs(x), theirs(y));
            prop_assert!(agrees(x + y, p + q, 0).is_ok(), "{:?} + {:?}: {}", x, y, agrees(x + y, p + q, 0).unwrap_err());
            prop_assert!(agrees(x - y, p - q, 0).is_ok(), "{:?} - {:?}: {}", x, y, agrees(x - y, p - q, 0).unwrap_err());
            prop_assert!(agrees(x * y, p * q, 1).is_ok(), "{:?} * {:?}: {}", x, y, agrees(x * y, p * q, 1).unwrap_err());
            prop_assert!(agrees(x.hull(y), p.convex_hull(q), 0).is_ok(), "hull {:?} {:?}", x, y);
            prop_assert!(agrees(x.intersect(y), p.intersection(q), 0).is_ok(), "intersect {:?} {:?}", x, y);
            // Division: ours is the hull of inari's when y straddles 0
            // (inari, like us, gives the entire line then, or [0, 0] for
            // x = [0, 0]); with 0 at a bound of y inari is tightest too.
            prop_assert!(agrees(x / y, p / q, 1).is_ok(), "{:?} / {:?}: {}", x, y, agrees(x / y, p / q, 1).unwrap_err());
        }

        #[test]
        fn unary_operations_agree_with_inari((x, _a) in any_interval_and_point()) {
            let p = theirs(x);
            prop_assert!(agrees(x.neg(), -p, 0).is_ok(), "-{:?}", x);
            prop_assert!(agrees(x.abs(), p.abs(), 0).is_ok(), "|{:?}|", x);
            prop_assert!(agrees(x.sqr(), p.sqr(), 1).is_ok(), "{:?}^2: {}", x, agrees(x.sqr(), p.sqr(), 1).unwrap_err());
            prop_assert!(agrees(x.sqrt(), p.sqrt(), 1).is_ok(), "sqrt {:?}: {}", x, agrees(x.sqrt(), p.sqrt(), 1).unwrap_err());
            prop_assert!(agrees(x.recip(), p.recip(), 1).is_ok(), "1 / {:?}: {}", x, agrees(x.recip(), p.recip(), 1).unwrap_err());
        }
    }
}
