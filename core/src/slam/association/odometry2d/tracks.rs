//! Tracks: detections at nearby steps proved to see one landmark from the
//! relative evidence and the minimum separation, for
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
//! is below s (the box's far corner, or the largest over pieces of the
//! measured intervals: [`gap_below`](crate::odometry::relative::gap_below)), the two landmarks are less than s
//! apart, so they are one:
//! a union. Unions chain through the union-find, so a landmark seen in
//! consecutive scans becomes one group (a track) as long as it is seen
//! again within the window. The merged groups then contract the positions
//! and the headings through the propagation (a group's landmark box is the
//! intersection of its members' boxes; bearings contract the heading).
//!
//! **Bridges** (a track broken for longer than the odometry can bridge):
//! when two groups A and B (proved, each one landmark) are both seen at
//! steps i and j (detections a_i, a_j, b_i, b_j), the constellation fixes
//! the relative pose without the odometry's heading: `l(A) - l(B)` is
//! `m(a_i) - m(b_i)` in the frame of i and `R(H)(m(a_j) - m(b_j))` seen
//! from j, so H lies in the pair heading of the two
//! ([`contract_pair_heading`], with the frame-i points as the landmark
//! boxes), and `P = (o + m(a_i)) - R(H)(o + m(a_j))` for each common group;
//! both are intersected with the odometry's relative pose. The gap test
//! above then runs between the detections of i and j with that pose. Each
//! step is bridged to the next `bridge_steps` detection steps within
//! `bridge_window` steps, after the track unions (which make the groups).
//!
//! Each step i is compared with the detection steps after it while they
//! lie within `window` steps and the relative pose stays narrower than s
//! (beyond that no pair can be proved), at most `max_steps` of them.
//!
//! # Soundness
//!
//! The gap box holds the true `l(a) - l(b)` ([`gap`]), and its norm's upper
//! bound is rounded up, so "below s" is proved, and with it `l(a) = l(b)`
//! when both detections are real. A bridge's pose holds the true relative
//! pose: the true landmarks of A and B are in the body boxes (frame i) and
//! the true (r, β) of a_j, b_j in their intervals, so the true H satisfies
//! the pair equation and the true P each group's equation (A and B seeing
//! one landmark, whatever it is, need not be distinct: equal landmarks give
//! a box holding the origin, from which the pair heading learns nothing).
//! A false detection sees no landmark, so
//! with `max_outliers` > 0 the rule proves nothing and is not run (the
//! caller returns no union; no q-relaxed form is attempted). Looking at
//! fewer pairs only finds fewer unions. s <= 0, NaN, or a mission that is
//! not odometry2d: no union.
//!
//! # Complexity
//!
//! O(S · W) relative-pose steps (S detection steps, W the window in
//! steps) and O(k · c · M) gap tests (c detections per step, M =
//! `max_steps`); the bridges O(S · W') pose steps and O(S · M' · c²) pair
//! headings and gap tests (W' = `bridge_window`, M' = `bridge_steps`);
//! memory O(k).

use crate::interval::Interval;
use crate::odometry::chain::OdometryChain;
use crate::odometry::pair_heading::{contract_pair_heading, Seen};
use crate::odometry::relative::{advance_from, body_point, gap_below_sides, GapSide, RelativePose};
use crate::slam::mission::Mission;
use crate::union_find::Uf;

/// How far the track rule looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackOptions {
    /// Most steps between two detections compared.
    pub window: usize,
    /// Most later detection steps each step is compared with.
    pub max_steps: usize,
    /// Bridges: most steps between the two steps.
    pub bridge_window: usize,
    /// Bridges: most later detection steps each step is bridged to.
    pub bridge_steps: usize,
}

impl Default for TrackOptions {
    fn default() -> Self {
        TrackOptions {
            window: 50,
            max_steps: 25,
            bridge_window: 300,
            bridge_steps: 150,
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
    let k = mission.detections.len();
    if mission.max_outliers > 0 || uf.len() != k {
        return unions;
    }
    let Some(steps) = StepRuns::new(mission) else {
        return unions;
    };
    steps.for_each_pair(chain, options, &mut |a, b, proved| {
        if uf.find(a) != uf.find(b) && proved() {
            uf.union(a, b);
            unions.push((a, b));
        }
    });
    let ctx = Bridge {
        chain,
        dets: &mission.detections,
        order: &steps.order,
        runs: &steps.runs,
        body: &steps.body,
        o: steps.o,
        s: steps.s,
    };
    ctx.bridge_unions(uf, options, &mut unions);
    unions
}

/// What [`StepRuns::for_each_pair`] calls for each pair it may compare:
/// `(a, b, proved)`, `proved()` running the gap test.
pub type OnPair<'f> = dyn FnMut(usize, usize, &mut dyn FnMut() -> bool) + 'f;

/// The detections of a mission in step order, in runs of one step, with
/// their body points: what the pair tests read.
pub struct StepRuns<'a> {
    dets: &'a [crate::slam::mission::Detection],
    /// Detection indices sorted by (step, index).
    order: Vec<usize>,
    /// Runs of one step: (step, start in `order`), then `(usize::MAX, k)`.
    runs: Vec<(usize, usize)>,
    body: Vec<[Interval; 2]>,
    o: [f64; 2],
    s: f64,
}

impl<'a> StepRuns<'a> {
    /// None when the rule cannot prove anything: no detection, or a
    /// separation that is not a positive number.
    pub fn new(mission: &'a Mission) -> Option<StepRuns<'a>> {
        let s = mission.landmark_min_separation;
        let k = mission.detections.len();
        if s.is_nan() || s <= 0.0 || k == 0 {
            return None;
        }
        let o = mission.sensor_offset.unwrap_or([0.0, 0.0]);
        let dets = &mission.detections[..];
        let mut order: Vec<usize> = (0..k).collect();
        crate::sort::total_by_key(&mut order, |&j| (dets[j].step, j));
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for (x, &j) in order.iter().enumerate() {
            if runs.last().is_none_or(|r| r.0 != dets[j].step) {
                runs.push((dets[j].step, x));
            }
        }
        runs.push((usize::MAX, k));
        let body = dets
            .iter()
            .map(|d| body_point(d.range, d.bearing, o, Interval::ZERO))
            .collect();
        Some(StepRuns {
            dets,
            order,
            runs,
            body,
            o,
            s,
        })
    }

    /// Calls `f(a, b, proved)` for every pair of detections a (step i) and
    /// b (step j, i < j) that the track rule may compare (module doc: j
    /// within `window` steps and `max_steps` detection steps of i, the
    /// relative pose narrower than 2s), in order of i then j; `proved()`
    /// runs the gap test ([`gap_below`](crate::odometry::relative::gap_below)): true when the two landmarks are
    /// proved less than s apart, hence one when both detections are real.
    pub fn for_each_pair(&self, chain: &OdometryChain, options: TrackOptions, f: &mut OnPair) {
        let (dets, order, runs, o, s) = (self.dets, &self.order, &self.runs, self.o, self.s);
        let (n, k) = (chain.steps(), order.len());
        for r in 0..runs.len() - 1 {
            let (i, from) = runs[r];
            let here = &order[from..runs[r + 1].1];
            let mut nears = near_sides(dets, here, o);
            let mut pose = RelativePose::ORIGIN;
            let mut at = i;
            for (x, later) in runs.iter().enumerate().skip(r + 1).take(options.max_steps) {
                let j = later.0;
                if j == usize::MAX || j > n || j - i > options.window {
                    break;
                }
                while at < j {
                    pose = advance_from(chain, &pose, i, at);
                    at += 1;
                }
                if pose.position_width() >= 2.0 * s {
                    break;
                }
                let next = runs.get(x + 1).map_or(k, |r| r.1);
                for &b in &order[later.1..next] {
                    let d = &dets[b];
                    let mut far = GapSide::far(d.range, d.bearing, o, pose.h);
                    for (&a, near) in here.iter().zip(nears.iter_mut()) {
                        f(a, b, &mut || gap_below_sides(near, &pose, &mut far, s));
                    }
                }
            }
        }
    }
}

/// The near sides of the gap tests ([`GapSide`]) of a step's detections
/// `here`, reused over every later step they are compared with (the same
/// bits as [`crate::odometry::relative::gap_below`] on each pair).
fn near_sides(
    dets: &[crate::slam::mission::Detection],
    here: &[usize],
    o: [f64; 2],
) -> Vec<GapSide> {
    here.iter()
        .map(|&a| GapSide::near(dets[a].range, dets[a].bearing, o))
        .collect()
}

/// What [`Bridge::bridge_unions`] reads: the detections in step order, their
/// runs of one step and their body points.
struct Bridge<'a> {
    chain: &'a OdometryChain,
    dets: &'a [crate::slam::mission::Detection],
    order: &'a [usize],
    runs: &'a [(usize, usize)],
    body: &'a [[Interval; 2]],
    o: [f64; 2],
    s: f64,
}

impl Bridge<'_> {
    /// The detections of run `r` with a bearing, by their group's root.
    fn roots(&self, uf: &mut Uf, r: usize) -> Vec<(usize, usize)> {
        let (from, to) = (self.runs[r].1, self.runs[r + 1].1);
        self.order[from..to]
            .iter()
            .filter(|&&j| self.dets[j].bearing.is_some())
            .map(|&j| (uf.find(j), j))
            .collect()
    }

    /// The pose of run `r2`'s step in the body frame of run `r`'s from two
    /// groups seen at both (module doc, "Bridges"), intersected with
    /// `odo`, the odometry's; None when fewer than two groups are common
    /// or the pose is proved empty.
    fn pose_from_groups(
        &self,
        uf: &mut Uf,
        r: usize,
        r2: usize,
        odo: &RelativePose,
    ) -> Option<RelativePose> {
        let at_i = self.roots(uf, r);
        let at_j = self.roots(uf, r2);
        let common: Vec<(usize, usize)> = at_i
            .iter()
            .filter_map(|&(ra, a)| at_j.iter().find(|x| x.0 == ra).map(|x| (a, x.1)))
            .collect();
        if common.len() < 2 {
            return None;
        }
        let seen = |a: usize, b: usize| Seen {
            landmark: self.body[a],
            range: self.dets[b].range,
            bearing: self.dets[b].bearing,
        };
        let mut h = odo.h;
        for (x, &(ai, aj)) in common.iter().enumerate() {
            for &(bi, bj) in &common[x + 1..] {
                h = contract_pair_heading(h, &seen(ai, aj), &seen(bi, bj));
            }
        }
        if h.is_empty() {
            return None;
        }
        let mut p = odo.p;
        for &(ai, aj) in &common {
            let d = &self.dets[aj];
            let b = body_point(d.range, d.bearing, self.o, h);
            p[0] = p[0].intersect(self.body[ai][0] - b[0]);
            p[1] = p[1].intersect(self.body[ai][1] - b[1]);
        }
        (!p[0].is_empty() && !p[1].is_empty()).then_some(RelativePose { p, h, ..*odo })
    }

    /// Bridges (module doc): for each detection step i and the next
    /// `bridge_steps` detection steps j within `bridge_window` steps, the
    /// relative pose from two groups seen at both steps; detections of i
    /// and j whose gap's norm is below s are one landmark.
    fn bridge_unions(&self, uf: &mut Uf, options: TrackOptions, unions: &mut Vec<(usize, usize)>) {
        let n = self.chain.steps();
        let k = self.order.len();
        for r in 0..self.runs.len() - 1 {
            let i = self.runs[r].0;
            let here = &self.order[self.runs[r].1..self.runs[r + 1].1];
            let mut nears = near_sides(self.dets, here, self.o);
            let mut odo = RelativePose::ORIGIN;
            let mut at = i;
            for r2 in r + 1..(r + 1 + options.bridge_steps).min(self.runs.len() - 1) {
                let j = self.runs[r2].0;
                if j > n || j - i > options.bridge_window {
                    break;
                }
                while at < j {
                    odo = advance_from(self.chain, &odo, i, at);
                    at += 1;
                }
                let Some(pose) = self.pose_from_groups(uf, r, r2, &odo) else {
                    continue;
                };
                if pose.position_width() >= 2.0 * self.s {
                    continue;
                }
                let (from, to) = (self.runs[r2].1, self.runs[r2 + 1].1.min(k));
                for &b in &self.order[from..to] {
                    let d = &self.dets[b];
                    let mut far = GapSide::far(d.range, d.bearing, self.o, pose.h);
                    for (&a, near) in here.iter().zip(nears.iter_mut()) {
                        if uf.find(a) == uf.find(b) {
                            continue;
                        }
                        if gap_below_sides(near, &pose, &mut far, self.s) {
                            uf.union(a, b);
                            unions.push((a, b));
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::simulate::odometry_scenario::{simulate_woods, WoodsOptions};

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
