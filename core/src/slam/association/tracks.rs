//! Tracks: detections at nearby steps proved to see one landmark from the
//! relative evidence and the minimum separation (issue 20, point 4), for
//! robots without a heading sensor (odometry2d).
//!
//! # Constraint
//!
//! Distinct landmarks are at least s apart (`landmark_min_separation`):
//! `l(a) != l(b)` implies `|l(a) - l(b)| >= s`; each detection sees a real
//! landmark (`max_outliers` = 0).
//!
//! # Math
//!
//! For detections a (step i) and b (step j, i < j <= i + `window`), the
//! vector `l(a) - l(b)` in the body frame of step i lies in the box of
//! [`gap`] over the relative pose of step j enclosed from the odometry
//! alone ([`crate::odometry::relative`]), which does not depend on the
//! absolute heading, however wide it is. When the upper bound of its norm
//! is below s, the two landmarks are less than s apart, so they are one:
//! a union. Unions chain through the union-find, so a landmark seen in
//! consecutive scans becomes one group (a track) as long as it is seen
//! again within the window. The merged groups then contract the positions
//! and the headings through the propagation (a group's landmark box is the
//! intersection of its members' boxes; bearings contract the heading).
//!
//! Each step i is compared with the detection steps after it while they
//! lie within `window` steps and the relative pose stays narrower than s
//! (beyond that no pair can be proved), at most `max_steps` of them.
//!
//! # Soundness
//!
//! The gap box holds the true `l(a) - l(b)` ([`gap`]), and its norm's upper
//! bound is rounded up, so "below s" is proved, and with it `l(a) = l(b)`
//! when both detections are real. A false detection sees no landmark, so
//! with `max_outliers` > 0 the rule proves nothing and is not run (the
//! caller returns no union; no q-relaxed form is attempted). Looking at
//! fewer pairs only finds fewer unions. s <= 0, NaN, or a mission that is
//! not odometry2d: no union.
//!
//! # Complexity
//!
//! O(S · W) relative-pose steps (S detection steps, W the window in
//! steps) and O(k · c · M) gap tests (c detections per step, M =
//! `max_steps`); memory O(k).

use crate::interval::Interval;
use crate::odometry::chain::OdometryChain;
use crate::odometry::relative::{advance, body_point, gap, norm_above, RelativePose};
use crate::slam::mission::Mission;
use crate::union_find::Uf;

/// How far the track rule looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackOptions {
    /// Most steps between two detections compared.
    pub window: usize,
    /// Most later detection steps each step is compared with.
    pub max_steps: usize,
}

impl Default for TrackOptions {
    fn default() -> Self {
        TrackOptions {
            window: 50,
            max_steps: 25,
        }
    }
}

/// The unions the relative evidence proves (module doc), applied to `uf`
/// and returned. `chain` is the mission's odometry chain.
pub fn track_unions(
    mission: &Mission,
    chain: &OdometryChain,
    uf: &mut Uf,
    options: TrackOptions,
) -> Vec<(usize, usize)> {
    let mut unions = Vec::new();
    let s = mission.landmark_min_separation;
    let k = mission.detections.len();
    if mission.max_outliers > 0 || s.is_nan() || s <= 0.0 || k == 0 || uf.len() != k {
        return unions;
    }
    let o = mission.sensor_offset.unwrap_or([0.0, 0.0]);
    let dets = &mission.detections;
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_unstable_by_key(|&j| (dets[j].step, j));
    // Runs of one step: (step, start in order).
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (x, &j) in order.iter().enumerate() {
        if runs.last().is_none_or(|r| r.0 != dets[j].step) {
            runs.push((dets[j].step, x));
        }
    }
    runs.push((usize::MAX, k));
    let body: Vec<[Interval; 2]> = dets
        .iter()
        .map(|d| body_point(d.range, d.bearing, o, Interval::ZERO))
        .collect();
    let n = chain.steps();
    for r in 0..runs.len() - 1 {
        let (i, from) = runs[r];
        let here = &order[from..runs[r + 1].1];
        let mut pose = RelativePose::ORIGIN;
        let mut at = i;
        for later in runs.iter().skip(r + 1).take(options.max_steps) {
            let j = later.0;
            if j == usize::MAX || j > n || j - i > options.window {
                break;
            }
            while at < j {
                pose = advance(chain, &pose, at);
                at += 1;
            }
            if pose.position_width() >= 2.0 * s {
                break;
            }
            let next = runs.iter().find(|x| x.0 > j).map_or(k, |x| x.1);
            for &b in &order[later.1..next] {
                let d = &dets[b];
                for &a in here {
                    if uf.find(a) == uf.find(b) {
                        continue;
                    }
                    let v = gap(&body[a], &pose, d.range, d.bearing, o);
                    if norm_above(&v) < s {
                        uf.union(a, b);
                        unions.push((a, b));
                    }
                }
            }
        }
    }
    unions
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::woods::{simulate_woods, WoodsOptions};

    /// Planted woods missions (random trajectories among identical
    /// landmarks, bounds around the truth): every union joins two
    /// detections of one true landmark.
    #[test]
    fn planted_woods_missions_only_merge_true_pairs() {
        let mut total = 0;
        for seed in 1..=40u64 {
            let opts = WoodsOptions {
                seed,
                steps: Some(120 + (seed as usize % 5) * 40),
                landmarks: Some(5 + (seed as usize % 20)),
                operator: false,
            };
            let mission = Mission::from_value(&simulate_woods(&opts)).expect("a woods mission");
            let truth = mission.truth.as_ref().expect("truth").matching.clone();
            let model = crate::slam::model::Model::new(&mission);
            let chain = model.odometry.as_ref().expect("odometry2d");
            let mut uf = Uf::new(mission.detections.len());
            let u = track_unions(&mission, chain, &mut uf, TrackOptions::default());
            total += u.len();
            for (a, b) in u {
                assert!(truth[a].is_some(), "seed {seed}: {a} has no true landmark");
                assert_eq!(truth[a], truth[b], "seed {seed}: {a} {b}");
            }
            for a in 0..truth.len() {
                let ra = uf.find(a);
                for b in a + 1..truth.len() {
                    if uf.find(b) == ra {
                        assert_eq!(truth[a], truth[b], "seed {seed}: {a} {b}");
                    }
                }
            }
        }
        assert!(total > 0, "the rule proved nothing on 40 missions");
    }
}
