//! The CMU Plaza 1 range-only data set (Djugash and Singh, via GTSAM's
//! examples; `data/cmu-plaza1`) as a `unicycle2d` mission with its truth.
//! docs/cmu-plaza1.md derives every bound from the data; `meta` records
//! the figures.

use crate::calibrate::convert::{self, Csvs, Span};
use crate::csv::read_table;
use crate::ImportError;
use serde_json::{json, Value};
use std::path::Path;

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

fn cmu_ranges(td: &[Vec<f64>], tl: &[Vec<f64>], gt: &[Vec<f64>]) -> Result<CmuRanges, ImportError> {
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
        let step = nearest_pose(&times, t);
        let (Ok(li), Some([bx, by])) = (ids.binary_search(&id), beacon(id)) else {
            return Err(ImportError::file(
                "Plaza1_TD.txt",
                format!("beacon {id} is not in Plaza1_TL.csv"),
            ));
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

/// The CMU Plaza 1 dataset as a mission (beacon ids hidden unless
/// `operator`), with the ground truth. `outlier_share` P: the range band
/// holds the central (1 - P) share of the residuals, and `max_outliers` is
/// the count left outside (0: every range inside, no `max_outliers`).
pub fn cmu_plaza(dir: &Path, operator: bool, outlier_share: f64) -> Result<Value, ImportError> {
    crate::check_outlier_share(outlier_share)?;
    let PlazaFiles { dr, gt, td, tl } = plaza_files(dir)?;
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
    crate::validated(mission)
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
            "calibration": {
                "source": "CMU Plaza 1, this run",
                "same_run": true,
                "method": "oracle: every bound fitted on this run's own truth (docs/cmu-plaza1.md): the anomalous steps found by the truth get their own motion error, the range band spans every residual; the heading error is stated (0.02 rad), the truth's heading being the integrated odometry; `nvector calibrate` fits the per-robot bounds that transfer to other runs (docs/calibration.md)",
            },
        },
        "truth": {"positions": positions},
    })
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
    let heading = cmu_inputs(&dr, &gt).heading;
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
