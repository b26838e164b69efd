//! `nvector bench`: the performance table of BENCHMARKS.md, one JSON line
//! per measure (docs/formats.md, "Benchmark lines"). Each measure is the
//! median of repeated runs; a baseline, when given, is timed in alternation
//! with the measure in the same run, and the ratio is the median of the
//! per-pair ratios, so that it depends neither on the machine nor on its
//! momentary load.

use super::measure::{median_ms, paired_ms, Bench};
use crate::CliError;
use nvector_core::nvector::nvalue::{atmost_nvalue, NValueScratch};
use nvector_core::nvector::{atmost_nvector, Contractor};
use nvector_core::slam::simulate::Rng;
use nvector_core::{Interval, IntervalBox};
use serde_json::{json, Value};

fn line(name: &str, ms: f64, baseline: Option<(&str, f64, f64)>, goal: Option<f64>) -> Value {
    let mut v = json!({"name": name, "ms": round3(ms)});
    if let Some((b, bms, ratio)) = baseline {
        v["baseline"] = json!(b);
        v["baseline_ms"] = json!(round3(bms));
        v["ratio"] = json!(round3(ratio));
    }
    if let Some(g) = goal {
        v["goal"] = json!(g);
    }
    v
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn sort_data(rng: &mut Rng, k: usize) -> Vec<f64> {
    (0..k).map(|_| rng.range(-1e3, 1e3)).collect()
}

fn sort_f64(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_unstable_by(|a, b| a.total_cmp(b));
    v
}

/// `k` intervals in `n` clusters: every interval of cluster j holds the
/// cluster's centre, clusters are apart, so exactly n values are needed and
/// the kernel pass (not the early exit) is measured.
fn clustered_intervals(rng: &mut Rng, k: usize, n: usize) -> Vec<Interval> {
    (0..k)
        .map(|_| {
            let j = (rng.next_u64() % n as u64) as f64;
            let c = j * 10.0;
            Interval::new(c - rng.range(0.0, 4.0), c + rng.range(0.0, 4.0))
        })
        .collect()
}

/// `k` boxes of dimension `d` in `n` clusters (paper-like: detections of n
/// landmarks with position uncertainty), centres on a jittered grid.
pub fn clustered_boxes(
    rng: &mut Rng,
    k: usize,
    n: usize,
    d: usize,
    spread: f64,
) -> Vec<IntervalBox> {
    let centres: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            (0..d)
                .map(|a| {
                    (j as f64) * 10.0
                        + if a % 2 == 1 {
                            rng.range(-3.0, 3.0)
                        } else {
                            0.0
                        }
                })
                .collect()
        })
        .collect();
    (0..k)
        .map(|_| {
            let c = &centres[(rng.next_u64() % n as u64) as usize];
            let axes: Vec<Interval> = c
                .iter()
                .map(|&x| Interval::new(x - rng.range(0.0, spread), x + rng.range(0.0, spread)))
                .collect();
            IntervalBox::new(&axes)
        })
        .collect()
}

/// The measures of the table, by name (without the `_quick` suffix).
pub const MEASURES: [&str; 13] = [
    "nvalue_1e6",
    "nvector_projection_1e5_3d",
    "nvector_independent_1e4_2d",
    "exact_max_k_1s",
    "sweep_1e6_2d",
    "paper_fixpoint",
    "auv_60k_total",
    "propagate_1e6",
    "best_1e6",
    "paper_seeds_1_10",
    "best_plaza1_hidden",
    "best_woods_seed3",
    "best_lost_woods_hidden",
];

/// Whether a line meets its goal, and the goal in words: `ratio <= goal`
/// (`goal` with a `ratio`), `ms <= goal_ms`, `ratio <= goal_ratio`,
/// `ms <= aim_ms`, and for `paper_seeds_*` the median ratio basic /
/// projection `>= goal`. `None` when the line has no goal.
pub fn judge(v: &Value) -> Option<(bool, String)> {
    let f = |k: &str| v[k].as_f64();
    let name = v["name"].as_str().unwrap_or("");
    let mut met = true;
    let mut words = Vec::new();
    let mut check = |ok: bool, text: String| {
        met &= ok;
        words.push(text);
    };
    if name.starts_with("paper_seeds") {
        if let (Some(g), Some(r)) = (f("goal"), f("median_ratio_basic_over_projection")) {
            check(
                r >= g,
                format!("median ratio basic / projection {r:.2} >= {g}"),
            );
        }
    } else if let (Some(g), Some(r)) = (f("goal"), f("ratio")) {
        check(r <= g, format!("ratio {r:.2} <= {g}"));
    }
    if let (Some(g), Some(r)) = (f("goal_ratio"), f("ratio")) {
        check(r <= g, format!("ratio {r:.2} <= {g}"));
    }
    if let (Some(g), Some(ms)) = (f("goal_ms"), f("ms")) {
        check(ms <= g, format!("{ms:.1} ms <= {g} ms"));
    }
    if let (Some(g), Some(ms)) = (f("aim_ms"), f("ms")) {
        check(ms <= g, format!("{ms:.1} ms <= {g} ms (aim)"));
    }
    (!words.is_empty()).then(|| (met, words.join(", ")))
}

/// Adds `meets_goal` to a line that has a goal and says on stderr how the
/// line stands against it.
fn mark(mut v: Value, quick: bool) -> Value {
    let name = v["name"].as_str().unwrap_or("?").to_string();
    match judge(&v) {
        Some((met, words)) => {
            v["meets_goal"] = json!(met);
            let quick = if quick {
                " (quick sizes: the goal is set for the full ones)"
            } else {
                ""
            };
            let verdict = if met { "goal met" } else { "GOAL MISSED" };
            say!("{name}: {verdict}: {words}{quick}");
        }
        None => say!("{name}: no goal"),
    }
    v
}

/// Refuses an `--only` that no measure's name contains: exit 2 (usage),
/// naming the measures.
fn check_only(only: Option<&str>, suffix: &str) {
    if let Some(o) = only {
        let known = MEASURES.iter().any(|m| format!("{m}{suffix}").contains(o));
        if !known {
            say!(
                "nvector: bench --only '{o}' names no measure{}; the measures are: {}",
                if suffix.is_empty() { "" } else { " of --quick" },
                MEASURES.map(|m| format!("{m}{suffix}")).join(", ")
            );
            std::process::exit(2);
        }
    }
}

fn nvalue_1e6(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("nvalue_1e6") else {
        return;
    };
    let k = if b.quick { 100_000 } else { 1_000_000 };
    // Each measure draws from its own stream: `--only` sees the same data.
    let mut rng = Rng::from_state(2009);
    let data = sort_data(&mut rng, k);
    let domains = clustered_intervals(&mut rng, k, 1000);
    let mut scratch = NValueScratch::default();
    let (base, ms, ratio) = paired_ms(
        runs,
        || data.clone(),
        sort_f64,
        || domains.clone(),
        |mut d| atmost_nvalue(1000, &mut d, &mut scratch),
    );
    let baseline = format!("sort_f64_1e6{}", b.suffix);
    b.emit(line(&name, ms, Some((&baseline, base, ratio)), Some(2.5)));
}

fn nvector_projection_1e5_3d(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("nvector_projection_1e5_3d") else {
        return;
    };
    let k = if b.quick { 10_000 } else { 100_000 };
    // Each measure draws from its own stream: `--only` sees the same data.
    let mut rng = Rng::from_state(2009);
    let data = sort_data(&mut rng, k);
    let boxes = clustered_boxes(&mut rng, k, 100, 3, 4.0);
    let (base, ms, ratio) = paired_ms(
        runs,
        || data.clone(),
        sort_f64,
        || boxes.clone(),
        |mut bx| atmost_nvector(100, &mut bx, Contractor::Projection),
    );
    let baseline = format!("sort_f64_1e5{}", b.suffix);
    b.emit(line(&name, ms, Some((&baseline, base, ratio)), Some(10.0)));
}

fn nvector_independent_1e4_2d(b: &mut Bench, runs: usize) {
    let Some(name) = b.wanted("nvector_independent_1e4_2d") else {
        return;
    };
    let k = if b.quick { 1_000 } else { 10_000 };
    // Each measure draws from its own stream: `--only` sees the same data.
    let mut rng = Rng::from_state(2009);
    let boxes = clustered_boxes(&mut rng, k, 50, 2, 4.0);
    let ms = median_ms(
        runs,
        || boxes.clone(),
        |mut bx| atmost_nvector(50, &mut bx, Contractor::Independent),
    );
    let mut v = line(&name, ms, None, None);
    v["aim_ms"] = json!(50);
    b.emit(v);
}

fn exact_max_k_1s(b: &mut Bench) {
    let Some(name) = b.wanted("exact_max_k_1s") else {
        return;
    };
    // Paper-like: 4 landmarks, k detections with overlapping boxes in 2-D.
    let limit_ms = if b.quick { 100.0 } else { 1000.0 };
    let mut best = 0usize;
    let mut best_ms = 0.0;
    let mut rng = Rng::from_state(2009);
    for k in (4..=40).step_by(4) {
        let boxes = clustered_boxes(&mut rng, k, 4, 2, 6.0);
        let ms = median_ms(
            3,
            || boxes.clone(),
            |mut bx| atmost_nvector(4, &mut bx, Contractor::Exact),
        );
        if ms < limit_ms {
            best = k;
            best_ms = ms;
        } else {
            break;
        }
    }
    let mut v = line(&name, best_ms, None, None);
    v["k"] = json!(best);
    v["limit_ms"] = json!(limit_ms);
    b.emit(v);
}

/// Runs the benchmarks; `threads`: those of the real-data lines.
pub fn run(quick: bool, only: Option<&str>, threads: usize) -> Result<(), CliError> {
    let suffix = if quick { "_quick" } else { "" };
    check_only(only, suffix);
    let mut print = |v: Value| {
        use std::io::Write as _;
        // A closed standard output loses the line, it does not panic.
        let _ = writeln!(std::io::stdout(), "{}", mark(v, quick));
    };
    let mut b = Bench {
        quick,
        suffix,
        only,
        threads,
        emit: &mut print,
    };
    let runs = if quick { 3 } else { 7 };
    nvalue_1e6(&mut b, runs);
    nvector_projection_1e5_3d(&mut b, runs);
    nvector_independent_1e4_2d(&mut b, runs);
    exact_max_k_1s(&mut b);
    super::bench_slam::run(&mut b);
    super::bench_real::run(&mut b);
    Ok(())
}
