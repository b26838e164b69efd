//! `nvector-contract/1` as JSON (docs/formats.md, "nvector contraction
//! request / response"): the request's fields. Validated into
//! `nvector::contract::ContractRequest` (which checks the format tag, n,
//! the boxes' common dimension and the contractor's name).

use super::leaf::{BoxIn, Integer, List};
use super::present;
use serde::Deserialize;
use serde_json::Value;

/// A contraction request.
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct ContractDoc {
    /// `"nvector-contract/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    pub format: Option<Value>,
    /// n.
    #[serde(default, deserialize_with = "present")]
    pub n: Option<Integer>,
    /// The k boxes.
    #[serde(default, deserialize_with = "present")]
    pub boxes: Option<List<BoxIn>>,
    /// The contractor's name (default `best`).
    pub contractor: Option<String>,
}

object_only!(ContractDoc);
