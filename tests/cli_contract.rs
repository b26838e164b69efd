//! `nvector contract` through the real binary: stdin -> stdout, errors on
//! stderr naming the JSON path, exit codes 0 / 1 / 2.

use std::io::Write;
use std::process::{Output, Stdio};

fn contract(args: &[&str], stdin: &str) -> Output {
    let mut child = nvector_tests::nvector()
        .arg("contract")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run nvector");
    // A usage error ends the process before it reads its input: the pipe
    // is then closed, which is not the test's failure (the exit code is
    // what the tests check).
    match child.stdin.take().unwrap().write_all(stdin.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        other => other.unwrap(),
    }
    child.wait_with_output().unwrap()
}

const SPEC_EXAMPLE: &str = r#"{
  "format": "nvector-contract/1",
  "n": 2,
  "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]],
  "contractor": "projection"
}"#;

#[test]
fn spec_example_gives_the_spec_response() {
    let out = contract(&[], SPEC_EXAMPLE);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["format"], "nvector-contract-result/1");
    assert_eq!(v["status"], "contracted");
    assert_eq!(v["groups"], serde_json::json!([[0, 1], [2]]));
    assert_eq!(v["boxes"][0], serde_json::json!([[1.0, 2.0], [1.0, 2.0]]));
    assert!(v["stats"]["elapsed_us"].is_u64());
}

#[test]
fn contractor_flag_overrides_and_is_validated() {
    let out = contract(&["--contractor", "exact"], SPEC_EXAMPLE);
    assert!(out.status.success());
    let out = contract(&["--contractor", "fastest"], SPEC_EXAMPLE);
    assert_eq!(
        out.status.code(),
        Some(2),
        "unknown contractor is a usage error"
    );
}

#[test]
fn bad_input_exits_1_naming_the_path() {
    let bad = r#"{"format": "nvector-contract/1", "n": 2, "boxes": [[[0, 1]], [[5, 4]]]}"#;
    let out = contract(&[], bad);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("boxes[1][0]: lower bound 5 is above upper bound 4"),
        "{err}"
    );
    let out = contract(&[], "{not json");
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("invalid JSON"));
    // A repeated key was read as its last value (n = 5 here): refused,
    // named, as the service refuses it.
    let twice =
        r#"{"format": "nvector-contract/1", "n": 1, "n": 5, "boxes": [[[0, 1]], [[5, 6]]]}"#;
    let out = contract(&[], twice);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("n: duplicate key"), "{err}");
}

#[test]
fn infeasible_is_a_result_not_an_error() {
    let req = r#"{"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]], [[2, 3]]]}"#;
    let out = contract(&[], req);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "infeasible");
}

#[test]
fn exact_out_of_its_work_budget_exits_1_naming_the_limit() {
    // A small budget keeps the test quick (the default, 16 million nodes,
    // answers in about 1.5 s on a release build).
    let out = contract(
        &["--contractor", "exact", "--node-budget", "100000"],
        &nvector_tests::worst_case_contract(None).to_string(),
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the exact contractor ran out of its work budget (100000 search nodes)"),
        "{err}"
    );
    // A polynomial contractor answers the same request.
    let out = contract(
        &["--contractor", "best", "--node-budget", "100000"],
        &nvector_tests::worst_case_contract(None).to_string(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
