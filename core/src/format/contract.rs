//! `nvector-contract/1` as JSON (docs/formats.md, "nvector contraction
//! request / response"): the request's fields. Validated into
//! `nvector::contract::ContractRequest` (which checks the format tag, n,
//! the boxes' common dimension and the contractor's name).

use super::leaf::{BoxIn, Integer, List};
#[cfg(feature = "openapi")]
use super::openapi::contract as oa;
use super::present;
use serde::Deserialize;
use serde_json::Value;

/// One atmost_nvector contraction (`nvector-contract/1`).
///
/// Rules beyond the schema (422 naming the JSON path): every box has the
/// dimension of `boxes[0]`; intervals have lo <= hi; `exact` takes at most
/// 40 boxes, and answers 422 (`work_limit`) when it runs out of its work
/// budget or the request's time limit.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = ContractRequest, example = json!({
    "format": "nvector-contract/1",
    "n": 2,
    "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]],
    "contractor": "projection"
})))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct ContractDoc {
    /// `"nvector-contract/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::format, required = true))]
    pub format: Option<Value>,
    /// The most distinct vectors allowed.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = u32, minimum = 1, maximum = 4294967295u32, required = true)
    )]
    pub n: Option<Integer>,
    /// The k boxes, all of one dimension.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Vec<BoxIn>, min_items = 1, max_items = 100000, required = true)
    )]
    pub boxes: Option<List<BoxIn>>,
    /// The contractor's name (default `best`).
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::contractor))]
    pub contractor: Option<String>,
}

object_only!(ContractDoc);
