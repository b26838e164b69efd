//! `nvector bench`: one JSON line per measure.

use crate::CliError;

/// Runs the benchmarks.
pub fn run(_quick: bool, _only: Option<&str>) -> Result<(), CliError> {
    Err(CliError("`nvector bench` is not implemented yet".into()))
}
