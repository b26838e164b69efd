//! The check of the detections and landmarks against the truth.
//!
//! # Constraint
//!
//! A detection j at step t sees a landmark L when the distance from the
//! sensor `s = p(t) + R(h)·sensor_offset` to L is in `range`, the
//! direction of `L - s` minus the heading h is in `bearing` + 2πZ, L is in
//! the detection's `region` and its z in `depth` (docs/formats.md). The
//! heading h is the input `heading` (unicycle2d; `heading(N-1)` at step
//! N), the input `yaw` (auv3d) or the true th(t) (odometry2d; any heading
//! when the truth does not know it).
//!
//! Which landmark (the rule; docs/cli.md, "check"):
//! - a detection with a true landmark (`truth.matching[j]`) and an
//!   operator `landmark` id is checked against its true landmark: the
//!   solver ties it to that id's group;
//! - a detection with a true landmark and no operator id (the solver is
//!   not told which landmark) holds when its true landmark satisfies it or,
//!   failing that, when SOME true landmark does: the world where it saw
//!   that landmark is a solution too, and holds the truth's positions;
//!   when none does, its violations are those of its true landmark;
//! - a false detection (`truth.matching[j]` null) holds when some true
//!   landmark satisfies it; when none does, its violations are those of
//!   the landmark whose excesses sum to the least.
//!
//! Then over the detections that hold (each with the landmark it was
//! matched to): the detections of one operator id see one landmark (the
//! first member's), those of one `scan` distinct landmarks, at most
//! `landmark_count` landmarks are seen, and two landmarks seen are at
//! least `landmark_min_separation` apart; every true landmark is in
//! `landmark_region`.
//!
//! # Soundness
//!
//! Distances and angles are outward-rounded enclosures: a violation is
//! reported when the enclosure misses the bound (its gap, rounded down,
//! is the excess), or when the solver's own detection contractor
//! (`contract_distance`/`contract_bearing`, or `OffsetDetection` with a
//! sensor offset or an odometry2d heading) empties a domain of the
//! truth's point boxes. A truth on a bound is never a violation.
//!
//! # Complexity
//!
//! O(1) per detection whose true landmark holds; O(landmarks) for one
//! that does not; O(k log k) for the scans and ids; the separation
//! O(L log L) plus the pairs closer in x than the separation.

use super::types::{
    angle_gap, angle_value, gap, minus_down, nearest, Bound, Kind, Truthy, Violation,
};
use crate::contractors::bearing::contract_bearing;
use crate::contractors::distance::contract_distance;
use crate::interval::Interval;
use crate::odometry::angle::{box_angle, contract_periodic};
use crate::odometry::sensor::{rotate_offset, OffsetDetection};
use crate::slam::mission::Model;

/// The heading the detection `j` is measured against (module doc).
fn heading_at(t: &Truthy, step: usize) -> Interval {
    let m = t.m;
    let i = step.min(m.steps - 1);
    match m.model {
        Model::Unicycle2d => m.inputs[1][i],
        Model::Auv3d => m.inputs[2][i],
        Model::Odometry2d => t.heading(step).map_or(Interval::ENTIRE, Interval::point),
    }
}

/// Whether the solver's detection contractor refuses the truth's point
/// boxes (p, the landmark, the heading).
fn contractor_refuses(t: &Truthy, j: usize, p: &[f64], l: &[f64], h: Interval) -> bool {
    let m = t.m;
    let d = &m.detections[j];
    let mut pb: Vec<Interval> = p.iter().map(|&x| Interval::point(x)).collect();
    let mut lb: Vec<Interval> = l.iter().map(|&x| Interval::point(x)).collect();
    let offset = m.sensor_offset.unwrap_or([0.0, 0.0]);
    let plain = m.model != Model::Odometry2d && offset == [0.0, 0.0];
    if plain {
        let mut range = d.range;
        let ok = contract_distance(&mut pb, &mut lb, &mut range)
            && d.bearing
                .is_none_or(|b| contract_bearing(&mut pb, &mut lb, h, b, range));
        return !ok;
    }
    let od = OffsetDetection::new(d.range, d.bearing, offset);
    let (mut p2, mut l2, mut h2) = ([pb[0], pb[1]], [lb[0], lb[1]], h);
    !od.contract(&mut p2, &mut h2, &mut l2)
}

/// The range and bearing of detection `j` from the sensor at the true
/// position `p` (heading `h`) to the landmark `lm`, against its bounds.
fn range_bearing(t: &Truthy, j: usize, p: &[f64], lm: &[f64], h: Interval) -> Vec<Violation> {
    let m = t.m;
    let d = &m.detections[j];
    let o = match m.model.dim() {
        2 => rotate_offset(h, m.sensor_offset.unwrap_or([0.0, 0.0])).to_vec(),
        _ => vec![Interval::ZERO; 3],
    };
    let diff: Vec<Interval> = (0..p.len())
        .map(|a| Interval::point(lm[a]) - (Interval::point(p[a]) + o[a]))
        .collect();
    let dist = diff.iter().fold(Interval::ZERO, |s, &x| s + x.sqr()).sqrt();
    let mut out = Vec::new();
    let g = gap(dist, d.range);
    if g > 0.0 {
        let b = Bound::Within(d.range.lo(), d.range.hi());
        let value = nearest(dist, d.range);
        out.push(Violation::new(
            format!("detections[{j}].range"),
            Kind::Range,
            value,
            b,
            g,
        ));
    }
    if let (Some(b), Some(a)) = (d.bearing, box_angle(diff[0], diff[1])) {
        let rel = a - h;
        if contract_periodic(rel, b).is_empty() {
            let value = angle_value(rel, b);
            let bound = Bound::Within(b.lo(), b.hi());
            let g = angle_gap(rel, b);
            out.push(Violation::new(
                format!("detections[{j}].bearing"),
                Kind::Bearing,
                value,
                bound,
                g,
            ));
        }
    }
    out
}

/// The violations of detection `j` (at the known true position `p`)
/// measured against landmark `l`.
fn measure(t: &Truthy, j: usize, p: &[f64], l: usize) -> Vec<Violation> {
    let m = t.m;
    let d = &m.detections[j];
    let lm = &m.truth.as_ref().expect("checked").landmarks[l];
    let h = heading_at(t, d.step);
    let path = format!("detections[{j}]");
    let mut out = range_bearing(t, j, p, lm, h);
    let measured = !out.is_empty();
    if let Some(r) = &d.region {
        for (a, (&x, &b)) in lm.iter().zip(r.axes()).enumerate() {
            if !b.contains(x) {
                let bound = Bound::Within(b.lo(), b.hi());
                let g = gap(Interval::point(x), b);
                out.push(Violation::new(
                    format!("{path}.region[{a}]"),
                    Kind::Region,
                    x,
                    bound,
                    g,
                ));
            }
        }
    }
    if let Some(z) = d.depth {
        if !z.contains(lm[2]) {
            let bound = Bound::Within(z.lo(), z.hi());
            let g = gap(Interval::point(lm[2]), z);
            out.push(Violation::new(
                format!("{path}.depth"),
                Kind::Depth,
                lm[2],
                bound,
                g,
            ));
        }
    }
    if !measured && contractor_refuses(t, j, p, lm, h) {
        out.push(Violation::new(
            path,
            Kind::Detection,
            1.0,
            Bound::AtMost(0.0),
            0.0,
        ));
    }
    for v in &mut out {
        v.step = Some(d.step);
        v.detection = Some(j);
        v.landmark = Some(l);
    }
    out
}

/// The landmark detection `j` is matched to, or its violations (module
/// doc, the rule).
fn match_detection(t: &Truthy, j: usize, p: &[f64]) -> Result<usize, Vec<Violation>> {
    let m = t.m;
    let truth = m.truth.as_ref().expect("checked");
    let true_l = truth.matching[j];
    let own = true_l.map(|l| measure(t, j, p, l));
    match &own {
        Some(v) if v.is_empty() => return Ok(true_l.expect("some")),
        Some(_) if m.detections[j].landmark.is_some() => return Err(own.expect("some")),
        _ => {}
    }
    let mut least: Option<(f64, Vec<Violation>)> = None;
    for l in (0..truth.landmarks.len()).filter(|&l| Some(l) != true_l) {
        let v = measure(t, j, p, l);
        if v.is_empty() {
            return Ok(l);
        }
        let total: f64 = v.iter().map(|v| v.excess).sum();
        if least.as_ref().is_none_or(|(s, _)| total < *s) {
            least = Some((total, v));
        }
    }
    if let Some(v) = own {
        return Err(v);
    }
    Err(least.map(|x| x.1).unwrap_or_else(|| {
        let d = m.detections[j].step;
        let v = Violation::new(
            format!("detections[{j}]"),
            Kind::Detection,
            1.0,
            Bound::AtMost(0.0),
            1.0,
        );
        vec![v.at_step(d).of(Some(j), None)]
    }))
}

/// Every detection: its violations, and the landmark each detection that
/// holds is matched to (`None`: it breaks its constraints, or its true
/// position is unknown).
pub fn detections(t: &mut Truthy, out: &mut Vec<Violation>) -> Vec<Option<usize>> {
    let m = t.m;
    let mut matched = vec![None; m.detections.len()];
    for (j, d) in m.detections.iter().enumerate() {
        let Some(p) = t.position(d.step) else {
            t.unchecked += 1;
            continue;
        };
        match match_detection(t, j, p) {
            Ok(l) => matched[j] = Some(l),
            Err(v) => out.extend(v),
        }
    }
    operator_ids(t, &mut matched, out);
    scans(t, &mut matched, out);
    matched
}

/// The detections of one operator id see the first member's landmark;
/// the others are violations (and no longer matched).
fn operator_ids(t: &Truthy, matched: &mut [Option<usize>], out: &mut Vec<Violation>) {
    let m = t.m;
    let mut by_id: Vec<(usize, usize)> = m
        .detections
        .iter()
        .enumerate()
        .filter_map(|(j, d)| Some((d.landmark?, j)))
        .filter(|&(_, j)| matched[j].is_some())
        .collect();
    crate::sort::sort_ord(&mut by_id);
    let mut x = 0;
    while x < by_id.len() {
        let id = by_id[x].0;
        let first = matched[by_id[x].1].expect("kept");
        while x < by_id.len() && by_id[x].0 == id {
            let j = by_id[x].1;
            let l = matched[j].expect("kept");
            if l != first {
                let b = Bound::Within(first as f64, first as f64);
                let v = Violation::new(
                    format!("detections[{j}].landmark"),
                    Kind::Landmark,
                    l as f64,
                    b,
                    1.0,
                );
                out.push(v.at_step(m.detections[j].step).of(Some(j), Some(l)));
                matched[j] = None;
            }
            x += 1;
        }
    }
}

/// The detections of one scan see distinct landmarks: the second (third,
/// ...) detection of a landmark in a scan is a violation.
fn scans(t: &Truthy, matched: &mut [Option<usize>], out: &mut Vec<Violation>) {
    let m = t.m;
    let mut seen: Vec<(u64, usize, usize)> = m
        .detections
        .iter()
        .enumerate()
        .filter_map(|(j, d)| Some((d.scan?, matched[j]?, j)))
        .collect();
    crate::sort::sort_ord(&mut seen);
    let mut count = 0usize;
    for x in 0..seen.len() {
        let (scan, l, j) = seen[x];
        let same = x > 0 && seen[x - 1].0 == scan && seen[x - 1].1 == l;
        count = if same { count + 1 } else { 1 };
        if count > 1 {
            let v = Violation::new(
                format!("detections[{j}].scan"),
                Kind::Scan,
                count as f64,
                Bound::AtMost(1.0),
                (count - 1) as f64,
            );
            out.push(v.at_step(m.detections[j].step).of(Some(j), Some(l)));
            matched[j] = None;
        }
    }
}

/// `landmark_region` (every true landmark), `landmark_count` and
/// `landmark_min_separation` (the landmarks the detections that hold are
/// matched to).
pub fn landmarks(t: &Truthy, matched: &[Option<usize>], out: &mut Vec<Violation>) {
    let m = t.m;
    let truth = m.truth.as_ref().expect("checked");
    if let Some(r) = &m.landmark_region {
        for (l, lm) in truth.landmarks.iter().enumerate() {
            for (a, (&x, &b)) in lm.iter().zip(r.axes()).enumerate() {
                if !b.contains(x) {
                    let bound = Bound::Within(b.lo(), b.hi());
                    let g = gap(Interval::point(x), b);
                    let v = Violation::new(
                        format!("landmark_region[{a}]"),
                        Kind::LandmarkRegion,
                        x,
                        bound,
                        g,
                    );
                    out.push(v.of(None, Some(l)));
                }
            }
        }
    }
    let mut seen: Vec<usize> = matched.iter().flatten().copied().collect();
    crate::sort::sort_ord(&mut seen);
    seen.dedup();
    if let Some(n) = m.landmark_count {
        if seen.len() > n {
            let v = Violation::new(
                "landmark_count",
                Kind::LandmarkCount,
                seen.len() as f64,
                Bound::AtMost(n as f64),
                (seen.len() - n) as f64,
            );
            out.push(v);
        }
    }
    separation(t, &seen, out);
}

/// Pairs of landmarks seen closer than `landmark_min_separation`.
fn separation(t: &Truthy, seen: &[usize], out: &mut Vec<Violation>) {
    let m = t.m;
    let sep = m.landmark_min_separation;
    if sep <= 0.0 {
        return;
    }
    let lms = &m.truth.as_ref().expect("checked").landmarks;
    let mut by_x: Vec<usize> = seen.to_vec();
    crate::sort::sort_by(&mut by_x, |&a, &b| lms[a][0].total_cmp(&lms[b][0]));
    for (x, &a) in by_x.iter().enumerate() {
        for &b in &by_x[x + 1..] {
            if lms[b][0] - lms[a][0] >= sep {
                break;
            }
            let dist = (0..lms.dim())
                .fold(Interval::ZERO, |s, k| {
                    s + (Interval::point(lms[b][k]) - Interval::point(lms[a][k])).sqr()
                })
                .sqrt();
            if dist.hi() < sep {
                let v = Violation::new(
                    "landmark_min_separation",
                    Kind::LandmarkMinSeparation,
                    dist.hi(),
                    Bound::AtLeast(sep),
                    minus_down(sep, dist.hi()),
                );
                let mut v = v.of(None, Some(a.min(b)));
                v.other_landmark = Some(a.max(b));
                out.push(v);
            }
        }
    }
}
