//! `nvector contract`: one atmost_nvector contraction, stdin -> stdout.

use crate::CliError;

/// Runs the subcommand.
pub fn run(_contractor: Option<&str>) -> Result<(), CliError> {
    Err(CliError("`nvector contract` is not implemented yet".into()))
}
