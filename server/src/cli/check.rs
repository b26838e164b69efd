//! `nvector check MISSION.json [--json]`: every constraint of the mission
//! that its truth breaks, and by how much (core's `slam::check`; docs/cli.md,
//! "check"). Exit 0 when none (or only detections `max_outliers` covers),
//! 1 when some, or on bad input.

use crate::CliError;
use nvector_core::slam::check::types::{Bound, Violation};
use nvector_core::slam::check::{check_json, Report};
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `nvector check`.
#[derive(clap::Args)]
pub struct Args {
    /// The mission (nvector-mission/1 JSON, with truth).
    mission: PathBuf,
    /// Print `{"violations": [...]}` (docs/formats.md, "Check") instead of
    /// one line per violation.
    #[arg(long)]
    json: bool,
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let text = std::fs::read_to_string(&a.mission)
        .map_err(|e| CliError(format!("reading {}: {e}", a.mission.display())))?;
    let report = check_json(&text).map_err(|e| {
        CliError(format!(
            "{}: {}",
            a.mission.display(),
            super::wrong_kind(&text, "nvector-mission/1", e.to_string())
        ))
    })?;
    let mut out = std::io::stdout().lock();
    let written = if a.json {
        writeln!(out, "{}", report.to_json())
    } else {
        report
            .violations
            .iter()
            .try_for_each(|v| writeln!(out, "{}", line(v)))
    };
    written.map_err(|e| CliError(format!("writing standard output: {e}")))?;
    let summary = summary(&report);
    if report.broken() > 0 {
        return Err(CliError(summary));
    }
    say!("nvector: {summary}");
    Ok(())
}

/// A number as the text output prints it (`inf` for an unbounded bound).
fn num(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    format!("{x}")
}

/// One violation as a line: path, kind, value against bound, excess.
pub fn line(v: &Violation) -> String {
    let unit = v.kind.unit();
    let bound = match v.bound {
        Bound::Within(lo, hi) => format!("outside [{}, {}]", num(lo), num(hi)),
        Bound::AtMost(x) => format!("above {}", num(x)),
        Bound::AtLeast(x) => format!("below {}", num(x)),
    };
    let mut s = format!(
        "{}: {} {} {bound} by {} {unit}",
        v.path,
        v.kind.name(),
        num(v.value),
        num(v.excess)
    );
    let mut about = Vec::new();
    if let Some(t) = v.step {
        about.push(format!("step {t}"));
    }
    if let Some(l) = v.landmark {
        about.push(format!("landmark {l}"));
    }
    if let Some(l) = v.other_landmark {
        about.push(format!("and landmark {l}"));
    }
    if v.outlier {
        about.push("covered by max_outliers".into());
    }
    if !about.is_empty() {
        s.push_str(&format!(" ({})", about.join(", ")));
    }
    s
}

/// The summary line: how many constraints the truth breaks, how many of
/// them `max_outliers` covers, and how many were not checked.
pub fn summary(r: &Report) -> String {
    let broken = r.broken();
    let covered = r.violations.len() - broken;
    let mut s = match broken {
        0 => "the truth satisfies every constraint checked".to_string(),
        1 => "the truth breaks 1 constraint".to_string(),
        n => format!("the truth breaks {n} constraints"),
    };
    if covered > 0 {
        s.push_str(&format!(
            "; {covered} violation{} of {} detection{} covered by max_outliers {}",
            if covered == 1 { "" } else { "s" },
            r.broken_detections,
            if r.broken_detections == 1 { "" } else { "s" },
            r.max_outliers
        ));
    }
    if r.unchecked > 0 {
        s.push_str(&format!(
            "; {} constraint{} not checked (the truth does not know a value there)",
            r.unchecked,
            if r.unchecked == 1 { "" } else { "s" }
        ));
    }
    s
}
