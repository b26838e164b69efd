//! `nvector-mission/1`: parsing and validation (spec/formats.md,
//! "Mission"). Every invalid input gets an [`InputError`] naming the JSON
//! path of the bad value.

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::json::{self, field_path, index_path, Lean, Numbers, Rows, Shape};
use serde::de::{Deserialize, IgnoredAny, MapAccess};
use serde::{Serialize, Serializer};
use serde_json::{Map, Value};
use std::collections::{BTreeMap, BTreeSet};

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

/// Points of one dimension, stored flat (`points[i]` is the i-th point as
/// a slice): a trajectory of 10^6 points takes 16 MB, not one allocation
/// per point.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Points {
    dim: usize,
    flat: Vec<f64>,
}

impl Points {
    /// Points of dimension `dim` (>= 1) from their coordinates, point after
    /// point (`flat.len()` a multiple of `dim`).
    pub fn new(dim: usize, flat: Vec<f64>) -> Points {
        debug_assert!(dim >= 1 && flat.len().is_multiple_of(dim));
        Points { dim, flat }
    }

    /// Dimension of each point.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.flat.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.flat.is_empty()
    }

    /// The points in order, each as a slice.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.flat.chunks_exact(self.dim.max(1))
    }
}

impl std::ops::Index<usize> for Points {
    type Output = [f64];

    fn index(&self, i: usize) -> &[f64] {
        &self.flat[i * self.dim..(i + 1) * self.dim]
    }
}

impl Serialize for Points {
    /// As JSON: an array of points, each an array of numbers.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

/// Ground truth of a simulated mission: used to score and draw, never read
/// by the solver.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// N+1 true positions.
    pub positions: Points,
    /// True landmark positions.
    pub landmarks: Points,
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
    /// n, the known number of landmarks (at most u32::MAX). An input
    /// number that the mission's size does not bound: n >= k (detections)
    /// constrains nothing more than n = k, and nothing may be sized by n.
    pub landmark_count: Option<usize>,
    /// A box holding every landmark.
    pub landmark_region: Option<IntervalBox>,
    /// q: at most this many detections may be false (`max_outliers`,
    /// default 0, at most u32::MAX). Carried for the propagator; q = 0
    /// changes nothing, and q >= k (detections) is the same as q = k, which
    /// is how the propagator reads it: nothing may be sized by q itself.
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

/// The error of [`json::object`] for a value that is not an object.
fn not_object(v: &Value, path: &str) -> InputError {
    err(path, format!("expected an object, found {}", json::kind(v)))
}

/// Field `field` of `obj`, taken out, or the error of [`json::required`].
fn take<T>(obj: &mut BTreeMap<String, T>, field: &str, path: &str) -> Result<T, InputError> {
    obj.remove(field)
        .ok_or_else(|| err(field_path(path, field), "missing required field"))
}

fn wrong_count(path: &str, n: usize, found: usize) -> InputError {
    err(
        path,
        format!("expected {n} values (one per step), found {found}"),
    )
}

/// A number or an array of `n` numbers, each >= 0.
fn per_step(v: Lean<Numbers>, path: &str, n: usize, what: &str) -> Result<Vec<f64>, InputError> {
    match v {
        Lean::Parsed(Numbers(a)) => {
            if a.len() != n {
                return Err(wrong_count(path, n, a.len()));
            }
            if let Some(i) = a.iter().position(|&x| x < 0.0) {
                let x = a[i];
                return Err(err(
                    index_path(path, i),
                    format!("{what} must be >= 0, found {x}"),
                ));
            }
            Ok(a)
        }
        Lean::Other(v) => per_step_json(&v, path, n, what),
    }
}

/// [`per_step`] of a JSON value.
fn per_step_json(v: &Value, path: &str, n: usize, what: &str) -> Result<Vec<f64>, InputError> {
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
                return Err(wrong_count(path, n, a.len()));
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

/// An array of `n` numbers.
fn numbers(v: Lean<Numbers>, path: &str, n: usize) -> Result<Vec<f64>, InputError> {
    let v = match v {
        Lean::Parsed(Numbers(a)) if a.len() == n => return Ok(a),
        Lean::Parsed(Numbers(a)) => return Err(wrong_count(path, n, a.len())),
        Lean::Other(v) => v,
    };
    let a = json::array(&v, path)?;
    if a.len() != n {
        return Err(wrong_count(path, n, a.len()));
    }
    a.iter()
        .enumerate()
        .map(|(i, x)| json::number(x, &index_path(path, i)))
        .collect()
}

fn parse_channel(v: Lean<Channel>, path: &str, n: usize) -> Result<Vec<Interval>, InputError> {
    let mut obj = match v {
        Lean::Parsed(Channel(obj)) => obj,
        Lean::Other(v) => return Err(not_object(&v, path)),
    };
    if obj.contains_key("value") {
        json::check_keys(obj.keys(), &["value", "error"], path)?;
        let values = numbers(
            take(&mut obj, "value", path)?,
            &field_path(path, "value"),
            n,
        )?;
        let error = per_step(
            take(&mut obj, "error", path)?,
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
        json::check_keys(obj.keys(), &["lo", "hi"], path)?;
        let lo = numbers(take(&mut obj, "lo", path)?, &field_path(path, "lo"), n)?;
        let hi = numbers(take(&mut obj, "hi", path)?, &field_path(path, "hi"), n)?;
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

/// An array of points of dimension `dim`.
fn points(v: Lean<Rows>, path: &str, dim: usize) -> Result<Points, InputError> {
    let wrong_dim = |i: usize, found: usize| {
        err(
            index_path(path, i),
            format!("expected a point of dimension {dim}, found {found} coordinates"),
        )
    };
    let v = match v {
        Lean::Parsed(rows) if rows.count > 0 && rows.width != dim => {
            return Err(wrong_dim(0, rows.width))
        }
        Lean::Parsed(rows) => return Ok(Points::new(dim, rows.flat)),
        Lean::Other(v) => v,
    };
    let a = json::array(&v, path)?;
    let mut flat = Vec::with_capacity(a.len() * dim);
    for (i, p) in a.iter().enumerate() {
        let pp = index_path(path, i);
        let c = json::array(p, &pp)?;
        if c.len() != dim {
            return Err(wrong_dim(i, c.len()));
        }
        for (j, x) in c.iter().enumerate() {
            flat.push(json::number(x, &index_path(&pp, j))?);
        }
    }
    Ok(Points::new(dim, flat))
}

/// An input channel's object: its fields, the arrays packed.
struct Channel(BTreeMap<String, Lean<Numbers>>);

/// The `inputs` object: its channels.
struct Inputs(BTreeMap<String, Lean<Channel>>);

/// The `truth` object: its keys, and the fields it should have.
#[derive(Default)]
struct TruthFields {
    keys: BTreeSet<String>,
    positions: Option<Lean<Rows>>,
    landmarks: Option<Lean<Rows>>,
    matching: Option<Value>,
}

/// A mission document before validation: the large arrays (input
/// channels, motion errors, true positions) parsed straight into floats,
/// everything else as JSON.
#[derive(Default)]
struct Document {
    fields: Map<String, Value>,
    inputs: Option<Lean<Inputs>>,
    motion_error: Option<Lean<Numbers>>,
    truth: Option<Lean<TruthFields>>,
}

/// Reads an object's entries with `entry(map, key)` reading each value.
fn entries<'de, A: MapAccess<'de>>(
    mut map: A,
    mut entry: impl FnMut(&mut A, String) -> Result<(), A::Error>,
) -> Result<(), A::Error> {
    while let Some(key) = map.next_key::<String>()? {
        entry(&mut map, key)?;
    }
    Ok(())
}

/// Every entry of an object, by key.
fn keyed<'de, A: MapAccess<'de>, V: Deserialize<'de>>(
    map: A,
) -> Result<BTreeMap<String, V>, A::Error> {
    let mut out = BTreeMap::new();
    entries(map, |m, k| {
        out.insert(k, m.next_value()?);
        Ok(())
    })?;
    Ok(out)
}

impl Shape for Channel {
    fn from_map<'de, A: MapAccess<'de>>(map: A) -> Result<Lean<Self>, A::Error> {
        Ok(Lean::Parsed(Channel(keyed(map)?)))
    }
}

impl Shape for Inputs {
    fn from_map<'de, A: MapAccess<'de>>(map: A) -> Result<Lean<Self>, A::Error> {
        Ok(Lean::Parsed(Inputs(keyed(map)?)))
    }
}

impl Shape for TruthFields {
    fn from_map<'de, A: MapAccess<'de>>(map: A) -> Result<Lean<Self>, A::Error> {
        let mut t = TruthFields::default();
        entries(map, |m, k| {
            match k.as_str() {
                "positions" => t.positions = Some(m.next_value()?),
                "landmarks" => t.landmarks = Some(m.next_value()?),
                "matching" => t.matching = Some(m.next_value()?),
                _ => {
                    m.next_value::<IgnoredAny>()?;
                }
            }
            t.keys.insert(k);
            Ok(())
        })?;
        Ok(Lean::Parsed(t))
    }
}

impl Shape for Document {
    fn from_map<'de, A: MapAccess<'de>>(map: A) -> Result<Lean<Self>, A::Error> {
        let mut d = Document::default();
        entries(map, |m, k| {
            match k.as_str() {
                "inputs" => d.inputs = Some(m.next_value()?),
                "motion_error" => d.motion_error = Some(m.next_value()?),
                "truth" => d.truth = Some(m.next_value()?),
                _ => {
                    let v = m.next_value()?;
                    d.fields.insert(k, v);
                }
            }
            Ok(())
        })?;
        Ok(Lean::Parsed(d))
    }
}

impl Document {
    /// Every top-level key, sorted (as a JSON object's keys iterate).
    fn keys(&self) -> Vec<String> {
        let mut keys: Vec<String> = self.fields.keys().cloned().collect();
        for (k, present) in [
            ("inputs", self.inputs.is_some()),
            ("motion_error", self.motion_error.is_some()),
            ("truth", self.truth.is_some()),
        ] {
            if present {
                keys.push(k.to_string());
            }
        }
        keys.sort_unstable();
        keys
    }
}

/// A value that is absent or `null`: `None`.
fn present<T>(v: Option<Lean<T>>) -> Option<Lean<T>> {
    v.filter(|v| !matches!(v, Lean::Other(Value::Null)))
}

impl Mission {
    /// Parses JSON text straight into typed data (the large arrays never
    /// become JSON values); errors and checks are those of
    /// [`Mission::from_value`].
    pub fn from_json(text: &str) -> Result<Mission, InputError> {
        let doc: Lean<Document> =
            serde_json::from_str(text).map_err(|e| err("", format!("invalid JSON: {e}")))?;
        Mission::from_document(doc)
    }

    /// Parses and validates a mission; errors name the JSON path.
    pub fn from_value(v: &Value) -> Result<Mission, InputError> {
        let doc =
            Lean::<Document>::deserialize(v).map_err(|e| err("", format!("invalid JSON: {e}")))?;
        Mission::from_document(doc)
    }

    /// Validates a parsed document: every check of the format, in one
    /// order, whichever way it was parsed.
    fn from_document(doc: Lean<Document>) -> Result<Mission, InputError> {
        let mut doc = match doc {
            Lean::Parsed(d) => d,
            Lean::Other(v) => return Err(not_object(&v, "")),
        };
        json::check_keys(
            &doc.keys(),
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
        let obj = &doc.fields;
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
        let mut inputs_v = match doc.inputs.take() {
            None => return Err(err("inputs", "missing required field")),
            Some(Lean::Parsed(Inputs(i))) => i,
            Some(Lean::Other(v)) => return Err(not_object(&v, "inputs")),
        };
        json::check_keys(inputs_v.keys(), model.channels(), "inputs")?;
        let mut inputs = Vec::new();
        for ch in model.channels() {
            let path = field_path("inputs", ch);
            let v = inputs_v
                .remove(*ch)
                .ok_or_else(|| err(&path, "missing required field"))?;
            inputs.push(parse_channel(v, &path, steps)?);
        }
        let motion_error = match present(doc.motion_error.take()) {
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
        let truth = present(doc.truth.take())
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
    v: Lean<TruthFields>,
    dim: usize,
    steps: usize,
    detections: usize,
) -> Result<Truth, InputError> {
    let o = match v {
        Lean::Parsed(o) => o,
        Lean::Other(v) => return Err(not_object(&v, "truth")),
    };
    json::check_keys(&o.keys, &["positions", "landmarks", "matching"], "truth")?;
    let missing = |f: &str| err(field_path("truth", f), "missing required field");
    let positions = points(
        o.positions.ok_or_else(|| missing("positions"))?,
        "truth.positions",
        dim,
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
        o.landmarks.ok_or_else(|| missing("landmarks"))?,
        "truth.landmarks",
        dim,
    )?;
    let m = json::array(
        o.matching.as_ref().ok_or_else(|| missing("matching"))?,
        "truth.matching",
    )?;
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

    /// The largest values of the u32 fields are accepted as they are (the
    /// solvers read them as the detection count; tests/huge_fields.rs runs
    /// them under a memory limit).
    #[test]
    fn the_largest_u32_fields_are_accepted() {
        let mut v = small();
        v["max_outliers"] = json!(u32::MAX);
        v["landmark_count"] = json!(u32::MAX);
        v["detections"][0]["landmark"] = json!(u32::MAX - 1);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(
            (m.max_outliers, m.landmark_count, m.detections[0].landmark),
            (
                u32::MAX as usize,
                Some(u32::MAX as usize),
                Some(u32::MAX as usize - 1)
            )
        );
        assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
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
                |v| v["max_outliers"] = json!(4294967296u64),
                "max_outliers: 4294967296 is above the limit 4294967295",
            ),
            (
                |v| v["landmark_count"] = json!(4294967296u64),
                "landmark_count: 4294967296 is above the limit 4294967295",
            ),
            (
                |v| {
                    v.as_object_mut().unwrap().remove("landmark_count");
                    v["detections"][0]["landmark"] = json!(4294967296u64);
                },
                "detections[0].landmark: 4294967296 is above the limit 4294967295",
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
            let streamed = Mission::from_json(&v.to_string()).unwrap_err().to_string();
            assert_eq!(streamed, e, "parsed from text");
        }
    }

    /// The streaming parse (large arrays straight into floats) gives the
    /// errors of a parse through JSON values, also where an array is not
    /// what it should be (a non-number, ragged or long rows, objects where
    /// arrays are due), and the same mission when it is valid.
    #[test]
    fn streamed_errors_are_those_of_values() {
        type Edit = fn(&mut Value);
        fn truth(v: &mut Value, positions: Value) {
            v["truth"] = json!({"positions": positions, "landmarks": [[1, 1]], "matching": [0]});
        }
        let cases: Vec<(Edit, &str)> = vec![
            (
                |v| v["motion_error"] = json!([0.1, -1]),
                "motion_error[1]: the motion error must be >= 0, found -1",
            ),
            (
                |v| v["motion_error"] = json!([0.1, 0.2, 0.3]),
                "motion_error: expected 2 values (one per step), found 3",
            ),
            (
                |v| v["motion_error"] = json!([0.1, {"a": 1}]),
                "motion_error[1]: expected a finite number, found an object",
            ),
            (
                |v| v["inputs"]["speed"]["error"] = json!([0.1, -0.5]),
                "inputs.speed.error[1]: an error bound must be >= 0, found -0.5",
            ),
            (
                |v| v["inputs"]["speed"]["value"] = json!([1, [2]]),
                "inputs.speed.value[1]: expected a finite number, found an array",
            ),
            (
                |v| v["inputs"]["speed"]["value"] = json!({"a": 1}),
                "inputs.speed.value: expected an array, found an object",
            ),
            (
                |v| v["inputs"]["heading"]["hi"] = json!([0.0, 0.05]),
                "inputs.heading.lo[1]: lower bound 0.1 is above upper bound 0.05",
            ),
            (
                |v| v["inputs"]["speed"]["lo"] = json!([1, 2]),
                "inputs.speed.lo: unknown field `lo`",
            ),
            (
                |v| v["inputs"]["speed"] = json!(3),
                "inputs.speed: expected an object, found a number",
            ),
            (
                |v| v["inputs"]["speed"] = json!({"x": [1, 2]}),
                "inputs.speed: an input channel is",
            ),
            (
                |v| v["inputs"] = json!([]),
                "inputs: expected an object, found an array",
            ),
            (
                |v| v["inputs"] = Value::Null,
                "inputs: expected an object, found null",
            ),
            (
                |v| {
                    v.as_object_mut().unwrap().remove("inputs");
                },
                "inputs: missing required field",
            ),
            (
                |v| v["inputs"]["roll"] = json!({"value": [0, 0], "error": 0}),
                "inputs.roll: unknown field `roll`",
            ),
            (
                |v| v["truth"] = json!("x"),
                "truth: expected an object, found a string",
            ),
            (
                |v| {
                    v["truth"] =
                        json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]]})
                },
                "truth.matching: missing required field",
            ),
            (
                |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [0], "fake": 1}),
                "truth.fake: unknown field",
            ),
            (
                |v| truth(v, json!([[0, 0], [1], [2, 0]])),
                "truth.positions[1]: expected a point of dimension 2, found 1 coordinates",
            ),
            (
                |v| truth(v, json!([[0, 0, 0], [1, 0, 0], [2, 0, 0]])),
                "truth.positions[0]: expected a point of dimension 2, found 3 coordinates",
            ),
            (
                |v| truth(v, json!([[0, 0], [1, 0, 0, 0], [2, 0]])),
                "truth.positions[1]: expected a point of dimension 2, found 4 coordinates",
            ),
            (
                |v| truth(v, json!([[0, 0], ["1", 0], [2, 0]])),
                "truth.positions[1][0]: expected a finite number, found a string",
            ),
            (
                |v| truth(v, json!([[0, 0], 5, [2, 0]])),
                "truth.positions[1]: expected an array, found a number",
            ),
            (
                |v| truth(v, json!([[0, 0], [1, 0]])),
                "truth.positions: expected 3 positions (steps + 1), found 2",
            ),
            (
                |v| truth(v, json!({})),
                "truth.positions: expected an array, found an object",
            ),
            (|v| *v = json!([1, 2]), "expected an object, found an array"),
            (
                |v| *v = json!("mission"),
                "expected an object, found a string",
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
            let streamed = Mission::from_json(&v.to_string()).unwrap_err().to_string();
            assert_eq!(streamed, e, "parsed from text");
        }
        // Null is absence for optional fields.
        let mut v = small();
        v["motion_error"] = Value::Null;
        v["truth"] = Value::Null;
        assert_eq!(
            Mission::from_json(&v.to_string()).unwrap(),
            Mission::from_value(&small()).unwrap()
        );
        // Invalid JSON: serde_json's own message.
        for text in ["{", "{\"steps\": 1,}", "[1, 2] x", ""] {
            let want = serde_json::from_str::<Value>(text).unwrap_err();
            assert_eq!(
                Mission::from_json(text).unwrap_err().to_string(),
                format!("invalid JSON: {want}")
            );
        }
    }

    #[test]
    fn streamed_missions_equal_parsed_values() {
        use crate::slam::simulate::{simulate, Scenario, SimulateOptions};
        for (scenario, seed, operator, false_detections) in [
            (Scenario::Paper, 1, false, 0),
            (Scenario::Paper, 2, true, 0),
            (Scenario::Paper, 3, false, 3),
            (Scenario::Auv, 4, true, 0),
        ] {
            let mut o = SimulateOptions::new(scenario, seed);
            o.steps = Some(800);
            o.operator = operator;
            o.false_detections = false_detections;
            let v = simulate(&o);
            let m = Mission::from_value(&v).unwrap();
            assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
            assert_eq!(m.truth.as_ref().unwrap().positions.len(), 801);
            // Through its own JSON again (inputs as lo/hi arrays).
            assert_eq!(Mission::from_json(&m.to_value().to_string()).unwrap(), m);
        }
    }
}
