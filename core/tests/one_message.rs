//! One rule, one message: every bad value of an integer field (negative,
//! zero where the least is 1, fractional, above the largest, another
//! JSON type) gets the same message, `FIELD: expected an integer from MIN
//! to MAX, found X`, whether the JSON reader or the validation refuses it
//! (landmark_count -3 and 0 were "expected a non-negative integer" and
//! "must be at least 1").

use nvector_core::nvector::contract::ContractRequest;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest};
use nvector_core::tdoa::TdoaProblem;
use serde_json::{json, Value};

fn mission() -> Value {
    json!({
        "format": "nvector-mission/1", "model": "odometry2d", "dt": 0.5, "steps": 2,
        "initial_position": [[0, 0], [0, 0]], "initial_heading": [0, 0],
        "inputs": {"speed": {"value": [1.0, 2.0], "error": 0.1},
                   "turn_rate": {"value": [0.0, 0.1], "error": 0.1}},
        "heading_drift": [{"steps": 1, "error": 0.1}],
        "motion_drift": [{"steps": 1, "error": 0.1}],
        "detections": [{"step": 1, "range": [2, 3], "landmark": 0, "scan": 0}],
        "landmark_count": 2, "max_outliers": 0,
        "truth": {"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1], [2, 2]], "matching": [0]}
    })
}

/// Sets the value at a JSON path of the form `a.b[0].c`.
fn set(v: &mut Value, path: &str, x: Value) {
    let mut cur = v;
    for part in path.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, i)) => (n, Some(i.trim_end_matches(']').parse::<usize>().unwrap())),
            None => (part, None),
        };
        cur = &mut cur[name];
        if let Some(i) = index {
            cur = &mut cur[i];
        }
    }
    *cur = x;
}

/// The bad values of a field whose rule is `min..=max`, as JSON and as
/// the message prints them.
fn bad_values(min: u64, max: u64) -> Vec<(Value, String)> {
    let mut v = vec![
        (json!(-3), "-3".to_string()),
        (json!(-1.0), "-1.0".to_string()),
        (json!(1.5), "1.5".to_string()),
        (json!("7"), "a string".to_string()),
        (json!(true), "a boolean".to_string()),
        (json!([1]), "an array".to_string()),
    ];
    if min > 0 {
        v.push((json!(0), "0".to_string()));
        v.push((json!(min - 1), (min - 1).to_string()));
    }
    if max < u64::MAX {
        v.push((json!(max + 1), (max + 1).to_string()));
    }
    v
}

/// What a field's message adds after the value (the same for every bad
/// value).
fn suffix(path: &str) -> &'static str {
    match path {
        "detections[0].landmark" => " (ids are below landmark_count 2)",
        _ => "",
    }
}

fn assert_one_message(
    doc: &Value,
    path: &str,
    min: u64,
    max: u64,
    read: &dyn Fn(&Value) -> Result<(), String>,
) {
    for (x, shown) in bad_values(min, max) {
        let mut d = doc.clone();
        set(&mut d, path, x.clone());
        let e = read(&d).expect_err(&format!("{path} = {x} accepted"));
        assert_eq!(
            e,
            format!(
                "{path}: expected an integer from {min} to {max}, found {shown}{}",
                suffix(path)
            ),
            "{path} = {x}"
        );
    }
    // The least value itself is not refused for this field (the rest of
    // the document may refuse it: steps 1 with inputs of 2 steps).
    let mut d = doc.clone();
    set(&mut d, path, json!(min));
    if let Err(e) = read(&d) {
        assert!(
            !e.starts_with(&format!("{path}:")),
            "{path} = {min} refused: {e}"
        );
    }
}

#[test]
fn every_integer_field_of_a_mission_has_one_message() {
    let read = |v: &Value| {
        Mission::from_value(v)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let read_text = |v: &Value| {
        Mission::from_json(&v.to_string())
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let u32max = u32::MAX as u64;
    let fields: [(&str, u64, u64); 9] = [
        ("steps", 1, 2_000_000),
        ("landmark_count", 1, u32max),
        ("max_outliers", 0, u32max),
        ("detections[0].step", 0, 2),
        ("detections[0].landmark", 0, 1),
        ("detections[0].scan", 0, u64::MAX),
        ("heading_drift[0].steps", 1, u64::MAX),
        ("motion_drift[0].steps", 1, u64::MAX),
        ("truth.matching[0]", 0, 1),
    ];
    for (path, min, max) in fields {
        let doc = mission();
        if path == "landmark_count" {
            // Its ids are then checked against it: the detection has none.
            let mut d = doc.clone();
            d["detections"][0]
                .as_object_mut()
                .unwrap()
                .remove("landmark");
            assert_one_message(&d, path, min, max, &read);
            assert_one_message(&d, path, min, max, &read_text);
            continue;
        }
        assert_one_message(&doc, path, min, max, &read);
        assert_one_message(&doc, path, min, max, &read_text);
    }
}

#[test]
fn the_requests_integer_fields_have_one_message() {
    let limits = SimulateLimits::CORE;
    let simulate = |v: &Value| {
        let r: SimulateRequest = nvector_core::format::from_value(v).map_err(|e| e.to_string())?;
        r.options(limits).map(|_| ()).map_err(|e| e.to_string())
    };
    let doc = json!({"scenario": "paper", "steps": 10, "landmarks": 2, "seed": 1});
    assert_one_message(&doc, "steps", 2, limits.max_steps, &simulate);
    assert_one_message(&doc, "landmarks", 1, 64, &simulate);
    assert_one_message(&doc, "seed", 0, u64::MAX, &simulate);
    let contract = |v: &Value| {
        ContractRequest::from_value(v)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let doc = json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]]});
    assert_one_message(&doc, "n", 1, u32::MAX as u64, &contract);
    let tdoa = |v: &Value| {
        TdoaProblem::from_value(v)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let doc = json!({
        "format": "nvector-tdoa/1", "propagation_speed": [299000000, 300000000],
        "receivers": [{"position": [[0, 1], [0, 1], [0, 0]]}, {"position": [[5, 6], [0, 1], [0, 0]]}],
        "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 1]}, {"receiver": 1, "time": 2}]}],
        "emitter_count": 1, "max_outliers": 0
    });
    assert_one_message(&doc, "emitter_count", 1, 1 << 20, &tdoa);
    assert_one_message(&doc, "max_outliers", 0, u32::MAX as u64, &tdoa);
}
