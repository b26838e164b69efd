//! `nvector bench`: one JSON line per measure.

use crate::CliError;

/// Runs the benchmarks.
pub fn run(quick: bool, only: Option<&str>) -> Result<(), CliError> {
    super::bench_slam::run(quick, only, &mut |line| println!("{line}"));
    Err(CliError("`nvector bench` is not implemented yet".into()))
}
