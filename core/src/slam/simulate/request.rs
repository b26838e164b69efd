//! `SimulateRequest`, the one simulation request of every front end
//! (paper, auv, woods), validated into [`SimulateOptions`] under
//! [`SimulateLimits`], each error naming the field.

use super::odometry_scenario::WOODS_STEPS;
use super::scenario::{
    Layout, Scenario, SimulateOptions, AUV_STEPS, MAX_FALSE_DETECTIONS, PAPER_STEPS,
};
use crate::error::InputError;
use crate::format::leaf::{Finite, Integer};
use crate::slam::mission::{MAX_LANDMARKS, MAX_STEPS};
use serde::Deserialize;
use serde_json::Value;

/// The largest values accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimulateLimits {
    /// Most steps.
    pub max_steps: u64,
    /// Most false detections.
    pub max_false_detections: u64,
}

impl SimulateLimits {
    /// Core's limits (the CLI, the page, Python).
    pub const CORE: SimulateLimits = SimulateLimits {
        max_steps: MAX_STEPS as u64,
        max_false_detections: MAX_FALSE_DETECTIONS as u64,
    };
}

/// A simulation request: every field optional but `scenario`; `null` is
/// absence. Unknown fields are refused, naming them.
#[derive(Debug, Default, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulateRequest {
    /// `"paper"`, `"auv"` or `"woods"` (any JSON, checked by the
    /// validation).
    pub scenario: Option<Value>,
    /// Seed (default 1).
    pub seed: Option<Integer>,
    /// Steps (default: the scenario's; at least 2, at most the limit).
    pub steps: Option<Integer>,
    /// Landmarks (paper; default 4, at most 64; 0 reads as 1).
    pub landmarks: Option<Integer>,
    /// Write the true matching as operator ids (default false).
    pub operator: Option<bool>,
    /// Scale of the noise bounds, in [0, 100] (default 1).
    pub noise: Option<Finite>,
    /// `"line"`, `"ring"` or `"random"` (paper; default line).
    pub layout: Option<Value>,
    /// Range-only detections (paper; default false).
    pub range_only: Option<bool>,
    /// Extra false detections (paper and woods; default 0).
    pub false_detections: Option<Integer>,
}

fn bad(path: &str, message: impl Into<String>) -> InputError {
    InputError::new(path, message)
}

impl SimulateRequest {
    /// The validated options under `limits`; errors name the field.
    pub fn options(&self, limits: SimulateLimits) -> Result<SimulateOptions, InputError> {
        let scenario = match &self.scenario {
            None | Some(Value::Null) => Some(Scenario::Paper),
            Some(v) => v.as_str().and_then(Scenario::parse),
        }
        .ok_or_else(|| {
            bad(
                "scenario",
                "scenario must be \"paper\", \"auv\" or \"woods\"",
            )
        })?;
        let seed = self
            .seed
            .as_ref()
            .map_or(Ok(1), |s| s.at_most(u64::MAX, "seed"))?;
        let mut o = SimulateOptions::new(scenario, seed);
        let default_steps = match scenario {
            Scenario::Paper => PAPER_STEPS,
            Scenario::Auv => AUV_STEPS,
            Scenario::Woods => WOODS_STEPS,
        } as u64;
        // A mission has at least one motion step between two positions
        // and one landmark (one rule, one message, per field).
        let steps = match &self.steps {
            Some(s) => s.in_range(2, limits.max_steps, "steps")?,
            None => default_steps.min(limits.max_steps),
        };
        o.steps = Some(steps as usize);
        o.landmarks = self
            .landmarks
            .as_ref()
            .map(|n| n.in_range(1, MAX_LANDMARKS as u64, "landmarks"))
            .transpose()?
            .map(|n| n as usize);
        o.operator = self.operator.unwrap_or(false);
        if let Some(Finite(n)) = self.noise {
            if !(0.0..=100.0).contains(&n) {
                return Err(bad("noise", "noise must be in [0, 100]"));
            }
            o.noise = n;
        }
        if let Some(x) = &self.layout {
            o.layout = x.as_str().and_then(Layout::parse).ok_or_else(|| {
                bad(
                    "layout",
                    format!("unknown layout {x} (expected line, ring or random)"),
                )
            })?;
        }
        o.range_only = self.range_only.unwrap_or(false);
        let max_false = limits.max_false_detections.min(MAX_FALSE_DETECTIONS as u64);
        o.false_detections =
            self.false_detections
                .as_ref()
                .map_or(Ok(0), |k| k.at_most(max_false, "false_detections"))? as usize;
        foreign_options(&o)?;
        Ok(o)
    }
}

/// Options of other scenarios pass only at their defaults: the first set
/// away from its default that `o`'s scenario does not take is an error
/// naming it.
fn foreign_options(o: &SimulateOptions) -> Result<(), InputError> {
    let scenario = o.scenario;
    // (field, set away from its default, this scenario takes it, who does)
    let (paper, not_woods) = (scenario == Scenario::Paper, scenario != Scenario::Woods);
    let not_auv = scenario != Scenario::Auv;
    let only = [
        (
            "layout",
            o.layout != Layout::Line,
            paper,
            "the paper scenario",
        ),
        ("range_only", o.range_only, paper, "the paper scenario"),
        (
            "false_detections",
            o.false_detections > 0,
            not_auv,
            "the paper and woods scenarios",
        ),
        (
            "noise",
            o.noise != 1.0,
            not_woods,
            "the paper and auv scenarios",
        ),
        (
            "landmarks",
            o.landmarks.is_some(),
            not_auv,
            "the paper and woods scenarios",
        ),
    ];
    match only.iter().find(|(_, set, takes, _)| *set && !takes) {
        Some((field, _, _, owner)) => Err(bad(field, format!("{field} applies to {owner} only"))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod request_tests {
    use super::*;
    use crate::format::{from_value, Object};
    use serde_json::json;

    fn options(v: Value) -> Result<SimulateOptions, InputError> {
        from_value::<Object<SimulateRequest>>(&v)?
            .0
            .options(SimulateLimits::CORE)
    }

    #[test]
    fn defaults_and_limits() {
        let o = options(json!({"scenario": "paper"})).unwrap();
        assert_eq!((o.seed, o.steps, o.landmarks), (1, Some(PAPER_STEPS), None));
        // Below 2 steps was read as 2, 0 landmarks as 1: refused now.
        let e = options(json!({"scenario": "auv", "steps": 0, "seed": null})).unwrap_err();
        assert_eq!(e.path, "steps");
        let o = options(json!({"scenario": "auv", "steps": 2, "seed": null})).unwrap();
        assert_eq!((o.steps, o.landmarks), (Some(2), None));
        let limits = SimulateLimits {
            max_steps: 20_000,
            max_false_detections: 7,
        };
        let o = SimulateRequest {
            scenario: Some(json!("auv")),
            ..SimulateRequest::default()
        }
        .options(limits)
        .unwrap();
        assert_eq!(o.steps, Some(20_000), "the default, at most the limit");
        let o = options(json!({"scenario": "woods", "false_detections": 100_000})).unwrap();
        assert_eq!(o.false_detections, MAX_FALSE_DETECTIONS);
    }

    #[test]
    fn errors_name_the_field() {
        for (v, want) in [
            (json!({"scenario": "moon"}), "scenario: scenario must be"),
            (json!({"layout": "spiral"}), "layout"),
            (
                json!({"scenario": "paper", "landmarks": 65}),
                "landmarks: expected an integer from 1 to 64, found 65",
            ),
            (
                json!({"scenario": "paper", "steps": 2_000_001}),
                "steps: expected an integer from 2 to 2000000, found 2000001",
            ),
            (
                json!({"scenario": "paper", "noise": -1}),
                "noise: noise must be in [0, 100]",
            ),
            (
                json!({"scenario": "paper", "noise": "x"}),
                "noise: expected a finite number, found a string",
            ),
            (
                json!({"scenario": "paper", "layout": "spiral"}),
                "layout: unknown layout \"spiral\"",
            ),
            (
                json!({"scenario": "paper", "false_detections": 100_001}),
                "false_detections: expected an integer from 0 to 100000, found 100001",
            ),
            (
                json!({"scenario": "woods", "false_detections": 100_001}),
                "false_detections: expected an integer from 0 to 100000, found 100001",
            ),
            (
                json!({"scenario": "auv", "false_detections": 2}),
                "false_detections: false_detections applies to the paper and woods scenarios only",
            ),
            (
                json!({"scenario": "auv", "range_only": true}),
                "range_only: range_only applies to the paper scenario only",
            ),
            (
                json!({"scenario": "paper", "operator": 1}),
                "operator: expected a boolean, found a number",
            ),
            (
                json!({"scenario": "paper", "stpes": 1}),
                "stpes: unknown field `stpes`",
            ),
            (json!([]), "expected an object, found an array"),
        ] {
            let e = options(v).unwrap_err().to_string();
            assert!(e.starts_with(want), "{e} does not start with {want}");
        }
    }
}
