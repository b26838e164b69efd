//! `nvector plot`.

use crate::CliError;

/// Arguments of `nvector plot`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> Result<(), CliError> {
    Err(CliError("`nvector plot` is not implemented yet".into()))
}
