//! `nvector calibrate`: a sensor model (`nvector-sensor-model/1`) fitted
//! on a run with truth, and `nvector import --sensor-model`: a mission
//! from raw measurements and that model (docs/calibration.md). The fitting
//! and the mission live in `nvector-import`; this file reads the flags.

use crate::CliError;
use nvector_import::apply;
use nvector_import::calibrate::{self, convert, data};
use nvector_import::sensor_model::SensorModel;
use nvector_import::{plaza, woods};
use std::path::{Path, PathBuf};

/// Arguments of `nvector calibrate`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion model of the log: odometry2d or unicycle2d.
    #[arg(long, value_parser = ["odometry2d", "unicycle2d"], required_unless_present = "convert")]
    model: Option<String>,
    /// The log CSV: `t` and the model's channels (odometry2d:
    /// speed,turn_rate; unicycle2d: speed,heading).
    #[arg(long, required_unless_present = "convert")]
    log: Option<PathBuf>,
    /// The raw detections CSV: `t,range[,bearing][,scan],landmark`.
    #[arg(long, required_unless_present = "convert")]
    detections: Option<PathBuf>,
    /// The truth CSV: `t,x,y[,heading]`, empty cells where it is missing.
    #[arg(long, required_unless_present = "convert")]
    truth: Option<PathBuf>,
    /// The landmarks CSV: `id,x,y`.
    #[arg(long, required_unless_present = "convert")]
    landmarks: Option<PathBuf>,
    /// Where the range-and-bearing sensor sits in the body frame, X,Y (m).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    sensor_offset: Option<String>,
    /// The relative margin F: every fitted bound is multiplied by 1 + F
    /// (the fewest samples a bound needs grows as F shrinks:
    /// docs/calibration.md); NAME=F gives one bound its own (heading,
    /// motion_error, heading_drift, motion_drift, range, bearing). Repeat
    /// the flag for several.
    #[arg(long, value_name = "F|NAME=F", allow_negative_numbers = true)]
    margin: Vec<String>,
    /// A bound stated instead of fitted, NAME=E (only `heading`: for a
    /// truth whose heading cannot calibrate it).
    #[arg(long, value_name = "NAME=E")]
    assume: Vec<String>,
    /// The zero-velocity class of the motion error: the steps reporting a
    /// distance |speed|·dt below D (m) get their own bound, fitted on
    /// theirs (docs/calibration.md, "Methods").
    #[arg(long, value_name = "D")]
    still_below: Option<f64>,
    /// The per-step bounds (heading, motion error) constant, the largest
    /// residual, instead of affine in the step's distance and turn.
    #[arg(long)]
    constant_steps: bool,
    /// The share P of the residuals each band (range, bearing) leaves out,
    /// 0 <= P < 0.5 (docs/outliers.md).
    #[arg(
        long,
        value_name = "P",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    outlier_share: f64,
    /// A same-run calibration (the oracle): the model is for this run
    /// alone (no sample rule, F may be 0, steps may be flagged); applied
    /// to another run it is no guarantee, with --flag it is refused.
    #[arg(long)]
    same_run: bool,
    /// With --same-run: a step whose residual is above T gets its own
    /// bound, NAME=T (heading in rad, motion_error in m per axis). Repeat
    /// for both.
    #[arg(long, value_name = "NAME=T", requires = "same_run")]
    flag: Vec<String>,
    /// With --flag: a flagged step's bound is its residual x FACTOR +
    /// MARGIN (default 1.5,0.01).
    #[arg(long, value_name = "FACTOR,MARGIN")]
    flag_bound: Option<String>,
    /// With --same-run: fit the per-step bounds and the windows on the
    /// truth completed across its gaps (linear interpolation), the steps
    /// touching a gap exempt from the heading windows.
    #[arg(long, requires = "same_run")]
    complete_gaps: bool,
    /// Choose the margins on a held-out part of this run: fit on its steps
    /// before 1 - FRACTION of them, check on the rest, raise the margin of
    /// each bound broken (0.1, 0.25, 0.5, 0.75, 1, 1.5, 2, 3) until the
    /// check is clean; then fit the whole run with those margins
    /// (docs/calibration.md, step 3). The margins chosen are printed.
    #[arg(long, value_name = "FRACTION")]
    holdout: Option<f64>,
    /// Instead of fitting: how a model holds on this run (the samples it
    /// leaves outside, bound by bound), as JSON; exit 1 when any.
    #[arg(long, value_name = "SENSOR.json")]
    verify: Option<PathBuf>,
    /// Output sensor model (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write a bundled data set as the calibration's CSVs instead:
    /// `woods` or `plaza`, read from --data, written to --out-dir.
    #[arg(long, hide = true, value_parser = ["woods", "plaza"])]
    convert: Option<String>,
    /// With --convert: the data set's directory.
    #[arg(long, hide = true, requires = "convert")]
    data: Option<PathBuf>,
    /// With --convert: the first time kept (the data set's clock).
    #[arg(long, hide = true, allow_negative_numbers = true)]
    from: Option<f64>,
    /// With --convert: the first time not kept.
    #[arg(long, hide = true, allow_negative_numbers = true)]
    to: Option<f64>,
    /// With --convert: where the four CSVs go.
    #[arg(long, hide = true, requires = "convert")]
    out_dir: Option<PathBuf>,
}

/// Two finite numbers `A,B` of the flag `flag`.
fn pair(s: &str, flag: &str) -> Result<[f64; 2], CliError> {
    let v: Option<Vec<f64>> = s.split(',').map(|x| x.trim().parse().ok()).collect();
    match v.as_deref() {
        Some([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        _ => Err(CliError(format!("{flag} {s}: expected two finite numbers"))),
    }
}

fn required<'a>(p: &'a Option<PathBuf>, flag: &str) -> Result<&'a Path, CliError> {
    p.as_deref()
        .ok_or_else(|| CliError(format!("{flag} is required")))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    if let Some(kind) = &a.convert {
        return run_convert(kind, &a);
    }
    let model = data::Model::parse(a.model.as_deref().unwrap_or(""))?;
    let log = required(&a.log, "--log")?;
    let files = data::Files {
        log,
        detections: required(&a.detections, "--detections")?,
        truth: Some(required(&a.truth, "--truth")?),
        landmarks: Some(required(&a.landmarks, "--landmarks")?),
    };
    let run = data::read_run(model, &files)?;
    if let Some(path) = &a.verify {
        return run_verify(path, &run);
    }
    let mut assume_heading = None;
    for s in &a.assume {
        match s.split_once('=') {
            Some(("heading", e)) => {
                assume_heading = Some(
                    e.parse::<f64>()
                        .map_err(|_| CliError(format!("--assume {s}: E must be a number (rad)")))?,
                )
            }
            _ => {
                return Err(CliError(format!(
                    "--assume {s}: expected heading=E (the only bound that may be stated)"
                )))
            }
        }
    }
    let (relative_margin, bound_margins) = margins(&a.margin)?;
    let options = calibrate::Options {
        relative_margin,
        bound_margins,
        sensor_offset: a
            .sensor_offset
            .as_deref()
            .map(|s| pair(s, "--sensor-offset"))
            .transpose()?
            .unwrap_or([0.0, 0.0]),
        assume_heading,
        source: format!(
            "{} (t {} to {} s, {} steps)",
            log.display(),
            run.t[0],
            run.t[run.steps() - 1],
            run.steps()
        ),
        same_run: a.same_run,
        flag: flag(&a)?,
        still_below: a.still_below,
        constant_steps: a.constant_steps,
        outlier_share: a.outlier_share,
    };
    let options = match a.holdout {
        Some(f) => held_out(&run, options, f)?,
        None => options,
    };
    let sensor = calibrate::calibrate(&run, &options)?;
    for r in &sensor.refused {
        say!("nvector calibrate: left out {}: {}", r.bound, r.reason);
    }
    let text = serde_json::to_string_pretty(&sensor)?;
    write_text(&text, a.out.as_deref())
}

/// `--holdout FRACTION`: the margins the held-out part asks for, said on
/// standard error.
fn held_out(
    run: &data::Run,
    o: calibrate::Options,
    fraction: f64,
) -> Result<calibrate::Options, CliError> {
    let (chosen, cov) = calibrate::holdout(run, &o, fraction)?;
    let margins: Vec<String> = calibrate::BOUND_NAMES
        .iter()
        .map(|n| format!("{n}={}", chosen.margin(n)))
        .collect();
    let outside: usize = cov.iter().map(|c| c.outside).sum();
    say!(
        "nvector calibrate: --holdout {fraction}: margins {} ({outside} sample(s) of the held-out part outside{})",
        margins.join(" "),
        if outside > 0 { ": the ladder ended" } else { "" }
    );
    Ok(chosen)
}

/// The `--flag NAME=T`, `--flag-bound` and `--complete-gaps` flags.
fn flag(a: &Args) -> Result<Option<calibrate::Flag>, CliError> {
    if a.flag.is_empty() && !a.complete_gaps {
        return Ok(None);
    }
    let [factor, margin] = match &a.flag_bound {
        Some(s) => pair(s, "--flag-bound")?,
        None => [1.5, 0.01],
    };
    let mut f = calibrate::Flag {
        heading_above: None,
        motion_above: None,
        factor,
        margin,
        complete_gaps: a.complete_gaps,
    };
    for s in &a.flag {
        let t = |x: &str| {
            x.parse::<f64>()
                .ok()
                .filter(|t| t.is_finite() && *t >= 0.0)
                .ok_or_else(|| CliError(format!("--flag {s}: T must be a number >= 0")))
        };
        match s.split_once('=') {
            Some(("heading", x)) => f.heading_above = Some(t(x)?),
            Some(("motion_error", x)) => f.motion_above = Some(t(x)?),
            _ => {
                return Err(CliError(format!(
                    "--flag {s}: expected heading=T or motion_error=T"
                )))
            }
        }
    }
    Ok(Some(f))
}

/// The `--margin` flags: the default F (0.1 unless a bare F is given) and
/// the bounds' own.
fn margins(flags: &[String]) -> Result<(f64, Vec<(String, f64)>), CliError> {
    let number = |s: &str, flag: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|_| CliError(format!("--margin {flag}: F must be a number")))
    };
    let (mut default, mut named) = (0.1, Vec::new());
    for m in flags {
        match m.split_once('=') {
            Some((name, f)) => named.push((name.trim().to_string(), number(f, m)?)),
            None => default = number(m, m)?,
        }
    }
    Ok((default, named))
}

fn write_text(text: &str, out: Option<&Path>) -> Result<(), CliError> {
    match out {
        Some(p) => std::fs::write(p, format!("{text}\n"))
            .map_err(|e| CliError(format!("writing {}: {e}", p.display()))),
        None => {
            use std::io::Write as _;
            writeln!(std::io::stdout(), "{text}")
                .map_err(|e| CliError(format!("writing standard output: {e}")))
        }
    }
}

/// Reads a sensor model file, naming the file.
pub fn read_model(path: &Path) -> Result<SensorModel, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    SensorModel::from_json(&text).map_err(|e| CliError(format!("{}: {e}", path.display())))
}

fn run_verify(path: &Path, run: &data::Run) -> Result<(), CliError> {
    let model = read_model(path)?;
    let cov = calibrate::verify(&model, run);
    let outside: usize = cov.iter().map(|c| c.outside).sum();
    let text =
        serde_json::to_string_pretty(&serde_json::json!({"outside": outside, "bounds": cov}))?;
    write_text(&text, None)?;
    if outside > 0 {
        return Err(CliError(format!(
            "{outside} sample(s) of this run lie outside {}'s bounds",
            path.display()
        )));
    }
    Ok(())
}

fn run_convert(kind: &str, a: &Args) -> Result<(), CliError> {
    let dir = required(&a.data, "--data")?;
    let out = required(&a.out_dir, "--out-dir")?;
    let span = convert::Span {
        from: a.from.unwrap_or(f64::NEG_INFINITY),
        to: a.to.unwrap_or(f64::INFINITY),
    };
    let csvs = match kind {
        "woods" => woods::calibration_csvs(dir, span)?,
        _ => plaza::calibration_csvs(dir, span)?,
    };
    Ok(csvs.write(out)?)
}

/// The flags `nvector import --sensor-model` reads beside import's own.
#[derive(clap::Args, Default)]
pub struct ImportArgs {
    /// A sensor model (nvector-sensor-model/1, from `nvector calibrate`):
    /// --log and --detections are raw (`t,range[,bearing][,scan][,landmark]`)
    /// and the model's bounds make the intervals.
    #[arg(long, value_name = "SENSOR.json")]
    pub sensor_model: Option<PathBuf>,
    /// With --sensor-model: the truth CSV `t,x,y[,heading]`, attached for
    /// scoring only (its first pose also fixes the map's frame).
    #[arg(long, requires = "sensor_model")]
    pub truth: Option<PathBuf>,
    /// With --sensor-model: the landmarks CSV `id,x,y` (scoring only, and
    /// the default landmark_count).
    #[arg(long, requires = "sensor_model")]
    pub landmarks: Option<PathBuf>,
}

/// What `nvector import` passes on to the sensor-model import.
pub struct ImportFlags<'a> {
    /// --model.
    pub model: Option<&'a str>,
    /// --log.
    pub log: Option<&'a Path>,
    /// --detections.
    pub detections: Option<&'a Path>,
    /// --operator.
    pub operator: bool,
    /// --name.
    pub name: Option<&'a str>,
    /// --initial (LO,HI,LO,HI).
    pub initial: Option<&'a str>,
    /// --initial-heading (LO,HI).
    pub initial_heading: Option<&'a str>,
    /// --landmark-count.
    pub landmark_count: Option<usize>,
    /// --landmark-min-separation.
    pub landmark_min_separation: Option<f64>,
    /// --max-outliers.
    pub max_outliers: Option<u64>,
}

/// `nvector import --sensor-model`: the mission of a raw run under a
/// sensor model (the model's `model` when --model is absent).
pub fn import(s: &ImportArgs, f: &ImportFlags) -> Result<serde_json::Value, CliError> {
    let path = required(&s.sensor_model, "--sensor-model")?;
    let sensor = read_model(path)?;
    let model = data::Model::parse(f.model.unwrap_or(&sensor.model))?;
    let log = f.log.ok_or_else(|| CliError("--log is required".into()))?;
    let files = data::Files {
        log,
        detections: f
            .detections
            .ok_or_else(|| CliError("--detections is required".into()))?,
        truth: s.truth.as_deref(),
        landmarks: s.landmarks.as_deref(),
    };
    let run = data::read_run(model, &files)?;
    let initial = f
        .initial
        .map(|s| {
            let v: Option<Vec<f64>> = s.split(',').map(|x| x.trim().parse().ok()).collect();
            match v.as_deref() {
                Some(&[a, b, c, d]) if a <= b && c <= d => Ok([[a, b], [c, d]]),
                _ => Err(CliError(format!("--initial {s}: expected LO,HI,LO,HI"))),
            }
        })
        .transpose()?;
    let options = apply::Options {
        operator: f.operator,
        name: f.name.map_or_else(
            || {
                log.file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("import")
                    .to_string()
            },
            str::to_string,
        ),
        sensor_model: path.display().to_string(),
        initial,
        initial_heading: f
            .initial_heading
            .map(|h| pair(h, "--initial-heading"))
            .transpose()?,
        landmark_count: f.landmark_count,
        landmark_min_separation: f.landmark_min_separation,
        max_outliers: f.max_outliers,
    };
    let m = apply::mission(&run, &sensor, &options)?;
    for (k, v) in m["meta"]["calibration"]["extrapolated"]
        .as_object()
        .into_iter()
        .flatten()
    {
        if v.as_u64().is_some_and(|n| n > 0) {
            say!("nvector import: {v} reading(s) beyond the span {k}'s bound was fitted over");
        }
    }
    Ok(m)
}
