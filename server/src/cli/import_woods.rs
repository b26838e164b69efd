//! `nvector import --utias-woods DIR [--operator]`: the UTIAS "Lost in the
//! Woods" data set (a robot without a heading sensor among 17 identical
//! tubes, range-and-bearing detections from a laser ahead of its centre)
//! as an `odometry2d` mission with its truth.
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
//! - `landmark_min_separation`: the smallest true distance between two
//!   tubes less a margin; `scan`: detections at the same time.

use crate::cli::import::read_csv;
use crate::CliError;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::Path;

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
}

/// `a` taken into (-pi, pi].
fn wrap(a: f64) -> f64 {
    a - 2.0 * PI * (a / (2.0 * PI)).round()
}

/// The columns of a CSV by name, or an error naming the file and column.
fn columns(
    csv: &crate::cli::import::Csv,
    path: &Path,
    names: &[&str],
) -> Result<Vec<usize>, CliError> {
    names
        .iter()
        .map(|n| {
            csv.header.iter().position(|h| h == n).ok_or_else(|| {
                CliError(format!(
                    "{}: missing column '{n}' in the header",
                    path.display()
                ))
            })
        })
        .collect()
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

/// The line `y <= a + b·x` over every point `(x, y)` with the smallest mean
/// `a + b·mean(x)` (the bound's mean over the points): for a slope b the
/// least a is `max(y - b·x)`, and the mean is convex in b (a maximum of
/// linear functions plus a linear one), so a ternary search over
/// b in [-2, 2] finds it. Returns `(a, b)`.
fn fit_upper_line(points: &[(f64, f64)]) -> (f64, f64) {
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / points.len().max(1) as f64;
    let a_of = |b: f64| {
        points
            .iter()
            .fold(f64::NEG_INFINITY, |m, &(x, y)| m.max(y - b * x))
    };
    let cost = |b: f64| a_of(b) + b * mean_x;
    let (mut lo, mut hi) = (-2.0f64, 2.0f64);
    for _ in 0..200 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if cost(m1) <= cost(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let b = (lo + hi) / 2.0;
    (a_of(b), b)
}

/// The Lost in the Woods data set in `dir` as a mission (tube labels kept
/// as the operator's matching when `operator`), with the truth.
pub fn utias_woods(dir: &Path, operator: bool) -> Result<Value, CliError> {
    use bounds::*;
    let (odo_p, truth_p, meas_p, lm_p) = (
        dir.join("odometry.csv"),
        dir.join("truth.csv"),
        dir.join("measurements.csv"),
        dir.join("landmarks.csv"),
    );
    let odo = read_csv(&odo_p, true)?;
    let tru = read_csv(&truth_p, true)?;
    let meas = read_csv(&meas_p, true)?;
    let lms = read_csv(&lm_p, true)?;
    let [ot, ov, oom] = columns(&odo, &odo_p, &["t", "v", "om"])?[..] else {
        unreachable!()
    };
    let [tt, tx, ty, tth, tvalid] =
        columns(&tru, &truth_p, &["t", "x", "y", "theta", "valid"])?[..]
    else {
        unreachable!()
    };
    let [mt, ml, mr, mb] = columns(&meas, &meas_p, &["t", "landmark", "range", "bearing"])?[..]
    else {
        unreachable!()
    };
    let [ll, lx, ly] = columns(&lms, &lm_p, &["landmark", "x", "y"])?[..] else {
        unreachable!()
    };
    let rows = odo.rows.len();
    if rows < 2 {
        return Err(CliError(format!(
            "{}: at least 2 rows are needed",
            odo_p.display()
        )));
    }
    if tru.rows.len() != rows {
        return Err(CliError(format!(
            "{}: {} rows, expected one per odometry row ({rows})",
            truth_p.display(),
            tru.rows.len()
        )));
    }
    let n = rows - 1;
    let t0 = odo.rows[0][ot];
    let dt = (odo.rows[n][ot] - t0) / n as f64;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(CliError(format!(
            "{}: times must increase",
            odo_p.display()
        )));
    }
    for (k, (o, t)) in odo.rows.iter().zip(&tru.rows).enumerate() {
        if (o[ot] - t0 - k as f64 * dt).abs() > dt / 4.0 {
            return Err(CliError(format!(
                "{}:{}: time {} is not on the grid t0 + k*dt (dt = {dt})",
                odo_p.display(),
                k + 2,
                o[ot]
            )));
        }
        if (t[tt] - o[ot]).abs() > dt / 4.0 {
            return Err(CliError(format!(
                "{}:{}: time {} differs from the odometry's {}",
                truth_p.display(),
                k + 2,
                t[tt],
                o[ot]
            )));
        }
    }
    let v: Vec<f64> = odo.rows[..n].iter().map(|r| r[ov]).collect();
    let om: Vec<f64> = odo.rows[..n].iter().map(|r| r[oom]).collect();
    let valid: Vec<bool> = tru.rows.iter().map(|r| r[tvalid] != 0.0).collect();
    if !valid[0] {
        return Err(CliError(format!(
            "{}:2: the truth at the first row is not valid (the initial pose comes from it)",
            truth_p.display()
        )));
    }
    // Unwrapped true headings at valid rows.
    let mut heading: Vec<Option<f64>> = vec![None; rows];
    let mut last = 0usize;
    heading[0] = Some(tru.rows[0][tth]);
    for k in 1..rows {
        if !valid[k] {
            continue;
        }
        let prev = heading[last].unwrap_or(0.0);
        let raw = tru.rows[k][tth];
        let predicted = prev + (last..k).map(|i| dt * om[i]).sum::<f64>();
        heading[k] = Some(raw + 2.0 * PI * ((predicted - raw) / (2.0 * PI)).round());
        last = k;
    }
    let position: Vec<Option<[f64; 2]>> = tru
        .rows
        .iter()
        .zip(&valid)
        .map(|(r, &ok)| ok.then_some([r[tx], r[ty]]))
        .collect();
    // The completed truth (only for the bounds of the gap steps).
    let mut ch: Vec<f64> = vec![0.0; rows];
    let mut cp: Vec<[f64; 2]> = vec![[0.0; 2]; rows];
    let mut gaps = 0usize;
    let mut k = 0usize;
    while k < rows {
        if let (Some(h), Some(p)) = (heading[k], position[k]) {
            ch[k] = h;
            cp[k] = p;
            k += 1;
            continue;
        }
        gaps += 1;
        let a = k - 1;
        let b = (k..rows).find(|&j| valid[j]);
        match b {
            Some(b) => {
                let (hb, pb) = (heading[b].unwrap_or(0.0), position[b].unwrap_or([0.0; 2]));
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
    // Per-step residuals of the completed truth against the model.
    let heading_residual: Vec<f64> = (0..n)
        .map(|i| (ch[i + 1] - ch[i] - dt * om[i]).abs())
        .collect();
    let motion_residual: Vec<f64> = (0..n)
        .map(|i| {
            let ex = cp[i + 1][0] - cp[i][0] - dt * v[i] * ch[i].cos();
            let ey = cp[i + 1][1] - cp[i][1] - dt * v[i] * ch[i].sin();
            ex.abs().max(ey.abs())
        })
        .collect();
    let (heading_error, heading_ordinary, heading_flagged) =
        flagged_bounds(&heading_residual, HEADING_FLAG, HEADING_MARGIN);
    let (motion_error, motion_ordinary, motion_flagged) =
        flagged_bounds(&motion_residual, MOTION_FLAG, MOTION_MARGIN);
    // Landmarks, indexed by their label.
    let count = lms.rows.len();
    let mut landmarks = vec![[f64::NAN; 2]; count];
    for (i, r) in lms.rows.iter().enumerate() {
        let id = r[ll];
        if id < 0.0 || id.fract() != 0.0 || id as usize >= count {
            return Err(CliError(format!(
                "{}:{}: landmark {id} is not an integer in 0..{count}",
                lm_p.display(),
                i + 2
            )));
        }
        landmarks[id as usize] = [r[lx], r[ly]];
    }
    if landmarks.iter().any(|l| l[0].is_nan()) {
        return Err(CliError(format!(
            "{}: the labels must be 0..{count}, each once",
            lm_p.display()
        )));
    }
    let mut separation = f64::INFINITY;
    for a in 0..count {
        for b in a + 1..count {
            let d = (landmarks[a][0] - landmarks[b][0]).hypot(landmarks[a][1] - landmarks[b][1]);
            separation = separation.min(d);
        }
    }
    // Detections: step, label, range, bearing; residuals at valid steps.
    let mut dets = Vec::with_capacity(meas.rows.len());
    let (mut rmin, mut rmax, mut bmin, mut bmax) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    let mut checked = 0usize;
    // (measured range, range residual, bearing residual) at valid steps.
    let mut residuals: Vec<(f64, f64, f64)> = Vec::with_capacity(meas.rows.len());
    for (i, r) in meas.rows.iter().enumerate() {
        let line = i + 2;
        let step = ((r[mt] - t0) / dt).round();
        if !(0.0..=n as f64).contains(&step) || (r[mt] - t0 - step * dt).abs() > dt / 4.0 {
            return Err(CliError(format!(
                "{}:{line}: time {} is not one of the odometry times",
                meas_p.display(),
                r[mt]
            )));
        }
        let step = step as usize;
        let id = r[ml];
        if id < 0.0 || id.fract() != 0.0 || id as usize >= count {
            return Err(CliError(format!(
                "{}:{line}: landmark {id} is not an integer in 0..{count}",
                meas_p.display()
            )));
        }
        let (id, range, bearing) = (id as usize, r[mr], r[mb]);
        if range < 0.0 {
            return Err(CliError(format!(
                "{}:{line}: range {range} is negative",
                meas_p.display()
            )));
        }
        if let (Some(p), Some(h)) = (position[step], heading[step]) {
            let s = [
                p[0] + SENSOR_OFFSET * h.cos(),
                p[1] + SENSOR_OFFSET * h.sin(),
            ];
            let (dx, dy) = (landmarks[id][0] - s[0], landmarks[id][1] - s[1]);
            let re = range - dx.hypot(dy);
            let be = wrap(bearing - (dy.atan2(dx) - h));
            (rmin, rmax) = (rmin.min(re), rmax.max(re));
            (bmin, bmax) = (bmin.min(be), bmax.max(be));
            residuals.push((range, re, be));
            checked += 1;
        }
        dets.push((step, id, range, bearing));
    }
    if checked == 0 {
        return Err(CliError(format!(
            "{}: no detection at a step with valid truth: no bound can be derived",
            meas_p.display()
        )));
    }
    // Residual bands that depend on the measured range r: the range
    // residual between two lines in r, the bearing residual between two
    // lines in 1/r (a lateral error of the truth or of the tube's centre
    // turns into a bearing error that shrinks with the range), each the
    // narrowest on average over the detections ([`fit_upper_line`]), and
    // intersected with the constant bands (both hold every residual).
    let inverse = |r: f64| 1.0 / r.max(MIN_RANGE_FOR_BEARING_MODEL);
    let range_hi = fit_upper_line(&residuals.iter().map(|p| (p.0, p.1)).collect::<Vec<_>>());
    let range_lo = fit_upper_line(&residuals.iter().map(|p| (p.0, -p.1)).collect::<Vec<_>>());
    let bearing_hi = fit_upper_line(
        &residuals
            .iter()
            .map(|p| (inverse(p.0), p.2))
            .collect::<Vec<_>>(),
    );
    let bearing_lo = fit_upper_line(
        &residuals
            .iter()
            .map(|p| (inverse(p.0), -p.2))
            .collect::<Vec<_>>(),
    );
    let band = |x: f64, hi: (f64, f64), lo: (f64, f64), bounds: (f64, f64)| {
        (
            bounds.0.max(-(lo.0 + lo.1 * x)),
            bounds.1.min(hi.0 + hi.1 * x),
        )
    };
    let detections: Vec<Value> = dets
        .iter()
        .map(|&(step, id, range, bearing)| {
            let (elo, ehi) = band(range, range_hi, range_lo, (rmin, rmax));
            let (blo, bhi) = band(inverse(range), bearing_hi, bearing_lo, (bmin, bmax));
            let lo = (range - ehi - RANGE_MARGIN).max(0.0);
            let hi = range - elo + RANGE_MARGIN;
            let mut d = json!({
                "step": step,
                "range": [lo, hi],
                "bearing": [bearing - bhi - BEARING_MARGIN, bearing - blo + BEARING_MARGIN],
                "scan": step,
            });
            if operator {
                d["landmark"] = json!(id);
            }
            d
        })
        .collect();
    let matching: Vec<usize> = dets.iter().map(|d| d.1).collect();
    let (p0, h0) = (cp[0], ch[0]);
    let (e0, eh) = (INITIAL_POSITION_ERROR, INITIAL_HEADING_ERROR);
    Ok(json!({
        "format": "nvector-mission/1",
        "name": if operator { "utias-woods-operator" } else { "utias-woods" },
        "model": "odometry2d",
        "dt": dt,
        "steps": n,
        "initial_position": [[p0[0] - e0, p0[0] + e0], [p0[1] - e0, p0[1] + e0]],
        "final_position": null,
        "initial_heading": [h0 - eh, h0 + eh],
        "inputs": {
            "speed": {"value": v, "error": 0.0},
            "turn_rate": {"value": om, "error": 0.0},
        },
        "heading_error": heading_error,
        "motion_error": motion_error,
        "sensor_offset": [SENSOR_OFFSET, 0.0],
        "detections": detections,
        "landmark_count": count,
        "landmark_min_separation": separation - SEPARATION_MARGIN,
        "meta": {
            "source": "UTIAS Lost in the Woods (dataset2.mat of T. D. Barfoot's AER1513 course, utiasASRL/aer1513, Apache-2.0), as CSV in ../shared/data/utias-lost-in-the-woods",
            "method": "every bound from the data against the motion-capture truth (docs/utias-woods.md): per-step residuals of the truth, completed across its gaps by linear interpolation, against the odometry2d model; steps above a threshold flagged with their own residual x 1.5 + margin; ranges and bearings: measured - true over every detection at a valid step, bounded by the narrowest lines in r (ranges) and 1/r (bearings) holding every residual, within the constant band, plus a margin",
            "heading_error": {"ordinary": heading_ordinary, "flag_above": HEADING_FLAG, "margin": HEADING_MARGIN, "flagged_steps": heading_flagged, "flagged_factor": FLAGGED_FACTOR, "flagged_margin": FLAGGED_MARGIN},
            "motion_error": {"ordinary": motion_ordinary, "flag_above": MOTION_FLAG, "margin": MOTION_MARGIN, "flagged_steps": motion_flagged, "flagged_factor": FLAGGED_FACTOR, "flagged_margin": FLAGGED_MARGIN},
            "speed_error": 0.0,
            "turn_rate_error": 0.0,
            "range_error_bounds": [rmin, rmax],
            "range_error_model": {"residual": "measured - true range, between -(lower[0] + lower[1] r) and upper[0] + upper[1] r (r the measured range), and within range_error_bounds", "upper": [range_hi.0, range_hi.1], "lower": [range_lo.0, range_lo.1]},
            "bearing_error_model": {"residual": "measured - true bearing (wrapped), between -(lower[0] + lower[1] / r) and upper[0] + upper[1] / r (r the measured range, at least 0.1 m), and within bearing_error_bounds", "upper": [bearing_hi.0, bearing_hi.1], "lower": [bearing_lo.0, bearing_lo.1]},
            "range_margin": RANGE_MARGIN,
            "bearing_error_bounds": [bmin, bmax],
            "bearing_margin": BEARING_MARGIN,
            "detections_checked": checked,
            "true_min_separation": separation,
            "separation_margin": SEPARATION_MARGIN,
            "truth_gaps": gaps,
            "invalid_truth_rows": valid.iter().filter(|&&ok| !ok).count(),
            "initial_position_error": e0,
            "initial_heading_error": eh,
            "headings": "the truth's theta unwrapped: a real heading, not taken modulo 2 pi",
        },
        "truth": {
            "positions": position.iter().map(|p| p.map_or(Value::Null, |p| json!(p))).collect::<Vec<_>>(),
            "headings": heading.iter().map(|h| h.map_or(Value::Null, |h| json!(h))).collect::<Vec<_>>(),
            "landmarks": landmarks,
            "matching": matching,
        },
    }))
}

/// Writes a mission to `out` (standard output when `None`).
///
/// The mission goes through core's common validation first
/// (`Mission::from_value`), like every other import: an invalid one is an
/// error naming the field, never a file written.
pub fn write(mission: &Value, out: Option<&Path>) -> Result<(), CliError> {
    nvector_core::slam::mission::Mission::from_value(mission)
        .map_err(|e| CliError(format!("the imported mission is invalid: {e}")))?;
    let text = serde_json::to_string(mission)?;
    match out {
        Some(p) => std::fs::write(p, text + "\n")
            .map_err(|e| CliError(format!("writing {}: {e}", p.display())))?,
        None => println!("{text}"),
    }
    Ok(())
}
