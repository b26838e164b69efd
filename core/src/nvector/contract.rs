//! The `nvector-contract/1` request and `nvector-contract-result/1`
//! response of docs/formats.md, shared by `nvector contract`,
//! `POST /api/v1/contract` and the browser.

pub use super::error::ContractError;
use super::hitting_set::Limits;
use super::{atmost_nvector_with, Contractor, Outcome, Status};
use crate::error::InputError;
use crate::format::{self, contract::ContractDoc, leaf::List};
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
    pub mode: Contractor,
}

impl ContractRequest {
    /// Parses and validates a request; errors name the JSON path.
    pub fn from_value(v: &Value) -> Result<ContractRequest, InputError> {
        ContractRequest::from_doc(format::from_value(v)?)
    }

    /// Validates a parsed request.
    pub fn from_doc(doc: ContractDoc) -> Result<ContractRequest, InputError> {
        let missing = |f: &str| InputError::new(f, "missing required field");
        let format = doc.format.ok_or_else(|| missing("format"))?;
        if format.as_str() != Some(REQUEST_FORMAT) {
            return Err(InputError::new(
                "format",
                format!("expected \"{REQUEST_FORMAT}\", found {format}"),
            ));
        }
        let n = doc
            .n
            .ok_or_else(|| missing("n"))?
            .at_most(u32::MAX as u64, "n")?;
        if n == 0 {
            return Err(InputError::new("n", "n must be at least 1"));
        }
        let List(boxes_doc) = doc.boxes.ok_or_else(|| missing("boxes"))?;
        if boxes_doc.is_empty() {
            return Err(InputError::new("boxes", "at least one box is needed"));
        }
        let mut boxes = Vec::with_capacity(boxes_doc.len());
        let mut dim = None;
        for (i, b) in boxes_doc.iter().enumerate() {
            let path = format!("boxes[{i}]");
            let parsed = b.dim(&path, dim).map_err(|e| match dim {
                Some(d) => InputError::new(
                    path.clone(),
                    format!(
                        "every box must have the dimension of boxes[0] ({d}): {}",
                        e.message
                    ),
                ),
                None => e,
            })?;
            dim = Some(parsed.dim());
            boxes.push(parsed);
        }
        let mode = match doc.contractor {
            None => Contractor::Best,
            Some(s) => Contractor::parse(&s).ok_or_else(|| {
                InputError::new(
                    "contractor",
                    format!("unknown contractor \"{s}\" (expected nvalue, projection, independent, exact or best)"),
                )
            })?,
        };
        Ok(ContractRequest {
            n: n as usize,
            boxes,
            mode,
        })
    }
}

/// The response JSON for a contraction outcome (`elapsed_us` = 0: core has
/// no clock; callers overwrite `stats.elapsed_us`). `stats.stopped` is
/// present, `true`, only when the fixpoint stopped at its round cap
/// ([`super::MAX_ROUNDS`]) with work pending: the boxes are sound, another
/// request on them may contract further.
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
    let mut stats = json!({"rounds": outcome.rounds, "elapsed_us": 0});
    if outcome.stopped_early {
        stats["stopped"] = Value::Bool(true);
    }
    out.insert("stats".into(), stats);
    Value::Object(out)
}

/// Runs one contraction request (JSON value) and returns the response.
/// `mode_override` (from the CLI's `--contractor`) wins over the request's.
/// `exact` runs with the default [`Limits`]; running out of them is an
/// `InputError` naming the limit (path `""`).
pub fn contract_json(
    request: &Value,
    mode_override: Option<Contractor>,
) -> Result<Value, InputError> {
    contract_json_with(request, mode_override, &Limits::default()).map_err(InputError::from)
}

/// [`contract_json`] with explicit limits on the work of `exact` (node
/// budget, cancellation flag for the caller's deadline), and a distinct
/// error when they run out ([`ContractError::Limit`]).
pub fn contract_json_with(
    request: &Value,
    mode_override: Option<Contractor>,
    limits: &Limits,
) -> Result<Value, ContractError> {
    let mut req = ContractRequest::from_value(request)?;
    let mode = mode_override.unwrap_or(req.mode);
    let outcome = atmost_nvector_with(req.n, &mut req.boxes, mode, limits)?;
    Ok(response_json(&req.boxes, &outcome))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nvector::hitting_set::WorkLimit;

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

    /// The worst case of issue 12 as a request (see
    /// `hitting_set::tests::worst_case`).
    fn worst_case_request() -> Value {
        let boxes: Vec<Value> = crate::nvector::hitting_set::tests::worst_case()
            .iter()
            .map(json::box_to_json)
            .collect();
        json!({"format": "nvector-contract/1", "n": 6, "boxes": boxes, "contractor": "exact"})
    }

    #[test]
    fn exact_out_of_budget_is_a_work_limit_error() {
        let limits = Limits {
            node_budget: 50_000,
            ..Limits::default()
        };
        let e = contract_json_with(&worst_case_request(), None, &limits).unwrap_err();
        assert_eq!(e, ContractError::Limit(WorkLimit::NodeBudget(50_000)));
        assert_eq!((e.code(), e.path()), ("work_limit", ""));
        assert!(e.message().contains("work budget (50000 search nodes)"));
        // One error type for the callers that know only InputError.
        let i = InputError::from(e);
        assert_eq!(i.path, "");
        assert!(i
            .to_string()
            .starts_with("the exact contractor ran out of its work budget"));
        // Bad input stays an input error with its path.
        let bad = json!({"format": "nvector-contract/1", "n": 0, "boxes": [[[0, 1]]]});
        let e = contract_json_with(&bad, None, &limits).unwrap_err();
        assert_eq!((e.code(), e.path()), ("invalid_request", "n"));
        // The same request with a polynomial contractor needs no budget.
        let out =
            contract_json_with(&worst_case_request(), Some(Contractor::Best), &limits).unwrap();
        assert_eq!(out["format"], RESPONSE_FORMAT);
    }

    #[test]
    fn the_round_cap_is_reported() {
        // Round 1: axis 0 needs one value (slack); axis 1 groups boxes 0
        // and 1, whose intersection moves box 0 on axis 0, so a second
        // round is due. Capped at one round, the response says it stopped,
        // and its boxes enclose the full fixpoint's.
        let req = json!({
            "format": "nvector-contract/1",
            "n": 2,
            "boxes": [[[0, 10], [0, 1]], [[2, 3], [0.5, 2]], [[0, 10], [8, 9]]],
            "contractor": "projection"
        });
        let full = contract_json(&req, None).unwrap();
        assert!(full["stats"].get("stopped").is_none(), "{}", full["stats"]);
        assert_eq!(full["stats"]["rounds"], 2);
        let capped = contract_json_with(
            &req,
            None,
            &Limits {
                max_rounds: 1,
                ..Limits::default()
            },
        )
        .unwrap();
        assert_eq!(capped["stats"]["stopped"], true, "{}", capped["stats"]);
        assert_eq!(capped["stats"]["rounds"], 1);
        let parse = |v: &Value| {
            ContractRequest::from_value(
                &json!({"format": REQUEST_FORMAT, "n": 2, "boxes": v["boxes"]}),
            )
            .unwrap()
            .boxes
        };
        for (a, b) in parse(&full).iter().zip(&parse(&capped)) {
            assert!(a.is_subset(b));
        }
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
