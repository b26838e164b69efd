//! Real-data measures of `nvector bench`: `best` on CMU Plaza 1 with the
//! ids hidden (`best_plaza1_hidden`), on the woods scenario of seed 3
//! (`best_woods_seed3`) and, only when `--only` names it (it takes about
//! 100 s: `--only lost_woods`), on UTIAS Lost in the Woods with the ids hidden
//! (`best_lost_woods_hidden`). Each is timed against `none` on the
//! 10^6-step paper mission (seed 5, operator's ids) measured in the same
//! run, the baseline of the goals (ratios 1.2, 3 and 12): the time to the
//! fixpoint (model and propagation; the import, the simulation and the
//! parse are not timed), one run each (the baseline: median of 3). The
//! logs are read from `data/` under the working directory (the
//! repository's root); a line says `skipped` when they are not there.
//! With `--quick` (the baseline on 10^5 steps) they run only when
//! `--only` is given.

use super::bench_slam::{paper_1e6_mission, solve_options};
use super::measure::{median_ms, Bench};
use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::{score, SolveStatus};
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_import::{DataSet, DataSetImport};
use serde_json::{json, Value};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// One real-data line: its name, the goal (ratio to the baseline) and how
/// its mission is made.
struct Real {
    name: &'static str,
    goal: f64,
    mission: fn() -> Result<Value, String>,
}

const REAL: [Real; 3] = [
    Real {
        name: "best_plaza1_hidden",
        goal: 1.2,
        mission: plaza1,
    },
    Real {
        name: "best_woods_seed3",
        goal: 3.0,
        mission: woods_seed3,
    },
    Real {
        name: "best_lost_woods_hidden",
        goal: 12.0,
        mission: lost_woods,
    },
];

/// The name of the measure that runs only when `--only` names it.
const ON_REQUEST: &str = "best_lost_woods_hidden";

fn data(dir: &str) -> Result<&Path, String> {
    let p = Path::new(dir);
    if p.is_dir() {
        Ok(p)
    } else {
        Err(format!(
            "{dir} not found (run `nvector bench` from the repository's root)"
        ))
    }
}

/// A data set as `nvector import` converts it (ids hidden).
fn data_set(which: DataSet, dir: &str) -> Result<Value, String> {
    nvector_import::import_dataset(which, data(dir)?, &DataSetImport::default())
        .map_err(|e| e.to_string())
}

fn plaza1() -> Result<Value, String> {
    data_set(DataSet::CmuPlaza, "data/cmu-plaza1")
}

fn woods_seed3() -> Result<Value, String> {
    Ok(simulate(&SimulateOptions::new(Scenario::Woods, 3)))
}

fn lost_woods() -> Result<Value, String> {
    data_set(DataSet::UtiasWoods, "data/utias-lost-in-the-woods")
}

/// Runs the real-data measures (module doc).
pub fn run(b: &mut Bench) {
    let wanted: Vec<(&Real, String)> = REAL
        .iter()
        .filter_map(|r| {
            let name = b.wanted(r.name)?;
            // The missions are real, so `--quick` has no smaller size:
            // there they run only when `--only` names them.
            let asked = if r.name == ON_REQUEST {
                b.only.is_some_and(|o| o.contains("lost_woods"))
            } else {
                !b.quick || b.only.is_some()
            };
            asked.then_some((r, name))
        })
        .collect();
    if wanted.is_empty() {
        return;
    }
    let steps = if b.quick { 100_000 } else { 1_000_000 };
    let base_mission = paper_1e6_mission(steps, true);
    let none = solve_options(Association::None);
    let base = median_ms(
        3,
        || (),
        |_| solve_model(&base_mission, &none, &mut |_| {}, &AtomicBool::new(false)),
    );
    drop(base_mission);
    let baseline = format!("none_paper_{steps}_operator");
    for (real, name) in wanted {
        let line = match (real.mission)().and_then(|v| {
            Mission::from_value(&v).map_err(|e| format!("the mission is invalid: {e}"))
        }) {
            Ok(m) => measure(&m, &name, (real.goal, b.threads), (&baseline, base)),
            Err(e) => json!({"name": name, "skipped": e}),
        };
        b.emit(line);
    }
}

/// `best` on `m` with `threads`, timed once, against the baseline `(name,
/// ms)`.
fn measure(
    m: &Mission,
    name: &str,
    (goal, threads): (f64, usize),
    (baseline, base): (&str, f64),
) -> Value {
    let options = SolveOptions {
        threads,
        ..solve_options(Association::NVector(Contractor::Best))
    };
    let t = Instant::now();
    let s = solve_model(m, &options, &mut |_| {}, &AtomicBool::new(false));
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let scored = score(m, &s);
    json!({
        "name": name, "ms": ms, "baseline": baseline, "baseline_ms": base,
        "ratio": ms / base, "goal": goal, "threads": threads, "steps": m.steps,
        "detections": m.detections.len(), "rounds": s.rounds,
        "consistent": s.status == SolveStatus::Consistent,
        "truth_inside": scored.map(|x| x.0), "matching_errors": scored.map(|x| x.1),
        "matching_recall": scored.map(|x| x.2), "groups": s.matching.len(),
        "max_trajectory_diameter": s.model.max_trajectory_diameter(),
    })
}
