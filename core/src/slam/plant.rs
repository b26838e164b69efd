//! Planting false range detections in a mission with truth: the
//! simulation's false readings added to a real log (`nvector import
//! --cmu-plaza DIR --false-detections K --seed S`), so that the robust
//! propagation can be measured against readings known to be false.
//!
//! Pure and deterministic for a seed (core's [`Rng`]); no I/O.

use super::mission::{Detection, Mission};
use crate::interval::Interval;
use crate::rng::Rng;

/// Most draws for one planted range.
pub const MAX_DRAWS: usize = 10_000;

/// No false range was found for a planted detection within [`MAX_DRAWS`]
/// draws: every draw held, or may have held, a landmark's true distance
/// (or the truth cannot tell).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "no false range found in {draws} draws \
     (every draw holds a landmark's true distance, or the truth is unknown)"
)]
pub struct NoFalseRange {
    /// The draws made.
    pub draws: usize,
}

/// Where each detection of a planted mission came from: `origin[i]` is
/// the index of detection `i` in the mission before planting, `None` for a
/// planted one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Planted {
    /// By detection of the planted mission.
    pub origin: Vec<Option<usize>>,
}

/// Plants `count` false ranges in `mission`: each at a random step of
/// `0..=steps`, a range interval as wide as the widest real one, its lower
/// bound drawn over the span of the real lower bounds (`[0, 10]` of width
/// 1 when there is no detection), no operator label, `None` in
/// `truth.matching`; `count` is added to `max_outliers` and the name gets
/// `-false-{count}`. Detections stay in step order (a planted one after
/// the real ones of its step, in planting order). Deterministic for a
/// seed: the draws are, per planted range, a step then a lower bound,
/// repeated until the range is false.
///
/// A planted range is *false* (no landmark there, docs/formats.md): a draw
/// is drawn again while its interval holds, or may hold, a landmark's true
/// distance from the sensor at its step ([`may_see_a_landmark`]); a range
/// that holds one would be a true detection labelled false.
///
/// Complexity: O(k log k) for the k detections, plus O(draws × n) for the
/// n true landmarks.
pub fn plant_false_ranges(
    mission: &mut Mission,
    count: usize,
    seed: u64,
) -> Result<Planted, NoFalseRange> {
    let mut rng = Rng::new(seed);
    let steps = mission.steps;
    let (mut lo_min, mut lo_max, mut width) = (f64::INFINITY, 0.0f64, 0.0f64);
    for d in &mission.detections {
        let (lo, hi) = (d.range.lo(), d.range.hi());
        (lo_min, lo_max, width) = (lo_min.min(lo), lo_max.max(lo), width.max(hi - lo));
    }
    if !lo_min.is_finite() {
        (lo_min, lo_max, width) = (0.0, 10.0, 1.0);
    }
    let mut planted = Vec::with_capacity(count);
    for _ in 0..count {
        let (step, lo) = (0..MAX_DRAWS)
            .map(|_| {
                let step = ((rng.unit() * (steps + 1) as f64) as usize).min(steps);
                (step, lo_min + (lo_max - lo_min) * rng.unit())
            })
            .find(|&(step, lo)| !may_see_a_landmark(mission, step, lo, lo + width))
            .ok_or(NoFalseRange { draws: MAX_DRAWS })?;
        planted.push(Detection {
            step,
            range: Interval::new(lo, lo + width),
            bearing: None,
            region: None,
            depth: None,
            landmark: None,
            scan: None,
        });
    }
    let real = std::mem::take(&mut mission.detections);
    let matching = mission
        .truth
        .as_mut()
        .map(|t| std::mem::take(&mut t.matching));
    // (step, input index, detection)
    let mut all: Vec<(usize, usize, Detection)> = real
        .into_iter()
        .chain(planted)
        .enumerate()
        .map(|(i, d)| (d.step, i, d))
        .collect();
    all.sort_by_key(|d| (d.0, d.1));
    let k = mission.detection_count;
    let origin: Vec<Option<usize>> = all.iter().map(|d| (d.1 < k).then_some(d.1)).collect();
    if let (Some(t), Some(before)) = (mission.truth.as_mut(), matching) {
        t.matching = origin
            .iter()
            .map(|o| o.and_then(|i| before.get(i).copied().flatten()))
            .collect();
    }
    mission.detections = all.into_iter().map(|d| d.2).collect();
    mission.detection_count = mission.detections.len();
    mission.max_outliers += count;
    mission.name = format!("{}-false-{count}", mission.name);
    Ok(Planted { origin })
}

/// Whether the range interval [lo, hi] at `step` holds, or may hold, the
/// true distance from the sensor to a landmark of the truth: the sensor is
/// within |`sensor_offset`| of the true position, so a distance d from the
/// position is [d - |o|, d + |o|] from the sensor. True where the truth
/// cannot tell (no truth, no true position at that step, no landmarks).
/// A decision on a redraw, not a bound: a range it lets through is false
/// by at least the rounding of one `hypot` (far below any range's width).
pub fn may_see_a_landmark(mission: &Mission, step: usize, lo: f64, hi: f64) -> bool {
    let Some(truth) = &mission.truth else {
        return true;
    };
    let known = truth
        .positions_known
        .as_ref()
        .is_none_or(|k| k.get(step).copied().unwrap_or(false));
    if !known || step >= truth.positions.len() || truth.landmarks.is_empty() {
        return true;
    }
    let p = &truth.positions[step];
    let o = mission
        .sensor_offset
        .map_or(0.0, |[x, y]| libm::hypot(x, y));
    truth.landmarks.iter().any(|l| {
        let d = libm::hypot(l[0] - p[0], l[1] - p[1]);
        d + o >= lo && d - o <= hi
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A 10-step mission along x from the origin, one landmark at (5, 0),
    /// two real ranges.
    fn mission() -> Mission {
        Mission::from_value(&json!({
            "format": "nvector-mission/1",
            "name": "m",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 10,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": vec![1.0; 10], "error": 0.0},
                       "heading": {"value": vec![0.0; 10], "error": 0.0}},
            "detections": [{"step": 2, "range": [2.9, 3.1], "landmark": 0},
                           {"step": 7, "range": [1.9, 2.1]}],
            "max_outliers": 1,
            "truth": {"positions": (0..=10).map(|i| [i as f64, 0.0]).collect::<Vec<_>>(),
                      "landmarks": [[5.0, 0.0]], "matching": [0, 0]},
        }))
        .unwrap()
    }

    #[test]
    fn planted_ranges_are_false_sorted_and_counted() {
        let mut m = mission();
        let p = plant_false_ranges(&mut m, 5, 3).unwrap();
        assert_eq!(m.detections.len(), 7);
        assert_eq!(m.detection_count, 7);
        assert_eq!(m.max_outliers, 6);
        assert_eq!(m.name, "m-false-5");
        assert!(m.detections.windows(2).all(|w| w[0].step <= w[1].step));
        let t = m.truth.as_ref().unwrap();
        for (i, d) in m.detections.iter().enumerate() {
            match p.origin[i] {
                Some(j) => {
                    assert_eq!(t.matching[i], Some(0));
                    assert!(j < 2);
                }
                None => {
                    assert_eq!(t.matching[i], None);
                    assert_eq!(d.landmark, None);
                    // No landmark's true distance inside: |5 - step|.
                    let truth = (5.0 - d.step as f64).abs();
                    assert!(!d.range.contains(truth), "{d:?}");
                    assert!((d.range.hi() - d.range.lo() - 0.2).abs() < 1e-12);
                }
            }
        }
        assert_eq!(p.origin.iter().filter(|o| o.is_none()).count(), 5);
        // The planted mission is a valid mission.
        Mission::from_value(&m.to_value()).unwrap();
    }

    #[test]
    fn the_same_seed_plants_the_same_ranges() {
        let (mut a, mut b, mut c) = (mission(), mission(), mission());
        plant_false_ranges(&mut a, 4, 9).unwrap();
        plant_false_ranges(&mut b, 4, 9).unwrap();
        plant_false_ranges(&mut c, 4, 10).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn a_truth_that_cannot_tell_refuses_to_plant() {
        let mut m = mission();
        m.truth = None;
        assert_eq!(
            plant_false_ranges(&mut m, 1, 1),
            Err(NoFalseRange { draws: MAX_DRAWS })
        );
        // A range on the boundary of a landmark's distance may see it.
        let m = mission();
        assert!(may_see_a_landmark(&m, 2, 3.0, 3.5));
        assert!(may_see_a_landmark(&m, 2, 2.0, 3.0));
        assert!(!may_see_a_landmark(&m, 2, 3.0 + 1e-9, 3.5));
        // No true position at that step: the truth cannot tell.
        assert!(may_see_a_landmark(&m, 11, 100.0, 101.0));
    }
}
