//! The importers on the repository's data sets and on small files written
//! here: what they produce, and the errors naming file, line and setting.

use super::*;
use std::path::PathBuf;

fn data(dir: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(dir)
}

/// A fresh directory of this test process.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("nvector-import-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn plaza_planting_keeps_the_real_detections_and_plants_false_ones() {
    let plain = import_dataset(
        DataSet::CmuPlaza,
        &data("cmu-plaza1"),
        &DataSetImport::default(),
    )
    .unwrap();
    let o = DataSetImport {
        operator: false,
        outlier_share: 0.02,
        false_detections: 20,
        seed: 3,
        set: 1,
    };
    let shared = import_dataset(
        DataSet::CmuPlaza,
        &data("cmu-plaza1"),
        &DataSetImport {
            false_detections: 0,
            ..o
        },
    )
    .unwrap();
    let planted = import_dataset(DataSet::CmuPlaza, &data("cmu-plaza1"), &o).unwrap();
    // The oracle, labelled: every bound fitted on the run's own truth.
    let c = &plain["meta"]["calibration"];
    assert_eq!(c["same_run"], true);
    assert!(c["method"].as_str().unwrap().starts_with("oracle"), "{c}");
    let real = plain["detections"].as_array().unwrap();
    let dets = planted["detections"].as_array().unwrap();
    let matching = planted["truth"]["matching"].as_array().unwrap();
    assert_eq!(dets.len(), real.len() + 20);
    assert_eq!(matching.iter().filter(|m| m.is_null()).count(), 20);
    assert_eq!(planted["name"], "cmu-plaza1-false-20");
    let outside = shared["meta"]["outlier_share"]["outside"]
        .as_array()
        .unwrap();
    assert_eq!(
        planted["max_outliers"].as_u64().unwrap(),
        outside.len() as u64 + 20
    );
    // Every range the share left outside is the same range at its new
    // index; the real ones keep their order within a step (planting sorts
    // the detections by step).
    let shared_dets = shared["detections"].as_array().unwrap();
    let new_outside = planted["meta"]["outlier_share"]["outside"]
        .as_array()
        .unwrap();
    for (old, new) in outside.iter().zip(new_outside) {
        let (old, new) = (
            old.as_u64().unwrap() as usize,
            new.as_u64().unwrap() as usize,
        );
        assert_eq!(shared_dets[old], dets[new]);
        assert!(!matching[new].is_null());
    }
    let kept: Vec<&Value> = dets
        .iter()
        .zip(matching)
        .filter(|(_, m)| !m.is_null())
        .map(|(d, _)| d)
        .collect();
    let mut by_step: Vec<&Value> = shared_dets.iter().collect();
    by_step.sort_by_key(|d| d["step"].as_u64());
    assert_eq!(kept, by_step);
    // Steps stay in order.
    let steps: Vec<u64> = dets.iter().map(|d| d["step"].as_u64().unwrap()).collect();
    assert!(steps.windows(2).all(|w| w[0] <= w[1]));
    assert!(plain["meta"]["source"]
        .as_str()
        .unwrap()
        .contains("CMU Plaza 1"));
}

#[test]
fn woods_and_locards_name_their_data_in_this_repository() {
    let woods = import_dataset(
        DataSet::UtiasWoods,
        &data("utias-lost-in-the-woods"),
        &DataSetImport::default(),
    )
    .unwrap();
    let source = woods["meta"]["source"].as_str().unwrap();
    assert_eq!(woods["meta"]["calibration"]["same_run"], true);
    assert!(
        source.contains("data/utias-lost-in-the-woods") && !source.contains(".."),
        "{source}"
    );
    let tdoa = import_dataset(
        DataSet::LocardsMlat,
        &data("locards-mlat"),
        &DataSetImport {
            set: 2,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(tdoa["format"], "nvector-tdoa/1");
    let source = tdoa["meta"]["source"].as_str().unwrap();
    assert_eq!(
        source,
        "LocaRDS set_2.csv (data/locards-mlat of the nvector repository)"
    );
}

#[test]
fn data_set_names_and_settings_are_checked() {
    assert_eq!(DataSet::parse("cmu-plaza1"), Some(DataSet::CmuPlaza));
    assert_eq!(DataSet::parse("utias-woods"), Some(DataSet::UtiasWoods));
    assert_eq!(DataSet::parse("locards-mlat"), Some(DataSet::LocardsMlat));
    assert_eq!(DataSet::parse("plaza"), None);
    let dir = data("cmu-plaza1");
    for share in [-0.1, 0.5, f64::NAN] {
        let o = DataSetImport {
            outlier_share: share,
            ..Default::default()
        };
        let e = import_dataset(DataSet::CmuPlaza, &dir, &o).unwrap_err();
        assert!(
            matches!(
                e,
                ImportError::Setting {
                    option: "outlier_share",
                    ..
                }
            ),
            "{e}"
        );
    }
    let o = DataSetImport {
        false_detections: MAX_FALSE_DETECTIONS + 1,
        ..Default::default()
    };
    let e = import_dataset(DataSet::CmuPlaza, &dir, &o).unwrap_err();
    assert_eq!(e.to_string(), "--false-detections must be at most 100000");
    let e = import_dataset(
        DataSet::UtiasWoods,
        &temp_dir("none"),
        &DataSetImport::default(),
    )
    .unwrap_err();
    assert!(matches!(e, ImportError::Read { .. }), "{e}");
    assert!(e.to_string().contains("odometry.csv"), "{e}");
}

/// A 3-step unicycle log and one detection, as docs/formats.md shows.
fn small_csv(dir: &Path, det: &str) -> CsvImport {
    std::fs::write(
        dir.join("log.csv"),
        "t,speed,heading,note\n0.0,1.0,0.0,1\n0.5,1.0,0.0,2\n1.0,1.0,0.0,3\n",
    )
    .unwrap();
    std::fs::write(dir.join("det.csv"), det).unwrap();
    CsvImport {
        model: "unicycle2d".into(),
        log: dir.join("log.csv"),
        detections: dir.join("det.csv"),
        errors: vec![("speed".into(), 0.1), ("heading".into(), 0.01)],
        landmark_count: Some(1),
        ..Default::default()
    }
}

#[test]
fn a_csv_pair_becomes_a_mission_with_notes() {
    let dir = temp_dir("csv-pair");
    let a = small_csv(&dir, "t,range_lo,range_hi,landmark\n1.0,4.0,4.5,0\n");
    let imported = import_csv(&a).unwrap();
    let m = Mission::from_value(&imported.mission).unwrap();
    assert_eq!((m.steps, m.dt, m.detections.len()), (3, 0.5, 1));
    assert_eq!(m.detections[0].step, 2);
    assert_eq!(m.name, "log");
    assert_eq!(imported.notes.len(), 1);
    assert!(
        imported.notes[0].ends_with("log.csv: ignoring column(s) note (read: t, speed, heading)")
    );
}

#[test]
fn csv_errors_name_the_file_the_line_and_the_setting() {
    let dir = temp_dir("csv-errors");
    let a = small_csv(&dir, "t,range_lo,range_hi\n1.0,4.0,4.5\n9.0,1,2\n");
    let e = import_csv(&a).unwrap_err().to_string();
    assert!(
        e.ends_with("det.csv:3: time 9 falls outside the log (step 18 not in 0..=3)"),
        "{e}"
    );
    let a = small_csv(&dir, "t,range_lo,range_hi,scan\n1.0,4.0,4.5,-1\n");
    let e = import_csv(&a).unwrap_err().to_string();
    assert!(
        e.ends_with("det.csv:2: scan must be a non-negative integer, found -1"),
        "{e}"
    );
    let mut a = small_csv(&dir, "t,range_lo,range_hi\n1.0,4.0,4.5\n");
    a.errors.pop();
    let e = import_csv(&a).unwrap_err();
    assert!(matches!(
        e,
        ImportError::Setting {
            option: "errors",
            ..
        }
    ));
    assert_eq!(
        e.to_string(),
        "--error heading=E is required (the bound of channel heading)"
    );
    let mut a = small_csv(&dir, "t,range_lo,range_hi\n1.0,4.0,4.5\n");
    a.initial = Some(vec![[0.0, 0.0]]);
    let e = import_csv(&a).unwrap_err();
    assert!(
        matches!(
            e,
            ImportError::Setting {
                option: "initial",
                ..
            }
        ),
        "{e}"
    );
    // An unbounded, reversed or NaN axis is refused, naming the setting.
    for axis in [[1.0, 0.0], [f64::NEG_INFINITY, 0.0], [0.0, f64::NAN]] {
        let mut a = small_csv(&dir, "t,range_lo,range_hi\n1.0,4.0,4.5\n");
        a.initial = Some(vec![[0.0, 0.0], axis]);
        let e = import_csv(&a).unwrap_err();
        assert!(
            matches!(
                e,
                ImportError::Setting {
                    option: "initial",
                    ..
                }
            ),
            "{axis:?}: {e}"
        );
    }
    let mut a = small_csv(&dir, "t,range_lo,range_hi\n1.0,4.0,4.5\n");
    a.model = "odometry2d".into();
    let e = import_csv(&a).unwrap_err().to_string();
    assert_eq!(e, "--initial-heading LO,HI is required for odometry2d");
    a.initial_heading = Some([0.0, f64::INFINITY]);
    let e = import_csv(&a).unwrap_err().to_string();
    assert_eq!(e, "--initial-heading 0,inf: expected two finite numbers");
    a.initial_heading = None;
    a.model = "boat".into();
    let e = import_csv(&a).unwrap_err().to_string();
    assert!(e.starts_with("--model: unknown model 'boat'"), "{e}");
    // What is read is validated by core: a landmark beyond landmark_count.
    let a = small_csv(&dir, "t,range_lo,range_hi,landmark\n1.0,4.0,4.5,3\n");
    let e = import_csv(&a).unwrap_err();
    assert!(matches!(e, ImportError::InvalidMission(_)), "{e}");
}

/// The converter writes what the importer reads: Plaza 1 as the
/// calibration's CSVs, read back by the calibration's reader, has the
/// mission's steps, detections (step by step) and true positions.
#[test]
fn plaza_converts_to_the_calibration_csvs_its_mission_is_made_of() {
    use crate::calibrate::convert::Span;
    use crate::calibrate::data::{read_run, Files, Model};
    let dir = data("cmu-plaza1");
    let mission = import_dataset(DataSet::CmuPlaza, &dir, &DataSetImport::default()).unwrap();
    let out = temp_dir("plaza-csvs");
    crate::plaza::calibration_csvs(&dir, Span::ALL)
        .unwrap()
        .write(&out)
        .unwrap();
    let files = Files {
        log: &out.join("log.csv"),
        detections: &out.join("detections.csv"),
        truth: Some(&out.join("truth.csv")),
        landmarks: Some(&out.join("landmarks.csv")),
    };
    let run = read_run(Model::Unicycle2d, &files).unwrap();
    assert_eq!(run.steps() as u64, mission["steps"].as_u64().unwrap());
    let steps: Vec<u64> = mission["detections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["step"].as_u64().unwrap())
        .collect();
    let read: Vec<u64> = run.detections.iter().map(|d| d.step as u64).collect();
    assert_eq!(read, steps);
    let truth = run.truth.as_ref().unwrap();
    for (k, p) in mission["truth"]["positions"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let q = truth.positions[k].unwrap();
        assert_eq!(
            [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()],
            q,
            "pose {k}"
        );
    }
    // A span without 2 rows is refused, naming the file.
    let e = crate::plaza::calibration_csvs(
        &dir,
        Span {
            from: 1e12,
            to: 2e12,
        },
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("Plaza1_GT.csv") && e.contains("fewer than 2 rows"),
        "{e}"
    );
}
