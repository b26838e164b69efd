//! `nvector worker` (hidden): a worker process of `nvector serve`, started
//! by the service with the job memory limit, never by hand. It runs the
//! jobs it reads on its standard input (`service::job_runner`).

use crate::service::job_runner;
use crate::CliError;

/// Arguments of `nvector worker`.
#[derive(clap::Args)]
pub struct Args {
    /// Memory limit of this process (bytes; RLIMIT_AS).
    #[arg(long)]
    memory_limit: Option<u64>,
}

/// Runs the worker until its input ends.
pub fn run(a: Args) -> Result<(), CliError> {
    job_runner::run(a.memory_limit).map_err(CliError)
}
