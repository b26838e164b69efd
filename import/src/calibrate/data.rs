//! A run as the calibration and `apply` read it: the odometry log, the raw
//! detections, and (for a calibration) the truth and the landmarks, from
//! the CSV files of docs/calibration.md.
//!
//! Times are matched to steps by the nearest time of the grid
//! `t(0), ..., t(N-1), t(N-1) + dt` (the log's own times, so an irregular
//! log does not drift away from its detections), within dt / 2; `dt` is
//! the log's mean spacing.

use crate::csv::{cells_of_text, read_cells, Table};
use crate::generic::integer_cell;
use crate::ImportError;
use std::path::{Path, PathBuf};

/// The motion models a sensor model covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// Speed and turn rate; the heading is a state.
    Odometry2d,
    /// Speed and a measured heading.
    Unicycle2d,
}

impl Model {
    /// The model named `name`.
    pub fn parse(name: &str) -> Result<Model, ImportError> {
        match name {
            "odometry2d" => Ok(Model::Odometry2d),
            "unicycle2d" => Ok(Model::Unicycle2d),
            _ => Err(ImportError::setting(
                "model",
                format!(
                    "--model: '{name}' has no sensor model (expected odometry2d or unicycle2d)"
                ),
            )),
        }
    }

    /// The model's name in a mission.
    pub fn name(self) -> &'static str {
        match self {
            Model::Odometry2d => "odometry2d",
            Model::Unicycle2d => "unicycle2d",
        }
    }

    /// The log's second channel: `turn_rate` or `heading`.
    pub fn rotation(self) -> &'static str {
        match self {
            Model::Odometry2d => "turn_rate",
            Model::Unicycle2d => "heading",
        }
    }
}

/// One raw detection.
#[derive(Clone, Debug, PartialEq)]
pub struct Detection {
    /// The step it is matched to.
    pub step: usize,
    /// Measured range (m).
    pub range: f64,
    /// Measured bearing (rad), when the sensor gives one.
    pub bearing: Option<f64>,
    /// The sensor scan it came from.
    pub scan: Option<u64>,
    /// The landmark's id (the truth's in a calibration, the operator's
    /// otherwise).
    pub landmark: Option<u64>,
    /// Its line in the detections file (0 when it was not read from one).
    pub line: usize,
}

/// The truth of a run: a pose per step (N + 1), `None` in its gaps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Truth {
    /// True positions.
    pub positions: Vec<Option<[f64; 2]>>,
    /// True headings (rad, a real number), all `None` without a heading
    /// column.
    pub headings: Vec<Option<f64>>,
    /// Whether the truth file has a heading column.
    pub has_heading: bool,
}

/// A run: the log (N rows: N steps), its detections, and optionally its
/// truth and landmarks.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// Motion model.
    pub model: Model,
    /// Log times (N).
    pub t: Vec<f64>,
    /// Time step: the log's mean spacing (s).
    pub dt: f64,
    /// Measured speed (m/s), N.
    pub speed: Vec<f64>,
    /// Measured turn rate (rad/s, odometry2d) or heading (rad, unicycle2d), N.
    pub rotation: Vec<f64>,
    /// Detections.
    pub detections: Vec<Detection>,
    /// Truth, for a calibration or for scoring.
    pub truth: Option<Truth>,
    /// Landmarks by id, sorted by id.
    pub landmarks: Option<Vec<(u64, [f64; 2])>>,
    /// The files the run was read from (errors name them).
    pub paths: Paths,
}

/// The files of a run, as read (empty when built in memory).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Paths {
    /// The log.
    pub log: PathBuf,
    /// The detections.
    pub detections: PathBuf,
}

impl Run {
    /// Steps N.
    pub fn steps(&self) -> usize {
        self.t.len()
    }

    /// A digest of the log's numbers (FNV-1a over their bits): equal for
    /// the same log, whatever its file is called.
    pub fn fingerprint(&self) -> String {
        let numbers = self.t.iter().chain(&self.speed).chain(&self.rotation);
        let h = nvector_core::rng::fnv1a(numbers.flat_map(|x| x.to_bits().to_le_bytes()));
        format!("{}:{h:016x}", self.model.name())
    }

    /// The steps `[a, b)` of the run as a run of their own (b - a >= 2):
    /// the log's rows, the detections at steps a..=b renumbered, the truth
    /// at poses a..=b (a held-out part of a calibration run:
    /// [`crate::calibrate::holdout`]).
    pub fn steps_between(&self, a: usize, b: usize) -> Run {
        let b = b.min(self.steps());
        let truth = self.truth.as_ref().map(|t| Truth {
            positions: t.positions[a..=b].to_vec(),
            headings: t.headings[a..=b].to_vec(),
            has_heading: t.has_heading,
        });
        Run {
            model: self.model,
            t: self.t[a..b].to_vec(),
            dt: self.dt,
            speed: self.speed[a..b].to_vec(),
            rotation: self.rotation[a..b].to_vec(),
            detections: self
                .detections
                .iter()
                .filter(|d| (a..=b).contains(&d.step))
                .map(|d| Detection {
                    step: d.step - a,
                    ..d.clone()
                })
                .collect(),
            truth,
            landmarks: self.landmarks.clone(),
            paths: self.paths.clone(),
        }
    }

    /// The index of a landmark id in the sorted landmarks.
    pub fn landmark_index(&self, id: u64) -> Option<usize> {
        self.landmarks
            .as_ref()
            .and_then(|l| l.binary_search_by_key(&id, |x| x.0).ok())
    }
}

/// The files of a run.
pub struct Files<'a> {
    /// The log: `t` and the model's channels.
    pub log: &'a Path,
    /// The detections: `t,range[,bearing][,scan][,landmark]`.
    pub detections: &'a Path,
    /// The truth: `t,x,y[,heading]`, empty cells in its gaps.
    pub truth: Option<&'a Path>,
    /// The landmarks: `id,x,y`.
    pub landmarks: Option<&'a Path>,
}

/// Reads a run from its files.
pub fn read_run(model: Model, files: &Files) -> Result<Run, ImportError> {
    let tables = Tables {
        log: read_cells(files.log)?,
        detections: read_cells(files.detections)?,
        truth: files.truth.map(read_cells).transpose()?,
        landmarks: files.landmarks.map(read_cells).transpose()?,
    };
    run_of_tables(model, &tables)
}

/// A run from the calibration's four files held in memory (a data set
/// converted by its importer: [`super::convert::Csvs`]), each named in
/// errors as `dir/log.csv`, ... .
pub fn run_of_csvs(
    model: Model,
    csvs: &super::convert::Csvs,
    dir: &Path,
) -> Result<Run, ImportError> {
    let table = |name: &str, text: &str| cells_of_text(text, &dir.join(name));
    let tables = Tables {
        log: table("log.csv", &csvs.log)?,
        detections: table("detections.csv", &csvs.detections)?,
        truth: Some(table("truth.csv", &csvs.truth)?),
        landmarks: Some(table("landmarks.csv", &csvs.landmarks)?),
    };
    run_of_tables(model, &tables)
}

/// The four files of a run, read.
struct Tables {
    log: Table,
    detections: Table,
    truth: Option<Table>,
    landmarks: Option<Table>,
}

fn run_of_tables(model: Model, tables: &Tables) -> Result<Run, ImportError> {
    let (t, speed, rotation) = read_log(model, &tables.log)?;
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let grid = Grid { t: &t, dt };
    let detections = read_detections(&tables.detections, &grid)?;
    let truth = tables
        .truth
        .as_ref()
        .map(|p| read_truth(p, &grid, model))
        .transpose()?;
    let landmarks = tables.landmarks.as_ref().map(read_landmarks).transpose()?;
    Ok(Run {
        model,
        t,
        dt,
        speed,
        rotation,
        detections,
        truth,
        landmarks,
        paths: Paths {
            log: tables.log.path.clone(),
            detections: tables.detections.path.clone(),
        },
    })
}

type Log = (Vec<f64>, Vec<f64>, Vec<f64>);

fn read_log(model: Model, log: &Table) -> Result<Log, ImportError> {
    let path = &log.path;
    let cols = [
        log.column("t")?,
        log.column("speed")?,
        log.column(model.rotation())?,
    ];
    if log.rows.len() < 2 {
        return Err(ImportError::file(path, "at least 2 rows are needed"));
    }
    let mut out: [Vec<f64>; 3] = Default::default();
    for r in 0..log.rows.len() {
        for (v, &c) in out.iter_mut().zip(&cols) {
            v.push(log.number(r, c)?);
        }
    }
    for (k, w) in out[0].windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(ImportError::line(
                path,
                log.rows[k + 1].0,
                format!("times must increase ({} after {})", w[1], w[0]),
            ));
        }
    }
    let [t, speed, rotation] = out;
    Ok((t, speed, rotation))
}

/// The step times of a log.
struct Grid<'a> {
    t: &'a [f64],
    dt: f64,
}

impl Grid<'_> {
    /// The step of time `x`: the nearest of `t(0..N)` and `t(N-1) + dt`,
    /// when within dt / 2.
    fn step(&self, x: f64) -> Option<usize> {
        let n = self.t.len();
        let time = |k: usize| {
            if k < n {
                self.t[k]
            } else {
                self.t[n - 1] + self.dt
            }
        };
        let i = self.t.partition_point(|&y| y < x);
        let best = [i.saturating_sub(1), i.min(n)]
            .into_iter()
            .min_by(|&a, &b| (time(a) - x).abs().total_cmp(&(time(b) - x).abs()))?;
        ((time(best) - x).abs() <= self.dt / 2.0).then_some(best)
    }
}

fn read_detections(det: &Table, grid: &Grid) -> Result<Vec<Detection>, ImportError> {
    let path = &det.path;
    let (tc, rc) = (det.column("t")?, det.column("range")?);
    let (bc, sc, lc) = (
        det.optional("bearing"),
        det.optional("scan"),
        det.optional("landmark"),
    );
    let mut out = Vec::with_capacity(det.rows.len());
    for r in 0..det.rows.len() {
        let line = det.rows[r].0;
        let t = det.number(r, tc)?;
        let step = grid.step(t).ok_or_else(|| {
            ImportError::line(
                path,
                line,
                format!("time {t} is not within dt/2 of a step of the log"),
            )
        })?;
        let range = det.number(r, rc)?;
        if range < 0.0 {
            return Err(ImportError::line(
                path,
                line,
                format!("range {range} is negative"),
            ));
        }
        let cell = |c: Option<usize>| c.and_then(|c| det.rows[r].1[c]);
        out.push(Detection {
            step,
            range,
            bearing: cell(bc),
            scan: cell(sc)
                .map(|x| integer_cell(x, path, line, "scan"))
                .transpose()?,
            landmark: cell(lc)
                .map(|x| integer_cell(x, path, line, "landmark"))
                .transpose()?,
            line,
        });
    }
    Ok(out)
}

fn read_truth(tab: &Table, grid: &Grid, model: Model) -> Result<Truth, ImportError> {
    let path = &tab.path;
    let [tc, xc, yc] = [tab.column("t")?, tab.column("x")?, tab.column("y")?];
    let hc = tab.optional("heading");
    let rows = grid.t.len() + 1;
    let mut truth = Truth {
        positions: vec![None; rows],
        headings: vec![None; rows],
        has_heading: hc.is_some(),
    };
    for r in 0..tab.rows.len() {
        let (line, cells) = &tab.rows[r];
        let t = tab.number(r, tc)?;
        let Some(step) = grid.step(t) else {
            return Err(ImportError::line(
                path,
                *line,
                format!("time {t} is not within dt/2 of a step of the log"),
            ));
        };
        if let (Some(x), Some(y)) = (cells[xc], cells[yc]) {
            truth.positions[step] = Some([x, y]);
        }
        truth.headings[step] = hc.and_then(|c| cells[c]);
    }
    if model == Model::Odometry2d && truth.has_heading {
        unwrap_headings(&mut truth.headings);
    }
    Ok(truth)
}

/// Makes consecutive known headings differ by less than pi (a real
/// heading, not taken modulo 2 pi), across gaps too.
fn unwrap_headings(h: &mut [Option<f64>]) {
    let tau = 2.0 * std::f64::consts::PI;
    let mut last: Option<f64> = None;
    for x in h.iter_mut() {
        if let (Some(v), Some(p)) = (x.as_mut(), last) {
            *v += tau * ((p - *v) / tau).round();
        }
        if x.is_some() {
            last = *x;
        }
    }
}

fn read_landmarks(tab: &Table) -> Result<Vec<(u64, [f64; 2])>, ImportError> {
    let path = &tab.path;
    let [ic, xc, yc] = [tab.column("id")?, tab.column("x")?, tab.column("y")?];
    let mut out = Vec::with_capacity(tab.rows.len());
    for r in 0..tab.rows.len() {
        let line = tab.rows[r].0;
        let id = integer_cell(tab.number(r, ic)?, path, line, "id")?;
        out.push((id, [tab.number(r, xc)?, tab.number(r, yc)?]));
    }
    out.sort_by_key(|l| l.0);
    if let Some(w) = out.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(ImportError::file(
            path,
            format!("landmark {} appears twice", w[0].0),
        ));
    }
    if out.is_empty() {
        return Err(ImportError::file(path, "no landmark"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    /// An irregular log: times matched to the nearest step time (not to
    /// round((t - t0) / dt), which would drift), the truth's empty cells
    /// read as gaps, the end pose at t(N-1) + dt, the headings unwrapped.
    #[test]
    fn times_match_the_nearest_step_and_empty_cells_are_gaps() {
        let dir = std::env::temp_dir().join(format!("nvector-data-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let log = write(
            &dir,
            "log.csv",
            "t,speed,turn_rate\n0,1,0\n0.1,1,0\n0.25,1,0\n0.35,1,0\n",
        );
        let det = write(
            &dir,
            "det.csv",
            "t,range,bearing,scan,landmark\n0.24,2,0.1,3,7\n0.47,1,,,\n",
        );
        let truth = write(
            &dir,
            "truth.csv",
            "t,x,y,heading\n0,0,0,3.1\n0.1,,,\n0.25,1,1,-3.1\n0.47,2,2,\n",
        );
        let lm = write(&dir, "lm.csv", "id,x,y\n7,1,1\n2,0,0\n");
        let f = Files {
            log: &log,
            detections: &det,
            truth: Some(&truth),
            landmarks: Some(&lm),
        };
        let run = read_run(Model::Odometry2d, &f).unwrap();
        assert_eq!(run.steps(), 4);
        assert!((run.dt - 0.35 / 3.0).abs() < 1e-12);
        assert_eq!(run.detections[0].step, 2);
        assert_eq!(run.detections[0].landmark, Some(7));
        // 0.47 is the end pose: t(3) + dt = 0.4667.
        assert_eq!(run.detections[1].step, 4);
        assert_eq!(run.detections[1].bearing, None);
        let t = run.truth.as_ref().unwrap();
        assert_eq!(t.positions[1], None);
        assert_eq!(t.positions[4], Some([2.0, 2.0]));
        // -3.1 follows 3.1 across the gap as 2 pi - 3.1.
        assert!((t.headings[2].unwrap() - (2.0 * std::f64::consts::PI - 3.1)).abs() < 1e-12);
        assert_eq!(run.landmark_index(7), Some(1));
        // A time off the grid is named.
        let det2 = write(&dir, "det2.csv", "t,range,landmark\n0.9,2,7\n");
        let f2 = Files {
            detections: &det2,
            ..f
        };
        let e = read_run(Model::Odometry2d, &f2).unwrap_err().to_string();
        assert!(e.contains("det2.csv:2: time 0.9 is not within dt/2"), "{e}");
        let bad = write(&dir, "bad.csv", "t,speed,turn_rate\n0,1,0\n0.1,1\n");
        let e = read_run(Model::Odometry2d, &Files { log: &bad, ..f })
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.csv:3: expected 3 columns"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
