//! The propagator by passes (`propagate`: a forward and a backward pass per round,
//! sweeping only what changed) against the one before it (each detection
//! swept on its own), kept as a reference in `propagation_reference/`: on
//! random simulated missions (paper and AUV scenarios, landmark layouts,
//! with and without the operator's matching, every association mode) both
//! end with the same status and the same matching, the truth lies in every
//! new box, and each new box lies in the reference's box up to a slack of
//! the order of the tolerance (bounds that a sweep stopping below the
//! tolerance leaves behind), and the other way round: the same fixpoint.
//! `best` has gained contractors since (the detection shapes):
//! there the new boxes lie in the old ones and the old groups in new ones.

use crate::propagation_reference;

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagate::fixpoint::propagate;
use nvector_core::slam::result::{score, Solution, SolveStatus};
use nvector_core::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::Interval;
use propagation_reference::reference_solve;
use std::sync::atomic::AtomicBool;

const MODES: [Association; 5] = [
    Association::None,
    Association::NVector(Contractor::Nvalue),
    Association::NVector(Contractor::Projection),
    Association::NVector(Contractor::Independent),
    Association::NVector(Contractor::Best),
];

/// Missions per test (fixed seeds): 24, or `PROPTEST_CASES` / 40 (at
/// least 8) for a longer run.
fn cases() -> u64 {
    ["PROPTEST_CASES", "NVECTOR_PROPTEST_CASES"]
        .iter()
        .find_map(|k| std::env::var(k).ok()?.parse::<u64>().ok())
        .map_or(24, |c| (c / 40).max(8))
}

/// How far `a` sticks out of `b` (0 when inside; +inf when `b` is empty and
/// `a` is not, or when an infinite bound of `a` meets a finite one of `b`).
fn outside(a: Interval, b: Interval) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    if b.is_empty() {
        return f64::INFINITY;
    }
    let lo = b.lo() - a.lo();
    let hi = a.hi() - b.hi();
    let lo = if lo.is_nan() { 0.0 } else { lo };
    let hi = if hi.is_nan() { 0.0 } else { hi };
    lo.max(hi).max(0.0)
}

/// The largest amount by which a box of `a` sticks out of the matching box
/// of `b` (positions and detections).
fn stick_out(a: &Solution, b: &Solution) -> f64 {
    let pos = a
        .model
        .pos
        .iter()
        .zip(&b.model.pos)
        .map(|(&x, &y)| outside(x, y));
    let det = a
        .model
        .det
        .iter()
        .zip(&b.model.det)
        .flat_map(|(x, y)| (0..x.dim()).map(move |i| outside(x[i], y[i])));
    pos.chain(det).fold(0.0, f64::max)
}

fn same_status(a: &SolveStatus, b: &SolveStatus) -> bool {
    matches!(
        (a, b),
        (SolveStatus::Consistent, SolveStatus::Consistent)
            | (SolveStatus::Stopped, SolveStatus::Stopped)
            | (SolveStatus::Infeasible(_), SolveStatus::Infeasible(_))
    )
}

/// Whether the association step of `propagate` is the reference's for
/// `association`: `best` gained the detection shapes (a
/// stronger contractor), where the new boxes may only be tighter and the
/// groups only larger.
fn same_association(association: Association) -> bool {
    association != Association::NVector(Contractor::Best)
}

/// Whether every group of `old` lies in one group of `new`.
fn refines(new: &[Vec<usize>], old: &[Vec<usize>]) -> bool {
    old.iter()
        .all(|g| new.iter().any(|h| g.iter().all(|j| h.contains(j))))
}

/// Runs both propagators on `mission` with every mode; returns the largest
/// stick-out seen in either direction (only new out of old for `best`).
fn compare(mission: &Mission, what: &str, slack: f64, stats: &mut Stats) -> f64 {
    let mut worst = 0.0f64;
    for association in MODES {
        let same = same_association(association);
        let options = SolveOptions {
            association,
            ..SolveOptions::default()
        };
        let cancel = AtomicBool::new(false);
        let new = propagate(mission, &options, &mut |_| {}, &cancel);
        let old = reference_solve(mission, &options, &cancel);
        let name = association.name();
        assert!(
            same_status(&new.status, &old.status),
            "{what} {name}: {:?} against {:?}",
            new.status,
            old.status
        );
        if same {
            assert_eq!(new.matching, old.matching, "{what} {name}: matching");
        } else {
            assert!(
                refines(&new.matching, &old.matching),
                "{what} {name}: a group was lost"
            );
        }
        if new.status != SolveStatus::Consistent {
            continue;
        }
        let (inside, errors, _) = score(mission, &new).expect("simulated missions have truth");
        assert!(inside, "{what} {name}: the truth is outside a new box");
        assert_eq!(errors, 0, "{what} {name}: matching errors");
        let out = stick_out(&new, &old);
        let back = if same { stick_out(&old, &new) } else { 0.0 };
        assert!(
            out <= slack,
            "{what} {name}: a new box sticks out of the old one by {out}"
        );
        assert!(
            back <= slack,
            "{what} {name}: an old box sticks out of the new one by {back}"
        );
        worst = worst.max(out).max(back);
        stats.runs += 1;
        stats.identical +=
            usize::from(new.model.pos == old.model.pos && new.model.det == old.model.det);
        stats.rounds += (new.rounds, old.rounds);
        stats.contractions += (new.contractions, old.contractions);
    }
    worst
}

/// What the comparisons saw (printed with `--nocapture`).
#[derive(Default)]
struct Stats {
    runs: usize,
    identical: usize,
    rounds: Pair,
    contractions: Pair,
}

#[derive(Default, Debug)]
struct Pair(u64, u64);

impl<A: Into<u64>, B: Into<u64>> std::ops::AddAssign<(A, B)> for Pair {
    fn add_assign(&mut self, (a, b): (A, B)) {
        self.0 += a.into();
        self.1 += b.into();
    }
}

impl Stats {
    fn print(&self, what: &str, worst: f64) {
        eprintln!(
            "{what}: {} consistent runs, {} with bit-identical boxes, largest difference {worst:e}; rounds new/old {:?}, contractions new/old {:?}",
            self.runs, self.identical, self.rounds, self.contractions
        );
    }
}

/// Bounds of width up to about 100 m, tolerance 1e-9: a sweep that stops
/// leaves each bound at most the tolerance short of its fixpoint, and the
/// detection contractors can carry such a gap over a few rounds.
const SLACK: f64 = 1e-6;

#[test]
fn paper_missions_reach_the_same_fixpoint() {
    let (mut worst, mut stats) = (0.0f64, Stats::default());
    for seed in 0..cases() {
        let mut o = SimulateOptions::new(Scenario::Paper, 100 + seed);
        o.steps = Some(300 + (seed as usize * 2977) % 11_700);
        o.landmarks = Some(1 + (seed as usize) % 5);
        o.noise = 0.5 + (seed % 5) as f64 * 0.5;
        o.operator = seed % 2 == 0;
        o.layout = [Layout::Line, Layout::Ring, Layout::Random][(seed % 3) as usize];
        o.range_only = seed % 4 == 3;
        let mission = Mission::from_value(&simulate(&o)).expect("valid");
        let what = format!("paper seed {}", 100 + seed);
        worst = worst.max(compare(&mission, &what, SLACK, &mut stats));
    }
    stats.print("paper", worst);
}

#[test]
fn auv_missions_reach_the_same_fixpoint() {
    let (mut worst, mut stats) = (0.0f64, Stats::default());
    for seed in 0..cases().div_ceil(4) {
        let mut o = SimulateOptions::new(Scenario::Auv, 200 + seed);
        o.steps = Some(10_000 + (seed as usize * 7919) % 20_000);
        o.operator = seed % 2 == 1;
        let mission = Mission::from_value(&simulate(&o)).expect("valid");
        let what = format!("auv seed {}", 200 + seed);
        worst = worst.max(compare(&mission, &what, SLACK, &mut stats));
    }
    stats.print("auv", worst);
}

/// Missions made infeasible (a wrong operator matching, or a range no
/// landmark can meet) are proved infeasible by both.
#[test]
fn infeasible_missions_stay_infeasible() {
    let mut infeasible = 0;
    for seed in 0..cases() {
        let mut o = SimulateOptions::new(Scenario::Paper, 300 + seed);
        o.steps = Some(1500);
        o.operator = true;
        let mut v = simulate(&o);
        let dets = v["detections"].as_array_mut().unwrap();
        let j = (seed as usize * 7) % dets.len();
        if seed % 2 == 0 {
            // A landmark id that is not the detection's.
            let l = dets[j]["landmark"].as_u64().unwrap();
            dets[j]["landmark"] = serde_json::json!((l + 1) % 4);
        } else {
            dets[j]["range"] = serde_json::json!([500.0, 501.0]);
        }
        v["landmark_count"] = serde_json::json!(4);
        let mission = Mission::from_value(&v).expect("valid");
        for association in MODES {
            let options = SolveOptions {
                association,
                ..SolveOptions::default()
            };
            let cancel = AtomicBool::new(false);
            let new = propagate(&mission, &options, &mut |_| {}, &cancel);
            let old = reference_solve(&mission, &options, &cancel);
            assert!(
                same_status(&new.status, &old.status),
                "seed {} {}: {:?} against {:?}",
                300 + seed,
                association.name(),
                new.status,
                old.status
            );
            infeasible += usize::from(matches!(new.status, SolveStatus::Infeasible(_)));
        }
    }
    assert!(
        infeasible as u64 >= cases() * MODES.len() as u64 / 2,
        "only {infeasible} infeasible runs: the edits should break most missions"
    );
}
