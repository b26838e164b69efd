//! `nvector simulate`: a simulated mission with truth.

use crate::CliError;
use nvector_core::format::leaf::{Finite, Integer};
use nvector_core::slam::simulate::simulate;
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `nvector simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// paper (the paper's section 6 experiment) or auv (Redermor-scale survey).
    #[arg(long)]
    scenario: String,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Number of steps (default: 10000 for paper, 60000 for auv).
    #[arg(long)]
    steps: Option<usize>,
    /// Number of landmarks (paper only; default 4; at most 64).
    #[arg(long)]
    landmarks: Option<usize>,
    /// Scale of the sensor noise bounds (default 1).
    #[arg(long, default_value_t = 1.0)]
    noise: f64,
    /// Also write the true matching as operator `landmark` fields.
    #[arg(long)]
    operator: bool,
    /// Landmark layout (paper only): line (10 m apart along x, the default),
    /// ring (evenly on a circle around the start: the axis projections
    /// interleave) or random (uniform in a square, at least 8 m apart).
    #[arg(long, default_value = "line")]
    layout: String,
    /// Range-only detections (paper only; the paper's P''): no bearing, a
    /// rough `region` per detection instead (a 30 m box holding the landmark).
    #[arg(long)]
    range_only: bool,
    /// Add K false detections (paper only): ranges to no landmark, `null` in
    /// truth.matching, and "max_outliers": K in the mission.
    #[arg(long, default_value_t = 0)]
    false_detections: usize,
    /// Output file (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    // The options go through core's one simulation request type and its
    // checks, with core's limits, as the service, the page and Python do.
    let request = SimulateRequest {
        scenario: Some(a.scenario.into()),
        seed: Some(Integer::Value(a.seed)),
        steps: a.steps.map(|s| Integer::Value(s as u64)),
        landmarks: a.landmarks.map(|n| Integer::Value(n as u64)),
        operator: Some(a.operator),
        noise: Some(Finite(a.noise)),
        layout: Some(a.layout.into()),
        range_only: Some(a.range_only),
        false_detections: Some(Integer::Value(a.false_detections as u64)),
    };
    let options = request
        .options(SimulateLimits::CORE)
        .map_err(|e| CliError(format!("--{}: {}", e.path.replace('_', "-"), e.message)))?;
    let mission = simulate(&options);
    // Written as it is serialized: a 2,000,000-step mission's text is
    // hundreds of megabytes more, on top of its JSON value.
    let write = |w: &mut dyn Write| -> std::io::Result<()> {
        let mut w = std::io::BufWriter::new(w);
        serde_json::to_writer(&mut w, &mission)?;
        w.write_all(b"\n")?;
        w.flush()
    };
    match a.out {
        Some(path) => std::fs::File::create(&path)
            .and_then(|mut f| write(&mut f))
            .map_err(|e| CliError(format!("writing {}: {e}", path.display())))?,
        None => write(&mut std::io::stdout().lock())
            .map_err(|e| CliError(format!("writing the mission: {e}")))?,
    }
    Ok(())
}
