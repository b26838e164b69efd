//! `nvector-import`: from sensor logs to missions.
//!
//! The data science between a robot's files and an `nvector-mission/1`:
//! reading CSV logs, converting the bundled data sets, fitting sensor
//! models on a run with truth and applying them to runs without it. It
//! reads files but holds no HTTP, no storage and no clock: the CLI and the
//! Python package call it.
//!
//! - [`csv`]: the one CSV reader (file, line and column in every error),
//!   of the data sets, the generic import and the calibration;
//! - [`generic`]: a mission from a log CSV and a detections CSV, the
//!   bounds given by the caller;
//! - [`plaza`], [`woods`]: CMU Plaza 1 and UTIAS Lost in the Woods,
//!   converted to the calibration's CSVs, calibrated on themselves (a
//!   same-run calibration) and the model applied (docs/cmu-plaza1.md,
//!   docs/utias-woods.md);
//! - [`locards`]: LocaRDS multilateration messages as a TDOA problem;
//! - [`calibrate`], [`sensor_model`], [`apply`]: a sensor model fitted on
//!   a run with truth and applied to runs without it
//!   (docs/calibration.md); the data sets convert to its CSVs
//!   ([`plaza::calibration_csvs`], [`woods::calibration_csvs`]);
//! - [`plant_false_ranges`]: core's planting of false ranges
//!   (`nvector_core::slam::plant`) applied to an imported mission.
//!
//! Every importer returns a document core's validation accepts.

pub mod apply;
pub mod calibrate;
pub mod csv;
mod doc;
mod error;
pub mod generic;
pub mod locards;
pub mod plaza;
pub mod sensor_model;
pub mod woods;

pub use error::ImportError;
pub use generic::{import_csv, CsvImport, Imported};

use nvector_core::format::leaf::{IntervalIn, List, ToJson};
use nvector_core::format::mission_doc::DetectionDoc;
use nvector_core::format::to_value;
use nvector_core::slam::mission::Mission;
use serde_json::{json, Value};
use std::path::Path;

/// Most false detections planted in one mission (as many as a simulation
/// may add).
pub const MAX_FALSE_DETECTIONS: usize = nvector_core::slam::simulate::MAX_FALSE_DETECTIONS;

/// `mission` once core's validation accepts it: an invalid one is an error
/// naming the field, never a mission handed on.
pub fn validated(mission: Value) -> Result<Value, ImportError> {
    Mission::from_value(&mission).map_err(ImportError::InvalidMission)?;
    Ok(mission)
}

/// What a data set's same-run calibration is, in `meta.calibration.method`.
pub const SAME_RUN_METHOD: &str = "every bound fitted on this run's own truth by the calibration (docs/calibration.md, \"Same-run calibration\"): the data set converted to the calibration's CSVs, calibrated on itself (`meta.sensor_model`: each bound's method, the flagged steps) and applied to the same run; `nvector calibrate` fits the per-robot bounds that transfer to other runs";

/// The outlier share P of the data-set importers: 0 <= P < 0.5.
fn check_outlier_share(share: f64) -> Result<(), ImportError> {
    if (0.0..0.5).contains(&share) {
        Ok(())
    } else {
        Err(ImportError::setting(
            "outlier_share",
            format!("--outlier-share must be in [0, 0.5), found {share}"),
        ))
    }
}

/// The data sets an importer converts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataSet {
    /// CMU Plaza 1 (`data/cmu-plaza1`): a mission.
    CmuPlaza,
    /// UTIAS Lost in the Woods (`data/utias-lost-in-the-woods`): a mission.
    UtiasWoods,
    /// LocaRDS multilateration (`data/locards-mlat`): a TDOA problem.
    LocardsMlat,
}

impl DataSet {
    /// The data set named as `nvector import`'s flag names it
    /// (`cmu-plaza`, `utias-woods`, `locards-mlat`) or as its directory in
    /// `data/` (`cmu-plaza1`, `utias-lost-in-the-woods`).
    pub fn parse(name: &str) -> Option<DataSet> {
        match name {
            "cmu-plaza" | "cmu-plaza1" => Some(DataSet::CmuPlaza),
            "utias-woods" | "utias-lost-in-the-woods" => Some(DataSet::UtiasWoods),
            "locards-mlat" => Some(DataSet::LocardsMlat),
            _ => None,
        }
    }
}

/// The settings of a data set's import (the flags of `nvector import
/// --cmu-plaza/--utias-woods/--locards-mlat`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DataSetImport {
    /// Plaza, woods: keep the data set's landmark ids as the operator's
    /// matching.
    pub operator: bool,
    /// Plaza, woods: the share of the residuals left outside the bands
    /// (0 <= P < 0.5); `max_outliers` counts the detections outside.
    pub outlier_share: f64,
    /// Plaza, woods: false ranges planted ([`plant_false_ranges`]).
    pub false_detections: usize,
    /// The seed of the planted ranges.
    pub seed: u64,
    /// LocaRDS: the set (the file `set_{set}.csv`).
    pub set: u32,
}

impl Default for DataSetImport {
    fn default() -> Self {
        DataSetImport {
            operator: false,
            outlier_share: 0.0,
            false_detections: 0,
            seed: 1,
            set: 1,
        }
    }
}

/// The data set `which` in `dir` as a mission (a TDOA problem for
/// LocaRDS), validated as core reads it.
pub fn import_dataset(which: DataSet, dir: &Path, o: &DataSetImport) -> Result<Value, ImportError> {
    check_false_detections(o.false_detections)?;
    if which == DataSet::LocardsMlat {
        return locards::locards(dir, o.set);
    }
    check_outlier_share(o.outlier_share)?;
    let mut mission = match which {
        DataSet::CmuPlaza => plaza::cmu_plaza(dir, o.operator, o.outlier_share)?,
        _ => woods::utias_woods(dir, o.operator, o.outlier_share)?,
    };
    plant_false_ranges(&mut mission, o.false_detections, o.seed)?;
    Ok(mission)
}

/// At most [`MAX_FALSE_DETECTIONS`] planted ranges.
pub fn check_false_detections(count: usize) -> Result<(), ImportError> {
    if count > MAX_FALSE_DETECTIONS {
        return Err(ImportError::setting(
            "false_detections",
            format!("--false-detections must be at most {MAX_FALSE_DETECTIONS}"),
        ));
    }
    Ok(())
}

/// Plants `count` false ranges in an imported mission with truth
/// (`nvector_core::slam::plant::plant_false_ranges`: random steps, ranges
/// drawn over the measured span, `truth.matching` null, `max_outliers`
/// raised by `count`, the name suffixed `-false-{count}`), keeping every
/// real detection's JSON as imported and renumbering the indices of
/// `meta.outlier_share.outside`. Nothing changes when `count` is 0.
/// Deterministic for a seed.
pub fn plant_false_ranges(mission: &mut Value, count: usize, seed: u64) -> Result<(), ImportError> {
    check_false_detections(count)?;
    if count == 0 {
        return Ok(());
    }
    let mut typed = Mission::from_value(mission).map_err(ImportError::InvalidMission)?;
    let planted =
        nvector_core::slam::plant::plant_false_ranges(&mut typed, count, seed).map_err(|e| {
            ImportError::setting("false_detections", format!("--false-detections: {e}"))
        })?;
    let real = match mission["detections"].take() {
        Value::Array(a) => a,
        _ => Vec::new(),
    };
    let mut new_index = vec![0usize; real.len()];
    let detections: Vec<Value> = planted
        .origin
        .iter()
        .zip(&typed.detections)
        .enumerate()
        .map(|(new, (origin, d))| match origin {
            Some(i) => {
                new_index[*i] = new;
                real[*i].clone()
            }
            None => to_value(&DetectionDoc {
                step: Some(doc::int(d.step)),
                range: Some(IntervalIn(d.range)),
                ..DetectionDoc::default()
            }),
        })
        .collect();
    let outside = mission
        .get_mut("meta")
        .and_then(|m| m.get_mut("outlier_share"))
        .and_then(|o| o.get_mut("outside"))
        .and_then(Value::as_array_mut);
    for j in outside.into_iter().flatten() {
        let old = j.as_u64().unwrap_or(0) as usize;
        *j = json!(new_index.get(old).copied().unwrap_or(old));
    }
    mission["detections"] = Value::Array(detections);
    if let Some(t) = &typed.truth {
        let matching: Vec<_> = t.matching.iter().map(|i| i.map(doc::int)).collect();
        mission["truth"]["matching"] = List(matching).to_json();
    }
    mission["max_outliers"] = doc::int(typed.max_outliers).to_json();
    mission["name"] = typed.name.to_json();
    Ok(())
}

#[cfg(test)]
mod tests;
