//! `nvector run`: one SLAM job, locally, with a progress line on a terminal.
//! The mission is parsed straight into typed data and the result streamed
//! out, so memory stays in proportion to the mission, not to its JSON. It ends
//! with a one-line summary on stderr ([`summary`]).

use crate::CliError;
use nvector_core::figure::metres;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::{result_doc, score, write_result, Solution, SolveStatus};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, OutlierTally, Progress, SolveOptions};
use std::io::{BufWriter, IsTerminal, Write};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Arguments of `nvector run`.
#[derive(clap::Args)]
pub struct Args {
    /// The mission (nvector-mission/1 JSON).
    mission: PathBuf,
    /// none, nvalue, projection, independent, shapes or best (default: best when the
    /// mission has landmark_count, none otherwise).
    #[arg(long, value_parser = parse_association)]
    contractor: Option<Association>,
    /// Most propagation rounds.
    #[arg(long, default_value_t = 10_000)]
    max_rounds: u32,
    /// Bounds moving by less than this count as fixed.
    #[arg(long, default_value_t = 1e-9, allow_negative_numbers = true)]
    tolerance: f64,
    /// Threads for the solve's independent work (default: the machine's
    /// available parallelism); the same result for any count.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Output file for the result (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also draw the result (.svg or .png).
    #[arg(long)]
    plot: Option<PathBuf>,
}

fn parse_association(s: &str) -> Result<Association, String> {
    Association::parse(s).ok_or_else(|| {
        format!("unknown contractor '{s}' (expected none, nvalue, projection, independent, shapes or best)")
    })
}

/// Reads and validates a mission file; errors name the file and JSON path.
/// The text is parsed straight into the typed mission (no JSON value of
/// the whole file) and freed on return.
pub fn read_mission(path: &PathBuf) -> Result<Mission, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    Mission::from_json(&text).map_err(|e| {
        CliError(format!(
            "{}: {}",
            path.display(),
            super::wrong_kind(&text, "nvector-mission/1", e.to_string())
        ))
    })
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let mission = read_mission(&a.mission)?;
    if !(a.tolerance.is_finite() && a.tolerance >= 0.0) {
        return Err(CliError(format!(
            "--tolerance must be a finite number >= 0, found {}",
            a.tolerance
        )));
    }
    let association = a.contractor.unwrap_or(if mission.landmark_count.is_some() {
        Association::NVector(nvector_core::nvector::Contractor::Best)
    } else {
        Association::None
    });
    let options = SolveOptions {
        association,
        max_rounds: a.max_rounds,
        tolerance: a.tolerance,
        threads: a
            .threads
            .map_or_else(super::machine_threads, |t| t as usize),
    };
    // A progress bar on a terminal, nothing otherwise.
    let bar = if std::io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:30} {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let start = Instant::now();
    let mut progress = |p: &Progress| {
        bar.set_position((p.fraction * 1000.0) as u64);
        if !bar.is_hidden() {
            bar.set_message(progress_message(p));
        }
    };
    let solution = solve_model(&mission, &options, &mut progress, &AtomicBool::new(false));
    let elapsed_ms = start.elapsed().as_secs_f64() * 1e3;
    bar.finish_and_clear();
    if let Some(path) = &a.plot {
        let result = result_doc(&mission, &options, &solution, elapsed_ms)
            .map_err(|e| CliError(format!("the result read back: {e}")))?;
        super::plot::write_plot(path, &result, &mission.to_value())?;
    }
    // The result goes out as it is serialized: a 10^6-step trajectory never
    // sits in memory as JSON.
    let write = |w: &mut dyn Write| -> std::io::Result<()> {
        let mut w = BufWriter::with_capacity(1 << 16, w);
        write_result(&mut w, &mission, &options, &solution, elapsed_ms)?;
        w.write_all(b"\n")?;
        w.flush()
    };
    match &a.out {
        Some(path) => std::fs::File::create(path)
            .and_then(|mut f| write(&mut f))
            .map_err(|e| CliError(format!("writing {}: {e}", path.display())))?,
        None => write(&mut std::io::stdout().lock())
            .map_err(|e| CliError(format!("writing the result: {e}")))?,
    }
    say!(
        "nvector: {}",
        summary(
            &mission,
            &solution,
            elapsed_ms,
            a.out.as_deref(),
            a.plot.as_deref()
        )
    );
    Ok(())
}

/// The line `run` ends with on stderr: status, the trajectory's max and
/// mean diameter in metres, matched detections, whether the truth (when
/// the mission has one) is inside, the time, and where the result and
/// figure went.
pub fn summary(
    mission: &Mission,
    solution: &Solution,
    elapsed_ms: f64,
    out: Option<&std::path::Path>,
    plot: Option<&std::path::Path>,
) -> String {
    let status = match &solution.status {
        SolveStatus::Consistent => "consistent".to_string(),
        SolveStatus::Infeasible(why) => format!("infeasible ({why})"),
        SolveStatus::Stopped => "stopped before the fixpoint (boxes still sound)".to_string(),
    };
    let (max_d, mean_d) = solution.model.trajectory_diameters();
    let matched: usize = solution.matching.iter().map(Vec::len).sum();
    let mut line = format!(
        "{status}; max trajectory diameter {}, mean {}; {matched} of {} detections matched in {} group{}",
        metres(Some(max_d)),
        metres(Some(mean_d)),
        mission.detections.len(),
        solution.matching.len(),
        if solution.matching.len() == 1 { "" } else { "s" },
    );
    if let Some(t) = solution.outliers {
        line.push_str(&outliers_clause(mission.max_outliers, t));
    }
    let calibration = Calibration::of(&mission.meta);
    if let Some(c) = &calibration {
        line.push_str(&format!("; {}", c.clause()));
    }
    if let Some((inside, errors, _)) = score(mission, solution) {
        let transferred = calibration.as_ref().is_some_and(|c| !c.same_run);
        line.push_str(if inside {
            "; truth inside"
        } else if transferred {
            // Bounds fitted on another run may not hold on this one: a
            // truth outside is then a broken bound, not a wrong proof.
            "; TRUTH OUTSIDE: this run's truth breaks bounds calibrated on another run (nvector check MISSION names the constraints)"
        } else if matches!(solution.status, SolveStatus::Infeasible(_)) {
            // No box holds anything: either the mission's truth breaks
            // one of its own constraints, or the proof is wrong.
            "; TRUTH OUTSIDE: the mission was proved infeasible, so its truth breaks one of its constraints (nvector check MISSION names them; if it names none, this is a soundness bug: please report it)"
        } else {
            "; TRUTH OUTSIDE (a soundness bug: please report it)"
        });
        if errors > 0 {
            line.push_str(&format!(", {errors} matching errors"));
        }
    }
    line.push_str(&format!("; {:.2} s", elapsed_ms / 1e3));
    if let Some(p) = out {
        line.push_str(&format!("; result in {}", p.display()));
    }
    if let Some(p) = plot {
        line.push_str(&format!("; figure in {}", p.display()));
    }
    line
}

/// Where a mission's bounds come from, as its `meta.calibration` says
/// (`{"source": "...", "same_run": bool}`, written by the importers and
/// `nvector calibrate`; docs/formats.md): fitted on this run's own truth
/// (the truth check holds by construction, up to the margins) or
/// calibrated on another run (the truth check is then a test of the
/// calibration, not a guarantee).
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    /// The run (or file) the bounds were fitted on, when named.
    pub source: Option<String>,
    /// Whether that run is this mission's own.
    pub same_run: bool,
}

impl Calibration {
    /// The calibration `meta` states, when it states one (`same_run` a
    /// boolean; anything else is not read).
    pub fn of(meta: &serde_json::Value) -> Option<Calibration> {
        let c = meta.get("calibration")?;
        Some(Calibration {
            source: c.get("source").and_then(|s| s.as_str()).map(str::to_string),
            same_run: c.get("same_run")?.as_bool()?,
        })
    }

    /// The summary's words.
    pub fn clause(&self) -> String {
        match (self.same_run, &self.source) {
            (true, _) => "bounds fitted on this run's truth".into(),
            (false, Some(s)) => {
                format!("bounds calibrated on another run ({s}): truth check not a guarantee")
            }
            (false, None) => "bounds calibrated on another run: truth check not a guarantee".into(),
        }
    }
}

/// What a robust solve proved of the false detections, for the summary:
/// how many are proved false and, while some of `max_outliers` is left
/// unaccounted for, why no group can be reported.
fn outliers_clause(q: usize, t: OutlierTally) -> String {
    let mut s = format!(" (max_outliers {q}: {} proved false", t.proved_false);
    if t.open > 0 {
        s.push_str(&format!(
            ", {} not accounted for, so any detection may be one of them and no group is proved",
            t.open
        ));
    }
    s.push(')');
    s
}

/// The progress line: round, pass, detections processed, detections still
/// moving, and the fall of the max trajectory diameter.
fn progress_message(p: &Progress) -> String {
    let moving = if p.round <= 1 && p.pass != "round" {
        String::new()
    } else {
        format!(", {} of {} detections still moving", p.moving, p.detections)
    };
    let pass = if p.pass == "round" {
        "end".to_string()
    } else {
        format!("{} pass {}/{}", p.pass, p.detections_done, p.detections)
    };
    format!(
        "round {} ({pass}){moving}, max trajectory diameter {} (dead reckoning {})",
        p.round,
        metres(Some(p.max_trajectory_diameter)),
        metres(Some(p.initial_max_trajectory_diameter))
    )
}

#[cfg(test)]
mod tests {
    use super::Calibration;
    use serde_json::json;

    #[test]
    fn the_calibration_is_read_from_meta() {
        let other = json!({"calibration": {"source": "woods t < 630 s", "same_run": false}});
        let c = Calibration::of(&other).unwrap();
        assert_eq!(
            c.clause(),
            "bounds calibrated on another run (woods t < 630 s): truth check not a guarantee"
        );
        let same = json!({"calibration": {"source": "x", "same_run": true}});
        assert_eq!(
            Calibration::of(&same).unwrap().clause(),
            "bounds fitted on this run's truth"
        );
        // Absent, or without a boolean same_run: nothing is said.
        assert_eq!(Calibration::of(&json!({})), None);
        assert_eq!(
            Calibration::of(&json!({"calibration": {"same_run": "no"}})),
            None
        );
    }
}
