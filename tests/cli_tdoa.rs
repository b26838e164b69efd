//! `nvector tdoa`, `nvector simulate --scenario radar` and `nvector import
//! --locards-mlat` through the built binary.
//!
//! The LocaRDS test reads the data's CSV files itself and checks, with its
//! own code (its own geodetic conversion, not the importer's nor core's),
//! that the truth satisfies every constraint of each imported set: for
//! every message some emission time fits every arrival (the intersection
//! over the arrivals of `time - bias - |truth - receiver| / c` is not
//! empty, with the distance's range over the receiver box and c over its
//! interval), the truth's distance from the Earth's centre is in the
//! altitude cut's range, and the truth is in the emitter region.

use nvector_tests::nvector;
use nvector_tests::{read_json, temp_file};
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn locards_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/locards-mlat");
    assert!(
        dir.join("sensors.csv").exists(),
        "the LocaRDS data must be at {}",
        dir.display()
    );
    dir
}

fn run(args: &[&str]) -> (i32, String) {
    let out = nvector().args(args).output().expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn num(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

/// The test's own WGS84 to ECEF.
fn ecef(lat: f64, lon: f64, h: f64) -> [f64; 3] {
    let a = 6378137.0;
    let b = a * (1.0 - 1.0 / 298.257223563);
    let (p, l) = (
        lat * std::f64::consts::PI / 180.0,
        lon * std::f64::consts::PI / 180.0,
    );
    let n = a * a / (a * a * p.cos() * p.cos() + b * b * p.sin() * p.sin()).sqrt();
    [
        (n + h) * p.cos() * l.cos(),
        (n + h) * p.cos() * l.sin(),
        (n * b * b / (a * a) + h) * p.sin(),
    ]
}

/// ENU of `q` at the origin `o` (geodetic), by the three unit vectors.
fn enu(o: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    let (p, l) = (o[0].to_radians(), o[1].to_radians());
    let d = {
        let (a, b) = (ecef(q[0], q[1], q[2]), ecef(o[0], o[1], o[2]));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    };
    let e = [-l.sin(), l.cos(), 0.0];
    let n = [-p.sin() * l.cos(), -p.sin() * l.sin(), p.cos()];
    let u = [p.cos() * l.cos(), p.cos() * l.sin(), p.sin()];
    let dot = |v: [f64; 3]| v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
    [dot(e), dot(n), dot(u)]
}

/// Distance range from a point to a box.
fn dist_range(x: [f64; 3], b: &[(f64, f64)]) -> (f64, f64) {
    let (mut lo, mut hi) = (0.0, 0.0);
    for k in 0..3 {
        let (a, c) = b[k];
        let near = if x[k] < a {
            a - x[k]
        } else if x[k] > c {
            x[k] - c
        } else {
            0.0
        };
        let far = (x[k] - a).abs().max((x[k] - c).abs());
        lo += near * near;
        hi += far * far;
    }
    (lo.sqrt(), hi.sqrt())
}

fn pair(v: &Value) -> (f64, f64) {
    (num(&v[0]), num(&v[1]))
}

/// Checks the truth of one imported set against the CSVs; returns the
/// number of messages checked.
fn check_set(dir: &Path, set: u32, problem: &Value) -> usize {
    let sensors: HashMap<u64, [f64; 3]> = std::fs::read_to_string(dir.join("sensors.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (
                c[0].parse().unwrap(),
                [
                    c[1].parse().unwrap(),
                    c[2].parse().unwrap(),
                    c[3].parse().unwrap(),
                ],
            )
        })
        .collect();
    let origin = problem["meta"]["frame"]["origin_lat_lon_h"].clone();
    let o = [num(&origin[0]), num(&origin[1]), num(&origin[2])];
    let text = std::fs::read_to_string(dir.join(format!("set_{set}.csv"))).unwrap();
    let c = problem["propagation_speed"].clone();
    let (c_lo, c_hi) = pair(&c);
    let region = &problem["emitter_region"];
    let mut n = 0;
    for (k, l) in text.lines().skip(1).enumerate() {
        let (head, quoted) = l.split_once('"').unwrap();
        let cols: Vec<&str> = head.split(',').collect();
        let lat: f64 = cols[3].parse().unwrap();
        let lon: f64 = cols[4].parse().unwrap();
        let h: f64 = cols[6].parse().unwrap();
        let truth = enu(o, [lat, lon, h]);
        for a in 0..3 {
            let (lo, hi) = pair(&region[a]);
            assert!(
                lo <= truth[a] && truth[a] <= hi,
                "set {set} message {k}: outside the region"
            );
        }
        // The altitude cut: the truth's distance from the Earth's centre.
        let cut = &problem["pulses"][k]["distance_from"];
        let cb: Vec<(f64, f64)> = (0..3).map(|i| pair(&cut["point"][i])).collect();
        let (r_lo, r_hi) = pair(&cut["range"]);
        let (d_lo, d_hi) = dist_range(truth, &cb);
        assert!(
            d_lo <= r_hi && r_lo <= d_hi,
            "set {set} message {k}: altitude cut misses the truth"
        );
        let ms: Vec<Vec<f64>> = serde_json::from_str(quoted.trim_end_matches('"')).unwrap();
        let pulse = &problem["pulses"][k]["arrivals"];
        assert_eq!(pulse.as_array().unwrap().len(), ms.len());
        let (mut tau_lo, mut tau_hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (a, m) in ms.iter().enumerate() {
            let arr = &pulse[a];
            let r = &problem["receivers"][arr["receiver"].as_u64().unwrap() as usize];
            // The receiver box must hold the sensor's own position.
            let s = sensors[&(m[0] as u64)];
            let sp = enu(o, s);
            let b: Vec<(f64, f64)> = (0..3).map(|i| pair(&r["position"][i])).collect();
            for i in 0..3 {
                assert!(
                    (b[i].0 - 0.01..=b[i].1 + 0.01).contains(&sp[i]),
                    "set {set}: sensor {} moved",
                    m[0]
                );
            }
            let (d_lo, d_hi) = dist_range(truth, &b);
            let (t_lo, t_hi) = pair(&arr["time"]);
            let (b_lo, b_hi) = pair(&r["clock_bias"]);
            tau_lo = tau_lo.max(t_lo - b_hi - d_hi / c_lo);
            tau_hi = tau_hi.min(t_hi - b_lo - d_lo / c_hi);
        }
        assert!(
            tau_lo <= tau_hi,
            "set {set} message {k}: no emission time fits ({tau_lo} > {tau_hi})"
        );
        n += 1;
    }
    n
}

#[test]
fn locards_truth_satisfies_every_constraint() {
    let dir = locards_dir();
    let mut total = 0;
    for set in 1..=4u32 {
        let out = temp_file(&format!("locards-{set}.json"));
        let (code, err) = run(&[
            "import",
            "--locards-mlat",
            dir.to_str().unwrap(),
            "--set",
            &set.to_string(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        total += check_set(&dir, set, &read_json(&out));
    }
    assert_eq!(total, 1147, "every message of sets 1-4");
}

fn radar(extra: &[&str], name: &str) -> Value {
    let m = temp_file(&format!("{name}.json"));
    let r = temp_file(&format!("{name}-result.json"));
    let mut args = vec![
        "simulate",
        "--scenario",
        "radar",
        "--pulses",
        "60",
        "--out",
        m.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    let (code, err) = run(&[
        "tdoa",
        m.to_str().unwrap(),
        "--out",
        r.to_str().unwrap(),
        "--budget",
        "48",
    ]);
    assert_eq!(code, 0, "{err}");
    read_json(&r)
}

#[test]
fn radar_truth_inside_and_no_matching_error() {
    for (extra, name) in [
        (&["--seed", "3", "--emitters", "3"][..], "hidden"),
        (
            &["--seed", "3", "--emitters", "3", "--operator"][..],
            "operator",
        ),
        (
            &["--seed", "4", "--emitters", "3", "--false-arrivals", "2"][..],
            "false",
        ),
    ] {
        let r = radar(extra, name);
        assert_eq!(r["format"], "nvector-tdoa-result/1");
        assert_eq!(r["status"], "consistent", "{name}");
        assert_eq!(r["score"]["truth_inside"], true, "{name}");
        assert_eq!(r["score"]["matching_errors"], 0, "{name}");
        assert_eq!(r["pulses"].as_array().unwrap().len(), 60);
    }
}

/// A round cap that ends the rounds while they still shrink the boxes is
/// `"stopped"` (formats.md: `max_rounds` reached before the fixpoint), not
/// `"consistent"`; the figure of `--plot` is SVG, so another name is
/// refused before the solve (a .png name got SVG bytes).
#[test]
fn a_round_cap_before_the_fixpoint_is_stopped() {
    let m = temp_file("capped.json");
    let (code, err) = run(&[
        "simulate",
        "--scenario",
        "radar",
        "--pulses",
        "30",
        "--seed",
        "3",
        "--emitters",
        "3",
        "--out",
        m.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let solve = |rounds: &str, name: &str| {
        let r = temp_file(name);
        let (code, err) = run(&[
            "tdoa",
            m.to_str().unwrap(),
            "--budget",
            "32",
            "--max-rounds",
            rounds,
            "--out",
            r.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        read_json(&r)
    };
    let full = solve("1000", "capped-full.json");
    assert_eq!(full["status"], "consistent", "{full}");
    assert_eq!(full["score"]["truth_inside"], true);
    let one = solve("1", "capped-one.json");
    assert_ne!(
        one["emission_times"], full["emission_times"],
        "one round is short of the fixpoint here"
    );
    assert_eq!(one["status"], "stopped");
    assert_eq!(one["score"]["truth_inside"], true);
    let (code, err) = run(&[
        "tdoa",
        m.to_str().unwrap(),
        "--plot",
        &temp_file("fig.png").to_string_lossy(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("must end in .svg"), "{err}");
}

#[test]
fn bad_problem_names_the_path_and_exits_1() {
    let m = temp_file("bad.json");
    std::fs::write(&m, r#"{"format": "nvector-tdoa/1", "propagation_speed": [1, 2], "receivers": [], "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 1]}]}]}"#).unwrap();
    let (code, err) = run(&["tdoa", m.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("pulses[0].arrivals[0].receiver"), "{err}");
    let (code, err) = run(&["simulate", "--scenario", "radar", "--receivers", "2"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("--receivers"), "{err}");
}

/// `--contractor` was declared `Option<Option<Contractor>>` with a parser
/// returning `Option<Contractor>`: clap took it for a flag with an optional
/// value of type `Contractor` and every use (`--contractor best`, `none`,
/// ...) panicked in clap (exit 101, "Mismatch between definition and access
/// of `contractor`"). Each name runs now, and an unknown one is a usage
/// error naming the option.
#[test]
fn every_contractor_name_runs() {
    let m = temp_file("contractors.json");
    let (code, err) = run(&[
        "simulate",
        "--scenario",
        "radar",
        "--pulses",
        "20",
        "--emitters",
        "2",
        "--operator",
        "--out",
        m.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for c in [
        "none",
        "nvalue",
        "projection",
        "independent",
        "exact",
        "shapes",
        "best",
    ] {
        let r = temp_file(&format!("contractors-{c}.json"));
        let (code, err) = run(&[
            "tdoa",
            m.to_str().unwrap(),
            "--contractor",
            c,
            "--budget",
            "16",
            "--out",
            r.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "--contractor {c}: {err}");
        let r = read_json(&r);
        assert_eq!(r["score"]["truth_inside"], true, "{c}");
        assert_eq!(r["score"]["matching_errors"], 0, "{c}");
    }
    let (code, err) = run(&["tdoa", m.to_str().unwrap(), "--contractor", "fast"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--contractor"), "{err}");
}
