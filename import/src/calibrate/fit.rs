//! The fits: an affine bound over |residuals|, a residual band between
//! two lines, a window's bound, and the rule on the number of samples.

use crate::sensor_model::{Band, BandOf, Bound, Fit, Measure};

/// The failure probability the sample rule allows (module doc of
/// [`min_samples`]).
pub const RULE_DELTA: f64 = 1e-3;

/// The fewest samples a bound may be fitted on with the relative margin
/// F: `ceil(ln(1 / delta) / ln(1 + F))`, delta = [`RULE_DELTA`].
///
/// The rule: when a run's residuals are drawn independently from errors
/// bounded by B whose law puts at least as much mass near ±B as the
/// uniform law on [-B, B] does, each sample lies below B / (1 + F) with
/// probability at most 1 / (1 + F), so the largest of n samples times
/// 1 + F falls short of B with probability at most (1 + F)^-n <= delta.
/// The fitted bound is then at least B, and covers every run drawn from
/// the same errors. F = 0.1 needs 73 samples; a window of k steps counts
/// its disjoint windows (N / k), not its overlapping pairs.
pub fn min_samples(relative_margin: f64) -> usize {
    let f = relative_margin.max(1e-6);
    ((1.0 / RULE_DELTA).ln() / f.ln_1p()).ceil() as usize
}

/// The line `y <= a + b·x` over every point with the smallest mean
/// `a + b·mean(x)`, b in `[slope_lo, slope_hi]`: for a slope b the least a
/// is the largest `y - b·x`, and the mean is convex in b (a maximum of
/// linear functions plus a linear one), so a ternary search finds it.
/// Returns `(a, b)`; an empty set gives `(-inf, 0)`.
pub fn upper_line(points: &[(f64, f64)], slope_lo: f64, slope_hi: f64) -> (f64, f64) {
    if points.is_empty() {
        return (f64::NEG_INFINITY, 0.0);
    }
    upper_line_skipping(points, slope_lo, slope_hi, 0)
}

/// [`upper_line`] over every point but the `skip` highest above the line
/// (the bands of an outlier share): for a slope b the least a is the
/// (skip + 1)-th largest `y - b·x`. With `skip` > 0 the mean need not be
/// convex in b and the search finds a local optimum; the points left above
/// are counted afterwards on the final bands. An empty set gives
/// `(-inf, b)`.
pub fn upper_line_skipping(
    points: &[(f64, f64)],
    slope_lo: f64,
    slope_hi: f64,
    skip: usize,
) -> (f64, f64) {
    line_search(points, slope_lo, slope_hi, skip, 200)
}

/// The search of [`upper_line_skipping`] with `iterations` steps of the
/// ternary search (each keeps 2/3 of the slope's interval).
fn line_search(
    points: &[(f64, f64)],
    slope_lo: f64,
    slope_hi: f64,
    skip: usize,
    iterations: usize,
) -> (f64, f64) {
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / points.len().max(1) as f64;
    let skip = skip.min(points.len().saturating_sub(1));
    let mut buf = vec![0.0; points.len()];
    let mut a_of = |b: f64| {
        if points.is_empty() {
            return f64::NEG_INFINITY;
        }
        if skip == 0 {
            return points
                .iter()
                .map(|&(x, y)| y - b * x)
                .fold(f64::NEG_INFINITY, f64::max);
        }
        for (x, &(px, py)) in buf.iter_mut().zip(points) {
            *x = py - b * px;
        }
        let k = buf.len() - 1 - skip;
        *buf.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let (mut lo, mut hi) = (slope_lo, slope_hi);
    for _ in 0..iterations {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if a_of(m1) + m1 * mean_x <= a_of(m2) + m2 * mean_x {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let b = (lo + hi) / 2.0;
    // The (skip + 1)-th largest y - b x at the final b: every other point
    // is on or below.
    (a_of(b), b)
}

/// The span of the xs.
fn span(points: &[(f64, f64)]) -> [f64; 2] {
    points
        .iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |s, p| {
            [s[0].min(p.0), s[1].max(p.0)]
        })
}

/// An affine bound over `(x, |residual|)` points: the narrowest line
/// (slope >= 0) holding every point, times 1 + F, plus `margin`; a
/// constant one (the largest |residual|) when `of` is [`Measure::None`].
pub fn affine_bound(
    points: &[(f64, f64)],
    of: Measure,
    relative_margin: f64,
    margin: f64,
    method: &str,
) -> Bound {
    let (a, b) = match of {
        Measure::None => (points.iter().map(|p| p.1).fold(0.0, f64::max), 0.0),
        _ => upper_line(points, 0.0, 4.0),
    };
    let k = 1.0 + relative_margin;
    let (a, b) = ((a.max(0.0)) * k + margin, b * k);
    let inside = points.iter().filter(|p| p.1 <= a + b * p.0).count();
    Bound {
        constant: a,
        slope: b,
        turn_slope: 0.0,
        still: None,
        of,
        fit: Fit {
            method: method.into(),
            relative_margin,
            margin,
            samples: points.len(),
            independent: points.len(),
            coverage: inside as f64 / points.len().max(1) as f64,
            largest_residual: points.iter().map(|p| p.1).fold(0.0, f64::max),
            span: if of == Measure::None {
                [0.0, 0.0]
            } else {
                span(points)
            },
        },
    }
}

/// A bound over `(distance, turn, |residual|)` points: the narrowest
/// plane `a + b·distance + c·turn` (b, c in [0, 4]) over every point, the
/// smallest mean over the points, times 1 + F, plus `margin`. The mean is
/// convex in (b, c) (a maximum of linear functions plus a linear one), so
/// its least value over b is convex in c: a ternary search over c of
/// [`upper_line`]'s search over b finds it. Without any turn (every point
/// at turn 0) it is [`affine_bound`]'s line, `turn_slope` 0.
pub fn plane_bound(
    points: &[(f64, f64, f64)],
    relative_margin: f64,
    margin: f64,
    method: &str,
) -> Bound {
    let line =
        |c: f64| -> Vec<(f64, f64)> { points.iter().map(|p| (p.0, p.2 - c * p.1)).collect() };
    let n = points.len().max(1) as f64;
    let (mean_d, mean_t) = points
        .iter()
        .fold((0.0, 0.0), |s, p| (s.0 + p.0 / n, s.1 + p.1 / n));
    // 60 steps on the slope (4 (2/3)^60 < 1e-10), 25 on the turn's
    // (4 (2/3)^25 < 1e-4): any slopes give a bound holding every point,
    // the search only makes it narrower.
    let cost = |c: f64| {
        let (a, b) = line_search(&line(c), 0.0, 4.0, 0, 60);
        a + b * mean_d + c * mean_t
    };
    let c = if points.iter().all(|p| p.1 == 0.0) {
        0.0
    } else {
        let (mut lo, mut hi) = (0.0f64, 4.0f64);
        for _ in 0..25 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if cost(m1) <= cost(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        (lo + hi) / 2.0
    };
    let mut bound = affine_bound(&line(c), Measure::Distance, relative_margin, margin, method);
    bound.turn_slope = c * (1.0 + relative_margin);
    bound.fit.largest_residual = points.iter().map(|p| p.2).fold(0.0, f64::max);
    let inside = points
        .iter()
        .filter(|p| p.2 <= bound.at_step(p.0, p.1))
        .count();
    bound.fit.coverage = inside as f64 / n;
    bound
}

/// A residual band over `(x, residual)` points: the narrowest lines above
/// the residuals and above their negations (slopes in [-2, 2]),
/// intersected with the constant band of the smallest and largest
/// residual; widened at use by F × its half-width plus `margin`
/// ([`Band::at`]). `skip` (below, above): the band of an outlier share,
/// each line over every point but the `skip` farthest beyond it
/// ([`upper_line_skipping`]), and the constant band spans the points
/// between the lines, so at most `skip.0 + skip.1` points are left out;
/// (0, 0) holds every point.
pub fn band(
    points: &[(f64, f64)],
    (of, min_range): (BandOf, f64),
    skip: (usize, usize),
    (relative_margin, margin): (f64, f64),
    method: &str,
) -> Band {
    let negated: Vec<(f64, f64)> = points.iter().map(|p| (p.0, -p.1)).collect();
    let (ua, ub) = upper_line_skipping(points, -2.0, 2.0, skip.1);
    let (la, lb) = upper_line_skipping(&negated, -2.0, 2.0, skip.0);
    // The constant band spans the points between the two lines: those
    // the lines leave out stay out, and no other (at most skip.0 +
    // skip.1 points outside in all).
    let constant = points
        .iter()
        .filter(|&&(x, y)| skip == (0, 0) || (-(la + lb * x) <= y && y <= ua + ub * x))
        .fold([f64::INFINITY, f64::NEG_INFINITY], |s, p| {
            [s[0].min(p.1), s[1].max(p.1)]
        });
    let mut out = Band {
        upper: [ua, ub],
        lower: [la, lb],
        constant,
        of,
        min_range,
        fit: Fit {
            method: method.into(),
            relative_margin,
            margin,
            samples: points.len(),
            independent: points.len(),
            coverage: 0.0,
            largest_residual: points.iter().map(|p| p.1.abs()).fold(0.0, f64::max),
            span: span(points),
        },
    };
    let inside = points
        .iter()
        .filter(|&&(x, e)| {
            let ((lo, hi), _) = out.at(x);
            lo <= e && e <= hi
        })
        .count();
    out.fit.coverage = inside as f64 / points.len().max(1) as f64;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nvector_core::slam::simulate::Rng;

    /// The fitted line holds every point: zero, tiny and huge values,
    /// and points planted on the boundary of a known line.
    #[test]
    fn the_upper_line_holds_every_point() {
        let mut rng = Rng::new(7);
        for scale in [0.0, 1e-300, 1e-9, 1.0, 1e6, 1e100] {
            let pts: Vec<(f64, f64)> = (0..200)
                .map(|_| (rng.range(0.0, 3.0) * scale, rng.sym(1.0) * scale))
                .collect();
            for (lo, hi) in [(0.0, 4.0), (-2.0, 2.0)] {
                let (a, b) = upper_line(&pts, lo, hi);
                assert!((lo..=hi).contains(&b));
                for &(x, y) in &pts {
                    // a is the largest y - b x: a + b x >= y up to one
                    // rounding of a + b x.
                    let v = a + b * x;
                    assert!(
                        v >= y - 4.0 * f64::EPSILON * (v.abs() + y.abs()),
                        "scale {scale}: {v} < {y}"
                    );
                }
            }
        }
        // Points on the line y = 1 + 0.5 x: that line is the answer.
        let on: Vec<(f64, f64)> = (0..=10).map(|i| (i as f64, 1.0 + 0.5 * i as f64)).collect();
        let (a, b) = upper_line(&on, 0.0, 4.0);
        assert!((a - 1.0).abs() < 1e-9 && (b - 0.5).abs() < 1e-9, "{a} {b}");
        assert_eq!(upper_line(&[], 0.0, 1.0).0, f64::NEG_INFINITY);
    }

    #[test]
    fn an_affine_bound_covers_its_samples_with_its_margins() {
        let pts = [(0.0, 0.1), (1.0, 0.3), (2.0, 0.2), (0.5, 0.0)];
        let b = affine_bound(&pts, Measure::Distance, 0.1, 0.005, "m");
        assert_eq!(b.fit.coverage, 1.0);
        assert!(b.slope >= 0.0 && b.constant >= 0.1 * 1.1);
        for &(x, y) in &pts {
            assert!(b.at(x) >= y * 1.1 + 0.005 - 1e-12, "{x}");
        }
        let c = affine_bound(&pts, Measure::None, 0.1, 0.005, "m");
        assert_eq!((c.constant, c.slope), (0.3 * 1.1 + 0.005, 0.0));
        assert_eq!(c.fit.span, [0.0, 0.0]);
    }

    /// The plane holds every point (zero, tiny and huge values); points
    /// planted on a known plane give that plane back; without turns it is
    /// the line.
    #[test]
    fn the_plane_bound_holds_every_point() {
        let mut rng = Rng::new(11);
        for scale in [0.0, 1e-300, 1e-9, 1.0, 1e6, 1e100] {
            let pts: Vec<(f64, f64, f64)> = (0..300)
                .map(|_| {
                    (
                        rng.range(0.0, 0.05) * scale,
                        rng.range(0.0, 0.05) * scale,
                        rng.range(0.0, 1.0) * scale,
                    )
                })
                .collect();
            let b = plane_bound(&pts, 0.1, 0.0, "p");
            assert!(b.slope >= 0.0 && b.turn_slope >= 0.0 && b.constant >= 0.0);
            for &(d, t, y) in &pts {
                let v = b.at_step(d, t);
                assert!(v >= y * (1.0 - 1e-12), "scale {scale}: {v} < {y}");
            }
            assert_eq!(b.fit.coverage, 1.0, "scale {scale}");
        }
        // On the plane 0.01 + 0.5 d + 2 t: that plane.
        let on: Vec<(f64, f64, f64)> = (0..=10)
            .flat_map(|i| (0..=10).map(move |j| (i as f64 * 0.01, j as f64 * 0.01, 0.0)))
            .map(|(d, t, _)| (d, t, 0.01 + 0.5 * d + 2.0 * t))
            .collect();
        let b = plane_bound(&on, 0.0, 0.0, "p");
        assert!(
            (b.constant - 0.01).abs() < 1e-5
                && (b.slope - 0.5).abs() < 1e-3
                && (b.turn_slope - 2.0).abs() < 1e-3,
            "{} {} {}",
            b.constant,
            b.slope,
            b.turn_slope
        );
        // No turn: the line of affine_bound, turn_slope 0.
        let flat = [(0.0, 0.0, 0.1), (1.0, 0.0, 0.3), (2.0, 0.0, 0.2)];
        let p = plane_bound(&flat, 0.1, 0.005, "m");
        let l = affine_bound(
            &[(0.0, 0.1), (1.0, 0.3), (2.0, 0.2)],
            Measure::Distance,
            0.1,
            0.005,
            "m",
        );
        assert_eq!(
            (p.constant, p.slope, p.turn_slope),
            (l.constant, l.slope, 0.0)
        );
    }

    #[test]
    fn the_sample_rule() {
        // (1 + F)^-n <= 1e-3 at n = min_samples(F), not at n - 1.
        for f in [0.01, 0.05, 0.1, 0.5, 1.0] {
            let n = min_samples(f);
            assert!(
                (1.0 + f).powi(-(n as i32)) <= RULE_DELTA * (1.0 + 1e-12),
                "F = {f}"
            );
            assert!((1.0 + f).powi(-(n as i32 - 1)) > RULE_DELTA, "F = {f}");
        }
    }
}
