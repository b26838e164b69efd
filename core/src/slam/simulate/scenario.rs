//! What every scenario shares: which scenario, its options and limits,
//! and the writing helpers (the margin over the noise drawn, angles,
//! channels and intervals as JSON, closest approaches).

use crate::format::leaf::{BoxIn, Finite, Integer, IntervalIn};
use crate::format::mission_doc::MissionDoc;
use crate::Interval;

/// Which scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scenario {
    /// The paper's section 6 experiment.
    Paper,
    /// Redermor-scale AUV survey.
    Auv,
    /// An odometry2d robot among identical landmarks, with scans
    /// ([`crate::slam::simulate::odometry_scenario`]).
    Woods,
}

impl Scenario {
    /// Parses `paper` / `auv` / `woods`.
    pub fn parse(s: &str) -> Option<Scenario> {
        match s {
            "paper" => Some(Scenario::Paper),
            "auv" => Some(Scenario::Auv),
            "woods" => Some(Scenario::Woods),
            _ => None,
        }
    }

    /// The name `parse` reads.
    pub fn name(self) -> &'static str {
        match self {
            Scenario::Paper => "paper",
            Scenario::Auv => "auv",
            Scenario::Woods => "woods",
        }
    }
}

/// Where the paper scenario puts its landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// 10 m apart along x, alternating north and south (the paper's
    /// Figure 9; today's default).
    Line,
    /// Evenly on a circle around the start, with jitter: the x and y
    /// projections interleave.
    Ring,
    /// Uniformly in a square around the start, with a minimum separation.
    Random,
}

impl Layout {
    /// Parses `line` / `ring` / `random`.
    pub fn parse(s: &str) -> Option<Layout> {
        match s {
            "line" => Some(Layout::Line),
            "ring" => Some(Layout::Ring),
            "random" => Some(Layout::Random),
            _ => None,
        }
    }

    /// The name `parse` reads.
    pub fn name(self) -> &'static str {
        match self {
            Layout::Line => "line",
            Layout::Ring => "ring",
            Layout::Random => "random",
        }
    }
}

/// Most false detections a simulation adds (every front end refuses more,
/// naming the option; each costs up to 1000 draws).
pub const MAX_FALSE_DETECTIONS: usize = 100_000;

/// Steps of the paper scenario by default.
pub const PAPER_STEPS: usize = 10_000;

/// Steps of the AUV scenario by default.
pub const AUV_STEPS: usize = 60_000;

/// Simulation options.
#[derive(Debug, Clone)]
pub struct SimulateOptions {
    /// Scenario.
    pub scenario: Scenario,
    /// Seed.
    pub seed: u64,
    /// Steps (None: the scenario's default: 10,000 for paper, 60,000 for
    /// auv, 3,000 for woods).
    pub steps: Option<usize>,
    /// Landmarks (None: 4 for paper, 17 for woods; auv always uses the 6
    /// seamarks).
    pub landmarks: Option<usize>,
    /// Write the true matching as operator `landmark` fields.
    pub operator: bool,
    /// Scale of the sensor noise bounds (1 = the scenario's defaults;
    /// paper and auv only).
    pub noise: f64,
    /// Landmark layout (paper only; default `Line`).
    pub layout: Layout,
    /// Range-only detections with a rough landmark region instead of a
    /// bearing (paper only: the paper's P''; default false).
    pub range_only: bool,
    /// Extra detections of no landmark (paper and woods; default 0).
    pub false_detections: usize,
}

impl SimulateOptions {
    /// Defaults for a scenario and seed.
    pub fn new(scenario: Scenario, seed: u64) -> SimulateOptions {
        SimulateOptions {
            scenario,
            seed,
            steps: None,
            landmarks: None,
            operator: false,
            noise: 1.0,
            layout: Layout::Line,
            range_only: false,
            false_detections: 0,
        }
    }
}

/// Margin added to every declared error bound, above the largest noise
/// drawn: covers the f64 rounding of the simulation (relative 1e-16 on
/// values below 1e4), so the truth is inside even though the simulation is
/// computed in floating point.
pub(super) const MARGIN: f64 = 1e-9;

pub(super) fn wrap(a: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    a - two_pi * libm::floor((a + std::f64::consts::PI) / two_pi)
}

/// `[lo, hi]` as a document's interval.
pub(super) fn interval(lo: f64, hi: f64) -> IntervalIn {
    IntervalIn(Interval::new(lo, hi))
}

/// `[[lo, hi], ...]` as a document's box.
pub(super) fn boxed(axes: &[[f64; 2]]) -> BoxIn {
    BoxIn(axes.iter().map(|&[lo, hi]| Interval::new(lo, hi)).collect())
}

/// The head of a simulated mission: its format, name, model, time step and
/// number of steps (the caller fills in the rest).
pub(super) fn mission_head(name: String, model: &str, dt: f64, steps: usize) -> MissionDoc {
    MissionDoc {
        format: Some(crate::slam::mission::FORMAT.into()),
        name: Some(name),
        model: Some(model.into()),
        dt: Some(Finite(dt)),
        steps: Some(Integer::Value(steps as u64)),
        ..MissionDoc::default()
    }
}

/// A count or an index as a document's integer.
pub(super) fn int(n: usize) -> Integer {
    Integer::Value(n as u64)
}

/// Steps where the distance series has a local minimum below `threshold`.
pub(super) fn closest_approaches(dist: &[f64], threshold: f64) -> Vec<usize> {
    (1..dist.len().saturating_sub(1))
        .filter(|&i| dist[i] < threshold && dist[i - 1] > dist[i] && dist[i] <= dist[i + 1])
        .collect()
}
