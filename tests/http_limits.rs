//! Bounded work: worst-case contraction requests fired at once
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

/// Writes `head`, then `total` bytes of body in 64 KiB writes (each framed
/// as a chunk when `chunked`), and only then reads the answer, as a client
/// that sends its whole body first does (Python's urllib). Panics when a
/// write fails: a service that answers an oversized body and closes the
/// connection while the client still sends resets it, and the client sees
/// a broken pipe instead of the 413.
fn send_whole_then_read(
    addr: &str,
    head: &str,
    total: usize,
    chunked: bool,
) -> (u16, String, Value) {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    s.write_all(head.as_bytes()).unwrap();
    let piece = vec![b' '; 64 << 10];
    let mut sent = 0;
    while sent < total {
        let n = piece.len().min(total - sent);
        let r = if chunked {
            s.write_all(format!("{n:x}\r\n").as_bytes())
                .and_then(|_| s.write_all(&piece[..n]))
                .and_then(|_| s.write_all(b"\r\n"))
        } else {
            s.write_all(&piece[..n])
        };
        if let Err(e) = r {
            panic!("writing the body failed after {sent} of {total} bytes: {e}");
        }
        sent += n;
    }
    if chunked {
        s.write_all(b"0\r\n\r\n").unwrap();
    }
    let mut buf = Vec::new();
    let _ = s.read_to_end(&mut buf);
    let (st, head, body) = nvector_tests::parse_response(&buf);
    (
        st,
        head,
        serde_json::from_slice(&body).unwrap_or(Value::Null),
    )
}

/// A body over `--max-body` is answered 413 `body_too_large`, naming the
/// limit, and a client that writes its whole body before reading reads
/// that answer (with a declared length and chunked); bodies within the
/// limit, chunked too, are still taken; what was stored stays.
#[test]
fn an_oversized_body_is_answered_413_to_a_client_that_sends_it_whole() {
    let limit: usize = 1 << 20;
    let s = Server::start(&["--workers", "1", "--max-body", &limit.to_string()]);
    let (st, kept) = s.post("/api/v1/missions", &small_mission(3, 50));
    assert_eq!(st, 201, "{kept}");
    // 48 times the limit: far more than the sockets' buffers hold.
    let total = 48 * limit;
    for chunked in [false, true] {
        let length = if chunked {
            "Transfer-Encoding: chunked".to_string()
        } else {
            format!("Content-Length: {total}")
        };
        let head = format!(
            "POST /api/v1/missions HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\nConnection: close\r\n{length}\r\n\r\n",
            s.addr
        );
        let (st, _, v) = send_whole_then_read(&s.addr, &head, total, chunked);
        assert_eq!(st, 413, "chunked {chunked}: {v}");
        assert_eq!(v["error"]["code"], "body_too_large", "{v}");
        let message = v["error"]["message"].as_str().unwrap_or("");
        assert!(
            message.contains(&limit.to_string()),
            "names the limit: {message}"
        );
    }
    // Within the limit, chunked: taken.
    let body = serde_json::to_vec(&small_mission(4, 50)).unwrap();
    assert!(body.len() < limit);
    let head = format!(
        "POST /api/v1/missions HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\nConnection: close\r\n\r\n{:x}\r\n",
        s.addr,
        body.len()
    );
    let mut request = head.into_bytes();
    request.extend_from_slice(&body);
    request.extend_from_slice(b"\r\n0\r\n\r\n");
    let (st, _, b) = s.raw(&request);
    assert_eq!(st, 201, "{}", String::from_utf8_lossy(&b));
    let (st, again) = s.get(&format!(
        "/api/v1/missions/{}",
        kept["id"].as_str().unwrap()
    ));
    assert_eq!(st, 200, "{again}");
    assert_eq!(again["steps"], 50, "the mission stored before is intact");
}

/// The resident memory (VmRSS) and its peak (VmHWM) of a process, in
/// bytes (Linux).
fn memory(pid: u32) -> (u64, u64) {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    let field = |name: &str| {
        let line = status.lines().find(|l| l.starts_with(name)).unwrap();
        let kib: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        kib * 1024
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// A 50 MiB mission (the paper scenario, 660,000 steps) uploaded ten
/// times: the service reads each upload into typed data without a JSON
/// tree, so its resident memory ends within three bodies of where it
/// started (it held about 5.5 bodies more, and peaked at 11, when each
/// upload became a JSON tree), and its peak stays under six bodies. Each
/// stored mission lists its steps and its stored size, the text without
/// whitespace.
#[test]
fn ten_large_uploads_leave_the_service_within_three_bodies_of_its_start() {
    let path = nvector_tests::temp_file("large.json");
    let out = nvector_tests::run(&[
        "simulate",
        "--scenario",
        "paper",
        "--steps",
        "660000",
        "--seed",
        "5",
        "--out",
        path.to_str().unwrap(),
    ]);
    nvector_tests::succeeded(&out);
    let body = std::fs::read(&path).unwrap();
    let size = body.len() as u64;
    assert!(size > 48 << 20, "{size} bytes");
    let s = Server::start(&["--workers", "1", "--short-lane-workers", "0"]);
    let pid = s.child.id();
    let (start, _) = memory(pid);
    for k in 0..10 {
        let (st, _, answer) = s.req(
            "POST",
            "/api/v1/missions",
            Some(("application/json", &body)),
            &[],
        );
        assert_eq!(st, 201, "upload {k}: {}", String::from_utf8_lossy(&answer));
    }
    let (end, peak) = memory(pid);
    let mib = |b: u64| b as f64 / (1 << 20) as f64;
    eprintln!(
        "BENCH upload_memory body {:.1} MiB: resident {:.1} -> {:.1} MiB, peak {:.1} MiB",
        mib(size),
        mib(start),
        mib(end),
        mib(peak)
    );
    assert!(
        end <= start + 3 * size,
        "resident {:.1} MiB after ten uploads of {:.1} MiB, from {:.1} MiB",
        mib(end),
        mib(size),
        mib(start)
    );
    assert!(peak <= start + 6 * size, "peak {:.1} MiB", mib(peak));
    let (st, list) = s.get("/api/v1/missions?limit=20");
    assert_eq!(st, 200);
    let missions = list["missions"].as_array().unwrap();
    assert_eq!(missions.len(), 10);
    let uploaded: Value = serde_json::from_slice(&body).unwrap();
    for m in &missions[..1] {
        assert_eq!(m["steps"], 660000);
        let id = m["id"].as_str().unwrap();
        let (st, _, stored) = s.req("GET", &format!("/api/v1/missions/{id}"), None, &[]);
        assert_eq!(st, 200);
        // The stored text reads as the uploaded mission, and is what the
        // list counts.
        assert_eq!(m["bytes"], stored.len() as u64, "{m}");
        assert!(stored.len() as u64 <= size);
        assert!(serde_json::from_slice::<Value>(&stored).unwrap() == uploaded);
    }
}
