//! The `nvector` command-line tool and HTTP service (docs/formats.md,
//! "Command-line contract"). Exit status: 0 success, 1 bad input, 2 usage.

/// `eprintln!` that does not panic when standard error is closed (`2>&1 |
/// true`: the message is lost, the exit status stays the command's own,
/// not a panic's 101).
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($t)*);
    }};
}

mod cli;
mod render;
mod service;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Guaranteed interval SLAM with the nvector global constraint.
#[derive(Parser)]
#[command(name = "nvector", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The HTTP service and the web UI.
    Serve(cli::serve::Args),
    /// One SLAM job, locally.
    Run(cli::run::Args),
    /// One atmost_nvector contraction: request JSON on stdin, response on stdout.
    Contract {
        /// nvalue, projection, independent, exact, shapes or best (overrides the request).
        #[arg(long, value_parser = cli::contract::parse_mode)]
        contractor: Option<nvector_core::nvector::Contractor>,
        /// Most search nodes of the exact contractor (default 16000000);
        /// out of them, exit 1 naming the limit.
        #[arg(long)]
        node_budget: Option<u64>,
    },
    /// A simulated mission with truth.
    Simulate(cli::simulate::Args),
    /// TDOA passive location: one nvector-tdoa/1 problem, locally.
    Tdoa(cli::tdoa::Args),
    /// A mission from sensor logs (CSV).
    Import(cli::import::Args),
    /// A sensor model fitted on a run with truth (docs/calibration.md).
    Calibrate(cli::calibrate::Args),
    /// A figure like the paper's Figure 9.
    Plot(cli::plot::Args),
    /// Every constraint of a mission that its truth breaks, and by how much
    /// (exit 1 when one does).
    Check(cli::check::Args),
    /// A worker process of `nvector serve` (started by the service, not by
    /// hand): runs the jobs it reads on standard input.
    #[command(hide = true)]
    Worker(cli::worker::Args),
    /// The performance table of BENCHMARKS.md, as JSON lines.
    Bench {
        /// Smaller sizes, for a smoke test (names end in `_quick`).
        #[arg(long)]
        quick: bool,
        /// Only the measures whose name contains this.
        #[arg(long)]
        only: Option<String>,
        /// Threads of the real-data `best` lines (default: the machine's
        /// available parallelism).
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
        threads: Option<u32>,
        /// Instead of the table: the load run against a real `nvector
        /// serve` started on loopback (one JSON line).
        #[arg(long)]
        service: bool,
        /// Load run: clients at once.
        #[arg(long, default_value_t = 200, requires = "service")]
        clients: usize,
        /// Load run: steps of each client's simulated mission.
        #[arg(long, default_value_t = 1000, requires = "service")]
        steps: usize,
        /// Load run: storage URL (default: a fresh SQLite file).
        #[arg(long, requires = "service")]
        database: Option<String>,
        /// Load run: worker threads of the service.
        #[arg(long, requires = "service")]
        workers: Option<usize>,
    },
}

/// A CLI failure: bad input (exit 1) with a message naming what is wrong.
pub struct CliError(pub String);

impl<E: std::fmt::Display> From<E> for CliError {
    fn from(e: E) -> Self {
        CliError(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Serve(a) => cli::serve::run(a),
        Command::Run(a) => cli::run::run(a),
        Command::Contract {
            contractor,
            node_budget,
        } => cli::contract::run(contractor, node_budget),
        Command::Simulate(a) => cli::simulate::run(a),
        Command::Tdoa(a) => cli::tdoa::run(a),
        Command::Import(a) => cli::import::run(a),
        Command::Calibrate(a) => cli::calibrate::run(a),
        Command::Plot(a) => cli::plot::run(a),
        Command::Check(a) => cli::check::run(a),
        Command::Worker(a) => cli::worker::run(a),
        Command::Bench {
            service: true,
            clients,
            steps,
            database,
            workers,
            ..
        } => cli::bench_service::run(&cli::bench_service::Options {
            clients,
            steps,
            database,
            workers,
        })
        .and_then(|v| {
            use std::io::Write as _;
            writeln!(std::io::stdout(), "{v}")
                .map_err(|e| CliError(format!("writing standard output: {e}")))
        }),
        Command::Bench {
            quick,
            only,
            threads,
            ..
        } => cli::bench::run(
            quick,
            only.as_deref(),
            threads.map_or_else(cli::machine_threads, |t| t as usize),
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError(msg)) => {
            say!("nvector: {msg}");
            ExitCode::from(1)
        }
    }
}
