//! The propagator before the passes (each detection that moves its position
//! swept forward and backward on its own, O(N·k) per round), kept verbatim
//! as the reference the new propagator is compared with. Progress reports
//! are left out; nothing else changed.

use nvector_core::contractors::bearing::contract_bearing;
use nvector_core::contractors::distance::contract_distance;
use nvector_core::contractors::motion_chain::{shrinkage, sweep_backward, sweep_forward, Sweep};
use nvector_core::nvector::{atmost_nvector, Status};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::model::Model;
use nvector_core::slam::result::{Solution, SolveStatus};
use nvector_core::slam::types::{Association, SolveOptions};
use nvector_core::Interval;
use std::sync::atomic::{AtomicBool, Ordering};

/// Union-find over detections (proved same landmark).
struct Matching {
    parent: Vec<usize>,
}

impl Matching {
    fn find(&mut self, i: usize) -> usize {
        let mut r = i;
        while self.parent[r] != r {
            r = self.parent[r];
        }
        self.parent[i] = r;
        r
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }

    /// Groups of size >= 2, sorted, by smallest index.
    fn groups(&mut self) -> Vec<Vec<usize>> {
        let k = self.parent.len();
        let mut by_root: Vec<Vec<usize>> = vec![Vec::new(); k];
        for i in 0..k {
            let r = self.find(i);
            by_root[r].push(i);
        }
        by_root.into_iter().filter(|g| g.len() >= 2).collect()
    }
}

/// Runs a mission to the fixpoint and returns the typed solution.
pub fn reference_solve(mission: &Mission, options: &SolveOptions, cancel: &AtomicBool) -> Solution {
    let mut model = Model::new(mission);
    let dim = model.dim;
    let n = model.steps;
    let tol = options.tolerance.max(0.0);
    let k = mission.detections.len();
    let mut matching = Matching {
        parent: (0..k).collect(),
    };
    // Operator matching: detections of one landmark share one variable.
    let mut by_landmark: Vec<(usize, usize)> = mission
        .detections
        .iter()
        .enumerate()
        .filter_map(|(j, d)| d.landmark.map(|l| (l, j)))
        .collect();
    by_landmark.sort_unstable();
    for w in by_landmark.windows(2) {
        if w[0].0 == w[1].0 {
            matching.union(w[0].1, w[1].1);
        }
    }
    let mut contractions: u64 = 0;
    let finish = |model: Model,
                  status: SolveStatus,
                  rounds: u32,
                  contractions: u64,
                  matching: &mut Matching| Solution {
        status,
        matching: matching.groups(),
        rounds,
        contractions,
        model,
        outliers: None,
    };

    // Dead reckoning from the start, and back from the end when known.
    if let Sweep::Empty(s) = sweep_forward(&mut model.pos, &model.disp, dim, 0, 0.0) {
        let reason = format!("motion chain: the position of step {s} is empty (the inputs cannot join the initial and final positions)");
        return finish(
            model,
            SolveStatus::Infeasible(reason),
            0,
            contractions,
            &mut matching,
        );
    }
    if mission.final_position.is_some() {
        if let Sweep::Empty(s) = sweep_backward(&mut model.pos, &model.disp, dim, n, 0.0) {
            let reason = format!("motion chain: the position of step {s} is empty (the inputs cannot join the initial and final positions)");
            return finish(
                model,
                SolveStatus::Infeasible(reason),
                0,
                contractions,
                &mut matching,
            );
        }
    }
    contractions += 2 * n as u64;

    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by_key(|&j| (mission.detections[j].step, j));
    let mut round = 0u32;
    let mut before = [Interval::EMPTY; 3];
    loop {
        if round >= options.max_rounds {
            return finish(
                model,
                SolveStatus::Stopped,
                round,
                contractions,
                &mut matching,
            );
        }
        if cancel.load(Ordering::Relaxed) {
            return finish(
                model,
                SolveStatus::Stopped,
                round,
                contractions,
                &mut matching,
            );
        }
        round += 1;
        let mut moved = false;
        for &j in &order {
            let det = &mission.detections[j];
            let t = det.step;
            let p = &mut model.pos[t * dim..(t + 1) * dim];
            before[..dim].copy_from_slice(p);
            let d_before = model.det[j].clone();
            let mut range = det.range;
            let ok = contract_distance(p, model.det[j].axes_mut(), &mut range)
                && det.bearing.is_none_or(|b| {
                    contract_bearing(p, model.det[j].axes_mut(), model.heading_at[j], b, range)
                });
            contractions += 1;
            if !ok || model.det[j].is_empty() {
                let reason = format!(
                    "detection {j} (step {t}): range {} cannot reach any landmark position",
                    det.range
                );
                model.det[j].set_empty();
                return finish(
                    model,
                    SolveStatus::Infeasible(reason),
                    round,
                    contractions,
                    &mut matching,
                );
            }
            let p_moved = (0..dim)
                .map(|a| shrinkage(before[a], p[a]))
                .fold(0.0, f64::max);
            let d_moved = (0..dim)
                .map(|a| shrinkage(d_before[a], model.det[j][a]))
                .fold(0.0, f64::max);
            if d_moved > tol {
                moved = true;
            }
            if p_moved > tol {
                moved = true;
                let f = sweep_forward(&mut model.pos, &model.disp, dim, t, tol);
                let b = sweep_backward(&mut model.pos, &model.disp, dim, t, tol);
                for s in [f, b] {
                    match s {
                        Sweep::Empty(s) => {
                            let reason = format!("motion chain: the position of step {s} is empty (propagating detection {j} at step {t})");
                            return finish(
                                model,
                                SolveStatus::Infeasible(reason),
                                round,
                                contractions,
                                &mut matching,
                            );
                        }
                        Sweep::Done(v) => contractions += v as u64,
                    }
                }
            }
        }
        // Tie detections: proved groups (operator or nvector) share a box.
        let groups = matching.groups();
        for g in &groups {
            let mut common = model.det[g[0]].clone();
            for &j in &g[1..] {
                common.intersect_with(&model.det[j]);
            }
            if common.is_empty() {
                let reason = format!(
                    "landmark of detections {:?}: their boxes have no common point (a wrong matching?)",
                    g
                );
                return finish(
                    model,
                    SolveStatus::Infeasible(reason),
                    round,
                    contractions,
                    &mut matching,
                );
            }
            for &j in g {
                let m = (0..dim)
                    .map(|a| shrinkage(model.det[j][a], common[a]))
                    .fold(0.0, f64::max);
                if m > tol {
                    moved = true;
                }
                model.det[j] = common.clone();
            }
            contractions += 1;
        }
        if let (Association::NVector(mode), Some(nl)) =
            (options.association, mission.landmark_count)
        {
            if k > 0 {
                let snapshot: Vec<_> = model.det.clone();
                match atmost_nvector(nl, &mut model.det, mode) {
                    Ok(out) => {
                        contractions += 1;
                        if let Status::Infeasible { reason } = out.status {
                            let reason =
                                format!("atmost_nvector({nl}) over the detections: {reason}");
                            return finish(
                                model,
                                SolveStatus::Infeasible(reason),
                                round,
                                contractions,
                                &mut matching,
                            );
                        }
                        for g in &out.groups {
                            for &j in &g[1..] {
                                matching.union(g[0], j);
                            }
                        }
                        for (a, b) in snapshot.iter().zip(&model.det) {
                            let m = (0..dim).map(|x| shrinkage(a[x], b[x])).fold(0.0, f64::max);
                            if m > tol {
                                moved = true;
                            }
                        }
                    }
                    Err(e) => {
                        let reason = format!("atmost_nvector({nl}): {e}");
                        return finish(
                            model,
                            SolveStatus::Infeasible(reason),
                            round,
                            contractions,
                            &mut matching,
                        );
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
    finish(
        model,
        SolveStatus::Consistent,
        round,
        contractions,
        &mut matching,
    )
}
