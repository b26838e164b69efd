//! `nvector simulate`: a simulated mission with truth.

use crate::CliError;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use std::path::PathBuf;

/// Arguments of `nvector simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// paper (the paper's section 6 experiment) or auv (Redermor-scale survey).
    #[arg(long, value_parser = parse_scenario)]
    scenario: Scenario,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Number of steps (default: 10000 for paper, 60000 for auv).
    #[arg(long)]
    steps: Option<usize>,
    /// Number of landmarks (paper only; default 4).
    #[arg(long)]
    landmarks: Option<usize>,
    /// Scale of the sensor noise bounds (default 1).
    #[arg(long, default_value_t = 1.0)]
    noise: f64,
    /// Also write the true matching as operator `landmark` fields.
    #[arg(long)]
    operator: bool,
    /// Output file (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
}

fn parse_scenario(s: &str) -> Result<Scenario, String> {
    Scenario::parse(s).ok_or_else(|| format!("unknown scenario '{s}' (expected paper or auv)"))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    if !(a.noise.is_finite() && a.noise >= 0.0) {
        return Err(CliError(format!(
            "--noise must be a finite number >= 0, found {}",
            a.noise
        )));
    }
    if a.steps == Some(0)
        || a.steps
            .is_some_and(|s| s > nvector_core::slam::mission::MAX_STEPS)
    {
        return Err(CliError("--steps must be between 1 and 2000000".into()));
    }
    let options = SimulateOptions {
        scenario: a.scenario,
        seed: a.seed,
        steps: a.steps,
        landmarks: a.landmarks,
        operator: a.operator,
        noise: a.noise,
        ..SimulateOptions::new(a.scenario, a.seed)
    };
    let mission = simulate(&options);
    let text = serde_json::to_string(&mission)?;
    match a.out {
        Some(path) => std::fs::write(&path, text + "\n")
            .map_err(|e| CliError(format!("writing {}: {e}", path.display())))?,
        None => println!("{text}"),
    }
    Ok(())
}
