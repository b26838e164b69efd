//! The differential test of the format layer's path-tracking reader
//! (`format::from_value`, `format/tracked.rs`) against the reader it
//! replaced (serde_path_to_error over serde_json's `&Value`, kept natively
//! as `format::from_value_reference`): over many bad documents (every
//! value of valid missions, simulation requests, contraction requests and
//! TDOA problems replaced by values of every JSON kind, removed, or given
//! an unknown neighbour; nested arrays; leaf types alone) both must
//! accept the same documents and refuse the others with the same path and
//! the same message, byte for byte.

use nvector_core::format::contract::ContractDoc;
use nvector_core::format::leaf::{
    BoxIn, Finite, Integer, IntervalIn, List, Numbers, PerStep, PointsIn,
};
use nvector_core::format::mission_doc::MissionDoc;
use nvector_core::format::tdoa::TdoaDoc;
use nvector_core::format::{from_value, from_value_reference, Object};
use nvector_core::slam::simulate::{simulate, SimulateLimits, SimulateRequest};
use serde::de::DeserializeOwned;
use serde_json::{json, Value};

/// The outcome of one reader: accepted, or the error's path and message.
fn outcome<T>(r: Result<T, nvector_core::InputError>) -> Result<(), (String, String)> {
    r.map(|_| ()).map_err(|e| (e.path, e.message))
}

/// Both readers over `doc`; panics naming the document when they differ.
/// Returns whether the document was refused.
fn same<T: DeserializeOwned>(doc: &Value) -> bool {
    let new = outcome(from_value::<T>(doc));
    let old = outcome(from_value_reference::<T>(doc));
    assert_eq!(
        new,
        old,
        "the readers differ on {} for {}",
        std::any::type_name::<T>(),
        doc
    );
    new.is_err()
}

/// The values every node is replaced by: one of each JSON kind, numbers
/// of every sort, the formats' special strings, nested arrays, objects.
fn replacements() -> Vec<Value> {
    vec![
        json!(null),
        json!(true),
        json!(false),
        json!(0),
        json!(3),
        json!(-1),
        json!(-3.0),
        json!(1.5),
        json!(-0.0),
        json!(1e300),
        json!(18446744073709551615u64),
        json!(-9223372036854775808i64),
        json!(3.0),
        json!("x"),
        json!(""),
        json!("empty"),
        json!("inf"),
        json!("-inf"),
        json!([]),
        json!([1]),
        json!([1, 2]),
        json!([2, 1]),
        json!([1, 2, 3]),
        json!(["-inf", "inf"]),
        json!([[0, 1], [2, 3]]),
        json!([[0, 1], "x"]),
        json!([[[]]]),
        json!([null]),
        json!([[1, 2], [3]]),
        json!({}),
        json!({"a": 1}),
        json!({"value": [1], "error": 0.1}),
    ]
}

/// Every node of `doc`, as a JSON pointer.
fn pointers(doc: &Value, at: String, out: &mut Vec<String>) {
    match doc {
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                pointers(x, format!("{at}/{i}"), out);
            }
        }
        Value::Object(m) => {
            for (k, x) in m {
                pointers(x, format!("{at}/{k}"), out);
            }
        }
        _ => {}
    }
    out.push(at);
}

/// Every mutation of `doc`: each node replaced by each replacement, each
/// object entry removed, an unknown field added to each object. Runs `T`'s
/// two readers over each; returns (documents, refused).
fn mutate<T: DeserializeOwned>(doc: &Value) -> (usize, usize) {
    let mut ps = Vec::new();
    pointers(doc, String::new(), &mut ps);
    let (mut n, mut refused) = (0, 0);
    let mut run = |d: &Value| {
        n += 1;
        refused += usize::from(same::<T>(d));
    };
    run(doc);
    for p in &ps {
        for r in replacements() {
            let mut d = doc.clone();
            *d.pointer_mut(p).unwrap() = r;
            run(&d);
        }
        let mut d = doc.clone();
        match d.pointer_mut(p).unwrap() {
            Value::Object(m) => {
                let keys: Vec<String> = m.keys().cloned().collect();
                m.insert("rnage".into(), json!(1));
                run(&d);
                for k in keys {
                    let mut e = doc.clone();
                    e.pointer_mut(p)
                        .unwrap()
                        .as_object_mut()
                        .unwrap()
                        .remove(&k);
                    run(&e);
                }
            }
            Value::Array(a) => {
                a.push(json!(7));
                run(&d);
                let mut e = doc.clone();
                e.pointer_mut(p).unwrap().as_array_mut().unwrap().clear();
                run(&e);
            }
            _ => {}
        }
    }
    (n, refused)
}

/// A small simulated mission of each scenario (with its truth).
fn missions() -> Vec<Value> {
    let requests = [
        json!({"scenario": "paper", "steps": 3, "landmarks": 2}),
        json!({"scenario": "paper", "steps": 3, "landmarks": 2, "operator": true, "false_detections": 1}),
        json!({"scenario": "auv", "steps": 2}),
        json!({"scenario": "woods", "steps": 2}),
    ];
    requests
        .iter()
        .map(|r| {
            let Object(req) = from_value::<Object<SimulateRequest>>(r).unwrap();
            let mut m = simulate(&req.options(SimulateLimits::CORE).unwrap());
            // Keep the documents small: at most 4 detections.
            if let Some(d) = m["detections"].as_array_mut() {
                d.truncate(4);
            }
            if let Some(t) = m["truth"]["matching"].as_array_mut() {
                t.truncate(4);
            }
            m
        })
        .collect()
}

#[test]
fn missions_read_the_same() {
    let (mut n, mut refused) = (0, 0);
    for m in missions() {
        let (a, b) = mutate::<MissionDoc>(&m);
        n += a;
        refused += b;
    }
    // The mutations must exercise the error paths, not only valid reads.
    assert!(
        n > 5_000 && refused > n / 2,
        "{n} documents, {refused} refused"
    );
}

#[test]
fn simulation_requests_read_the_same() {
    let doc = json!({"scenario": "paper", "seed": 3, "steps": 10, "landmarks": 4,
        "operator": false, "noise": 1.0, "layout": "ring", "range_only": false,
        "false_detections": 2});
    let (n, refused) = mutate::<Object<SimulateRequest>>(&doc);
    // Four of its eight fields are integers, whose values (negative,
    // fractional, another type) the validation refuses, not the reader
    // (one message per rule, `Integer::in_range`): a third is refused here.
    assert!(
        n > 300 && refused > n / 3,
        "{n} documents, {refused} refused"
    );
}

#[test]
fn contraction_requests_read_the_same() {
    let doc = json!({"format": "nvector-contract/1", "n": 2, "contractor": "best",
        "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]]});
    let (n, refused) = mutate::<ContractDoc>(&doc);
    assert!(
        n > 500 && refused > n / 2,
        "{n} documents, {refused} refused"
    );
}

#[test]
fn tdoa_problems_read_the_same() {
    let doc = json!({
        "format": "nvector-tdoa/1", "name": "t", "propagation_speed": [299000000, 300000000],
        "receivers": [{"position": [[0, 1], [0, 1], [0, 0]], "clock_bias": [0, 0]},
                      {"position": [[5, 6], [0, 1], [0, 0]]}],
        "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 1]}, {"receiver": 1, "time": 2}],
                    "altitude": [0, 100], "region": [[-10, 10], [-10, 10], [0, 100]], "emitter": 0,
                    "distance_from": {"point": [[0, 0], [0, 0], [0, 0]], "range": [1, 2]}}],
        "emitter_count": 1, "emitter_region": [[-10, 10], [-10, 10], [0, 100]], "max_outliers": 0,
        "meta": {"k": [1, {"z": null}]},
        "truth": {"positions": [[1, 2, 3], null], "emitters": [[1, 2, 3]], "matching": [0, null]}
    });
    let (n, refused) = mutate::<TdoaDoc>(&doc);
    assert!(
        n > 1_000 && refused > n / 2,
        "{n} documents, {refused} refused"
    );
}

#[test]
fn leaf_values_read_the_same() {
    let mut refused = 0;
    let mut docs = replacements();
    docs.extend([
        json!([[1, 2], [3, 4], null, [5]]),
        json!([[1, 2, 3, 4], [1, "x"]]),
        json!([1, [2], {"a": []}]),
        json!([[0, 1], [0, 1, 2]]),
        json!([["-inf", 3], ["inf", "inf"]]),
        json!([1, 2, null]),
    ]);
    for d in &docs {
        refused += usize::from(same::<IntervalIn>(d));
        refused += usize::from(same::<BoxIn>(d));
        refused += usize::from(same::<Integer>(d));
        refused += usize::from(same::<Finite>(d));
        refused += usize::from(same::<PerStep>(d));
        refused += usize::from(same::<PointsIn>(d));
        refused += usize::from(same::<Numbers>(d));
        refused += usize::from(same::<List<Option<Integer>>>(d));
        refused += usize::from(same::<List<BoxIn>>(d));
        refused += usize::from(same::<Option<String>>(d));
        refused += usize::from(same::<Value>(d));
    }
    assert!(refused > docs.len() * 5, "{refused} refused");
}

/// The messages in full, as formats.md words them (written by hand, not
/// copied from a run): a path into nested objects, into an array of
/// objects, into an array of numbers.
#[test]
fn mission_errors_name_the_path_in_full() {
    use nvector_core::slam::mission::Mission;
    let mission = |inputs: &str, detections: &str| {
        let text = format!(
            r#"{{"format": "nvector-mission/1", "model": "unicycle2d", "dt": 1, "steps": 1,
            "initial_position": [[0, 0], [0, 0]], "inputs": {inputs}, "detections": {detections}}}"#
        );
        let v: Value = serde_json::from_str(&text).unwrap();
        Mission::from_value(&v).err().unwrap().to_string()
    };
    assert_eq!(
        mission(
            r#"{"speed": {"value": [1], "eror": 0.1}, "heading": {"value": [0], "error": 0}}"#,
            "[]"
        ),
        "inputs.speed.eror: unknown field `eror` (expected one of: value, error, lo, hi)"
    );
    assert_eq!(
        mission(
            r#"{"speed": {"value": [1], "error": 0}, "heading": {"value": [0], "error": 0}}"#,
            r#"[{"step": 1, "range": [1, 2]}, {"step": 0, "range": [3, 2]}]"#
        ),
        "detections[1].range: lower bound 3 is above upper bound 2"
    );
    assert_eq!(
        mission(r#"{"speed": {"value": [1, "x"], "error": 0}}"#, "[]"),
        "inputs.speed.value[1]: expected a finite number, found a string"
    );
}
