//! The CMU Plaza 1 range-only data set (Djugash and Singh, via GTSAM's
//! examples; `data/cmu-plaza1`) as a `unicycle2d` mission with its truth:
//! the data set converted to the calibration's four CSVs
//! ([`calibration_csvs`]), a same-run calibration of them (the one fitting
//! code, [`crate::calibrate`], with the settings of [`cmu`]) and the model
//! applied to the same run ([`crate::apply`]). docs/cmu-plaza1.md gives
//! the figures; `meta` records them.

use crate::calibrate::convert::{self, Csvs, Span};
use crate::calibrate::{self, data, Flag};
use crate::csv::read_table;
use crate::ImportError;
use nvector_core::format::leaf::Integer;
use nvector_core::format::to_value;
use serde_json::{json, Value};
use std::path::Path;

/// The settings of Plaza 1's same-run calibration (docs/cmu-plaza1.md
/// explains each).
pub mod cmu {
    /// The heading bound (rad), stated: the truth's heading is the
    /// integrated odometry heading, it cannot calibrate it.
    pub const HEADING_ERROR: f64 = 0.02;
    /// A step whose motion residual exceeds this (m) is flagged and gets
    /// its own motion error.
    pub const FLAG_ABOVE: f64 = 0.02;
    /// A flagged step's bound: its residual x this + [`FLAGGED_MARGIN`].
    pub const FLAGGED_FACTOR: f64 = 1.5;
    /// See [`FLAGGED_FACTOR`] (m).
    pub const FLAGGED_MARGIN: f64 = 0.05;
    /// Below this reported distance (m per step) the odometry says the
    /// robot stands still (the zero-velocity class).
    pub const STILL_BELOW: f64 = 0.01;
}

/// The heading of Plaza 1's odometry at each row: `delta_heading`
/// integrated from the truth's first heading.
fn cmu_heading(dr: &[Vec<f64>], gt: &[Vec<f64>]) -> Vec<f64> {
    let mut heading = Vec::with_capacity(dr.len());
    let mut h = gt[0][3];
    for row in dr {
        heading.push(h);
        h += row[2];
    }
    heading
}

/// The pose (row of the truth) nearest in time to `t`; the earlier one
/// on a tie.
fn nearest_pose(times: &[f64], t: f64) -> usize {
    match times.binary_search_by(|x| x.total_cmp(&t)) {
        Ok(i) => i,
        Err(0) => 0,
        Err(i) if i >= times.len() => times.len() - 1,
        Err(i) => {
            if t - times[i - 1] < times[i] - t {
                i - 1
            } else {
                i
            }
        }
    }
}

/// The four files of Plaza 1, each row with at least the columns read:
/// DR time, distance, heading change; GT time, x, y, heading; TD time,
/// (unused), beacon id, range; TL id, x, y.
struct PlazaFiles {
    dr: Vec<Vec<f64>>,
    gt: Vec<Vec<f64>>,
    td: Vec<Vec<f64>>,
    tl: Vec<Vec<f64>>,
}

/// Reads the files of Plaza 1 and checks their row counts.
fn plaza_files(dir: &Path) -> Result<PlazaFiles, ImportError> {
    let dr = read_table(&dir.join("Plaza1_DR.txt"), 3)?;
    let gt = read_table(&dir.join("Plaza1_GT.csv"), 4)?;
    let td = read_table(&dir.join("Plaza1_TD.txt"), 4)?;
    let tl = read_table(&dir.join("Plaza1_TL.csv"), 3)?;
    let n = dr.len();
    if td.is_empty() || tl.is_empty() || n == 0 {
        return Err(ImportError::file(
            dir,
            format!(
                "Plaza1_TD.txt, Plaza1_TL.csv and Plaza1_DR.txt must each hold a row ({}, {} and {} rows)",
                td.len(),
                tl.len(),
                n
            ),
        ));
    }
    if gt.len() != n + 1 {
        return Err(ImportError::file(
            dir,
            format!(
                "expected one more ground-truth row than odometry rows ({} and {})",
                gt.len(),
                n
            ),
        ));
    }
    Ok(PlazaFiles { dr, gt, td, tl })
}

/// The same-run calibration of Plaza 1 (docs/cmu-plaza1.md): every bound
/// fitted on the run's own truth with no relative margin, the heading
/// stated, the motion error constant with its still class and the steps
/// the truth flags, the range band holding every residual (or the
/// central 1 - `outlier_share` of them).
pub fn calibration_options(outlier_share: f64) -> calibrate::Options {
    use cmu::*;
    calibrate::Options {
        relative_margin: 0.0,
        assume_heading: Some(HEADING_ERROR),
        source: "CMU Plaza 1, this run".into(),
        same_run: true,
        flag: Some(Flag {
            heading_above: None,
            motion_above: Some(FLAG_ABOVE),
            factor: FLAGGED_FACTOR,
            margin: FLAGGED_MARGIN,
            complete_gaps: false,
        }),
        still_below: Some(STILL_BELOW),
        constant_steps: true,
        outlier_share,
        ..calibrate::Options::default()
    }
}

/// The CMU Plaza 1 dataset as a mission (beacon ids hidden unless
/// `operator`), with the ground truth: the data set's CSVs, calibrated on
/// themselves ([`calibration_options`]) and the model applied to them.
/// `outlier_share` P: the range band holds the central (1 - P) share of
/// the residuals, and `max_outliers` is the count left outside (0: every
/// range inside, no `max_outliers`).
pub fn cmu_plaza(dir: &Path, operator: bool, outlier_share: f64) -> Result<Value, ImportError> {
    crate::check_outlier_share(outlier_share)?;
    let csvs = calibration_csvs(dir, Span::ALL)?;
    let run = data::run_of_csvs(data::Model::Unicycle2d, &csvs, dir)?;
    let model = calibrate::calibrate(&run, &calibration_options(outlier_share))?;
    let name = if operator {
        "cmu-plaza1-operator"
    } else {
        "cmu-plaza1"
    };
    let options = crate::apply::Options {
        operator,
        name: name.into(),
        sensor_model: "same-run calibration (meta.sensor_model)".into(),
        ..crate::apply::Options::default()
    };
    let mut mission = crate::apply::mission_doc(&run, &model, &options)?;
    let m = &model.motion_error;
    let meta = mission.meta.get_or_insert(Value::Null);
    meta["source"] = json!("CMU Plaza 1 (Djugash and Singh), via GTSAM's examples");
    meta["calibration"]["method"] = json!(format!("oracle: {}", crate::SAME_RUN_METHOD));
    meta["ordinary_motion_error"] = json!(m.constant);
    meta["stationary_motion_error"] = json!(m.still.as_ref().map(|s| s.error));
    meta["stationary_steps"] = json!(m.still.as_ref().map_or(0, |s| s.fit.samples));
    meta["anomalous_steps"] = json!(model.flagged.as_ref().map_or(0, |f| f.motion.len()));
    meta["range_error_bounds"] = json!(model.range.constant);
    meta["range_error_model"] = json!({"upper": model.range.upper, "lower": model.range.lower, "margin": model.range.fit.margin});
    if outlier_share > 0.0 {
        let outside = crate::apply::readings_outside(&run, &model);
        mission.max_outliers = Some(Integer::Value(outside.len() as u64));
        meta["outlier_share"] = json!({
            "share": outlier_share,
            "method": "the range band holds the central (1 - share) of the residuals: floor(share k / 2) lowest and the rest of floor(share k) highest left out of each line and of the constant band; `outside` lists the ranges (by index) whose true distance is outside their interval, margin included, and max_outliers is their count",
            "outside": outside,
        });
    }
    crate::validated(to_value(&mission))
}

/// Plaza 1 in `dir` over `span` (of the poses' times) as the
/// calibration's four CSVs (docs/calibration.md), read as [`cmu_plaza`]
/// reads it: the log `t,speed,heading` (unicycle2d), one row per odometry
/// row at the time of the pose it starts from, the speed its distance over
/// the span's mean time step (so that dt × speed is the distance), the
/// heading integrated from the truth's first heading; the
/// detections `t,range,landmark` at the time of the nearest pose; the
/// truth `t,x,y,heading` as the data set gives it; the beacons `id,x,y`.
pub fn calibration_csvs(dir: &Path, span: Span) -> Result<Csvs, ImportError> {
    use std::fmt::Write as _;
    let PlazaFiles { dr, gt, td, tl } = plaza_files(dir)?;
    let times: Vec<f64> = gt.iter().map(|r| r[0]).collect();
    let (a, b) = convert::rows(&times[..dr.len()], span, &dir.join("Plaza1_GT.csv"))?;
    let dt = (times[b - 1] - times[a]) / (b - 1 - a) as f64;
    let heading = cmu_heading(&dr, &gt);
    let mut out = Csvs {
        log: "t,speed,heading\n".into(),
        detections: "t,range,landmark\n".into(),
        truth: "t,x,y,heading\n".into(),
        landmarks: "id,x,y\n".into(),
    };
    for i in a..b {
        let _ = writeln!(out.log, "{},{},{}", times[i], dr[i][1] / dt, heading[i]);
    }
    for r in &gt[a..=b] {
        let _ = writeln!(out.truth, "{},{},{},{}", r[0], r[1], r[2], r[3]);
    }
    for r in &td {
        if !tl.iter().any(|l| l[0] == r[2]) {
            return Err(ImportError::file(
                dir.join("Plaza1_TD.txt"),
                format!("beacon {} is not in Plaza1_TL.csv", r[2]),
            ));
        }
        let step = nearest_pose(&times, r[0]);
        if (a..=b).contains(&step) {
            let _ = writeln!(out.detections, "{},{},{}", times[step], r[3], r[2]);
        }
    }
    for r in &tl {
        let _ = writeln!(out.landmarks, "{},{},{}", r[0], r[1], r[2]);
    }
    Ok(out)
}
