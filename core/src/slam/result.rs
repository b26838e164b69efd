//! `nvector-result/1`: the boxes, matching, metrics and score of a solved
//! mission (spec/formats.md, "Result").

use super::mission::Mission;
use super::model::Model;
use super::outliers::relaxed_intersection;
use super::propagator::SolveOptions;
use crate::ibox::IntervalBox;
use crate::json::box_to_json;
use serde_json::{json, Map, Value};

/// How propagation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveStatus {
    /// Fixpoint reached, no empty domain.
    Consistent,
    /// A domain became empty; the reason names the constraint and variable.
    Infeasible(String),
    /// `max_rounds` or cancellation before the fixpoint (boxes still sound).
    Stopped,
}

/// A solved mission: domains and what was proved.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Consistent, infeasible or stopped.
    pub status: SolveStatus,
    /// Groups (size >= 2) of detections proved to be the same landmark.
    pub matching: Vec<Vec<usize>>,
    /// Propagation rounds.
    pub rounds: u32,
    /// Contractor calls and swept steps.
    pub contractions: u64,
    /// Final domains.
    pub model: Model,
}

impl Solution {
    /// One box per matching group, in the order of `matching`: the common
    /// intersection of its members' boxes; with false detections allowed
    /// (q = `max_outliers` > 0), the q-relaxed intersection of the boxes of
    /// the members not proved false (a sub-mission may drop up to q of
    /// them; see [`super::outliers`]).
    pub fn landmarks(&self) -> Vec<IntervalBox> {
        let q = self.model.max_outliers;
        self.matching
            .iter()
            .map(|g| {
                if q > 0 {
                    let members: Vec<&IntervalBox> = g
                        .iter()
                        .map(|&j| &self.model.det[j])
                        .filter(|b| !b.is_empty())
                        .collect();
                    return relaxed_intersection(&members, q, self.model.dim);
                }
                let mut b = self.model.det[g[0]].clone();
                for &j in &g[1..] {
                    b.intersect_with(&self.model.det[j]);
                }
                b
            })
            .collect()
    }
}

/// Score against the mission's truth: (truth_inside, matching_errors,
/// matching_recall). A false detection (`None` in `truth.matching`) has no
/// landmark: its box is not checked, it is never counted as matched, and
/// every pair of a group that holds it is a matching error. The recall is
/// the fraction of the true detections that ended in a group of size >= 2
/// (1 when there is none).
pub fn score(mission: &Mission, s: &Solution) -> Option<(bool, usize, f64)> {
    let truth = mission.truth.as_ref()?;
    let m = &s.model;
    let mut inside = truth
        .positions
        .iter()
        .enumerate()
        .all(|(i, p)| m.position(i).contains(p));
    for (j, b) in m.det.iter().enumerate() {
        if let Some(l) = truth.matching[j] {
            inside &= b.contains(&truth.landmarks[l]);
        }
    }
    for (g, b) in s.matching.iter().zip(s.landmarks()) {
        if let Some(l) = g.iter().find_map(|&j| truth.matching[j]) {
            inside &= b.contains(&truth.landmarks[l]);
        }
    }
    let mut errors = 0;
    for g in &s.matching {
        for (x, &a) in g.iter().enumerate() {
            for &b in &g[x + 1..] {
                match (truth.matching[a], truth.matching[b]) {
                    (Some(la), Some(lb)) if la == lb => {}
                    _ => errors += 1,
                }
            }
        }
    }
    let grouped = s
        .matching
        .iter()
        .flatten()
        .filter(|&&j| truth.matching[j].is_some())
        .count();
    let real = truth.matching.iter().filter(|l| l.is_some()).count();
    let recall = if real == 0 {
        1.0
    } else {
        grouped as f64 / real as f64
    };
    Some((inside, errors, recall))
}

fn finite_or_inf(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        json!("inf")
    }
}

/// The result JSON (`metrics.elapsed_ms` = 0; the caller measures time).
pub fn result_json(mission: &Mission, options: &SolveOptions, s: &Solution) -> Value {
    let m = &s.model;
    let mut o = Map::new();
    o.insert("format".into(), "nvector-result/1".into());
    o.insert("mission".into(), mission.name.clone().into());
    let status = match &s.status {
        SolveStatus::Consistent => "consistent",
        SolveStatus::Infeasible(_) => "infeasible",
        SolveStatus::Stopped => "stopped",
    };
    o.insert("status".into(), status.into());
    if let SolveStatus::Infeasible(r) = &s.status {
        o.insert("reason".into(), r.clone().into());
    }
    o.insert(
        "options".into(),
        json!({
            "contractor": options.association.name(),
            "max_rounds": options.max_rounds,
            "tolerance": options.tolerance,
        }),
    );
    let trajectory: Vec<Value> = (0..=m.steps).map(|i| box_to_json(&m.position(i))).collect();
    o.insert("trajectory".into(), Value::Array(trajectory));
    o.insert(
        "detections".into(),
        Value::Array(m.det.iter().map(box_to_json).collect()),
    );
    o.insert(
        "landmarks".into(),
        Value::Array(s.landmarks().iter().map(box_to_json).collect()),
    );
    o.insert("matching".into(), json!(s.matching));
    let (max_d, mean_d) = m.trajectory_diameters();
    let max_det = m.det.iter().map(|b| b.diameter()).fold(0.0, f64::max);
    let matched: usize = s.matching.iter().map(|g| g.len()).sum();
    o.insert(
        "metrics".into(),
        json!({
            "max_trajectory_diameter": finite_or_inf(max_d),
            "mean_trajectory_diameter": finite_or_inf(mean_d),
            "max_detection_diameter": finite_or_inf(max_det),
            "matched_detections": matched,
            "rounds": s.rounds,
            "contractions": s.contractions,
            "elapsed_ms": 0.0,
        }),
    );
    if let Some((inside, errors, recall)) = score(mission, s) {
        o.insert(
            "score".into(),
            json!({"truth_inside": inside, "matching_errors": errors, "matching_recall": recall}),
        );
    }
    Value::Object(o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::mission::Mission;
    use serde_json::json;

    /// Three detections of one landmark at (2, 2) by truth, the third a
    /// false detection (`null`), scored against hand-made solutions.
    fn mission() -> Mission {
        Mission::from_value(&json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [0.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": [
                {"step": 0, "range": [2.8, 2.9]},
                {"step": 1, "range": [2.8, 2.9]},
                {"step": 1, "range": [5, 6]}
            ],
            "landmark_count": 1,
            "max_outliers": 1,
            "truth": {"positions": [[0, 0], [0, 0]], "landmarks": [[2, 2]], "matching": [0, 0, null]}
        }))
        .unwrap()
    }

    fn solution(m: &Mission, matching: Vec<Vec<usize>>) -> Solution {
        let mut model = Model::new(m);
        model.pos.fill(crate::Interval::ZERO);
        model.det = vec![
            IntervalBox::new(&[crate::Interval::new(1.0, 3.0); 2]),
            IntervalBox::new(&[crate::Interval::new(1.5, 2.5); 2]),
            // Far from the landmark: not checked, the detection is false.
            IntervalBox::new(&[crate::Interval::new(4.0, 5.0); 2]),
        ];
        Solution {
            status: SolveStatus::Consistent,
            matching,
            rounds: 1,
            contractions: 0,
            model,
        }
    }

    #[test]
    fn a_false_detection_is_never_matched_and_its_group_is_an_error() {
        let m = mission();
        assert_eq!(
            score(&m, &solution(&m, vec![vec![0, 1]])),
            Some((true, 0, 1.0))
        );
        // Grouped with both true detections: two wrong pairs; the recall
        // counts the true detections only.
        assert_eq!(
            score(&m, &solution(&m, vec![vec![0, 1, 2]])),
            Some((false, 2, 1.0)),
            "the group's box (empty intersection) cannot hold the landmark"
        );
        assert_eq!(
            score(&m, &solution(&m, vec![vec![1, 2]])),
            Some((false, 1, 0.5))
        );
        assert_eq!(score(&m, &solution(&m, vec![])), Some((true, 0, 0.0)));
    }
}
