//! A result file uploaded as a mission, over a real socket against the real
//! binary: refused with 422, the error at `format` naming the file's format
//! (`nvector-result/1`, a SLAM result), as JSON and as a form, and nothing
//! stored; the CLI's `nvector run` on the same file says the same.

use nvector_tests as common;
use nvector_tests::{small_mission, Server};
use serde_json::Value;

#[test]
fn a_result_uploaded_as_a_mission_is_refused_as_a_result() {
    // A real result: the CLI's run of a small mission.
    let dir = common::temp_dir("result-upload");
    let (mission, result) = (dir.join("m.json"), dir.join("r.json"));
    std::fs::write(&mission, small_mission(3, 300).to_string()).unwrap();
    let out = common::nvector()
        .arg("run")
        .arg(&mission)
        .arg("--out")
        .arg(&result)
        .output()
        .unwrap();
    common::succeeded(&out);
    let text = std::fs::read_to_string(&result).unwrap();
    let s = Server::start(&[]);
    let check = |st: u16, body: &[u8]| {
        let v: Value = serde_json::from_slice(body).unwrap_or(Value::Null);
        assert_eq!(st, 422, "{v}");
        let e = &v["error"];
        assert_eq!(e["code"], "invalid_mission", "{v}");
        assert_eq!(e["path"], "format", "{v}");
        let m = e["message"].as_str().unwrap();
        assert!(
            m.contains("not a mission")
                && m.contains("\"nvector-result/1\"")
                && m.contains("a SLAM result"),
            "{m}"
        );
    };
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("application/json", text.as_bytes())),
        &[],
    );
    check(st, &b);
    let form = format!(
        "--XyZ\r\nContent-Disposition: form-data; name=\"file\"; filename=\"r.json\"\r\nContent-Type: application/json\r\n\r\n{text}\r\n--XyZ--\r\n"
    );
    let (st, _, b) = s.req(
        "POST",
        "/api/v1/missions",
        Some(("multipart/form-data; boundary=XyZ", form.as_bytes())),
        &[],
    );
    check(st, &b);
    let (st, list) = s.get("/api/v1/missions");
    assert_eq!(st, 200);
    assert_eq!(list["missions"], serde_json::json!([]), "stored: {list}");
    // The CLI's recognition, the same words.
    let out = common::nvector().arg("run").arg(&result).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the file's format is \"nvector-result/1\": a SLAM result"),
        "{err}"
    );
}
