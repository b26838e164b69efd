//! `nvector import --cmu-plaza DIR --outlier-share P` through the real
//! binary (issue 18, "honest tight bounds"): the range band holds the
//! central (1 - P) share of the residuals and `max_outliers` counts the
//! ranges left outside. This test reads the data set's CSVs with its own
//! code (nearest ground-truth row by time, true distance to the beacon)
//! and checks that exactly the ranges `meta.outlier_share.outside` names
//! miss the true distance, that `max_outliers` covers them, that they are
//! at most the share asked for, and that the bands are narrower than the
//! bands holding every range. The same for `--utias-woods` (range and
//! bearing from the laser point to the true tube, at rows with a valid
//! truth).

use nvector_tests::{run, temp_file};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn cmu_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    assert!(
        dir.join("Plaza1_TD.txt").exists(),
        "the CMU Plaza 1 data must be at {}",
        dir.display()
    );
    dir
}

/// The rows of a data file (comma or whitespace separated numbers).
fn rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .map(|s| s.parse().unwrap())
                .collect()
        })
        .collect()
}

/// The true distance of every range of Plaza1_TD.txt, in file order: the
/// ground-truth row nearest in time, the beacon of Plaza1_TL.csv.
fn true_distances() -> Vec<f64> {
    let dir = cmu_dir();
    let gt = rows(&dir.join("Plaza1_GT.csv"));
    let td = rows(&dir.join("Plaza1_TD.txt"));
    let tl = rows(&dir.join("Plaza1_TL.csv"));
    td.iter()
        .map(|r| {
            let (t, id) = (r[0], r[2]);
            let row = gt
                .iter()
                .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
                .unwrap();
            let b = tl.iter().find(|l| l[0] == id).expect("a known beacon");
            (row[1] - b[1]).hypot(row[2] - b[2])
        })
        .collect()
}

fn import(share: &str) -> Value {
    let out_path = temp_file(&format!("cmu-{share}.json"));
    let out = run(&[
        "import",
        "--cmu-plaza",
        cmu_dir().to_str().unwrap(),
        "--outlier-share",
        share,
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&out_path).unwrap()).unwrap()
}

/// The ranges (by index) whose interval misses the true distance, and the
/// mean width of the intervals.
fn misses(m: &Value, truth: &[f64]) -> (Vec<usize>, f64) {
    let dets = m["detections"].as_array().unwrap();
    assert_eq!(dets.len(), truth.len());
    let mut out = Vec::new();
    let mut width = 0.0;
    for (j, (d, &t)) in dets.iter().zip(truth).enumerate() {
        let (lo, hi) = (
            d["range"][0].as_f64().unwrap(),
            d["range"][1].as_f64().unwrap(),
        );
        width += hi - lo;
        if !(lo <= t && t <= hi) {
            out.push(j);
        }
    }
    (out, width / dets.len() as f64)
}

#[test]
fn cmu_plaza_outlier_share_names_exactly_the_ranges_left_outside() {
    let truth = true_distances();
    let k = truth.len();
    assert_eq!(k, 3529);
    // Share 0: every range holds its true distance, no max_outliers.
    let wide = import("0");
    let (outside, wide_width) = misses(&wide, &truth);
    assert!(outside.is_empty(), "{outside:?}");
    assert!(wide.get("max_outliers").is_none_or(|q| q == 0));
    for (share, p) in [("0.01", 0.01), ("0.02", 0.02)] {
        let m = import(share);
        let (outside, width) = misses(&m, &truth);
        let named: Vec<usize> = m["meta"]["outlier_share"]["outside"]
            .as_array()
            .unwrap_or_else(|| panic!("share {share}: meta.outlier_share.outside"))
            .iter()
            .map(|x| x.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(
            outside, named,
            "share {share}: the ranges missing the truth"
        );
        assert_eq!(
            m["max_outliers"].as_u64(),
            Some(outside.len() as u64),
            "share {share}: max_outliers covers them"
        );
        let most = (p * k as f64).floor() as usize;
        assert!(
            !outside.is_empty() && outside.len() <= most,
            "share {share}: {} outside, at most {most}",
            outside.len()
        );
        assert!(
            width < wide_width,
            "share {share}: mean width {width} not below {wide_width}"
        );
    }
}

/// The rows of a CSV with a header.
fn csv(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|s| s.trim().parse().unwrap()).collect())
        .collect()
}

/// Whether some `x + 2 pi k` lies in `[lo, hi]`.
fn inside_mod_2pi(x: f64, lo: f64, hi: f64) -> bool {
    let two_pi = 2.0 * std::f64::consts::PI;
    let k = ((lo - x) / two_pi).ceil();
    x + two_pi * k <= hi
}

#[test]
fn utias_woods_outlier_share_names_exactly_the_detections_left_outside() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/utias-lost-in-the-woods");
    assert!(
        dir.join("truth.csv").exists(),
        "the data must be at {}",
        dir.display()
    );
    let odo = csv(&dir.join("odometry.csv"));
    let truth = csv(&dir.join("truth.csv"));
    let meas = csv(&dir.join("measurements.csv"));
    let tubes = csv(&dir.join("landmarks.csv"));
    let (t0, n) = (odo[0][0], odo.len() - 1);
    let dt = (odo[n][0] - t0) / n as f64;
    let out_path = temp_file("woods-0.02.json");
    let out = run(&[
        "import",
        "--utias-woods",
        dir.to_str().unwrap(),
        "--outlier-share",
        "0.02",
        "--out",
        out_path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&out_path).unwrap()).unwrap();
    let dets = m["detections"].as_array().unwrap();
    assert_eq!(dets.len(), meas.len());
    let (mut outside, mut checked) = (Vec::new(), 0usize);
    for (j, (d, row)) in dets.iter().zip(&meas).enumerate() {
        let step = ((row[0] - t0) / dt).round() as usize;
        let tr = &truth[step];
        if tr[4] == 0.0 {
            continue;
        }
        checked += 1;
        let tube = tubes.iter().find(|l| l[0] == row[1]).expect("a known tube");
        let (sx, sy) = (
            tr[1] + 0.219016 * tr[3].cos(),
            tr[2] + 0.219016 * tr[3].sin(),
        );
        let (dx, dy) = (tube[1] - sx, tube[2] - sy);
        let (range, bearing) = (dx.hypot(dy), dy.atan2(dx) - tr[3]);
        let iv = |k: &str, i: usize| d[k][i].as_f64().unwrap();
        let ok = iv("range", 0) <= range
            && range <= iv("range", 1)
            && inside_mod_2pi(bearing, iv("bearing", 0), iv("bearing", 1));
        if !ok {
            outside.push(j);
        }
    }
    let named: Vec<usize> = m["meta"]["outlier_share"]["outside"]
        .as_array()
        .expect("meta.outlier_share.outside")
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    assert_eq!(outside, named);
    assert_eq!(m["max_outliers"].as_u64(), Some(outside.len() as u64));
    // Each of the two bands leaves at most floor(0.02 k) out.
    let most = 2 * (0.02 * checked as f64).floor() as usize;
    assert!(
        !outside.is_empty() && outside.len() <= most,
        "{} of {most}",
        outside.len()
    );
}

#[test]
fn outlier_share_is_refused_out_of_range_and_without_a_real_log() {
    let dir = cmu_dir();
    for bad in ["0.5", "-0.1", "NaN"] {
        let out = run(&[
            "import",
            "--cmu-plaza",
            dir.to_str().unwrap(),
            "--outlier-share",
            bad,
        ]);
        assert_eq!(out.status.code(), Some(1), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--outlier-share"), "{bad}: {err}");
    }
    let out = run(&["import", "--outlier-share", "0.01", "--model", "unicycle2d"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--outlier-share needs"));
}
