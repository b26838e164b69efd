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
use serde::Serialize;
use serde_json::Value;

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
            .in_range(1, u32::MAX as u64, "n")?;
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
                    format!("unknown contractor \"{s}\" (expected nvalue, projection, independent, exact, shapes or best)"),
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

/// The status of a contraction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = ContractStatus))]
#[serde(rename_all = "lowercase")]
pub enum ResponseStatus {
    /// Some box shrank.
    Contracted,
    /// Nothing changed.
    Unchanged,
    /// The constraint is unsatisfiable; every box is `"empty"`.
    Infeasible,
}

/// Bounds on the minimum number of distinct vectors.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct MinDistinct {
    /// A proved lower bound.
    pub lower: u64,
    /// The size of a hitting set that was found.
    pub upper: u64,
}

/// Counters of a contraction.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ContractStats {
    /// Rounds to the fixpoint.
    pub rounds: u64,
    /// Wall time (µs).
    pub elapsed_us: u64,
    /// Present (true) when the fixpoint's round cap stopped it with work
    /// pending: the boxes are sound, another contraction may shrink them.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub stopped: Option<bool>,
}

/// The answer of a contraction (`nvector-contract-result/1`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ContractResponse {
    /// Always `"nvector-contract-result/1"`.
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = String, pattern = "^nvector-contract-result/1$")
    )]
    pub format: &'static str,
    /// What happened.
    pub status: ResponseStatus,
    /// Why it is infeasible (with `infeasible`).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub reason: Option<String>,
    /// The contracted boxes, in the request's order (`json::box_to_json`).
    #[cfg_attr(feature = "openapi", schema(schema_with = response_boxes))]
    pub boxes: Vec<Value>,
    /// A partition of the box indices into groups proved equal.
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<Vec<u64>>))]
    pub groups: Vec<Vec<usize>>,
    /// Bounds on the minimum number of distinct vectors.
    pub min_distinct: MinDistinct,
    /// Counters.
    pub stats: ContractStats,
}

#[cfg(feature = "openapi")]
fn response_boxes() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
    format::openapi::output::boxes("The contracted boxes, in the request's order.")
}

impl ContractResponse {
    /// The response for a contraction outcome (`elapsed_us` = 0: core has
    /// no clock; callers overwrite `stats.elapsed_us`). `stats.stopped` is
    /// present, `true`, only when the fixpoint stopped at its round cap
    /// ([`super::MAX_ROUNDS`]) with work pending: the boxes are sound,
    /// another request on them may contract further.
    pub fn new(boxes: &[IntervalBox], outcome: &Outcome) -> ContractResponse {
        let (status, reason) = match &outcome.status {
            Status::Contracted => (ResponseStatus::Contracted, None),
            Status::Unchanged => (ResponseStatus::Unchanged, None),
            Status::Infeasible { reason } => (ResponseStatus::Infeasible, Some(reason.clone())),
        };
        ContractResponse {
            format: RESPONSE_FORMAT,
            status,
            reason,
            boxes: boxes.iter().map(json::box_to_json).collect(),
            groups: outcome.groups.clone(),
            min_distinct: MinDistinct {
                lower: outcome.min_distinct_lower as u64,
                upper: outcome.min_distinct_upper as u64,
            },
            stats: ContractStats {
                rounds: u64::from(outcome.rounds),
                elapsed_us: 0,
                stopped: outcome.stopped_early.then_some(true),
            },
        }
    }
}

/// The response JSON for a contraction outcome ([`ContractResponse::new`]).
pub fn response_json(boxes: &[IntervalBox], outcome: &Outcome) -> Value {
    serde_json::to_value(ContractResponse::new(boxes, outcome)).unwrap_or(Value::Null)
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
    use serde_json::json;

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

    /// The worst case of `exact` as a request (see
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
