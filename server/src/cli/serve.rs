//! `nvector serve`.

use crate::CliError;

/// Arguments of `nvector serve`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> Result<(), CliError> {
    Err(CliError("`nvector serve` is not implemented yet".into()))
}
