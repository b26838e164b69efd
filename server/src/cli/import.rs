//! `nvector import`: a mission from sensor logs.
//!
//! Generic CSV (spec/formats.md): a log with a header row and one row per
//! step (`t` and the model's channels), detections in a second CSV
//! (`t,range_lo,range_hi[,landmark]`), error bounds on the command line;
//! times are matched to steps by `round((t - t0) / dt)`.
//!
//! `--cmu-plaza DIR`: the CMU Plaza 1 range-only dataset (see
//! docs/cmu-plaza1.md for how every bound is derived from the data).

use crate::CliError;
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};

/// Arguments of `nvector import`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion model of the log: unicycle2d or auv3d.
    #[arg(long)]
    model: Option<String>,
    /// Sensor log CSV: header row with `t` and the model's channels.
    #[arg(long)]
    log: Option<PathBuf>,
    /// Detections CSV: `t,range_lo,range_hi[,landmark]`.
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
    /// drawn over the measured span, `truth.matching` null) and set
    /// `max_outliers` to it.
    #[arg(long, default_value_t = 0)]
    false_detections: usize,
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
}

/// A parsed CSV: header and numeric rows, with file/line/column in errors.
pub struct Csv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows of numbers.
    pub rows: Vec<Vec<f64>>,
}

/// Reads a CSV with a header row (comma or whitespace separated).
pub fn read_csv(path: &Path, header: bool) -> Result<Csv, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let split = |l: &str| -> Vec<String> {
        if l.contains(',') {
            l.split(',').map(|s| s.trim().to_string()).collect()
        } else {
            l.split_whitespace().map(str::to_string).collect()
        }
    };
    let head = if header {
        let (_, l) = lines
            .next()
            .ok_or_else(|| CliError(format!("{}: empty file", path.display())))?;
        split(l)
    } else {
        Vec::new()
    };
    let mut rows = Vec::new();
    for (i, l) in lines {
        let cells = split(l);
        if !head.is_empty() && cells.len() != head.len() {
            return Err(CliError(format!(
                "{}:{}: expected {} columns like the header, found {}",
                path.display(),
                i + 1,
                head.len(),
                cells.len()
            )));
        }
        let mut row = Vec::with_capacity(cells.len());
        for (c, cell) in cells.iter().enumerate() {
            let x: f64 = cell
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| {
                    CliError(format!(
                        "{}:{}: column {} ({}): '{cell}' is not a finite number",
                        path.display(),
                        i + 1,
                        c + 1,
                        head.get(c).map_or("", String::as_str)
                    ))
                })?;
            row.push(x);
        }
        rows.push(row);
    }
    Ok(Csv { header: head, rows })
}

fn channels(model: &str) -> Result<&'static [&'static str], CliError> {
    match model {
        "unicycle2d" => Ok(&["speed", "heading"]),
        "auv3d" => Ok(&["roll", "pitch", "yaw", "vx", "vy", "vz"]),
        _ => Err(CliError(format!(
            "--model: unknown model '{model}' (expected unicycle2d or auv3d)"
        ))),
    }
}

fn generic(a: &Args) -> Result<Value, CliError> {
    let model = a
        .model
        .as_deref()
        .ok_or_else(|| CliError("--model is required (or --cmu-plaza DIR)".into()))?;
    let chans = channels(model)?;
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
    let col = |name: &str| {
        log.header.iter().position(|h| h == name).ok_or_else(|| {
            CliError(format!(
                "{}: missing column '{name}' in the header",
                log_path.display()
            ))
        })
    };
    let t_col = col("t")?;
    if log.rows.len() < 2 {
        return Err(CliError(format!(
            "{}: at least 2 rows are needed",
            log_path.display()
        )));
    }
    let t: Vec<f64> = log.rows.iter().map(|r| r[t_col]).collect();
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
    let steps = log.rows.len();
    let mut inputs = Map::new();
    for ch in chans {
        let c = col(ch)?;
        let err = errors.get(*ch).cloned().ok_or_else(|| {
            CliError(format!(
                "--error {ch}=E is required (the bound of channel {ch})"
            ))
        })?;
        let values: Vec<f64> = log.rows.iter().map(|r| r[c]).collect();
        inputs.insert((*ch).into(), json!({"value": values, "error": err}));
    }
    let det = read_csv(det_path, true)?;
    for name in ["t", "range_lo", "range_hi"] {
        if !det.header.iter().any(|h| h == name) {
            return Err(CliError(format!(
                "{}: missing column '{name}' in the header",
                det_path.display()
            )));
        }
    }
    let dcol = |name: &str| det.header.iter().position(|h| h == name);
    let (tc, lc, hc, mc) = (
        dcol("t").unwrap(),
        dcol("range_lo").unwrap(),
        dcol("range_hi").unwrap(),
        dcol("landmark"),
    );
    let t0 = t[0];
    let mut dets = Vec::new();
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
        if let Some(m) = mc {
            if r[m] < 0.0 || r[m].fract() != 0.0 {
                return Err(CliError(format!(
                    "{}:{line}: landmark must be a non-negative integer",
                    det_path.display()
                )));
            }
            d["landmark"] = json!(r[m] as u64);
        }
        dets.push(d);
    }
    let initial = match &a.initial {
        Some(s) => {
            let v: Vec<f64> = s
                .split(',')
                .map(|x| x.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|_| CliError(format!("--initial {s}: expected numbers")))?;
            if v.len() != 2 * dim {
                return Err(CliError(format!(
                    "--initial {s}: expected {} numbers (lo,hi per axis)",
                    2 * dim
                )));
            }
            json!(v.chunks(2).map(|c| json!([c[0], c[1]])).collect::<Vec<_>>())
        }
        None => json!(vec![json!([0.0, 0.0]); dim]),
    };
    let mut m = json!({
        "format": "nvector-mission/1",
        "name": a.name.clone().unwrap_or_else(|| log_path.file_stem().and_then(|s| s.to_str()).unwrap_or("import").to_string()),
        "model": model,
        "dt": dt,
        "steps": steps,
        "initial_position": initial,
        "inputs": Value::Object(inputs),
        "motion_error": a.motion_error,
        "detections": dets,
        "meta": {"imported_from": log_path.display().to_string()},
    });
    if let Some(n) = a.landmark_count {
        m["landmark_count"] = json!(n);
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
        return crate::cli::import_woods::write(&p, a.out.as_deref());
    }
    if let Some(dir) = &a.utias_woods {
        let mut m = crate::cli::import_woods::utias_woods(dir, a.operator)?;
        if a.false_detections > 0 {
            plant_false_ranges(&mut m, a.false_detections, a.seed);
        }
        return crate::cli::import_woods::write(&m, a.out.as_deref());
    }
    let mission = match &a.cmu_plaza {
        Some(dir) => {
            let mut m = cmu_plaza(dir, a.operator)?;
            if a.false_detections > 0 {
                plant_false_ranges(&mut m, a.false_detections, a.seed);
            }
            m
        }
        None if a.false_detections > 0 => {
            return Err(CliError(
                "--false-detections needs --cmu-plaza (plant false ranges in a real log)".into(),
            ))
        }
        None => generic(&a)?,
    };
    // Whatever was built must be a valid mission.
    nvector_core::slam::mission::Mission::from_value(&mission)
        .map_err(|e| CliError(format!("the imported mission is invalid: {e}")))?;
    let text = serde_json::to_string(&mission)?;
    match &a.out {
        Some(p) => std::fs::write(p, text + "\n")
            .map_err(|e| CliError(format!("writing {}: {e}", p.display())))?,
        None => println!("{text}"),
    }
    Ok(())
}

/// Plants `count` false ranges in an imported mission: each at a random
/// step, with a range interval as wide as the real ones, drawn over the
/// span of the real ranges, and no operator label; `truth.matching` is null
/// for them, and `max_outliers` is set to `count`. Detections stay in step
/// order. Deterministic for a seed.
pub fn plant_false_ranges(mission: &mut Value, count: usize, seed: u64) {
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
        let step = ((rng.unit() * (steps + 1) as f64) as usize).min(steps);
        let lo = lo_min + (lo_max - lo_min) * rng.unit();
        let d = json!({"step": step, "range": [lo, lo + width]});
        all.push((step, dets.len() + x, d, Value::Null));
    }
    all.sort_by_key(|d| (d.0, d.1));
    mission["detections"] = Value::Array(all.iter().map(|d| d.2.clone()).collect());
    mission["truth"]["matching"] = Value::Array(all.into_iter().map(|d| d.3).collect());
    mission["max_outliers"] = json!(count);
    if let Some(name) = mission["name"].as_str() {
        mission["name"] = json!(format!("{name}-false-{count}"));
    }
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

/// The CMU Plaza 1 dataset as a mission (beacon ids hidden unless
/// `operator`), with the ground truth.
pub fn cmu_plaza(dir: &Path, operator: bool) -> Result<Value, CliError> {
    let dr = read_csv(&dir.join("Plaza1_DR.txt"), false)?.rows;
    let gt = read_csv(&dir.join("Plaza1_GT.csv"), false)?.rows;
    let td = read_csv(&dir.join("Plaza1_TD.txt"), false)?.rows;
    let tl = read_csv(&dir.join("Plaza1_TL.csv"), false)?.rows;
    let n = dr.len();
    if gt.len() != n + 1 || tl.is_empty() {
        return Err(CliError(format!(
            "{}: expected one more ground-truth row than odometry rows ({} and {})",
            dir.display(),
            gt.len(),
            n
        )));
    }
    // Heading integrated from the odometry, from the known initial heading.
    let mut heading = Vec::with_capacity(n);
    let mut h = gt[0][3];
    for row in &dr {
        heading.push(h);
        h += row[2];
    }
    // Speed per step (dt = 1 step): delta_distance, sign unknown when small.
    use cmu::*;
    let speed: Vec<[f64; 2]> = dr
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
    // Per-step motion error: the residual of the true step against the
    // interval model (speed and heading intervals), from the ground truth:
    // a global bound for ordinary steps, the residual itself (plus margin)
    // for the few anomalous steps (sideways jumps with no sign in the
    // odometry).
    let mut residual = Vec::with_capacity(n);
    for i in 0..n {
        let (dx, dy) = (gt[i + 1][1] - gt[i][1], gt[i + 1][2] - gt[i][2]);
        let (mut bx, mut by) = (
            (f64::INFINITY, f64::NEG_INFINITY),
            (f64::INFINITY, f64::NEG_INFINITY),
        );
        // Enclose v·(cos, sin) over the speed and heading intervals by
        // sampling their corners and the extremal angles inside.
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
        residual.push(ex.max(ey));
    }
    // Two classes of ordinary steps: zero-velocity steps (the odometry
    // reports under STILL_BELOW) and moving ones, each bounded by its own
    // largest residual plus a margin.
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
    let motion_error: Vec<f64> = (0..n)
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
    // Ranges: matched to the nearest odometry row; true distance from the
    // ground truth at that row; bias bounds from all ranges.
    let times: Vec<f64> = gt.iter().map(|r| r[0]).collect();
    let mut ids: Vec<i64> = tl.iter().map(|r| r[0] as i64).collect();
    ids.sort_unstable();
    let landmark_index = |id: i64| ids.binary_search(&id).ok();
    let beacon = |id: i64| tl.iter().find(|r| r[0] as i64 == id).map(|r| (r[1], r[2]));
    let mut dets = Vec::new();
    let mut errs = Vec::new();
    let mut matching = Vec::new();
    for r in &td {
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
        let (Some(li), Some((bx, by))) = (landmark_index(id), beacon(id)) else {
            return Err(CliError(format!(
                "Plaza1_TD.txt: beacon {id} is not in Plaza1_TL.csv"
            )));
        };
        let truth = ((gt[step][1] - bx).powi(2) + (gt[step][2] - by).powi(2)).sqrt();
        errs.push(range - truth);
        dets.push((step, range, li));
        matching.push(li);
    }
    // Range error model: error = measured - true distance lies in
    // [a_lo + b·measured, a_hi + b·measured] (a scale error of the ranging,
    // as UWB clocks give, plus an offset), with the slope b that makes the
    // band narrowest over all ranges: the width max(e - b·r) - min(e - b·r)
    // is convex in b (a maximum of linear functions minus a minimum of
    // linear functions), so a ternary search finds it.
    let band = |b: f64| {
        dets.iter()
            .zip(&errs)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, (d, &e)| {
                let x = e - b * d.1;
                (a.0.min(x), a.1.max(x))
            })
    };
    let width = |b: f64| {
        let (lo, hi) = band(b);
        hi - lo
    };
    let (mut b_lo, mut b_hi) = (-1.0f64, 1.0f64);
    for _ in 0..200 {
        let (m1, m2) = (b_lo + (b_hi - b_lo) / 3.0, b_hi - (b_hi - b_lo) / 3.0);
        if width(m1) <= width(m2) {
            b_hi = m2;
        } else {
            b_lo = m1;
        }
    }
    let slope = (b_lo + b_hi) / 2.0;
    let (alo, ahi) = band(slope);
    let (emin, emax) = errs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &e| {
            (a.0.min(e), a.1.max(e))
        });
    let detections: Vec<Value> = dets
        .iter()
        .map(|&(step, range, li)| {
            // true = measured - error, error in [alo, ahi] + slope·measured
            // (+ margin).
            let lo = (range - (ahi + slope * range) - MARGIN).max(0.0);
            let hi = range - (alo + slope * range) + MARGIN;
            let mut d = json!({"step": step, "range": [lo, hi]});
            if operator {
                d["landmark"] = json!(li);
            }
            d
        })
        .collect();
    let positions: Vec<[f64; 2]> = gt.iter().map(|r| [r[1], r[2]]).collect();
    let landmarks: Vec<[f64; 2]> = ids
        .iter()
        .map(|&id| beacon(id).map(|(x, y)| [x, y]).unwrap())
        .collect();
    let e0 = 0.01;
    Ok(json!({
        "format": "nvector-mission/1",
        "name": if operator { "cmu-plaza1-operator" } else { "cmu-plaza1" },
        "model": "unicycle2d",
        "dt": 1.0,
        "steps": n,
        "initial_position": [[gt[0][1] - e0, gt[0][1] + e0], [gt[0][2] - e0, gt[0][2] + e0]],
        "final_position": null,
        "inputs": {
            "speed": {"lo": speed.iter().map(|s| s[0]).collect::<Vec<_>>(), "hi": speed.iter().map(|s| s[1]).collect::<Vec<_>>()},
            "heading": {"value": heading, "error": HEADING_ERROR},
        },
        "motion_error": motion_error,
        "detections": detections,
        "landmark_count": ids.len(),
        "meta": {
            "source": "CMU Plaza 1 (Djugash and Singh), via GTSAM's examples",
            "range_error_bounds": [emin, emax],
            "range_error_model": {"slope": slope, "offset": [alo, ahi], "margin": MARGIN},
            "ordinary_motion_error": ordinary,
            "stationary_motion_error": stationary,
            "stationary_steps": (0..n).filter(|&i| still(i) && residual[i] <= FLAG_ABOVE).count(),
            "anomalous_steps": residual.iter().filter(|&&r| r > FLAG_ABOVE).count(),
            "dt_note": "one step per odometry row; speed is metres per step",
        },
        "truth": {"positions": positions, "landmarks": landmarks, "matching": matching},
    }))
}
