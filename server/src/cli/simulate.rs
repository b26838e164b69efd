//! `nvector simulate`.

use crate::CliError;

/// Arguments of `nvector simulate`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> Result<(), CliError> {
    Err(CliError("`nvector simulate` is not implemented yet".into()))
}
