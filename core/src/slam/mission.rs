//! `nvector-mission/1`: parsing and validation (spec/formats.md,
//! "Mission"). Every invalid input gets an [`InputError`] naming the JSON
//! path of the bad value.

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::json::{self, field_path, index_path};
use serde_json::{Map, Value};

/// Format tag of a mission.
pub const FORMAT: &str = "nvector-mission/1";
/// Most steps accepted.
pub const MAX_STEPS: usize = 2_000_000;

/// The motion model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Planar unicycle: inputs speed, heading.
    Unicycle2d,
    /// 3-D AUV: inputs roll, pitch, yaw, vx, vy, vz (body frame).
    Auv3d,
}

impl Model {
    /// Dimension of a position.
    pub fn dim(self) -> usize {
        match self {
            Model::Unicycle2d => 2,
            Model::Auv3d => 3,
        }
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Model::Unicycle2d => "unicycle2d",
            Model::Auv3d => "auv3d",
        }
    }

    /// Input channels, in order.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Model::Unicycle2d => &["speed", "heading"],
            Model::Auv3d => &["roll", "pitch", "yaw", "vx", "vy", "vz"],
        }
    }
}

/// One landmark detection.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// Step of the robot position p(step), 0..=N.
    pub step: usize,
    /// Range to the landmark (lo >= 0).
    pub range: Interval,
    /// Angle of the landmark relative to the heading (2-D) or yaw (3-D).
    pub bearing: Option<Interval>,
    /// A box known to hold the landmark.
    pub region: Option<IntervalBox>,
    /// Interval of the landmark's z (auv3d).
    pub depth: Option<Interval>,
    /// Operator's matching: the landmark id.
    pub landmark: Option<usize>,
}

/// Ground truth of a simulated mission: used to score and draw, never read
/// by the solver.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// N+1 true positions.
    pub positions: Vec<Vec<f64>>,
    /// True landmark positions.
    pub landmarks: Vec<Vec<f64>>,
    /// For each detection, the true landmark index; `None` (JSON `null`)
    /// for a false detection (no landmark there).
    pub matching: Vec<Option<usize>>,
}

/// A validated mission.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    /// `name` field.
    pub name: String,
    /// Motion model.
    pub model: Model,
    /// Time step (s).
    pub dt: f64,
    /// N, the number of steps.
    pub steps: usize,
    /// Number of detections.
    pub detection_count: usize,
    /// Box of p(0).
    pub initial_position: IntervalBox,
    /// Box of p(N), when known.
    pub final_position: Option<IntervalBox>,
    /// Input channels in the order of [`Model::channels`], N intervals each.
    pub inputs: Vec<Vec<Interval>>,
    /// Per-step integration error bound (N entries).
    pub motion_error: Vec<f64>,
    /// Detections, in input order.
    pub detections: Vec<Detection>,
    /// n, the known number of landmarks.
    pub landmark_count: Option<usize>,
    /// A box holding every landmark.
    pub landmark_region: Option<IntervalBox>,
    /// q: at most this many detections may be false (`max_outliers`,
    /// default 0). Carried for the propagator; q = 0 changes nothing.
    pub max_outliers: usize,
    /// Free-form metadata, carried through.
    pub meta: Value,
    /// Ground truth (scoring and drawing only).
    pub truth: Option<Truth>,
}

fn err(path: impl Into<String>, msg: impl Into<String>) -> InputError {
    InputError::new(path, msg)
}

fn optional<'a>(obj: &'a Map<String, Value>, field: &str) -> Option<&'a Value> {
    obj.get(field).filter(|v| !v.is_null())
}

/// A number or an array of `n` numbers, each >= 0.
fn per_step(v: &Value, path: &str, n: usize, what: &str) -> Result<Vec<f64>, InputError> {
    let check = |x: f64, p: &str| {
        if x < 0.0 {
            Err(err(p, format!("{what} must be >= 0, found {x}")))
        } else {
            Ok(x)
        }
    };
    match v {
        Value::Array(a) => {
            if a.len() != n {
                return Err(err(
                    path,
                    format!("expected {n} values (one per step), found {}", a.len()),
                ));
            }
            a.iter()
                .enumerate()
                .map(|(i, x)| {
                    let p = index_path(path, i);
                    check(json::number(x, &p)?, &p)
                })
                .collect()
        }
        _ => Ok(vec![check(json::number(v, path)?, path)?; n]),
    }
}

fn numbers(v: &Value, path: &str, n: usize) -> Result<Vec<f64>, InputError> {
    let a = json::array(v, path)?;
    if a.len() != n {
        return Err(err(
            path,
            format!("expected {n} values (one per step), found {}", a.len()),
        ));
    }
    a.iter()
        .enumerate()
        .map(|(i, x)| json::number(x, &index_path(path, i)))
        .collect()
}

fn parse_channel(v: &Value, path: &str, n: usize) -> Result<Vec<Interval>, InputError> {
    let obj = json::object(v, path)?;
    if obj.contains_key("value") {
        json::check_fields(obj, &["value", "error"], path)?;
        let values = numbers(&obj["value"], &field_path(path, "value"), n)?;
        let error = per_step(
            json::required(obj, "error", path)?,
            &field_path(path, "error"),
            n,
            "an error bound",
        )?;
        Ok(values
            .iter()
            .zip(&error)
            .map(|(&x, &e)| Interval::centered(x, e))
            .collect())
    } else if obj.contains_key("lo") || obj.contains_key("hi") {
        json::check_fields(obj, &["lo", "hi"], path)?;
        let lo = numbers(json::required(obj, "lo", path)?, &field_path(path, "lo"), n)?;
        let hi = numbers(json::required(obj, "hi", path)?, &field_path(path, "hi"), n)?;
        lo.iter()
            .zip(&hi)
            .enumerate()
            .map(|(i, (&l, &h))| {
                if l > h {
                    Err(err(
                        index_path(&field_path(path, "lo"), i),
                        format!("lower bound {l} is above upper bound {h}"),
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

fn points(v: &Value, path: &str, dim: Option<usize>) -> Result<Vec<Vec<f64>>, InputError> {
    let a = json::array(v, path)?;
    a.iter()
        .enumerate()
        .map(|(i, p)| {
            let pp = index_path(path, i);
            let c = json::array(p, &pp)?;
            if let Some(d) = dim {
                if c.len() != d {
                    return Err(err(
                        &pp,
                        format!(
                            "expected a point of dimension {d}, found {} coordinates",
                            c.len()
                        ),
                    ));
                }
            }
            c.iter()
                .enumerate()
                .map(|(j, x)| json::number(x, &index_path(&pp, j)))
                .collect()
        })
        .collect()
}

impl Mission {
    /// Parses JSON text.
    pub fn from_json(text: &str) -> Result<Mission, InputError> {
        let v: Value =
            serde_json::from_str(text).map_err(|e| err("", format!("invalid JSON: {e}")))?;
        Mission::from_value(&v)
    }

    /// Parses and validates a mission; errors name the JSON path.
    pub fn from_value(v: &Value) -> Result<Mission, InputError> {
        let obj = json::object(v, "")?;
        json::check_fields(
            obj,
            &[
                "format",
                "name",
                "model",
                "dt",
                "steps",
                "initial_position",
                "final_position",
                "inputs",
                "motion_error",
                "detections",
                "landmark_count",
                "landmark_region",
                "max_outliers",
                "meta",
                "truth",
            ],
            "",
        )?;
        let format = json::required(obj, "format", "")?;
        if format.as_str() != Some(FORMAT) {
            return Err(err(
                "format",
                format!("expected \"{FORMAT}\", found {format}"),
            ));
        }
        let name = match optional(obj, "name") {
            None => "mission".to_string(),
            Some(Value::String(s)) => s.clone(),
            Some(o) => {
                return Err(err(
                    "name",
                    format!("expected a string, found {}", json::kind(o)),
                ))
            }
        };
        let model = match json::required(obj, "model", "")? {
            Value::String(s) if s == "unicycle2d" => Model::Unicycle2d,
            Value::String(s) if s == "auv3d" => Model::Auv3d,
            o => {
                return Err(err(
                    "model",
                    format!("expected \"unicycle2d\" or \"auv3d\", found {o}"),
                ))
            }
        };
        let dim = model.dim();
        let dt = json::number(json::required(obj, "dt", "")?, "dt")?;
        if dt <= 0.0 {
            return Err(err("dt", format!("the time step must be > 0, found {dt}")));
        }
        let steps =
            json::integer(json::required(obj, "steps", "")?, "steps", MAX_STEPS as u64)? as usize;
        if steps == 0 {
            return Err(err("steps", "a mission needs at least 1 step"));
        }
        let initial_position = json::ibox(
            json::required(obj, "initial_position", "")?,
            "initial_position",
            Some(dim),
        )?;
        let final_position = optional(obj, "final_position")
            .map(|v| json::ibox(v, "final_position", Some(dim)))
            .transpose()?;
        let inputs_v = json::object(json::required(obj, "inputs", "")?, "inputs")?;
        json::check_fields(inputs_v, model.channels(), "inputs")?;
        let mut inputs = Vec::new();
        for ch in model.channels() {
            let path = field_path("inputs", ch);
            let v = inputs_v
                .get(*ch)
                .ok_or_else(|| err(&path, "missing required field"))?;
            inputs.push(parse_channel(v, &path, steps)?);
        }
        let motion_error = match optional(obj, "motion_error") {
            None => vec![0.0; steps],
            Some(v) => per_step(v, "motion_error", steps, "the motion error")?,
        };
        let landmark_count = optional(obj, "landmark_count")
            .map(|v| json::integer(v, "landmark_count", u32::MAX as u64))
            .transpose()?
            .map(|n| n as usize);
        if landmark_count == Some(0) {
            return Err(err("landmark_count", "landmark_count must be at least 1"));
        }
        let landmark_region = optional(obj, "landmark_region")
            .map(|v| json::ibox(v, "landmark_region", Some(dim)))
            .transpose()?;
        let max_outliers = optional(obj, "max_outliers")
            .map(|v| json::integer(v, "max_outliers", u32::MAX as u64))
            .transpose()?
            .map_or(0, |q| q as usize);
        let dets = json::array(json::required(obj, "detections", "")?, "detections")?;
        let mut detections = Vec::with_capacity(dets.len());
        for (i, d) in dets.iter().enumerate() {
            let path = index_path("detections", i);
            let o = json::object(d, &path)?;
            json::check_fields(
                o,
                &["step", "range", "bearing", "region", "depth", "landmark"],
                &path,
            )?;
            let step_path = field_path(&path, "step");
            let step = json::integer(json::required(o, "step", &path)?, &step_path, u64::MAX)?;
            if step > steps as u64 {
                return Err(err(
                    step_path,
                    format!("step {step} is out of range 0..={steps}"),
                ));
            }
            let range_path = field_path(&path, "range");
            let range = json::interval(json::required(o, "range", &path)?, &range_path)?;
            if range.lo() < 0.0 {
                return Err(err(
                    range_path,
                    format!("negative range: lower bound {} is below 0", range.lo()),
                ));
            }
            let bearing = optional(o, "bearing")
                .map(|v| json::interval(v, &field_path(&path, "bearing")))
                .transpose()?;
            let region = optional(o, "region")
                .map(|v| json::ibox(v, &field_path(&path, "region"), Some(dim)))
                .transpose()?;
            let depth = optional(o, "depth")
                .map(|v| json::interval(v, &field_path(&path, "depth")))
                .transpose()?;
            if depth.is_some() && model != Model::Auv3d {
                return Err(err(
                    field_path(&path, "depth"),
                    "depth is only for auv3d missions",
                ));
            }
            let landmark = match optional(o, "landmark") {
                None => None,
                Some(v) => {
                    let lp = field_path(&path, "landmark");
                    let id = json::integer(v, &lp, u32::MAX as u64)? as usize;
                    if let Some(n) = landmark_count {
                        if id >= n {
                            return Err(err(
                                lp,
                                format!("landmark {id} is not below landmark_count {n}"),
                            ));
                        }
                    }
                    Some(id)
                }
            };
            detections.push(Detection {
                step: step as usize,
                range,
                bearing,
                region,
                depth,
                landmark,
            });
        }
        let meta = match optional(obj, "meta") {
            None => Value::Object(Map::new()),
            Some(v @ Value::Object(_)) => v.clone(),
            Some(o) => {
                return Err(err(
                    "meta",
                    format!("expected an object, found {}", json::kind(o)),
                ))
            }
        };
        let truth = optional(obj, "truth")
            .map(|v| parse_truth(v, dim, steps, detections.len()))
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
            landmark_region,
            max_outliers,
            meta,
            truth,
        })
    }

    /// The mission in the spec's format (`from_value(to_value(m)) == m`).
    pub fn to_value(&self) -> Value {
        let mut o = Map::new();
        o.insert("format".into(), FORMAT.into());
        o.insert("name".into(), self.name.clone().into());
        o.insert("model".into(), self.model.name().into());
        o.insert("dt".into(), self.dt.into());
        o.insert("steps".into(), self.steps.into());
        o.insert(
            "initial_position".into(),
            json::box_to_json(&self.initial_position),
        );
        o.insert(
            "final_position".into(),
            self.final_position
                .as_ref()
                .map_or(Value::Null, json::box_to_json),
        );
        let mut inputs = Map::new();
        for (name, ch) in self.model.channels().iter().zip(&self.inputs) {
            let lo: Vec<f64> = ch.iter().map(|x| x.lo()).collect();
            let hi: Vec<f64> = ch.iter().map(|x| x.hi()).collect();
            inputs.insert((*name).into(), serde_json::json!({"lo": lo, "hi": hi}));
        }
        o.insert("inputs".into(), Value::Object(inputs));
        o.insert("motion_error".into(), serde_json::json!(self.motion_error));
        let dets: Vec<Value> = self
            .detections
            .iter()
            .map(|d| {
                let mut m = Map::new();
                m.insert("step".into(), d.step.into());
                m.insert("range".into(), json::interval_to_json(d.range));
                if let Some(b) = d.bearing {
                    m.insert("bearing".into(), json::interval_to_json(b));
                }
                if let Some(r) = &d.region {
                    m.insert("region".into(), json::box_to_json(r));
                }
                if let Some(z) = d.depth {
                    m.insert("depth".into(), json::interval_to_json(z));
                }
                if let Some(l) = d.landmark {
                    m.insert("landmark".into(), l.into());
                }
                Value::Object(m)
            })
            .collect();
        o.insert("detections".into(), Value::Array(dets));
        if let Some(n) = self.landmark_count {
            o.insert("landmark_count".into(), n.into());
        }
        if let Some(r) = &self.landmark_region {
            o.insert("landmark_region".into(), json::box_to_json(r));
        }
        if self.max_outliers > 0 {
            o.insert("max_outliers".into(), self.max_outliers.into());
        }
        o.insert("meta".into(), self.meta.clone());
        if let Some(t) = &self.truth {
            o.insert(
                "truth".into(),
                serde_json::json!({"positions": t.positions, "landmarks": t.landmarks, "matching": t.matching}),
            );
        }
        Value::Object(o)
    }
}

fn parse_truth(
    v: &Value,
    dim: usize,
    steps: usize,
    detections: usize,
) -> Result<Truth, InputError> {
    let o = json::object(v, "truth")?;
    json::check_fields(o, &["positions", "landmarks", "matching"], "truth")?;
    let positions = points(
        json::required(o, "positions", "truth")?,
        "truth.positions",
        Some(dim),
    )?;
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
    let landmarks = points(
        json::required(o, "landmarks", "truth")?,
        "truth.landmarks",
        Some(dim),
    )?;
    let m = json::array(json::required(o, "matching", "truth")?, "truth.matching")?;
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
        .iter()
        .enumerate()
        .map(|(i, x)| {
            if x.is_null() {
                // A false detection: no landmark there.
                return Ok(None);
            }
            let p = index_path("truth.matching", i);
            let id = json::integer(x, &p, u32::MAX as u64)? as usize;
            if id >= landmarks.len() {
                return Err(err(
                    p,
                    format!(
                        "landmark {id} is not below the {} true landmarks",
                        landmarks.len()
                    ),
                ));
            }
            Ok(Some(id))
        })
        .collect::<Result<_, _>>()?;
    Ok(Truth {
        positions,
        landmarks,
        matching,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn small() -> Value {
        json!({
            "format": "nvector-mission/1",
            "name": "t",
            "model": "unicycle2d",
            "dt": 0.5,
            "steps": 2,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {
                "speed": {"value": [1.0, 2.0], "error": 0.1},
                "heading": {"lo": [0.0, 0.1], "hi": [0.0, 0.2]}
            },
            "detections": [{"step": 1, "range": [2, 3], "landmark": 0}],
            "landmark_count": 1
        })
    }

    #[test]
    fn parses_a_small_mission() {
        let m = Mission::from_value(&small()).unwrap();
        assert_eq!(
            (m.steps, m.detection_count, m.model),
            (2, 1, Model::Unicycle2d)
        );
        assert!(
            m.inputs[0][1].contains(1.9)
                && m.inputs[0][1].contains(2.1)
                && !m.inputs[0][1].contains(2.11)
        );
        assert_eq!(m.inputs[1][1], Interval::new(0.1, 0.2));
        assert_eq!(m.motion_error, vec![0.0, 0.0]);
        assert_eq!(m.detections[0].landmark, Some(0));
    }

    #[test]
    fn round_trips() {
        let m = Mission::from_value(&small()).unwrap();
        let again = Mission::from_value(&m.to_value()).unwrap();
        assert_eq!(m, again);
    }

    #[test]
    fn max_outliers_and_false_detections_round_trip() {
        let m = Mission::from_value(&small()).unwrap();
        assert_eq!(m.max_outliers, 0, "absent means 0");
        let mut v = small();
        v["max_outliers"] = json!(2);
        v["detections"] = json!([{"step": 1, "range": [2, 3]}, {"step": 2, "range": [1, 2]}]);
        v["truth"] = json!({
            "positions": [[0, 0], [0.5, 0], [1.5, 0]],
            "landmarks": [[2, 2]],
            "matching": [0, null]
        });
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.max_outliers, 2);
        assert_eq!(m.truth.as_ref().unwrap().matching, vec![Some(0), None]);
        let again = Mission::from_value(&m.to_value()).unwrap();
        assert_eq!(m, again);
        assert_eq!(m.to_value()["truth"]["matching"], json!([0, null]));
        v["max_outliers"] = Value::Null;
        assert_eq!(Mission::from_value(&v).unwrap().max_outliers, 0);
    }

    #[test]
    fn bad_inputs_name_their_path() {
        type Edit = fn(&mut Value);
        let cases: Vec<(Edit, &str)> = vec![
            (
                |v| v["inputs"]["speed"]["value"] = json!([1.0]),
                "inputs.speed.value: expected 2 values",
            ),
            (
                |v| v["detections"][0]["range"] = json!([5, 4]),
                "detections[0].range: lower bound 5 is above upper bound 4",
            ),
            (
                |v| v["detections"][0]["range"] = json!([-1, 4]),
                "detections[0].range: negative range",
            ),
            (
                |v| v["detections"][0]["step"] = json!(3),
                "detections[0].step: step 3 is out of range 0..=2",
            ),
            (
                |v| v["detections"][0]["landmark"] = json!(1),
                "detections[0].landmark: landmark 1 is not below landmark_count 1",
            ),
            (
                |v| v["detections"][0]["rnage"] = json!(1),
                "detections[0].rnage: unknown field",
            ),
            (|v| v["stpes"] = json!(1), "stpes: unknown field"),
            (
                |v| v["format"] = json!("nvector-mission/2"),
                "format: expected",
            ),
            (|v| v["dt"] = json!(0), "dt: the time step must be > 0"),
            (
                |v| v["detections"][0]["depth"] = json!([1, 2]),
                "detections[0].depth: depth is only for auv3d",
            ),
            (
                |v| v["inputs"]["speed"]["value"][1] = json!("NaN"),
                "inputs.speed.value[1]: expected a finite number",
            ),
            (
                |v| {
                    v["inputs"].as_object_mut().unwrap().remove("heading");
                },
                "inputs.heading: missing required field",
            ),
            (
                |v| v["initial_position"] = json!([[0, 1]]),
                "initial_position: expected a box of dimension 2",
            ),
            (
                |v| {
                    v["truth"] =
                        json!({"positions": [[0, 0]], "landmarks": [[1, 1]], "matching": [0]})
                },
                "truth.positions: expected 3 positions",
            ),
            (
                |v| v["max_outliers"] = json!(-1),
                "max_outliers: expected a non-negative integer, found -1",
            ),
            (
                |v| v["max_outliers"] = json!(1.5),
                "max_outliers: expected a non-negative integer, found 1.5",
            ),
            (
                |v| v["max_outliers"] = json!("2"),
                "max_outliers: expected a non-negative integer, found a string",
            ),
            (
                |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [-1]}),
                "truth.matching[0]: expected a non-negative integer, found -1",
            ),
        ];
        for (edit, expected) in cases {
            let mut v = small();
            edit(&mut v);
            let e = Mission::from_value(&v).unwrap_err().to_string();
            assert!(
                e.starts_with(expected),
                "{e} does not start with {expected}"
            );
        }
    }
}
