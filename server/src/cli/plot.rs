//! `nvector plot` (and `nvector run --plot`): reads a result and its
//! mission and writes the figure (crate::render draws it) to .svg or .png.

use crate::render::{render_png, try_render_svg};
use crate::CliError;
use nvector_core::format::result::ResultDoc;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Arguments of `nvector plot`.
#[derive(clap::Args)]
pub struct Args {
    /// The result (nvector-result/1 JSON).
    result: PathBuf,
    /// The mission it was computed from (for the truth).
    #[arg(long)]
    mission: PathBuf,
    /// Output figure: .svg or .png.
    #[arg(long)]
    out: PathBuf,
}

/// Writes the figure to `path` (.svg or .png).
pub fn write_plot(path: &Path, result: &ResultDoc, mission: &Value) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = match ext.as_str() {
        "svg" => try_render_svg(result, mission)?.into_bytes(),
        "png" => render_png(result, mission)?,
        _ => {
            return Err(CliError(format!(
                "{}: the figure must end in .svg or .png",
                path.display()
            )))
        }
    };
    std::fs::write(path, bytes).map_err(|e| CliError(format!("writing {}: {e}", path.display())))
}

/// The result file read through the format's types
/// (`nvector_core::format::result`): the first fault named by its JSON
/// path (a result edited by hand or cut short is refused, not drawn).
fn read_result(path: &PathBuf) -> Result<ResultDoc, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    nvector_core::format::result::read(&text)
        .map_err(|e| CliError(format!("{}: {e}", path.display())))
}

/// Why `result` does not look computed from `mission`, if it does not: the
/// names differ, or the trajectory or detections do not count as the
/// mission's steps and detections.
pub fn mismatch(result: &ResultDoc, mission: &Value) -> Option<String> {
    let mut why = Vec::new();
    if let (r, Some(m)) = (&result.mission, mission["name"].as_str()) {
        if r != m {
            why.push(format!(
                "the result is of mission \"{r}\", the mission is \"{m}\""
            ));
        }
    }
    if let (t, Some(steps)) = (&result.trajectory.0, mission["steps"].as_u64()) {
        if t.len() as u64 != steps.saturating_add(1) {
            why.push(format!(
                "the result has {} trajectory boxes, the mission {} steps (expected {})",
                t.len(),
                steps,
                steps.saturating_add(1)
            ));
        }
    }
    if let (d, Some(md)) = (&result.detections.0, mission["detections"].as_array()) {
        if d.len() != md.len() {
            why.push(format!(
                "the result has {} detections, the mission {}",
                d.len(),
                md.len()
            ));
        }
    }
    (!why.is_empty()).then(|| why.join("; "))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let result = read_result(&a.result)?;
    // The mission as `run` reads it (unknown fields, bad bounds, a step
    // count its file cannot hold are refused, named); the figure reads
    // the value.
    let text = std::fs::read_to_string(&a.mission)
        .map_err(|e| CliError(format!("reading {}: {e}", a.mission.display())))?;
    nvector_core::slam::mission::Mission::from_json(&text)
        .map_err(|e| CliError(format!("{}: {e}", a.mission.display())))?;
    let mission: Value = serde_json::from_str(&text)
        .map_err(|e| CliError(format!("{}: invalid JSON: {e}", a.mission.display())))?;
    if let Some(why) = mismatch(&result, &mission) {
        say!(
            "nvector: warning: {} does not look computed from {}: {why} (the truth drawn may not be this result's)",
            a.result.display(),
            a.mission.display()
        );
    }
    write_plot(&a.out, &result, &mission)
}
