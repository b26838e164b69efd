//! The headings in the robust rounds (`max_outliers` = q > 0) of an
//! odometry2d mission: q-relaxed evidence passes over th(0..=N), the drift
//! windows, then the displacements and `heading_at` from the new headings.
//!
//! Also [`cut_headings`]: the headings cut to an enclosure of every
//! reading's (consensus over subsets' hull, [`crate::slam::robust::subsets`]),
//! with the same refresh.
//!
//! # Constraint
//!
//! The solution set is the union, over every set F of at most q dropped
//! detections, of the solutions of the mission without F
//! ([`crate::slam::robust`]). The heading chain `th(t+1) = th(t) + Δth(t)`
//! (`Δth(t) = dt·ω(t) + [-f(t), f(t)]`, [`OdometryChain::heading_increment`]),
//! the `heading_drift` windows, `initial_heading` and `final_heading` hold
//! in every sub-mission. A detection j with a bearing β(j) holds only where
//! j is kept: there the direction of d(j) - p(t_j) is th(t_j) + β(j),
//! modulo 2π (the robust engine reads detections seen from p, the sensor
//! offset folded in: `Mission::seen_from_p`). Headings are real
//! numbers, never wrapped.
//!
//! # Math
//!
//! 1. **Evidence.** For each detection j not proved false, with a bearing
//!    and an evidence box M(j) of p(t_j) ([`crate::slam::robust`]: p(t_j)
//!    contracted, on a copy, by j's range and bearing towards d(j), its own
//!    box cut by its group's q-relaxed landmark box), the interval
//!    `E(j) = th(t_j) ∩ (angle(d(j) - M(j)) - β(j) + 2πZ)`
//!    ([`contract_heading`]; the current th(t_j) when the box d(j) - M(j)
//!    holds the origin). In a sub-mission keeping j, p(t_j) ∈ M(j),
//!    d(j) lies in j's box, so th(t_j) ∈ E(j). An empty E(j) gives no
//!    evidence (sound: one vote less).
//! 2. **Relaxed passes.** Along the heading chain, for t >= t_j,
//!    `th(t) >= E(j).lo + Σ_{s=t_j}^{t-1} Δth(s).lo` in a sub-mission
//!    keeping j (and the mirror bounds, and backward). A sub-mission drops
//!    at most `budget` (q minus the detections proved false) of the listed
//!    evidences, so th(t) is at least the (budget+1)-th largest of the
//!    carried lower bounds, at most the (budget+1)-th smallest upper bound.
//!    These are the positions' passes ([`crate::slam::robust`], `relaxed_passes`)
//!    on a chain of dimension 1: keys relative to running sums of the
//!    turn bounds, the (budget+1) best kept in a sorted list, the forward
//!    keys recorded and merged by the backward pass; an unbounded turn
//!    voids the evidence behind it.
//! 3. **Drift.** The `heading_drift` windows hold in every sub-mission:
//!    [`OdometryChain::drift_flat`] (the windows over th, then the chain
//!    over (p, th) from every heading they moved).
//! 4. **Refresh.** `D(t) = dt·v(t)·(cos th(t), sin th(t)) + E(t)` and
//!    `heading_at[j] = th(t_j)` from the new headings
//!    ([`Model::refresh_displacements`], [`Model::refresh_headings_at`]),
//!    so the position passes that follow, and the next round's evidence
//!    (the bearing constraint under `heading_at`), use them.
//!
//! # Soundness
//!
//! Every interval computed encloses th(t) in every sub-mission with at
//! most q dropped detections: E(j) is computed from enclosures (the current
//! th, M(j), d(j)) by [`contract_heading`], which keeps every real heading
//! congruent modulo 2π to a direction of the box (outward rounded, any
//! magnitude: bounds beyond 1e12 are left alone); the passes keep the
//! (budget+1)-th best bound, and a sub-mission keeps at least one of any
//! budget+1 listed evidences, whose carried bound holds (sums through
//! outward-rounded interval additions, as for the positions); the chain,
//! the windows and the refresh are contractors of constraints that hold in
//! every sub-mission. Keeping the budget-th best instead would let
//! `budget` false bearings agreeing on a wrong heading cut the true one
//! (core/tests/slam/robust/heading.rs shows it).
//!
//! # Complexity
//!
//! Per round: O(k) for the evidence, O(N + k log q) for the two passes
//! (O(1) per step, a sorted insertion of O(log q) per detection, the
//! backward merge O(q) per step only where keys changed, as the positions'),
//! O(N·W) for the W drift windows and O(N) for the refresh. Memory O(N + k)
//! beyond the recorded key snapshots of the passes.

use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::odometry::angle::contract_heading;
use crate::odometry::angle::heading_moved;
use crate::odometry::chain::OdometryChain;
use crate::slam::mission::Mission;
use crate::slam::model::Model;

/// The relaxed passes of [`crate::slam::robust`] on a chain of dimension 1:
/// `(states th(0..=N), increments Δth(0..N), evidence E(j) per detection
/// (one-axis boxes, empty: none), keep)`, keeping the `keep`-th best
/// carried bound; the largest move, or `Err(step)` when a state empties.
/// (A callback, so that this file does not import the propagation that
/// calls it.)
pub type RelaxedPasses<'a> =
    dyn FnMut(&mut [Interval], &[Interval], Vec<IntervalBox>, usize) -> Result<f64, usize> + 'a;

/// The heading evidence E(j) of every detection (module doc, step 1):
/// one-axis boxes, empty where j gives none (proved false: an empty
/// evidence box of p).
fn heading_evidence(
    mission: &Mission,
    model: &Model,
    evidence: &[IntervalBox],
) -> Vec<IntervalBox> {
    let n = model.steps;
    let none = IntervalBox::empty(1);
    mission
        .detections
        .iter()
        .enumerate()
        .map(|(j, det)| {
            let (m, d) = (&evidence[j], &model.det[j]);
            let Some(beta) = det.bearing else {
                return none.clone();
            };
            if m.is_empty() || d.is_empty() || beta.is_empty() {
                return none.clone();
            }
            let th = model.heading[det.step.min(n)];
            let e = contract_heading(th, d[0] - m[0], d[1] - m[1], beta);
            if e.is_empty() {
                none.clone()
            } else {
                IntervalBox::new(&[e])
            }
        })
        .collect()
}

/// The headings of an odometry2d mission in a robust round (see the
/// module doc), `budget` the drops left (q minus the detections proved
/// false), `evidence` the round's evidence boxes of p(t_j) (empty for the
/// detections proved false), `passes` the relaxed passes. Returns the
/// largest move of a heading (0 for the other models); `Err`: a heading
/// became empty (the mission is infeasible).
pub fn robust_heading(
    mission: &Mission,
    model: &mut Model,
    evidence: &[IntervalBox],
    budget: usize,
    passes: &mut RelaxedPasses,
) -> Result<f64, String> {
    let Some(chain) = model.odometry.take() else {
        return Ok(0.0);
    };
    let result = headings(mission, model, &chain, evidence, budget, passes);
    model.odometry = Some(chain);
    let moved = result?;
    model.refresh_displacements();
    model.refresh_headings_at(mission);
    Ok(moved)
}

/// Steps 1-3 of the module doc on `model.heading`, `chain` the model's
/// odometry chain (taken out of the model for the borrow).
fn headings(
    mission: &Mission,
    model: &mut Model,
    chain: &OdometryChain,
    evidence: &[IntervalBox],
    budget: usize,
    passes: &mut RelaxedPasses,
) -> Result<f64, String> {
    let n = model.steps;
    if model.heading.len() != n + 1 || chain.steps() != n || evidence.len() != model.det.len() {
        return Ok(0.0);
    }
    let before = model.heading.clone();
    let boxes = heading_evidence(mission, model, evidence);
    let turns: Vec<Interval> = (0..n).map(|i| chain.heading_increment(i)).collect();
    let q = model.max_outliers;
    // The (budget+1)-th best: a sub-mission drops at most `budget`.
    passes(&mut model.heading, &turns, boxes, budget + 1).map_err(|t| {
        format!("the heading of step {t} is empty: no choice of at most {q} false detections is consistent")
    })?;
    chain
        .drift_flat(&mut model.pos, &mut model.heading, 0.0)
        .map_err(|e| {
            format!(
                "heading_drift: the heading or position of step {} is empty: no choice of at most {q} false detections is consistent",
                e.step
            )
        })?;
    let moved = before
        .iter()
        .zip(&model.heading)
        .map(|(a, b)| heading_moved(*a, *b))
        .fold(0.0, f64::max);
    Ok(moved)
}

/// odometry2d: th(0..=N) cut to `headings` (N + 1 intervals enclosing
/// every heading of every reading: consensus over subsets'
/// hull, [`crate::slam::robust::subsets`]), then the displacements and
/// `heading_at` from them. Returns how many headings changed; `Err`: one
/// became empty. Nothing for the other models (or another length). O(N).
pub fn cut_headings(
    mission: &Mission,
    model: &mut Model,
    headings: &[Interval],
) -> Result<usize, String> {
    if model.odometry.is_none() || headings.len() != model.heading.len() {
        return Ok(0);
    }
    let mut changed = 0;
    for (t, (h, cut)) in model.heading.iter_mut().zip(headings).enumerate() {
        let new = h.intersect(*cut);
        if new.is_empty() {
            return Err(format!(
                "the heading of step {t} is empty: no choice of at most {} false detections is consistent",
                model.max_outliers
            ));
        }
        changed += usize::from(new != *h);
        *h = new;
    }
    model.refresh_displacements();
    model.refresh_headings_at(mission);
    Ok(changed)
}
