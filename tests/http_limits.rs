//! Bounded work (issue 12): worst-case contraction requests fired at once
//! each get their 422 `work_limit` within the service's time limit per
//! contraction, while health checks, a polynomial contraction and a SLAM
//! job still answer. Times are measured and printed (run with
//! `--nocapture` to see them); the only timing assertion is the limit
//! itself, with a grace second for the flag to be read and the answer
//! written on a loaded machine.

use nvector_tests::{small_mission, worst_case_contract, Server};
use serde_json::{json, Value};
use std::time::{Duration, Instant};

/// The limit given to the service under test (s).
const LIMIT_S: f64 = 3.0;
/// Worst-case requests at once.
const STORM: usize = 4;

#[test]
fn worst_case_contractions_are_bounded_and_the_service_keeps_answering() {
    let limit = LIMIT_S.to_string();
    let s = Server::start(&["--workers", "1", "--contract-time-limit", &limit]);
    let (st, m) = s.post("/api/v1/missions", &small_mission(9, 2000));
    assert_eq!(st, 201, "{m}");
    let storm_start = Instant::now();
    let answers: Vec<(u16, Value, Duration)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..STORM)
            .map(|_| {
                let s = &s;
                scope.spawn(move || {
                    let t = Instant::now();
                    let (st, v) = s.post("/api/v1/contract", &worst_case_contract(Some("exact")));
                    (st, v, t.elapsed())
                })
            })
            .collect();
        // While they run: health checks, a polynomial contraction, a job.
        std::thread::sleep(Duration::from_millis(200));
        let (st, job) = s.post("/api/v1/jobs", &json!({"mission": m["id"]}));
        assert_eq!(st, 202, "{job}");
        let mut health = Vec::new();
        while storm_start.elapsed() < Duration::from_secs_f64(LIMIT_S) {
            let t = Instant::now();
            let (st, _, body) = s.req("GET", "/healthz", None, &[]);
            assert_eq!((st, body.as_slice()), (200, b"ok\n".as_slice()));
            health.push(t.elapsed());
            std::thread::sleep(Duration::from_millis(100));
        }
        let t = Instant::now();
        let (st, v) = s.post("/api/v1/contract", &worst_case_contract(Some("best")));
        assert_eq!(st, 200, "{v}");
        let best = t.elapsed();
        let done = s.wait_job(job["id"].as_str().unwrap(), Duration::from_secs(120));
        assert_eq!(done["state"], "done", "{done}");
        let worst_health = health.iter().max().copied().unwrap_or_default();
        eprintln!(
            "during the storm: {} health checks, slowest {worst_health:?}; best on the worst \
             case {best:?}; the job ended after {:?}",
            health.len(),
            storm_start.elapsed()
        );
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (st, v, took) in &answers {
        eprintln!(
            "worst case (exact): {st} after {took:?}: {}",
            v["error"]["message"]
        );
        assert_eq!(*st, 422, "{v}");
        assert_eq!(v["error"]["code"], "work_limit", "{v}");
        let message = v["error"]["message"].as_str().unwrap();
        assert!(
            message.contains("time limit of 3 s") || message.contains("work budget"),
            "the message names the limit: {message}"
        );
        assert!(
            *took <= Duration::from_secs_f64(LIMIT_S + 1.0),
            "answered after {took:?}, limit {LIMIT_S} s"
        );
    }
}
