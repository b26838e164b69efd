//! The OpenAPI document against the service's real behaviour: every
//! documented operation is routed, and real responses (statuses and the
//! required properties of their JSON bodies) match what it documents.

use nvector_tests as common;

use common::{small_mission, Server};
use serde_json::{json, Value};
use std::time::Duration;

/// Checks one real response against the document.
fn conforms(doc: &Value, method: &str, template: &str, status: u16, body: &[u8]) {
    let op = &doc["paths"][template][method];
    assert!(op.is_object(), "{method} {template} is not documented");
    let resp = &op["responses"][status.to_string()];
    assert!(
        resp.is_object(),
        "{method} {template} answered {status}, which is not documented"
    );
    if let Some(r) = resp["content"]["application/json"]["schema"]["$ref"].as_str() {
        let name = r.rsplit('/').next().unwrap();
        let schema = &doc["components"]["schemas"][name];
        let v: Value = serde_json::from_slice(body)
            .unwrap_or_else(|_| panic!("{method} {template} {status}: not JSON"));
        for field in schema["required"].as_array().unwrap() {
            assert!(
                v.get(field.as_str().unwrap()).is_some(),
                "{method} {template} {status}: missing `{field}` of {name}: {v}"
            );
        }
        if name == "Error" {
            for f in ["code", "message", "path"] {
                assert!(v["error"].get(f).is_some(), "error body without `{f}`: {v}");
            }
        }
    }
}

#[test]
fn real_responses_match_the_document() {
    let s = Server::start(&["--workers", "1"]);
    let (st, doc) = s.get("/api/v1/openapi.json");
    assert_eq!(st, 200);
    assert_eq!(doc["openapi"], "3.0.3");
    let mut exchanges: Vec<(&str, String, &str, u16, Vec<u8>)> = Vec::new();
    let mut send = |method: &'static str,
                    path: String,
                    template: &'static str,
                    body: Option<Value>|
     -> Value {
        let text = body.map(|b| b.to_string());
        let (st, _, b) = s.req(
            &method.to_ascii_uppercase(),
            &path,
            text.as_deref().map(|t| ("application/json", t.as_bytes())),
            &[],
        );
        let v = serde_json::from_slice(&b).unwrap_or(Value::Null);
        exchanges.push((method, path, template, st, b));
        v
    };
    let m = send(
        "post",
        "/api/v1/missions".into(),
        "/api/v1/missions",
        Some(small_mission(3, 500)),
    );
    let id = m["id"].as_str().unwrap().to_string();
    send(
        "post",
        "/api/v1/missions".into(),
        "/api/v1/missions",
        Some(json!({"format": "nope"})),
    );
    send("get", "/api/v1/missions".into(), "/api/v1/missions", None);
    send(
        "get",
        format!("/api/v1/missions/{id}"),
        "/api/v1/missions/{id}",
        None,
    );
    send(
        "get",
        "/api/v1/missions/m-none".into(),
        "/api/v1/missions/{id}",
        None,
    );
    let j = send(
        "post",
        "/api/v1/jobs".into(),
        "/api/v1/jobs",
        Some(json!({"mission": id})),
    );
    let jid = j["id"].as_str().unwrap().to_string();
    send(
        "post",
        "/api/v1/jobs".into(),
        "/api/v1/jobs",
        Some(json!({"mission": "m-none"})),
    );
    send(
        "post",
        "/api/v1/jobs".into(),
        "/api/v1/jobs",
        Some(json!({"mission": id, "contractor": 3})),
    );
    s.wait_job(&jid, Duration::from_secs(60));
    send(
        "get",
        format!("/api/v1/jobs/{jid}"),
        "/api/v1/jobs/{id}",
        None,
    );
    send(
        "get",
        format!("/api/v1/jobs/{jid}/result"),
        "/api/v1/jobs/{id}/result",
        None,
    );
    send(
        "get",
        format!("/api/v1/jobs/{jid}/result?format=bmp"),
        "/api/v1/jobs/{id}/result",
        None,
    );
    send(
        "get",
        format!("/api/v1/jobs/{jid}/events"),
        "/api/v1/jobs/{id}/events",
        None,
    );
    send(
        "delete",
        format!("/api/v1/jobs/{jid}"),
        "/api/v1/jobs/{id}",
        None,
    );
    send(
        "delete",
        "/api/v1/jobs/j-none".into(),
        "/api/v1/jobs/{id}",
        None,
    );
    send(
        "post",
        "/api/v1/contract".into(),
        "/api/v1/contract",
        Some(json!({"format": "nvector-contract/1", "n": 1, "boxes": [[[0, 1]]]})),
    );
    send(
        "post",
        "/api/v1/contract".into(),
        "/api/v1/contract",
        Some(json!({"format": "nvector-contract/1", "n": 0, "boxes": [[[0, 1]]]})),
    );
    send(
        "post",
        "/api/v1/simulate".into(),
        "/api/v1/simulate",
        Some(json!({"scenario": "paper", "steps": 300})),
    );
    send(
        "delete",
        format!("/api/v1/missions/{id}"),
        "/api/v1/missions/{id}",
        None,
    );
    send("get", "/healthz".into(), "/healthz", None);
    send("get", "/readyz".into(), "/readyz", None);
    send("get", "/metrics".into(), "/metrics", None);
    for (method, path, template, status, body) in &exchanges {
        assert!(*status < 500, "{method} {path}: {status}");
        conforms(&doc, method, template, *status, body);
    }
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
