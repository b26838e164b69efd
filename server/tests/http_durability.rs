//! Durability: a job running when the process is killed (kill -9) is
//! re-queued at the next start and completes; the mission is intact.

mod common;

use common::Server;
use serde_json::json;
use std::time::{Duration, Instant};

#[test]
fn a_killed_service_finishes_its_job_after_restart() {
    let s = Server::start(&["--workers", "1"]);
    let (st, m) = s.post("/api/v1/simulate", &json!({"scenario": "auv", "seed": 4}));
    assert_eq!(st, 201);
    let mid = m["id"].as_str().unwrap().to_string();
    let mission = m["mission"].clone();
    // Several jobs so that one is surely running when the process dies.
    let ids: Vec<String> = (0..3)
        .map(|_| {
            s.post(
                "/api/v1/jobs",
                &json!({"mission": mid, "contractor": "best"}),
            )
            .1["id"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    let start = Instant::now();
    loop {
        let (_, j) = s.get(&format!("/api/v1/jobs/{}", ids[0]));
        if j["state"] == "running" || j["state"] == "done" {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(30));
        std::thread::sleep(Duration::from_millis(10));
    }
    let (dir, db) = (s.dir.clone(), s.db.clone());
    let mut s = s;
    s.child.kill().unwrap(); // SIGKILL: no graceful shutdown
    s.child.wait().unwrap();
    drop(s);
    let s = Server::start_with(dir, db, &["--workers", "1"]);
    for id in &ids {
        let j = s.wait_job(id, Duration::from_secs(120));
        assert_eq!(j["state"], "done", "{j}");
    }
    assert_eq!(s.get(&format!("/api/v1/missions/{mid}")).1, mission);
}
