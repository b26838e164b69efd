//! The OpenAPI schema of [`SimulateRequest`] (feature `openapi`: the
//! server's document only, never in the wasm build), written next to the
//! type that reads the body, from its own constants.
//!
//! The request is one flat serde type (every front end fills it in, and
//! [`SimulateRequest::options`] checks it), but which fields may take which
//! values depends on `scenario`: the paper scenario takes every option, the
//! auv scenario takes the paper's options only at their defaults, woods
//! takes `false_detections` but the other paper options only at their
//! defaults, and no `noise` but 1. JSON Schema says that as a
//! `oneOf` of one object per scenario, told apart by `scenario`; the fuzzer
//! of `make test` sends the service requests drawn from it, and every
//! schema-valid one must be accepted (201) or refused by a service limit
//! (413), every schema-invalid one refused.

use crate::format::openapi::nullable;
use crate::slam::mission::{MAX_LANDMARKS, MAX_STEPS};
use crate::slam::simulate::{SimulateRequest, MAX_FALSE_DETECTIONS};
use utoipa::openapi::schema::{AdditionalProperties, ObjectBuilder, OneOfBuilder, Schema, Type};
use utoipa::openapi::RefOr;
use utoipa::{PartialSchema, ToSchema};

/// `{"type": "integer", "minimum": min, "maximum": max}` or null.
fn count(min: u64, max: u64, description: &str) -> RefOr<Schema> {
    nullable(
        ObjectBuilder::new()
            .schema_type(Type::Integer)
            .minimum(Some(min))
            .maximum(Some(max)),
        description,
    )
}

/// One of `values` or null.
fn one_of<T: Into<serde_json::Value>>(
    ty: Type,
    values: Vec<T>,
    description: &str,
) -> RefOr<Schema> {
    nullable(
        ObjectBuilder::new()
            .schema_type(ty)
            .enum_values(Some(values.into_iter().map(Into::into))),
        description,
    )
}

/// What a scenario accepts of the options that are not its own.
struct Scenario {
    name: &'static str,
    description: &'static str,
    steps: &'static str,
    landmarks: &'static str,
    /// `landmarks` taken (the auv survey has its own seamarks: only null).
    takes_landmarks: bool,
    /// The layouts accepted (`line` only but for the paper).
    layouts: &'static [&'static str],
    /// `range_only` accepted true.
    range_only: bool,
    /// Most false detections.
    false_detections: u64,
    /// `noise`: `Some(max)` for a scale in [0, max], `None` for 1 only.
    noise: Option<f64>,
}

const SCENARIOS: [Scenario; 3] = [
    Scenario {
        name: "paper",
        description: "A simulation of the paper's experiment.",
        steps: "Steps (default 10,000; at least 2, at most this service's limit).",
        landmarks: "Landmarks (default 4; at least 1).",
        takes_landmarks: true,
        layouts: &["line", "ring", "random"],
        range_only: true,
        false_detections: MAX_FALSE_DETECTIONS as u64,
        noise: Some(100.0),
    },
    Scenario {
        name: "auv",
        description: "A simulated AUV survey (the paper-only options at their defaults).",
        steps: "Steps (default 60,000; at least 2, at most this service's limit).",
        landmarks: "Not taken: the survey always has its 6 seamarks (null only).",
        takes_landmarks: false,
        layouts: &["line"],
        range_only: false,
        false_detections: 0,
        noise: Some(100.0),
    },
    Scenario {
        name: "woods",
        description: "An odometry2d robot among identical landmarks, with scans and a \
            minimum separation (`layout`, `range_only` and `noise` at their defaults; \
            `false_detections` adds false range-and-bearing detections in the robot's \
            scans). A service refuses (413) a request whose mission could hold more true \
            detections than its limit: (steps / 2 + 1) x landmarks.",
        steps: "Steps (default 3,000; at least 2, at most this service's limit).",
        landmarks: "Landmarks (default 17; at least 1).",
        takes_landmarks: true,
        layouts: &["line"],
        range_only: false,
        false_detections: MAX_FALSE_DETECTIONS as u64,
        noise: None,
    },
];

impl Scenario {
    fn schema(&self) -> ObjectBuilder {
        let noise = match self.noise {
            Some(max) => nullable(
                ObjectBuilder::new()
                    .schema_type(Type::Number)
                    .minimum(Some(0.0))
                    .maximum(Some(max)),
                "Scale of the sensor noise bounds (default 1).",
            ),
            None => one_of(Type::Number, vec![1.0], "Only the default, 1."),
        };
        let range_only = if self.range_only {
            one_of(
                Type::Boolean,
                vec![false, true],
                "Range-only detections with a rough landmark region instead of a bearing \
                 (the paper's P''; default false).",
            )
        } else {
            one_of(Type::Boolean, vec![false], "Only the default, false.")
        };
        ObjectBuilder::new()
            .title(Some(self.name))
            .description(Some(self.description))
            .property(
                "scenario",
                ObjectBuilder::new()
                    .schema_type(Type::String)
                    .enum_values(Some([self.name])),
            )
            .required("scenario")
            .property("seed", count(0, u64::MAX, "The seed (default 1)."))
            .property("steps", count(2, MAX_STEPS as u64, self.steps))
            .property(
                "landmarks",
                if self.takes_landmarks {
                    count(1, MAX_LANDMARKS as u64, self.landmarks)
                } else {
                    ObjectBuilder::new()
                        .schema_type(Type::Null)
                        .description(Some(self.landmarks))
                        .into()
                },
            )
            .property(
                "operator",
                one_of(
                    Type::Boolean,
                    vec![false, true],
                    "Write the true matching as operator `landmark` fields (default false).",
                ),
            )
            .property("noise", noise)
            .property(
                "layout",
                one_of(
                    Type::String,
                    self.layouts.to_vec(),
                    "Landmark layout (default `line`).",
                ),
            )
            .property("range_only", range_only)
            .property(
                "false_detections",
                count(
                    0,
                    self.false_detections,
                    "Extra detections of no landmark (`null` in truth.matching, \
                     `max_outliers` set; default 0). Fewer are drawn when the mission would \
                     hold more detections in all than this service's limit: the mission's \
                     `max_outliers` says how many.",
                ),
            )
            .additional_properties(Some(AdditionalProperties::<Schema>::FreeForm(false)))
    }
}

impl PartialSchema for SimulateRequest {
    fn schema() -> RefOr<Schema> {
        let mut one = OneOfBuilder::new().description(Some(
            "A simulation request: the paper's experiment, an AUV survey or the woods \
             scenario. Every field but `scenario` is optional, and null means absent.",
        ));
        for s in &SCENARIOS {
            one = one.item(s.schema());
        }
        // `example` (deprecated by OpenAPI 3.1 in favour of `examples`) as
        // every other schema of the document gives it.
        #[allow(deprecated)]
        let one = one.example(Some(serde_json::json!(
            {"scenario": "paper", "seed": 3, "steps": 2000, "operator": true}
        )));
        one.into()
    }
}

impl ToSchema for SimulateRequest {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::simulate::SimulateLimits;
    use serde_json::json;

    /// The schema's bounds are the parser's: the largest value each
    /// scenario's schema allows is accepted, one more is refused.
    #[test]
    fn the_schema_bounds_are_the_parsers() {
        let doc = serde_json::to_value(SimulateRequest::schema()).unwrap();
        let variants = doc["oneOf"].as_array().unwrap();
        assert_eq!(variants.len(), 3);
        for v in variants {
            let name = v["properties"]["scenario"]["enum"][0].as_str().unwrap();
            let max = |field: &str| v["properties"][field]["oneOf"][1]["maximum"].as_f64();
            for field in ["steps", "landmarks", "false_detections"] {
                let Some(m) = max(field) else {
                    // Null only (auv's landmarks): any number is refused.
                    assert_eq!(v["properties"][field]["type"], "null", "{name}.{field}");
                    let r = serde_json::from_value::<SimulateRequest>(
                        json!({"scenario": name, field: 1}),
                    )
                    .unwrap()
                    .options(SimulateLimits::CORE);
                    assert_eq!(r.unwrap_err().path, field, "{name}.{field}");
                    continue;
                };
                let m = m as u64;
                let parse = |n: u64| {
                    serde_json::from_value::<SimulateRequest>(json!({"scenario": name, field: n}))
                        .unwrap()
                        .options(SimulateLimits::CORE)
                };
                assert!(parse(m).is_ok(), "{name}.{field} = {m}");
                assert_eq!(parse(m + 1).unwrap_err().path, field, "{name}.{field}");
            }
            let layouts = v["properties"]["layout"]["oneOf"][1]["enum"]
                .as_array()
                .unwrap();
            for layout in ["line", "ring", "random"] {
                let r = serde_json::from_value::<SimulateRequest>(
                    json!({"scenario": name, "layout": layout}),
                )
                .unwrap()
                .options(SimulateLimits::CORE);
                assert_eq!(
                    r.is_ok(),
                    layouts.contains(&json!(layout)),
                    "{name} {layout}"
                );
            }
        }
    }
}
