//! `nvector run --threads`, through the real binary: the result is the
//! same bytes (its `elapsed_ms` aside) with 1 and 2 threads on a mission
//! where `best` shares work between threads (the paper scenario, range
//! only, random layout, ids hidden: several registrations and groups'
//! pieces per round), and a count of 0 is a usage error naming the flag.

use nvector_tests::{read_json, run, succeeded, temp_file};
use serde_json::Value;

/// The result without its time.
fn timeless(mut v: Value) -> Value {
    if let Some(m) = v["metrics"].as_object_mut() {
        m.remove("elapsed_ms");
    }
    v
}

#[test]
fn run_gives_the_same_result_with_1_and_2_threads() {
    let m = temp_file("threads-mission.json");
    succeeded(&run(&[
        "simulate",
        "--scenario",
        "paper",
        "--seed",
        "3",
        "--steps",
        "2000",
        "--layout",
        "random",
        "--range-only",
        "--out",
        m.to_str().unwrap(),
    ]));
    let results: Vec<Value> = ["1", "2"]
        .iter()
        .map(|t| {
            let r = temp_file(&format!("threads-result-{t}.json"));
            succeeded(&run(&[
                "run",
                m.to_str().unwrap(),
                "--contractor",
                "best",
                "--threads",
                t,
                "--out",
                r.to_str().unwrap(),
            ]));
            timeless(read_json(&r))
        })
        .collect();
    assert!(
        results[0]["matching"]
            .as_array()
            .is_some_and(|g| !g.is_empty()),
        "no group proved: the threads had nothing to share"
    );
    assert!(
        results[0] == results[1],
        "1 and 2 threads give other results"
    );
}

#[test]
fn run_refuses_zero_threads() {
    let out = run(&["run", "missing.json", "--threads", "0"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--threads"), "{err}");
}
