//! The UTIAS "Lost in the Woods" data set (`data/utias-lost-in-the-woods`;
//! `nvector import --utias-woods DIR [--operator]`): a robot without a
//! heading sensor among 17 identical tubes, range-and-bearing detections
//! from a laser ahead of its centre, as an `odometry2d` mission with its
//! truth.
//!
//! Every error bound is derived from the data against the motion-capture
//! truth, with a stated margin (docs/utias-woods.md gives the method and
//! the figures; `meta` records them):
//!
//! - headings: the truth's theta unwrapped into a real heading (consecutive
//!   valid rows differ by less than pi; across a motion-capture gap the
//!   copy closest to the odometry's integral is taken);
//! - the truth is completed across its gaps (heading and position
//!   interpolated linearly between the valid ends; after the last valid row,
//!   dead reckoning) only to derive the bounds of the gap steps: the
//!   mission's truth stays `null` there;
//! - per-step heading and motion errors: the residual of the (completed)
//!   truth against the model; steps whose residual is at most a threshold
//!   are ordinary and share the largest ordinary residual plus a margin;
//!   the others are flagged and get their own residual × 1.5 plus a margin
//!   (the flagged-steps model of docs/cmu-plaza1.md);
//! - ranges and bearings: (measured - true) over every detection at a
//!   valid step bounded on each side by the narrowest line (in the measured
//!   range r for ranges, in 1/r for bearings) that holds every residual,
//!   intersected with the constant band, widened by a margin;
//! - `heading_drift`, `motion_drift`: the truth's largest k-step heading
//!   and (Euclidean) motion residuals over windows, at valid pairs and
//!   over the completed truth, × a factor plus a margin;
//! - `landmark_min_separation`: the smallest true distance between two
//!   tubes less a margin; `scan`: detections at the same time.

use crate::calibrate::convert::{self, Csvs, Span};
use crate::csv::{columns, read_csv, Csv};
use crate::ImportError;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// The bounds' constants (docs/utias-woods.md explains each).
pub mod bounds {
    /// The laser's place ahead of the robot's centre (the data set's d), m.
    pub const SENSOR_OFFSET: f64 = 0.219016;
    /// A heading residual (rad per step) above this flags its step.
    pub const HEADING_FLAG: f64 = 0.02;
    /// Margin on the ordinary heading error (rad).
    pub const HEADING_MARGIN: f64 = 0.005;
    /// A motion residual (m per step and axis) above this flags its step.
    pub const MOTION_FLAG: f64 = 0.02;
    /// Margin on the ordinary motion error (m).
    pub const MOTION_MARGIN: f64 = 0.005;
    /// Margin on a flagged step's own bound (heading rad, motion m), after
    /// the factor [`FLAGGED_FACTOR`].
    pub const FLAGGED_MARGIN: f64 = 0.01;
    /// Factor on a flagged step's residual.
    pub const FLAGGED_FACTOR: f64 = 1.5;
    /// Margin on the range band (m).
    pub const RANGE_MARGIN: f64 = 0.01;
    /// Margin on the bearing band (rad).
    pub const BEARING_MARGIN: f64 = 0.01;
    /// Margin taken off the smallest true distance between tubes (m).
    pub const SEPARATION_MARGIN: f64 = 0.05;
    /// The bearing band in 1/r takes r at least this (m).
    pub const MIN_RANGE_FOR_BEARING_MODEL: f64 = 0.1;
    /// Half-width of the initial position box around the truth (m).
    pub const INITIAL_POSITION_ERROR: f64 = 0.01;
    /// Half-width of the initial heading around the truth (rad).
    pub const INITIAL_HEADING_ERROR: f64 = 0.01;
    /// The heading drift windows (steps): every k of 2..=50 (the gaps
    /// between sightings of a returning landmark), then a geometric
    /// ladder, chosen by measuring the truth's k-step residuals
    /// (docs/utias-woods.md); those up to N are kept.
    pub const DRIFT_SHORT: std::ops::RangeInclusive<usize> = 2..=50;
    pub const DRIFT_LONG: [usize; 9] = [60, 80, 100, 150, 200, 300, 1000, 3000, 10000];
    /// The windows also given without exemptions (the ladder of the plain
    /// windows: over hundreds of steps the exempt steps' own bounds add up
    /// to more than the drift they leave out).
    pub const DRIFT_PLAIN: [usize; 6] = [30, 100, 300, 1000, 3000, 10000];
    /// A step touching an invalid truth row (a gap of the motion capture)
    /// has a heading bound at least the ordinary one plus this (rad), so
    /// the drift windows exempt it: its residual is the completion's
    /// guess, the gap's whole discrepancy spread evenly over its steps,
    /// which would otherwise set the short windows' bounds.
    pub const GAP_HEADING_MARGIN: f64 = 1e-6;
    /// Factor on a window's largest residual.
    pub const DRIFT_FACTOR: f64 = 1.1;
    /// Margin on a window's bound (rad), after the factor.
    pub const DRIFT_MARGIN: f64 = 0.02;
    /// The motion drift windows (steps): every k of 3..=60 (the gaps
    /// between sightings of a returning tube), then a ladder up to 300
    /// steps (docs/utias-woods.md, "Motion drift over windows"); those up
    /// to N are kept.
    pub const MOTION_DRIFT_SHORT: std::ops::RangeInclusive<usize> = 3..=60;
    pub const MOTION_DRIFT_LONG: [usize; 5] = [80, 100, 150, 200, 300];
    /// Factor on a motion window's largest residual.
    pub const MOTION_DRIFT_FACTOR: f64 = 1.1;
    /// Margin on a motion window's bound (m), after the factor.
    pub const MOTION_DRIFT_MARGIN: f64 = 0.01;
}

/// `a` taken into (-pi, pi].
fn wrap(a: f64) -> f64 {
    a - 2.0 * PI * (a / (2.0 * PI)).round()
}

/// Flagged-steps bounds: `(per-step bounds, ordinary bound, flagged count)`.
fn flagged_bounds(residual: &[f64], flag: f64, margin: f64) -> (Vec<f64>, f64, usize) {
    use bounds::*;
    let ordinary = residual
        .iter()
        .filter(|&&r| r <= flag)
        .fold(0.0f64, |a, &r| a.max(r))
        + margin;
    let per_step = residual
        .iter()
        .map(|&r| {
            if r <= flag {
                ordinary
            } else {
                r * FLAGGED_FACTOR + FLAGGED_MARGIN
            }
        })
        .collect();
    let flagged = residual.iter().filter(|&&r| r > flag).count();
    (per_step, ordinary, flagged)
}

/// The line of a band over every point but the `skip` highest above it,
/// slope in [-2, 2]: the calibration's fit
/// ([`crate::calibrate::fit::upper_line_skipping`]).
fn fit_upper_line(points: &[(f64, f64)], skip: usize) -> (f64, f64) {
    crate::calibrate::fit::upper_line_skipping(points, -2.0, 2.0, skip)
}

/// The CSV files of the data set, with the columns the import reads.
struct WoodsFiles {
    odo: (PathBuf, Csv, [usize; 3]),
    truth: (PathBuf, Csv, [usize; 5]),
    meas: (PathBuf, Csv, [usize; 4]),
    lms: (PathBuf, Csv, [usize; 3]),
}

fn read_with<const N: usize>(
    dir: &Path,
    name: &str,
    names: [&str; N],
) -> Result<(PathBuf, Csv, [usize; N]), ImportError> {
    let path = dir.join(name);
    let csv = read_csv(&path, true)?;
    let cols = columns(&csv, &path, &names)?;
    let cols: [usize; N] = cols.try_into().unwrap_or([0; N]);
    Ok((path, csv, cols))
}

fn woods_files(dir: &Path) -> Result<WoodsFiles, ImportError> {
    Ok(WoodsFiles {
        odo: read_with(dir, "odometry.csv", ["t", "v", "om"])?,
        truth: read_with(dir, "truth.csv", ["t", "x", "y", "theta", "valid"])?,
        meas: read_with(
            dir,
            "measurements.csv",
            ["t", "landmark", "range", "bearing"],
        )?,
        lms: read_with(dir, "landmarks.csv", ["landmark", "x", "y"])?,
    })
}

/// The odometry on its time grid and the motion-capture truth.
struct WoodsLog {
    t0: f64,
    dt: f64,
    /// Steps (rows - 1).
    n: usize,
    v: Vec<f64>,
    om: Vec<f64>,
    valid: Vec<bool>,
    /// Unwrapped true headings at valid rows.
    heading: Vec<Option<f64>>,
    position: Vec<Option<[f64; 2]>>,
}

/// Checks the time grid of the odometry and of the truth, and unwraps the
/// true headings.
fn woods_log(f: &WoodsFiles) -> Result<WoodsLog, ImportError> {
    let (odo_p, odo, [ot, ov, oom]) = &f.odo;
    let (truth_p, tru, [tt, tx, ty, tth, tvalid]) = &f.truth;
    let rows = odo.rows.len();
    if rows < 2 {
        return Err(ImportError::file(odo_p, "at least 2 rows are needed"));
    }
    if tru.rows.len() != rows {
        return Err(ImportError::file(
            truth_p,
            format!(
                "{} rows, expected one per odometry row ({rows})",
                tru.rows.len()
            ),
        ));
    }
    let n = rows - 1;
    let t0 = odo.rows[0][*ot];
    let dt = (odo.rows[n][*ot] - t0) / n as f64;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(ImportError::file(odo_p, "times must increase"));
    }
    for (k, (o, t)) in odo.rows.iter().zip(&tru.rows).enumerate() {
        if (o[*ot] - t0 - k as f64 * dt).abs() > dt / 4.0 {
            return Err(ImportError::line(
                odo_p,
                k + 2,
                format!("time {} is not on the grid t0 + k*dt (dt = {dt})", o[*ot]),
            ));
        }
        if (t[*tt] - o[*ot]).abs() > dt / 4.0 {
            return Err(ImportError::line(
                truth_p,
                k + 2,
                format!("time {} differs from the odometry's {}", t[*tt], o[*ot]),
            ));
        }
    }
    let v: Vec<f64> = odo.rows[..n].iter().map(|r| r[*ov]).collect();
    let om: Vec<f64> = odo.rows[..n].iter().map(|r| r[*oom]).collect();
    let valid: Vec<bool> = tru.rows.iter().map(|r| r[*tvalid] != 0.0).collect();
    if !valid[0] {
        return Err(ImportError::line(
            truth_p,
            2,
            "the truth at the first row is not valid (the initial pose comes from it)",
        ));
    }
    let theta: Vec<f64> = tru.rows.iter().map(|r| r[*tth]).collect();
    let heading = unwrap_headings(&theta, &valid, &om, dt);
    let position = tru
        .rows
        .iter()
        .zip(&valid)
        .map(|(r, &ok)| ok.then_some([r[*tx], r[*ty]]))
        .collect();
    Ok(WoodsLog {
        t0,
        dt,
        n,
        v,
        om,
        valid,
        heading,
        position,
    })
}

/// The true headings unwrapped at valid rows: consecutive valid rows
/// differ by less than pi; across a gap the copy closest to the
/// odometry's integral is taken.
fn unwrap_headings(theta: &[f64], valid: &[bool], om: &[f64], dt: f64) -> Vec<Option<f64>> {
    let mut heading: Vec<Option<f64>> = vec![None; theta.len()];
    let mut last = 0usize;
    heading[0] = Some(theta[0]);
    for k in 1..theta.len() {
        if !valid[k] {
            continue;
        }
        let prev = heading[last].unwrap_or(0.0);
        let predicted = prev + (last..k).map(|i| dt * om[i]).sum::<f64>();
        heading[k] = Some(theta[k] + 2.0 * PI * ((predicted - theta[k]) / (2.0 * PI)).round());
        last = k;
    }
    heading
}

/// The truth completed across its gaps (only for the bounds of the gap
/// steps): headings and positions, and the number of gaps.
struct Completed {
    heading: Vec<f64>,
    position: Vec<[f64; 2]>,
    gaps: usize,
}

/// Interpolates linearly between the valid ends of each gap; after the
/// last valid row, dead reckoning.
fn complete_truth(log: &WoodsLog) -> Completed {
    let rows = log.n + 1;
    let (dt, v, om) = (log.dt, &log.v, &log.om);
    let mut ch: Vec<f64> = vec![0.0; rows];
    let mut cp: Vec<[f64; 2]> = vec![[0.0; 2]; rows];
    let mut gaps = 0usize;
    let mut k = 0usize;
    while k < rows {
        if let (Some(h), Some(p)) = (log.heading[k], log.position[k]) {
            ch[k] = h;
            cp[k] = p;
            k += 1;
            continue;
        }
        gaps += 1;
        let a = k - 1;
        match (k..rows).find(|&j| log.valid[j]) {
            Some(b) => {
                let (hb, pb) = (
                    log.heading[b].unwrap_or(0.0),
                    log.position[b].unwrap_or([0.0; 2]),
                );
                for j in k..b {
                    let s = (j - a) as f64 / (b - a) as f64;
                    ch[j] = ch[a] + s * (hb - ch[a]);
                    cp[j] = [
                        cp[a][0] + s * (pb[0] - cp[a][0]),
                        cp[a][1] + s * (pb[1] - cp[a][1]),
                    ];
                }
                k = b;
            }
            None => {
                for j in k..rows {
                    ch[j] = ch[j - 1] + dt * om[j - 1];
                    cp[j] = [
                        cp[j - 1][0] + dt * v[j - 1] * ch[j - 1].cos(),
                        cp[j - 1][1] + dt * v[j - 1] * ch[j - 1].sin(),
                    ];
                }
                k = rows;
            }
        }
    }
    Completed {
        heading: ch,
        position: cp,
        gaps,
    }
}

/// Per-step heading and motion bounds (flagged-steps model), and the
/// number of steps touching a truth gap.
struct WoodsMotion {
    heading: (Vec<f64>, f64, usize),
    motion: (Vec<f64>, f64, usize),
    gap_steps: usize,
}

fn woods_motion(log: &WoodsLog, c: &Completed) -> WoodsMotion {
    use bounds::*;
    let (dt, v, om, ch, cp) = (log.dt, &log.v, &log.om, &c.heading, &c.position);
    let heading_residual: Vec<f64> = (0..log.n)
        .map(|i| (ch[i + 1] - ch[i] - dt * om[i]).abs())
        .collect();
    let motion_residual: Vec<f64> = (0..log.n)
        .map(|i| {
            let ex = cp[i + 1][0] - cp[i][0] - dt * v[i] * ch[i].cos();
            let ey = cp[i + 1][1] - cp[i][1] - dt * v[i] * ch[i].sin();
            ex.abs().max(ey.abs())
        })
        .collect();
    let mut heading = flagged_bounds(&heading_residual, HEADING_FLAG, HEADING_MARGIN);
    let gap = heading.1 + GAP_HEADING_MARGIN;
    let mut gap_steps = 0;
    for (i, e) in heading.0.iter_mut().enumerate() {
        if !(log.valid[i] && log.valid[i + 1]) {
            *e = e.max(gap);
            gap_steps += 1;
        }
    }
    WoodsMotion {
        heading,
        motion: flagged_bounds(&motion_residual, MOTION_FLAG, MOTION_MARGIN),
        gap_steps,
    }
}

/// One heading drift window: k, whether it exempts the steps above the
/// ordinary bound, the truth's largest k-step residual (of the non-exempt
/// steps) at valid pairs (both ends valid) and over the completed truth,
/// and the bound.
struct DriftWindow {
    steps: usize,
    exempt: bool,
    valid_max: f64,
    completed_max: f64,
    error: f64,
}

/// The heading drift windows (`heading_drift`): for each k of
/// [`bounds::DRIFT_SHORT`] and [`bounds::DRIFT_LONG`] up to N a window
/// exempting the steps whose heading bound e_j is above the ordinary one
/// `ordinary` (the flagged steps and those touching a truth gap: each adds
/// its own e_j to the window's bound instead), and for each k of
/// [`bounds::DRIFT_PLAIN`] a window without exemptions. The bound: the
/// largest `|th(i+k) - th(i) - sum dt om - sum of the exempt steps'
/// residuals|` of the truth over the pairs whose ends are both valid, and
/// over the truth completed across its gaps (which the gap checks of
/// tests/cli_woods.rs hold the mission to), the larger one ×
/// [`bounds::DRIFT_FACTOR`] + [`bounds::DRIFT_MARGIN`]. An exempt step's
/// residual is that of the completed truth, the one its e_j bounds, so
/// `|th(i+k) - th(i) - S| <= b + sum of the exempt e_j` holds wherever
/// the non-exempt residuals do. A window whose bound is not below k
/// ordinary bounds says nothing the per-step bounds do not: left out
/// (returned apart). Sums from prefix sums (a rounding of ~1e-13 rad, far
/// below the margin). O(N) per window.
fn woods_drift(
    log: &WoodsLog,
    c: &Completed,
    e: &[f64],
    ordinary: f64,
) -> (Vec<DriftWindow>, Vec<DriftWindow>) {
    use bounds::*;
    let (mut turn, mut exempt) = (vec![0.0f64], vec![0.0f64]);
    for (j, &w) in log.om.iter().enumerate() {
        turn.push(turn[j] + log.dt * w);
        let r = c.heading[j + 1] - c.heading[j] - log.dt * w;
        exempt.push(exempt[j] + if e[j] > ordinary { r } else { 0.0 });
    }
    let zero = vec![0.0f64; log.n + 1];
    let window = |k: usize, exempting: bool| {
        let x = if exempting { &exempt } else { &zero };
        let (mut valid_max, mut completed_max) = (0.0f64, 0.0f64);
        for i in 0..=log.n - k {
            let s = turn[i + k] - turn[i] + x[i + k] - x[i];
            if let (Some(a), Some(b)) = (log.heading[i], log.heading[i + k]) {
                valid_max = valid_max.max((b - a - s).abs());
            }
            let r = c.heading[i + k] - c.heading[i] - s;
            completed_max = completed_max.max(r.abs());
        }
        DriftWindow {
            steps: k,
            exempt: exempting,
            valid_max,
            completed_max,
            error: valid_max.max(completed_max) * DRIFT_FACTOR + DRIFT_MARGIN,
        }
    };
    let exempting = DRIFT_SHORT.chain(DRIFT_LONG).map(|k| (k, true));
    let plain = DRIFT_PLAIN.into_iter().map(|k| (k, false));
    exempting
        .chain(plain)
        .filter(|&(k, _)| k <= log.n)
        .map(|(k, x)| window(k, x))
        .partition(|w| w.error < w.steps as f64 * ordinary)
}

/// One motion drift window: k, the truth's largest Euclidean k-step
/// residual at valid pairs (both ends valid) and over the completed truth,
/// and the bound.
struct MotionWindow {
    steps: usize,
    valid_max: f64,
    completed_max: f64,
    error: f64,
}

/// The motion drift windows (`motion_drift`): for each k of
/// [`bounds::MOTION_DRIFT_SHORT`] and [`bounds::MOTION_DRIFT_LONG`] up to
/// N, the largest Euclidean residual
/// `|p(i+k) - p(i) - sum_{j=i}^{i+k-1} dt v(j) (cos th(j), sin th(j))|`
/// of the truth over the pairs whose two ends are valid rows (the
/// headings inside from the completed truth: the true heading is what the
/// statement quantifies, the completion its witness) and over the truth
/// completed across its gaps (which tests/cli_woods.rs holds the mission
/// to), the larger one × [`bounds::MOTION_DRIFT_FACTOR`] +
/// [`bounds::MOTION_DRIFT_MARGIN`]. The speed's error is 0 (the
/// odometry's speed is the true one of the model). A window whose bound is
/// not below k × `ordinary` × √2 (k per-step bounds per axis, in any
/// rotated frame) says nothing the per-step bounds do not: left out
/// (returned apart). Sums from prefix sums of `dt v cos th`, `dt v sin th`
/// (a rounding of ~1e-12 m over the log, far below the margin). O(N) per
/// window.
fn woods_motion_drift(
    log: &WoodsLog,
    c: &Completed,
    ordinary: f64,
) -> (Vec<MotionWindow>, Vec<MotionWindow>) {
    use bounds::*;
    let (mut sx, mut sy) = (vec![0.0f64], vec![0.0f64]);
    for (j, &v) in log.v.iter().enumerate() {
        let h = c.heading[j];
        sx.push(sx[j] + log.dt * v * h.cos());
        sy.push(sy[j] + log.dt * v * h.sin());
    }
    let cp = &c.position;
    let window = |k: usize| {
        let (mut valid_max, mut completed_max) = (0.0f64, 0.0f64);
        for i in 0..=log.n - k {
            let (dx, dy) = (sx[i + k] - sx[i], sy[i + k] - sy[i]);
            if let (Some(a), Some(b)) = (log.position[i], log.position[i + k]) {
                let r = (b[0] - a[0] - dx).hypot(b[1] - a[1] - dy);
                valid_max = valid_max.max(r);
            }
            let r = (cp[i + k][0] - cp[i][0] - dx).hypot(cp[i + k][1] - cp[i][1] - dy);
            completed_max = completed_max.max(r);
        }
        MotionWindow {
            steps: k,
            valid_max,
            completed_max,
            error: valid_max.max(completed_max) * MOTION_DRIFT_FACTOR + MOTION_DRIFT_MARGIN,
        }
    };
    MOTION_DRIFT_SHORT
        .chain(MOTION_DRIFT_LONG)
        .filter(|&k| k <= log.n)
        .map(window)
        .partition(|w| w.error < w.steps as f64 * ordinary * std::f64::consts::SQRT_2)
}

/// `motion_drift` and its `meta.motion_drift` (method, constants, each
/// window's figures, the windows left out).
fn woods_motion_drift_meta(m: &mut Value, log: &WoodsLog, c: &Completed, motion: &WoodsMotion) {
    let ordinary = motion.motion.1;
    let (drift, dropped) = woods_motion_drift(log, c, ordinary);
    m["motion_drift"] = drift
        .iter()
        .map(|w| json!({"steps": w.steps, "error": w.error}))
        .collect();
    let figures = |ws: &[MotionWindow]| {
        ws.iter()
            .map(|w| json!({"steps": w.steps, "valid_max": w.valid_max, "completed_max": w.completed_max, "error": w.error}))
            .collect::<Vec<_>>()
    };
    m["meta"]["motion_drift"] = json!({
        "method": "per window of k steps: the largest Euclidean |p(i+k) - p(i) - sum_{j=i}^{i+k-1} dt v(j) (cos th(j), sin th(j))| of the truth over the pairs with both ends valid (the headings inside from the completed truth) and over the truth completed across its gaps (linear interpolation), the larger one x factor + margin; a window whose bound is not below k x the ordinary per-step motion bound x sqrt 2 (what the per-axis per-step bounds give in any rotated frame) is left out (`dropped`)",
        "factor": bounds::MOTION_DRIFT_FACTOR,
        "margin": bounds::MOTION_DRIFT_MARGIN,
        "ordinary": ordinary,
        "windows": figures(&drift),
        "dropped": figures(&dropped),
    });
}

/// The tubes, indexed by their label, and the smallest true distance
/// between two of them.
fn woods_landmarks(f: &WoodsFiles) -> Result<(Vec<[f64; 2]>, f64), ImportError> {
    let (lm_p, lms, [ll, lx, ly]) = &f.lms;
    let count = lms.rows.len();
    let mut landmarks = vec![[f64::NAN; 2]; count];
    for (i, r) in lms.rows.iter().enumerate() {
        let id = r[*ll];
        if id < 0.0 || id.fract() != 0.0 || id as usize >= count {
            return Err(ImportError::line(
                lm_p,
                i + 2,
                format!("landmark {id} is not an integer in 0..{count}"),
            ));
        }
        landmarks[id as usize] = [r[*lx], r[*ly]];
    }
    if landmarks.iter().any(|l| l[0].is_nan()) {
        return Err(ImportError::file(
            lm_p,
            format!("the labels must be 0..{count}, each once"),
        ));
    }
    let mut separation = f64::INFINITY;
    for a in 0..count {
        for b in a + 1..count {
            let d = (landmarks[a][0] - landmarks[b][0]).hypot(landmarks[a][1] - landmarks[b][1]);
            separation = separation.min(d);
        }
    }
    Ok((landmarks, separation))
}

/// A detection: step, label, measured range and bearing, and its
/// (range, bearing) residuals against the truth when its step has one.
struct WoodsDetection {
    step: usize,
    id: usize,
    range: f64,
    bearing: f64,
    residual: Option<(f64, f64)>,
}

fn woods_detections(
    f: &WoodsFiles,
    log: &WoodsLog,
    landmarks: &[[f64; 2]],
) -> Result<Vec<WoodsDetection>, ImportError> {
    use bounds::*;
    let (meas_p, meas, [mt, ml, mr, mb]) = &f.meas;
    let (t0, dt, n, count) = (log.t0, log.dt, log.n, landmarks.len());
    let mut dets = Vec::with_capacity(meas.rows.len());
    for (i, r) in meas.rows.iter().enumerate() {
        let line = i + 2;
        let step = ((r[*mt] - t0) / dt).round();
        if !(0.0..=n as f64).contains(&step) || (r[*mt] - t0 - step * dt).abs() > dt / 4.0 {
            return Err(ImportError::line(
                meas_p,
                line,
                format!("time {} is not one of the odometry times", r[*mt]),
            ));
        }
        let step = step as usize;
        let id = r[*ml];
        if id < 0.0 || id.fract() != 0.0 || id as usize >= count {
            return Err(ImportError::line(
                meas_p,
                line,
                format!("landmark {id} is not an integer in 0..{count}"),
            ));
        }
        let (id, range, bearing) = (id as usize, r[*mr], r[*mb]);
        if range < 0.0 {
            return Err(ImportError::line(
                meas_p,
                line,
                format!("range {range} is negative"),
            ));
        }
        let residual = match (log.position[step], log.heading[step]) {
            (Some(p), Some(h)) => {
                let s = [
                    p[0] + SENSOR_OFFSET * h.cos(),
                    p[1] + SENSOR_OFFSET * h.sin(),
                ];
                let (dx, dy) = (landmarks[id][0] - s[0], landmarks[id][1] - s[1]);
                Some((range - dx.hypot(dy), wrap(bearing - (dy.atan2(dx) - h))))
            }
            _ => None,
        };
        dets.push(WoodsDetection {
            step,
            id,
            range,
            bearing,
            residual,
        });
    }
    if dets.iter().all(|d| d.residual.is_none()) {
        return Err(ImportError::file(
            meas_p,
            "no detection at a step with valid truth: no bound can be derived",
        ));
    }
    Ok(dets)
}

/// One residual band: (measured - true) between `-(lower.0 + lower.1 x)`
/// and `upper.0 + upper.1 x` (x the measured range, or its inverse), and
/// within `constant`.
#[derive(Clone, Copy)]
struct Band {
    upper: (f64, f64),
    lower: (f64, f64),
    constant: (f64, f64),
}

impl Band {
    /// Fits the band on `(x, residual)` points leaving `skip_lo` points
    /// below and `skip_hi` above (both 0: every point inside).
    fn fit(points: &[(f64, f64)], skip_lo: usize, skip_hi: usize) -> Band {
        let mut sorted: Vec<f64> = points.iter().map(|p| p.1).collect();
        sorted.sort_unstable_by(f64::total_cmp);
        let last = sorted.len() - 1;
        let negated: Vec<(f64, f64)> = points.iter().map(|p| (p.0, -p.1)).collect();
        Band {
            upper: fit_upper_line(points, skip_hi),
            lower: fit_upper_line(&negated, skip_lo),
            constant: (sorted[skip_lo.min(last)], sorted[last - skip_hi.min(last)]),
        }
    }

    /// The residual's interval at `x`.
    fn at(&self, x: f64) -> (f64, f64) {
        (
            self.constant.0.max(-(self.lower.0 + self.lower.1 * x)),
            self.constant.1.min(self.upper.0 + self.upper.1 * x),
        )
    }
}

/// The range and bearing bands of the import (module doc), each holding
/// the central (1 - share) of the residuals at valid steps.
struct WoodsBands {
    range: Band,
    bearing: Band,
}

fn inverse(r: f64) -> f64 {
    1.0 / r.max(bounds::MIN_RANGE_FOR_BEARING_MODEL)
}

fn woods_bands(dets: &[WoodsDetection], share: f64) -> WoodsBands {
    let residuals: Vec<(f64, f64, f64)> = dets
        .iter()
        .filter_map(|d| d.residual.map(|(re, be)| (d.range, re, be)))
        .collect();
    let dropped = (share * residuals.len() as f64).floor() as usize;
    let (lo, hi) = (dropped / 2, dropped - dropped / 2);
    let ranges: Vec<(f64, f64)> = residuals.iter().map(|p| (p.0, p.1)).collect();
    let bearings: Vec<(f64, f64)> = residuals.iter().map(|p| (inverse(p.0), p.2)).collect();
    WoodsBands {
        range: Band::fit(&ranges, lo, hi),
        bearing: Band::fit(&bearings, lo, hi),
    }
}

impl WoodsBands {
    /// The (range, bearing) intervals of a detection, margins included.
    fn intervals(&self, range: f64, bearing: f64) -> ([f64; 2], [f64; 2]) {
        use bounds::*;
        let (elo, ehi) = self.range.at(range);
        let (blo, bhi) = self.bearing.at(inverse(range));
        (
            [
                (range - ehi - RANGE_MARGIN).max(0.0),
                range - elo + RANGE_MARGIN,
            ],
            [
                bearing - bhi - BEARING_MARGIN,
                bearing - blo + BEARING_MARGIN,
            ],
        )
    }

    /// Whether a detection's truth (its residuals) is outside its
    /// intervals.
    fn outside(&self, d: &WoodsDetection) -> bool {
        let Some((re, be)) = d.residual else {
            return false;
        };
        let (r, b) = self.intervals(d.range, d.bearing);
        let truth = d.range - re;
        let (elo, ehi) = (d.bearing - b[1], d.bearing - b[0]);
        !(r[0] <= truth && truth <= r[1] && elo <= be && be <= ehi)
    }
}

/// The Lost in the Woods data set in `dir` as a mission (tube labels kept
/// as the operator's matching when `operator`), with the truth. With
/// `outlier_share` P > 0 the range and bearing bands hold the central
/// (1 - P) share of the residuals each, and `max_outliers` is the count of
/// detections (at steps with a truth) left outside either.
pub fn utias_woods(dir: &Path, operator: bool, outlier_share: f64) -> Result<Value, ImportError> {
    crate::check_outlier_share(outlier_share)?;
    let files = woods_files(dir)?;
    let log = woods_log(&files)?;
    let completed = complete_truth(&log);
    let motion = woods_motion(&log, &completed);
    let (landmarks, separation) = woods_landmarks(&files)?;
    let dets = woods_detections(&files, &log, &landmarks)?;
    let bands = woods_bands(&dets, outlier_share);
    let detections: Vec<Value> = dets
        .iter()
        .map(|d| {
            let (range, bearing) = bands.intervals(d.range, d.bearing);
            let mut v = json!({"step": d.step, "range": range, "bearing": bearing, "scan": d.step});
            if operator {
                v["landmark"] = json!(d.id);
            }
            v
        })
        .collect();
    let mut m = woods_document(operator, &log, &completed, &motion, detections);
    woods_meta(&mut m["meta"], &dets, &bands, separation);
    m["meta"]["truth_gaps"] = json!(completed.gaps);
    woods_drift_meta(&mut m, &log, &completed, &motion);
    woods_motion_drift_meta(&mut m, &log, &completed, &motion);
    m["landmark_count"] = json!(landmarks.len());
    m["landmark_min_separation"] = json!(separation - bounds::SEPARATION_MARGIN);
    m["truth"]["landmarks"] = json!(landmarks);
    m["truth"]["matching"] = json!(dets.iter().map(|d| d.id).collect::<Vec<_>>());
    if outlier_share > 0.0 {
        let outside: Vec<usize> = (0..dets.len())
            .filter(|&j| bands.outside(&dets[j]))
            .collect();
        m["max_outliers"] = json!(outside.len());
        m["meta"]["outlier_share"] = json!({
            "share": outlier_share,
            "method": "each band (range, bearing) holds the central (1 - share) of the residuals at steps with a truth: floor(share k / 2) below and the rest of floor(share k) above left out of the lines and of the constant band; `outside` lists the detections (by index) whose truth is outside their range or bearing interval, margins included, and max_outliers is their count (detections at steps without a truth are taken inside, as with share 0)",
            "outside": outside,
        });
    }
    crate::validated(m)
}

/// `heading_drift` and its `meta.heading_drift` (method, constants, each
/// window's figures, the windows left out).
fn woods_drift_meta(m: &mut Value, log: &WoodsLog, c: &Completed, motion: &WoodsMotion) {
    let ordinary = motion.heading.1;
    let (drift, dropped) = woods_drift(log, c, &motion.heading.0, ordinary);
    m["heading_drift"] = drift
        .iter()
        .map(|w| match w.exempt {
            true => json!({"steps": w.steps, "error": w.error, "exempt_above": ordinary}),
            false => json!({"steps": w.steps, "error": w.error}),
        })
        .collect();
    let figures = |ws: &[DriftWindow]| {
        ws.iter()
            .map(|w| json!({"steps": w.steps, "exempt": w.exempt, "valid_max": w.valid_max, "completed_max": w.completed_max, "error": w.error}))
            .collect::<Vec<_>>()
    };
    m["meta"]["heading_drift"] = json!({
        "method": "per window of k steps (with exempt_above = the ordinary per-step heading bound: the flagged steps and the steps touching a truth gap, whose heading_error is above it, each add their own heading_error to the window's bound; or without exemptions): the largest |th(i+k) - th(i) - sum_{j=i}^{i+k-1} dt om(j) - sum of the exempt steps' residuals (of the completed truth)| of the truth over the pairs with both ends valid and over the truth completed across its gaps (linear interpolation), the larger one x factor + margin; a window whose bound is not below k ordinary bounds is left out (`dropped`)",
        "factor": bounds::DRIFT_FACTOR,
        "margin": bounds::DRIFT_MARGIN,
        "exempt_above": ordinary,
        "gap_heading_margin": bounds::GAP_HEADING_MARGIN,
        "gap_steps": motion.gap_steps,
        "windows": figures(&drift),
        "dropped": figures(&dropped),
    });
}

/// The mission document around the detections (`meta` holds the motion
/// bounds; the caller adds the detection bands, landmarks and matching).
fn woods_document(
    operator: bool,
    log: &WoodsLog,
    c: &Completed,
    motion: &WoodsMotion,
    detections: Vec<Value>,
) -> Value {
    use bounds::*;
    let (p0, h0) = (c.position[0], c.heading[0]);
    let (e0, eh) = (INITIAL_POSITION_ERROR, INITIAL_HEADING_ERROR);
    let (heading, motion_b) = (&motion.heading, &motion.motion);
    json!({
        "format": "nvector-mission/1",
        "name": if operator { "utias-woods-operator" } else { "utias-woods" },
        "model": "odometry2d",
        "dt": log.dt,
        "steps": log.n,
        "initial_position": [[p0[0] - e0, p0[0] + e0], [p0[1] - e0, p0[1] + e0]],
        "final_position": null,
        "initial_heading": [h0 - eh, h0 + eh],
        "inputs": {
            "speed": {"value": log.v, "error": 0.0},
            "turn_rate": {"value": log.om, "error": 0.0},
        },
        "heading_error": heading.0,
        "motion_error": motion_b.0,
        "sensor_offset": [SENSOR_OFFSET, 0.0],
        "detections": detections,
        "meta": {
            "source": "UTIAS Lost in the Woods (dataset2.mat of T. D. Barfoot's AER1513 course, utiasASRL/aer1513, Apache-2.0), as CSV in data/utias-lost-in-the-woods of the nvector repository",
            "method": "every bound from the data against the motion-capture truth (docs/utias-woods.md): per-step residuals of the truth, completed across its gaps by linear interpolation, against the odometry2d model; steps above a threshold flagged with their own residual x 1.5 + margin; ranges and bearings: measured - true over every detection at a valid step, bounded by the narrowest lines in r (ranges) and 1/r (bearings) holding every residual, within the constant band, plus a margin",
            "heading_error": {"ordinary": heading.1, "flag_above": HEADING_FLAG, "margin": HEADING_MARGIN, "flagged_steps": heading.2, "flagged_factor": FLAGGED_FACTOR, "flagged_margin": FLAGGED_MARGIN},
            "motion_error": {"ordinary": motion_b.1, "flag_above": MOTION_FLAG, "margin": MOTION_MARGIN, "flagged_steps": motion_b.2, "flagged_factor": FLAGGED_FACTOR, "flagged_margin": FLAGGED_MARGIN},
            "speed_error": 0.0,
            "turn_rate_error": 0.0,
            "invalid_truth_rows": log.valid.iter().filter(|&&ok| !ok).count(),
            "initial_position_error": e0,
            "initial_heading_error": eh,
            "headings": "the truth's theta unwrapped: a real heading, not taken modulo 2 pi",
            "calibration": {
                "source": "UTIAS Lost in the Woods, this run",
                "same_run": true,
                "method": "oracle: every bound fitted on this run's own truth (docs/utias-woods.md): per-step bounds with the flagged steps found by the truth, drift windows and bands over the whole run; `nvector calibrate` fits the per-robot bounds that transfer to other runs (docs/calibration.md)",
            },
        },
        "truth": {
            "positions": log.position.iter().map(|p| p.map_or(Value::Null, |p| json!(p))).collect::<Vec<_>>(),
            "headings": log.heading.iter().map(|h| h.map_or(Value::Null, |h| json!(h))).collect::<Vec<_>>(),
        },
    })
}

/// The detection bands' figures in `meta`.
fn woods_meta(meta: &mut Value, dets: &[WoodsDetection], bands: &WoodsBands, separation: f64) {
    use bounds::*;
    let span = |f: fn((f64, f64)) -> f64| {
        dets.iter()
            .filter_map(|d| d.residual.map(f))
            .fold([f64::INFINITY, f64::NEG_INFINITY], |a, e| {
                [a[0].min(e), a[1].max(e)]
            })
    };
    let (r, b) = (&bands.range, &bands.bearing);
    let fields = json!({
        "range_error_bounds": span(|x| x.0),
        "range_error_model": {"residual": "measured - true range, between -(lower[0] + lower[1] r) and upper[0] + upper[1] r (r the measured range), and within range_error_bounds", "upper": [r.upper.0, r.upper.1], "lower": [r.lower.0, r.lower.1]},
        "bearing_error_model": {"residual": "measured - true bearing (wrapped), between -(lower[0] + lower[1] / r) and upper[0] + upper[1] / r (r the measured range, at least 0.1 m), and within bearing_error_bounds", "upper": [b.upper.0, b.upper.1], "lower": [b.lower.0, b.lower.1]},
        "range_margin": RANGE_MARGIN,
        "bearing_error_bounds": span(|x| x.1),
        "bearing_margin": BEARING_MARGIN,
        "detections_checked": dets.iter().filter(|d| d.residual.is_some()).count(),
        "true_min_separation": separation,
        "separation_margin": SEPARATION_MARGIN,
    });
    if let (Some(meta), Value::Object(fields)) = (meta.as_object_mut(), fields) {
        meta.extend(fields);
    }
}

/// The data set in `dir` over `span` as the calibration's four CSVs
/// (docs/calibration.md), read as [`utias_woods`] reads it: the log
/// `t,speed,turn_rate` (odometry2d), one row per step; the detections
/// `t,range,bearing,scan,landmark` (scan: the step, the detections of one
/// time); the truth `t,x,y,heading` at the span's steps and the end pose,
/// the heading unwrapped into a real number, the rows the motion capture
/// marks invalid left empty; the tubes `id,x,y`.
pub fn calibration_csvs(dir: &Path, span: Span) -> Result<Csvs, ImportError> {
    use std::fmt::Write as _;
    let files = woods_files(dir)?;
    let log = woods_log(&files)?;
    let (landmarks, _) = woods_landmarks(&files)?;
    let dets = woods_detections(&files, &log, &landmarks)?;
    let t: Vec<f64> = (0..=log.n)
        .map(|k| files.odo.1.rows[k][files.odo.2[0]])
        .collect();
    let (a, b) = convert::rows(&t, span, &files.odo.0)?;
    let end = b.min(log.n);
    let mut out = Csvs {
        log: "t,speed,turn_rate\n".into(),
        detections: "t,range,bearing,scan,landmark\n".into(),
        truth: "t,x,y,heading\n".into(),
        landmarks: "id,x,y\n".into(),
    };
    for ((ti, v), om) in t[a..end].iter().zip(&log.v[a..end]).zip(&log.om[a..end]) {
        let _ = writeln!(out.log, "{ti},{v},{om}");
    }
    let truth = log.position[a..=end].iter().zip(&log.heading[a..=end]);
    for (ti, (p, h)) in t[a..=end].iter().zip(truth) {
        let _ = writeln!(
            out.truth,
            "{ti},{},{},{}",
            convert::cell(p.map(|p| p[0])),
            convert::cell(p.map(|p| p[1])),
            convert::cell(*h)
        );
    }
    for d in dets.iter().filter(|d| (a..=end).contains(&d.step)) {
        let _ = writeln!(
            out.detections,
            "{},{},{},{},{}",
            t[d.step], d.range, d.bearing, d.step, d.id
        );
    }
    for (id, l) in landmarks.iter().enumerate() {
        let _ = writeln!(out.landmarks, "{id},{},{}", l[0], l[1]);
    }
    Ok(out)
}
