//! Validation of a parsed `nvector-mission/1` document into a [`Mission`]:
//! every check that depends on other fields (the model's dimension and
//! channels, N, landmark_count), in one order, each error naming the JSON
//! path of the bad value.

use super::{Detection, Mission, Model, Points, Truth, FORMAT, MAX_STEPS};
use crate::error::InputError;
use crate::format::leaf::{wrong_count, Finite, Integer, List, PointsIn};
use crate::format::mission_doc::{ChannelDoc, DetectionDoc, DriftWindowDoc, MissionDoc, TruthDoc};
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::json;
use crate::odometry::drift::{DriftWindow, MAX_EXEMPT_LEVELS};
use crate::odometry::motion_drift::MotionWindow;
use serde_json::{Map, Value};

fn err(path: impl Into<String>, msg: impl Into<String>) -> InputError {
    InputError::new(path, msg)
}

/// `path` + `.field` (or `field` at the root).
fn field_path(path: &str, field: &str) -> String {
    json::field_path(path, field)
}

fn missing(path: impl Into<String>) -> InputError {
    err(path, "missing required field")
}

/// The required field `field` of the object at `path`.
fn need<T>(v: Option<T>, path: &str, field: &str) -> Result<T, InputError> {
    v.ok_or_else(|| missing(field_path(path, field)))
}

/// A channel's array (`value`, `lo` or `hi`): one number per step.
fn per_step(v: Vec<f64>, path: &str, n: usize) -> Result<Vec<f64>, InputError> {
    if v.len() != n {
        return Err(wrong_count(path, n, v.len()));
    }
    Ok(v)
}

/// The fields of `names` present (`true`) that are not in `allowed`: the
/// first as an "unknown field" error at `path`.
fn only(names: &[(&str, bool)], allowed: &[&str], path: &str) -> Result<(), InputError> {
    match names
        .iter()
        .find(|(n, present)| *present && !allowed.contains(n))
    {
        Some((n, _)) => Err(err(
            field_path(path, n),
            format!(
                "unknown field `{n}` (expected one of: {})",
                allowed.join(", ")
            ),
        )),
        None => Ok(()),
    }
}

/// One input channel: N intervals.
fn channel(c: ChannelDoc, path: &str, n: usize) -> Result<Vec<Interval>, InputError> {
    let fields = [
        ("value", c.value.is_some()),
        ("error", c.error.is_some()),
        ("lo", c.lo.is_some()),
        ("hi", c.hi.is_some()),
    ];
    if let Some(value) = c.value {
        only(&fields, &["value", "error"], path)?;
        let values = per_step(value.0, &field_path(path, "value"), n)?;
        let error = need(c.error, path, "error")?.non_negative(
            &field_path(path, "error"),
            n,
            "an error bound",
        )?;
        Ok(values
            .iter()
            .zip(&error)
            .map(|(&x, &e)| Interval::centered(x, e))
            .collect())
    } else if c.lo.is_some() || c.hi.is_some() {
        only(&fields, &["lo", "hi"], path)?;
        let lo_path = field_path(path, "lo");
        let hi_path = field_path(path, "hi");
        let lo = per_step(need(c.lo, path, "lo")?.0, &lo_path, n)?;
        let hi = per_step(need(c.hi, path, "hi")?.0, &hi_path, n)?;
        lo.iter()
            .zip(&hi)
            .enumerate()
            .map(|(i, (&l, &h))| {
                if l > h {
                    Err(err(
                        format!("{lo_path}[{i}]"),
                        format!("lower bound {l} is above upper bound {h}"),
                    ))
                } else if l == f64::INFINITY {
                    Err(err(
                        format!("{lo_path}[{i}]"),
                        "a lower bound of inf holds no real number",
                    ))
                } else if h == f64::NEG_INFINITY {
                    Err(err(
                        format!("{hi_path}[{i}]"),
                        "an upper bound of -inf holds no real number",
                    ))
                } else {
                    Ok(Interval::new(l, h))
                }
            })
            .collect()
    } else {
        Err(err(path, "an input channel is {\"value\": [...], \"error\": e} or {\"lo\": [...], \"hi\": [...]}"))
    }
}

/// Points of dimension `dim` (`null` entries are unknown points: zeros,
/// and `false` in the mask returned when there is one, or refused when
/// `nulls_allowed` is false).
fn points(
    p: PointsIn,
    path: &str,
    dim: usize,
    nulls_allowed: bool,
) -> Result<(Points, Option<Vec<bool>>), InputError> {
    let wrong = |i: usize, len: usize| {
        err(
            format!("{path}[{i}]"),
            format!("expected a point of dimension {dim}, found {len} coordinates"),
        )
    };
    let first_null = p.nulls.first().copied();
    match (p.mismatch, first_null) {
        (Some((i, _)), Some(j)) if !nulls_allowed && j < i => {
            return Err(err(format!("{path}[{j}]"), "expected an array, found null"))
        }
        (Some((i, len)), _) if p.width == dim => return Err(wrong(i, len)),
        (None, Some(j)) if !nulls_allowed => {
            return Err(err(format!("{path}[{j}]"), "expected an array, found null"))
        }
        _ => {}
    }
    if p.count > p.nulls.len() && p.width != dim {
        // The first point given has the wrong length.
        let i = (0..p.count)
            .find(|i| p.nulls.binary_search(i).is_err())
            .unwrap_or(0);
        return Err(wrong(i, p.width));
    }
    if p.nulls.is_empty() {
        return Ok((Points::new(dim, p.flat), None));
    }
    let mut known = vec![true; p.count];
    for &j in &p.nulls {
        known[j] = false;
    }
    let mut flat = Vec::with_capacity(p.count * dim);
    let mut given = p.flat.chunks_exact(dim);
    for &k in &known {
        let point = if k { given.next() } else { None };
        match point {
            Some(point) => flat.extend_from_slice(point),
            None => flat.extend(std::iter::repeat_n(0.0, dim)),
        }
    }
    Ok((Points::new(dim, flat), Some(known)))
}

/// The headings of odometry2d, refused for the other models.
struct Headings {
    initial: Option<Interval>,
    last: Option<Interval>,
    error: Vec<f64>,
    drift: Vec<DriftWindow>,
    motion: Vec<MotionWindow>,
}

/// A window's `exempt_above` (at `path`), >= 0 when given, added to the
/// distinct `levels` of its list: at most [`MAX_EXEMPT_LEVELS`] (one
/// prefix array or exempt sum each).
fn exempt_level(
    t: Option<Finite>,
    path: &str,
    levels: &mut Vec<f64>,
) -> Result<Option<f64>, InputError> {
    let Some(t) = t.map(|t| t.0) else {
        return Ok(None);
    };
    let t_path = field_path(path, "exempt_above");
    if t.is_nan() || t < 0.0 {
        return Err(err(
            t_path,
            format!("the exemption threshold must be >= 0, found {t}"),
        ));
    }
    if !levels.contains(&t) {
        if levels.len() == MAX_EXEMPT_LEVELS {
            return Err(err(
                t_path,
                format!("at most {MAX_EXEMPT_LEVELS} distinct exempt_above values over the windows (one prefix array each), found a {}th: {t}", MAX_EXEMPT_LEVELS + 1),
            ));
        }
        levels.push(t);
    }
    Ok(Some(t))
}

/// A drift window's fields as read: `steps`, `error`, `exempt_above`.
type WindowFields = (Option<Integer>, Option<Finite>, Option<Finite>);

/// `heading_drift` or `motion_drift` (`name`): each window's `steps` >= 1
/// (any size: a window longer than N is kept and constrains nothing;
/// nothing is sized by it), `error` >= 0, `exempt_above` >= 0 when given,
/// with at most [`MAX_EXEMPT_LEVELS`] distinct values over the windows
/// (one prefix array or exempt sum each).
fn drift_windows(
    name: &str,
    list: impl Iterator<Item = WindowFields>,
) -> Result<Vec<DriftWindow>, InputError> {
    let mut out: Vec<DriftWindow> = Vec::new();
    let mut levels: Vec<f64> = Vec::new();
    for (x, (steps, error, exempt)) in list.enumerate() {
        let path = format!("{name}[{x}]");
        let steps_path = field_path(&path, "steps");
        let k = need(steps, &path, "steps")?.in_range(1, u64::MAX, &steps_path)?;
        let b = need(error, &path, "error")?.0;
        if b.is_nan() || b < 0.0 {
            return Err(err(
                field_path(&path, "error"),
                format!("the drift bound must be >= 0, found {b}"),
            ));
        }
        let exempt_above = exempt_level(exempt, &path, &mut levels)?;
        out.push(DriftWindow {
            steps: k,
            error: b,
            exempt_above,
        });
    }
    Ok(out)
}

fn heading_drift(list: List<DriftWindowDoc>) -> Result<Vec<DriftWindow>, InputError> {
    let fields = list
        .0
        .into_iter()
        .map(|w| (w.steps, w.error, w.exempt_above));
    drift_windows("heading_drift", fields)
}

fn motion_drift(list: List<DriftWindowDoc>) -> Result<Vec<MotionWindow>, InputError> {
    let fields = list
        .0
        .into_iter()
        .map(|w| (w.steps, w.error, w.exempt_above));
    drift_windows("motion_drift", fields)
}

fn headings(doc: &mut MissionDoc, model: Model, steps: usize) -> Result<Headings, InputError> {
    if model != Model::Odometry2d {
        for (field, present) in [
            ("initial_heading", doc.initial_heading.is_some()),
            ("final_heading", doc.final_heading.is_some()),
            ("heading_error", doc.heading_error.is_some()),
            ("heading_drift", doc.heading_drift.is_some()),
            ("motion_drift", doc.motion_drift.is_some()),
        ] {
            if present {
                return Err(err(
                    field,
                    format!("{field} is only for odometry2d missions"),
                ));
            }
        }
        return Ok(Headings {
            initial: None,
            last: None,
            error: Vec::new(),
            drift: Vec::new(),
            motion: Vec::new(),
        });
    }
    Ok(Headings {
        initial: Some(need(doc.initial_heading.take(), "", "initial_heading")?.0),
        last: doc.final_heading.take().map(|x| x.0),
        error: match doc.heading_error.take() {
            None => vec![0.0; steps],
            Some(e) => e.non_negative("heading_error", steps, "the heading error")?,
        },
        drift: doc
            .heading_drift
            .take()
            .map(heading_drift)
            .transpose()?
            .unwrap_or_default(),
        motion: doc
            .motion_drift
            .take()
            .map(motion_drift)
            .transpose()?
            .unwrap_or_default(),
    })
}

/// One detection, validated.
fn detection(
    d: DetectionDoc,
    path: &str,
    model: Model,
    steps: usize,
    landmark_count: Option<usize>,
) -> Result<Detection, InputError> {
    let dim = model.dim();
    let step_path = field_path(path, "step");
    let step = need(d.step, path, "step")?.in_range(0, steps as u64, &step_path)?;
    let range = need(d.range, path, "range")?.0;
    if range.lo() < 0.0 {
        return Err(err(
            field_path(path, "range"),
            format!("negative range: lower bound {} is below 0", range.lo()),
        ));
    }
    let region = d
        .region
        .map(|b| b.dim(&field_path(path, "region"), Some(dim)))
        .transpose()?;
    if d.depth.is_some() && model != Model::Auv3d {
        return Err(err(
            field_path(path, "depth"),
            "depth is only for auv3d missions",
        ));
    }
    let landmark = match d.landmark {
        None => None,
        Some(v) => {
            let lp = field_path(path, "landmark");
            // One rule: an id below landmark_count (at most u32::MAX).
            let max = landmark_count.map_or(u32::MAX as u64, |n| n as u64 - 1);
            let id = v.in_range(0, max, &lp).map_err(|mut e| {
                if let Some(n) = landmark_count {
                    e.message
                        .push_str(&format!(" (ids are below landmark_count {n})"));
                }
                e
            })?;
            Some(id as usize)
        }
    };
    let scan = d
        .scan
        .map(|s| s.at_most(u64::MAX, &field_path(path, "scan")))
        .transpose()?;
    Ok(Detection {
        step: step as usize,
        range,
        bearing: d.bearing.map(|x| x.0),
        region,
        depth: d.depth.map(|x| x.0),
        landmark,
        scan,
    })
}

/// The sensor offset: 2 numbers, 2-D models only.
fn sensor_offset(v: Option<List<Finite>>, model: Model) -> Result<Option<[f64; 2]>, InputError> {
    let Some(List(v)) = v else { return Ok(None) };
    if model.dim() != 2 {
        return Err(err(
            "sensor_offset",
            "sensor_offset is only for the 2-D models (unicycle2d, odometry2d)",
        ));
    }
    match v[..] {
        [Finite(x), Finite(y)] => Ok(Some([x, y])),
        _ => Err(err(
            "sensor_offset",
            format!("expected 2 numbers [forward, left], found {}", v.len()),
        )),
    }
}

impl Mission {
    /// Validates a parsed document into a mission: every check that
    /// depends on other fields (the model's dimension and channels, N,
    /// landmark_count), in one order.
    pub fn from_doc(mut doc: MissionDoc) -> Result<Mission, InputError> {
        let (name, model) = header(&mut doc)?;
        let dim = model.dim();
        let (dt, steps) = clock(&doc)?;
        let initial_position = need(doc.initial_position.take(), "", "initial_position")?
            .dim("initial_position", Some(dim))?;
        let final_position = doc
            .final_position
            .take()
            .map(|b| b.dim("final_position", Some(dim)))
            .transpose()?;
        let heading = headings(&mut doc, model, steps)?;
        let inputs = inputs(&mut doc, model, steps)?;
        let motion_error = match doc.motion_error.take() {
            None => vec![0.0; steps],
            Some(v) => v.non_negative("motion_error", steps, "the motion error")?,
        };
        let sensor_offset = sensor_offset(doc.sensor_offset.take(), model)?;
        let lm = landmark_options(&mut doc, dim)?;
        let landmark_count = lm.count;
        let List(dets) = need(doc.detections.take(), "", "detections")?;
        let detections = dets
            .into_iter()
            .enumerate()
            .map(|(i, d)| detection(d, &format!("detections[{i}]"), model, steps, landmark_count))
            .collect::<Result<Vec<_>, _>>()?;
        let meta = meta(doc.meta.take())?;
        let truth = doc
            .truth
            .take()
            .map(|t| truth(t, model, steps, detections.len()))
            .transpose()?;
        Ok(Mission {
            name,
            model,
            dt,
            steps,
            detection_count: detections.len(),
            initial_position,
            final_position,
            inputs,
            motion_error,
            detections,
            landmark_count,
            landmark_region: lm.region,
            max_outliers: lm.max_outliers,
            meta,
            truth,
            initial_heading: heading.initial,
            final_heading: heading.last,
            heading_error: heading.error,
            heading_drift: heading.drift,
            motion_drift: heading.motion,
            sensor_offset,
            landmark_min_separation: lm.min_separation,
        })
    }
}

/// `format` (checked), `name` (default "mission") and `model`.
fn header(doc: &mut MissionDoc) -> Result<(String, Model), InputError> {
    let format = need(doc.format.take(), "", "format")?;
    if format.as_str() != Some(FORMAT) {
        return Err(err(
            "format",
            format!("expected \"{FORMAT}\", found {format}"),
        ));
    }
    let name = doc.name.take().unwrap_or_else(|| "mission".to_string());
    let model = match need(doc.model.take(), "", "model")? {
        Value::String(s) if s == "unicycle2d" => Model::Unicycle2d,
        Value::String(s) if s == "auv3d" => Model::Auv3d,
        Value::String(s) if s == "odometry2d" => Model::Odometry2d,
        o => {
            return Err(err(
                "model",
                format!("expected \"unicycle2d\", \"auv3d\" or \"odometry2d\", found {o}"),
            ))
        }
    };
    Ok((name, model))
}

/// `dt` (> 0) and `steps` (1 to [`MAX_STEPS`]).
fn clock(doc: &MissionDoc) -> Result<(f64, usize), InputError> {
    let dt = need(doc.dt, "", "dt")?.0;
    if dt <= 0.0 {
        return Err(err("dt", format!("the time step must be > 0, found {dt}")));
    }
    let steps =
        need(doc.steps.as_ref(), "", "steps")?.in_range(1, MAX_STEPS as u64, "steps")? as usize;
    Ok((dt, steps))
}

/// The model's input channels, each of `steps` intervals, no other.
fn inputs(
    doc: &mut MissionDoc,
    model: Model,
    steps: usize,
) -> Result<Vec<Vec<Interval>>, InputError> {
    let mut inputs_doc = need(doc.inputs.take(), "", "inputs")?;
    let present: Vec<(&str, bool)> = inputs_doc.names().into_iter().map(|n| (n, true)).collect();
    only(&present, model.channels(), "inputs")?;
    let mut inputs = Vec::with_capacity(model.channels().len());
    for ch in model.channels() {
        let path = field_path("inputs", ch);
        let c = inputs_doc.take(ch).ok_or_else(|| missing(&path))?;
        inputs.push(channel(c, &path, steps)?);
    }
    Ok(inputs)
}

/// What a mission says of its landmarks and false detections.
struct LandmarkOptions {
    count: Option<usize>,
    region: Option<IntervalBox>,
    min_separation: f64,
    max_outliers: usize,
}

/// `landmark_count` (>= 1), `landmark_region` (of the model's dimension),
/// `landmark_min_separation` (>= 0, default 0), `max_outliers` (default 0),
/// checked in that order.
fn landmark_options(doc: &mut MissionDoc, dim: usize) -> Result<LandmarkOptions, InputError> {
    let count = doc
        .landmark_count
        .take()
        .map(|v| v.in_range(1, u32::MAX as u64, "landmark_count"))
        .transpose()?
        .map(|n| n as usize);
    let region = doc
        .landmark_region
        .take()
        .map(|b| b.dim("landmark_region", Some(dim)))
        .transpose()?;
    let min_separation = doc.landmark_min_separation.map_or(0.0, |x| x.0);
    if min_separation < 0.0 {
        return Err(err(
            "landmark_min_separation",
            format!("the separation must be >= 0, found {min_separation}"),
        ));
    }
    let max_outliers = doc
        .max_outliers
        .take()
        .map(|v| v.at_most(u32::MAX as u64, "max_outliers"))
        .transpose()?
        .map_or(0, |q| q as usize);
    Ok(LandmarkOptions {
        count,
        region,
        min_separation,
        max_outliers,
    })
}

/// `meta`: absent or null is `{}`; anything but an object is refused.
fn meta(v: Option<Value>) -> Result<Value, InputError> {
    match v {
        None | Some(Value::Null) => Ok(Value::Object(Map::new())),
        Some(v @ Value::Object(_)) => Ok(v),
        Some(o) => Err(err(
            "meta",
            format!("expected an object, found {}", json::kind(&o)),
        )),
    }
}

fn truth(t: TruthDoc, model: Model, steps: usize, detections: usize) -> Result<Truth, InputError> {
    let dim = model.dim();
    let rows = need(t.positions, "truth", "positions")?;
    let (positions, positions_known) = points(rows, "truth.positions", dim, true)?;
    if positions.len() != steps + 1 {
        return Err(err(
            "truth.positions",
            format!(
                "expected {} positions (steps + 1), found {}",
                steps + 1,
                positions.len()
            ),
        ));
    }
    let rows = need(t.landmarks, "truth", "landmarks")?;
    let (landmarks, _) = points(rows, "truth.landmarks", dim, false)?;
    let List(m) = need(t.matching, "truth", "matching")?;
    if m.len() != detections {
        return Err(err(
            "truth.matching",
            format!(
                "expected one landmark per detection ({detections}), found {}",
                m.len()
            ),
        ));
    }
    let matching = m
        .into_iter()
        .enumerate()
        .map(|(i, x)| {
            // null: a false detection (no landmark there).
            let Some(x) = x else { return Ok(None) };
            let p = format!("truth.matching[{i}]");
            // One rule: an index of truth.landmarks (or null).
            if landmarks.is_empty() {
                return Err(err(p, "expected null (truth.landmarks is empty)"));
            }
            let id = x.in_range(0, landmarks.len() as u64 - 1, &p)?;
            Ok(Some(id as usize))
        })
        .collect::<Result<_, _>>()?;
    let headings = match t.headings {
        None => None,
        Some(_) if model != Model::Odometry2d => {
            return Err(err(
                "truth.headings",
                "truth.headings is only for odometry2d missions",
            ))
        }
        Some(List(h)) if h.len() != steps + 1 => {
            return Err(err(
                "truth.headings",
                format!(
                    "expected {} headings (steps + 1), found {}",
                    steps + 1,
                    h.len()
                ),
            ))
        }
        Some(List(h)) => Some(h.into_iter().map(|x| x.map(|x| x.0)).collect()),
    };
    Ok(Truth {
        positions,
        landmarks,
        matching,
        positions_known,
        headings,
    })
}
