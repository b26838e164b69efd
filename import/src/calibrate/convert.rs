//! The bundled data sets as the calibration's CSVs (`log.csv`,
//! `detections.csv`, `truth.csv`, `landmarks.csv`), over a time span
//! `[from, to)`: calibrate on one span, solve another. The data sets'
//! importers write them ([`crate::woods::calibration_csvs`],
//! [`crate::plaza::calibration_csvs`]) from the same readers their
//! missions come from.

use crate::ImportError;
use std::path::Path;

/// The time span of a conversion: rows with `from <= t < to`.
#[derive(Clone, Copy, Debug)]
pub struct Span {
    /// First time kept.
    pub from: f64,
    /// First time not kept.
    pub to: f64,
}

impl Span {
    /// Every time.
    pub const ALL: Span = Span {
        from: f64::NEG_INFINITY,
        to: f64::INFINITY,
    };
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
    pub fn write(&self, dir: &Path) -> Result<(), ImportError> {
        std::fs::create_dir_all(dir)
            .map_err(|e| ImportError::file(dir, format!("creating the directory: {e}")))?;
        for (name, text) in [
            ("log.csv", &self.log),
            ("detections.csv", &self.detections),
            ("truth.csv", &self.truth),
            ("landmarks.csv", &self.landmarks),
        ] {
            let p = dir.join(name);
            std::fs::write(&p, text).map_err(|e| ImportError::file(&p, format!("writing: {e}")))?;
        }
        Ok(())
    }
}

/// The rows `[a, b)` of times `t` inside the span, or an error naming the
/// file the times come from.
pub fn rows(t: &[f64], span: Span, file: &Path) -> Result<(usize, usize), ImportError> {
    let a = t.partition_point(|&x| x < span.from);
    let b = t.partition_point(|&x| x < span.to);
    if b < a + 2 {
        return Err(ImportError::file(
            file,
            format!(
                "fewer than 2 rows in [{}, {}) (the log spans {} to {})",
                span.from,
                span.to,
                t.first().copied().unwrap_or(f64::NAN),
                t.last().copied().unwrap_or(f64::NAN)
            ),
        ));
    }
    Ok((a, b))
}

/// A CSV cell: empty for `None`.
pub fn cell(x: Option<f64>) -> String {
    x.map_or(String::new(), |v| v.to_string())
}
