//! The `auv` scenario: a Redermor-scale 3-D survey over the six Redermor
//! seamarks (the module doc of [`super`]).

use super::scenario::{
    boxed, closest_approaches, int, interval, mission_head, wrap, SimulateOptions, AUV_STEPS,
    MARGIN,
};
use crate::format::leaf::{List, PerStep, PointsIn};
use crate::format::mission_doc::{ChannelDoc, DetectionDoc, InputsDoc, MissionDoc, TruthDoc};
use crate::rng::Rng;
use serde_json::{json, Value};

/// The six Redermor seamarks (x, y, depth), as the public Codac loader gives them.
const SEAMARKS: [[f64; 3]; 6] = [
    [594.053, 374.729, 19.0],
    [599.609, 484.553, 19.0],
    [601.461, 557.357, 19.0],
    [94.013, -2.868, 19.0],
    [119.941, 84.752, 20.0],
    [127.349, 156.328, 20.0],
];

/// The distance between two 3-D points, with basic operations and the
/// correctly rounded `libm::sqrt` only (`f64::powi` has no specified
/// precision: it may differ between platforms).
fn distance3(q: &[f64; 3], l: &[f64; 3]) -> f64 {
    let (dx, dy, dz) = (q[0] - l[0], q[1] - l[1], q[2] - l[2]);
    libm::sqrt(dx * dx + dy * dy + dz * dz)
}

/// The survey's waypoints: legs along y, 50 m apart, x from 60 to 660 m.
fn auv_waypoints() -> Vec<[f64; 2]> {
    let mut waypoints = Vec::new();
    let mut xw = 60.0;
    let mut up = true;
    while xw <= 660.0 {
        let (y0, y1) = if up { (-60.0, 600.0) } else { (600.0, -60.0) };
        waypoints.push([xw, y0]);
        waypoints.push([xw, y1]);
        xw += 50.0;
        up = !up;
    }
    waypoints
}

/// The auv scenario's drive along the waypoints: the true positions
/// (steps + 1) and the six measured channels (roll, pitch, yaw, vx, vy,
/// vz) of each step, with the angle, yaw and velocity error bounds.
fn auv_drive(
    rng: &mut Rng,
    (steps, dt): (usize, f64),
    waypoints: &[[f64; 2]],
    start: [f64; 3],
    [angle_err, yaw_err, vel_err]: [f64; 3],
) -> (Vec<[f64; 3]>, [Vec<f64>; 6]) {
    let mut p = start;
    let mut yaw = std::f64::consts::FRAC_PI_2;
    let mut wp = 0usize;
    let mut positions = vec![p];
    let mut ch: [Vec<f64>; 6] = Default::default();
    for _ in 0..steps {
        let target = waypoints[wp.min(waypoints.len() - 1)];
        if libm::hypot(target[0] - p[0], target[1] - p[1]) < 10.0 && wp + 1 < waypoints.len() {
            wp += 1;
        }
        let want = libm::atan2(target[1] - p[1], target[0] - p[0]);
        yaw = wrap(yaw + wrap(want - yaw).clamp(-0.3 * dt, 0.3 * dt));
        let roll = 0.02 * libm::sin(0.3 * positions.len() as f64 * dt);
        let pitch = 0.01 * libm::cos(0.2 * positions.len() as f64 * dt);
        let v = [1.5, 0.05 * libm::sin(0.01 * positions.len() as f64), 0.0];
        let (cf, sf) = (libm::cos(roll), libm::sin(roll));
        let (ct, st) = (libm::cos(pitch), libm::sin(pitch));
        let (cp, sp) = (libm::cos(yaw), libm::sin(yaw));
        let r = [
            [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf],
            [sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf],
            [-st, ct * sf, ct * cf],
        ];
        for a in 0..3 {
            p[a] += dt * (r[a][0] * v[0] + r[a][1] * v[1] + r[a][2] * v[2]);
        }
        positions.push(p);
        ch[0].push(roll + rng.sym(angle_err));
        ch[1].push(pitch + rng.sym(angle_err));
        ch[2].push(yaw + rng.sym(yaw_err));
        for a in 0..3 {
            ch[3 + a].push(v[a] + rng.sym(vel_err));
        }
    }
    (positions, ch)
}

/// The sonar detections (closest approaches within the sonar range, by
/// step then seamark) as JSON, and the true matching.
fn auv_detections(
    o: &SimulateOptions,
    rng: &mut Rng,
    positions: &[[f64; 3]],
    (sonar_range, range_err): (f64, f64),
) -> (Vec<DetectionDoc>, Vec<usize>) {
    let mut detections: Vec<(usize, usize)> = Vec::new();
    for (j, l) in SEAMARKS.iter().enumerate() {
        let dist: Vec<f64> = positions.iter().map(|q| distance3(q, l)).collect();
        for s in closest_approaches(&dist, sonar_range) {
            detections.push((s, j));
        }
    }
    crate::sort::sort_ord(&mut detections);
    let mut det_json = Vec::new();
    let mut matching = Vec::new();
    for &(s, j) in &detections {
        let q = positions[s];
        let l = SEAMARKS[j];
        let r = distance3(&q, &l);
        let r_meas = r + rng.sym(range_err);
        det_json.push(DetectionDoc {
            step: Some(int(s)),
            range: Some(interval(
                (r_meas - range_err - MARGIN).max(0.0),
                r_meas + range_err + MARGIN,
            )),
            depth: Some(interval(l[2] - 1.0, l[2] + 1.0)),
            landmark: o.operator.then(|| int(j)),
            ..DetectionDoc::default()
        });
        matching.push(j);
    }
    (det_json, matching)
}

pub(super) fn auv(o: &SimulateOptions) -> Value {
    let mut rng = Rng::new(o.seed);
    let steps = o.steps.unwrap_or(AUV_STEPS).max(2);
    let dt = 0.1;
    let noise = o.noise.max(0.0);
    let (angle_err, yaw_err, vel_err) = (0.001 * noise, 0.002 * noise, 0.004 * noise);
    let range_err = 0.2 * noise;
    let sonar_range = 60.0;
    let auv_depth = 5.0;
    let waypoints = auv_waypoints();
    let start = [waypoints[0][0], waypoints[0][1] - 20.0, auv_depth];
    let errs3 = [angle_err, yaw_err, vel_err];
    let (positions, ch) = auv_drive(&mut rng, (steps, dt), &waypoints, start, errs3);
    let (det_json, matching) = auv_detections(o, &mut rng, &positions, (sonar_range, range_err));
    let gps = 2.0;
    let end = positions[steps];
    let errs = [angle_err, angle_err, yaw_err, vel_err, vel_err, vel_err];
    let [roll, pitch, yaw, vx, vy, vz] =
        std::array::from_fn(|a| Some(ChannelDoc::measured(ch[a].clone(), errs[a] + MARGIN)));
    let inputs = InputsDoc {
        roll,
        pitch,
        yaw,
        vx,
        vy,
        vz,
        ..InputsDoc::default()
    };
    let around = |c: [f64; 3], r: f64, dz: f64| {
        Some(boxed(&[
            [c[0] - r, c[0] + r],
            [c[1] - r, c[1] + r],
            [c[2] - dz, c[2] + dz],
        ]))
    };
    let mission = MissionDoc {
        initial_position: around(start, gps, 0.5),
        final_position: around(end, gps, 0.5),
        inputs: Some(inputs),
        motion_error: Some(PerStep::One(MARGIN)),
        detections: Some(List(det_json)),
        landmark_count: Some(int(SEAMARKS.len())),
        meta: Some(json!({"scenario": "auv", "seed": o.seed, "generator": "nvector simulate"})),
        truth: Some(TruthDoc {
            positions: Some(PointsIn::rows(3, positions.as_flattened())),
            landmarks: Some(PointsIn::rows(3, SEAMARKS.as_flattened())),
            matching: Some(List(matching.into_iter().map(|j| Some(int(j))).collect())),
            headings: None,
        }),
        ..mission_head(format!("auv-seed-{}", o.seed), "auv3d", dt, steps)
    };
    crate::format::to_value(&mission)
}

// The simulation options as the front ends give them (`POST /simulate`,
// the page's SLAM demo, Python's `simulate`, `nvector simulate`): one type,
// read from JSON by the JSON front ends or filled in by the others, and one
// validation with one set of limits ([`SimulateRequest::options`]): core's
// ([`SimulateLimits::CORE`]), or a service's own, lower ones.
