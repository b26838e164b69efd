//! Durability and shutdown, on SQLite and on PostgreSQL: a job running when
//! the process is killed (kill -9) is re-queued once its lease expires and
//! completes after a restart; a SIGTERM re-queues the running job at once
//! and the process exits cleanly; accepted missions are never lost. On
//! PostgreSQL, two processes share one queue: 50 jobs each run exactly once
//! and all finish, and a job of a killed process is taken over by the other.

use nvector_tests as common;
use nvector_tests::{on_both_storages, small_mission, Backend, Server};
use serde_json::{json, Value};
use std::time::{Duration, Instant};

/// Uploads an AUV mission and queues `jobs` long jobs on it; returns the
/// mission id, the mission and the job ids. 300,000 steps (5 times the
/// survey's default): `best` solved the default one in a quarter of a
/// second, which could end the job before the test stopped the service.
fn long_jobs(s: &Server, jobs: usize) -> (String, Value, Vec<String>) {
    let (st, m) = s.post(
        "/api/v1/simulate",
        &json!({"scenario": "auv", "seed": 4, "steps": 300_000}),
    );
    assert_eq!(st, 201, "{m}");
    let mid = m["id"].as_str().unwrap().to_string();
    let ids = (0..jobs)
        .map(|_| {
            let (st, j) = s.post(
                "/api/v1/jobs",
                &json!({"mission": mid, "contractor": "best"}),
            );
            assert_eq!(st, 202, "{j}");
            j["id"].as_str().unwrap().to_string()
        })
        .collect();
    (mid, m["mission"].clone(), ids)
}

fn wait_running(s: &Server, id: &str) -> Value {
    let start = Instant::now();
    loop {
        let (_, j) = s.get(&format!("/api/v1/jobs/{id}"));
        if j["state"] == "running" {
            return j;
        }
        assert_ne!(
            j["state"], "done",
            "the job ended before the test could stop it"
        );
        assert!(start.elapsed() < Duration::from_secs(30), "{j}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn a_killed_service_finishes_its_job_after_restart(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "1", "--job-lease", "3"]);
    let (mid, mission, ids) = long_jobs(&s, 3);
    let first = wait_running(&s, &ids[0]);
    let workers = s.worker_pids();
    assert!(!workers.is_empty(), "the running job has a worker process");
    let (dir, db) = (s.dir.clone(), s.db.clone());
    let mut s = s;
    s.child.kill().unwrap(); // SIGKILL: no graceful shutdown
    s.child.wait().unwrap();
    drop(s);
    // Its worker processes die with it (none goes on running the job).
    let start = Instant::now();
    while workers.iter().any(|&p| common::process_alive(p)) {
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "worker processes {workers:?} outlived the service"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let s = Server::start_with(dir, db, &["--workers", "1", "--job-lease", "3"]);
    for id in &ids {
        let j = s.wait_job(id, Duration::from_secs(120));
        assert_eq!(j["state"], "done", "{j}");
    }
    // The first job ran twice: once in the killed process, once after.
    let (_, j) = s.get(&format!("/api/v1/jobs/{}", ids[0]));
    assert_eq!(j["attempts"], 2, "{j}");
    assert_ne!(j["runner"], first["runner"], "{j}");
    assert_eq!(s.get(&format!("/api/v1/missions/{mid}")).1, mission);
    let (st, r) = s.get(&format!("/api/v1/jobs/{}/result", ids[0]));
    assert_eq!((st, r["format"].as_str()), (200, Some("nvector-result/1")));
}

fn sigterm_requeues_the_running_job_and_exits(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "1"]);
    let (mid, mission, ids) = long_jobs(&s, 1);
    wait_running(&s, &ids[0]);
    let pid = s.child.id().to_string();
    let ok = std::process::Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .unwrap();
    assert!(ok.success());
    let (dir, db) = (s.dir.clone(), s.db.clone());
    let mut s = s;
    let start = Instant::now();
    let status = loop {
        if let Some(st) = s.child.try_wait().unwrap() {
            break st;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the service did not stop on SIGTERM"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "exit status after SIGTERM: {status}");
    drop(s);
    // A lease far longer than the test: only the graceful re-queue can have
    // put the job back.
    let s = Server::start_with(dir, db, &["--workers", "1", "--job-lease", "3600"]);
    let j = s.wait_job(&ids[0], Duration::from_secs(120));
    assert_eq!(j["state"], "done", "{j}");
    assert_eq!(j["attempts"], 2, "{j}");
    assert_eq!(s.get(&format!("/api/v1/missions/{mid}")).1, mission);
}

on_both_storages!(
    a_killed_service_finishes_its_job_after_restart,
    sigterm_requeues_the_running_job_and_exits,
);

/// Two processes on one PostgreSQL database, 50 jobs queued through both:
/// every job ends done, each was claimed exactly once, and both processes
/// ran jobs.
#[test]
fn two_processes_share_the_queue_on_postgres() {
    common::pg::with_cluster(|c| {
        let db = c.create_db();
        let a = Server::start_with(common::temp_dir("a"), db.clone(), &["--workers", "2"]);
        let b = Server::start_with(common::temp_dir("b"), db, &["--workers", "2"]);
        let (st, m) = a.post("/api/v1/missions", &small_mission(8, 3000));
        assert_eq!(st, 201, "{m}");
        let mid = m["id"].as_str().unwrap().to_string();
        // B sees A's mission: one database.
        assert_eq!(b.get(&format!("/api/v1/missions/{mid}")).0, 200);
        let ids: Vec<String> = (0..50)
            .map(|i| {
                let s = if i % 2 == 0 { &a } else { &b };
                let (st, j) = s.post(
                    "/api/v1/jobs",
                    &json!({"mission": mid, "contractor": "projection"}),
                );
                assert_eq!(st, 202, "{j}");
                j["id"].as_str().unwrap().to_string()
            })
            .collect();
        let mut runners = std::collections::BTreeMap::<String, usize>::new();
        for id in &ids {
            let j = a.wait_job(id, Duration::from_secs(300));
            assert_eq!(j["state"], "done", "{j}");
            assert_eq!(j["attempts"], 1, "job {id} ran more than once: {j}");
            *runners
                .entry(j["runner"].as_str().unwrap().to_string())
                .or_default() += 1;
        }
        assert_eq!(runners.len(), 2, "both processes run jobs: {runners:?}");
        assert_eq!(runners.values().sum::<usize>(), 50);
        let (_, _, metrics) = b.req("GET", "/metrics", None, &[]);
        let metrics = String::from_utf8(metrics).unwrap();
        assert!(
            metrics.contains("nvector_jobs{state=\"done\"} 50"),
            "{metrics}"
        );
    });
}

/// On PostgreSQL, a job whose process is killed is re-queued by the other
/// process once the lease expires, and finishes there.
#[test]
fn a_live_process_takes_over_the_job_of_a_killed_one() {
    common::pg::with_cluster(|c| {
        let db = c.create_db();
        let flags = ["--workers", "1", "--job-lease", "3"];
        let mut a = Server::start_with(common::temp_dir("a"), db.clone(), &flags);
        let (_, _, ids) = long_jobs(&a, 1);
        let first = wait_running(&a, &ids[0]);
        let b = Server::start_with(common::temp_dir("b"), db, &flags);
        a.child.kill().unwrap();
        a.child.wait().unwrap();
        let j = b.wait_job(&ids[0], Duration::from_secs(120));
        assert_eq!(j["state"], "done", "{j}");
        assert_eq!(j["attempts"], 2, "{j}");
        assert_ne!(j["runner"], first["runner"]);
    });
}
