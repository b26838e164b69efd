//! `SolveOptions::threads`: the independent work of a shapes round (the
//! registrations, the local frames' pieces and their tests,
//! `nvector_core::par`) split over threads gives the same result bits with
//! 1, 2 and 16 threads: every position and detection box, the groups, the
//! rounds, the contraction count and the status. The missions are small
//! ones on which `best` registers at several steps and rebuilds several
//! groups' pieces in one round (the paper scenario, range only, ids
//! hidden; the woods scenario, odometry2d), so that the threads have work
//! to share. The bits are checked against one thread (the plain loop), an
//! independent reference: the threads only decide which core computes
//! what.

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::Solution;
use nvector_core::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};
use nvector_core::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, SolveOptions};
use std::sync::atomic::AtomicBool;

/// Everything a solve gives, as bits.
fn bits(s: &Solution) -> (String, Vec<Vec<usize>>, u32, u64, Vec<u64>) {
    let intervals = s
        .model
        .pos
        .iter()
        .chain(s.model.det.iter().flat_map(|b| b.axes().iter()))
        .flat_map(|x| [x.lo().to_bits(), x.hi().to_bits()])
        .collect();
    (
        format!("{:?}", s.status),
        s.matching.clone(),
        s.rounds,
        s.contractions,
        intervals,
    )
}

fn solve(m: &Mission, threads: usize) -> Solution {
    let options = SolveOptions {
        association: Association::NVector(Contractor::Best),
        threads,
        ..SolveOptions::default()
    };
    solve_model(m, &options, &mut |_| {}, &AtomicBool::new(false))
}

fn same_bits_for_any_thread_count(m: &Mission, what: &str) {
    let one = solve(m, 1);
    assert!(!one.matching.is_empty(), "{what}: no group proved");
    let want = bits(&one);
    for threads in [2, 16] {
        assert!(
            bits(&solve(m, threads)) == want,
            "{what}: {threads} threads give other bits than one"
        );
    }
}

#[test]
fn the_paper_scenario_gives_the_same_bits_with_1_2_and_16_threads() {
    for seed in [3, 4] {
        let mut o = SimulateOptions::new(Scenario::Paper, seed);
        o.steps = Some(2000);
        o.layout = Layout::Random;
        o.range_only = true;
        let m = Mission::from_value(&simulate(&o)).expect("a simulated mission is valid");
        same_bits_for_any_thread_count(&m, &format!("paper seed {seed}, range only"));
    }
}

#[test]
fn the_woods_scenario_gives_the_same_bits_with_1_2_and_16_threads() {
    let m = simulate_woods(&WoodsOptions {
        seed: 3,
        steps: Some(300),
        landmarks: None,
        operator: false,
    });
    let m = Mission::from_value(&m).expect("a simulated mission is valid");
    same_bits_for_any_thread_count(&m, "woods seed 3, 300 steps");
}
