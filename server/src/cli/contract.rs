//! `nvector contract`: one atmost_nvector contraction, request JSON on
//! stdin, response JSON on stdout (docs/formats.md).

use crate::CliError;
use nvector_core::nvector::contract::contract_json_with;
use nvector_core::nvector::hitting_set::Limits;
use nvector_core::nvector::Contractor;
use std::io::{Read, Write};
use std::time::Instant;

/// Parses `--contractor`: an unknown name is a usage error (exit 2).
pub fn parse_mode(name: &str) -> Result<Contractor, String> {
    Contractor::parse(name).ok_or_else(|| {
        format!(
            "unknown contractor '{name}' (expected nvalue, projection, independent, exact, shapes or best)"
        )
    })
}

/// Runs the subcommand; `node_budget` bounds the exact contractor's search
/// (default [`nvector_core::nvector::hitting_set::DEFAULT_NODE_BUDGET`]).
pub fn run(mode: Option<Contractor>, node_budget: Option<u64>) -> Result<(), CliError> {
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .map_err(|e| CliError(format!("reading standard input: {e}")))?;
    let request: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| CliError(format!("invalid JSON on standard input: {e}")))?;
    // A `Value` keeps the last of a repeated key silently (`"n": 1, "n":
    // 5` was read as 5): refused, as the service and the typed reads of
    // missions and TDOA problems refuse it.
    if let Some(path) = nvector_core::format::duplicate_key(&text) {
        return Err(CliError(format!(
            "{path}: duplicate key: a key may appear once in an object"
        )));
    }
    let start = Instant::now();
    let mut limits = Limits::default();
    if let Some(b) = node_budget {
        limits.node_budget = b;
    }
    let mut response =
        contract_json_with(&request, mode, &limits).map_err(|e| CliError(e.to_string()))?;
    response["stats"]["elapsed_us"] = serde_json::Value::from(start.elapsed().as_micros() as u64);
    let mut out = std::io::stdout().lock();
    serde_json::to_writer(&mut out, &response)?;
    writeln!(out)?;
    Ok(())
}
