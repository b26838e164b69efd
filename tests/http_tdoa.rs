//! TDOA passive location over real HTTP (`POST /api/v1/tdoa`, docs/api.md),
//! on SQLite and on PostgreSQL: a simulated radar problem solved as a job
//! (its result checked against the problem's truth by this file's own
//! code, and against the OpenAPI document), a job stopped by its time
//! limit still sound, cancellation, and bad bodies refused naming the
//! path.

use nvector_tests::schema::validate;
use nvector_tests::{on_both_storages, read_json, run, succeeded, temp_file, Backend, Server};
use serde_json::{json, Value};
use std::time::Duration;

/// A radar problem of `nvector simulate --scenario radar` (small: the tests
/// run the debug binary).
fn radar(seed: u64, pulses: usize) -> Value {
    let out = temp_file("radar.json");
    succeeded(&run(&[
        "simulate",
        "--scenario",
        "radar",
        "--seed",
        &seed.to_string(),
        "--emitters",
        "3",
        "--pulses",
        &pulses.to_string(),
        "--out",
        out.to_str().unwrap(),
    ]));
    read_json(&out)
}

/// An interval of the result (`[lo, hi]`, bounds numbers or infinities).
fn interval(v: &Value) -> Option<(f64, f64)> {
    let bound = |b: &Value| match b {
        Value::Number(n) => n.as_f64(),
        Value::String(s) if s == "-inf" => Some(f64::NEG_INFINITY),
        Value::String(s) if s == "inf" => Some(f64::INFINITY),
        _ => None,
    };
    Some((bound(&v[0])?, bound(&v[1])?))
}

/// Whether the result box `b` holds the point `p`.
fn holds(b: &Value, p: &Value) -> bool {
    let Some(axes) = b.as_array() else {
        return false; // "empty" holds nothing
    };
    axes.len() == 3
        && axes.iter().zip(p.as_array().unwrap()).all(|(a, x)| {
            let x = x.as_f64().unwrap();
            interval(a).is_some_and(|(lo, hi)| lo <= x && x <= hi)
        })
}

/// Checks a result against the problem's truth: every pulse box holds its
/// true position, every group is one true emitter whose position its
/// emitter box holds; returns the recall (pulses in a group of >= 2).
fn check_against_truth(problem: &Value, result: &Value) -> f64 {
    let truth = &problem["truth"];
    let pulses = result["pulses"].as_array().unwrap();
    assert_eq!(pulses.len(), problem["pulses"].as_array().unwrap().len());
    for (k, b) in pulses.iter().enumerate() {
        let p = &truth["positions"][k];
        assert!(holds(b, p), "pulse {k}: {b} does not hold its truth {p}");
    }
    let groups = result["matching"].as_array().unwrap();
    let emitters = result["emitters"].as_array().unwrap();
    assert_eq!(groups.len(), emitters.len());
    let mut grouped = 0;
    for (g, members) in groups.iter().enumerate() {
        let members: Vec<usize> = members
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m.as_u64().unwrap() as usize)
            .collect();
        let e = &truth["matching"][members[0]];
        for &m in &members {
            assert_eq!(
                &truth["matching"][m], e,
                "group {g} mixes pulses of emitters {e} and {}",
                truth["matching"][m]
            );
        }
        let point = &truth["emitters"][e.as_u64().unwrap() as usize];
        assert!(
            holds(&emitters[g], point),
            "group {g}: {} does not hold its emitter {point}",
            emitters[g]
        );
        if members.len() > 1 {
            grouped += members.len();
        }
    }
    grouped as f64 / pulses.len() as f64
}

fn radar_job_matches_the_truth(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "1"]);
    // The ids hidden (no operator labels): the groups are atmost_nvector's.
    let problem = radar(3, 40);
    assert!(problem["pulses"][0].get("emitter").is_none());
    let (st, q) = s.post("/api/v1/tdoa", &problem);
    assert_eq!(st, 202, "{q}");
    assert_eq!(q["state"], "queued");
    assert_eq!(q["pulses"], 40);
    let id = q["id"].as_str().unwrap();
    let pid = q["problem"].as_str().unwrap();
    assert!(pid.starts_with("t-"), "{q}");
    let job = s.wait_job(id, Duration::from_secs(120));
    assert_eq!(job["state"], "done", "{job}");
    assert_eq!(job["mission"], pid);
    let (st, result) = s.get(&format!("/api/v1/jobs/{id}/result"));
    assert_eq!(st, 200, "{result}");
    assert_eq!(result["format"], "nvector-tdoa-result/1");
    assert_eq!(result["status"], "consistent", "{result}");
    assert_eq!(result["contractor"], "best");
    let recall = check_against_truth(&problem, &result);
    assert!(recall >= 0.8, "recall {recall}");
    // The service's own score agrees with this file's check.
    assert_eq!(result["score"]["truth_inside"], true);
    assert_eq!(result["score"]["matching_errors"], 0);
    // The result is what the OpenAPI document says of a job's result.
    let (_, doc) = s.get("/api/v1/openapi.json");
    let schema = &doc["paths"]["/api/v1/jobs/{id}/result"]["get"]["responses"]["200"]["content"]
        ["application/json"]["schema"];
    let errors = validate(&doc, schema, &result);
    assert!(errors.is_empty(), "{errors:?}");
    assert!(validate(
        &doc,
        &json!({"$ref": "#/components/schemas/SlamResult"}),
        &result
    )
    .iter()
    .any(|e| e.contains("trajectory")));
    // The problem is stored as sent and not listed among the missions.
    let (st, stored) = s.get(&format!("/api/v1/missions/{pid}"));
    assert_eq!(st, 200);
    assert_eq!(stored, problem);
    let (_, list) = s.get("/api/v1/missions");
    assert_eq!(list["missions"], json!([]), "{list}");
    // As CSV, one row of bounds per pulse box, as in the JSON.
    let (st, _, csv) = s.req(
        "GET",
        &format!("/api/v1/jobs/{id}/result?format=csv"),
        None,
        &[],
    );
    assert_eq!(st, 200);
    let csv = String::from_utf8(csv).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "pulse,x_lo,x_hi,y_lo,y_hi,z_lo,z_hi");
    assert_eq!(rows.len(), 41);
    let first: Vec<f64> = rows[1]
        .split(',')
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let axes = result["pulses"][0].as_array().unwrap();
    let want: Vec<f64> = axes
        .iter()
        .flat_map(|a| [a[0].as_f64().unwrap(), a[1].as_f64().unwrap()])
        .collect();
    assert_eq!(first, want);
    // As SVG: a receiver per receiver, a ring per proved group, a box per pulse.
    let (st, _, svg) = s.req(
        "GET",
        &format!("/api/v1/jobs/{id}/result?format=svg"),
        None,
        &[],
    );
    assert_eq!(st, 200);
    let svg = String::from_utf8(svg).unwrap();
    assert!(svg.starts_with("<svg"), "{svg}");
    let count = |class: &str| svg.matches(&format!("class=\"{class}\"")).count();
    assert_eq!(
        count("receiver"),
        problem["receivers"].as_array().unwrap().len()
    );
    assert_eq!(
        count("emitter"),
        result["matching"].as_array().unwrap().len()
    );
    assert_eq!(count("pulse"), 40);
    assert_eq!(count("truth"), 3);

    // Without atmost_nvector and with the ids hidden, nothing is grouped;
    // the boxes still hold the truth.
    let (st, q) = s.post("/api/v1/tdoa?contractor=none", &problem);
    assert_eq!(st, 202, "{q}");
    let id = q["id"].as_str().unwrap();
    assert_eq!(s.wait_job(id, Duration::from_secs(120))["state"], "done");
    let (_, result) = s.get(&format!("/api/v1/jobs/{id}/result"));
    assert_eq!(result["contractor"], "none");
    assert_eq!(check_against_truth(&problem, &result), 0.0);

    // A time limit shorter than a round: the rounds stop after the first,
    // the job is done with `time_limit`, and its boxes are still sound.
    let (st, q) = s.post("/api/v1/tdoa?time_limit_s=0.001", &problem);
    assert_eq!(st, 202, "{q}");
    let id = q["id"].as_str().unwrap();
    let job = s.wait_job(id, Duration::from_secs(120));
    assert_eq!(
        (&job["state"], &job["error_code"]),
        (&json!("done"), &json!("time_limit")),
        "{job}"
    );
    let (_, result) = s.get(&format!("/api/v1/jobs/{id}/result"));
    assert_eq!(result["metrics"]["rounds"], 1, "{}", result["metrics"]);
    check_against_truth(&problem, &result);

    // Cancelled while queued or running: the job stays, cancelled.
    let (st, q) = s.post("/api/v1/tdoa", &radar(4, 200));
    assert_eq!(st, 202, "{q}");
    let id = q["id"].as_str().unwrap();
    let (st, _, c) = s.req("DELETE", &format!("/api/v1/jobs/{id}"), None, &[]);
    assert_eq!(st, 202, "{}", String::from_utf8_lossy(&c));
    assert_eq!(
        s.wait_job(id, Duration::from_secs(60))["state"],
        "cancelled"
    );
}

/// Bad bodies and options: 4xx naming what and where, never a 500.
fn bad_requests_name_the_path(b: &Backend) {
    let s = Server::start_on(b, &["--workers", "1", "--max-detections", "100"]);
    let good = radar(5, 4);
    let bad = |edit: &dyn Fn(&mut Value)| {
        let mut v = good.clone();
        edit(&mut v);
        v
    };
    let cases: Vec<(Value, &str)> = vec![
        (
            bad(&|v| v["pulses"][2]["arrivals"][1]["receiver"] = json!(99)),
            "pulses[2].arrivals[1].receiver",
        ),
        (
            bad(&|v| {
                v.as_object_mut().unwrap().remove("propagation_speed");
            }),
            "propagation_speed",
        ),
        (
            bad(&|v| v["receivers"][1]["position"] = json!([[0, 1], [0, 1]])),
            "receivers[1].position",
        ),
        (
            bad(&|v| v["pulses"][0]["arrivals"][0]["time"] = json!([2, 1])),
            "pulses[0].arrivals[0].time",
        ),
        (
            bad(&|v| v["pulses"][3]["wobble"] = json!(1)),
            "pulses[3].wobble",
        ),
        (bad(&|v| v["format"] = json!("nvector-mission/1")), "format"),
        (
            bad(&|v| v["truth"]["matching"] = json!([0])),
            "truth.matching",
        ),
        (json!([1, 2]), ""),
    ];
    for (body, path) in cases {
        let (st, e) = s.post("/api/v1/tdoa", &body);
        assert_eq!(st, 422, "{path}: {e}");
        assert_eq!(e["error"]["code"], "invalid_tdoa", "{e}");
        assert_eq!(e["error"]["path"], path, "{e}");
    }
    // Over this service's limit on arrivals: 413 naming `pulses`.
    let (st, e) = s.post("/api/v1/tdoa", &radar(5, 40));
    assert_eq!((st, &e["error"]["path"]), (413, &json!("pulses")), "{e}");
    // Bad options, malformed JSON, another media type.
    for (query, path) in [
        ("contractor=exact", "contractor"),
        ("contractor=fast", "contractor"),
        ("max_rounds=0", "max_rounds"),
        ("max_rounds=x", "max_rounds"),
        ("time_limit_s=-1", "time_limit_s"),
        ("time_limit_s=1e9", "time_limit_s"),
    ] {
        let (st, e) = s.post(&format!("/api/v1/tdoa?{query}"), &good);
        assert_eq!(
            (st, &e["error"]["path"]),
            (400, &json!(path)),
            "{query}: {e}"
        );
    }
    let (st, _, body) = s.req(
        "POST",
        "/api/v1/tdoa",
        Some(("application/json", b"{\"format\": ")),
        &[],
    );
    assert_eq!(st, 400, "{}", String::from_utf8_lossy(&body));
    let (st, _, _) = s.req("POST", "/api/v1/tdoa", Some(("text/plain", b"{}")), &[]);
    assert_eq!(st, 415);
}

on_both_storages!(radar_job_matches_the_truth, bad_requests_name_the_path);
