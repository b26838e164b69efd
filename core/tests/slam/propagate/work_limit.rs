//! A contractor that runs out of work is no proof: `exact` past its work
//! budget (more than 40 detections) must leave the mission consistent, with
//! the truth inside, not "infeasible" (the propagator once read every error
//! of atmost_nvector as infeasibility).

use nvector_core::nvector::Contractor;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::SolveStatus;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, SolveOptions};
use std::sync::atomic::AtomicBool;

#[test]
fn exact_out_of_budget_proves_nothing() {
    let mut o = SimulateOptions::new(Scenario::Paper, 4);
    o.steps = Some(12_000);
    let m = Mission::from_value(&simulate(&o)).expect("valid");
    assert!(m.detections.len() > 40, "{} detections", m.detections.len());
    let exact = SolveOptions {
        association: Association::NVector(Contractor::Exact),
        ..SolveOptions::default()
    };
    let none = SolveOptions {
        association: Association::None,
        ..SolveOptions::default()
    };
    let s = solve_model(&m, &exact, &mut |_| {}, &AtomicBool::new(false));
    assert_eq!(s.status, SolveStatus::Consistent, "{:?}", s.status);
    let base = solve_model(&m, &none, &mut |_| {}, &AtomicBool::new(false));
    // What `exact` could not do it did not pretend to: the positions are
    // those of the basic model or tighter, and each holds the truth.
    let truth = m.truth.as_ref().expect("simulated truth");
    let dim = s.model.dim;
    for (i, t) in truth.positions.iter().enumerate() {
        for (a, &x) in t.iter().enumerate() {
            let (p, b) = (s.model.pos[i * dim + a], base.model.pos[i * dim + a]);
            assert!(p.contains(x), "truth lost at step {i}, axis {a}");
            assert!(p.is_subset(b), "step {i}: wider than the basic model");
        }
    }
}
