//! `nvector import`: a mission from sensor logs.
//!
//! Generic CSV (docs/formats.md): a log with a header row and one row per
//! step (`t` and the model's channels), detections in a second CSV
//! (`t,range_lo,range_hi`, optional `bearing_lo,bearing_hi`, `scan`,
//! `landmark`), error bounds on the command line; times are matched to
//! steps by `round((t - t0) / dt)`. A column named twice is refused; a
//! column the import does not read is named on standard error.
//!
//! `--cmu-plaza DIR`: the CMU Plaza 1 range-only dataset (see
//! docs/cmu-plaza1.md for how every bound is derived from the data).

use super::csv::{read_csv, read_table, Csv};
use crate::CliError;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};

/// Arguments of `nvector import`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion model of the log: unicycle2d, auv3d or odometry2d (required
    /// unless a data set is named: --cmu-plaza, --utias-woods or
    /// --locards-mlat; a missing or unknown model is a usage error, exit 2).
    #[arg(
        long,
        value_parser = ["unicycle2d", "auv3d", "odometry2d"],
        required_unless_present_any = ["cmu_plaza", "utias_woods", "locards_mlat", "sensor_model"]
    )]
    model: Option<String>,
    /// Sensor log CSV: header row with `t` and the model's channels.
    #[arg(long)]
    log: Option<PathBuf>,
    /// Detections CSV: `t,range_lo,range_hi`, optional
    /// `bearing_lo,bearing_hi` (radians), `scan` and `landmark`.
    #[arg(long)]
    detections: Option<PathBuf>,
    /// Error bound of a channel, as NAME=E (repeat for each channel).
    #[arg(long = "error", value_name = "CHANNEL=E")]
    errors: Vec<String>,
    /// Time step (default: the median spacing of the log's `t`).
    #[arg(long, allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Per-step integration error bound.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    motion_error: f64,
    /// Initial position box, as comma-separated lo,hi pairs per axis.
    /// (A list starting with a negative number is read as the value, not
    /// as a flag: `--initial -0.1,0.1,-0.1,0.1`.)
    #[arg(long, value_name = "LO,HI,LO,HI[,LO,HI]", allow_hyphen_values = true)]
    initial: Option<String>,
    /// Number of landmarks (enables atmost_nvector).
    #[arg(long)]
    landmark_count: Option<usize>,
    /// odometry2d: the initial heading interval, LO,HI (radians; required
    /// for odometry2d).
    #[arg(long, value_name = "LO,HI", allow_hyphen_values = true)]
    initial_heading: Option<String>,
    /// odometry2d: the per-step heading integration error bound (radians).
    #[arg(long, allow_negative_numbers = true)]
    heading_error: Option<f64>,
    /// unicycle2d, odometry2d: where the range-and-bearing sensor sits in
    /// the body frame, X,Y (m, X along the heading).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    sensor_offset: Option<String>,
    /// Distinct landmarks are at least this far apart (m).
    #[arg(long, allow_negative_numbers = true)]
    landmark_min_separation: Option<f64>,
    /// At most this many detections may be false (`max_outliers`).
    #[arg(long)]
    max_outliers: Option<u64>,
    /// Mission name.
    #[arg(long)]
    name: Option<String>,
    /// Import the CMU Plaza 1 dataset from this directory instead.
    #[arg(long, value_name = "DIR")]
    cmu_plaza: Option<PathBuf>,
    /// Import the UTIAS Lost in the Woods data set from this directory (docs/utias-woods.md).
    #[arg(long, value_name = "DIR", conflicts_with = "cmu_plaza")]
    utias_woods: Option<PathBuf>,
    /// With --cmu-plaza or --utias-woods: keep the data set's landmark ids as
    /// the operator's matching.
    #[arg(long)]
    operator: bool,
    /// With --cmu-plaza or --utias-woods: plant this many false ranges (random steps, ranges
    /// drawn over the measured span, `truth.matching` null) and
    /// add it to `max_outliers`.
    #[arg(long, default_value_t = 0)]
    false_detections: usize,
    /// With --cmu-plaza or --utias-woods: the share P of the residuals left
    /// outside the error bands (0 <= P < 0.5): the bands hold the central
    /// (1 - P) share, and `max_outliers` is the count of detections left
    /// outside (listed in `meta.outlier_share`).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    outlier_share: f64,
    /// With --false-detections: the seed of the planted ranges.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output mission file (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Import LocaRDS multilateration messages (an nvector-tdoa/1 problem; docs/tdoa.md).
    #[arg(long, value_name = "DIR")]
    locards_mlat: Option<PathBuf>,
    /// With --locards-mlat: the set (1-4).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=8))]
    set: u32,
    /// --sensor-model SENSOR.json [--truth T.csv --landmarks L.csv]: raw readings, bounds from a calibration.
    #[command(flatten)]
    sensor: crate::cli::calibrate::ImportArgs,
}

fn channels(model: &str) -> Result<&'static [&'static str], CliError> {
    match model {
        "unicycle2d" => Ok(&["speed", "heading"]),
        "auv3d" => Ok(&["roll", "pitch", "yaw", "vx", "vy", "vz"]),
        "odometry2d" => Ok(&["speed", "turn_rate"]),
        _ => Err(CliError(format!(
            "--model: unknown model '{model}' (expected unicycle2d, auv3d or odometry2d)"
        ))),
    }
}

/// The time step: `--dt`, or the median spacing of the log's times.
fn time_step(a: &Args, t: &[f64], log_path: &Path) -> Result<f64, CliError> {
    let dt = match a.dt {
        Some(d) if d > 0.0 && d.is_finite() => d,
        Some(d) => return Err(CliError(format!("--dt must be > 0, found {d}"))),
        None => {
            let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            d.sort_by(f64::total_cmp);
            d[d.len() / 2]
        }
    };
    if dt.is_nan() || dt <= 0.0 {
        return Err(CliError(format!(
            "{}: times must increase",
            log_path.display()
        )));
    }
    Ok(dt)
}

/// The `--error CHANNEL=E` bounds, by channel.
fn channel_errors(a: &Args, model: &str, chans: &[&str]) -> Result<Map<String, Value>, CliError> {
    let mut errors: Map<String, Value> = Map::new();
    for e in &a.errors {
        let (k, v) = e
            .split_once('=')
            .ok_or_else(|| CliError(format!("--error {e}: expected CHANNEL=E")))?;
        let v: f64 = v
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite() && *x >= 0.0)
            .ok_or_else(|| CliError(format!("--error {e}: E must be a number >= 0")))?;
        if !chans.contains(&k) {
            return Err(CliError(format!(
                "--error {e}: unknown channel '{k}' for {model}"
            )));
        }
        errors.insert(k.into(), json!(v));
    }
    Ok(errors)
}

/// The model's inputs from the log's channel columns and their bounds.
fn channel_inputs(
    log: &Csv,
    log_path: &Path,
    chans: &[&str],
    errors: &Map<String, Value>,
) -> Result<Map<String, Value>, CliError> {
    let mut inputs = Map::new();
    for ch in chans {
        let c = log.header.iter().position(|h| h == ch).ok_or_else(|| {
            CliError(format!(
                "{}: missing column '{ch}' in the header",
                log_path.display()
            ))
        })?;
        let err = errors.get(*ch).cloned().ok_or_else(|| {
            CliError(format!(
                "--error {ch}=E is required (the bound of channel {ch})"
            ))
        })?;
        let values: Vec<f64> = log.rows.iter().map(|r| r[c]).collect();
        inputs.insert((*ch).into(), json!({"value": values, "error": err}));
    }
    Ok(inputs)
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
/// read?) and names on standard error the columns not in `read`.
fn check_columns(csv: &Csv, path: &Path, read: &[&str]) -> Result<(), CliError> {
    for (i, h) in csv.header.iter().enumerate() {
        if csv.header[..i].contains(h) {
            return Err(CliError(format!(
                "{}: column '{h}' appears twice in the header",
                path.display()
            )));
        }
    }
    let unread: Vec<&str> = csv
        .header
        .iter()
        .map(String::as_str)
        .filter(|h| !read.contains(h))
        .collect();
    if !unread.is_empty() {
        say!(
            "nvector import: {}: ignoring column(s) {} (read: {})",
            path.display(),
            unread.join(", "),
            read.join(", ")
        );
    }
    Ok(())
}

/// A non-negative integer cell, or an error naming its file, line and
/// column.
fn integer_cell(x: f64, path: &Path, line: usize, name: &str) -> Result<u64, CliError> {
    if x >= 0.0 && x.fract() == 0.0 && x <= 9_007_199_254_740_992.0 {
        Ok(x as u64)
    } else {
        Err(CliError(format!(
            "{}:{line}: {name} must be a non-negative integer, found {x}",
            path.display()
        )))
    }
}

/// The detections CSV (`t,range_lo,range_hi`, optional
/// `bearing_lo,bearing_hi`, `scan`, `landmark`), each time matched to the
/// step `round((t - t0) / dt)` in `0..=steps`.
fn csv_detections(det_path: &Path, t0: f64, dt: f64, steps: usize) -> Result<Vec<Value>, CliError> {
    let det = read_csv(det_path, true)?;
    check_columns(&det, det_path, &DETECTION_COLUMNS)?;
    let dcol = |name: &str| {
        det.header.iter().position(|h| h == name).ok_or_else(|| {
            CliError(format!(
                "{}: missing column '{name}' in the header",
                det_path.display()
            ))
        })
    };
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
            return Err(CliError(format!(
                "{}:{line}: time {} falls outside the log (step {step} not in 0..={steps})",
                det_path.display(),
                r[tc]
            )));
        }
        if r[lc] > r[hc] || r[lc] < 0.0 {
            return Err(CliError(format!(
                "{}:{line}: range [{}, {}] must satisfy 0 <= range_lo <= range_hi",
                det_path.display(),
                r[lc],
                r[hc]
            )));
        }
        let mut d = json!({"step": step as u64, "range": [r[lc], r[hc]]});
        if let Some((bl, bh)) = bc {
            if r[bl] > r[bh] {
                return Err(CliError(format!(
                    "{}:{line}: bearing [{}, {}] must satisfy bearing_lo <= bearing_hi",
                    det_path.display(),
                    r[bl],
                    r[bh]
                )));
            }
            d["bearing"] = json!([r[bl], r[bh]]);
        }
        if let Some(c) = sc {
            d["scan"] = json!(integer_cell(r[c], det_path, line, "scan")?);
        }
        if let Some(m) = mc {
            d["landmark"] = json!(integer_cell(r[m], det_path, line, "landmark")?);
        }
        dets.push(d);
    }
    Ok(dets)
}

/// A flag's comma-separated numbers, `None` when one is not a number.
fn flag_numbers(s: &str) -> Option<Vec<f64>> {
    s.split(',').map(|x| x.trim().parse::<f64>().ok()).collect()
}

/// Two finite numbers `A,B` of the flag `flag`.
fn number_pair(s: &str, flag: &str) -> Result<[f64; 2], CliError> {
    let v = flag_numbers(s).ok_or_else(|| CliError(format!("{flag} {s}: expected two numbers")))?;
    match v[..] {
        [a, b] if a.is_finite() && b.is_finite() => Ok([a, b]),
        _ => Err(CliError(format!("{flag} {s}: expected two finite numbers"))),
    }
}

/// The model's own fields from the flags: `initial_heading` and
/// `heading_error` (odometry2d), `sensor_offset` (unicycle2d,
/// odometry2d), and `landmark_count`, `landmark_min_separation`,
/// `max_outliers`; a flag the model has no field for is refused.
fn model_fields(a: &Args, model: &str, m: &mut Value) -> Result<(), CliError> {
    let odometry = model == "odometry2d";
    match (&a.initial_heading, odometry) {
        (Some(h), true) => {
            let [lo, hi] = number_pair(h, "--initial-heading")?;
            if lo > hi {
                return Err(CliError(format!("--initial-heading {h}: LO is above HI")));
            }
            m["initial_heading"] = json!([lo, hi]);
        }
        (None, true) => {
            return Err(CliError(
                "--initial-heading LO,HI is required for odometry2d".into(),
            ))
        }
        (Some(_), false) => {
            return Err(CliError(format!(
                "--initial-heading is only for odometry2d, not {model}"
            )))
        }
        (None, false) => {}
    }
    if let Some(e) = a.heading_error {
        if !odometry {
            return Err(CliError(format!(
                "--heading-error is only for odometry2d, not {model}"
            )));
        }
        if !(e.is_finite() && e >= 0.0) {
            return Err(CliError(format!(
                "--heading-error must be a number >= 0, found {e}"
            )));
        }
        m["heading_error"] = json!(e);
    }
    if let Some(o) = &a.sensor_offset {
        if model == "auv3d" {
            return Err(CliError(
                "--sensor-offset is for unicycle2d and odometry2d, not auv3d".into(),
            ));
        }
        m["sensor_offset"] = json!(number_pair(o, "--sensor-offset")?);
    }
    if let Some(n) = a.landmark_count {
        m["landmark_count"] = json!(n);
    }
    if let Some(d) = a.landmark_min_separation {
        if !(d.is_finite() && d >= 0.0) {
            return Err(CliError(format!(
                "--landmark-min-separation must be a number >= 0, found {d}"
            )));
        }
        m["landmark_min_separation"] = json!(d);
    }
    if let Some(q) = a.max_outliers {
        m["max_outliers"] = json!(q);
    }
    Ok(())
}

/// The `--initial` box (lo,hi per axis), the origin when absent.
fn initial_box(a: &Args, dim: usize) -> Result<Value, CliError> {
    let Some(s) = &a.initial else {
        return Ok(json!(vec![json!([0.0, 0.0]); dim]));
    };
    let v = flag_numbers(s).ok_or_else(|| CliError(format!("--initial {s}: expected numbers")))?;
    if v.len() != 2 * dim {
        return Err(CliError(format!(
            "--initial {s}: expected {} numbers (lo,hi per axis)",
            2 * dim
        )));
    }
    Ok(json!(v
        .chunks(2)
        .map(|c| json!([c[0], c[1]]))
        .collect::<Vec<_>>()))
}

fn generic(a: &Args) -> Result<Value, CliError> {
    let model = a
        .model
        .as_deref()
        .ok_or_else(|| CliError("--model is required (or --cmu-plaza DIR)".into()))?;
    let chans = channels(model)?;
    // The model's flags are checked before the files are read.
    let mut fields = json!({});
    model_fields(a, model, &mut fields)?;
    let dim = if model == "auv3d" { 3 } else { 2 };
    let log_path = a
        .log
        .as_ref()
        .ok_or_else(|| CliError("--log is required".into()))?;
    let det_path = a
        .detections
        .as_ref()
        .ok_or_else(|| CliError("--detections is required".into()))?;
    let log = read_csv(log_path, true)?;
    let mut read = vec!["t"];
    read.extend_from_slice(chans);
    check_columns(&log, log_path, &read)?;
    let t_col = log.header.iter().position(|h| h == "t").ok_or_else(|| {
        CliError(format!(
            "{}: missing column 't' in the header",
            log_path.display()
        ))
    })?;
    if log.rows.len() < 2 {
        return Err(CliError(format!(
            "{}: at least 2 rows are needed",
            log_path.display()
        )));
    }
    let t: Vec<f64> = log.rows.iter().map(|r| r[t_col]).collect();
    let dt = time_step(a, &t, log_path)?;
    let errors = channel_errors(a, model, chans)?;
    let steps = log.rows.len();
    let inputs = channel_inputs(&log, log_path, chans, &errors)?;
    let dets = csv_detections(det_path, t[0], dt, steps)?;
    let mut m = json!({
        "format": "nvector-mission/1",
        "name": a.name.clone().unwrap_or_else(|| log_path.file_stem().and_then(|s| s.to_str()).unwrap_or("import").to_string()),
        "model": model,
        "dt": dt,
        "steps": steps,
        "initial_position": initial_box(a, dim)?,
        "inputs": Value::Object(inputs),
        "motion_error": a.motion_error,
        "detections": dets,
        "meta": {"imported_from": log_path.display().to_string()},
    });
    if let (Some(m), Value::Object(fields)) = (m.as_object_mut(), fields) {
        m.extend(fields);
    }
    Ok(m)
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    // Each planted range is a detection: as many as a simulation may add.
    let most = nvector_core::slam::simulate::MAX_FALSE_DETECTIONS;
    if a.false_detections > most {
        return Err(CliError(format!(
            "--false-detections must be at most {most}"
        )));
    }
    if let Some(dir) = &a.locards_mlat {
        let p = crate::cli::import_locards::locards(dir, a.set)?;
        nvector_core::tdoa::problem::TdoaProblem::from_value(&p)
            .map_err(|e| CliError(format!("the imported TDOA problem is invalid: {e}")))?;
        return crate::cli::import_woods::write_json(&p, a.out.as_deref());
    }
    if !(0.0..0.5).contains(&a.outlier_share) {
        return Err(CliError(format!(
            "--outlier-share must be in [0, 0.5), found {}",
            a.outlier_share
        )));
    }
    let real = a.cmu_plaza.is_some() || a.utias_woods.is_some();
    if !real && a.false_detections > 0 {
        return Err(CliError(
            "--false-detections needs --cmu-plaza (plant false ranges in a real log)".into(),
        ));
    }
    if !real && a.outlier_share > 0.0 {
        return Err(CliError(
            "--outlier-share needs --cmu-plaza or --utias-woods (bands derived against a truth)"
                .into(),
        ));
    }
    let mut mission = if a.sensor.sensor_model.is_some() {
        crate::cli::calibrate::import(
            &a.sensor,
            &crate::cli::calibrate::ImportFlags {
                model: a.model.as_deref(),
                log: a.log.as_deref(),
                detections: a.detections.as_deref(),
                operator: a.operator,
                name: a.name.as_deref(),
                initial: a.initial.as_deref(),
                initial_heading: a.initial_heading.as_deref(),
                landmark_count: a.landmark_count,
                landmark_min_separation: a.landmark_min_separation,
                max_outliers: a.max_outliers,
            },
        )?
    } else if let Some(dir) = &a.utias_woods {
        crate::cli::import_woods::utias_woods(dir, a.operator, a.outlier_share)?
    } else if let Some(dir) = &a.cmu_plaza {
        cmu_plaza(dir, a.operator, a.outlier_share)?
    } else {
        generic(&a)?
    };
    if a.false_detections > 0 {
        plant_false_ranges(&mut mission, a.false_detections, a.seed)?;
    }
    // Whatever was built must be a valid mission.
    nvector_core::slam::mission::Mission::from_value(&mission)
        .map_err(|e| CliError(format!("the imported mission is invalid: {e}")))?;
    crate::cli::import_woods::write(&mission, a.out.as_deref())
}

/// Plants `count` false ranges in an imported mission: each at a random
/// step, with a range interval as wide as the real ones, drawn over the
/// span of the real ranges, and no operator label; `truth.matching` is null
/// for them, and `count` is added to `max_outliers`. Detections stay in step
/// order. Deterministic for a seed.
///
/// A planted range is *false* (formats.md: no landmark there): a draw is
/// drawn again while its interval holds, or may hold, a landmark's true
/// distance from the sensor at its step ([`may_see_a_landmark`]); a range
/// that holds one would be a true detection of that landmark, labelled
/// false. An error when [`MAX_DRAWS`] draws a range do not find one.
pub fn plant_false_ranges(mission: &mut Value, count: usize, seed: u64) -> Result<(), CliError> {
    let mut rng = nvector_core::slam::simulate::Rng::new(seed);
    let steps = mission["steps"].as_u64().unwrap_or(0) as usize;
    let empty = Vec::new();
    let dets = mission["detections"].as_array().unwrap_or(&empty);
    let truth = mission["truth"]["matching"].as_array().unwrap_or(&empty);
    // (step, input index, detection, true landmark)
    let mut all: Vec<(usize, usize, Value, Value)> = Vec::with_capacity(dets.len() + count);
    let (mut lo_min, mut lo_max, mut width) = (f64::INFINITY, 0.0f64, 0.0f64);
    for (i, d) in dets.iter().enumerate() {
        let (lo, hi) = (
            d["range"][0].as_f64().unwrap_or(0.0),
            d["range"][1].as_f64().unwrap_or(0.0),
        );
        (lo_min, lo_max, width) = (lo_min.min(lo), lo_max.max(lo), width.max(hi - lo));
        let step = d["step"].as_u64().unwrap_or(0) as usize;
        all.push((
            step,
            i,
            d.clone(),
            truth.get(i).cloned().unwrap_or(Value::Null),
        ));
    }
    if !lo_min.is_finite() {
        (lo_min, lo_max, width) = (0.0, 10.0, 1.0);
    }
    for x in 0..count {
        let (step, lo) = (0..MAX_DRAWS)
            .map(|_| {
                let step = ((rng.unit() * (steps + 1) as f64) as usize).min(steps);
                (step, lo_min + (lo_max - lo_min) * rng.unit())
            })
            .find(|&(step, lo)| !may_see_a_landmark(mission, step, lo, lo + width))
            .ok_or_else(|| {
                CliError(format!(
                    "--false-detections: no false range found in {MAX_DRAWS} draws \
                     (every draw holds a landmark's true distance, or the truth is unknown)"
                ))
            })?;
        let d = json!({"step": step, "range": [lo, lo + width]});
        all.push((step, dets.len() + x, d, Value::Null));
    }
    all.sort_by_key(|d| (d.0, d.1));
    // The ranges an outlier share left outside, renumbered.
    let mut new_index = vec![0usize; all.len()];
    for (new, d) in all.iter().enumerate() {
        new_index[d.1] = new;
    }
    let outside = mission
        .get_mut("meta")
        .and_then(|m| m.get_mut("outlier_share"))
        .and_then(|o| o.get_mut("outside"))
        .and_then(Value::as_array_mut);
    if let Some(outside) = outside {
        for j in outside.iter_mut() {
            *j = json!(new_index[j.as_u64().unwrap_or(0) as usize]);
        }
    }
    mission["detections"] = Value::Array(all.iter().map(|d| d.2.clone()).collect());
    mission["truth"]["matching"] = Value::Array(all.into_iter().map(|d| d.3).collect());
    let before = mission["max_outliers"].as_u64().unwrap_or(0) as usize;
    mission["max_outliers"] = json!(before + count);
    if let Some(name) = mission["name"].as_str() {
        mission["name"] = json!(format!("{name}-false-{count}"));
    }
    Ok(())
}

/// Most draws for one planted range.
const MAX_DRAWS: usize = 10_000;

/// Whether the range interval [lo, hi] at `step` holds, or may hold, the
/// true distance from the sensor to a landmark of `truth.landmarks`: the
/// sensor is within |`sensor_offset`| of the true position, so a distance
/// d from the position is [d - |o|, d + |o|] from the sensor. True where
/// the truth cannot tell (no true position at that step, no landmarks).
fn may_see_a_landmark(mission: &Value, step: usize, lo: f64, hi: f64) -> bool {
    let point = |v: &Value| -> Option<(f64, f64)> { Some((v[0].as_f64()?, v[1].as_f64()?)) };
    let Some((px, py)) = point(&mission["truth"]["positions"][step]) else {
        return true;
    };
    let Some(landmarks) = mission["truth"]["landmarks"].as_array() else {
        return true;
    };
    let o = point(&mission["sensor_offset"]).map_or(0.0, |(x, y)| x.hypot(y));
    landmarks.iter().any(|l| match point(l) {
        Some((lx, ly)) => {
            let d = (lx - px).hypot(ly - py);
            d + o >= lo && d - o <= hi
        }
        None => true,
    })
}

/// Bounds of the CMU import (docs/cmu-plaza1.md explains each).
pub mod cmu {
    /// Error bound on delta_distance per step (m).
    pub const SPEED_ERROR: f64 = 0.01;
    /// Error bound on the integrated heading (rad).
    pub const HEADING_ERROR: f64 = 0.02;
    /// Below this delta_distance (m per step) the robot may be backing up.
    pub const BACKUP_BELOW: f64 = 0.08;
    /// A step whose residual against the interval model exceeds this (m) is
    /// an anomaly and gets its own motion error.
    pub const FLAG_ABOVE: f64 = 0.02;
    /// Margin added to every bound derived from the data.
    pub const MARGIN: f64 = 0.05;
    /// Below this delta_distance (m per step) the odometry says the robot
    /// stands still (a zero-velocity step).
    pub const STILL_BELOW: f64 = 0.01;
    /// Margin added to the largest residual of the zero-velocity steps.
    pub const STILL_MARGIN: f64 = 0.001;
    /// Margin added to the largest residual of the other ordinary steps.
    pub const ORDINARY_MARGIN: f64 = 0.005;
}

/// The odometry of Plaza 1 as the model's inputs: the heading integrated
/// from the known initial heading, and the speed per step (dt = 1 step:
/// `delta_distance`, its sign unknown below [`cmu::BACKUP_BELOW`]).
struct CmuInputs {
    heading: Vec<f64>,
    speed: Vec<[f64; 2]>,
}

fn cmu_inputs(dr: &[Vec<f64>], gt: &[Vec<f64>]) -> CmuInputs {
    use cmu::*;
    let mut heading = Vec::with_capacity(dr.len());
    let mut h = gt[0][3];
    for row in dr {
        heading.push(h);
        h += row[2];
    }
    let speed = dr
        .iter()
        .map(|r| {
            let d = r[1];
            let lo = if d < BACKUP_BELOW {
                -d - SPEED_ERROR
            } else {
                d - SPEED_ERROR
            };
            [lo, d + SPEED_ERROR]
        })
        .collect();
    CmuInputs { heading, speed }
}

/// The per-step motion error of Plaza 1 (docs/cmu-plaza1.md, "Motion
/// error per step") and the figures `meta` records.
struct CmuMotion {
    per_step: Vec<f64>,
    ordinary: f64,
    stationary: f64,
    stationary_steps: usize,
    anomalous_steps: usize,
}

/// The residual of each true step against the interval model (speed and
/// heading intervals): v·(cos, sin) enclosed by sampling the corners and
/// the extremal angles inside.
fn cmu_residuals(gt: &[Vec<f64>], inputs: &CmuInputs) -> Vec<f64> {
    use cmu::*;
    let (speed, heading) = (&inputs.speed, &inputs.heading);
    (0..speed.len())
        .map(|i| {
            let (dx, dy) = (gt[i + 1][1] - gt[i][1], gt[i + 1][2] - gt[i][2]);
            let (mut bx, mut by) = (
                (f64::INFINITY, f64::NEG_INFINITY),
                (f64::INFINITY, f64::NEG_INFINITY),
            );
            for v in [
                speed[i][0],
                speed[i][1],
                0.0f64.clamp(speed[i][0], speed[i][1]),
            ] {
                for k in 0..=8 {
                    let a = heading[i] - HEADING_ERROR + 2.0 * HEADING_ERROR * k as f64 / 8.0;
                    let (x, y) = (v * a.cos(), v * a.sin());
                    bx = (bx.0.min(x), bx.1.max(x));
                    by = (by.0.min(y), by.1.max(y));
                }
            }
            let ex = (bx.0 - dx).max(dx - bx.1).max(0.0);
            let ey = (by.0 - dy).max(dy - by.1).max(0.0);
            ex.max(ey)
        })
        .collect()
}

/// Two classes of ordinary steps (zero-velocity ones, where the odometry
/// reports under [`cmu::STILL_BELOW`], and moving ones), each bounded by
/// its own largest residual plus a margin; the anomalies (residual above
/// [`cmu::FLAG_ABOVE`]) get their own residual × 1.5 + margin.
fn cmu_motion(dr: &[Vec<f64>], residual: &[f64]) -> CmuMotion {
    use cmu::*;
    let n = residual.len();
    let still = |i: usize| dr[i][1] < STILL_BELOW;
    let class_max = |moving: bool| {
        (0..n)
            .filter(|&i| residual[i] <= FLAG_ABOVE && still(i) != moving)
            .map(|i| residual[i])
            .fold(0.0, f64::max)
    };
    let (ordinary, stationary) = (
        class_max(true) + ORDINARY_MARGIN,
        class_max(false) + STILL_MARGIN,
    );
    let per_step = (0..n)
        .map(|i| {
            let r = residual[i];
            if r > FLAG_ABOVE {
                r * 1.5 + MARGIN
            } else if still(i) {
                stationary
            } else {
                ordinary
            }
        })
        .collect();
    CmuMotion {
        per_step,
        ordinary,
        stationary,
        stationary_steps: (0..n)
            .filter(|&i| still(i) && residual[i] <= FLAG_ABOVE)
            .count(),
        anomalous_steps: residual.iter().filter(|&&r| r > FLAG_ABOVE).count(),
    }
}

/// The ranges of Plaza 1, each matched to the nearest odometry row by
/// time, with its beacon (0-based index of the sorted ids) and its error
/// against the true distance at that row.
struct CmuRanges {
    /// (step, measured range, landmark index).
    dets: Vec<(usize, f64, usize)>,
    /// Measured minus true distance, per range.
    errs: Vec<f64>,
    /// The beacons' positions, by landmark index.
    landmarks: Vec<[f64; 2]>,
}

fn cmu_ranges(td: &[Vec<f64>], tl: &[Vec<f64>], gt: &[Vec<f64>]) -> Result<CmuRanges, CliError> {
    let times: Vec<f64> = gt.iter().map(|r| r[0]).collect();
    let mut ids: Vec<i64> = tl.iter().map(|r| r[0] as i64).collect();
    ids.sort_unstable();
    let beacon = |id: i64| tl.iter().find(|r| r[0] as i64 == id).map(|r| [r[1], r[2]]);
    let mut out = CmuRanges {
        dets: Vec::with_capacity(td.len()),
        errs: Vec::with_capacity(td.len()),
        landmarks: ids.iter().filter_map(|&id| beacon(id)).collect(),
    };
    for r in td {
        let (t, id, range) = (r[0], r[2] as i64, r[3]);
        let step = match times.binary_search_by(|x| x.total_cmp(&t)) {
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
        };
        let (Ok(li), Some([bx, by])) = (ids.binary_search(&id), beacon(id)) else {
            return Err(CliError(format!(
                "Plaza1_TD.txt: beacon {id} is not in Plaza1_TL.csv"
            )));
        };
        let truth = ((gt[step][1] - bx).powi(2) + (gt[step][2] - by).powi(2)).sqrt();
        out.errs.push(range - truth);
        out.dets.push((step, range, li));
    }
    Ok(out)
}

/// The range band of the import: error = measured - true distance lies in
/// `[offset.0 + slope·r, offset.1 + slope·r]` (r the measured range), on
/// all ranges but `outside`.
struct RangeBand {
    slope: f64,
    offset: (f64, f64),
    /// The ranges left outside the band (by index), at most the share
    /// asked for; their true distance is outside their interval.
    outside: Vec<usize>,
}

/// The lowest and highest values of `x` once the `drop_lo` lowest and the
/// `drop_hi` highest are left out (all of `x` when both are 0).
fn trimmed_span(x: &mut [f64], drop_lo: usize, drop_hi: usize) -> (f64, f64) {
    x.sort_unstable_by(f64::total_cmp);
    (x[drop_lo], x[x.len() - 1 - drop_hi])
}

/// The range band (docs/cmu-plaza1.md): a scale error of the ranging plus
/// an offset, with the slope b that makes the band narrowest. With the
/// outlier share P > 0 the band is the central (1 - P) share: of the k
/// residuals e - b·r, the floor(P·k / 2) lowest and the rest of floor(P·k)
/// highest are left out, and b makes that trimmed band narrowest (the
/// ternary search of the P = 0 case; the trimmed width need not be convex,
/// so b is a local optimum; which ranges fall outside is then counted
/// exactly on the final intervals, margin included).
fn range_band(ranges: &CmuRanges, share: f64) -> RangeBand {
    let k = ranges.errs.len();
    let dropped = ((share * k as f64).floor() as usize).min(k.saturating_sub(1));
    let (drop_lo, drop_hi) = (dropped / 2, dropped - dropped / 2);
    let mut buf = vec![0.0; k];
    let mut band = |b: f64| {
        for ((x, d), &e) in buf.iter_mut().zip(&ranges.dets).zip(&ranges.errs) {
            *x = e - b * d.1;
        }
        trimmed_span(&mut buf, drop_lo, drop_hi)
    };
    let (mut b_lo, mut b_hi) = (-1.0f64, 1.0f64);
    for _ in 0..200 {
        let (m1, m2) = (b_lo + (b_hi - b_lo) / 3.0, b_hi - (b_hi - b_lo) / 3.0);
        let (w1, w2) = (band(m1), band(m2));
        if w1.1 - w1.0 <= w2.1 - w2.0 {
            b_hi = m2;
        } else {
            b_lo = m1;
        }
    }
    let slope = (b_lo + b_hi) / 2.0;
    let offset = band(slope);
    let mut out = RangeBand {
        slope,
        offset,
        outside: Vec::new(),
    };
    out.outside = (0..k)
        .filter(|&j| {
            let truth = ranges.dets[j].1 - ranges.errs[j];
            let [lo, hi] = out.interval(ranges.dets[j].1);
            !(lo <= truth && truth <= hi)
        })
        .collect();
    out
}

impl RangeBand {
    /// The interval of the true distance for a measured range:
    /// true = measured - error, error in offset + slope·measured, widened
    /// by the margin.
    fn interval(&self, range: f64) -> [f64; 2] {
        let (alo, ahi) = self.offset;
        [
            (range - (ahi + self.slope * range) - cmu::MARGIN).max(0.0),
            range - (alo + self.slope * range) + cmu::MARGIN,
        ]
    }
}

/// The CMU Plaza 1 dataset as a mission (beacon ids hidden unless
/// `operator`), with the ground truth. `outlier_share` P: the range band
/// holds the central (1 - P) share of the residuals, and `max_outliers` is
/// the count left outside (0: every range inside, no `max_outliers`).
pub fn cmu_plaza(dir: &Path, operator: bool, outlier_share: f64) -> Result<Value, CliError> {
    // The columns read below: DR time, distance, heading change; GT time,
    // x, y, heading; TD time, (unused), beacon id, range; TL id, x, y.
    let dr = read_table(&dir.join("Plaza1_DR.txt"), 3)?;
    let gt = read_table(&dir.join("Plaza1_GT.csv"), 4)?;
    let td = read_table(&dir.join("Plaza1_TD.txt"), 4)?;
    let tl = read_table(&dir.join("Plaza1_TL.csv"), 3)?;
    let n = dr.len();
    if td.is_empty() || tl.is_empty() || n == 0 {
        return Err(CliError(format!(
            "{}: Plaza1_TD.txt, Plaza1_TL.csv and Plaza1_DR.txt must each hold a row ({}, {} and {} rows)",
            dir.display(),
            td.len(),
            tl.len(),
            n
        )));
    }
    if gt.len() != n + 1 {
        return Err(CliError(format!(
            "{}: expected one more ground-truth row than odometry rows ({} and {})",
            dir.display(),
            gt.len(),
            n
        )));
    }
    let inputs = cmu_inputs(&dr, &gt);
    let motion = cmu_motion(&dr, &cmu_residuals(&gt, &inputs));
    let ranges = cmu_ranges(&td, &tl, &gt)?;
    let band = range_band(&ranges, outlier_share);
    let detections: Vec<Value> = ranges
        .dets
        .iter()
        .map(|&(step, range, li)| {
            let mut d = json!({"step": step, "range": band.interval(range)});
            if operator {
                d["landmark"] = json!(li);
            }
            d
        })
        .collect();
    let mut mission = cmu_document(operator, &gt, &inputs, &motion, detections);
    let meta = &mut mission["meta"];
    meta["range_error_bounds"] =
        json!(ranges
            .errs
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |a, &e| [
                a[0].min(e),
                a[1].max(e)
            ]));
    meta["range_error_model"] = json!({"slope": band.slope, "offset": [band.offset.0, band.offset.1], "margin": cmu::MARGIN});
    if outlier_share > 0.0 {
        meta["outlier_share"] = json!({
            "share": outlier_share,
            "method": "the range band holds the central (1 - share) of the residuals: floor(share k / 2) lowest and the rest of floor(share k) highest left out, the slope making that band narrowest; `outside` lists the ranges (by index) whose true distance is outside their interval, margin included, and max_outliers is their count",
            "outside": band.outside,
        });
        mission["max_outliers"] = json!(band.outside.len());
    }
    let matching: Vec<usize> = ranges.dets.iter().map(|d| d.2).collect();
    mission["truth"]["landmarks"] = json!(ranges.landmarks);
    mission["truth"]["matching"] = json!(matching);
    mission["landmark_count"] = json!(ranges.landmarks.len());
    Ok(mission)
}

/// The mission document of Plaza 1 around its detections (the range
/// model's `meta`, the landmarks and the matching are added by the caller).
fn cmu_document(
    operator: bool,
    gt: &[Vec<f64>],
    inputs: &CmuInputs,
    motion: &CmuMotion,
    detections: Vec<Value>,
) -> Value {
    let speed = &inputs.speed;
    let positions: Vec<[f64; 2]> = gt.iter().map(|r| [r[1], r[2]]).collect();
    let e0 = 0.01;
    json!({
        "format": "nvector-mission/1",
        "name": if operator { "cmu-plaza1-operator" } else { "cmu-plaza1" },
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": speed.len(),
        "initial_position": [[gt[0][1] - e0, gt[0][1] + e0], [gt[0][2] - e0, gt[0][2] + e0]],
        "final_position": null,
        "inputs": {
            "speed": {"lo": speed.iter().map(|s| s[0]).collect::<Vec<_>>(), "hi": speed.iter().map(|s| s[1]).collect::<Vec<_>>()},
            "heading": {"value": inputs.heading, "error": cmu::HEADING_ERROR},
        },
        "motion_error": motion.per_step,
        "detections": detections,
        "meta": {
            "source": "CMU Plaza 1 (Djugash and Singh), via GTSAM's examples",
            "ordinary_motion_error": motion.ordinary,
            "stationary_motion_error": motion.stationary,
            "stationary_steps": motion.stationary_steps,
            "anomalous_steps": motion.anomalous_steps,
            "dt_note": "one step per odometry row; speed is metres per step",
        },
        "truth": {"positions": positions},
    })
}
