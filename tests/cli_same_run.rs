//! The data sets' importers are the calibration on the same run
//! (docs/calibration.md, "Same-run calibration"): `import --cmu-plaza`
//! gives the mission that the documented commands give (`calibrate
//! --convert`, `calibrate --same-run` with Plaza's flags, `import
//! --sensor-model`), bound for bound; a model with flagged steps is
//! refused on another run; the same-run flags are refused without
//! `--same-run`.

use nvector_tests::{nvector, read_json, temp_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn plaza() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    assert!(dir.exists(), "the data set must be at {}", dir.display());
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn nv(args: &[&str]) -> std::process::Output {
    nvector().args(args).output().expect("run nvector")
}

fn ok(args: &[&str]) {
    let o = nv(args);
    assert!(
        o.status.success(),
        "nvector {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The calibration CSVs of Plaza 1 over [from, to) in `dir`, and the flags
/// naming them.
fn csvs(dir: &Path, from: &str, to: &str) -> Vec<String> {
    ok(&[
        "calibrate",
        "--convert",
        "plaza",
        "--data",
        s(&plaza()),
        "--from",
        from,
        "--to",
        to,
        "--out-dir",
        s(dir),
    ]);
    ["log", "detections", "truth", "landmarks"]
        .iter()
        .flat_map(|f| {
            [
                format!("--{f}"),
                s(&dir.join(format!("{f}.csv"))).to_string(),
            ]
        })
        .collect()
}

/// `calibrate --same-run` with Plaza 1's settings (the table of
/// docs/calibration.md), written to `out`.
fn calibrate_like_plaza(files: &[String], out: &Path) -> std::process::Output {
    let mut args: Vec<&str> = vec!["calibrate", "--model", "unicycle2d"];
    args.extend(files.iter().map(String::as_str));
    args.extend([
        "--assume",
        "heading=0.02",
        "--same-run",
        "--margin",
        "0",
        "--constant-steps",
        "--still-below",
        "0.01",
        "--flag",
        "motion_error=0.02",
        "--flag-bound",
        "1.5,0.05",
        "--out",
        s(out),
    ]);
    nv(&args)
}

fn numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Number(n) => vec![n.as_f64().unwrap()],
        Value::Array(a) => a.iter().flat_map(numbers).collect(),
        Value::Object(o) => o.values().flat_map(numbers).collect(),
        _ => Vec::new(),
    }
}

#[test]
fn the_plaza_import_is_the_documented_same_run_calibration() {
    let dir = temp_dir("same-run-plaza");
    let files = csvs(&dir, "-1e300", "1e300");
    let model = dir.join("p.sensor.json");
    let o = calibrate_like_plaza(&files, &model);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let via_model = dir.join("via-model.json");
    let mut args = vec!["import", "--sensor-model", s(&model)];
    args.extend(files.iter().map(String::as_str));
    args.extend(["--out", s(&via_model)]);
    ok(&args);
    let imported = dir.join("imported.json");
    ok(&["import", "--cmu-plaza", s(&plaza()), "--out", s(&imported)]);
    let (a, b) = (read_json(&via_model), read_json(&imported));
    for key in [
        "dt",
        "steps",
        "initial_position",
        "inputs",
        "motion_error",
        "detections",
    ] {
        assert_eq!(numbers(&a[key]), numbers(&b[key]), "{key}");
    }
    assert_eq!(
        a["meta"]["sensor_model"]["flagged"],
        b["meta"]["sensor_model"]["flagged"]
    );
    // Both are said to be the oracle; the importer names its method.
    for m in [&a, &b] {
        assert_eq!(m["meta"]["calibration"]["same_run"], true);
    }
    let method = b["meta"]["calibration"]["method"].as_str().unwrap();
    assert!(method.starts_with("oracle"), "{method}");
    // The flagged steps are Plaza's anomalies: a few dozen to a few
    // hundred of 9657 steps (docs/cmu-plaza1.md lists the jumps and
    // skids), each bound above the ordinary one.
    let flagged = b["meta"]["sensor_model"]["flagged"]["motion"]
        .as_array()
        .unwrap();
    let ordinary = b["meta"]["ordinary_motion_error"].as_f64().unwrap();
    assert!((20..500).contains(&flagged.len()), "{}", flagged.len());
    assert!(flagged.iter().all(|f| f[1].as_f64().unwrap() > ordinary));
}

#[test]
fn flagged_steps_are_refused_on_another_run_and_without_same_run() {
    let dir = temp_dir("same-run-refused");
    let first = csvs(&dir.join("a"), "-1e300", "4300");
    let second = csvs(&dir.join("b"), "4300", "1e300");
    let model = dir.join("a.sensor.json");
    let o = calibrate_like_plaza(&first, &model);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut args = vec!["import", "--sensor-model", s(&model)];
    args.extend(second.iter().map(String::as_str));
    let o = nv(&args);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("flagged steps") && err.contains("this one"),
        "{err}"
    );
    // --flag without --same-run: a usage error naming the flag.
    let mut args = vec!["calibrate", "--model", "unicycle2d"];
    args.extend(first.iter().map(String::as_str));
    args.extend(["--assume", "heading=0.02", "--flag", "motion_error=0.02"]);
    let o = nv(&args);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--same-run"));
    // F = 0 is the same run's only.
    let mut args = vec!["calibrate", "--model", "unicycle2d"];
    args.extend(first.iter().map(String::as_str));
    args.extend(["--assume", "heading=0.02", "--margin", "0"]);
    let o = nv(&args);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--margin"));
}
