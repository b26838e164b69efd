//! `nvector-import`: from sensor logs to missions.
//!
//! The data science between a robot's files and an `nvector-mission/1`:
//! reading CSV logs, converting the bundled data sets, fitting sensor
//! models on a run with truth and applying them to runs without it. It
//! reads files but holds no HTTP, no storage and no clock: the CLI and the
//! Python package call it.

pub mod apply;
pub mod calibrate;
pub mod sensor_model;

/// An error of the import crate: a message naming what is wrong and where
/// (file, line, column, flag).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error(pub String);

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}
