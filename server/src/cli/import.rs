//! `nvector import`: a mission from sensor logs, or a data set converted
//! (docs/cli.md, "import"). The importers are the library nvector-import;
//! this is its command line: the flags, one library call, the file
//! written.

use crate::CliError;
use nvector_import::{CsvImport, DataSet, DataSetImport};
use serde_json::Value;
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
    /// --sensor-model SENSOR.json [--truth T.csv --landmarks L.csv]: raw
    /// readings, the bounds from a calibration (docs/calibration.md).
    #[command(flatten)]
    sensor: crate::cli::calibrate::ImportArgs,
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

/// The `--error CHANNEL=E` bounds, in order.
fn channel_errors(errors: &[String]) -> Result<Vec<(String, f64)>, CliError> {
    errors
        .iter()
        .map(|e| {
            let (k, v) = e
                .split_once('=')
                .ok_or_else(|| CliError(format!("--error {e}: expected CHANNEL=E")))?;
            let v: f64 = v
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite() && *x >= 0.0)
                .ok_or_else(|| CliError(format!("--error {e}: E must be a number >= 0")))?;
            Ok((k.to_string(), v))
        })
        .collect()
}

/// The `--initial` box (lo,hi per axis) of a model of dimension `dim`.
fn initial_box(s: &str, dim: usize) -> Result<Vec<[f64; 2]>, CliError> {
    let v = flag_numbers(s).ok_or_else(|| CliError(format!("--initial {s}: expected numbers")))?;
    if v.len() != 2 * dim {
        return Err(CliError(format!(
            "--initial {s}: expected {} numbers (lo,hi per axis)",
            2 * dim
        )));
    }
    Ok(v.chunks(2).map(|c| [c[0], c[1]]).collect())
}

/// The generic import's settings from the flags.
fn csv_settings(a: &Args) -> Result<CsvImport, CliError> {
    let model = a
        .model
        .clone()
        .ok_or_else(|| CliError("--model is required (or --cmu-plaza DIR)".into()))?;
    let pair =
        |s: &Option<String>, flag: &str| s.as_deref().map(|s| number_pair(s, flag)).transpose();
    let dim = if model == "auv3d" { 3 } else { 2 };
    Ok(CsvImport {
        initial_heading: pair(&a.initial_heading, "--initial-heading")?,
        sensor_offset: pair(&a.sensor_offset, "--sensor-offset")?,
        initial: a
            .initial
            .as_deref()
            .map(|s| initial_box(s, dim))
            .transpose()?,
        errors: channel_errors(&a.errors)?,
        log: a
            .log
            .clone()
            .ok_or_else(|| CliError("--log is required".into()))?,
        detections: a
            .detections
            .clone()
            .ok_or_else(|| CliError("--detections is required".into()))?,
        model,
        dt: a.dt,
        motion_error: a.motion_error,
        heading_error: a.heading_error,
        landmark_count: a.landmark_count,
        landmark_min_separation: a.landmark_min_separation,
        max_outliers: a.max_outliers,
        name: a.name.clone(),
    })
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    nvector_import::check_false_detections(a.false_detections)?;
    let o = DataSetImport {
        operator: a.operator,
        outlier_share: a.outlier_share,
        false_detections: a.false_detections,
        seed: a.seed,
        set: a.set,
    };
    if let Some(dir) = &a.locards_mlat {
        let problem = nvector_import::import_dataset(DataSet::LocardsMlat, dir, &o)?;
        return write_json(&problem, a.out.as_deref());
    }
    if !(0.0..0.5).contains(&a.outlier_share) {
        return Err(CliError(format!(
            "--outlier-share must be in [0, 0.5), found {}",
            a.outlier_share
        )));
    }
    let data_set = match (&a.utias_woods, &a.cmu_plaza) {
        (Some(dir), _) => Some((DataSet::UtiasWoods, dir)),
        (None, Some(dir)) => Some((DataSet::CmuPlaza, dir)),
        (None, None) => None,
    };
    if a.sensor.sensor_model.is_some() {
        let mission = crate::cli::calibrate::import(
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
        )?;
        let mut mission = mission;
        nvector_import::plant_false_ranges(&mut mission, a.false_detections, a.seed)?;
        return write_json(&mission, a.out.as_deref());
    }
    let mission = match data_set {
        Some((which, dir)) => nvector_import::import_dataset(which, dir, &o)?,
        None if a.false_detections > 0 => {
            return Err(CliError(
                "--false-detections needs --cmu-plaza (plant false ranges in a real log)".into(),
            ))
        }
        None if a.outlier_share > 0.0 => return Err(CliError(
            "--outlier-share needs --cmu-plaza or --utias-woods (bands derived against a truth)"
                .into(),
        )),
        None => {
            let imported = nvector_import::import_csv(&csv_settings(&a)?)?;
            for note in &imported.notes {
                say!("nvector import: {note}");
            }
            imported.mission
        }
    };
    write_json(&mission, a.out.as_deref())
}

/// Writes a document the importer validated to `out` (standard output
/// when `None`).
fn write_json(doc: &Value, out: Option<&Path>) -> Result<(), CliError> {
    let text = serde_json::to_string(doc)?;
    match out {
        Some(p) => std::fs::write(p, text + "\n")
            .map_err(|e| CliError(format!("writing {}: {e}", p.display())))?,
        None => {
            use std::io::Write as _;
            writeln!(std::io::stdout(), "{text}")
                .map_err(|e| CliError(format!("writing standard output: {e}")))?
        }
    }
    Ok(())
}
