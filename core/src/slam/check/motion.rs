//! The check of the motion's constraints against the truth: the initial
//! and final boxes, each step (unicycle2d, auv3d: the displacement box;
//! odometry2d: the heading increment and the displacement at the true
//! heading), and the drift windows (`heading_drift`, `motion_drift`).
//!
//! # Constraint
//!
//! As the solver states them (docs/formats.md, "Mission"): step i holds
//! when `p(i+1) - p(i)` lies in the displacement box of the step's inputs
//! (`contractors::motion_chain`: `dt·speed·(cos h, sin h)` for
//! unicycle2d, `dt·R(roll, pitch, yaw)·v` for auv3d, `dt·speed·(cos th(i),
//! sin th(i))` for odometry2d) widened by `motion_error` per axis, and for
//! odometry2d when `th(i+1) - th(i)` lies in `dt·turn_rate + [-f, f]`
//! (`odometry::chain`). A heading drift window `(k, b)` holds at i when
//! `th(i+k) - th(i)` lies in the solver's increment
//! (`odometry::drift::HeadingDrift::relative_heading`); a motion drift
//! window `(k, c)` when the Euclidean norm of `p(i+k) - p(i) - Σ dt·v(j)
//! (cos th(j), sin th(j))` is at most c (plus √2·e(j) per exempt step).
//!
//! # Math
//!
//! The value is the residual: the distance (per axis, the largest) from
//! the truth's displacement to the box of the nominal displacement (no
//! per-step error), in interval arithmetic; its lower bound, rounded
//! down, above the bound proves the violation; the excess is the
//! difference rounded down. A step is also a violation when the solver's
//! own step (`sweep_forward`/`sweep_backward` of the motion chain, the
//! odometry chain's `forward_step`/`backward_step` on a chain of that one
//! step) empties a domain of the truth's point boxes: a truth this check
//! accepts is kept by those contractors.
//!
//! # Soundness
//!
//! Every quantity that decides is an outward-rounded enclosure, so a truth
//! exactly on a bound is never a violation (its residual's lower bound is
//! at most the bound). A constraint that needs a value the truth does not
//! know (a `null` position, a missing heading) is not checked and counted
//! in `unchecked`. An unknown true heading inside a motion drift window
//! reads as any heading (a wider sum: fewer violations, never a false one).
//!
//! # Complexity
//!
//! O(N) for the steps, O(N) per drift window (prefix sums, as the
//! solver's), O(k) more per violated heading drift window (its exempt
//! sum).

use super::types::{gap, minus_down, plus_up, Bound, Kind, Truthy, Violation};
use crate::contractors::motion_chain::{
    auv_displacement, sweep_backward, sweep_forward, unicycle_displacement, Sweep,
};
use crate::interval::Interval;
use crate::odometry::chain::OdometryChain;
use crate::odometry::drift::{DriftWindow, HeadingDrift};
use crate::odometry::motion_drift::SQRT_2_ABOVE;
use crate::slam::mission::Model;

/// How the mission wrote the per-step bounds: one number (the path is the
/// field) or an array (the path is its entry).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PathStyle {
    /// `motion_error` is an array.
    pub motion_error_array: bool,
    /// `heading_error` is an array.
    pub heading_error_array: bool,
}

impl Default for PathStyle {
    fn default() -> Self {
        PathStyle {
            motion_error_array: true,
            heading_error_array: true,
        }
    }
}

impl PathStyle {
    fn motion_error(&self, i: usize) -> String {
        match self.motion_error_array {
            true => format!("motion_error[{i}]"),
            false => "motion_error".into(),
        }
    }

    fn heading_error(&self, i: usize) -> String {
        match self.heading_error_array {
            true => format!("heading_error[{i}]"),
            false => "heading_error".into(),
        }
    }
}

/// The truth's coordinates against a box, axis by axis.
fn point_in_box(
    p: &[f64],
    b: &[Interval],
    field: &str,
    kind: Kind,
    step: usize,
    out: &mut Vec<Violation>,
) {
    for (a, (&x, &bx)) in p.iter().zip(b).enumerate() {
        if !bx.contains(x) {
            let v = Violation::new(
                format!("{field}[{a}]"),
                kind,
                x,
                Bound::Within(bx.lo(), bx.hi()),
                gap(Interval::point(x), bx),
            );
            out.push(v.at_step(step));
        }
    }
}

/// A true heading against an interval.
fn heading_in(x: f64, b: Interval, field: &str, kind: Kind, step: usize) -> Option<Violation> {
    (!b.contains(x)).then(|| {
        Violation::new(
            field,
            kind,
            x,
            Bound::Within(b.lo(), b.hi()),
            gap(Interval::point(x), b),
        )
        .at_step(step)
    })
}

/// `initial_position`, `final_position`, `initial_heading`,
/// `final_heading`.
pub fn boxes(t: &mut Truthy, out: &mut Vec<Violation>) {
    let m = t.m;
    let n = m.steps;
    match t.position(0) {
        Some(p) => point_in_box(
            p,
            m.initial_position.axes(),
            "initial_position",
            Kind::InitialPosition,
            0,
            out,
        ),
        None => t.unchecked += 1,
    }
    if let Some(f) = &m.final_position {
        match t.position(n) {
            Some(p) => point_in_box(p, f.axes(), "final_position", Kind::FinalPosition, n, out),
            None => t.unchecked += 1,
        }
    }
    let ends = [
        (
            m.initial_heading,
            0,
            "initial_heading",
            Kind::InitialHeading,
        ),
        (m.final_heading, n, "final_heading", Kind::FinalHeading),
    ];
    for (b, step, field, kind) in ends {
        let Some(b) = b else { continue };
        match t.heading(step) {
            Some(x) => out.extend(heading_in(x, b, field, kind, step)),
            None => t.unchecked += 1,
        }
    }
}

/// The truth's displacement `q - p`, outward.
fn displacement(p: &[f64], q: &[f64]) -> Vec<Interval> {
    p.iter()
        .zip(q)
        .map(|(&a, &b)| Interval::point(b) - Interval::point(a))
        .collect()
}

/// The largest per-axis distance (a lower bound) from `d` to `nominal`.
fn residual(d: &[Interval], nominal: &[Interval]) -> f64 {
    d.iter()
        .zip(nominal)
        .map(|(&x, &b)| gap(x, b))
        .fold(0.0, f64::max)
}

/// Whether the solver's motion chain empties a position when it joins
/// the point boxes of `p` and `q` by the displacement `disp` (forward,
/// then backward).
fn chain_refuses(p: &[f64], q: &[f64], disp: &[Interval]) -> bool {
    let dim = p.len();
    let mut pos: Vec<Interval> = p.iter().chain(q).map(|&x| Interval::point(x)).collect();
    matches!(sweep_forward(&mut pos, disp, dim, 0, 0.0), Sweep::Empty(_))
        || matches!(sweep_backward(&mut pos, disp, dim, 1, 0.0), Sweep::Empty(_))
}

/// The steps of a unicycle2d or auv3d mission.
#[allow(clippy::needless_range_loop)] // the channels are read in parallel
fn box_steps(t: &mut Truthy, style: &PathStyle, out: &mut Vec<Violation>) {
    let m = t.m;
    let c = &m.inputs;
    for i in 0..m.steps {
        let (Some(p), Some(q)) = (t.position(i), t.position(i + 1)) else {
            t.unchecked += 1;
            continue;
        };
        let e = m.motion_error[i];
        let nominal: Vec<Interval> = match m.model {
            Model::Auv3d => auv_displacement(
                m.dt,
                c[0][i],
                c[1][i],
                c[2][i],
                [c[3][i], c[4][i], c[5][i]],
                0.0,
            )
            .to_vec(),
            _ => unicycle_displacement(m.dt, c[0][i], c[1][i], 0.0).to_vec(),
        };
        let value = residual(&displacement(p, q), &nominal);
        let widened: Vec<Interval> = nominal.iter().map(|&x| x + Interval::new(-e, e)).collect();
        if value > e || chain_refuses(p, q, &widened) {
            let v = Violation::new(
                style.motion_error(i),
                Kind::MotionStep,
                value,
                Bound::AtMost(e),
                minus_down(value, e),
            );
            out.push(v.at_step(i));
        }
    }
}

/// Point boxes of the truth where known, the whole line elsewhere.
fn known(x: Option<f64>) -> Interval {
    x.map_or(Interval::ENTIRE, Interval::point)
}

/// The odometry chain of step i alone, and whether it refuses the truth's
/// states i and i+1 (unknown values: the whole line). `Some(true)` when
/// it refuses because of the headings alone.
fn odometry_refuses(t: &Truthy, i: usize, p: &[f64], q: &[f64]) -> Option<bool> {
    let m = t.m;
    let chain = OdometryChain::new(
        m.dt,
        &m.inputs[0][i..=i],
        &m.inputs[1][i..=i],
        &[m.heading_error[i]],
        &[m.motion_error[i]],
    );
    let (h0, h1) = (known(t.heading(i)), known(t.heading(i + 1)));
    let mut pos = [
        [Interval::point(p[0]), Interval::point(p[1])],
        [Interval::point(q[0]), Interval::point(q[1])],
    ];
    let mut heading = [h0, h1];
    let refused = chain.forward_step(&mut pos, &mut heading, 0).is_err()
        || chain.backward_step(&mut pos, &mut heading, 0).is_err();
    refused.then(|| !h1.meets(h0 + chain.heading_increment(0)))
}

/// The steps of an odometry2d mission: the heading increment (when both
/// true headings are known) and the displacement at the true heading
/// (any heading when it is unknown).
fn odometry_steps(t: &mut Truthy, style: &PathStyle, out: &mut Vec<Violation>) {
    let m = t.m;
    for i in 0..m.steps {
        let (th0, th1) = (t.heading(i), t.heading(i + 1));
        let mut heading_bad = false;
        let f = m.heading_error[i];
        let mut heading_value = 0.0;
        match (th0, th1) {
            (Some(a), Some(b)) => {
                let d = Interval::point(b) - Interval::point(a);
                heading_value = gap(d, m.inputs[1][i].scale(m.dt));
                heading_bad = heading_value > f;
            }
            _ => t.unchecked += 1,
        }
        let (Some(p), Some(q)) = (t.position(i), t.position(i + 1)) else {
            t.unchecked += 1;
            push_heading_step(heading_bad, i, heading_value, f, style, out);
            continue;
        };
        let h = known(th0);
        let s = m.inputs[0][i].scale(m.dt);
        let nominal = [s * h.cos(), s * h.sin()];
        let e = m.motion_error[i];
        let value = residual(&displacement(p, q), &nominal);
        let mut motion_bad = value > e;
        match odometry_refuses(t, i, p, q) {
            Some(true) => heading_bad = true,
            Some(false) => motion_bad |= !heading_bad,
            None => {}
        }
        push_heading_step(heading_bad, i, heading_value, f, style, out);
        if motion_bad {
            out.push(step_above(
                style.motion_error(i),
                Kind::MotionStep,
                value,
                e,
                i,
            ));
        }
    }
}

/// A step's `value` above its bound `e` (motion or heading), by how much.
fn step_above(path: String, kind: Kind, value: f64, e: f64, i: usize) -> Violation {
    Violation::new(path, kind, value, Bound::AtMost(e), minus_down(value, e)).at_step(i)
}

fn push_heading_step(
    bad: bool,
    i: usize,
    value: f64,
    f: f64,
    style: &PathStyle,
    out: &mut Vec<Violation>,
) {
    if bad {
        out.push(step_above(
            style.heading_error(i),
            Kind::HeadingStep,
            value,
            f,
            i,
        ));
    }
}

/// Every step of the mission's model.
pub fn steps(t: &mut Truthy, style: &PathStyle, out: &mut Vec<Violation>) {
    match t.m.model {
        Model::Odometry2d => odometry_steps(t, style, out),
        _ => box_steps(t, style, out),
    }
}

/// The exempt steps' bounds summed over `[i, i + k)` (the steps whose
/// per-step bound `e` is above `t`), each times `factor`, rounded up.
fn exempt_sum(e: &[f64], t: Option<f64>, i: usize, k: usize, factor: Interval) -> f64 {
    let Some(t) = t else { return 0.0 };
    e[i..i + k]
        .iter()
        .filter(|&&x| x > t)
        .fold(0.0, |s, &x| plus_up(s, (Interval::point(x) * factor).hi()))
}

/// The `heading_drift` windows.
pub fn heading_drift(t: &mut Truthy, out: &mut Vec<Violation>) {
    let m = t.m;
    let n = m.steps;
    for (x, w) in m.heading_drift.iter().enumerate() {
        if w.steps == 0 || w.steps > n as u64 {
            continue;
        }
        let Some(d) = HeadingDrift::new(m.dt, &m.inputs[1], &m.heading_error, &[*w]) else {
            continue;
        };
        let k = w.steps as usize;
        for i in 0..=n - k {
            let (Some(a), Some(b)) = (t.heading(i), t.heading(i + k)) else {
                t.unchecked += 1;
                continue;
            };
            let dh = Interval::point(b) - Interval::point(a);
            let inc = d.relative_heading(i, k);
            if dh.meets(inc) {
                continue;
            }
            let x_sum = exempt_sum(&m.heading_error, w.exempt_above, i, k, Interval::point(1.0));
            let bound = plus_up(w.error, x_sum);
            let value = gap(dh, d.turn_sum(i, k));
            let v = Violation::new(
                format!("heading_drift[{x}]"),
                Kind::HeadingDrift,
                value,
                Bound::AtMost(bound),
                gap(dh, inc),
            );
            out.push(v.at_step(i));
        }
    }
}

/// Prefix sums of interval terms (round to nearest, with the rounding
/// bound of `odometry::drift`: k additions put a difference within
/// `k·u·M` of the exact sum, M the largest |prefix|).
struct Prefix {
    lo: Vec<f64>,
    hi: Vec<f64>,
    lo_inf: Vec<u32>,
    hi_inf: Vec<u32>,
    largest: f64,
}

/// u = 2^-53.
const UNIT_ROUNDOFF: f64 = 1.0 / 9_007_199_254_740_992.0;

impl Prefix {
    fn new(terms: impl Iterator<Item = Interval>) -> Prefix {
        let mut p = Prefix {
            lo: vec![0.0],
            hi: vec![0.0],
            lo_inf: vec![0],
            hi_inf: vec![0],
            largest: 0.0,
        };
        let (mut a, mut c, mut na, mut nc) = (0.0f64, 0.0f64, 0u32, 0u32);
        for s in terms {
            match s.lo().is_finite() && !s.is_empty() {
                true => a += s.lo(),
                false => na += 1,
            }
            match s.hi().is_finite() && !s.is_empty() {
                true => c += s.hi(),
                false => nc += 1,
            }
            p.largest = p.largest.max(a.abs()).max(c.abs());
            p.lo.push(a);
            p.hi.push(c);
            p.lo_inf.push(na);
            p.hi_inf.push(nc);
        }
        p
    }

    /// An enclosure of the sum of the terms `i..i + k`.
    fn sum(&self, i: usize, k: usize) -> Interval {
        let r = Interval::point(k as f64)
            .mul(Interval::point(self.largest))
            .scale(UNIT_ROUNDOFF)
            .hi();
        if !r.is_finite() {
            return Interval::ENTIRE;
        }
        let j = i + k;
        let lo = match self.lo_inf[j] != self.lo_inf[i] {
            true => f64::NEG_INFINITY,
            false => {
                (Interval::point(self.lo[j]) - Interval::point(self.lo[i]) - Interval::point(r))
                    .lo()
            }
        };
        let hi = match self.hi_inf[j] != self.hi_inf[i] {
            true => f64::INFINITY,
            false => (Interval::point(self.hi[j]) - Interval::point(self.hi[i])
                + Interval::point(r))
            .hi(),
        };
        Interval::new(lo, hi)
    }
}

/// The nominal displacement sums of odometry2d, per axis: `dt·v(j)·cos
/// th(j)` and `dt·v(j)·sin th(j)` at the true headings (any heading where
/// unknown).
fn nominal_sums(t: &Truthy) -> [Prefix; 2] {
    let m = t.m;
    let term = |j: usize| {
        let s = m.inputs[0][j].scale(m.dt);
        let h = known(t.heading(j));
        (s * h.cos(), s * h.sin())
    };
    [
        Prefix::new((0..m.steps).map(|j| term(j).0)),
        Prefix::new((0..m.steps).map(|j| term(j).1)),
    ]
}

/// The `motion_drift` windows.
pub fn motion_drift(t: &mut Truthy, out: &mut Vec<Violation>) {
    let m = t.m;
    let n = m.steps;
    if m.motion_drift.is_empty() {
        return;
    }
    let sums = nominal_sums(t);
    for (x, w) in m.motion_drift.iter().enumerate() {
        if w.steps == 0 || w.steps > n as u64 {
            continue;
        }
        let exempt = exempt_prefix(&m.motion_error, w);
        let k = w.steps as usize;
        for i in 0..=n - k {
            let (Some(p), Some(q)) = (t.position(i), t.position(i + k)) else {
                t.unchecked += 1;
                continue;
            };
            let d = displacement(p, q);
            let r = [d[0] - sums[0].sum(i, k), d[1] - sums[1].sum(i, k)];
            let mig = |x: Interval| gap(x, Interval::ZERO);
            let norm = (Interval::point(mig(r[0])).sqr() + Interval::point(mig(r[1])).sqr())
                .sqrt()
                .lo();
            let bound = match &exempt {
                Some(e) => plus_up(w.error, e.sum(i, k).hi()),
                None => w.error,
            };
            if norm > bound {
                let v = Violation::new(
                    format!("motion_drift[{x}]"),
                    Kind::MotionDrift,
                    norm,
                    Bound::AtMost(bound),
                    minus_down(norm, bound),
                );
                out.push(v.at_step(i));
            }
        }
    }
}

/// The exempt steps' `e(j)·√2` as prefix sums, when the window exempts.
fn exempt_prefix(e: &[f64], w: &DriftWindow) -> Option<Prefix> {
    let t = w.exempt_above?;
    let root2 = Interval::new(SQRT_2_ABOVE, SQRT_2_ABOVE);
    Some(Prefix::new(e.iter().map(|&x| match x > t {
        true => Interval::point(x) * root2,
        false => Interval::ZERO,
    })))
}
