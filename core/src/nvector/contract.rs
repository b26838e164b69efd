//! The `nvector-contract/1` request and `nvector-contract-result/1`
//! response of spec/formats.md. OWNER: helper A.

use crate::error::InputError;
use serde_json::Value;

/// Runs one contraction request (JSON value) and returns the response.
/// `mode_override` (from the CLI's `--contractor`) wins over the request's.
pub fn contract_json(
    request: &Value,
    mode_override: Option<super::Mode>,
) -> Result<Value, InputError> {
    let _ = (request, mode_override);
    Err(InputError::new("", "not implemented yet"))
}
