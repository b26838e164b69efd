//! Progress that tracks the work, over a real socket against the real
//! binary: CMU Plaza 1 run by the service (the default contractor), its
//! Server-Sent Events read as they come, each with its arrival time. The
//! job's `progress.fraction` never goes back, ends at 1, is at most 0.75
//! at half the job's time, and is never still for more than a third of the
//! job's time before the end. The old estimate (a geometric series on the
//! count of detections still moving) said 0.97 from round 9 of 52 on,
//! about 45 % into the run, and stayed there until the last round: it
//! fails both. The times are ratios within one run, not durations.

use nvector_tests as common;
use nvector_tests::Server;
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::time::{Duration, Instant};

/// The `(seconds since the request, event name, job)` of a job's event
/// stream, read until its `end` event.
fn events(s: &Server, id: &str) -> Vec<(f64, String, Value)> {
    let mut c = TcpStream::connect(&s.addr).unwrap();
    c.set_read_timeout(Some(Duration::from_secs(600))).unwrap();
    write!(
        c,
        "GET /api/v1/jobs/{id}/events HTTP/1.1\r\nHost: {}\r\nAccept: text/event-stream\r\nConnection: close\r\n\r\n",
        s.addr
    )
    .unwrap();
    let start = Instant::now();
    let (mut text, mut out) = (String::new(), Vec::new());
    let mut buf = [0u8; 65536];
    loop {
        let n = c.read(&mut buf).unwrap_or(0);
        if n == 0 {
            break;
        }
        let at = start.elapsed().as_secs_f64();
        text.push_str(&String::from_utf8_lossy(&buf[..n]));
        // Whole events (a blank line ends each); chunk sizes of the
        // chunked encoding sit between them as lines of hex digits.
        while let Some(end) = text.find("\n\n") {
            let block: String = text.drain(..end + 2).collect();
            let name = block
                .lines()
                .find_map(|l| l.strip_prefix("event: "))
                .map(str::to_string);
            let data = block.lines().find_map(|l| l.strip_prefix("data: "));
            if let (Some(name), Some(data)) = (name, data) {
                out.push((at, name, serde_json::from_str(data).unwrap()));
            }
        }
        if out.last().is_some_and(|e| e.1 == "end") {
            break;
        }
    }
    out
}

#[test]
fn plaza_progress_tracks_the_work() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    let dir = common::temp_dir("progress");
    let mission = dir.join("plaza.json");
    let st = common::nvector()
        .args(["import", "--cmu-plaza"])
        .arg(&data)
        .arg("--out")
        .arg(&mission)
        .status()
        .unwrap();
    assert!(st.success());
    let s = Server::start(&[]);
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&mission).unwrap()).unwrap();
    let (st, stored) = s.post("/api/v1/missions", &m);
    assert_eq!(st, 201, "{stored}");
    let (st, job) = s.post("/api/v1/jobs", &json!({"mission": stored["id"]}));
    assert_eq!(st, 202, "{job}");
    let ev = events(&s, job["id"].as_str().unwrap());
    let end = ev.last().unwrap();
    assert_eq!(end.1, "end");
    assert_eq!(end.2["state"], "done", "{}", end.2);
    assert_eq!(end.2["progress"]["fraction"], 1.0);
    // The run: from the first event of the running job to the end.
    let running: Vec<(f64, f64)> = ev
        .iter()
        .filter(|e| e.2["state"] == "running" || e.1 == "end")
        .map(|e| (e.0, e.2["progress"]["fraction"].as_f64().unwrap()))
        .collect();
    assert!(running.len() >= 10, "too few events: {ev:?}");
    let (t0, t1) = (running[0].0, end.0);
    let share = |t: f64| (t - t0) / (t1 - t0);
    let tenths: Vec<String> = (0..=10)
        .map(|k| {
            let v = running
                .iter()
                .rfind(|e| share(e.0) <= k as f64 / 10.0)
                .map_or(0.0, |e| e.1);
            format!("{v:.2}")
        })
        .collect();
    eprintln!(
        "HTTP plaza progress at tenths of the run ({:.1} s, {} events): {}",
        t1 - t0,
        running.len(),
        tenths.join(" ")
    );
    for w in running.windows(2) {
        assert!(w[1].1 >= w[0].1, "the fraction went back: {w:?}");
    }
    let half = running.iter().rfind(|e| share(e.0) <= 0.5).unwrap();
    assert!(half.1 <= 0.75, "{} at half the run: {tenths:?}", half.1);
    // The longest stretch of one value before the end.
    let mut still = 0.0f64;
    let mut since = running[0];
    for e in &running[1..] {
        if e.1 != since.1 {
            still = still.max(share(e.0) - share(since.0));
            since = *e;
        }
    }
    assert!(
        still <= 1.0 / 3.0,
        "the fraction stood still for {:.0} % of the run: {tenths:?}",
        100.0 * still
    );
}
