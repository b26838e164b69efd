//! `nvector run`.

use crate::CliError;

/// Arguments of `nvector run`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> Result<(), CliError> {
    Err(CliError("`nvector run` is not implemented yet".into()))
}
