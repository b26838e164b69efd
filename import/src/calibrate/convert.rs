//! The bundled data sets as the calibration's CSVs (`log.csv`,
//! `detections.csv`, `truth.csv`, `landmarks.csv`), over a time span
//! `[from, to)`: calibrate on one span, solve another.
//!
//! - UTIAS Lost in the Woods: the log `t,speed,turn_rate` (odometry2d);
//!   detections `t,range,bearing,scan,landmark` (scan: the odometry row,
//!   the detections of one time); the truth `t,x,y,heading`, the heading
//!   unwrapped into a real number (consecutive valid rows differ by less
//!   than pi, across a gap the copy nearest the odometry's integral), the
//!   rows the motion capture marks invalid left empty.
//! - CMU Plaza 1: the log `t,speed,heading` (unicycle2d): one row per
//!   odometry row at the time of the pose it starts from, the speed its
//!   distance over the span's mean time step (so that dt × speed is the
//!   distance), the heading integrated from the truth's first heading;
//!   detections `t,range,landmark` at the time of the nearest pose; the
//!   truth `t,x,y,heading` as the data set gives it.

use super::data::read_table;
use crate::Error;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

/// The time span of a conversion: rows with `from <= t < to`.
#[derive(Clone, Copy, Debug)]
pub struct Span {
    /// First time kept.
    pub from: f64,
    /// First time not kept.
    pub to: f64,
}

/// The four files' texts.
pub struct Csvs {
    /// `log.csv`.
    pub log: String,
    /// `detections.csv`.
    pub detections: String,
    /// `truth.csv`.
    pub truth: String,
    /// `landmarks.csv`.
    pub landmarks: String,
}

impl Csvs {
    /// Writes the four files into `dir` (created if needed).
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error(format!("creating {}: {e}", dir.display())))?;
        for (name, text) in [
            ("log.csv", &self.log),
            ("detections.csv", &self.detections),
            ("truth.csv", &self.truth),
            ("landmarks.csv", &self.landmarks),
        ] {
            let p = dir.join(name);
            std::fs::write(&p, text).map_err(|e| Error(format!("writing {}: {e}", p.display())))?;
        }
        Ok(())
    }
}

/// The rows `[a, b)` of times `t` inside the span, or an error.
fn rows(t: &[f64], span: Span, what: &str) -> Result<(usize, usize), Error> {
    let a = t.partition_point(|&x| x < span.from);
    let b = t.partition_point(|&x| x < span.to);
    if b < a + 2 {
        return Err(Error(format!(
            "{what}: fewer than 2 rows in [{}, {}) (the log spans {} to {})",
            span.from,
            span.to,
            t.first().copied().unwrap_or(f64::NAN),
            t.last().copied().unwrap_or(f64::NAN)
        )));
    }
    Ok((a, b))
}

fn cell(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| v.to_string())
}

/// A table's numeric columns by name (every cell required).
fn columns(path: &Path, names: &[&str]) -> Result<Vec<Vec<f64>>, Error> {
    let tab = read_table(path)?;
    let idx: Vec<usize> = names
        .iter()
        .map(|n| tab.column(n, path))
        .collect::<Result<_, _>>()?;
    let mut out = vec![Vec::with_capacity(tab.rows.len()); names.len()];
    for r in 0..tab.rows.len() {
        for (o, &c) in out.iter_mut().zip(&idx) {
            o.push(tab.number(r, c, path)?);
        }
    }
    Ok(out)
}

/// Lost in the Woods (`dir`: odometry.csv, truth.csv, measurements.csv,
/// landmarks.csv) over `span`.
pub fn woods(dir: &Path, span: Span) -> Result<Csvs, Error> {
    let odo = columns(&dir.join("odometry.csv"), &["t", "v", "om"])?;
    let tru = columns(&dir.join("truth.csv"), &["t", "x", "y", "theta", "valid"])?;
    let meas = columns(
        &dir.join("measurements.csv"),
        &["t", "landmark", "range", "bearing"],
    )?;
    let lms = columns(&dir.join("landmarks.csv"), &["landmark", "x", "y"])?;
    let (t, v, om) = (&odo[0], &odo[1], &odo[2]);
    if tru[0].len() != t.len() {
        return Err(Error(format!(
            "{}: one truth row per odometry row expected",
            dir.display()
        )));
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    let heading = unwrap(&tru[3], &tru[4], om, dt);
    let (a, b) = rows(t, span, "odometry.csv")?;
    let mut out = Csvs {
        log: "t,speed,turn_rate\n".into(),
        detections: "t,range,bearing,scan,landmark\n".into(),
        truth: "t,x,y,heading\n".into(),
        landmarks: "id,x,y\n".into(),
    };
    for i in a..b {
        let _ = writeln!(out.log, "{},{},{}", t[i], v[i], om[i]);
    }
    for i in a..=b.min(t.len() - 1) {
        let ok = tru[4][i] != 0.0;
        let (x, y) = (ok.then_some(tru[1][i]), ok.then_some(tru[2][i]));
        let _ = writeln!(
            out.truth,
            "{},{},{},{}",
            t[i],
            cell(x),
            cell(y),
            cell(heading[i])
        );
    }
    let [mt, ml, mr, mb] = [&meas[0], &meas[1], &meas[2], &meas[3]];
    for (k, &tk) in mt.iter().enumerate() {
        let row = ((tk - t[0]) / dt).round();
        if row < a as f64 || row > b as f64 || row >= t.len() as f64 {
            continue;
        }
        let _ = writeln!(
            out.detections,
            "{},{},{},{},{}",
            t[row as usize], mr[k], mb[k], row as usize, ml[k]
        );
    }
    for ((id, x), y) in lms[0].iter().zip(&lms[1]).zip(&lms[2]) {
        let _ = writeln!(out.landmarks, "{id},{x},{y}");
    }
    Ok(out)
}

/// The truth's theta unwrapped at valid rows: consecutive valid rows
/// differ by less than pi; across a gap the copy nearest the odometry's
/// integral.
fn unwrap(theta: &[f64], valid: &[f64], om: &[f64], dt: f64) -> Vec<Option<f64>> {
    let mut out = vec![None; theta.len()];
    let mut last: Option<(usize, f64)> = None;
    for k in 0..theta.len() {
        if valid[k] == 0.0 {
            continue;
        }
        let h = match last {
            None => theta[k],
            Some((j, hj)) => {
                let predicted = hj + (j..k).map(|i| dt * om[i]).sum::<f64>();
                theta[k] + 2.0 * PI * ((predicted - theta[k]) / (2.0 * PI)).round()
            }
        };
        out[k] = Some(h);
        last = Some((k, h));
    }
    out
}

/// Rows of numbers separated by white space or commas, at least `min`
/// per row.
fn numbers(path: &Path, min: usize) -> Result<Vec<Vec<f64>>, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error(format!("reading {}: {e}", path.display())))?;
    let mut out = Vec::new();
    for (i, l) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let row: Option<Vec<f64>> = l
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect();
        match row {
            Some(r) if r.len() >= min => out.push(r),
            _ => {
                return Err(Error(format!(
                    "{}:{}: expected at least {min} finite numbers",
                    path.display(),
                    i + 1
                )))
            }
        }
    }
    Ok(out)
}

/// CMU Plaza 1 (`dir`: Plaza1_DR.txt, Plaza1_GT.csv, Plaza1_TD.txt,
/// Plaza1_TL.csv) over `span` (of the poses' times).
pub fn plaza(dir: &Path, span: Span) -> Result<Csvs, Error> {
    let dr = numbers(&dir.join("Plaza1_DR.txt"), 3)?;
    let gt = numbers(&dir.join("Plaza1_GT.csv"), 4)?;
    let td = numbers(&dir.join("Plaza1_TD.txt"), 4)?;
    let tl = numbers(&dir.join("Plaza1_TL.csv"), 3)?;
    if gt.len() != dr.len() + 1 {
        return Err(Error(format!(
            "{}: expected one more ground-truth row than odometry rows",
            dir.display()
        )));
    }
    let times: Vec<f64> = gt.iter().map(|r| r[0]).collect();
    let (a, b) = rows(&times[..dr.len()], span, "Plaza1_GT.csv")?;
    let dt = (times[b - 1] - times[a]) / (b - 1 - a) as f64;
    let mut out = Csvs {
        log: "t,speed,heading\n".into(),
        detections: "t,range,landmark\n".into(),
        truth: "t,x,y,heading\n".into(),
        landmarks: "id,x,y\n".into(),
    };
    let mut h = gt[0][3];
    for (i, r) in dr.iter().enumerate().take(b) {
        if i >= a {
            let _ = writeln!(out.log, "{},{},{}", times[i], r[1] / dt, h);
        }
        h += r[2];
    }
    for r in &gt[a..=b] {
        let _ = writeln!(out.truth, "{},{},{},{}", r[0], r[1], r[2], r[3]);
    }
    for r in &td {
        let i = times.partition_point(|&x| x < r[0]);
        let step = match i {
            0 => 0,
            i if i >= times.len() => times.len() - 1,
            i if r[0] - times[i - 1] < times[i] - r[0] => i - 1,
            i => i,
        };
        if (a..=b).contains(&step) {
            let _ = writeln!(out.detections, "{},{},{}", times[step], r[3], r[2]);
        }
    }
    for r in &tl {
        let _ = writeln!(out.landmarks, "{},{},{}", r[0], r[1], r[2]);
    }
    Ok(out)
}
