//! `nvector calibrate` and `nvector import --sensor-model` on the real
//! data: Lost in the Woods calibrated on its first 630 s, a short window
//! after it imported with that model and the operator's ids and solved
//! (`best`): consistent, the truth inside. CMU Plaza 1, whose truth heading
//! is its integrated odometry heading, is refused a heading bound, naming
//! the reason.

use nvector_tests::{nvector, read_json, temp_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(name);
    assert!(dir.exists(), "the data set must be at {}", dir.display());
    dir
}

fn ok(args: &[&str]) -> String {
    let o = nvector().args(args).output().expect("run nvector");
    assert!(
        o.status.success(),
        "nvector {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The four CSVs of a data set over [from, to).
fn convert(kind: &str, dir: &Path, from: &str, to: &str, out: &Path) {
    ok(&[
        "calibrate",
        "--convert",
        kind,
        "--data",
        s(dir),
        "--from",
        from,
        "--to",
        to,
        "--out-dir",
        s(out),
    ]);
    for f in ["log.csv", "detections.csv", "truth.csv", "landmarks.csv"] {
        assert!(out.join(f).exists(), "{f}");
    }
}

fn files(dir: &Path) -> Vec<String> {
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

#[test]
fn woods_calibrated_on_its_first_630_s_solves_a_later_window_with_the_truth_inside() {
    let tmp = temp_dir("calibrate-woods");
    let (cal, sol) = (tmp.join("cal"), tmp.join("sol"));
    let woods = data("utias-lost-in-the-woods");
    convert("woods", &woods, "0", "630", &cal);
    convert("woods", &woods, "630", "660", &sol);
    let sensor = tmp.join("sensor.json");
    let mut args = vec!["calibrate", "--model", "odometry2d"];
    let f = files(&cal);
    args.extend(f.iter().map(String::as_str));
    args.extend(["--sensor-offset", "0.219016,0", "--out", s(&sensor)]);
    let stderr = ok(&args);
    // Windows longer than the data can support are left out, named.
    assert!(stderr.contains("too few samples"), "{stderr}");
    let model = read_json(&sensor);
    assert_eq!(model["format"], "nvector-sensor-model/1");
    assert_eq!(model["calibration"]["steps"], 6300);
    assert_eq!(model["calibration"]["min_samples"], 73);
    for b in ["heading", "motion_error", "range", "bearing"] {
        assert_eq!(model[b]["fit"]["coverage"], 1.0, "{b}");
        assert!(
            model[b]["fit"]["method"].as_str().unwrap().len() > 20,
            "{b}"
        );
    }
    assert!(!model["heading_drift"].as_array().unwrap().is_empty());

    let mission = tmp.join("mission.json");
    let mut args = vec!["import", "--sensor-model", s(&sensor)];
    let f = files(&sol);
    args.extend(f.iter().map(String::as_str));
    args.extend(["--operator", "--out", s(&mission)]);
    ok(&args);
    let m = read_json(&mission);
    assert_eq!(m["model"], "odometry2d");
    assert_eq!(m["steps"], 300);
    let c = &m["meta"]["calibration"];
    assert_eq!(c["same_run"], false);
    assert!(c["source"].as_str().unwrap().contains("cal/log.csv"), "{c}");
    assert!(m["detections"][0]["landmark"].is_u64());
    assert_eq!(m["sensor_offset"], serde_json::json!([0.219016, 0.0]));

    let result = tmp.join("result.json");
    ok(&[
        "run",
        s(&mission),
        "--contractor",
        "best",
        "--out",
        s(&result),
    ]);
    let r: Value = read_json(&result);
    assert_eq!(r["status"], "consistent", "{}", r["reason"]);
    assert_eq!(r["score"]["truth_inside"], true, "{}", r["score"]);

    // The model applied to its own run says so.
    let own = tmp.join("own.json");
    let mut args = vec!["import", "--sensor-model", s(&sensor)];
    let f = files(&cal);
    args.extend(f.iter().map(String::as_str));
    args.extend(["--out", s(&own)]);
    ok(&args);
    assert_eq!(read_json(&own)["meta"]["calibration"]["same_run"], true);
}

#[test]
fn plaza_is_refused_a_heading_bound_its_truth_cannot_support() {
    let tmp = temp_dir("calibrate-plaza");
    let cal = tmp.join("cal");
    convert("plaza", &data("cmu-plaza1"), "3800", "4300", &cal);
    let sensor = tmp.join("sensor.json");
    let f = files(&cal);
    let mut args = vec!["calibrate", "--model", "unicycle2d"];
    args.extend(f.iter().map(String::as_str));
    args.extend(["--out", s(&sensor)]);
    let o = nvector().args(&args).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("heading residual identically 0") && e.contains("derived from this channel"),
        "{e}"
    );
    assert!(!sensor.exists());
    // A margin for a bound the model does not have, or not a number: named.
    for (flag, what) in [
        ("bogus=1", "no bound 'bogus'"),
        ("range=x", "F must be a number"),
    ] {
        let mut bad = args.clone();
        bad.extend(["--assume", "heading=0.02", "--margin", flag]);
        let o = nvector().args(&bad).output().unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(e.contains(what), "{flag}: {e}");
    }
    // Stated instead: a model, the heading marked as assumed.
    args.extend(["--assume", "heading=0.02"]);
    ok(&args);
    let m = read_json(&sensor);
    assert_eq!(m["heading"]["constant"], 0.02);
    assert!(m["heading"]["fit"]["method"]
        .as_str()
        .unwrap()
        .starts_with("assumed"));
    // The log never reports a negative speed and the truth backs up: the
    // sign is unknown below a fitted speed.
    let below = m["speed"]["sign_unknown_below"].as_f64().unwrap();
    assert!(below > 0.0);
    // Applied to its own run: a valid unicycle2d mission, the slow steps'
    // speed of either sign, marked as the oracle mode.
    let mission = tmp.join("mission.json");
    let mut args = vec!["import", "--sensor-model", s(&sensor)];
    args.extend(f.iter().map(String::as_str));
    args.extend(["--out", s(&mission)]);
    ok(&args);
    let mm = read_json(&mission);
    assert_eq!(mm["model"], "unicycle2d");
    assert_eq!(mm["meta"]["calibration"]["same_run"], true);
    assert_eq!(mm["inputs"]["heading"]["error"], 0.02);
    let (lo, hi) = (&mm["inputs"]["speed"]["lo"], &mm["inputs"]["speed"]["hi"]);
    let slow = (0..mm["steps"].as_u64().unwrap() as usize)
        .find(|&i| hi[i].as_f64().unwrap() > 0.0 && hi[i].as_f64().unwrap() < below)
        .expect("a slow step");
    assert_eq!(lo[slow].as_f64().unwrap(), -hi[slow].as_f64().unwrap());
    // Its own truth breaks none of its bounds: --verify exits 0.
    let mut args = vec!["calibrate", "--model", "unicycle2d", "--verify", s(&sensor)];
    args.extend(f.iter().map(String::as_str));
    let out = nvector().args(&args).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["outside"], 0);
}

#[test]
fn a_bad_sensor_model_or_csv_is_named() {
    let tmp = temp_dir("calibrate-bad");
    let log = tmp.join("log.csv");
    std::fs::write(&log, "t,speed,turn_rate\n0,1,0\n0.1,x,0\n").unwrap();
    std::fs::write(tmp.join("det.csv"), "t,range,landmark\n0,1,0\n").unwrap();
    let o = nvector()
        .args([
            "calibrate",
            "--model",
            "odometry2d",
            "--log",
            s(&log),
            "--detections",
        ])
        .arg(tmp.join("det.csv"))
        .args(["--truth", s(&log), "--landmarks", s(&log)])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("log.csv:3: column 2 (speed): 'x' is not a finite number"),
        "{e}"
    );
    let bad = tmp.join("bad.json");
    std::fs::write(&bad, "{\"format\": \"nvector-sensor-model/1\"}").unwrap();
    let o = nvector()
        .args([
            "import",
            "--sensor-model",
            s(&bad),
            "--log",
            s(&log),
            "--detections",
        ])
        .arg(tmp.join("det.csv"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("bad.json") && e.contains("missing field"), "{e}");
}
