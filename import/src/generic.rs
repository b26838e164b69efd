//! The generic CSV import (docs/formats.md, "Importing"): a log with a
//! header row and one row per step (`t` and the model's channels),
//! detections in a second CSV (`t,range_lo,range_hi`, optional
//! `bearing_lo,bearing_hi`, `scan`, `landmark`), error bounds given by the
//! caller; times are matched to steps by `round((t - t0) / dt)`. A column
//! named twice is refused; a column the import does not read is named in
//! the notes.

use crate::csv::{column, read_csv, Csv};
use crate::doc::{boxed, finite_interval, int, interval};
use crate::ImportError;
use nvector_core::format::leaf::{BoxIn, Finite, Integer, List, PerStep};
use nvector_core::format::mission_doc::{ChannelDoc, DetectionDoc, InputsDoc, MissionDoc};
use nvector_core::format::to_value;
use nvector_core::slam::mission::FORMAT;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a generic CSV import reads and the bounds it states. Every
/// setting is checked before the files are read, except the channel
/// bounds (checked against the model).
#[derive(Debug, Clone, Default)]
pub struct CsvImport {
    /// Motion model of the log: `unicycle2d`, `auv3d` or `odometry2d`.
    pub model: String,
    /// Sensor log CSV: header row with `t` and the model's channels.
    pub log: PathBuf,
    /// Detections CSV.
    pub detections: PathBuf,
    /// The error bound of each channel (CHANNEL, E >= 0); each of the
    /// model's channels needs one (a later one for the same channel wins).
    pub errors: Vec<(String, f64)>,
    /// Time step (default: the median spacing of the log's `t`).
    pub dt: Option<f64>,
    /// Per-step integration error bound.
    pub motion_error: f64,
    /// Initial position box, one `[lo, hi]` per axis (default: the
    /// origin).
    pub initial: Option<Vec<[f64; 2]>>,
    /// odometry2d: the initial heading interval (required there).
    pub initial_heading: Option<[f64; 2]>,
    /// odometry2d: the per-step heading integration error bound.
    pub heading_error: Option<f64>,
    /// unicycle2d, odometry2d: where the sensor sits in the body frame.
    pub sensor_offset: Option<[f64; 2]>,
    /// Number of landmarks (enables atmost_nvector).
    pub landmark_count: Option<usize>,
    /// Distinct landmarks are at least this far apart (m).
    pub landmark_min_separation: Option<f64>,
    /// At most this many detections may be false.
    pub max_outliers: Option<u64>,
    /// Mission name (default: the log's file stem).
    pub name: Option<String>,
}

/// An imported mission and the notes of its import (the columns it did
/// not read, one line each), for the caller to show.
#[derive(Debug, Clone)]
pub struct Imported {
    /// The mission (`nvector-mission/1`, validated).
    pub mission: Value,
    /// Lines for the user.
    pub notes: Vec<String>,
}

/// The channels of a model (the log's columns besides `t`).
pub fn channels(model: &str) -> Result<&'static [&'static str], ImportError> {
    match model {
        "unicycle2d" => Ok(&["speed", "heading"]),
        "auv3d" => Ok(&["roll", "pitch", "yaw", "vx", "vy", "vz"]),
        "odometry2d" => Ok(&["speed", "turn_rate"]),
        _ => Err(ImportError::setting(
            "model",
            format!("--model: unknown model '{model}' (expected unicycle2d, auv3d or odometry2d)"),
        )),
    }
}

/// The time step: `dt`, or the median spacing of the log's times.
fn time_step(dt: Option<f64>, t: &[f64], log_path: &Path) -> Result<f64, ImportError> {
    let dt = match dt {
        Some(d) if d > 0.0 && d.is_finite() => d,
        Some(d) => {
            return Err(ImportError::setting(
                "dt",
                format!("--dt must be > 0, found {d}"),
            ))
        }
        None => {
            let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            d.sort_by(f64::total_cmp);
            d[d.len() / 2]
        }
    };
    if dt.is_nan() || dt <= 0.0 {
        return Err(ImportError::file(log_path, "times must increase"));
    }
    Ok(dt)
}

/// The channel bounds, by channel.
fn channel_errors(a: &CsvImport, chans: &[&str]) -> Result<BTreeMap<String, f64>, ImportError> {
    let mut errors = BTreeMap::new();
    for (k, v) in &a.errors {
        if !(v.is_finite() && *v >= 0.0) {
            return Err(ImportError::setting(
                "errors",
                format!("--error {k}={v}: E must be a number >= 0"),
            ));
        }
        if !chans.contains(&k.as_str()) {
            return Err(ImportError::setting(
                "errors",
                format!("--error {k}={v}: unknown channel '{k}' for {}", a.model),
            ));
        }
        errors.insert(k.clone(), *v);
    }
    Ok(errors)
}

/// The model's inputs from the log's channel columns and their bounds.
fn channel_inputs(
    log: &Csv,
    log_path: &Path,
    chans: &[&'static str],
    errors: &BTreeMap<String, f64>,
) -> Result<InputsDoc, ImportError> {
    let mut inputs = Vec::with_capacity(chans.len());
    for &ch in chans {
        let c = column(log, log_path, ch)?;
        let err = errors.get(ch).copied().ok_or_else(|| {
            ImportError::setting(
                "errors",
                format!("--error {ch}=E is required (the bound of channel {ch})"),
            )
        })?;
        let values: Vec<f64> = log.rows.iter().map(|r| r[c]).collect();
        inputs.push((ch, ChannelDoc::measured(values, err)));
    }
    Ok(InputsDoc::of(inputs))
}

/// The columns a detections CSV may have.
const DETECTION_COLUMNS: [&str; 7] = [
    "t",
    "range_lo",
    "range_hi",
    "bearing_lo",
    "bearing_hi",
    "scan",
    "landmark",
];

/// Refuses a column named twice in `csv`'s header (which one would be
/// read?) and names in `notes` the columns not in `read`.
fn check_columns(
    csv: &Csv,
    path: &Path,
    read: &[&str],
    notes: &mut Vec<String>,
) -> Result<(), ImportError> {
    for (i, h) in csv.header.iter().enumerate() {
        if csv.header[..i].contains(h) {
            return Err(ImportError::file(
                path,
                format!("column '{h}' appears twice in the header"),
            ));
        }
    }
    let unread: Vec<&str> = csv
        .header
        .iter()
        .map(String::as_str)
        .filter(|h| !read.contains(h))
        .collect();
    if !unread.is_empty() {
        notes.push(format!(
            "{}: ignoring column(s) {} (read: {})",
            path.display(),
            unread.join(", "),
            read.join(", ")
        ));
    }
    Ok(())
}

/// A non-negative integer cell, or an error naming its file, line and
/// column.
pub(crate) fn integer_cell(
    x: f64,
    path: &Path,
    line: usize,
    name: &str,
) -> Result<u64, ImportError> {
    if x >= 0.0 && x.fract() == 0.0 && x <= 9_007_199_254_740_992.0 {
        Ok(x as u64)
    } else {
        Err(ImportError::line(
            path,
            line,
            format!("{name} must be a non-negative integer, found {x}"),
        ))
    }
}

/// The detections CSV (`t,range_lo,range_hi`, optional
/// `bearing_lo,bearing_hi`, `scan`, `landmark`), each time matched to the
/// step `round((t - t0) / dt)` in `0..=steps`.
fn csv_detections(
    det_path: &Path,
    t0: f64,
    dt: f64,
    steps: usize,
    notes: &mut Vec<String>,
) -> Result<Vec<DetectionDoc>, ImportError> {
    let det = read_csv(det_path, true)?;
    check_columns(&det, det_path, &DETECTION_COLUMNS, notes)?;
    let dcol = |name: &str| column(&det, det_path, name);
    let (tc, lc, hc) = (dcol("t")?, dcol("range_lo")?, dcol("range_hi")?);
    let mc = dcol("landmark").ok();
    let sc = dcol("scan").ok();
    let bc = match (dcol("bearing_lo"), dcol("bearing_hi")) {
        (Ok(l), Ok(h)) => Some((l, h)),
        (Err(_), Err(_)) => None,
        (Ok(_), Err(e)) | (Err(e), Ok(_)) => return Err(e),
    };
    let mut dets = Vec::with_capacity(det.rows.len());
    for (i, r) in det.rows.iter().enumerate() {
        let step = ((r[tc] - t0) / dt).round();
        let line = i + 2;
        if step < 0.0 || step > steps as f64 {
            return Err(ImportError::line(
                det_path,
                line,
                format!(
                    "time {} falls outside the log (step {step} not in 0..={steps})",
                    r[tc]
                ),
            ));
        }
        if r[lc] > r[hc] || r[lc] < 0.0 {
            return Err(ImportError::line(
                det_path,
                line,
                format!(
                    "range [{}, {}] must satisfy 0 <= range_lo <= range_hi",
                    r[lc], r[hc]
                ),
            ));
        }
        let mut d = DetectionDoc {
            step: Some(Integer::Value(step as u64)),
            range: Some(interval([r[lc], r[hc]])),
            ..DetectionDoc::default()
        };
        if let Some((bl, bh)) = bc {
            if r[bl] > r[bh] {
                return Err(ImportError::line(
                    det_path,
                    line,
                    format!(
                        "bearing [{}, {}] must satisfy bearing_lo <= bearing_hi",
                        r[bl], r[bh]
                    ),
                ));
            }
            d.bearing = Some(interval([r[bl], r[bh]]));
        }
        if let Some(c) = sc {
            d.scan = Some(Integer::Value(integer_cell(r[c], det_path, line, "scan")?));
        }
        if let Some(m) = mc {
            let id = integer_cell(r[m], det_path, line, "landmark")?;
            d.landmark = Some(Integer::Value(id));
        }
        dets.push(d);
    }
    Ok(dets)
}

/// The heading fields of the settings: `initial_heading` (required for
/// odometry2d, refused for the other models) and `heading_error`
/// (odometry2d only).
fn heading_fields(a: &CsvImport, m: &mut MissionDoc) -> Result<(), ImportError> {
    let (model, odometry) = (a.model.as_str(), a.model == "odometry2d");
    match (a.initial_heading, odometry) {
        (Some([lo, hi]), true) => {
            if lo > hi {
                return Err(ImportError::setting(
                    "initial_heading",
                    format!("--initial-heading {lo},{hi}: LO is above HI"),
                ));
            }
            if !finite_interval([lo, hi]) {
                return Err(ImportError::setting(
                    "initial_heading",
                    format!("--initial-heading {lo},{hi}: expected two finite numbers"),
                ));
            }
            m.initial_heading = Some(interval([lo, hi]));
        }
        (None, true) => {
            return Err(ImportError::setting(
                "initial_heading",
                "--initial-heading LO,HI is required for odometry2d",
            ))
        }
        (Some(_), false) => {
            return Err(ImportError::setting(
                "initial_heading",
                format!("--initial-heading is only for odometry2d, not {model}"),
            ))
        }
        (None, false) => {}
    }
    if let Some(e) = a.heading_error {
        if !odometry {
            return Err(ImportError::setting(
                "heading_error",
                format!("--heading-error is only for odometry2d, not {model}"),
            ));
        }
        if !(e.is_finite() && e >= 0.0) {
            return Err(ImportError::setting(
                "heading_error",
                format!("--heading-error must be a number >= 0, found {e}"),
            ));
        }
        m.heading_error = Some(PerStep::One(e));
    }
    Ok(())
}

/// The model's own fields from the settings: the heading fields
/// (odometry2d), `sensor_offset` (unicycle2d, odometry2d), and
/// `landmark_count`, `landmark_min_separation`, `max_outliers`; a setting
/// the model has no field for is refused.
fn model_fields(a: &CsvImport, m: &mut MissionDoc) -> Result<(), ImportError> {
    heading_fields(a, m)?;
    if let Some(o) = a.sensor_offset {
        if a.model == "auv3d" {
            return Err(ImportError::setting(
                "sensor_offset",
                "--sensor-offset is for unicycle2d and odometry2d, not auv3d",
            ));
        }
        if !o.iter().all(|x| x.is_finite()) {
            return Err(ImportError::setting(
                "sensor_offset",
                format!(
                    "--sensor-offset {},{}: expected two finite numbers",
                    o[0], o[1]
                ),
            ));
        }
        m.sensor_offset = Some(List(o.map(Finite).to_vec()));
    }
    if let Some(n) = a.landmark_count {
        m.landmark_count = Some(int(n));
    }
    if let Some(d) = a.landmark_min_separation {
        if !(d.is_finite() && d >= 0.0) {
            return Err(ImportError::setting(
                "landmark_min_separation",
                format!("--landmark-min-separation must be a number >= 0, found {d}"),
            ));
        }
        m.landmark_min_separation = Some(Finite(d));
    }
    if let Some(q) = a.max_outliers {
        m.max_outliers = Some(Integer::Value(q));
    }
    Ok(())
}

/// The initial box (lo,hi per axis, finite, lo <= hi), the origin when
/// absent.
fn initial_box(a: &CsvImport, dim: usize) -> Result<BoxIn, ImportError> {
    let Some(axes) = &a.initial else {
        return Ok(boxed(&vec![[0.0, 0.0]; dim]));
    };
    if axes.len() != dim {
        return Err(ImportError::setting(
            "initial",
            format!(
                "--initial: expected {} numbers (lo,hi per axis), found {}",
                2 * dim,
                2 * axes.len()
            ),
        ));
    }
    if let Some((k, [lo, hi])) = axes.iter().enumerate().find(|x| !finite_interval(*x.1)) {
        return Err(ImportError::setting(
            "initial",
            format!("--initial: axis {k}: [{lo}, {hi}] is not finite with lo <= hi"),
        ));
    }
    Ok(boxed(axes))
}

/// The log's rows (at least 2) and its column `t`.
fn read_log(
    path: &Path,
    chans: &[&str],
    notes: &mut Vec<String>,
) -> Result<(Csv, Vec<f64>), ImportError> {
    let log = read_csv(path, true)?;
    let mut read = vec!["t"];
    read.extend_from_slice(chans);
    check_columns(&log, path, &read, notes)?;
    let t_col = column(&log, path, "t")?;
    if log.rows.len() < 2 {
        return Err(ImportError::file(path, "at least 2 rows are needed"));
    }
    let t: Vec<f64> = log.rows.iter().map(|r| r[t_col]).collect();
    Ok((log, t))
}

/// A mission from a sensor log and a detections CSV (module doc), validated
/// as core reads it; the notes name the columns left unread.
pub fn import_csv(a: &CsvImport) -> Result<Imported, ImportError> {
    let chans = channels(&a.model)?;
    // The model's settings are checked before the files are read.
    let mut m = MissionDoc::default();
    model_fields(a, &mut m)?;
    let dim = if a.model == "auv3d" { 3 } else { 2 };
    let initial = initial_box(a, dim)?;
    let mut notes = Vec::new();
    let (log, t) = read_log(&a.log, chans, &mut notes)?;
    let dt = time_step(a.dt, &t, &a.log)?;
    let errors = channel_errors(a, chans)?;
    let steps = log.rows.len();
    let inputs = channel_inputs(&log, &a.log, chans, &errors)?;
    let dets = csv_detections(&a.detections, t[0], dt, steps, &mut notes)?;
    let name = a.name.clone().unwrap_or_else(|| {
        a.log
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("import")
            .to_string()
    });
    let m = MissionDoc {
        format: Some(FORMAT.into()),
        name: Some(name),
        model: Some(a.model.clone().into()),
        dt: Some(Finite(dt)),
        steps: Some(int(steps)),
        initial_position: Some(initial),
        inputs: Some(inputs),
        motion_error: Some(PerStep::One(a.motion_error)),
        detections: Some(List(dets)),
        meta: Some(json!({"imported_from": a.log.display().to_string()})),
        ..m
    };
    let mut m = to_value(&m);
    // The generic import leaves an unknown final position out (the
    // document writes it `null`).
    if let Some(o) = m.as_object_mut() {
        o.remove("final_position");
    }
    Ok(Imported {
        mission: crate::validated(m)?,
        notes,
    })
}
