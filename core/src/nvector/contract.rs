//! The `nvector-contract/1` request and `nvector-contract-result/1`
//! response of spec/formats.md, shared by `nvector contract`,
//! `POST /api/v1/contract` and the browser.

use super::{atmost_nvector, Mode, Outcome, Status};
use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::json;
use serde_json::{json, Map, Value};

/// Format tag of a request.
pub const REQUEST_FORMAT: &str = "nvector-contract/1";
/// Format tag of a response.
pub const RESPONSE_FORMAT: &str = "nvector-contract-result/1";

/// A validated contraction request.
#[derive(Debug, Clone)]
pub struct ContractRequest {
    /// Most distinct vectors.
    pub n: usize,
    /// The k boxes, one dimension.
    pub boxes: Vec<IntervalBox>,
    /// The contractor.
    pub mode: Mode,
}

impl ContractRequest {
    /// Parses and validates a request; errors name the JSON path.
    pub fn from_value(v: &Value) -> Result<ContractRequest, InputError> {
        let obj = json::object(v, "")?;
        json::check_fields(obj, &["format", "n", "boxes", "contractor"], "")?;
        let format = json::required(obj, "format", "")?;
        if format.as_str() != Some(REQUEST_FORMAT) {
            return Err(InputError::new(
                "format",
                format!("expected \"{REQUEST_FORMAT}\", found {format}"),
            ));
        }
        let n = json::integer(json::required(obj, "n", "")?, "n", u32::MAX as u64)?;
        if n == 0 {
            return Err(InputError::new("n", "n must be at least 1"));
        }
        let boxes_v = json::array(json::required(obj, "boxes", "")?, "boxes")?;
        if boxes_v.is_empty() {
            return Err(InputError::new("boxes", "at least one box is needed"));
        }
        let mut boxes = Vec::with_capacity(boxes_v.len());
        let mut dim = None;
        for (i, b) in boxes_v.iter().enumerate() {
            let path = json::index_path("boxes", i);
            let parsed = json::ibox(b, &path, dim).map_err(|e| match dim {
                Some(d)
                    if e.path == path && e.message.starts_with("expected a box of dimension") =>
                {
                    InputError::new(
                        path.clone(),
                        format!(
                            "every box must have the dimension of boxes[0] ({d}): {}",
                            e.message
                        ),
                    )
                }
                _ => e,
            })?;
            dim = Some(parsed.dim());
            boxes.push(parsed);
        }
        let mode = match obj.get("contractor") {
            None | Some(Value::Null) => Mode::Best,
            Some(Value::String(s)) => Mode::parse(s).ok_or_else(|| {
                InputError::new(
                    "contractor",
                    format!("unknown contractor \"{s}\" (expected nvalue, projection, independent, exact or best)"),
                )
            })?,
            Some(other) => {
                return Err(InputError::new(
                    "contractor",
                    format!("expected a string, found {}", json::kind(other)),
                ))
            }
        };
        Ok(ContractRequest {
            n: n as usize,
            boxes,
            mode,
        })
    }
}

/// The response JSON for a contraction outcome (`elapsed_us` = 0: core has
/// no clock; callers overwrite `stats.elapsed_us`).
pub fn response_json(boxes: &[IntervalBox], outcome: &Outcome) -> Value {
    let mut out = Map::new();
    out.insert("format".into(), Value::from(RESPONSE_FORMAT));
    let status = match &outcome.status {
        Status::Contracted => "contracted",
        Status::Unchanged => "unchanged",
        Status::Infeasible { .. } => "infeasible",
    };
    out.insert("status".into(), Value::from(status));
    if let Status::Infeasible { reason } = &outcome.status {
        out.insert("reason".into(), Value::from(reason.as_str()));
    }
    out.insert(
        "boxes".into(),
        Value::Array(boxes.iter().map(json::box_to_json).collect()),
    );
    out.insert("groups".into(), json!(outcome.groups));
    out.insert(
        "min_distinct".into(),
        json!({"lower": outcome.min_distinct_lower, "upper": outcome.min_distinct_upper}),
    );
    out.insert(
        "stats".into(),
        json!({"rounds": outcome.rounds, "elapsed_us": 0}),
    );
    Value::Object(out)
}

/// Runs one contraction request (JSON value) and returns the response.
/// `mode_override` (from the CLI's `--contractor`) wins over the request's.
pub fn contract_json(request: &Value, mode_override: Option<Mode>) -> Result<Value, InputError> {
    let mut req = ContractRequest::from_value(request)?;
    let mode = mode_override.unwrap_or(req.mode);
    let outcome = atmost_nvector(req.n, &mut req.boxes, mode)?;
    Ok(response_json(&req.boxes, &outcome))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_example_round_trip() {
        let req = json!({
            "format": "nvector-contract/1",
            "n": 2,
            "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]],
            "contractor": "projection"
        });
        let out = contract_json(&req, None).unwrap();
        assert_eq!(out["format"], "nvector-contract-result/1");
        assert_eq!(out["status"], "contracted");
        assert_eq!(
            out["boxes"],
            json!([
                [[1.0, 2.0], [1.0, 2.0]],
                [[1.0, 2.0], [1.0, 2.0]],
                [[5.0, 6.0], [5.0, 6.0]]
            ])
        );
        assert_eq!(out["groups"], json!([[0, 1], [2]]));
        assert_eq!(out["min_distinct"], json!({"lower": 2, "upper": 2}));
    }

    #[test]
    fn errors_name_the_path() {
        let bad = |v: Value| contract_json(&v, None).unwrap_err().to_string();
        let base = |boxes: Value| json!({"format": "nvector-contract/1", "n": 1, "boxes": boxes});
        assert_eq!(
            bad(base(json!([[[0, 1]], [[3, 2]]]))),
            "boxes[1][0]: lower bound 3 is above upper bound 2"
        );
        assert!(bad(base(json!([[[0, 1]], [[0, 1], [0, 1]]])))
            .starts_with("boxes[1]: every box must have the dimension"));
        assert!(bad(json!({"format": "x", "n": 1, "boxes": []})).starts_with("format:"));
        assert!(
            bad(json!({"format": "nvector-contract/1", "n": 0, "boxes": [[[0, 1]]]}))
                .starts_with("n:")
        );
        assert!(
            bad(json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]], "nn": 2}))
                .starts_with("nn: unknown field")
        );
        assert!(bad(json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]], "contractor": "fast"})).starts_with("contractor:"));
    }

    #[test]
    fn infeasible_response_has_empty_boxes_and_reason() {
        let req = json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]], [[2, 3]]]});
        let out = contract_json(&req, None).unwrap();
        assert_eq!(out["status"], "infeasible");
        assert_eq!(out["boxes"], json!(["empty", "empty"]));
        assert!(out["reason"].as_str().unwrap().contains("n = 1"));
    }
}
