//! Writes target/web-reference.json: inputs and the native outputs that the
//! wasm test (tests/wasm.rs, in headless Chromium) must reproduce bit for
//! bit. Also checks the facade natively.
#![cfg(not(target_arch = "wasm32"))]

use nvector_web::{contract_with_kernels, run_mission, simulate_json};
use serde_json::{json, Value};

/// The contractor of the page's range-only preset.
const PRESET_CONTRACTOR: &str = "shapes";

#[test]
fn bad_simulation_options_name_the_field() {
    let e = simulate_json(&json!({"layout": "spiral"})).unwrap_err();
    assert!(e.to_string().contains("layout"), "{e}");
}

/// The page's woods preset: core's woods generator through the facade
/// (the CLI's `simulate --scenario woods`), its options checked by name.
#[test]
fn woods_through_the_facade() {
    let m = simulate_json(&json!({"scenario": "woods", "seed": 3, "steps": 120, "operator": null}))
        .unwrap();
    let direct = nvector_core::slam::simulate::odometry_scenario::simulate_woods(
        &nvector_core::slam::simulate::odometry_scenario::WoodsOptions {
            seed: 3,
            steps: Some(120),
            landmarks: None,
            operator: false,
        },
    );
    assert_eq!(m, direct);
    assert_eq!(m["model"], "odometry2d");
    assert_eq!(m["truth"]["headings"].as_array().unwrap().len(), 121);
    for (bad, field) in [
        (json!({"scenario": "woods", "layout": "ring"}), "layout"),
        (json!({"scenario": "woods", "noise": 2}), "noise"),
        (json!({"scenario": "woods", "steps": -1}), "steps"),
        (json!({"scenario": "woods", "steps": 1e12}), "steps"),
        (json!({"scenario": "woods", "landmarks": 1000}), "landmarks"),
        (json!({"scenario": "woods", "seed": -1}), "seed"),
    ] {
        let e = simulate_json(&bad).unwrap_err();
        assert_eq!(e.path, field, "{bad}: {e}");
    }
}

#[test]
fn native_reference() {
    let contract_inputs = [
        json!({"format": "nvector-contract/1", "n": 2, "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]]}),
        json!({"format": "nvector-contract/1", "n": 3, "contractor": "independent", "boxes": [[[0, 1], [0, 1]], [[4, 5], [2, 3]], [[2, 3], [4, 5]], [[0.5, 2.5], [0.5, 2.5]]]}),
        json!({"format": "nvector-contract/1", "n": 2, "contractor": "exact", "boxes": [[[1, 6], [2, 6]], [[3, 5], [6, 9]], [[4, 10], [1, 4]], [[5, 9], [3, 7]], [[9, 11], [0, 5]]]}),
    ];
    let mut cases = Vec::new();
    for c in &contract_inputs {
        let out = contract_with_kernels(c).unwrap();
        cases.push(json!({"kind": "contract", "input": c.to_string(), "output": out.to_string()}));
    }
    let sim = json!({"scenario": "paper", "seed": 9, "steps": 1500});
    let mission = simulate_json(&sim).unwrap();
    cases
        .push(json!({"kind": "simulate", "input": sim.to_string(), "output": mission.to_string()}));
    for contractor in ["none", "projection", "independent"] {
        let out = run_mission(&mission, contractor, &mut |_| {}).unwrap();
        assert_eq!(out["score"]["truth_inside"], true);
        cases.push(json!({"kind": "run", "contractor": contractor, "input": mission.to_string(), "output": out.to_string()}));
    }
    // The options of `nvector simulate` passed through the facade: each
    // changes the mission (a facade that dropped one would fail here), and
    // the range-only mission is run as the page's preset runs it.
    let base = simulate_json(&json!({"scenario": "paper", "seed": 4, "steps": 3000})).unwrap();
    let variants = [
        json!({"scenario": "paper", "seed": 4, "steps": 3000, "layout": "ring"}),
        json!({"scenario": "paper", "seed": 4, "steps": 3000, "layout": "random", "false_detections": 3}),
        json!({"scenario": "paper", "seed": 4, "steps": 3000, "range_only": true}),
    ];
    for v in &variants {
        let m = simulate_json(v).unwrap();
        assert_ne!(m, base, "{v} gave the default mission");
        cases.push(json!({"kind": "simulate", "input": v.to_string(), "output": m.to_string()}));
    }
    let range_only = simulate_json(&variants[2]).unwrap();
    let dets = range_only["detections"].as_array().unwrap();
    assert!(dets
        .iter()
        .all(|d| d.get("region").is_some() && d.get("bearing").is_none()));
    let with_false = simulate_json(&variants[1]).unwrap();
    assert_eq!(with_false["max_outliers"], 3);
    for contractor in ["none", PRESET_CONTRACTOR] {
        let out = run_mission(&range_only, contractor, &mut |_| {}).unwrap();
        assert_eq!(out["score"]["truth_inside"], true);
        if contractor == PRESET_CONTRACTOR {
            // What the page draws: proved groups and a landmark region
            // (a paving) per landmark.
            assert!(out["score"]["matching_recall"].as_f64().unwrap() > 0.0);
            let regions = out["landmark_regions"].as_array().unwrap();
            assert_eq!(regions.len(), out["landmarks"].as_array().unwrap().len());
            assert!(regions.iter().all(|p| !p.as_array().unwrap().is_empty()));
        }
        cases.push(json!({"kind": "run", "contractor": contractor, "input": range_only.to_string(), "output": out.to_string()}));
    }
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/web-reference.json");
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, Value::Array(cases).to_string()).unwrap();
}
