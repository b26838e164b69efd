//! `nvector contract`: one atmost_nvector contraction, request JSON on
//! stdin, response JSON on stdout (spec/formats.md).

use crate::CliError;
use nvector_core::nvector::contract::contract_json;
use nvector_core::nvector::Mode;
use std::io::{Read, Write};
use std::time::Instant;

/// Parses `--contractor`: an unknown name is a usage error (exit 2).
pub fn parse_mode(name: &str) -> Result<Mode, String> {
    Mode::parse(name).ok_or_else(|| {
        format!(
            "unknown contractor '{name}' (expected nvalue, projection, independent, exact or best)"
        )
    })
}

/// Runs the subcommand.
pub fn run(mode: Option<Mode>) -> Result<(), CliError> {
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .map_err(|e| CliError(format!("reading standard input: {e}")))?;
    let request: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| CliError(format!("invalid JSON on standard input: {e}")))?;
    let start = Instant::now();
    let mut response = contract_json(&request, mode).map_err(|e| CliError(e.to_string()))?;
    response["stats"]["elapsed_us"] = serde_json::Value::from(start.elapsed().as_micros() as u64);
    let mut out = std::io::stdout().lock();
    serde_json::to_writer(&mut out, &response)?;
    writeln!(out)?;
    Ok(())
}
