//! The REST API of docs/api.md over a real socket, against the real binary
//! on a real SQLite file and on a real PostgreSQL server (the same
//! scenarios on both).

use nvector_tests as common;
use nvector_tests::{on_both_storages, small_mission, Backend, Server};
use serde_json::{json, Value};
use std::time::Duration;

fn missions_jobs_results(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "2"]);
    assert_eq!(s.req("GET", "/healthz", None, &[]).0, 200);
    assert_eq!(s.req("GET", "/readyz", None, &[]).0, 200);

    // Upload as JSON.
    let mission = small_mission(5, 2500);
    let (st, m) = s.post("/api/v1/missions", &mission);
    assert_eq!(st, 201, "{m}");
    let id = m["id"].as_str().unwrap().to_string();
    assert_eq!(m["steps"], 2500);
    assert_eq!(
        m["detections"],
        mission["detections"].as_array().unwrap().len()
    );
    // Stored as uploaded.
    let (st, back) = s.get(&format!("/api/v1/missions/{id}"));
    assert_eq!(st, 200);
    assert_eq!(back, mission);

    // Upload as multipart.
    let text = small_mission(6, 1000).to_string();
    let body = format!(
        "--XyZ\r\nContent-Disposition: form-data; name=\"file\"; filename=\"m.json\"\r\nContent-Type: application/json\r\n\r\n{text}\r\n--XyZ--\r\n"
    );
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("multipart/form-data; boundary=XyZ", body.as_bytes())),
        &[],
    );
    assert_eq!(st, 201, "{}", String::from_utf8_lossy(&b));

    // Listing with paging.
    let (st, page1) = s.get("/api/v1/missions?limit=1");
    assert_eq!(st, 200);
    assert_eq!(page1["missions"].as_array().unwrap().len(), 1);
    let next = page1["next"].as_str().unwrap();
    let (_, page2) = s.get(&format!("/api/v1/missions?limit=10&after={next}"));
    assert_eq!(page2["missions"].as_array().unwrap().len(), 1);
    assert_ne!(page1["missions"][0]["id"], page2["missions"][0]["id"]);
    // Each item says when it was stored and its size: the stored JSON's
    // bytes (the first mission is stored as its JSON text).
    let first = &page1["missions"][0];
    assert_eq!(first["id"], m["id"]);
    assert_eq!(first["bytes"], mission.to_string().len(), "{first}");
    assert!(
        first["created_ms"].as_i64().unwrap() > 1_600_000_000_000,
        "{first}"
    );
    // The cursor's mission deleted between two pages: the next page is
    // still the missions after it (it was empty: a client lost the rest).
    let (st, extra) = s.post("/api/v1/missions", &small_mission(7, 200));
    assert_eq!(st, 201, "{extra}");
    let (_, first) = s.get("/api/v1/missions?limit=2");
    let cursor = first["next"].as_str().unwrap().to_string();
    assert_eq!(
        s.req("DELETE", &format!("/api/v1/missions/{cursor}"), None, &[])
            .0,
        204
    );
    let (st, rest) = s.get(&format!("/api/v1/missions?limit=10&after={cursor}"));
    assert_eq!(st, 200, "{rest}");
    assert_eq!(rest["missions"].as_array().unwrap().len(), 1, "{rest}");
    assert_eq!(rest["missions"][0]["id"], extra["id"], "{rest}");

    // A job to the end, with its events.
    let (st, job) = s.post(
        "/api/v1/jobs",
        &json!({"mission": id, "contractor": "projection"}),
    );
    assert_eq!(st, 202, "{job}");
    assert_eq!(job["state"], "queued");
    let jid = job["id"].as_str().unwrap().to_string();
    let (st, head, events) = s.req("GET", &format!("/api/v1/jobs/{jid}/events"), None, &[]);
    assert_eq!(st, 200);
    assert!(head.to_ascii_lowercase().contains("text/event-stream"));
    let events = String::from_utf8_lossy(&events);
    assert!(
        events.contains("event: end"),
        "the stream ends with the job: {events}"
    );
    let done = s.wait_job(&jid, Duration::from_secs(60));
    assert_eq!(done["state"], "done", "{done}");
    assert_eq!(done["progress"]["fraction"], 1.0);
    let (st, result) = s.get(&format!("/api/v1/jobs/{jid}/result"));
    assert_eq!(st, 200);
    assert_eq!(result["format"], "nvector-result/1");
    // A finished job's progress is its result's (the last progress line
    // came within the throttle of the one before and was dropped).
    assert_eq!(
        done["progress"]["round"], result["metrics"]["rounds"],
        "{done}"
    );
    assert_eq!(
        done["progress"]["max_trajectory_diameter"], result["metrics"]["max_trajectory_diameter"],
        "{done}"
    );
    assert_eq!(result["score"]["truth_inside"], true);
    assert_eq!(result["trajectory"].as_array().unwrap().len(), 2501);
    let (st, _, csv) = s.req(
        "GET",
        &format!("/api/v1/jobs/{jid}/result?format=csv"),
        None,
        &[],
    );
    assert_eq!(st, 200);
    let csv = String::from_utf8(csv).unwrap();
    assert!(
        csv.starts_with("step,t,x_lo,x_hi,y_lo,y_hi\n"),
        "{}",
        &csv[..80]
    );
    assert_eq!(csv.lines().count(), 2502);
    // The time of step i is i dt (the mission's `dt`), and the bounds are
    // the result's.
    let dt = mission["dt"].as_f64().unwrap();
    for i in [0usize, 1, 1000, 2500] {
        let row: Vec<&str> = csv.lines().nth(i + 1).unwrap().split(',').collect();
        assert_eq!(row[0], i.to_string());
        let t: f64 = row[1].parse().unwrap();
        assert!(
            (t - i as f64 * dt).abs() <= 1e-9 * (1.0 + t),
            "step {i}: t = {t}"
        );
        let x_lo: f64 = row[2].parse().unwrap();
        assert_eq!(
            Some(x_lo),
            result["trajectory"][i][0][0].as_f64(),
            "step {i}"
        );
    }
    let (st, _, svg) = s.req(
        "GET",
        &format!("/api/v1/jobs/{jid}/result?format=svg"),
        None,
        &[],
    );
    assert_eq!(st, 200);
    assert!(String::from_utf8_lossy(&svg).starts_with("<svg"));

    // Metrics count the finished job and the requests, and time them.
    let (_, head, metrics) = s.req("GET", "/metrics", None, &[]);
    assert!(head.contains("application/openmetrics-text"), "{head}");
    let metrics = String::from_utf8(metrics).unwrap();
    assert!(
        metrics.contains("nvector_jobs{state=\"done\"} 1"),
        "{metrics}"
    );
    assert!(
        metrics
            .contains("nvector_http_requests_total{route=\"/api/v1/missions\",status=\"201\"} 3"),
        "{metrics}"
    );
    assert!(
        metrics.contains(
            "nvector_http_request_duration_ms_count{route=\"/api/v1/missions\",status=\"201\"} 3"
        ),
        "{metrics}"
    );
    assert!(
        metrics.contains("nvector_job_duration_ms_count{lane=\"short\"} 1"),
        "{metrics}"
    );
    assert!(
        metrics.contains("nvector_job_queue_wait_ms_count{lane=\"short\"} 1"),
        "{metrics}"
    );

    // Delete the mission: its jobs go with it.
    assert_eq!(
        s.req("DELETE", &format!("/api/v1/missions/{id}"), None, &[])
            .0,
        204
    );
    assert_eq!(s.get(&format!("/api/v1/missions/{id}")).0, 404);
    assert_eq!(s.get(&format!("/api/v1/jobs/{jid}")).0, 404);
    assert_eq!(
        s.req("DELETE", &format!("/api/v1/missions/{id}"), None, &[])
            .0,
        404
    );
}

fn cancel_a_long_job(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "1"]);
    let (_, m) = s.post("/api/v1/simulate", &json!({"scenario": "auv", "seed": 2}));
    let id = m["id"].as_str().unwrap();
    // Three long jobs on one worker: the later ones wait in the queue.
    let ids: Vec<String> = (0..3)
        .map(|_| {
            s.post(
                "/api/v1/jobs",
                &json!({"mission": id, "contractor": "best"}),
            )
            .1["id"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    let (st, _, c) = s.req("DELETE", &format!("/api/v1/jobs/{}", ids[2]), None, &[]);
    assert_eq!(st, 202, "{}", String::from_utf8_lossy(&c));
    let j = s.wait_job(&ids[2], Duration::from_secs(5));
    assert_eq!(j["state"], "cancelled");
    assert_eq!(s.get(&format!("/api/v1/jobs/{}/result", ids[2])).0, 409);
    assert_eq!(s.req("DELETE", "/api/v1/jobs/j-nope", None, &[]).0, 404);
    for id in &ids[..2] {
        assert_eq!(s.wait_job(id, Duration::from_secs(120))["state"], "done");
    }
}

fn contract_and_simulate_endpoints(b: &Backend) {
    let s = Server::start_on(b, &[]);
    let (st, r) = s.post(
        "/api/v1/contract",
        &json!({"format": "nvector-contract/1", "n": 2, "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]]}),
    );
    assert_eq!(st, 200, "{r}");
    assert_eq!(r["groups"], json!([[0, 1], [2]]));
    let (st, r) = s.post(
        "/api/v1/contract",
        &json!({"format": "nvector-contract/1", "n": 2, "boxes": [[[3, 2]]]}),
    );
    assert_eq!(st, 422);
    assert_eq!(r["error"]["path"], "boxes[0][0]");
    let (st, r) = s.post(
        "/api/v1/simulate",
        &json!({"scenario": "paper", "seed": 3, "steps": 500}),
    );
    assert_eq!(st, 201, "{r}");
    assert_eq!(r["mission"]["format"], "nvector-mission/1");
    assert_eq!(
        s.get(&format!("/api/v1/missions/{}", r["id"].as_str().unwrap()))
            .0,
        200
    );
    let (st, r) = s.post("/api/v1/simulate", &json!({"scenario": "moon"}));
    assert_eq!((st, r["error"]["path"].as_str()), (422, Some("scenario")));
}

fn malformed_requests_get_4xx_naming_the_problem(b: &Backend) {
    let s = Server::start_on(
        b,
        &[
            "--max-steps",
            "100000",
            "--max-queue",
            "1",
            "--workers",
            "1",
            // One worker in all, so that a second job waits.
            "--short-lane-workers",
            "0",
        ],
    );
    let mission = small_mission(1, 300);
    let check = |st: u16, body: &[u8], code: &str| {
        assert!(
            (400..500).contains(&st),
            "status {st}: {}",
            String::from_utf8_lossy(body)
        );
        let v: Value = serde_json::from_slice(body)
            .unwrap_or_else(|_| panic!("JSON error body: {}", String::from_utf8_lossy(body)));
        assert_eq!(v["error"]["code"], code, "{v}");
        v
    };
    // Broken JSON, NaN and Infinity literals.
    for text in ["{\"format\": ", "{\"dt\": NaN}", "[Infinity]"] {
        let (st, _, b) = s.req(
            "POST",
            "/api/v1/missions",
            Some(("application/json", text.as_bytes())),
            &[],
        );
        check(st, &b, "invalid_json");
    }
    // The path names the value a syntax error stopped at (it was "").
    for (text, path) in [
        ("{\"format\": \"nvector-mission/1\", \"dt\": NaN}", "dt"),
        ("{\"steps\": 10, \"dt\": 1e400}", "dt"),
        (
            "{\"detections\": [{\"range\": [1, 2]}, {\"range\": [1, Infinity]}]}",
            "detections[1].range[1]",
        ),
        // A repeated key: the CLI's typed read refuses it; the service
        // kept the last value and stored the mission (201).
        (
            "{\"format\": \"nvector-mission/1\", \"dt\": 0.1, \"dt\": 0.2}",
            "dt",
        ),
    ] {
        let (st, _, b) = s.req(
            "POST",
            "/api/v1/missions",
            Some(("application/json", text.as_bytes())),
            &[],
        );
        let v = check(st, &b, "invalid_json");
        assert_eq!(v["error"]["path"], path, "{text}: {v}");
    }
    // Wrong types and lo > hi, with the path.
    let mut m = mission.clone();
    m["dt"] = json!("fast");
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", m.to_string().as_bytes())),
        &[],
    );
    assert_eq!(check(st, &b, "invalid_mission")["error"]["path"], "dt");
    let mut m = mission.clone();
    m["detections"][0]["range"] = json!([9, 1]);
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", m.to_string().as_bytes())),
        &[],
    );
    let v = check(st, &b, "invalid_mission");
    assert_eq!(v["error"]["path"], "detections[0].range");
    assert!(v["error"]["message"]
        .as_str()
        .unwrap()
        .contains("lower bound 9 is above upper bound 1"));
    // Too many steps for this service.
    let mut m = mission.clone();
    m["steps"] = json!(200_000);
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", m.to_string().as_bytes())),
        &[],
    );
    assert_eq!(check(st, &b, "too_large")["error"]["path"], "steps");
    // Wrong content type; truncated multipart; multipart without file.
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("text/plain", b"hello")),
        &[],
    );
    check(st, &b, "unsupported_media_type");
    let trunc = b"--XyZ\r\nContent-Disposition: form-data; name=\"file\"\r\n\r\n{\"format\"";
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("multipart/form-data; boundary=XyZ", trunc)),
        &[],
    );
    assert!(
        (400..500).contains(&st),
        "truncated multipart: {st} {}",
        String::from_utf8_lossy(&b)
    );
    let nofile = b"--XyZ\r\nContent-Disposition: form-data; name=\"other\"\r\n\r\nx\r\n--XyZ--\r\n";
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("multipart/form-data; boundary=XyZ", nofile)),
        &[],
    );
    check(st, &b, "invalid_multipart");
    // Unknown ids, unknown endpoint, bad job fields.
    let (st, _, b) = s.req("GET", "/api/v1/missions/m-nope", None, &[]);
    check(st, &b, "not_found");
    let (st, _, b) = s.req("GET", "/api/v1/nothing", None, &[]);
    check(st, &b, "not_found");
    let (st, v) = s.post("/api/v1/jobs", &json!({"mission": "m-nope"}));
    assert_eq!((st, v["error"]["path"].as_str()), (404, Some("mission")));
    let (_, created) = s.post("/api/v1/missions", &mission);
    let mid = created["id"].as_str().unwrap();
    let (st, v) = s.post(
        "/api/v1/jobs",
        &json!({"mission": mid, "contractor": "magic"}),
    );
    assert_eq!((st, v["error"]["path"].as_str()), (422, Some("contractor")));
    let (st, v) = s.post("/api/v1/jobs", &json!({"mission": mid, "max_rounds": -3}));
    assert_eq!((st, v["error"]["path"].as_str()), (422, Some("max_rounds")));
    let (st, v) = s.post("/api/v1/jobs", &json!({"mission": mid, "colour": "red"}));
    assert_eq!((st, v["error"]["path"].as_str()), (422, Some("colour")));
    // A bad query names its parameter (a non-integer `limit` said "").
    for (query, path) in [
        ("limit=zero", "limit"),
        ("limit=1.5", "limit"),
        ("limit=", "limit"),
        ("limit=2&limit=3", "limit"),
    ] {
        let (st, _, b) = s.req("GET", &format!("/api/v1/missions?{query}"), None, &[]);
        assert_eq!(
            check(st, &b, "invalid_query")["error"]["path"],
            path,
            "{query}"
        );
    }
    // An `after` naming no mission (any string is well formed): 404.
    for query in ["after=m-never", "after="] {
        let (st, _, b) = s.req("GET", &format!("/api/v1/missions?{query}"), None, &[]);
        assert_eq!(st, 404, "{query}");
        assert_eq!(
            check(st, &b, "not_found")["error"]["path"],
            "after",
            "{query}"
        );
    }
    // The framework's own answers carry the JSON error body too (a 405
    // and a 404 past the routes had an empty body, a path that is not
    // UTF-8 a text one).
    let (st, head, b) = s.req("GET", "/api/v1/jobs", None, &[]);
    assert_eq!(st, 405);
    check(st, &b, "method_not_allowed");
    assert!(head.to_ascii_lowercase().contains("allow: post"), "{head}");
    let (st, _, b) = s.req("PUT", "/api/v1/missions/m-nope", None, &[]);
    check(st, &b, "method_not_allowed");
    let (st, _, b) = s.req("GET", "/api/v1/", None, &[]);
    check(st, &b, "not_found");
    let (st, _, b) = s.req("GET", "/api/v1/missions/%ff", None, &[]);
    assert_eq!(check(st, &b, "bad_request")["error"]["path"], "id");
    // The queue limit: 429 with Retry-After once one job waits.
    let (_, auv) = s.post(
        "/api/v1/simulate",
        &json!({"scenario": "auv", "seed": 1, "steps": 60000}),
    );
    let aid = auv["id"].as_str().unwrap();
    let mut saw_429 = false;
    for _ in 0..6 {
        let body = json!({"mission": aid}).to_string();
        let (st, head, _) = s.req(
            "POST",
            "/api/v1/jobs",
            Some(("application/json", body.as_bytes())),
            &[],
        );
        if st == 429 {
            assert!(
                head.to_ascii_lowercase().contains("retry-after: 5"),
                "{head}"
            );
            saw_429 = true;
            break;
        }
        assert_eq!(st, 202);
    }
    assert!(saw_429, "the queue limit of 1 was never reached");
    // Nothing stored was lost along the way.
    assert_eq!(s.get(&format!("/api/v1/missions/{mid}")).1, mission);
}

fn api_keys_separate_owners(b: &Backend) {
    let dir = common::temp_dir("keys");
    let keys = dir.join("keys.txt");
    std::fs::write(&keys, "alpha\nbeta\n").unwrap();
    let s = Server::start_on(b, &["--api-key-file", keys.to_str().unwrap()]);
    let body = small_mission(2, 200).to_string();
    let (st, _, _) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", body.as_bytes())),
        &[],
    );
    assert_eq!(st, 401);
    let (st, head, _) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", body.as_bytes())),
        &[("Authorization", "Bearer gamma")],
    );
    assert_eq!(st, 401);
    assert!(
        head.to_ascii_lowercase()
            .contains("www-authenticate: bearer"),
        "a 401 names its scheme: {head}"
    );
    // The scheme's name is case-insensitive.
    let (st, _, b) = s.req(
        "GET",
        "/api/v1/missions",
        None,
        &[("Authorization", "bearer beta")],
    );
    assert_eq!(st, 200, "{}", String::from_utf8_lossy(&b));
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", body.as_bytes())),
        &[("Authorization", "Bearer alpha")],
    );
    assert_eq!(st, 201);
    let id = serde_json::from_slice::<Value>(&b).unwrap()["id"]
        .as_str()
        .unwrap()
        .to_string();
    let path = format!("/api/v1/missions/{id}");
    assert_eq!(
        s.req("GET", &path, None, &[("Authorization", "Bearer alpha")])
            .0,
        200
    );
    assert_eq!(
        s.req("GET", &path, None, &[("Authorization", "Bearer beta")])
            .0,
        404
    );
    assert_eq!(
        s.req("DELETE", &path, None, &[("Authorization", "Bearer beta")])
            .0,
        404
    );
    assert_eq!(
        s.req("GET", &path, None, &[("Authorization", "Bearer alpha")])
            .0,
        200
    );
}

/// `nvector bench --service`: clients at once against a real service; every
/// client's job ends done, none fails.
fn load_run_of_the_bench(b: &Backend) {
    let mut cmd = common::nvector();
    cmd.args(["bench", "--service", "--clients", "24", "--steps", "300"]);
    if let Backend::Postgres(c) = b {
        cmd.args(["--database", &c.create_db()]);
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["name"], "service_load");
    assert_eq!(v["clients"], 24);
    assert_eq!(v["errors"], 0, "{v}");
    assert!(
        v["p50_ms"].as_f64().unwrap() <= v["p99_ms"].as_f64().unwrap(),
        "{v}"
    );
    assert!(v["peak_rss_mib"].as_f64().unwrap() > 1.0, "{v}");
}

/// An odometry2d mission with every field of the model (`scan`,
/// `sensor_offset`, `landmark_min_separation`, `initial_heading`,
/// `heading_error`, `truth.headings`, null truth entries) is accepted and
/// stored as uploaded; its job's result carries a heading interval per
/// step holding the true heading, and its SVG figure draws them.
fn odometry2d_missions_and_headings(b: &Backend) {
    let path = common::temp_file("woods-http.json");
    common::succeeded(&common::run(&[
        "simulate",
        "--scenario",
        "woods",
        "--steps",
        "120",
        "--seed",
        "4",
        "--out",
        path.to_str().unwrap(),
    ]));
    let mut mission = common::read_json(&path);
    assert_eq!(mission["model"], "odometry2d");
    for field in [
        "sensor_offset",
        "landmark_min_separation",
        "initial_heading",
        "heading_error",
    ] {
        assert!(!mission[field].is_null(), "the woods mission lacks {field}");
    }
    assert!(mission["detections"][0]["scan"].is_u64());
    // A motion-capture gap: null truth at step 30.
    mission["truth"]["positions"][30] = Value::Null;
    mission["truth"]["headings"][30] = Value::Null;

    let s = Server::start_on(b, &["--workers", "1"]);
    let (st, m) = s.post("/api/v1/missions", &mission);
    assert_eq!(st, 201, "{m}");
    let id = m["id"].as_str().unwrap().to_string();
    assert_eq!(m["steps"], 120);
    let (_, back) = s.get(&format!("/api/v1/missions/{id}"));
    assert_eq!(back, mission, "stored as uploaded");
    let (st, job) = s.post(
        "/api/v1/jobs",
        &json!({"mission": id, "contractor": "none"}),
    );
    assert_eq!(st, 202, "{job}");
    let jid = job["id"].as_str().unwrap().to_string();
    let done = s.wait_job(&jid, Duration::from_secs(60));
    assert_eq!(done["state"], "done", "{done}");
    let (st, result) = s.get(&format!("/api/v1/jobs/{jid}/result"));
    assert_eq!(st, 200);
    assert_eq!(result["score"]["truth_inside"], true, "{}", result["score"]);
    let headings = result["headings"].as_array().expect("headings");
    assert_eq!(headings.len(), 121);
    let truth = mission["truth"]["headings"].as_array().unwrap();
    for (i, (h, t)) in headings.iter().zip(truth).enumerate() {
        let (lo, hi) = (h[0].as_f64().unwrap(), h[1].as_f64().unwrap());
        if let Some(t) = t.as_f64() {
            assert!(
                lo <= t && t <= hi,
                "step {i}: true heading {t} not in [{lo}, {hi}]"
            );
        }
    }
    assert!(result["metrics"]["max_heading_width"].as_f64().unwrap() > 0.0);
    let (st, _, svg) = s.req(
        "GET",
        &format!("/api/v1/jobs/{jid}/result?format=svg"),
        None,
        &[],
    );
    assert_eq!(st, 200);
    let svg = String::from_utf8_lossy(&svg);
    assert!(
        svg.contains("heading (interval)"),
        "the figure draws no heading"
    );
    assert!(svg.contains("true heading"));
}

on_both_storages!(
    odometry2d_missions_and_headings,
    load_run_of_the_bench,
    missions_jobs_results,
    cancel_a_long_job,
    contract_and_simulate_endpoints,
    malformed_requests_get_4xx_naming_the_problem,
    api_keys_separate_owners,
);

#[test]
fn static_files_cannot_escape_their_directory() {
    let s = Server::start(&[]);
    let www = s.dir.join("www");
    // No page yet: the built-in one.
    let (st, _, b) = s.req("GET", "/", None, &[]);
    assert_eq!(st, 200);
    assert!(String::from_utf8_lossy(&b).contains("not built"));
    drop(s);
    std::fs::create_dir_all(&www).unwrap();
    std::fs::write(www.join("index.html"), "<h1>page</h1>").unwrap();
    std::fs::write(www.parent().unwrap().join("secret.txt"), "top secret").unwrap();
    let s = Server::start_with(
        www.parent().unwrap().to_path_buf(),
        format!(
            "sqlite://{}",
            www.parent().unwrap().join("db2.db").display()
        ),
        &[],
    );
    let (st, _, b) = s.req("GET", "/", None, &[]);
    assert_eq!(
        (st, String::from_utf8_lossy(&b).contains("<h1>page</h1>")),
        (200, true)
    );
    for p in [
        "/../secret.txt",
        "/..%2fsecret.txt",
        "/%2e%2e/secret.txt",
        "/a/../../secret.txt",
    ] {
        let (st, _, b) = s.req("GET", p, None, &[]);
        assert!(
            !String::from_utf8_lossy(&b).contains("top secret"),
            "{p} leaked the file ({st})"
        );
    }
}

/// Regression (found by the fuzzer): POST /simulate with `false_detections`
/// at the service's detection limit stored and returned a mission with more
/// detections than the limit (the true ones on top), which the document's
/// Mission schema (maxItems) and GET /missions/{id} then contradicted.
#[test]
fn issue_13_simulated_missions_fit_the_detection_limit() {
    let s = nvector_tests::Server::start(&["--max-detections", "60"]);
    let (status, body) = s.post(
        "/api/v1/simulate",
        &serde_json::json!({"scenario": "paper", "seed": 3, "steps": 4000, "false_detections": 60}),
    );
    assert_eq!(status, 201, "{body}");
    let dets = body["mission"]["detections"].as_array().unwrap().len();
    assert_eq!(dets, 60, "true detections plus as many false ones as fit");
    let falses = body["mission"]["truth"]["matching"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m.is_null())
        .count();
    assert!(falses > 0 && falses < 60);
    assert_eq!(body["mission"]["max_outliers"], falses);
    let (status, stored) = s.get(&format!(
        "/api/v1/missions/{}",
        body["id"].as_str().unwrap()
    ));
    assert_eq!(status, 200);
    assert_eq!(stored["detections"].as_array().unwrap().len(), 60);
}

/// The value of header `name` in a response head (lower-cased name).
fn header_of(head: &str, name: &str) -> Option<String> {
    head.lines().find_map(|l| {
        let (k, v) = l.split_once(':')?;
        (k.trim().eq_ignore_ascii_case(name)).then(|| v.trim().to_string())
    })
}

/// Decompresses with the command-line tool (`brotli` or `gzip`), as a
/// client would see the body.
fn decompressed(tool: &str, body: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut child = std::process::Command::new(tool)
        .args(["-d", "-c"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{tool} (scripts/setup.sh installs it): {e}"));
    child.stdin.take().unwrap().write_all(body).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{tool} -d failed");
    out.stdout
}

/// The page's files are sent precompressed by content negotiation (brotli,
/// gzip, or as they are), the page's first wasm (the playground's) in at most
/// scripts/web.sh's budget, with validation
/// headers: a client that has the file gets 304.
#[test]
fn the_page_is_served_precompressed_and_revalidated() {
    let www = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../web/www");
    let wasm = std::fs::read(www.join("pkg/nvector_web_bg.wasm"))
        .expect("the page is not built: run `scripts/web.sh build` (make test does)");
    let dir = std::env::temp_dir().join(format!("nvector-static-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let link = dir.join("www");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&www, &link).unwrap();
    let db = format!("sqlite://{}", dir.join("nvector.db").display());
    let s = Server::start_with(dir, db, &[]);
    let path = "/pkg/nvector_web_bg.wasm";
    for (accept, encoding, tool) in [
        ("br, gzip", Some("br"), "brotli"),
        ("gzip", Some("gzip"), "gzip"),
        ("identity", None, ""),
    ] {
        let (st, head, body) = s.req("GET", path, None, &[("Accept-Encoding", accept)]);
        assert_eq!(st, 200, "{head}");
        assert_eq!(
            header_of(&head, "content-encoding").as_deref(),
            encoding,
            "{head}"
        );
        assert_eq!(
            header_of(&head, "content-type").as_deref(),
            Some("application/wasm")
        );
        assert_eq!(
            header_of(&head, "cache-control").as_deref(),
            Some("no-cache")
        );
        assert_eq!(header_of(&head, "vary").as_deref(), Some("accept-encoding"));
        let plain = match encoding {
            Some(_) => decompressed(tool, &body),
            None => body.clone(),
        };
        assert!(plain == wasm, "{accept}: the body is not the page's wasm");
        if encoding == Some("br") {
            assert!(
                body.len() <= 75_000,
                "{} bytes of wasm sent with brotli",
                body.len()
            );
        }
        // Revalidation: unchanged since the last answer, 304 and no body.
        let modified = header_of(&head, "last-modified").expect("last-modified");
        let (st, _, body) = s.req(
            "GET",
            path,
            None,
            &[
                ("Accept-Encoding", accept),
                ("If-Modified-Since", &modified),
            ],
        );
        assert_eq!((st, body.len()), (304, 0), "{accept}");
    }
    // The page itself, and a file with no compressed copy, as they are.
    let (st, head, body) = s.req("GET", "/", None, &[("Accept-Encoding", "br")]);
    assert_eq!(st, 200, "{head}");
    assert_eq!(header_of(&head, "content-encoding").as_deref(), Some("br"));
    let html = std::fs::read(www.join("index.html")).unwrap();
    assert!(decompressed("brotli", &body) == html);
}
