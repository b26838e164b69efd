//! The UTIAS "Lost in the Woods" data set (`data/utias-lost-in-the-woods`;
//! `nvector import --utias-woods DIR [--operator]`): a robot without a
//! heading sensor among 17 identical tubes, range-and-bearing detections
//! from a laser ahead of its centre, as an `odometry2d` mission with its
//! truth.
//!
//! The data set is converted to the calibration's four CSVs
//! ([`calibration_csvs`]: the truth's theta unwrapped into a real heading,
//! the motion capture's invalid rows left empty), calibrated on itself
//! (the one fitting code, [`crate::calibrate`], with the settings of
//! [`bounds`]: the truth completed across its gaps, the flagged steps,
//! constant per-step bounds, windows exempting the flagged steps, the
//! bands holding every residual), and the model applied to the same run
//! ([`crate::apply`]). docs/utias-woods.md gives the method and the
//! figures; `meta` records them. The import adds
//! `landmark_min_separation` (the smallest true distance between two
//! tubes less a margin) and `scan` (detections at the same time).

use crate::calibrate::convert::{self, Csvs, Span};
use crate::calibrate::{self, data, Flag};
use crate::csv::{columns, read_csv, Csv};
use crate::ImportError;
use nvector_core::format::leaf::Integer;
use nvector_core::format::to_value;
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// The settings of the same-run calibration (docs/utias-woods.md explains
/// each).
pub mod bounds {
    /// The laser's place ahead of the robot's centre (the data set's d), m.
    pub const SENSOR_OFFSET: f64 = 0.219016;
    /// A heading residual (rad per step) above this flags its step.
    pub const HEADING_FLAG: f64 = 0.02;
    /// A motion residual (m per step and axis) above this flags its step.
    pub const MOTION_FLAG: f64 = 0.02;
    /// Margin on a flagged step's own bound (heading rad, motion m), after
    /// the factor [`FLAGGED_FACTOR`].
    pub const FLAGGED_MARGIN: f64 = 0.01;
    /// Factor on a flagged step's residual.
    pub const FLAGGED_FACTOR: f64 = 1.5;
    /// The drift windows' relative margin F (their largest residual x
    /// (1 + F) + the calibration's window margin); the per-step bounds
    /// and the bands have none (the largest residual + the margin).
    pub const DRIFT_RELATIVE_MARGIN: f64 = 0.1;
    /// Margin taken off the smallest true distance between tubes (m).
    pub const SEPARATION_MARGIN: f64 = 0.05;
}

/// The same-run calibration of Lost in the Woods (docs/utias-woods.md).
pub fn calibration_options(outlier_share: f64) -> calibrate::Options {
    use bounds::*;
    calibrate::Options {
        relative_margin: 0.0,
        bound_margins: vec![
            ("heading_drift".into(), DRIFT_RELATIVE_MARGIN),
            ("motion_drift".into(), DRIFT_RELATIVE_MARGIN),
        ],
        sensor_offset: [SENSOR_OFFSET, 0.0],
        source: "UTIAS Lost in the Woods, this run".into(),
        same_run: true,
        flag: Some(Flag {
            heading_above: Some(HEADING_FLAG),
            motion_above: Some(MOTION_FLAG),
            factor: FLAGGED_FACTOR,
            margin: FLAGGED_MARGIN,
            complete_gaps: true,
        }),
        constant_steps: true,
        outlier_share,
        ..calibrate::Options::default()
    }
}

/// `a` taken into (-pi, pi].
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

/// A detection: step, label, measured range and bearing.
struct WoodsDetection {
    step: usize,
    id: usize,
    range: f64,
    bearing: f64,
}

fn woods_detections(
    f: &WoodsFiles,
    log: &WoodsLog,
    landmarks: &[[f64; 2]],
) -> Result<Vec<WoodsDetection>, ImportError> {
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
        dets.push(WoodsDetection {
            step,
            id,
            range,
            bearing,
        });
    }
    if dets.iter().all(|d| log.position[d.step].is_none()) {
        return Err(ImportError::file(
            meas_p,
            "no detection at a step with valid truth: no bound can be derived",
        ));
    }
    Ok(dets)
}

/// The Lost in the Woods data set in `dir` as a mission (tube labels kept
/// as the operator's matching when `operator`), with the truth: the data
/// set's CSVs calibrated on themselves ([`calibration_options`]) and the
/// model applied to them. With `outlier_share` P > 0 the range and bearing
/// bands hold the central (1 - P) share of the residuals each, and
/// `max_outliers` is the count of detections (at steps with a truth) left
/// outside either.
pub fn utias_woods(dir: &Path, operator: bool, outlier_share: f64) -> Result<Value, ImportError> {
    crate::check_outlier_share(outlier_share)?;
    let files = woods_files(dir)?;
    let (_, separation) = woods_landmarks(&files)?;
    let csvs = calibration_csvs(dir, Span::ALL)?;
    let run = data::run_of_csvs(data::Model::Odometry2d, &csvs, dir)?;
    let model = calibrate::calibrate(&run, &calibration_options(outlier_share))?;
    let options = crate::apply::Options {
        operator,
        name: if operator {
            "utias-woods-operator"
        } else {
            "utias-woods"
        }
        .into(),
        sensor_model: "same-run calibration (meta.sensor_model)".into(),
        landmark_min_separation: Some(separation - bounds::SEPARATION_MARGIN),
        ..crate::apply::Options::default()
    };
    let mut m = crate::apply::mission_doc(&run, &model, &options)?;
    let meta = m.meta.get_or_insert(Value::Null);
    woods_meta(meta, &model, &run, separation);
    if outlier_share > 0.0 {
        let outside = crate::apply::readings_outside(&run, &model);
        m.max_outliers = Some(Integer::Value(outside.len() as u64));
        meta["outlier_share"] = json!({
            "share": outlier_share,
            "method": "each band (range, bearing) holds the central (1 - share) of the residuals at steps with a truth: floor(share k / 2) below and the rest of floor(share k) above left out of the lines and of the constant band; `outside` lists the detections (by index) whose truth is outside their range or bearing interval, margins included, and max_outliers is their count (detections at steps without a truth are taken inside, as with share 0)",
            "outside": outside,
        });
    }
    crate::validated(to_value(&m))
}

/// The data set's figures in `meta`, from the same-run model.
fn woods_meta(
    meta: &mut Value,
    model: &crate::sensor_model::SensorModel,
    run: &data::Run,
    separation: f64,
) {
    let flagged = model.flagged.as_ref();
    let count = |f: fn(&crate::sensor_model::Flagged) -> usize| flagged.map_or(0, f);
    let (r, b) = (&model.range, model.bearing.as_ref());
    let fields = json!({
        "source": "UTIAS Lost in the Woods (dataset2.mat of T. D. Barfoot's AER1513 course, utiasASRL/aer1513, Apache-2.0), as CSV in data/utias-lost-in-the-woods of the nvector repository",
        "method": model.motion_error.fit.method,
        "heading_error": {"ordinary": model.heading.constant, "flag_above": bounds::HEADING_FLAG, "flagged_steps": count(|f| f.heading.len()), "method": model.heading.fit.method},
        "motion_error": {"ordinary": model.motion_error.constant, "flag_above": bounds::MOTION_FLAG, "flagged_steps": count(|f| f.motion.len()), "method": model.motion_error.fit.method},
        "truth_gaps": model.calibration.truth_gaps,
        "invalid_truth_rows": run.truth.as_ref().map_or(0, |t| t.positions.iter().filter(|p| p.is_none()).count()),
        "headings": "the truth's theta unwrapped: a real heading, not taken modulo 2 pi",
        "range_error_bounds": r.constant,
        "range_margin": r.fit.margin,
        "bearing_error_bounds": b.map(|b| b.constant),
        "bearing_margin": b.map(|b| b.fit.margin),
        "detections_checked": r.fit.samples,
        "true_min_separation": separation,
        "separation_margin": bounds::SEPARATION_MARGIN,
        "heading_drift": {"method": model.heading_drift.first().map(|w| w.fit.method.clone())},
        "motion_drift": {"method": model.motion_drift.first().map(|w| w.fit.method.clone())},
    });
    meta["calibration"]["method"] = json!(format!("oracle: {}", crate::SAME_RUN_METHOD));
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
