//! The CLI talks back, through the real binary: `run`'s summary
//! line, `bench`'s goal marks and its refusal of an unknown `--only`,
//! negative numbers at the start of a value list, and `plot`'s warning on
//! a result that is not of the mission.

use nvector_tests::{read_json, run, succeeded, temp_file};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn simulate(name: &str, steps: &str, seed: &str) -> PathBuf {
    let m = temp_file(name);
    succeeded(&run(&[
        "simulate",
        "--scenario",
        "paper",
        "--seed",
        seed,
        "--steps",
        steps,
        "--out",
        m.to_str().unwrap(),
    ]));
    m
}

#[test]
fn run_ends_with_a_summary_line() {
    let m = simulate("sum.json", "400", "2");
    let r = temp_file("sum-result.json");
    let err = succeeded(&run(&[
        "run",
        m.to_str().unwrap(),
        "--out",
        r.to_str().unwrap(),
    ]));
    let result = read_json(&r);
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line on stderr: {err}");
    let line = lines[0];
    let metrics = &result["metrics"];
    let max = metrics["max_trajectory_diameter"].as_f64().unwrap();
    let mean = metrics["mean_trajectory_diameter"].as_f64().unwrap();
    // The figures of the result file, rounded to metres as a person reads them.
    let max_text = nvector_core::figure::metres(Some(max));
    let mean_text = nvector_core::figure::metres(Some(mean));
    assert!(max_text.ends_with(" m") && mean_text.ends_with(" m"));
    assert!(
        line.starts_with(&format!(
            "nvector: {}; max trajectory diameter {max_text}, mean {mean_text};",
            result["status"].as_str().unwrap()
        )),
        "{line}"
    );
    let matched = metrics["matched_detections"].as_u64().unwrap();
    let detections = result["detections"].as_array().unwrap().len();
    assert!(
        line.contains(&format!("{matched} of {detections} detections matched")),
        "{line}"
    );
    assert_eq!(result["score"]["truth_inside"], true);
    assert!(line.contains("; truth inside;"), "{line}");
    assert!(
        line.contains(&format!("result in {}", r.display())),
        "{line}"
    );
    // The time, in seconds with two decimals.
    let secs = line
        .split("; ")
        .find(|p| p.ends_with(" s"))
        .and_then(|p| p.trim_end_matches(" s").parse::<f64>().ok());
    assert!(secs.is_some_and(|s| s >= 0.0), "{line}");
}

#[test]
fn bench_refuses_an_unknown_only_and_names_the_measures() {
    let out = run(&["bench", "--quick", "--only", "nonexistent"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("'nonexistent' names no measure"), "{err}");
    for name in [
        "nvalue_1e6_quick",
        "paper_fixpoint_quick",
        "paper_seeds_1_10_quick",
    ] {
        assert!(err.contains(name), "{name} not in: {err}");
    }
}

#[test]
fn bench_marks_each_line_against_its_goal() {
    let out = run(&["bench", "--quick", "--only", "nvalue_1e6"]);
    let err = succeeded(&out);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 1, "{stdout}");
    let v = &lines[0];
    assert_eq!(v["name"], "nvalue_1e6_quick");
    let (ratio, goal) = (v["ratio"].as_f64().unwrap(), v["goal"].as_f64().unwrap());
    assert_eq!(v["meets_goal"], Value::Bool(ratio <= goal), "{v}");
    let verdict = if ratio <= goal {
        "nvalue_1e6_quick: goal met: ratio"
    } else {
        "nvalue_1e6_quick: GOAL MISSED: ratio"
    };
    assert!(err.contains(verdict), "{err}");
    assert!(err.contains(&format!("<= {goal}")), "{err}");
}

#[test]
fn import_takes_a_list_starting_with_a_negative_number() {
    let log = temp_file("neg-log.csv");
    std::fs::write(
        &log,
        "t,speed,heading\n0.0,1.0,0.0\n0.5,1.0,0.0\n1.0,1.0,0.0\n",
    )
    .unwrap();
    let det = temp_file("neg-det.csv");
    std::fs::write(&det, "t,range_lo,range_hi,landmark\n1.0,4.0,4.5,0\n").unwrap();
    let out_path = temp_file("neg.json");
    succeeded(&run(&[
        "import",
        "--model",
        "unicycle2d",
        "--log",
        log.to_str().unwrap(),
        "--detections",
        det.to_str().unwrap(),
        "--error",
        "speed=0.1",
        "--error",
        "heading=0.01",
        "--initial",
        "-0.1,0.2,-0.3,0.4",
        "--out",
        out_path.to_str().unwrap(),
    ]));
    let m = read_json(&out_path);
    assert_eq!(
        m["initial_position"],
        serde_json::json!([[-0.1, 0.2], [-0.3, 0.4]])
    );
    // A bad list is still refused with its name.
    let out = run(&[
        "import",
        "--model",
        "unicycle2d",
        "--log",
        log.to_str().unwrap(),
        "--detections",
        det.to_str().unwrap(),
        "--error",
        "speed=0.1",
        "--error",
        "heading=0.01",
        "--initial",
        "-0.1,x",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--initial -0.1,x"));
}

#[test]
fn plot_warns_when_the_result_is_not_of_the_mission() {
    let a = simulate("plot-a.json", "200", "4");
    let b = simulate("plot-b.json", "300", "5");
    let r = temp_file("plot-a-result.json");
    succeeded(&run(&[
        "run",
        a.to_str().unwrap(),
        "--out",
        r.to_str().unwrap(),
    ]));
    let fig = temp_file("plot.svg");
    let plot = |mission: &Path| {
        run(&[
            "plot",
            r.to_str().unwrap(),
            "--mission",
            mission.to_str().unwrap(),
            "--out",
            fig.to_str().unwrap(),
        ])
    };
    let err = succeeded(&plot(&a));
    assert!(!err.contains("warning"), "{err}");
    let err = succeeded(&plot(&b));
    assert!(err.contains("warning"), "{err}");
    assert!(err.contains("does not look computed from"), "{err}");
    assert!(
        err.contains("the result has 201 trajectory boxes, the mission 300 steps"),
        "{err}"
    );
}
