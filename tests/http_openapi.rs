//! The OpenAPI document against the service's real behaviour: every
//! documented operation is routed; real responses (statuses, content types
//! and whole JSON bodies, checked against their schemas) match what it
//! documents; its links lead from a mission to its job, the job's events
//! and its result; its request examples are accepted; and the cases a
//! schema-driven fuzzer found (nulls, whole floats, unknown fields) agree
//! between the document and the service.

use nvector_tests as common;

use common::schema::validate;
use common::{small_mission, Server};
use serde_json::{json, Value};
use std::time::Duration;

/// The content type of a response head, without parameters.
fn content_type(head: &str) -> String {
    head.lines()
        .find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.eq_ignore_ascii_case("content-type")
                .then(|| v.split(';').next().unwrap_or("").trim().to_string())
        })
        .unwrap_or_default()
}

/// Checks one real response against the document: the status is
/// documented, with the content type, and a JSON body conforms to its
/// schema.
fn conforms(doc: &Value, method: &str, template: &str, status: u16, head: &str, body: &[u8]) {
    let op = &doc["paths"][template][method];
    assert!(op.is_object(), "{method} {template} is not documented");
    let resp = &op["responses"][status.to_string()];
    assert!(
        resp.is_object(),
        "{method} {template} answered {status}, which is not documented"
    );
    let ctype = content_type(head);
    if body.is_empty() {
        return;
    }
    let content = &resp["content"][&ctype];
    assert!(
        content.is_object(),
        "{method} {template} {status}: content type {ctype} is not documented: {}",
        resp["content"]
    );
    if ctype == "application/json" {
        let v: Value = serde_json::from_slice(body)
            .unwrap_or_else(|_| panic!("{method} {template} {status}: not JSON"));
        let errors = validate(doc, &content["schema"], &v);
        assert!(
            errors.is_empty(),
            "{method} {template} {status}: the body does not match the document: {errors:?}\n{v}"
        );
    }
}

/// A client of one server that records every exchange for `conforms`.
struct Recorder<'a> {
    s: &'a Server,
    exchanges: Vec<(String, String, String, u16, String, Vec<u8>)>,
}

impl Recorder<'_> {
    fn send(&mut self, method: &str, path: &str, template: &str, body: Option<Value>) -> Value {
        let text = body.map(|b| b.to_string());
        let (st, head, b) = self.s.req(
            &method.to_ascii_uppercase(),
            path,
            text.as_deref().map(|t| ("application/json", t.as_bytes())),
            &[],
        );
        let v = serde_json::from_slice(&b).unwrap_or(Value::Null);
        self.exchanges
            .push((method.into(), path.into(), template.into(), st, head, b));
        v
    }

    fn status(&self) -> u16 {
        self.exchanges.last().unwrap().3
    }

    fn check_all(&self, doc: &Value) {
        for (method, path, template, status, head, body) in &self.exchanges {
            assert!(*status < 500, "{method} {path}: {status}");
            conforms(doc, method, template, *status, head, body);
        }
    }
}

#[test]
fn real_responses_match_the_document() {
    let s = Server::start(&["--workers", "1"]);
    let (st, doc) = s.get("/api/v1/openapi.json");
    assert_eq!(st, 200);
    assert_eq!(doc["openapi"], "3.1.0");
    let mut r = Recorder {
        s: &s,
        exchanges: Vec::new(),
    };
    let m = r.send(
        "post",
        "/api/v1/missions",
        "/api/v1/missions",
        Some(small_mission(3, 500)),
    );
    let id = m["id"].as_str().unwrap().to_string();
    r.send(
        "post",
        "/api/v1/missions",
        "/api/v1/missions",
        Some(json!({"format": "nope"})),
    );
    r.send("get", "/api/v1/missions", "/api/v1/missions", None);
    r.send("get", "/api/v1/missions?limit=0", "/api/v1/missions", None);
    r.send(
        "get",
        &format!("/api/v1/missions/{id}"),
        "/api/v1/missions/{id}",
        None,
    );
    r.send(
        "get",
        "/api/v1/missions/m-none",
        "/api/v1/missions/{id}",
        None,
    );
    let j = r.send(
        "post",
        "/api/v1/jobs",
        "/api/v1/jobs",
        Some(json!({"mission": id})),
    );
    let jid = j["id"].as_str().unwrap().to_string();
    r.send(
        "post",
        "/api/v1/jobs",
        "/api/v1/jobs",
        Some(json!({"mission": "m-none"})),
    );
    r.send(
        "post",
        "/api/v1/jobs",
        "/api/v1/jobs",
        Some(json!({"mission": id, "contractor": 3})),
    );
    s.wait_job(&jid, Duration::from_secs(60));
    r.send(
        "get",
        &format!("/api/v1/jobs/{jid}"),
        "/api/v1/jobs/{id}",
        None,
    );
    for q in [
        "",
        "?format=json",
        "?format=csv",
        "?format=svg",
        "?format=bmp",
    ] {
        r.send(
            "get",
            &format!("/api/v1/jobs/{jid}/result{q}"),
            "/api/v1/jobs/{id}/result",
            None,
        );
    }
    r.send(
        "get",
        &format!("/api/v1/jobs/{jid}/events"),
        "/api/v1/jobs/{id}/events",
        None,
    );
    r.send(
        "delete",
        &format!("/api/v1/jobs/{jid}"),
        "/api/v1/jobs/{id}",
        None,
    );
    r.send("delete", "/api/v1/jobs/j-none", "/api/v1/jobs/{id}", None);
    r.send(
        "post",
        "/api/v1/contract",
        "/api/v1/contract",
        Some(json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]]})),
    );
    r.send(
        "post",
        "/api/v1/contract",
        "/api/v1/contract",
        Some(json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]], [[2, 3]]]})),
    );
    r.send(
        "post",
        "/api/v1/contract",
        "/api/v1/contract",
        Some(json!({"format": "nvector-contract/1", "n": 0, "boxes": [[[0, 1]]]})),
    );
    r.send(
        "post",
        "/api/v1/simulate",
        "/api/v1/simulate",
        Some(json!({"scenario": "paper", "steps": 300})),
    );
    r.send(
        "delete",
        &format!("/api/v1/missions/{id}"),
        "/api/v1/missions/{id}",
        None,
    );
    r.send("get", "/healthz", "/healthz", None);
    r.send("get", "/readyz", "/readyz", None);
    r.send("get", "/metrics", "/metrics", None);
    r.send("get", "/api/v1/openapi.json", "/api/v1/openapi.json", None);
    r.check_all(&doc);
    // Every documented operation is routed (no 404 "no such endpoint" and
    // no 405).
    for (template, ops) in doc["paths"].as_object().unwrap() {
        for method in ops.as_object().unwrap().keys() {
            let path = template.replace("{id}", "x-unknown");
            let (st, _, b) = s.req(
                &method.to_ascii_uppercase(),
                &path,
                Some(("application/json", b"{}")),
                &[],
            );
            let routed = st != 405
                && !(st == 404 && String::from_utf8_lossy(&b).contains("no such endpoint"));
            assert!(
                routed,
                "{method} {template} is documented but not routed ({st})"
            );
        }
    }
}

/// The (path template, method) of an operation id.
fn operation(doc: &Value, id: &str) -> (String, String) {
    for (path, ops) in doc["paths"].as_object().unwrap() {
        for (method, op) in ops.as_object().unwrap() {
            if op["operationId"] == id {
                return (path.clone(), method.clone());
            }
        }
    }
    panic!("no operation {id}");
}

/// A link's value with its `$response.body#/...` expressions evaluated.
fn evaluate(v: &Value, response: &Value) -> Value {
    match v {
        Value::String(s) if s.starts_with("$response.body#") => response
            .pointer(&s["$response.body#".len()..])
            .cloned()
            .unwrap_or_else(|| panic!("{s} is not in {response}")),
        Value::Object(o) => Value::Object(
            o.iter()
                .map(|(k, x)| (k.clone(), evaluate(x, response)))
                .collect(),
        ),
        other => other.clone(),
    }
}

/// Follows every link of `response` (the answer of `op_id` with
/// `status`); returns the answers by link name.
fn follow(
    r: &mut Recorder,
    doc: &Value,
    op_id: &str,
    status: u16,
    response: &Value,
    skip: &[&str],
) -> Vec<(String, u16, Value)> {
    let (path, method) = operation(doc, op_id);
    let links = doc["paths"][&path][&method]["responses"][status.to_string()]["links"]
        .as_object()
        .unwrap_or_else(|| panic!("{op_id} {status} has no links"))
        .clone();
    let mut out = Vec::new();
    for (name, link) in links {
        if skip.contains(&name.as_str()) {
            continue;
        }
        let (target, target_method) = operation(doc, link["operationId"].as_str().unwrap());
        let mut concrete = target.clone();
        for (p, expr) in link["parameters"].as_object().into_iter().flatten() {
            let value = evaluate(expr, response);
            concrete = concrete.replace(&format!("{{{p}}}"), value.as_str().unwrap());
        }
        let body = link.get("requestBody").map(|b| evaluate(b, response));
        let v = r.send(&target_method, &concrete, &target, body);
        out.push((name, r.status(), v));
    }
    out
}

/// Regression (once: "no links from a created mission to its jobs,
/// events and results"): the document's links, followed as a client
/// generator would, lead from a simulated mission to a job, its events and
/// its result, and from the job back to its mission.
#[test]
fn issue_13_links_lead_from_a_mission_to_its_job_events_and_result() {
    let s = Server::start(&["--workers", "1"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let mut r = Recorder {
        s: &s,
        exchanges: Vec::new(),
    };
    let sim = r.send(
        "post",
        "/api/v1/simulate",
        "/api/v1/simulate",
        Some(json!({"scenario": "paper", "steps": 400, "seed": 2})),
    );
    assert_eq!(r.status(), 201, "{sim}");
    let from_mission = follow(&mut r, &doc, "simulate", 201, &sim, &["deleteMission"]);
    let names: Vec<&str> = from_mission.iter().map(|(n, _, _)| n.as_str()).collect();
    assert!(
        names.contains(&"createJob") && names.contains(&"getMission"),
        "{names:?}"
    );
    let (_, st, job) = from_mission
        .iter()
        .find(|(n, _, _)| n == "createJob")
        .unwrap()
        .clone();
    assert_eq!(st, 202, "{job}");
    s.wait_job(job["id"].as_str().unwrap(), Duration::from_secs(60));
    for (name, st, v) in follow(&mut r, &doc, "createJob", 202, &job, &[]) {
        match name.as_str() {
            "getJob" => assert_eq!(v["state"], "done", "{v}"),
            "jobResult" => assert_eq!(v["format"], "nvector-result/1", "{v}"),
            "jobEvents" => assert_eq!(st, 200),
            "cancelJob" => assert_eq!(st, 409, "{v}"),
            other => panic!("unexpected link {other}"),
        }
    }
    let (_, got) = s.get(&format!("/api/v1/jobs/{}", job["id"].as_str().unwrap()));
    for (name, st, v) in follow(&mut r, &doc, "getJob", 200, &got, &[]) {
        assert_eq!(st, 200, "{name}: {v}");
    }
    // The mission's delete link last: the job goes with it.
    let deleted = follow(&mut r, &doc, "createMission", 201, &sim, &[]);
    assert!(deleted
        .iter()
        .any(|(n, st, _)| n == "deleteMission" && *st == 204));
    r.check_all(&doc);
}

/// The examples the document gives for request bodies are accepted.
#[test]
fn request_examples_are_accepted() {
    let s = Server::start(&["--workers", "1"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let example = |name: &str| doc["components"]["schemas"][name]["example"].clone();
    let (st, m) = s.post("/api/v1/missions", &example("Mission"));
    assert_eq!(st, 201, "{m}");
    let (st, v) = s.post("/api/v1/contract", &example("ContractRequest"));
    assert_eq!((st, &v["status"]), (200, &json!("contracted")), "{v}");
    let (st, v) = s.post("/api/v1/simulate", &example("SimulateRequest"));
    assert_eq!(st, 201, "{v}");
    let mut job = example("JobRequest");
    job["mission"] = m["id"].clone();
    let (st, v) = s.post("/api/v1/jobs", &job);
    assert_eq!(st, 202, "{v}");
}

/// Regression (the API fuzzer's findings): what the document allows
/// the service accepts, and what it refuses the service refuses:
/// `"steps": null` is documented (null means absent) and accepted; a whole
/// float is an integer for both; a non-boolean `operator` and an unknown
/// field are refused by both.
#[test]
fn issue_13_nulls_whole_floats_and_unknown_fields_agree() {
    let s = Server::start(&["--workers", "1", "--max-steps", "5000"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let schema = |name: &str| json!({"$ref": format!("#/components/schemas/{name}")});
    let agree = |name: &str, path: &str, body: Value, expect: u16| {
        let valid = validate(&doc, &schema(name), &body).is_empty();
        let (st, v) = s.post(path, &body);
        assert_eq!(st, expect, "{body} -> {v}");
        assert_eq!(
            valid,
            st < 300,
            "document valid = {valid}, service {st}: {body}"
        );
        v
    };
    let sim = agree(
        "SimulateRequest",
        "/api/v1/simulate",
        json!({"scenario": "paper", "steps": null, "seed": 4.0, "landmarks": null}),
        201,
    );
    // Absent steps: the scenario's 10,000, capped at this service's 5,000.
    assert_eq!(sim["steps"], 5000);
    let v = agree(
        "SimulateRequest",
        "/api/v1/simulate",
        json!({"scenario": "paper", "operator": "yes"}),
        422,
    );
    assert_eq!(v["error"]["path"], "operator");
    agree(
        "SimulateRequest",
        "/api/v1/simulate",
        json!({"scenario": "auv", "layout": "ring"}),
        422,
    );
    agree(
        "SimulateRequest",
        "/api/v1/simulate",
        json!({"scenario": "paper", "stpes": 10}),
        422,
    );
    let id = sim["id"].clone();
    agree(
        "JobRequest",
        "/api/v1/jobs",
        json!({"mission": id, "max_rounds": 5.0, "time_limit_s": null}),
        202,
    );
    agree(
        "JobRequest",
        "/api/v1/jobs",
        json!({"mission": id, "max_rounds": 5.5}),
        422,
    );
    agree(
        "ContractRequest",
        "/api/v1/contract",
        json!({"format": "nvector-contract/1", "n": 2.0, "boxes": [[[0, 1]]], "contractor": null}),
        200,
    );
    agree(
        "ContractRequest",
        "/api/v1/contract",
        json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]], "extra": 1}),
        422,
    );
    let mut m = small_mission(5, 2000);
    assert!(!m["detections"].as_array().unwrap().is_empty());
    m["final_position"] = Value::Null;
    m["landmark_count"] = json!(4.0);
    agree("Mission", "/api/v1/missions", m.clone(), 201);
    m["detections"][0]["range"] = json!([-1, 2]);
    agree("Mission", "/api/v1/missions", m, 422);
}

/// The woods scenario through
/// `POST /simulate`, read by core's one request type and described by
/// its schema: a small woods mission is accepted and is core's woods
/// mission, with false detections too; what the document refuses (noise,
/// a paper layout, range-only) the service refuses naming the field; a request whose mission could hold more
/// detections than the service's limit is schema-valid and refused with
/// 413 before anything is simulated.
#[test]
fn woods_through_post_simulate() {
    let s = Server::start(&["--workers", "1", "--max-detections", "20000"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let schema = json!({"$ref": "#/components/schemas/SimulateRequest"});
    let post = |body: Value| {
        let valid = validate(&doc, &schema, &body).is_empty();
        let (st, v) = s.post("/api/v1/simulate", &body);
        (valid, st, v)
    };
    let (valid, st, v) =
        post(json!({"scenario": "woods", "seed": 4, "steps": 200, "landmarks": 9}));
    assert!(valid && st == 201, "{st} {v}");
    let m = &v["mission"];
    assert_eq!(m["model"], "odometry2d");
    assert_eq!(m["truth"]["landmarks"].as_array().unwrap().len(), 9);
    assert!(m["detections"]
        .as_array()
        .unwrap()
        .iter()
        .all(|d| d["scan"].is_u64()));
    assert!(m["landmark_min_separation"].as_f64().unwrap() > 0.0);
    // False detections in the woods scenario, in the document
    // and in the service: core's mission, max_outliers set.
    let body = json!({"scenario": "woods", "seed": 4, "steps": 200, "landmarks": 9, "false_detections": 3});
    let (valid, st, v) = post(body);
    assert!(valid && st == 201, "{st} {v}");
    let m = &v["mission"];
    assert_eq!(m["max_outliers"], 3, "{}", m["meta"]);
    let nulls = m["truth"]["matching"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|j| j.is_null())
        .count();
    assert_eq!(nulls, 3);
    for (body, field) in [
        (json!({"scenario": "woods", "noise": 2}), "noise"),
        (json!({"scenario": "woods", "layout": "ring"}), "layout"),
        (
            json!({"scenario": "woods", "range_only": true}),
            "range_only",
        ),
        (
            json!({"scenario": "auv", "false_detections": 3}),
            "false_detections",
        ),
    ] {
        let (valid, st, v) = post(body.clone());
        assert!(!valid, "the document allows {body}");
        assert_eq!(
            (st, v["error"]["path"].as_str()),
            (422, Some(field)),
            "{body}: {v}"
        );
    }
    // (20,000 / 2 + 1) x 17 = 170,017 > 20,000: refused, unsimulated.
    let (valid, st, v) = post(json!({"scenario": "woods", "steps": 20000}));
    assert!(
        valid,
        "the document refuses a woods request of 20,000 steps"
    );
    assert_eq!(
        (st, v["error"]["path"].as_str()),
        (413, Some("steps")),
        "{v}"
    );
    assert!(
        v["error"]["message"].as_str().unwrap().contains("170017"),
        "{v}"
    );
}

/// The `shapes` contractor is a job contractor, in the document
/// and in the service, and the refusal of an unknown one lists it.
#[test]
fn issue_11_shapes_is_a_job_contractor() {
    let s = Server::start(&["--workers", "1"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let names = &doc["components"]["schemas"]["Association"]["enum"];
    assert!(
        names.as_array().unwrap().contains(&json!("shapes")),
        "{names}"
    );
    let (st, m) = s.post("/api/v1/missions", &small_mission(4, 800));
    assert_eq!(st, 201, "{m}");
    let (st, j) = s.post(
        "/api/v1/jobs",
        &json!({"mission": m["id"], "contractor": "shapes"}),
    );
    assert_eq!(st, 202, "{j}");
    let done = s.wait_job(j["id"].as_str().unwrap(), Duration::from_secs(60));
    assert_eq!(
        (&done["state"], &done["contractor"]),
        (&json!("done"), &json!("shapes")),
        "{done}"
    );
    let (st, e) = s.post(
        "/api/v1/jobs",
        &json!({"mission": m["id"], "contractor": "fastest"}),
    );
    assert_eq!(st, 422);
    let msg = e["error"]["message"].as_str().unwrap();
    assert!(msg.contains("shapes or best"), "{msg}");
    assert!(!msg.contains("exact"), "{msg}");
}

/// `heading_drift` (an odometry2d mission's windows): the document and the
/// service agree on a woods mission with windows (one longer than N), and
/// on the windows they refuse (k = 0, a negative bound, an unknown field),
/// the service naming the field.
#[test]
fn heading_drift_agrees_between_the_document_and_the_service() {
    let s = Server::start(&["--workers", "1"]);
    let (_, doc) = s.get("/api/v1/openapi.json");
    let schema = json!({"$ref": "#/components/schemas/Mission"});
    let (st, sim) = s.post(
        "/api/v1/simulate",
        &json!({"scenario": "woods", "seed": 3, "steps": 120, "landmarks": 6}),
    );
    assert_eq!(st, 201, "{sim}");
    let (_, mut m) = s.get(&format!("/api/v1/missions/{}", sim["id"].as_str().unwrap()));
    if m.get("mission").is_some() {
        m = m["mission"].clone();
    }
    assert_eq!(m["model"], "odometry2d");
    let cases = [
        (
            json!([{"steps": 30, "error": 0.1}, {"steps": 100000, "error": 0}]),
            None,
        ),
        (
            json!([{"steps": 0, "error": 0.1}]),
            Some("heading_drift[0].steps"),
        ),
        (
            json!([{"steps": 5, "error": -0.1}]),
            Some("heading_drift[0].error"),
        ),
        (
            json!([{"steps": 5, "error": 0.1, "k": 1}]),
            Some("heading_drift[0].k"),
        ),
        (
            json!([{"steps": 30, "error": 0.1, "exempt_above": 0.02}, {"steps": 5, "error": 0, "exempt_above": 0}]),
            None,
        ),
        (
            json!([{"steps": 5, "error": 0.1, "exempt_above": -0.01}]),
            Some("heading_drift[0].exempt_above"),
        ),
        (
            json!([{"steps": 5, "error": 0.1}, {"steps": 5, "error": 0.1, "exempt_above": "x"}]),
            Some("heading_drift[1].exempt_above"),
        ),
    ];
    for (windows, refused) in cases {
        let mut body = m.clone();
        body["heading_drift"] = windows.clone();
        let valid = validate(&doc, &schema, &body).is_empty();
        let (st, v) = s.post("/api/v1/missions", &body);
        match refused {
            None => assert!(valid && st == 201, "{windows}: valid {valid}, {st} {v}"),
            Some(path) => {
                assert!(!valid && st == 422, "{windows}: valid {valid}, {st} {v}");
                assert_eq!(v["error"]["path"], path, "{v}");
            }
        }
    }
    // A ninth distinct exempt_above: schema-valid (a rule the schema does
    // not state, docs/formats.md), refused by the service.
    let mut body = m.clone();
    body["heading_drift"] = (0..9)
        .map(|x| json!({"steps": 5, "error": 0.1, "exempt_above": 0.01 * x as f64}))
        .collect();
    assert!(validate(&doc, &schema, &body).is_empty());
    let (st, v) = s.post("/api/v1/missions", &body);
    assert_eq!(st, 422, "{v}");
    assert_eq!(v["error"]["path"], "heading_drift[8].exempt_above", "{v}");
}
