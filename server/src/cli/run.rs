//! `nvector run`: one SLAM job, locally, with a progress line on a terminal.

use crate::CliError;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagator::{solve, Association, SolveOptions};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Arguments of `nvector run`.
#[derive(clap::Args)]
pub struct Args {
    /// The mission (nvector-mission/1 JSON).
    mission: PathBuf,
    /// none, nvalue, projection, independent or best (default: best when the
    /// mission has landmark_count, none otherwise).
    #[arg(long, value_parser = parse_association)]
    contractor: Option<Association>,
    /// Most propagation rounds.
    #[arg(long, default_value_t = 10_000)]
    max_rounds: u32,
    /// Bounds moving by less than this count as fixed.
    #[arg(long, default_value_t = 1e-9)]
    tolerance: f64,
    /// Output file for the result (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also draw the result (.svg or .png).
    #[arg(long)]
    plot: Option<PathBuf>,
}

fn parse_association(s: &str) -> Result<Association, String> {
    Association::parse(s).ok_or_else(|| {
        format!("unknown contractor '{s}' (expected none, nvalue, projection, independent or best)")
    })
}

/// Reads and validates a mission file; errors name the file and JSON path.
pub fn read_mission(path: &PathBuf) -> Result<(Mission, serde_json::Value), CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| CliError(format!("{}: invalid JSON: {e}", path.display())))?;
    let mission =
        Mission::from_value(&value).map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    Ok((mission, value))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let (mission, mission_json) = read_mission(&a.mission)?;
    if !(a.tolerance.is_finite() && a.tolerance >= 0.0) {
        return Err(CliError(format!(
            "--tolerance must be a finite number >= 0, found {}",
            a.tolerance
        )));
    }
    let association = a.contractor.unwrap_or(if mission.landmark_count.is_some() {
        Association::NVector(nvector_core::nvector::Mode::Best)
    } else {
        Association::None
    });
    let options = SolveOptions {
        association,
        max_rounds: a.max_rounds,
        tolerance: a.tolerance,
    };
    // A progress bar on a terminal, nothing otherwise.
    let bar = if std::io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:30} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let start = Instant::now();
    let mut progress = |p: &nvector_core::slam::propagator::Progress| {
        bar.set_position((p.fraction * 1000.0) as u64);
        bar.set_message(format!(
            "round {}, max trajectory diameter {:.4}",
            p.round, p.max_trajectory_diameter
        ));
    };
    let mut result = solve(&mission, &options, &mut progress, &AtomicBool::new(false));
    bar.finish_and_clear();
    result["metrics"]["elapsed_ms"] = serde_json::json!(start.elapsed().as_secs_f64() * 1e3);
    if let Some(path) = &a.plot {
        super::plot::write_plot(path, &result, &mission_json)?;
    }
    let text = serde_json::to_string(&result)?;
    match a.out {
        Some(path) => std::fs::write(&path, text + "\n")
            .map_err(|e| CliError(format!("writing {}: {e}", path.display())))?,
        None => println!("{text}"),
    }
    Ok(())
}
