//! Fault isolation and load: jobs run in worker processes apart
//! from the HTTP service. A job over the memory limit fails with
//! `memory_limit` while health checks answer and the next job completes; a
//! worker process killed with SIGKILL mid-job is retried, then the job
//! fails (`worker_crashed`), never re-queued forever; concurrent
//! submissions never overshoot the queue limit; a short job submitted after
//! long ones finishes before them. Linux only (the tests find the worker
//! processes in /proc).

use nvector_tests::{kill9, on_both_storages, small_mission, Backend, Server};
use serde_json::{json, Value};
use std::time::{Duration, Instant};

/// A simulated paper mission of `steps` steps, stored by the service.
fn simulated(s: &Server, steps: u64) -> String {
    let (st, m) = s.post(
        "/api/v1/simulate",
        &json!({"scenario": "paper", "steps": steps, "seed": 2}),
    );
    assert_eq!(st, 201, "{m}");
    m["id"].as_str().unwrap().to_string()
}

fn queue(s: &Server, mission: &str) -> String {
    let (st, j) = s.post(
        "/api/v1/jobs",
        &json!({"mission": mission, "contractor": "best"}),
    );
    assert_eq!(st, 202, "{j}");
    j["id"].as_str().unwrap().to_string()
}

fn healthy(s: &Server) {
    let (st, _, body) = s.req("GET", "/healthz", None, &[]);
    assert_eq!((st, body.as_slice()), (200, b"ok\n".as_slice()));
}

/// A small mission, uploaded, and a job on it that must end done.
fn a_small_job_completes(s: &Server) -> Value {
    let (st, m) = s.post("/api/v1/missions", &small_mission(5, 1000));
    assert_eq!(st, 201, "{m}");
    let id = queue(s, m["id"].as_str().unwrap());
    let j = s.wait_job(&id, Duration::from_secs(60));
    assert_eq!(j["state"], "done", "{j}");
    j
}

/// 200,000 steps need more than 64 MiB honestly: the worker reads the
/// mission (14 MB of text), reports progress, and an allocation of the
/// propagation fails after a second or two (measured: 4 progress reports
/// first); a 1000-step mission runs in under 16 MiB.
#[test]
fn a_job_over_the_memory_limit_fails_and_the_service_keeps_answering() {
    let s = Server::start(&[
        "--workers",
        "1",
        "--short-lane-workers",
        "0",
        "--job-memory-limit",
        "64MiB",
    ]);
    let big = simulated(&s, 200_000);
    let id = queue(&s, &big);
    let start = Instant::now();
    let mut checks = 0;
    let j = loop {
        healthy(&s);
        checks += 1;
        let (_, j) = s.get(&format!("/api/v1/jobs/{id}"));
        if matches!(j["state"].as_str(), Some("done" | "failed" | "cancelled")) {
            break j;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "{j}");
        std::thread::sleep(Duration::from_millis(20));
    };
    eprintln!("{checks} health checks answered while the job ran: {j}");
    assert_eq!(j["state"], "failed", "{j}");
    assert_eq!(j["error_code"], "memory_limit", "{j}");
    let message = j["error"].as_str().unwrap();
    assert!(
        message.starts_with("memory_limit: ") && message.contains("64 MiB"),
        "the error says why in a word, then names the limit: {message}"
    );
    // It failed in the propagation, not reading the mission.
    assert!(j["progress"]["round"].as_i64() >= Some(1), "{j}");
    // The failed job, as the OpenAPI document describes a Job.
    let (_, doc) = s.get("/api/v1/openapi.json");
    let errors =
        nvector_tests::schema::validate(&doc, &json!({"$ref": "#/components/schemas/Job"}), &j);
    assert!(errors.is_empty(), "{errors:?}: {j}");
    // Not retried: the same job needs the same memory.
    assert_eq!(
        (j["attempts"].as_i64(), j["worker_crashes"].as_i64()),
        (Some(1), Some(1))
    );
    healthy(&s);
    // The one worker runs the next job in a new process.
    a_small_job_completes(&s);
    let (_, _, metrics) = s.req("GET", "/metrics", None, &[]);
    let metrics = String::from_utf8(metrics).unwrap();
    assert!(
        metrics.contains("nvector_worker_deaths_total{reason=\"memory_limit\"} 1"),
        "{metrics}"
    );
}

/// The crash count is stored with the job: a restart of the service (here
/// a kill -9 between the two crashes, the job then re-queued by the lease)
/// does not reset it.
fn a_killed_worker_is_retried_then_its_job_fails(b: &Backend) {
    let flags = [
        "--workers",
        "1",
        "--short-lane-workers",
        "0",
        "--job-attempts",
        "2",
        "--job-lease",
        "3",
    ];
    let s = Server::start_on(b, &flags);
    let long = simulated(&s, 200_000);
    let id = queue(&s, &long);
    let limit = Duration::from_secs(60);
    let (_, first) = s.wait_running_in_worker(&id, &[], limit);
    kill9(first);
    // Re-queued and run again, in a new worker process.
    let (j, second) = s.wait_running_in_worker(&id, &[first], limit);
    assert_eq!(
        (j["worker_crashes"].as_i64(), j["attempts"].as_i64()),
        (Some(1), Some(2))
    );
    // The whole service killed: the job comes back after the restart.
    let (dir, db) = (s.dir.clone(), s.db.clone());
    let mut s = s;
    s.child.kill().unwrap();
    s.child.wait().unwrap();
    drop(s);
    let s = Server::start_with(dir, db, &flags);
    let (j, third) = s.wait_running_in_worker(&id, &[first, second], limit);
    assert_eq!(
        (j["worker_crashes"].as_i64(), j["attempts"].as_i64()),
        (Some(1), Some(3))
    );
    kill9(third);
    let j = s.wait_job(&id, limit);
    assert_eq!(j["state"], "failed", "{j}");
    assert_eq!(j["error_code"], "worker_crashed", "{j}");
    assert_eq!(
        (j["attempts"].as_i64(), j["worker_crashes"].as_i64()),
        (Some(3), Some(2))
    );
    let message = j["error"].as_str().unwrap();
    assert!(
        message.starts_with("worker_crashed: ")
            && message.contains("SIGKILL")
            && message.contains("2 of at most 2"),
        "{message}"
    );
    healthy(&s);
    a_small_job_completes(&s);
    // Still failed: nothing put it back.
    let (_, j) = s.get(&format!("/api/v1/jobs/{id}"));
    assert_eq!(
        (j["state"].as_str(), j["attempts"].as_i64()),
        (Some("failed"), Some(3))
    );
}

/// 40 submissions at once against a queue limit of 10, with no worker to
/// empty the queue: exactly 10 are queued.
fn the_queue_limit_holds_under_concurrent_submissions(b: &Backend) {
    let s = Server::start_on(
        b,
        &[
            "--workers",
            "0",
            "--short-lane-workers",
            "0",
            "--max-queue",
            "10",
        ],
    );
    let (st, m) = s.post("/api/v1/missions", &small_mission(5, 300));
    assert_eq!(st, 201, "{m}");
    let mission = m["id"].as_str().unwrap();
    let barrier = std::sync::Barrier::new(40);
    let statuses: Vec<u16> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..40)
            .map(|_| {
                let (s, barrier) = (&s, &barrier);
                scope.spawn(move || {
                    barrier.wait();
                    s.post("/api/v1/jobs", &json!({"mission": mission})).0
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let queued = statuses.iter().filter(|&&st| st == 202).count();
    let refused = statuses.iter().filter(|&&st| st == 429).count();
    assert_eq!((queued, refused), (10, 30), "{statuses:?}");
    let (_, _, metrics) = s.req("GET", "/metrics", None, &[]);
    let metrics = String::from_utf8(metrics).unwrap();
    assert!(
        metrics.contains("nvector_jobs{state=\"queued\"} 10"),
        "{metrics}"
    );
}

on_both_storages!(
    a_killed_worker_is_retried_then_its_job_fails,
    the_queue_limit_holds_under_concurrent_submissions,
);

/// Three long jobs (200,000 steps), then a short one (300 steps; short
/// below 10^6 steps × detections). With one worker the short job runs
/// right after the running long job, before the two queued ones; with a
/// short lane it runs while the first long job still runs.
#[test]
fn a_short_job_submitted_after_long_ones_finishes_first() {
    for lane in ["0", "1"] {
        let s = Server::start(&[
            "--workers",
            "1",
            "--short-lane-workers",
            lane,
            "--short-job-cost",
            "1000000",
        ]);
        let long = simulated(&s, 200_000);
        let longs: Vec<String> = (0..3).map(|_| queue(&s, &long)).collect();
        let (st, m) = s.post("/api/v1/missions", &small_mission(5, 300));
        assert_eq!(st, 201, "{m}");
        let short = queue(&s, m["id"].as_str().unwrap());
        let j = s.wait_job(&short, Duration::from_secs(60));
        assert_eq!(j["state"], "done", "{j}");
        let job = |id: &str| s.get(&format!("/api/v1/jobs/{id}")).1;
        if lane == "0" {
            // Ahead of the queued long jobs: they have not started.
            for id in &longs[1..] {
                let l = job(id);
                assert!(
                    l["started_ms"].is_null()
                        || l["started_ms"].as_i64() >= j["finished_ms"].as_i64(),
                    "short {j} / long {l}"
                );
            }
        } else {
            // Beside the running long job: it has not finished.
            let l = job(&longs[0]);
            assert_eq!(l["state"], "running", "short {j} / long {l}");
        }
        for id in &longs {
            s.req("DELETE", &format!("/api/v1/jobs/{id}"), None, &[]);
        }
    }
}

/// The time limit holds while the robust propagation (`max_outliers` > 0)
/// runs its sub-propagations, which report no progress: the worker read
/// the clock only in its progress callback, so a job on the paper mission
/// with 10 false detections and a limit of 0.05 s or 0.3 s ran on, the
/// service killed its worker after the 5 s grace and the job failed
/// (`time_limit ... no result kept`). A watchdog thread now sets the
/// cancel flag at the limit: the job is done (`time_limit` when the limit
/// stopped it) and its boxes are sound.
#[test]
fn a_time_limit_stops_the_robust_propagation_with_a_sound_result() {
    let s = Server::start(&["--workers", "1", "--short-lane-workers", "0"]);
    let mut o = nvector_core::slam::simulate::SimulateOptions::new(
        nvector_core::slam::simulate::Scenario::Paper,
        1,
    );
    o.false_detections = 10;
    let mission = nvector_core::slam::simulate::simulate(&o);
    assert_eq!(mission["max_outliers"], 10);
    let (st, m) = s.post("/api/v1/missions", &mission);
    assert_eq!(st, 201, "{m}");
    for limit in [0.05, 0.3] {
        let (st, j) = s.post(
            "/api/v1/jobs",
            &json!({"mission": m["id"], "contractor": "best", "time_limit_s": limit}),
        );
        assert_eq!(st, 202, "{j}");
        let id = j["id"].as_str().unwrap();
        let j = s.wait_job(id, Duration::from_secs(120));
        assert_eq!(j["state"], "done", "limit {limit}: {j}");
        let (st, r) = s.get(&format!("/api/v1/jobs/{id}/result"));
        assert_eq!(st, 200, "{r}");
        assert_ne!(r["status"], "infeasible", "{}", r["reason"]);
        assert_eq!(r["score"]["truth_inside"], true, "limit {limit}");
        assert_eq!(r["score"]["matching_errors"], 0, "limit {limit}");
    }
    healthy(&s);
}
