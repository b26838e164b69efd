//! The facade in a real browser (wasm-bindgen-test in headless Chromium):
//! the same JSON in gives the same JSON out as natively — the expected
//! strings are written by the native test `native_reference` into
//! target/web-reference.json before this runs (scripts/web.sh test).
#![cfg(target_arch = "wasm32")]

use nvector_web::Nvector;
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const REFERENCE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../target/web-reference.json"
));

#[wasm_bindgen_test]
fn same_bits_as_native() {
    let reference: serde_json::Value = serde_json::from_str(REFERENCE).unwrap();
    let nv = Nvector::new();
    for case in reference.as_array().unwrap() {
        let input = case["input"].as_str().unwrap();
        let expected = case["output"].as_str().unwrap();
        let got = match case["kind"].as_str().unwrap() {
            "contract" => nv.contract(input).ok().unwrap(),
            "simulate" => nv.simulate(input).ok().unwrap(),
            // As the page runs a mission: read by the simulators' module,
            // handed to the solver's in binary.
            "run" => nv
                .run(
                    &nv.read_mission(input).ok().unwrap(),
                    case["contractor"].as_str().unwrap(),
                    &js_sys::Function::new_no_args(""),
                )
                .ok()
                .unwrap(),
            k => panic!("unknown kind {k}"),
        };
        assert_eq!(got, expected, "{} differs from native", case["kind"]);
    }
}

/// The message of a facade error, as the page shows it.
fn message(e: wasm_bindgen::JsError) -> String {
    js_sys::Error::from(wasm_bindgen::JsValue::from(e))
        .message()
        .into()
}

#[wasm_bindgen_test]
fn errors_name_the_path() {
    let nv = Nvector::new();
    let err = nv
        .contract(r#"{"format": "nvector-contract/1", "n": 1, "boxes": [[[2, 1]]]}"#)
        .err()
        .map(message)
        .unwrap();
    assert!(err.contains("boxes[0]"), "{err}");
    let err = nv
        .simulate(r#"{"scenario": "paper", "layout": "spiral"}"#)
        .err()
        .map(message)
        .unwrap();
    assert!(err.contains("layout"), "{err}");
    // The simulators' module reads a mission for the solver's with the
    // format layer's path-tracking reader (core/src/format/tracked.rs):
    // the path and the message in full, as formats.md words them.
    let run = |mission: &str| nv.read_mission(mission).err().map(message).unwrap();
    let mission = |inputs: &str, detections: &str| {
        format!(
            r#"{{"format": "nvector-mission/1", "model": "unicycle2d", "dt": 1, "steps": 1,
            "initial_position": [[0, 0], [0, 0]], "inputs": {inputs}, "detections": {detections}}}"#
        )
    };
    assert_eq!(
        run(&mission(
            r#"{"speed": {"value": [1], "eror": 0.1}, "heading": {"value": [0], "error": 0}}"#,
            "[]"
        )),
        "inputs.speed.eror: unknown field `eror` (expected one of: value, error, lo, hi)"
    );
    assert_eq!(
        run(&mission(
            r#"{"speed": {"value": [1], "error": 0}, "heading": {"value": [0], "error": 0}}"#,
            r#"[{"step": 1, "range": [1, 2]}, {"step": 0, "range": [3, 2]}]"#
        )),
        "detections[1].range: lower bound 3 is above upper bound 2"
    );
    assert_eq!(
        run(&mission(
            r#"{"speed": {"value": [1, "x"], "error": 0}}"#,
            "[]"
        )),
        "inputs.speed.value[1]: expected a finite number, found a string"
    );
    // The solver's module refuses what is not a binary mission.
    let err = nv
        .run(b"{}", "none", &js_sys::Function::new_no_args(""))
        .err()
        .map(message)
        .unwrap();
    assert!(err.starts_with("mission: invalid binary mission"), "{err}");
}
