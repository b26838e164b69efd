//! [`ContractError`]: why a contraction gave no answer. It sits below
//! both the contractors ([`super::atmost_nvector_with`]) and the
//! `nvector-contract/1` job ([`super::contract`], which re-exports it under
//! its former path), so that neither imports the other.

use super::hitting_set::WorkLimit;
use crate::error::InputError;

/// Why a contraction gave no response: bad input, or `exact` out of its
/// work limits. The service answers both with HTTP 422 and the spec's error
/// body, under the codes of [`ContractError::code`]; the CLI exits 1 with
/// the message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ContractError {
    /// The request is invalid (the JSON path says where).
    Input(InputError),
    /// The exact contractor ran out of its node budget or was cancelled.
    Limit(WorkLimit),
}

impl ContractError {
    /// The error code of the spec's error body: `"invalid_request"` or
    /// `"work_limit"`.
    pub fn code(&self) -> &'static str {
        match self {
            ContractError::Input(_) => "invalid_request",
            ContractError::Limit(_) => "work_limit",
        }
    }

    /// The JSON path of the offending value (`""` for a work limit: the
    /// request as a whole).
    pub fn path(&self) -> &str {
        match self {
            ContractError::Input(e) => &e.path,
            ContractError::Limit(_) => "",
        }
    }

    /// What went wrong, without the path.
    pub fn message(&self) -> String {
        match self {
            ContractError::Input(e) => e.message.clone(),
            ContractError::Limit(l) => l.to_string(),
        }
    }
}

impl std::fmt::Display for ContractError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ContractError::Input(e) => e.fmt(f),
            ContractError::Limit(l) => l.fmt(f),
        }
    }
}

impl std::error::Error for ContractError {}

impl From<InputError> for ContractError {
    fn from(e: InputError) -> Self {
        ContractError::Input(e)
    }
}

impl From<WorkLimit> for ContractError {
    fn from(e: WorkLimit) -> Self {
        ContractError::Limit(e)
    }
}

/// For the callers that know one error type: a work limit becomes an
/// `InputError` of the whole request (path `""`) naming the limit.
impl From<ContractError> for InputError {
    fn from(e: ContractError) -> Self {
        match e {
            ContractError::Input(e) => e,
            ContractError::Limit(l) => InputError::new("", l.to_string()),
        }
    }
}
