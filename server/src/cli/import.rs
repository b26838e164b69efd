//! `nvector import`.

use crate::CliError;

/// Arguments of `nvector import`.
#[derive(clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> Result<(), CliError> {
    Err(CliError("`nvector import` is not implemented yet".into()))
}
