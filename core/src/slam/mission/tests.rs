//! The mission's parsing, validation and writing.

use super::*;
use serde_json::json;

fn small() -> Value {
    json!({
        "format": "nvector-mission/1",
        "name": "t",
        "model": "unicycle2d",
        "dt": 0.5,
        "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {
            "speed": {"value": [1.0, 2.0], "error": 0.1},
            "heading": {"lo": [0.0, 0.1], "hi": [0.0, 0.2]}
        },
        "detections": [{"step": 1, "range": [2, 3], "landmark": 0}],
        "landmark_count": 1
    })
}

#[test]
fn parses_a_small_mission() {
    let m = Mission::from_value(&small()).unwrap();
    assert_eq!(
        (m.steps, m.detection_count, m.model),
        (2, 1, Model::Unicycle2d)
    );
    assert!(
        m.inputs[0][1].contains(1.9)
            && m.inputs[0][1].contains(2.1)
            && !m.inputs[0][1].contains(2.11)
    );
    assert_eq!(m.inputs[1][1], Interval::new(0.1, 0.2));
    assert_eq!(m.motion_error, vec![0.0, 0.0]);
    assert_eq!(m.detections[0].landmark, Some(0));
}

#[test]
fn unbounded_channel_bounds_are_read_and_written_back() {
    let mut v = small();
    v["inputs"]["heading"] = json!({"lo": ["-inf", 0.1], "hi": [0.0, "inf"]});
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.inputs[1][0], Interval::new(f64::NEG_INFINITY, 0.0));
    assert_eq!(m.inputs[1][1], Interval::new(0.1, f64::INFINITY));
    let back = m.to_value();
    assert_eq!(back["inputs"]["heading"]["lo"], json!(["-inf", 0.1]));
    assert_eq!(back["inputs"]["heading"]["hi"], json!([0.0, "inf"]));
    assert_eq!(Mission::from_value(&back).unwrap(), m);
    // A value and error that overflow are written back as bounds too.
    v["inputs"]["speed"] = json!({"value": [1.0, 1e308], "error": 1e308});
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.inputs[0][1].hi(), f64::INFINITY);
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
}

#[test]
fn round_trips() {
    let m = Mission::from_value(&small()).unwrap();
    let again = Mission::from_value(&m.to_value()).unwrap();
    assert_eq!(m, again);
}

/// The largest values of the u32 fields are accepted as they are (the
/// solvers read them as the detection count; tests/huge_fields.rs runs
/// them under a memory limit).
#[test]
fn the_largest_u32_fields_are_accepted() {
    let mut v = small();
    v["max_outliers"] = json!(u32::MAX);
    v["landmark_count"] = json!(u32::MAX);
    v["detections"][0]["landmark"] = json!(u32::MAX - 1);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(
        (m.max_outliers, m.landmark_count, m.detections[0].landmark),
        (
            u32::MAX as usize,
            Some(u32::MAX as usize),
            Some(u32::MAX as usize - 1)
        )
    );
    assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
}

#[test]
fn max_outliers_and_false_detections_round_trip() {
    let m = Mission::from_value(&small()).unwrap();
    assert_eq!(m.max_outliers, 0, "absent means 0");
    let mut v = small();
    v["max_outliers"] = json!(2);
    v["detections"] = json!([{"step": 1, "range": [2, 3]}, {"step": 2, "range": [1, 2]}]);
    v["truth"] = json!({
        "positions": [[0, 0], [0.5, 0], [1.5, 0]],
        "landmarks": [[2, 2]],
        "matching": [0, null]
    });
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.max_outliers, 2);
    assert_eq!(m.truth.as_ref().unwrap().matching, vec![Some(0), None]);
    let again = Mission::from_value(&m.to_value()).unwrap();
    assert_eq!(m, again);
    assert_eq!(m.to_value()["truth"]["matching"], json!([0, null]));
    v["max_outliers"] = Value::Null;
    assert_eq!(Mission::from_value(&v).unwrap().max_outliers, 0);
}

#[test]
fn bad_inputs_name_their_path() {
    type Edit = fn(&mut Value);
    let cases: Vec<(Edit, &str)> = vec![
        (
            |v| v["inputs"]["speed"]["value"] = json!([1.0]),
            "inputs.speed.value: expected 2 values",
        ),
        (
            |v| v["detections"][0]["range"] = json!([5, 4]),
            "detections[0].range: lower bound 5 is above upper bound 4",
        ),
        (
            |v| v["detections"][0]["range"] = json!([-1, 4]),
            "detections[0].range: negative range",
        ),
        (
            |v| v["detections"][0]["step"] = json!(3),
            "detections[0].step: expected an integer from 0 to 2, found 3",
        ),
        (
            |v| v["detections"][0]["landmark"] = json!(1),
            "detections[0].landmark: expected an integer from 0 to 0, found 1 (ids are below landmark_count 1)",
        ),
        (
            |v| v["detections"][0]["rnage"] = json!(1),
            "detections[0].rnage: unknown field",
        ),
        (|v| v["stpes"] = json!(1), "stpes: unknown field"),
        (
            |v| v["format"] = json!("nvector-mission/2"),
            "format: expected",
        ),
        (|v| v["dt"] = json!(0), "dt: the time step must be > 0"),
        (
            |v| v["detections"][0]["depth"] = json!([1, 2]),
            "detections[0].depth: depth is only for auv3d",
        ),
        (
            |v| v["inputs"]["speed"]["value"][1] = json!("NaN"),
            "inputs.speed.value[1]: expected a finite number",
        ),
        (
            |v| {
                v["inputs"].as_object_mut().unwrap().remove("heading");
            },
            "inputs.heading: missing required field",
        ),
        (
            |v| v["initial_position"] = json!([[0, 1]]),
            "initial_position: expected a box of dimension 2",
        ),
        (
            |v| v["truth"] = json!({"positions": [[0, 0]], "landmarks": [[1, 1]], "matching": [0]}),
            "truth.positions: expected 3 positions",
        ),
        (
            |v| v["max_outliers"] = json!(-1),
            "max_outliers: expected an integer from 0 to 4294967295, found -1",
        ),
        (
            |v| v["max_outliers"] = json!(1.5),
            "max_outliers: expected an integer from 0 to 4294967295, found 1.5",
        ),
        (
            |v| v["max_outliers"] = json!("2"),
            "max_outliers: expected an integer from 0 to 4294967295, found a string",
        ),
        (
            |v| v["max_outliers"] = json!(4294967296u64),
            "max_outliers: expected an integer from 0 to 4294967295, found 4294967296",
        ),
        (
            |v| v["landmark_count"] = json!(4294967296u64),
            "landmark_count: expected an integer from 1 to 4294967295, found 4294967296",
        ),
        (
            |v| {
                v.as_object_mut().unwrap().remove("landmark_count");
                v["detections"][0]["landmark"] = json!(4294967296u64);
            },
            "detections[0].landmark: expected an integer from 0 to 4294967295, found 4294967296",
        ),
        (
            |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [-1]}),
            "truth.matching[0]: expected an integer from 0 to 0, found -1",
        ),
    ];
    for (edit, expected) in cases {
        let mut v = small();
        edit(&mut v);
        let e = Mission::from_value(&v).unwrap_err().to_string();
        assert!(
            e.starts_with(expected),
            "{e} does not start with {expected}"
        );
        let streamed = Mission::from_json(&v.to_string()).unwrap_err().to_string();
        assert_eq!(streamed, e, "parsed from text");
    }
}

/// The streaming parse (large arrays straight into floats) gives the
/// errors of a parse through JSON values, also where an array is not
/// what it should be (a non-number, ragged or long rows, objects where
/// arrays are due), and the same mission when it is valid.
#[test]
fn streamed_errors_are_those_of_values() {
    type Edit = fn(&mut Value);
    fn truth(v: &mut Value, positions: Value) {
        v["truth"] = json!({"positions": positions, "landmarks": [[1, 1]], "matching": [0]});
    }
    let cases: Vec<(Edit, &str)> = vec![
        (
            |v| v["motion_error"] = json!([0.1, -1]),
            "motion_error[1]: the motion error must be >= 0, found -1",
        ),
        (
            |v| v["motion_error"] = json!([0.1, 0.2, 0.3]),
            "motion_error: expected 2 values (one per step), found 3",
        ),
        (
            |v| v["motion_error"] = json!([0.1, {"a": 1}]),
            "motion_error[1]: expected a finite number, found an object",
        ),
        (
            |v| v["inputs"]["speed"]["error"] = json!([0.1, -0.5]),
            "inputs.speed.error[1]: an error bound must be >= 0, found -0.5",
        ),
        (
            |v| v["inputs"]["speed"]["value"] = json!([1, [2]]),
            "inputs.speed.value[1]: expected a finite number, found an array",
        ),
        (
            |v| v["inputs"]["speed"]["value"] = json!({"a": 1}),
            "inputs.speed.value: expected an array, found an object",
        ),
        (
            |v| v["inputs"]["heading"]["hi"] = json!([0.0, 0.05]),
            "inputs.heading.lo[1]: lower bound 0.1 is above upper bound 0.05",
        ),
        (
            |v| v["inputs"]["speed"]["lo"] = json!([1, 2]),
            "inputs.speed.lo: unknown field `lo`",
        ),
        (
            |v| v["inputs"]["heading"]["lo"] = json!(["inf", 0.1]),
            "inputs.heading.lo[0]: lower bound inf is above upper bound 0",
        ),
        (
            |v| v["inputs"]["heading"] = json!({"lo": [0, "inf"], "hi": [1, "inf"]}),
            "inputs.heading.lo[1]: a lower bound of inf holds no real number",
        ),
        (
            |v| v["inputs"]["heading"] = json!({"lo": ["-inf", 0], "hi": ["-inf", 1]}),
            "inputs.heading.hi[0]: an upper bound of -inf holds no real number",
        ),
        (
            |v| v["inputs"]["heading"]["hi"] = json!([0, "infinity"]),
            "inputs.heading.hi[1]",
        ),
        (
            |v| v["inputs"]["speed"] = json!(3),
            "inputs.speed: expected an object, found a number",
        ),
        (
            |v| v["inputs"]["speed"] = json!({"x": [1, 2]}),
            "inputs.speed.x: unknown field `x` (expected one of: value, error, lo, hi)",
        ),
        (
            |v| v["inputs"]["speed"] = json!({}),
            "inputs.speed: an input channel is",
        ),
        (
            |v| v["inputs"] = json!([]),
            "inputs: expected an object, found an array",
        ),
        (
            |v| v["inputs"] = Value::Null,
            "inputs: expected an object, found null",
        ),
        (
            |v| {
                v.as_object_mut().unwrap().remove("inputs");
            },
            "inputs: missing required field",
        ),
        (
            |v| v["inputs"]["roll"] = json!({"value": [0, 0], "error": 0}),
            "inputs.roll: unknown field `roll`",
        ),
        (
            |v| v["truth"] = json!("x"),
            "truth: expected an object, found a string",
        ),
        (
            |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]]}),
            "truth.matching: missing required field",
        ),
        (
            |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [0], "fake": 1}),
            "truth.fake: unknown field",
        ),
        (
            |v| truth(v, json!([[0, 0], [1], [2, 0]])),
            "truth.positions[1]: expected a point of dimension 2, found 1 coordinates",
        ),
        (
            |v| truth(v, json!([[0, 0, 0], [1, 0, 0], [2, 0, 0]])),
            "truth.positions[0]: expected a point of dimension 2, found 3 coordinates",
        ),
        (
            |v| truth(v, json!([[0, 0], [1, 0, 0, 0], [2, 0]])),
            "truth.positions[1]: expected a point of dimension 2, found 4 coordinates",
        ),
        (
            |v| truth(v, json!([[0, 0], ["1", 0], [2, 0]])),
            "truth.positions[1][0]: expected a finite number, found a string",
        ),
        (
            |v| truth(v, json!([[0, 0], 5, [2, 0]])),
            "truth.positions[1]: expected an array, found a number",
        ),
        (
            |v| truth(v, json!([[0, 0], [1, 0]])),
            "truth.positions: expected 3 positions (steps + 1), found 2",
        ),
        (
            |v| truth(v, json!({})),
            "truth.positions: expected an array, found an object",
        ),
        (|v| *v = json!([1, 2]), "expected an object, found an array"),
        (
            |v| *v = json!("mission"),
            "expected an object, found a string",
        ),
    ];
    for (edit, expected) in cases {
        let mut v = small();
        edit(&mut v);
        let e = Mission::from_value(&v).unwrap_err().to_string();
        assert!(
            e.starts_with(expected),
            "{e} does not start with {expected}"
        );
        let streamed = Mission::from_json(&v.to_string()).unwrap_err().to_string();
        assert_eq!(streamed, e, "parsed from text");
    }
    // Null is absence for optional fields.
    let mut v = small();
    v["motion_error"] = Value::Null;
    v["truth"] = Value::Null;
    assert_eq!(
        Mission::from_json(&v.to_string()).unwrap(),
        Mission::from_value(&small()).unwrap()
    );
    // Invalid JSON: serde_json's own message.
    for text in ["{", "{\"steps\": 1,}", "[1, 2] x", ""] {
        let want = serde_json::from_str::<Value>(text).unwrap_err();
        assert_eq!(
            Mission::from_json(text).unwrap_err().to_string(),
            format!("invalid JSON: {want}")
        );
    }
}

fn odometry() -> Value {
    json!({
        "format": "nvector-mission/1",
        "model": "odometry2d",
        "dt": 0.1,
        "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "initial_heading": [-0.01, 0.01],
        "inputs": {
            "speed": {"value": [1.0, -0.5], "error": 0.05},
            "turn_rate": {"value": [0.2, 0.1], "error": 0.01}
        },
        "heading_error": [0.001, 0.002],
        "sensor_offset": [0.3, 0],
        "detections": [
            {"step": 1, "range": [2, 3], "bearing": [0.1, 0.2], "scan": 0},
            {"step": 1, "range": [4, 5], "bearing": [1.1, 1.2], "scan": 0}
        ],
        "landmark_min_separation": 1.33,
        "truth": {
            "positions": [[0, 0], null, [0.15, 0.01]],
            "landmarks": [[2.5, 0.3], [2, 4]],
            "matching": [0, 1],
            "headings": [0.0, null, 0.03]
        }
    })
}

/// The fields of docs/formats.md for robots without a heading sensor
/// (odometry2d): parsed into the mission, written back, and accepted by
/// `unsupported` (the solver handles them).
#[test]
fn odometry2d_offset_scan_separation_and_null_truth_parse() {
    let m = Mission::from_value(&odometry()).unwrap();
    assert_eq!(m.model, Model::Odometry2d);
    assert_eq!(m.inputs.len(), 2);
    assert!(m.inputs[0][1].contains(-0.5) && m.inputs[1][0].contains(0.21));
    assert_eq!(m.initial_heading, Some(Interval::new(-0.01, 0.01)));
    assert_eq!(m.final_heading, None);
    assert_eq!(m.heading_error, vec![0.001, 0.002]);
    assert_eq!(m.sensor_offset, Some([0.3, 0.0]));
    assert_eq!(m.landmark_min_separation, 1.33);
    assert_eq!(
        m.detections.iter().map(|d| d.scan).collect::<Vec<_>>(),
        vec![Some(0), Some(0)]
    );
    let t = m.truth.as_ref().unwrap();
    assert_eq!(t.positions_known, Some(vec![true, false, true]));
    assert_eq!(&t.positions[2], &[0.15, 0.01][..]);
    assert_eq!(&t.positions[1], &[0.0, 0.0][..]);
    assert_eq!(t.headings, Some(vec![Some(0.0), None, Some(0.03)]));
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
    assert_eq!(m.to_value()["truth"]["positions"][1], Value::Null);
    assert_eq!(Mission::from_json(&odometry().to_string()).unwrap(), m);
    // heading_error absent: 0; final_heading given.
    let mut v = odometry();
    v.as_object_mut().unwrap().remove("heading_error");
    v["final_heading"] = json!(0.5);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.heading_error, vec![0.0, 0.0]);
    assert_eq!(m.final_heading, Some(Interval::point(0.5)));
    assert!(m.heading_drift.is_empty());
    assert!(m.to_value().get("heading_drift").is_none());
    // heading_drift: windows kept as given, a window longer than N
    // (even huge) included; written back.
    let mut v = odometry();
    v["heading_drift"] = json!([
        {"steps": 1, "error": 0.0},
        {"steps": 2, "error": 0.25},
        {"steps": 18446744073709551615u64, "error": 3}
    ]);
    let m = Mission::from_value(&v).unwrap();
    let plain = DriftWindow::plain;
    assert_eq!(
        m.heading_drift,
        vec![plain(1, 0.0), plain(2, 0.25), plain(u64::MAX, 3.0)]
    );
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
    assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
    // exempt_above: kept, written back only when given; eight
    // distinct values (and repeats of them) accepted.
    let mut v = odometry();
    let mut w: Vec<Value> = (0..8)
        .map(|x| json!({"steps": 2, "error": 0.1, "exempt_above": 0.01 * x as f64}))
        .collect();
    w.push(json!({"steps": 3, "error": 0.2, "exempt_above": 0.07}));
    w.push(json!({"steps": 3, "error": 0.2, "exempt_above": null}));
    w.push(json!({"steps": 1, "error": 0.2}));
    v["heading_drift"] = Value::Array(w);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.heading_drift[1].exempt_above, Some(0.01));
    assert_eq!(m.heading_drift[8].exempt_above, Some(0.07));
    assert_eq!(m.heading_drift[9], DriftWindow::plain(3, 0.2));
    assert_eq!(m.heading_drift[10], DriftWindow::plain(1, 0.2));
    let back = m.to_value();
    assert_eq!(back["heading_drift"][3]["exempt_above"], json!(0.03));
    assert!(back["heading_drift"][10].get("exempt_above").is_none());
    assert_eq!(Mission::from_value(&back).unwrap(), m);
    // motion_drift: windows kept as given (a huge k included), written
    // back; absent: empty and not written.
    assert!(m.motion_drift.is_empty());
    assert!(back.get("motion_drift").is_none());
    let mut v = odometry();
    v["motion_drift"] = json!([
        {"steps": 3, "error": 0.0},
        {"steps": 18446744073709551615u64, "error": 0.4}
    ]);
    let m = Mission::from_value(&v).unwrap();
    let w = MotionWindow::plain;
    assert_eq!(m.motion_drift, vec![w(3, 0.0), w(u64::MAX, 0.4)]);
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
    // exempt_above: kept and written back.
    v["motion_drift"][1]["exempt_above"] = json!(0.025);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.motion_drift[1].exempt_above, Some(0.025));
    assert_eq!(
        m.to_value()["motion_drift"][1]["exempt_above"],
        json!(0.025)
    );
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
    // sensor_offset on unicycle2d: parsed.
    let mut v = small();
    v["sensor_offset"] = json!([0.2, -0.1]);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(m.sensor_offset, Some([0.2, -0.1]));
    // scan and landmark_min_separation only add evidence: accepted.
    let mut v = small();
    v["detections"][0]["scan"] = json!(7);
    v["landmark_min_separation"] = json!(2);
    let m = Mission::from_value(&v).unwrap();
    assert_eq!(
        (m.detections[0].scan, m.landmark_min_separation),
        (Some(7), 2.0)
    );
    assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
}

#[test]
fn bad_new_fields_name_their_path() {
    type Edit = fn(&mut Value);
    let odo: Vec<(Edit, &str)> = vec![
        (
            |v| {
                v.as_object_mut().unwrap().remove("initial_heading");
            },
            "initial_heading: missing required field",
        ),
        (
            |v| v["initial_heading"] = json!([1, 0]),
            "initial_heading: lower bound 1 is above upper bound 0",
        ),
        (
            |v| v["final_heading"] = json!("north"),
            "final_heading: expected an interval [lo, hi] or a number, found a string",
        ),
        (
            |v| v["heading_error"] = json!([0.1, -0.1]),
            "heading_error[1]: the heading error must be >= 0, found -0.1",
        ),
        (
            |v| v["heading_error"] = json!([0.1]),
            "heading_error: expected 2 values (one per step), found 1",
        ),
        (
            |v| v["inputs"]["heading"] = json!({"value": [0, 0], "error": 0}),
            "inputs.heading: unknown field `heading` (expected one of: speed, turn_rate)",
        ),
        (
            |v| {
                v["inputs"].as_object_mut().unwrap().remove("turn_rate");
            },
            "inputs.turn_rate: missing required field",
        ),
        (
            |v| v["sensor_offset"] = json!([1]),
            "sensor_offset: expected 2 numbers [forward, left], found 1",
        ),
        (
            |v| v["sensor_offset"] = json!(["a", 0]),
            "sensor_offset[0]: expected a finite number, found a string",
        ),
        (
            |v| v["detections"][1]["scan"] = json!(-1),
            "detections[1].scan: expected an integer from 0 to 18446744073709551615, found -1",
        ),
        (
            |v| v["detections"][1]["scan"] = json!(0.5),
            "detections[1].scan: expected an integer from 0 to 18446744073709551615, found 0.5",
        ),
        (
            |v| v["landmark_min_separation"] = json!(-1),
            "landmark_min_separation: the separation must be >= 0, found -1",
        ),
        (
            |v| v["landmark_min_separation"] = json!([1]),
            "landmark_min_separation: expected a finite number, found an array",
        ),
        (
            |v| v["truth"]["headings"] = json!([0, 0]),
            "truth.headings: expected 3 headings (steps + 1), found 2",
        ),
        (
            |v| v["truth"]["headings"][2] = json!("x"),
            "truth.headings[2]: expected a finite number, found a string",
        ),
        (
            |v| v["truth"]["positions"][1] = json!([1]),
            "truth.positions[1]: expected a point of dimension 2, found 1 coordinates",
        ),
        (
            |v| v["truth"]["landmarks"][1] = Value::Null,
            "truth.landmarks[1]: expected an array, found null",
        ),
        (
            |v| {
                v["heading_drift"] =
                    json!([{"steps": 10, "error": 0.1}, {"steps": 0, "error": 0.1}])
            },
            "heading_drift[1].steps: expected an integer from 1 to 18446744073709551615, found 0",
        ),
        (
            |v| v["motion_drift"] = json!([{"steps": 4, "error": 0.1}, {"steps": 0, "error": 0.1}]),
            "motion_drift[1].steps: expected an integer from 1 to 18446744073709551615, found 0",
        ),
        (
            |v| v["motion_drift"] = json!([{"steps": 2, "error": -0.1}]),
            "motion_drift[0].error: the drift bound must be >= 0, found -0.1",
        ),
        (
            |v| v["motion_drift"] = json!([{"steps": 2}]),
            "motion_drift[0].error: missing",
        ),
        (
            |v| v["motion_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": -0.1}]),
            "motion_drift[0].exempt_above: the exemption threshold must be >= 0, found -0.1",
        ),
        (
            |v| v["motion_drift"] = json!([{"steps": 2, "error": 1, "t": 0.1}]),
            "motion_drift[0].t: unknown field",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": -3, "error": 0.1}]),
            "heading_drift[0].steps: expected an integer from 1 to 18446744073709551615, found -3",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2.5, "error": 0.1}]),
            "heading_drift[0].steps: expected an integer from 1 to 18446744073709551615, found 2.5",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2, "error": -0.1}]),
            "heading_drift[0].error: the drift bound must be >= 0, found -0.1",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2, "error": "NaN"}]),
            "heading_drift[0].error: expected a finite number, found a string",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2}]),
            "heading_drift[0].error: missing",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "k": 3}]),
            "heading_drift[0].k: unknown field",
        ),
        (
            |v| v["heading_drift"] = json!({"steps": 2, "error": 1}),
            "heading_drift: expected an array, found an object",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": -0.5}]),
            "heading_drift[0].exempt_above: the exemption threshold must be >= 0, found -0.5",
        ),
        (
            |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": "NaN"}]),
            "heading_drift[0].exempt_above: expected a finite number, found a string",
        ),
        (
            |v| {
                let w: Vec<Value> = (0..9)
                    .map(|x| json!({"steps": 2, "error": 1, "exempt_above": x}))
                    .collect();
                v["heading_drift"] = Value::Array(w);
            },
            "heading_drift[8].exempt_above: at most 8 distinct exempt_above values over the windows (one prefix array each), found a 9th: 8",
        ),
        (
            |v| v["model"] = json!("odometry3d"),
            "model: expected \"unicycle2d\", \"auv3d\" or \"odometry2d\", found \"odometry3d\"",
        ),
    ];
    let uni: Vec<(Edit, &str)> = vec![
        (
            |v| v["initial_heading"] = json!(0),
            "initial_heading: initial_heading is only for odometry2d missions",
        ),
        (
            |v| v["heading_error"] = json!(0),
            "heading_error: heading_error is only for odometry2d missions",
        ),
        (
            |v| v["heading_drift"] = json!([]),
            "heading_drift: heading_drift is only for odometry2d missions",
        ),
        (
            |v| v["motion_drift"] = json!([]),
            "motion_drift: motion_drift is only for odometry2d missions",
        ),
        (
            |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [0], "headings": [0, 0, 0]}),
            "truth.headings: truth.headings is only for odometry2d missions",
        ),
    ];
    for (base, cases) in [(odometry(), odo), (small(), uni)] {
        for (edit, expected) in cases {
            let mut v = base.clone();
            edit(&mut v);
            let e = Mission::from_value(&v).unwrap_err().to_string();
            assert!(
                e.starts_with(expected),
                "{e} does not start with {expected}"
            );
            let streamed = Mission::from_json(&v.to_string()).unwrap_err().to_string();
            assert_eq!(streamed, e, "parsed from text");
        }
    }
    // auv3d: no sensor offset.
    let mut o =
        crate::slam::simulate::SimulateOptions::new(crate::slam::simulate::Scenario::Auv, 1);
    o.steps = Some(5);
    let mut v = crate::slam::simulate::simulate(&o);
    v["sensor_offset"] = json!([0, 0]);
    let e = Mission::from_value(&v).unwrap_err().to_string();
    assert!(
        e.starts_with("sensor_offset: sensor_offset is only for the 2-D models"),
        "{e}"
    );
}

#[test]
fn streamed_missions_equal_parsed_values() {
    use crate::slam::simulate::{simulate, Scenario, SimulateOptions};
    for (scenario, seed, operator, false_detections) in [
        (Scenario::Paper, 1, false, 0),
        (Scenario::Paper, 2, true, 0),
        (Scenario::Paper, 3, false, 3),
        (Scenario::Auv, 4, true, 0),
    ] {
        let mut o = SimulateOptions::new(scenario, seed);
        o.steps = Some(800);
        o.operator = operator;
        o.false_detections = false_detections;
        let v = simulate(&o);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
        assert_eq!(m.truth.as_ref().unwrap().positions.len(), 801);
        // Through its own JSON again (inputs as lo/hi arrays).
        assert_eq!(Mission::from_json(&m.to_value().to_string()).unwrap(), m);
    }
}
