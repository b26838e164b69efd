//! A mission from raw measurements and a sensor model: the model's bounds
//! turn each reading into an interval (docs/calibration.md). The truth,
//! when the run has one, is attached for scoring only; the solver never
//! reads it.
//!
//! The initial pose fixes the map's frame: the user's box, else the
//! truth's first pose (the frame the truth and the landmarks are in)
//! within [`FRAME_POSITION`] and [`FRAME_HEADING`], else the origin with
//! heading 0.

use crate::calibrate::data::{Model, Run};
use crate::calibrate::residuals::{speed_interval, step_turn, true_reading};
use crate::doc::{boxed, finite_interval, int, interval, points};
use crate::sensor_model::SensorModel;
use crate::ImportError;
use nvector_core::format::leaf::{BoxIn, Finite, Integer, List, PerStep};
use nvector_core::format::mission_doc::{
    ChannelDoc, DetectionDoc, DriftWindowDoc, InputsDoc, MissionDoc, TruthDoc,
};
use nvector_core::format::to_value;
use nvector_core::slam::mission::FORMAT;
use serde_json::{json, Value};

/// Half-width of the initial position box around the truth's first
/// position (m).
pub const FRAME_POSITION: f64 = 0.01;
/// Half-width of the initial heading around the truth's first heading
/// (rad).
pub const FRAME_HEADING: f64 = 0.01;

/// What the user gives besides the run and the model.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Keep the detections' `landmark` column as the operator's ids.
    pub operator: bool,
    /// The mission's name.
    pub name: String,
    /// What the sensor model file was called.
    pub sensor_model: String,
    /// The initial position box `[[lo, hi], [lo, hi]]`.
    pub initial: Option<[[f64; 2]; 2]>,
    /// The initial heading (odometry2d).
    pub initial_heading: Option<[f64; 2]>,
    /// `landmark_count` (default: the landmarks file's count).
    pub landmark_count: Option<usize>,
    /// `landmark_min_separation`.
    pub landmark_min_separation: Option<f64>,
    /// `max_outliers`.
    pub max_outliers: Option<u64>,
}

/// How many readings lie outside the span a bound was fitted over.
#[derive(Default)]
struct Extrapolated {
    heading: usize,
    motion: usize,
    range: usize,
    bearing: usize,
}

/// The mission of `run` under `model`, written.
pub fn mission(run: &Run, model: &SensorModel, o: &Options) -> Result<Value, ImportError> {
    mission_doc(run, model, o).map(|m| to_value(&m))
}

/// The mission of `run` under `model` as a document (the data sets'
/// importers add their figures to its `meta` before writing it).
pub fn mission_doc(run: &Run, model: &SensorModel, o: &Options) -> Result<MissionDoc, ImportError> {
    if model.model != run.model.name() {
        return Err(ImportError::setting(
            "sensor_model",
            format!(
                "the sensor model is for {}, the log is read as {}",
                model.model,
                run.model.name()
            ),
        ));
    }
    let same_run = model.calibration.fingerprint == run.fingerprint();
    if model.flagged.is_some() && !same_run {
        return Err(ImportError::setting(
            "sensor_model",
            format!(
                "the sensor model has flagged steps: a same-run calibration of {} whose steps' own bounds hold on that log only, not on this one (calibrate without flagged steps to transfer it)",
                model.calibration.source
            ),
        ));
    }
    check_initial(o)?;
    let mut ex = Extrapolated::default();
    let landmark_count = o.landmark_count.or(run.landmarks.as_ref().map(Vec::len));
    let mut m = MissionDoc {
        format: Some(FORMAT.into()),
        name: Some(o.name.clone()),
        model: Some(model.model.clone().into()),
        dt: Some(Finite(run.dt)),
        steps: Some(int(run.steps())),
        initial_position: Some(initial_position(run, o)),
        inputs: Some(inputs(run, model)),
        sensor_offset: Some(List(model.sensor_offset.map(Finite).to_vec())),
        detections: Some(List(detections(run, model, o, &mut ex)?)),
        landmark_count: landmark_count.map(int),
        landmark_min_separation: o.landmark_min_separation.map(Finite),
        max_outliers: o.max_outliers.map(Integer::Value),
        ..MissionDoc::default()
    };
    motion_fields(&mut m, run, model, o, &mut ex);
    m.meta = Some(meta(run, model, o, &ex));
    m.truth = truth(run);
    Ok(m)
}

/// The user's initial box and heading: finite bounds, lo <= hi.
fn check_initial(o: &Options) -> Result<(), ImportError> {
    if let Some(b) = o.initial.filter(|b| !b.iter().all(|&x| finite_interval(x))) {
        return Err(ImportError::setting(
            "initial",
            format!("--initial {b:?}: expected finite LO <= HI on each axis"),
        ));
    }
    if let Some(h) = o.initial_heading.filter(|&h| !finite_interval(h)) {
        return Err(ImportError::setting(
            "initial_heading",
            format!("--initial-heading {h:?}: expected finite LO <= HI"),
        ));
    }
    Ok(())
}

fn initial_position(run: &Run, o: &Options) -> BoxIn {
    if let Some(b) = o.initial {
        return boxed(&b);
    }
    let e = FRAME_POSITION;
    match run.truth.as_ref().and_then(|t| t.positions[0]) {
        Some(p) => boxed(&[[p[0] - e, p[0] + e], [p[1] - e, p[1] + e]]),
        None => boxed(&[[0.0, 0.0], [0.0, 0.0]]),
    }
}

/// The input channels: the speed as intervals (its error, and the sign
/// rule), the turn rate exact (odometry2d) or the heading within its bound
/// (unicycle2d).
fn inputs(run: &Run, model: &SensorModel) -> InputsDoc {
    let (mut lo, mut hi) = (
        Vec::with_capacity(run.steps()),
        Vec::with_capacity(run.steps()),
    );
    for &v in &run.speed {
        let e = model.speed.error.at((v * run.dt).abs());
        let [a, b] = speed_interval(v, e, model.speed.sign_unknown_below);
        lo.push(a);
        hi.push(b);
    }
    // Exact speeds (no error, no sign rule) as their values: the same
    // intervals in half the bytes.
    let exact = lo.iter().zip(&hi).all(|(a, b)| a == b);
    let speed = match exact {
        true => ChannelDoc::measured(run.speed.clone(), 0.0),
        false => ChannelDoc::bounds(lo, hi),
    };
    let rotation = match run.model {
        Model::Odometry2d => ("turn_rate", ChannelDoc::measured(run.rotation.clone(), 0.0)),
        Model::Unicycle2d => (
            "heading",
            ChannelDoc::measured(run.rotation.clone(), model.heading.at(0.0)),
        ),
    };
    InputsDoc::of([("speed", speed), rotation])
}

/// Whether x lies outside a fitted span (a constant bound has none).
fn beyond(span: [f64; 2], x: f64) -> bool {
    span != [0.0, 0.0] && !(span[0]..=span[1]).contains(&x)
}

/// `motion_error`, and for odometry2d `initial_heading`, `heading_error`
/// and the drift windows.
fn motion_fields(
    m: &mut MissionDoc,
    run: &Run,
    model: &SensorModel,
    o: &Options,
    ex: &mut Extrapolated,
) {
    let me = &model.motion_error;
    let same = model.calibration.fingerprint == run.fingerprint();
    let motion = (0..run.steps())
        .map(|i| {
            let x = (run.speed[i] * run.dt).abs();
            let still = me.still.as_ref().is_some_and(|s| x < s.below);
            ex.motion += usize::from(!still && beyond(me.fit.span, x));
            model.motion_error_at(i, x, step_turn(run, i), same)
        })
        .collect();
    m.motion_error = Some(PerStep::Each(motion));
    if run.model != Model::Odometry2d {
        return;
    }
    let h = &model.heading;
    let heading = run
        .rotation
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let x = (w * run.dt).abs();
            ex.heading += usize::from(beyond(h.fit.span, x));
            model.heading_error_at(i, x, same)
        })
        .collect();
    m.heading_error = Some(PerStep::Each(heading));
    let e = FRAME_HEADING;
    m.initial_heading = Some(interval(
        match (
            o.initial_heading,
            run.truth.as_ref().and_then(|t| t.headings[0]),
        ) {
            (Some(b), _) => b,
            (None, Some(h0)) => [h0 - e, h0 + e],
            (None, None) => [0.0, 0.0],
        },
    ));
    let windows = |ws: &[crate::sensor_model::Window]| {
        let ws = ws.iter().map(|w| DriftWindowDoc {
            steps: Some(int(w.steps)),
            error: Some(Finite(w.error)),
            exempt_above: w.exempt_above.map(Finite),
        });
        Some(List(ws.collect()))
    };
    m.heading_drift = windows(&model.heading_drift);
    m.motion_drift = windows(&model.motion_drift);
}

/// The detections: each reading's interval from the model's bands.
fn detections(
    run: &Run,
    model: &SensorModel,
    o: &Options,
    ex: &mut Extrapolated,
) -> Result<Vec<DetectionDoc>, ImportError> {
    let mut out = Vec::with_capacity(run.detections.len());
    for (j, d) in run.detections.iter().enumerate() {
        let (range, outside) = model.range.interval(d.range, d.range);
        ex.range += usize::from(outside);
        let mut v = DetectionDoc {
            step: Some(int(d.step)),
            range: Some(interval([range[0].max(0.0), range[1].max(0.0)])),
            scan: d.scan.map(Integer::Value),
            ..DetectionDoc::default()
        };
        match (&model.bearing, d.bearing) {
            (Some(b), Some(m)) => {
                let (bearing, outside) = b.interval(m, d.range);
                ex.bearing += usize::from(outside);
                v.bearing = Some(interval(bearing));
            }
            (None, Some(_)) | (Some(_), None) => {
                return Err(at_detection(
                    run,
                    j,
                    if model.bearing.is_some() {
                        "no bearing, but the sensor model has a bearing band (every detection needs one)"
                    } else {
                        "a bearing, but the sensor model has no bearing band (calibrate on a run with bearings)"
                    },
                ))
            }
            (None, None) => {}
        }
        if o.operator {
            v.landmark = Some(Integer::Value(operator_id(run, j)?));
        }
        out.push(v);
    }
    Ok(out)
}

/// A detection's operator id: its landmark's index among the sorted ids of
/// the landmarks file, or the id itself without one.
fn operator_id(run: &Run, j: usize) -> Result<u64, ImportError> {
    let d = &run.detections[j];
    let id = d
        .landmark
        .ok_or_else(|| at_detection(run, j, "--operator: no landmark id"))?;
    match &run.landmarks {
        None => Ok(id),
        Some(_) => run.landmark_index(id).map(|i| i as u64).ok_or_else(|| {
            at_detection(
                run,
                j,
                &format!("--operator: landmark {id} is not in the landmarks file"),
            )
        }),
    }
}

/// An error at detection j: its file and line when it was read from one.
fn at_detection(run: &Run, j: usize, what: &str) -> ImportError {
    let d = &run.detections[j];
    let message = format!("detection {j} (step {}): {what}", d.step);
    if d.line > 0 {
        ImportError::line(&run.paths.detections, d.line, message)
    } else {
        ImportError::setting("detections", message)
    }
}

fn meta(run: &Run, model: &SensorModel, o: &Options, ex: &Extrapolated) -> Value {
    let same_run = model.calibration.fingerprint == run.fingerprint();
    json!({
        "calibration": {
            "source": model.calibration.source,
            "same_run": same_run,
            "sensor_model": o.sensor_model,
            "fingerprint": model.calibration.fingerprint,
            "relative_margin": model.calibration.relative_margin,
            "extrapolated": {
                "note": "readings beyond the span the bound was fitted over: the bound holds there only as far as its line does",
                "heading_error": ex.heading,
                "motion_error": ex.motion,
                "range": ex.range,
                "bearing": ex.bearing,
            },
            "initial_pose": match (o.initial, run.truth.as_ref().and_then(|t| t.positions[0])) {
                (Some(_), _) => "the user's box".to_string(),
                (None, Some(_)) => format!("the truth's first pose within {FRAME_POSITION} m and {FRAME_HEADING} rad (the map's frame)"),
                (None, None) => "the origin, heading 0 (the map's frame)".to_string(),
            },
        },
        "sensor_model": model,
    })
}

/// The truth for scoring: positions (and headings for odometry2d), null in
/// the gaps; the landmarks and the matching when the landmarks file and
/// every detection's id are known.
fn truth(run: &Run) -> Option<TruthDoc> {
    let t = run.truth.as_ref()?;
    let mut v = TruthDoc {
        positions: Some(points(t.positions.iter().copied())),
        ..TruthDoc::default()
    };
    if run.model == Model::Odometry2d && t.has_heading {
        v.headings = Some(List(t.headings.iter().map(|h| h.map(Finite)).collect()));
    }
    if let Some(l) = &run.landmarks {
        v.landmarks = Some(points(l.iter().map(|x| Some(x.1))));
        let matching: Option<Vec<usize>> = run
            .detections
            .iter()
            .map(|d| run.landmark_index(d.landmark?))
            .collect();
        if let Some(mt) = matching {
            v.matching = Some(List(mt.into_iter().map(|i| Some(int(i))).collect()));
        }
    }
    Some(v)
}

/// The detections (by index) whose true range or bearing lies outside the
/// interval `model` gives them (as [`mission`] writes it), at the steps
/// where the truth is known: the readings an outlier share
/// ([`crate::calibrate::Options::outlier_share`]) left outside.
pub fn readings_outside(run: &Run, model: &SensorModel) -> Vec<usize> {
    let inside_mod_2pi = |x: f64, [lo, hi]: [f64; 2]| {
        let tau = 2.0 * std::f64::consts::PI;
        x + tau * ((lo - x) / tau).ceil() <= hi
    };
    (0..run.detections.len())
        .filter(|&j| {
            let Some((range, bearing)) = true_reading(run, j, model.sensor_offset) else {
                return false;
            };
            let d = &run.detections[j];
            let (r, _) = model.range.interval(d.range, d.range);
            let r_ok = r[0].max(0.0) <= range && range <= r[1].max(0.0);
            let b_ok = match (&model.bearing, d.bearing, bearing) {
                (Some(b), Some(m), Some(t)) => inside_mod_2pi(t, b.interval(m, d.range).0),
                _ => true,
            };
            !(r_ok && b_ok)
        })
        .collect()
}
