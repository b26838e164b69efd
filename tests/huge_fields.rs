//! Every numeric field of the formats and every size option of the CLI at
//! its largest accepted value, through the real binary under a 1 GiB
//! address-space limit (`ulimit -v`): each run ends with a result or with
//! a clear error naming the field, never with a signal (an allocation
//! sized by an input number aborts the process: once `max_outliers`
//! 4294967295 asked 34 GB, `landmark_count` 4294967295 17 GB).

use serde_json::{json, Value};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// The address-space limit of every run, in KiB (1 GiB).
const LIMIT_KIB: u32 = 1 << 20;

/// The largest value of a `u32` field (`max_outliers`, `landmark_count`,
/// a detection's `landmark`, a contraction's `n`).
const U32_MAX: u64 = u32::MAX as u64;

/// `nvector ARGS` under the limit (through `bash -c 'ulimit -v ...; exec'`),
/// with `stdin` when given. glibc's per-thread arenas reserve address
/// space without using it: two are enough for the CLI and the service.
fn limited(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new("bash")
        .arg("-c")
        .arg(format!("ulimit -v {LIMIT_KIB} && exec \"$0\" \"$@\""))
        .arg(nvector_tests::nvector_bin())
        .args(args)
        .env("MALLOC_ARENA_MAX", "2")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run bash");
    let mut input = child.stdin.take().unwrap();
    input
        .write_all(stdin.unwrap_or("").as_bytes())
        .expect("write stdin");
    drop(input);
    child.wait_with_output().unwrap()
}

/// What a run must be: exit 0, or exit 1 with a message naming `field` on
/// stderr; never a signal (an abort is SIGABRT) nor a panic (101).
fn ended_cleanly(out: &Output, what: &str, field: &str) -> bool {
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => true,
        Some(1) => {
            assert!(
                stderr.contains(field),
                "{what}: the error does not name {field}: {stderr}"
            );
            false
        }
        other => panic!("{what}: ended with {other:?} (a signal when None): {stderr}"),
    }
}

/// A small mission (2 steps, 3 detections, one labelled) with `extra`
/// fields set.
fn tiny(extra: Value) -> Value {
    let mut m = json!({
        "format": "nvector-mission/1",
        "name": "tiny",
        "model": "unicycle2d",
        "dt": 0.1,
        "steps": 2,
        "initial_position": [[0, 0], [0, 0]],
        "inputs": {
            "speed": {"value": [1, 1], "error": 0.1},
            "heading": {"value": [0, 0], "error": 0.01}
        },
        "detections": [
            {"step": 1, "range": [1, 2]},
            {"step": 2, "range": [1, 2], "landmark": 0},
            {"step": 2, "range": [3, 4], "landmark": 0}
        ]
    });
    for (k, v) in extra.as_object().unwrap() {
        m[k] = v.clone();
    }
    m
}

const RUN_CONTRACTORS: [&str; 6] = [
    "none",
    "nvalue",
    "projection",
    "independent",
    "shapes",
    "best",
];

/// `nvector run` of a mission file under the limit with each contractor:
/// each a result whose status is one of the spec's.
fn run_all(mission: &Path, contractors: &[&str], what: &str, field: &str) {
    let out_path = mission.with_extension("result.json");
    for c in contractors {
        let out = limited(
            &[
                "run",
                mission.to_str().unwrap(),
                "--contractor",
                c,
                "--out",
                out_path.to_str().unwrap(),
            ],
            None,
        );
        let what = format!("{what}, --contractor {c}");
        if ended_cleanly(&out, &what, field) {
            let r: Value = serde_json::from_slice(&std::fs::read(&out_path).unwrap()).unwrap();
            assert!(
                matches!(
                    r["status"].as_str(),
                    Some("consistent" | "infeasible" | "stopped")
                ),
                "{what}: {r}"
            );
        }
    }
}

#[test]
fn mission_fields_at_their_largest_run_under_1_gib_with_every_contractor() {
    let dir = nvector_tests::temp_dir("huge-fields");
    let cases = [
        ("max_outliers", json!({"max_outliers": U32_MAX})),
        ("landmark_count", json!({"landmark_count": U32_MAX})),
        (
            "max_outliers",
            json!({"landmark_count": U32_MAX, "max_outliers": U32_MAX}),
        ),
        (
            "landmark",
            json!({"detections": [
                {"step": 1, "range": [1, 2], "landmark": U32_MAX},
                {"step": 2, "range": [1, 2], "landmark": U32_MAX},
                {"step": 2, "range": [3, 4]}
            ]}),
        ),
        (
            "landmark",
            json!({"max_outliers": 1, "detections": [
                {"step": 1, "range": [1, 2], "landmark": U32_MAX},
                {"step": 2, "range": [1, 2], "landmark": U32_MAX},
                {"step": 2, "range": [3, 4]}
            ]}),
        ),
    ];
    for (i, (field, extra)) in cases.iter().enumerate() {
        let path = dir.join(format!("case-{i}.json"));
        std::fs::write(&path, tiny(extra.clone()).to_string()).unwrap();
        run_all(&path, &RUN_CONTRACTORS, &format!("{extra}"), field);
    }
    // One past the largest: a clear error naming the field.
    for field in ["max_outliers", "landmark_count"] {
        let path = dir.join(format!("{field}-over.json"));
        std::fs::write(&path, tiny(json!({ field: U32_MAX + 1 })).to_string()).unwrap();
        let out = limited(&["run", path.to_str().unwrap()], None);
        assert!(
            !ended_cleanly(&out, field, field),
            "{field} above u32 accepted"
        );
    }
}

#[test]
fn contraction_n_at_its_largest_with_every_contractor() {
    for c in [
        "nvalue",
        "projection",
        "independent",
        "exact",
        "shapes",
        "best",
    ] {
        let request = json!({
            "format": "nvector-contract/1",
            "n": U32_MAX,
            "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]],
            "contractor": c
        });
        let out = limited(&["contract"], Some(&request.to_string()));
        assert!(ended_cleanly(&out, c, "n"), "{c}: refused");
        let r: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(r["status"], "unchanged", "{c}: {r}");
    }
    let over = json!({"format": "nvector-contract/1", "n": U32_MAX + 1, "boxes": [[[0, 1]]]});
    let out = limited(&["contract"], Some(&over.to_string()));
    assert!(!ended_cleanly(&out, "n over", "n"));
}

#[test]
fn simulate_options_at_their_largest_under_1_gib() {
    let dir = nvector_tests::temp_dir("huge-simulate");
    let max_steps = nvector_core::slam::mission::MAX_STEPS.to_string();
    let landmarks = nvector_core::slam::simulate::MAX_LANDMARKS.to_string();
    let falses = nvector_core::slam::simulate::MAX_FALSE_DETECTIONS.to_string();
    let out_path = dir.join("m.json");
    let out_arg = out_path.to_str().unwrap();
    let accepted: [&[&str]; 5] = [
        &["--scenario", "paper", "--steps", &max_steps],
        &["--scenario", "auv", "--steps", &max_steps],
        &[
            "--scenario",
            "paper",
            "--landmarks",
            &landmarks,
            "--layout",
            "ring",
        ],
        &[
            "--scenario",
            "paper",
            "--steps",
            "3000",
            "--false-detections",
            &falses,
            "--operator",
        ],
        &[
            "--scenario",
            "paper",
            "--steps",
            "300",
            "--seed",
            "18446744073709551615",
        ],
    ];
    for args in accepted {
        let mut all = vec!["simulate"];
        all.extend_from_slice(args);
        all.extend(["--out", out_arg]);
        let out = limited(&all, None);
        assert!(
            ended_cleanly(&out, &format!("{args:?}"), "--"),
            "{args:?}: refused"
        );
        let m: Value = serde_json::from_slice(&std::fs::read(&out_path).unwrap()).unwrap();
        assert_eq!(m["format"], "nvector-mission/1", "{args:?}");
    }
    let huge = u64::MAX.to_string();
    let refused: [(&[&str], &str); 5] = [
        (&["--steps", &huge], "--steps"),
        (&["--steps", "2000001"], "--steps"),
        (&["--landmarks", &huge], "--landmarks"),
        (&["--landmarks", "65"], "--landmarks"),
        (&["--false-detections", &huge], "--false-detections"),
    ];
    for (args, field) in refused {
        let mut all = vec!["simulate", "--scenario", "paper"];
        all.extend_from_slice(args);
        let out = limited(&all, None);
        assert!(!ended_cleanly(&out, field, field), "{args:?} accepted");
    }
    // Planting false ranges in a real log: refused before any is drawn.
    let out = limited(
        &[
            "import",
            "--cmu-plaza",
            dir.to_str().unwrap(),
            "--false-detections",
            &huge,
        ],
        None,
    );
    assert!(!ended_cleanly(&out, "import", "--false-detections"));
}

#[test]
fn the_largest_mission_runs_under_1_gib_with_false_detections() {
    // 2,000,000 steps (the format's limit) with false detections allowed:
    // the robust propagation's records are O(N), never O(q).
    let dir = nvector_tests::temp_dir("huge-steps");
    let path = dir.join("m.json");
    let max_steps = nvector_core::slam::mission::MAX_STEPS.to_string();
    let out = limited(
        &[
            "simulate",
            "--scenario",
            "paper",
            "--steps",
            &max_steps,
            "--operator",
            "--false-detections",
            "3",
            "--out",
            path.to_str().unwrap(),
        ],
        None,
    );
    assert!(ended_cleanly(&out, "simulate", "--"));
    run_all(
        &path,
        &["best"],
        "2,000,000 steps, max_outliers 3",
        "max_outliers",
    );
    let mut m: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    m["max_outliers"] = json!(U32_MAX);
    std::fs::write(&path, m.to_string()).unwrap();
    run_all(
        &path,
        &["best"],
        "2,000,000 steps, max_outliers u32::MAX",
        "max_outliers",
    );
}

#[test]
fn the_service_runs_huge_field_jobs_under_1_gib_and_keeps_answering() {
    // Once, one such upload aborted `nvector serve` (and, the job
    // queued again at restart, every restart after it).
    let dir = nvector_tests::temp_dir("huge-serve");
    let db = format!("sqlite://{}", dir.join("nvector.db").display());
    let mut under_limit = Command::new("bash");
    under_limit
        .arg("-c")
        .arg(format!("ulimit -v {LIMIT_KIB} && exec \"$0\" \"$@\""))
        .arg(nvector_tests::nvector_bin())
        .env("MALLOC_ARENA_MAX", "2");
    let server = nvector_tests::Server::start_from(under_limit, dir, db, &[]);
    for extra in [
        json!({"max_outliers": U32_MAX}),
        json!({"landmark_count": U32_MAX, "max_outliers": U32_MAX}),
        json!({"landmark_count": U32_MAX}),
    ] {
        let (st, m) = server.post("/api/v1/missions", &tiny(extra.clone()));
        assert_eq!(st, 201, "{m}");
        for c in RUN_CONTRACTORS {
            let (st, j) = server.post(
                "/api/v1/jobs",
                &json!({"mission": m["id"], "contractor": c}),
            );
            assert_eq!(st, 202, "{j}");
            let j = server.wait_job(
                j["id"].as_str().unwrap(),
                std::time::Duration::from_secs(60),
            );
            assert_eq!(j["state"], "done", "{extra} {c}: {j}");
            let (st, _) = server.get("/healthz");
            assert_eq!(st, 200, "{extra} {c}: the service stopped answering");
        }
    }
}
