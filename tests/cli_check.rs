//! `nvector check MISSION.json [--json]`: the constraints a mission's truth
//! breaks. Truthful missions (simulated, and the real data sets imported
//! with bounds fitted on their truth) break none (exit 0); a bound moved
//! past the truth is named with its path and excess (exit 1); usage errors
//! exit 2, bad input 1 naming the file and the JSON path. And `run`'s
//! summary says where a mission's bounds come from (`meta.calibration`).

use nvector_tests::{nvector, read_json, run, succeeded, temp_file};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

fn write(name: &str, v: &Value) -> PathBuf {
    let p = temp_file(name);
    std::fs::write(&p, v.to_string()).unwrap();
    p
}

fn simulated(scenario: &str, extra: &[&str]) -> Value {
    let out = temp_file("m.json");
    let mut args = vec![
        "simulate",
        "--scenario",
        scenario,
        "--seed",
        "5",
        "--steps",
        "400",
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", out.to_str().unwrap()]);
    succeeded(&run(&args));
    read_json(&out)
}

fn check(path: &Path, json: bool) -> (i32, String, String) {
    let mut args = vec!["check", path.to_str().unwrap()];
    if json {
        args.push("--json");
    }
    let o = run(&args);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).to_string(),
        String::from_utf8_lossy(&o.stderr).to_string(),
    )
}

#[test]
fn simulated_missions_break_nothing() {
    for (scenario, extra) in [
        ("paper", vec!["--operator"]),
        ("paper", vec![]),
        ("woods", vec!["--false-detections", "2"]),
        ("auv", vec![]),
    ] {
        let p = write("m.json", &simulated(scenario, &extra));
        let (code, out, err) = check(&p, false);
        assert_eq!(code, 0, "{scenario}: {out}{err}");
        assert!(
            err.contains("the truth satisfies every constraint checked"),
            "{err}"
        );
        let (code, out, _) = check(&p, true);
        assert_eq!(code, 0);
        let v: Value = serde_json::from_str(&out).unwrap();
        let broken: Vec<&Value> = v["violations"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|v| v["outlier"] != json!(true))
            .collect();
        assert!(broken.is_empty(), "{scenario}: {broken:?}");
    }
}

#[test]
fn a_planted_violation_is_named_with_its_path_and_excess() {
    let mut m = simulated("paper", &["--operator"]);
    let range = &m["detections"][1]["range"];
    let (lo, hi) = (range[0].as_f64().unwrap(), range[1].as_f64().unwrap());
    m["detections"][1]["range"] = json!([hi + 1.5, hi + 2.0]);
    let x0 = m["truth"]["positions"][0][0].as_f64().unwrap();
    m["initial_position"][0] = json!([x0 - 1.0, x0 - 0.25]);
    let p = write("bad.json", &m);
    let (code, out, err) = check(&p, false);
    assert_eq!(code, 1, "{out}{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    assert!(
        lines[0].starts_with("initial_position[0]: initial_position "),
        "{out}"
    );
    assert!(lines[0].ends_with(" m (step 0)"), "{out}");
    assert!(lines[1].starts_with("detections[1].range: range "), "{out}");
    assert!(err.contains("the truth breaks 2 constraints"), "{err}");
    let (code, out, _) = check(&p, true);
    assert_eq!(code, 1);
    let v: Value = serde_json::from_str(&out).unwrap();
    let vs = v["violations"].as_array().unwrap();
    assert_eq!(vs[0]["path"], "initial_position[0]");
    assert!((vs[0]["excess"].as_f64().unwrap() - 0.25).abs() < 1e-12);
    assert_eq!(vs[0]["bound"], json!([x0 - 1.0, x0 - 0.25]));
    assert_eq!(vs[1]["path"], "detections[1].range");
    assert_eq!(vs[1]["kind"], "range");
    assert_eq!(vs[1]["detection"], 1);
    // The truth's distance is in the original range [lo, hi].
    let excess = vs[1]["excess"].as_f64().unwrap();
    assert!(
        excess >= 1.5 - 1e-9 && excess <= 1.5 + (hi - lo) + 1e-9,
        "{excess}"
    );
}

#[test]
fn usage_and_bad_input() {
    let o = nvector().args(["check"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    let o = nvector()
        .args(["check", "x.json", "--jsn"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let missing = temp_file("absent.json");
    let (code, _, err) = check(&missing, false);
    assert_eq!(code, 1);
    assert!(err.contains("absent.json"), "{err}");
    let mut m = simulated("paper", &[]);
    m["detections"][1]["range"] = json!([3, 2]);
    let p = write("inverted.json", &m);
    let (code, _, err) = check(&p, false);
    assert_eq!(code, 1);
    assert!(
        err.contains("inverted.json: detections[1].range: lower bound 3 is above upper bound 2"),
        "{err}"
    );
    m.as_object_mut().unwrap().remove("truth");
    m["detections"][1]["range"] = json!([2, 3]);
    let p = write("no-truth.json", &m);
    let (code, _, err) = check(&p, false);
    assert_eq!(code, 1);
    assert!(
        err.contains("no-truth.json: truth: the mission has no truth"),
        "{err}"
    );
}

fn import(flag: &str, dir: &str, operator: bool) -> PathBuf {
    let data = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(dir);
    let out = temp_file("imported.json");
    let mut args = vec![
        "import",
        flag,
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    if operator {
        args.push("--operator");
    }
    succeeded(&run(&args));
    out
}

/// The importers fit every bound on the data's own truth: the truth
/// breaks none of them.
#[test]
fn the_real_data_sets_break_nothing() {
    for (flag, dir) in [
        ("--cmu-plaza", "cmu-plaza1"),
        ("--utias-woods", "utias-lost-in-the-woods"),
    ] {
        for operator in [false, true] {
            let p = import(flag, dir, operator);
            let (code, out, err) = check(&p, true);
            let v: Value = serde_json::from_str(&out).unwrap_or(Value::Null);
            assert_eq!(code, 0, "{dir} (operator {operator}): {err} {v}");
            assert_eq!(v["violations"], json!([]), "{dir}: {err}");
        }
    }
}

/// `run`'s summary: bounds calibrated on another run are said to be so.
#[test]
fn run_says_where_the_bounds_come_from() {
    let mut m = simulated("paper", &["--operator"]);
    m["meta"]["calibration"] = json!({"source": "paper seed 4", "same_run": false});
    let p = write("other.json", &m);
    let o = run(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        temp_file("r.json").to_str().unwrap(),
    ]);
    let err = succeeded(&o);
    assert!(
        err.contains(
            "bounds calibrated on another run (paper seed 4): truth check not a guarantee"
        ),
        "{err}"
    );
    m["meta"]["calibration"] = json!({"source": "this run", "same_run": true});
    let p = write("same.json", &m);
    let o = run(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        temp_file("r.json").to_str().unwrap(),
    ]);
    assert!(succeeded(&o).contains("bounds fitted on this run's truth"));
}
