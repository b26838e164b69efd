//! The residuals of a run's truth against the motion and sensor models:
//! what each bound must hold. Only steps whose truth is known at the ends
//! the residual reads count (a gap of the truth removes its steps, it is
//! never filled in).

use super::data::{Model, Run, Truth};
use std::f64::consts::PI;

/// `a` taken into (-pi, pi].
pub fn wrap(a: f64) -> f64 {
    a - 2.0 * PI * (a / (2.0 * PI)).round()
}

/// The truth of a run, or an empty one.
fn truth(run: &Run) -> Truth {
    run.truth.clone().unwrap_or_default()
}

/// `unicycle2d`: (step, true heading - measured heading, wrapped) at the
/// steps with a true heading.
pub fn heading_channel(run: &Run) -> Vec<(usize, f64)> {
    let t = truth(run);
    (0..run.steps())
        .filter_map(|i| {
            Some((
                i,
                wrap(t.headings.get(i).copied().flatten()? - run.rotation[i]),
            ))
        })
        .collect()
}

/// `odometry2d`: (step, |turn_rate|·dt, th(i+1) - th(i) - dt·turn_rate(i))
/// at the steps whose two ends have a true heading.
pub fn heading_steps(run: &Run) -> Vec<(usize, f64, f64)> {
    let t = truth(run);
    (0..run.steps())
        .filter_map(|i| {
            let (a, b) = (
                t.headings.get(i).copied()??,
                t.headings.get(i + 1).copied()??,
            );
            let turn = run.dt * run.rotation[i];
            Some((i, turn.abs(), b - a - turn))
        })
        .collect()
}

/// The heading at step i the motion model uses: the truth's (odometry2d),
/// the measured one (unicycle2d).
fn model_heading(run: &Run, t: &Truth, i: usize) -> Option<f64> {
    match run.model {
        Model::Odometry2d => t.headings.get(i).copied().flatten(),
        Model::Unicycle2d => Some(run.rotation[i]),
    }
}

/// The true positions at both ends of step i, when the truth has both.
fn ends(t: &Truth, i: usize) -> Option<([f64; 2], [f64; 2])> {
    Some((
        t.positions.get(i).copied()??,
        t.positions.get(i + 1).copied()??,
    ))
}

/// (step, measured speed, along-track true speed) at the steps whose two
/// ends have a true position (and a heading): the true displacement
/// projected on the model's heading, over dt.
pub fn along_track(run: &Run) -> Vec<(usize, f64, f64)> {
    let t = truth(run);
    (0..run.steps())
        .filter_map(|i| {
            let (a, b) = ends(&t, i)?;
            let h = model_heading(run, &t, i)?;
            let u = ((b[0] - a[0]) * h.cos() + (b[1] - a[1]) * h.sin()) / run.dt;
            Some((i, run.speed[i], u))
        })
        .collect()
}

/// The hull of `s·(cos h, sin h)` for s in `[s0, s1]` and h in
/// `[h0, h1]` (h1 - h0 < 2 pi): the corners and the axis crossings.
fn hull(s: [f64; 2], h: [f64; 2]) -> [[f64; 2]; 2] {
    let mut angles = vec![h[0], h[1]];
    let first = (h[0] / (PI / 2.0)).ceil() as i64;
    let last = (h[1] / (PI / 2.0)).floor() as i64;
    for q in first..=last.min(first + 4) {
        angles.push(q as f64 * PI / 2.0);
    }
    let mut b = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
    for &a in &angles {
        for &v in &s {
            let (x, y) = (v * a.cos(), v * a.sin());
            b[0] = [b[0][0].min(x), b[0][1].max(x)];
            b[1] = [b[1][0].min(y), b[1][1].max(y)];
        }
    }
    b
}

/// The speed interval of a step: `[v - e, v + e]`, or `[-(|v| + e),
/// |v| + e]` below the sign threshold.
pub fn speed_interval(v: f64, e: f64, sign_unknown_below: Option<f64>) -> [f64; 2] {
    match sign_unknown_below {
        Some(s) if v.abs() < s => [-(v.abs() + e), v.abs() + e],
        _ => [v - e, v + e],
    }
}

/// The turn the log reports for step i: odometry2d `|turn_rate|·dt`;
/// unicycle2d the measured heading's change to the next step, wrapped
/// (0 at the last step).
pub fn step_turn(run: &Run, i: usize) -> f64 {
    match run.model {
        Model::Odometry2d => (run.rotation[i] * run.dt).abs(),
        Model::Unicycle2d => run
            .rotation
            .get(i + 1)
            .map_or(0.0, |&next| wrap(next - run.rotation[i]).abs()),
    }
}

/// (step, |speed|·dt, the step's turn ([`step_turn`]), per-axis residual)
/// of each step whose ends have a true
/// position (and a heading): the distance, per axis, from the true
/// displacement to the hull of `dt·s·(cos h, sin h)` over the step's
/// speed interval and heading interval (unicycle2d: the measured heading
/// ± `heading_error`; odometry2d: the true heading).
pub fn motion_steps(
    run: &Run,
    speed_error: &dyn Fn(f64) -> f64,
    sign_unknown_below: Option<f64>,
    heading_error: f64,
) -> Vec<(usize, f64, f64, f64)> {
    let t = truth(run);
    (0..run.steps())
        .filter_map(|i| {
            let (a, b) = ends(&t, i)?;
            let h = model_heading(run, &t, i)?;
            let dist = run.speed[i].abs() * run.dt;
            let s = speed_interval(run.speed[i], speed_error(dist), sign_unknown_below);
            let s = [s[0] * run.dt, s[1] * run.dt];
            let box_ = hull(s, [h - heading_error, h + heading_error]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let r = (0..2)
                .map(|k| (box_[k][0] - d[k]).max(d[k] - box_[k][1]).max(0.0))
                .fold(0.0, f64::max);
            Some((i, dist, step_turn(run, i), r))
        })
        .collect()
}

/// The heading drift residuals of windows of k steps (odometry2d): the
/// pairs (i, i + k) with both headings true,
/// `th(i+k) - th(i) - sum dt·turn_rate`; `prefix_turn` may also hold the
/// exempt steps' residuals ([`prefix_turn_exempting`]), which the window
/// then leaves out.
pub fn heading_window(run: &Run, prefix_turn: &[f64], k: usize) -> Vec<f64> {
    heading_window_at(run, prefix_turn, k)
        .into_iter()
        .map(|x| x.1)
        .collect()
}

/// [`heading_window`] with each window's first step: `(i, residual)`.
pub fn heading_window_at(run: &Run, prefix_turn: &[f64], k: usize) -> Vec<(usize, f64)> {
    let t = truth(run);
    let n = run.steps();
    if k > n {
        return Vec::new();
    }
    (0..=n - k)
        .filter_map(|i| {
            let (a, b) = (t.headings[i]?, t.headings[i + k]?);
            Some((i, b - a - (prefix_turn[i + k] - prefix_turn[i])))
        })
        .collect()
}

/// Prefix sums of dt·turn_rate (N + 1).
pub fn prefix_turn(run: &Run) -> Vec<f64> {
    prefix_turn_exempting(run, &[])
}

/// Prefix sums of dt·turn_rate plus, at the `exempt` steps (sorted), the
/// truth's own step residual th(j+1) - th(j) - dt·turn_rate(j): a window
/// over them leaves those steps' residuals out (each bounded by its own
/// heading error instead). An exempt step needs its two true headings.
pub fn prefix_turn_exempting(run: &Run, exempt: &[usize]) -> Vec<f64> {
    let t = truth(run);
    let mut p = vec![0.0];
    for (j, &w) in run.rotation.iter().enumerate() {
        let mut s = run.dt * w;
        if exempt.binary_search(&j).is_ok() {
            if let (Some(a), Some(b)) = (t.headings[j], t.headings[j + 1]) {
                s = b - a;
            }
        }
        p.push(p[j] + s);
    }
    p
}

/// Prefix sums of dt·v·(cos th, sin th) over runs of true headings: an
/// entry is `None` when a heading before it since the last gap is missing;
/// the second array numbers the stretches of known headings: a window
/// whose ends are in one stretch has every heading inside known.
pub fn prefix_motion(run: &Run) -> (Vec<Option<[f64; 2]>>, Vec<usize>) {
    let t = truth(run);
    let n = run.steps();
    let mut p: Vec<Option<[f64; 2]>> = vec![None; n + 1];
    let mut id = vec![0usize; n + 1];
    let (mut acc, mut cur) = ([0.0f64; 2], 0usize);
    for i in 0..=n {
        id[i] = cur;
        p[i] = Some(acc);
        if i == n {
            break;
        }
        match t.headings[i] {
            Some(h) => {
                acc[0] += run.dt * run.speed[i] * h.cos();
                acc[1] += run.dt * run.speed[i] * h.sin();
            }
            None => {
                cur += 1;
                acc = [0.0; 2];
            }
        }
    }
    (p, id)
}

/// The motion drift residuals of windows of k steps (odometry2d): the
/// Euclidean `|p(i+k) - p(i) - sum dt v(j) (cos th(j), sin th(j))|` over
/// the windows whose end positions are true and whose every heading
/// th(i..i+k) is true (both ends in one stretch of [`prefix_motion`]).
pub fn motion_window(
    run: &Run,
    prefix: &(Vec<Option<[f64; 2]>>, Vec<usize>),
    k: usize,
) -> Vec<f64> {
    let (p, id) = prefix;
    let n = run.steps();
    let Some(t) = run.truth.as_ref() else {
        return Vec::new();
    };
    if k > n {
        return Vec::new();
    }
    (0..=n - k)
        .filter(|&i| id[i] == id[i + k])
        .filter_map(|i| {
            let (a, b) = (t.positions[i]?, t.positions[i + k]?);
            let (sa, sb) = (p[i]?, p[i + k]?);
            Some((b[0] - a[0] - (sb[0] - sa[0])).hypot(b[1] - a[1] - (sb[1] - sa[1])))
        })
        .collect()
}

/// One detection's residuals against the truth: (measured range,
/// measured - true range, measured - true bearing wrapped) ([`true_reading`]).
pub fn detection(run: &Run, j: usize, offset: [f64; 2]) -> Option<(f64, f64, Option<f64>)> {
    let (range, bearing) = true_reading(run, j, offset)?;
    let d = &run.detections[j];
    Some((
        d.range,
        d.range - range,
        d.bearing.zip(bearing).map(|(m, t)| wrap(m - t)),
    ))
}

/// The true range and bearing of detection j, from the true pose at its
/// step to its true landmark, when both are known: the sensor sits at
/// `p + R(th)·offset`, th the true heading (or, for unicycle2d without
/// one, the measured heading); the bearing `atan2 - th`, unwrapped.
pub fn true_reading(run: &Run, j: usize, offset: [f64; 2]) -> Option<(f64, Option<f64>)> {
    let t = run.truth.as_ref()?;
    let d = &run.detections[j];
    let p = t.positions.get(d.step).copied()??;
    let h = match (t.headings.get(d.step).copied().flatten(), run.model) {
        (Some(h), _) => h,
        (None, Model::Unicycle2d) => run.rotation[d.step.min(run.steps() - 1)],
        (None, Model::Odometry2d) => return None,
    };
    let l = run.landmark_index(d.landmark?)?;
    let l = run.landmarks.as_ref()?[l].1;
    let (c, s) = (h.cos(), h.sin());
    let sx = p[0] + c * offset[0] - s * offset[1];
    let sy = p[1] + s * offset[0] + c * offset[1];
    let (dx, dy) = (l[0] - sx, l[1] - sy);
    Some((dx.hypot(dy), d.bearing.map(|_| dy.atan2(dx) - h)))
}
