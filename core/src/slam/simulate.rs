//! Simulated missions (the paper's experiment, an AUV survey). OWNER: helper B.

use serde_json::Value;

/// Which scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scenario {
    /// The paper's section 6 experiment.
    Paper,
    /// Redermor-scale AUV survey.
    Auv,
}

/// Simulation options.
#[derive(Debug, Clone)]
pub struct SimulateOptions {
    /// Scenario.
    pub scenario: Scenario,
    /// Seed.
    pub seed: u64,
    /// Steps (None: the scenario's default).
    pub steps: Option<usize>,
    /// Landmarks (None: default).
    pub landmarks: Option<usize>,
    /// Write the true matching as operator `landmark` fields.
    pub operator: bool,
}

/// A simulated mission with truth, as `nvector-mission/1` JSON.
pub fn simulate(options: &SimulateOptions) -> Value {
    let _ = options;
    Value::Null
}
