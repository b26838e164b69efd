//! `nvector simulate`: a simulated mission with truth.

use crate::CliError;
use nvector_core::format::leaf::{Finite, Integer};
use nvector_core::slam::simulate::{simulate, Layout, Scenario};
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `nvector simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// paper (the paper's section 6 experiment), auv (Redermor-scale
    /// survey), woods (an odometry2d robot among identical landmarks, with
    /// scans) or radar (TDOA: static emitters, fixed receivers, pulse
    /// trains; an `nvector-tdoa/1` problem).
    #[arg(long, value_parser = parse_scenario)]
    scenario: Which,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Number of steps (at least 2; default: 10000 for paper, 60000 for
    /// auv, 3000 for woods).
    #[arg(long)]
    steps: Option<usize>,
    /// Number of landmarks (paper and woods; default 4 for paper, 17 for
    /// woods; at least 1, at most 64).
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
    #[arg(long, value_parser = parse_layout, default_value = "line")]
    layout: Layout,
    /// Range-only detections (paper only; the paper's P''): no bearing, a
    /// rough `region` per detection instead (a 30 m box holding the landmark).
    #[arg(long)]
    range_only: bool,
    /// Add K false detections (paper and woods): `null` in truth.matching,
    /// and "max_outliers": K in the mission. paper: ranges to no landmark;
    /// woods: range-and-bearing detections in the robot's scans of phantom
    /// points at least landmark_min_separation + 0.5 m from every landmark
    /// (seen once, two or three times from nearby scans, or with
    /// --operator under a real landmark's label).
    #[arg(long, default_value_t = 0)]
    false_detections: usize,
    /// Output file (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// radar: emitters (default 4).
    #[arg(long)]
    emitters: Option<usize>,
    /// radar: receivers (default 5).
    #[arg(long)]
    receivers: Option<usize>,
    /// radar: pulses (default 200).
    #[arg(long)]
    pulses: Option<usize>,
    /// radar: share of arrivals missing (default 0.1).
    #[arg(long)]
    missing: Option<f64>,
    /// radar: false arrivals added, and "max_outliers" set to their count.
    #[arg(long, default_value_t = 0)]
    false_arrivals: usize,
}

/// A scenario of core's `slam::simulate` (paper, auv, woods), or the
/// radar scenario of `tdoa::simulate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Which {
    Slam(Scenario),
    Radar,
}

fn parse_scenario(s: &str) -> Result<Which, String> {
    match s {
        "radar" => Ok(Which::Radar),
        _ => Scenario::parse(s)
            .map(Which::Slam)
            .ok_or_else(|| format!("unknown scenario '{s}' (expected paper, auv, woods or radar)")),
    }
}

fn parse_layout(s: &str) -> Result<Layout, String> {
    Layout::parse(s).ok_or_else(|| format!("unknown layout '{s}' (expected line, ring or random)"))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    // A flag of the other kind of scenario was ignored without a word.
    let radar_flags = [
        ("--emitters", a.emitters.is_some()),
        ("--receivers", a.receivers.is_some()),
        ("--pulses", a.pulses.is_some()),
        ("--missing", a.missing.is_some()),
        ("--false-arrivals", a.false_arrivals > 0),
    ];
    let slam_flags = [
        ("--steps", a.steps.is_some()),
        ("--landmarks", a.landmarks.is_some()),
        ("--noise", a.noise != 1.0),
        ("--layout", a.layout != Layout::Line),
        ("--range-only", a.range_only),
        ("--false-detections", a.false_detections > 0),
    ];
    let (foreign, why) = match a.scenario {
        Which::Slam(_) => (&radar_flags[..], "applies to the radar scenario only"),
        Which::Radar => (&slam_flags[..], "does not apply to the radar scenario"),
    };
    if let Some((flag, _)) = foreign.iter().find(|(_, set)| *set) {
        return Err(CliError(format!("{flag} {why}")));
    }
    let scenario = match a.scenario {
        Which::Slam(scenario) => scenario,
        Which::Radar => return radar(a),
    };
    // The options go through core's one simulation request type and its
    // checks, with core's limits, as the service, the page and Python do.
    let request = SimulateRequest {
        scenario: Some(scenario.name().into()),
        seed: Some(Integer::Value(a.seed)),
        steps: a.steps.map(|s| Integer::Value(s as u64)),
        landmarks: a.landmarks.map(|n| Integer::Value(n as u64)),
        operator: Some(a.operator),
        noise: Some(Finite(a.noise)),
        layout: Some(a.layout.name().into()),
        range_only: Some(a.range_only),
        false_detections: Some(Integer::Value(a.false_detections as u64)),
    };
    let options = request
        .options(SimulateLimits::CORE)
        .map_err(|e| CliError(format!("--{}: {}", e.path.replace('_', "-"), e.message)))?;
    let mission = simulate(&options);
    write_mission(&mission, a.out)
}

/// The radar scenario (core's `tdoa::simulate`).
fn radar(a: Args) -> Result<(), CliError> {
    let d = nvector_core::tdoa::simulate::RadarOptions::default();
    let o = nvector_core::tdoa::simulate::RadarOptions {
        seed: a.seed,
        emitters: a.emitters.unwrap_or(d.emitters),
        receivers: a.receivers.unwrap_or(d.receivers),
        pulses: a.pulses.unwrap_or(d.pulses),
        missing: a.missing.unwrap_or(d.missing),
        false_arrivals: a.false_arrivals,
        operator: a.operator,
    };
    write_mission(&crate::cli::tdoa::simulate(&o)?, a.out)
}

/// Writes the mission to `out` (standard output when `None`).
fn write_mission(mission: &serde_json::Value, out: Option<PathBuf>) -> Result<(), CliError> {
    // Written as it is serialized: a 2,000,000-step mission's text is
    // hundreds of megabytes more, on top of its JSON value.
    let write = |w: &mut dyn Write| -> std::io::Result<()> {
        let mut w = std::io::BufWriter::new(w);
        serde_json::to_writer(&mut w, &mission)?;
        w.write_all(b"\n")?;
        w.flush()
    };
    match out {
        Some(path) => std::fs::File::create(&path)
            .and_then(|mut f| write(&mut f))
            .map_err(|e| CliError(format!("writing {}: {e}", path.display())))?,
        None => write(&mut std::io::stdout().lock())
            .map_err(|e| CliError(format!("writing the mission: {e}")))?,
    }
    Ok(())
}
