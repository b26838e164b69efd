//! The scan pose in the passes (odometry2d): when a pass reaches a detection
//! step, its detections contract p(step), th(step) and their landmark
//! boxes together ([`contract_scan_pose`], over pieces of the heading).
//!
//! Constraint, math and soundness: [`crate::odometry::scan_pose`]; each
//! detection's box is first intersected with its group's box (held at the
//! group's root, a sequential filter, as the offset pass does), and the
//! root's box with the result. Every detection must see a real landmark
//! (the rounds call it with `max_outliers` = 0).
//!
//! Complexity: O(K c) per step for c detections with a bearing, K =
//! [`PIECES`]; skipped (O(c)) when the heading is narrower than
//! [`MIN_WIDTH`], where the pieces would add little to the detections'
//! own contractions.

use crate::interval::Interval;
use crate::odometry::scan_pose::{contract_scan_pose, PoseOutcome, PoseReading};
use crate::slam::mission::Mission;
use crate::slam::model::Model;
use crate::union_find::Uf;

/// Heading pieces per step.
pub const PIECES: usize = 16;

/// Headings narrower than this (rad) are not cut.
pub const MIN_WIDTH: f64 = 0.05;

/// Per step, the domains the scan pose left there (th, p and the sum of
/// the landmark boxes' bounds): a step whose domains are still those is
/// not contracted again (the pieces would find little more; skipping a
/// contraction is always sound). O(N) memory.
#[derive(Debug, Clone, Default)]
pub struct ScanPoseMemo(Vec<Option<[f64; 7]>>);

/// The stamp of a step's domains for [`ScanPoseMemo`].
fn stamp(th: Interval, p: &[Interval; 2], reads: &[PoseReading]) -> [f64; 7] {
    let sum = reads
        .iter()
        .flat_map(|r| r.landmark)
        .fold(0.0, |a, x| a + x.lo() + x.hi());
    [
        th.lo(),
        th.hi(),
        p[0].lo(),
        p[0].hi(),
        p[1].lo(),
        p[1].hi(),
        sum,
    ]
}

/// Contracts the detections `at` (all at step `t`) with p(t) and th(t);
/// returns the detections whose box shrank by more than `tol` and whether
/// p(t) or th(t) did. Err: no heading piece fits every detection.
pub fn scan_pose_step(
    mission: &Mission,
    model: &mut Model,
    uf: &mut Uf,
    memo: &mut ScanPoseMemo,
    at: &[usize],
    t: usize,
    tol: f64,
) -> Result<(Vec<usize>, bool), String> {
    let Some(&th) = model.heading.get(t) else {
        return Ok((Vec::new(), false));
    };
    if at.is_empty()
        || th.is_empty()
        || th.width() <= MIN_WIDTH
        || model.det.first().is_none_or(|d| d.dim() != 2)
    {
        return Ok((Vec::new(), false));
    }
    let (js, mut reads) = readings(mission, model, uf, at);
    let mut p = [model.pos[2 * t], model.pos[2 * t + 1]];
    let mut h = th;
    if memo.0.len() <= t {
        memo.0.resize(model.heading.len().max(t + 1), None);
    }
    let before = stamp(th, &p, &reads);
    if memo.0[t].is_some_and(|m| {
        m.iter()
            .zip(&before)
            .all(|(a, b)| a.to_bits() == b.to_bits())
    }) {
        return Ok((Vec::new(), false));
    }
    if contract_scan_pose(&mut p, &mut h, model.sensor_offset, &mut reads, PIECES)
        == PoseOutcome::Empty
    {
        return Err(format!(
            "step {t}: no heading in [{}, {}] fits every detection of the step at once",
            th.lo(),
            th.hi()
        ));
    }
    let moved_pose = [
        (model.pos[2 * t], p[0]),
        (model.pos[2 * t + 1], p[1]),
        (th, h),
    ]
    .iter()
    .any(|&(a, b)| shrink(a, b) > tol);
    (model.pos[2 * t], model.pos[2 * t + 1], model.heading[t]) = (p[0], p[1], h);
    for &j in at {
        model.heading_at[j] = h;
    }
    let moved = write_landmarks(model, uf, &js, &reads, tol);
    memo.0[t] = Some(stamp(h, &p, &reads));
    Ok((moved, moved_pose))
}

/// The readings of the detections `at` that have a bearing (with their
/// indices): range, bearing, and the landmark box of the detection met
/// with its group's.
fn readings(
    mission: &Mission,
    model: &Model,
    uf: &mut Uf,
    at: &[usize],
) -> (Vec<usize>, Vec<PoseReading>) {
    let mut js = Vec::with_capacity(at.len());
    let mut reads = Vec::with_capacity(at.len());
    for &j in at {
        let Some(bearing) = mission.detections[j].bearing else {
            continue;
        };
        let root = uf.find(j);
        let mut b = model.det[j].clone();
        b.intersect_with(&model.det[root]);
        js.push(j);
        reads.push(PoseReading {
            range: mission.detections[j].range,
            bearing,
            landmark: [b[0], b[1]],
        });
    }
    (js, reads)
}

/// Writes the contracted landmark boxes back (each also into its group's
/// box); returns the detections whose box shrank by more than `tol`.
fn write_landmarks(
    model: &mut Model,
    uf: &mut Uf,
    js: &[usize],
    reads: &[PoseReading],
    tol: f64,
) -> Vec<usize> {
    let mut moved = Vec::new();
    for (&j, r) in js.iter().zip(reads) {
        let before = [model.det[j][0], model.det[j][1]];
        model.det[j][0] = r.landmark[0];
        model.det[j][1] = r.landmark[1];
        if shrink(before[0], r.landmark[0]).max(shrink(before[1], r.landmark[1])) > tol {
            moved.push(j);
            let root = uf.find(j);
            let dj = model.det[j].clone();
            model.det[root].intersect_with(&dj);
        }
    }
    moved
}

/// How much an interval shrank (infinite bounds becoming finite count as
/// infinite).
fn shrink(before: Interval, after: Interval) -> f64 {
    crate::contractors::motion_chain::shrinkage(before, after)
}
