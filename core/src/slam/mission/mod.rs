//! `nvector-mission/1`: parsing and validation (docs/formats.md,
//! "Mission"). Every invalid input gets an [`InputError`] naming the JSON
//! path of the bad value.

use crate::error::InputError;
use crate::format::leaf::{wrong_count, Finite, Integer, PointsIn};
use crate::format::mission::{
    ChannelDoc, DetectionDoc, HeadingDriftDoc, MissionDoc, MotionDriftDoc, TruthDoc,
};
use crate::format::{self, leaf::List};
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::json;
use crate::odometry::drift::{DriftWindow, MAX_EXEMPT_LEVELS};
use crate::odometry::motion_drift::MotionWindow;
use serde::{Serialize, Serializer};
use serde_json::{Map, Value};

/// Format tag of a mission.
pub const FORMAT: &str = "nvector-mission/1";
/// Most steps accepted.
pub const MAX_STEPS: usize = 2_000_000;

/// Most landmarks a simulation takes (every front end refuses more, naming
/// the option): the paper scenario's work grows with steps × landmarks.
pub const MAX_LANDMARKS: usize = 64;

/// The motion model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Planar unicycle: inputs speed, heading.
    Unicycle2d,
    /// 3-D AUV: inputs roll, pitch, yaw, vx, vy, vz (body frame).
    Auv3d,
    /// Planar robot whose heading is integrated from its odometry: inputs
    /// speed, turn_rate; the heading is a state (docs/formats.md).
    Odometry2d,
}

impl Model {
    /// Dimension of a position.
    pub fn dim(self) -> usize {
        match self {
            Model::Unicycle2d | Model::Odometry2d => 2,
            Model::Auv3d => 3,
        }
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Model::Unicycle2d => "unicycle2d",
            Model::Auv3d => "auv3d",
            Model::Odometry2d => "odometry2d",
        }
    }

    /// Input channels, in order.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Model::Unicycle2d => &["speed", "heading"],
            Model::Auv3d => &["roll", "pitch", "yaw", "vx", "vy", "vz"],
            Model::Odometry2d => &["speed", "turn_rate"],
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
    /// The sensor scan the detection came from: detections of one scan see
    /// pairwise distinct landmarks (evidence the solver may use; any u64,
    /// sizing nothing).
    pub scan: Option<u64>,
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
    /// Which entries of `positions` are known (`None`: all of them); an
    /// unknown one (JSON `null`, a motion-capture gap) holds zeros in
    /// `positions` and is not scored.
    pub positions_known: Option<Vec<bool>>,
    /// odometry2d: N+1 true headings, `None` where unknown.
    pub headings: Option<Vec<Option<f64>>>,
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
    /// odometry2d: interval of the heading th(0) (required there, refused
    /// for the other models).
    pub initial_heading: Option<Interval>,
    /// odometry2d: interval of th(N), when known.
    pub final_heading: Option<Interval>,
    /// odometry2d: per-step heading integration error bound (N entries;
    /// empty for the other models).
    pub heading_error: Vec<f64>,
    /// odometry2d: the heading drift windows (`heading_drift`:
    /// `|th(i+k) - th(i) - sum dt turn_rate| <= b + sum of the exempt
    /// steps' heading_error`), k >= 1 (possibly above N: no constraint),
    /// b >= 0, `exempt_above` >= 0 when given (at most
    /// [`MAX_EXEMPT_LEVELS`] distinct values); empty when none (always
    /// for the other models).
    pub heading_drift: Vec<DriftWindow>,
    /// odometry2d: the motion drift windows (`motion_drift`: the norm of
    /// `p(i+k) - p(i) - sum dt speed (cos th, sin th)` is at most c), k >= 1
    /// (possibly above N: no constraint), c >= 0; empty when none (always
    /// for the other models).
    pub motion_drift: Vec<MotionWindow>,
    /// Where the sensor sits in the body frame, metres forward and left of
    /// p (2-D models; `None` is `[0, 0]`).
    pub sensor_offset: Option<[f64; 2]>,
    /// Distinct landmarks are at least this far apart (metres, >= 0,
    /// default 0: no constraint).
    pub landmark_min_separation: f64,
}

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
        let k = need(steps, &path, "steps")?.at_most(u64::MAX, &steps_path)?;
        if k == 0 {
            return Err(err(
                steps_path,
                "a window must span at least 1 step, found 0",
            ));
        }
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

fn heading_drift(list: List<HeadingDriftDoc>) -> Result<Vec<DriftWindow>, InputError> {
    let fields = list
        .0
        .into_iter()
        .map(|w| (w.steps, w.error, w.exempt_above));
    drift_windows("heading_drift", fields)
}

fn motion_drift(list: List<MotionDriftDoc>) -> Result<Vec<MotionWindow>, InputError> {
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
    let step = need(d.step, path, "step")?.at_most(u64::MAX, &step_path)?;
    if step > steps as u64 {
        return Err(err(
            step_path,
            format!("step {step} is out of range 0..={steps}"),
        ));
    }
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
            let id = v.at_most(u32::MAX as u64, &lp)? as usize;
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
    /// Parses JSON text straight into typed data (the large arrays never
    /// become JSON values) and validates it; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<Mission, InputError> {
        Mission::from_doc(format::from_str(text)?)
    }

    /// Parses and validates a mission; errors name the JSON path (the same
    /// as [`Mission::from_json`] of its text).
    pub fn from_value(v: &Value) -> Result<Mission, InputError> {
        Mission::from_doc(format::from_value(v)?)
    }

    /// The mission with every detection restated as seen from p itself
    /// (`sensor_offset` folded in, then dropped): for the parts of the
    /// solver that know no offset (the shapes reasoning, the robust
    /// propagation).
    ///
    /// Math: with the sensor at `p + R(th)·o`, the landmark is
    /// `d = p + R(th)·L`, `L = o + r·(cos b, sin b)`; so `|d - p| = |L|`
    /// and the direction of `d - p` is `th + angle(L)`. For the boxes
    /// `r`, `b`: range' = `sqrt(Lx² + Ly²)` over the box L (outward
    /// rounded), bearing' = the direction arc of the box L
    /// ([`crate::odometry::angle::box_angle`]; none when L may hold the
    /// origin). Without a bearing: range' = `r + [-|o|, |o|]` (cut at 0),
    /// no bearing.
    ///
    /// Soundness: the true (r, b) are in their intervals, so the true L is
    /// in the box L, its norm in range' and its angle in bearing' + 2πZ,
    /// which is how every bearing contractor reads a bearing. O(k).
    pub fn seen_from_position(&self) -> Mission {
        self.restated_from_p()
    }

    /// [`Mission::seen_from_position`], borrowing `self` when it has no
    /// sensor offset (nothing to restate, no copy).
    pub fn seen_from_p(&self) -> std::borrow::Cow<'_, Mission> {
        if !self.sensor_offset.is_some_and(|o| o != [0.0, 0.0]) {
            return std::borrow::Cow::Borrowed(self);
        }
        std::borrow::Cow::Owned(self.restated_from_p())
    }

    /// The restatement of [`Mission::seen_from_position`] (a copy).
    fn restated_from_p(&self) -> Mission {
        let mut m = self.clone();
        let Some(o) = m.sensor_offset.take() else {
            return m;
        };
        if o == [0.0, 0.0] {
            return m;
        }
        let (ox, oy) = (Interval::point(o[0]), Interval::point(o[1]));
        let norm = (ox.sqr() + oy.sqr()).sqrt();
        let half_line = Interval::new(0.0, f64::INFINITY);
        for d in &mut m.detections {
            let r = d.range.intersect(half_line);
            match d.bearing {
                Some(b) if !r.is_empty() && !b.is_empty() => {
                    let lx = ox + r * b.cos();
                    let ly = oy + r * b.sin();
                    d.range = (lx.sqr() + ly.sqr()).sqrt();
                    d.bearing = crate::odometry::angle::box_angle(lx, ly);
                }
                _ => {
                    let widened = r + Interval::new(-norm.hi(), norm.hi());
                    d.range = if r.is_empty() {
                        r
                    } else {
                        widened.intersect(half_line)
                    };
                    d.bearing = None;
                }
            }
        }
        m
    }

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

    /// odometry2d's fields of [`Mission::to_value`]: `heading_error` and
    /// the drift windows when there are any.
    fn odometry_fields(&self, o: &mut Map<String, Value>) {
        o.insert(
            "heading_error".into(),
            serde_json::json!(self.heading_error),
        );
        for (name, windows) in [
            ("heading_drift", &self.heading_drift),
            ("motion_drift", &self.motion_drift),
        ] {
            if windows.is_empty() {
                continue;
            }
            let w: Vec<Value> = windows
                .iter()
                .map(|w| {
                    let mut o = serde_json::json!({"steps": w.steps, "error": w.error});
                    if let Some(t) = w.exempt_above {
                        o["exempt_above"] = t.into();
                    }
                    o
                })
                .collect();
            o.insert(name.into(), Value::Array(w));
        }
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
            // Bounds, not bare floats: an unbounded input is "-inf" /
            // "inf" (serde_json would write a non-finite float as null).
            let lo: Vec<Value> = ch.iter().map(|x| json::bound_to_json(x.lo())).collect();
            let hi: Vec<Value> = ch.iter().map(|x| json::bound_to_json(x.hi())).collect();
            inputs.insert((*name).into(), serde_json::json!({"lo": lo, "hi": hi}));
        }
        o.insert("inputs".into(), Value::Object(inputs));
        o.insert("motion_error".into(), serde_json::json!(self.motion_error));
        if let Some(h) = self.initial_heading {
            o.insert("initial_heading".into(), json::interval_to_json(h));
        }
        if let Some(h) = self.final_heading {
            o.insert("final_heading".into(), json::interval_to_json(h));
        }
        if self.model == Model::Odometry2d {
            self.odometry_fields(&mut o);
        }
        if let Some(s) = self.sensor_offset {
            o.insert("sensor_offset".into(), serde_json::json!(s));
        }
        if self.landmark_min_separation > 0.0 {
            o.insert(
                "landmark_min_separation".into(),
                self.landmark_min_separation.into(),
            );
        }
        let dets: Vec<Value> = self.detections.iter().map(detection_json).collect();
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
            o.insert("truth".into(), truth_json(t));
        }
        Value::Object(o)
    }
}

/// A detection in the spec's format (the optional fields when present).
fn detection_json(d: &Detection) -> Value {
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
    if let Some(scan) = d.scan {
        m.insert("scan".into(), scan.into());
    }
    Value::Object(m)
}

/// The truth in the spec's format (`null` for an unknown position).
fn truth_json(t: &Truth) -> Value {
    let positions = match &t.positions_known {
        None => serde_json::json!(t.positions),
        Some(known) => Value::Array(
            t.positions
                .iter()
                .zip(known)
                .map(|(p, &k)| if k { serde_json::json!(p) } else { Value::Null })
                .collect(),
        ),
    };
    let mut truth = serde_json::json!({"positions": positions, "landmarks": t.landmarks, "matching": t.matching});
    if let Some(h) = &t.headings {
        truth["headings"] = serde_json::json!(h);
    }
    truth
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
    let steps = need(doc.steps, "", "steps")?.at_most(MAX_STEPS as u64, "steps")? as usize;
    if steps == 0 {
        return Err(err("steps", "a mission needs at least 1 step"));
    }
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
        .map(|v| v.at_most(u32::MAX as u64, "landmark_count"))
        .transpose()?
        .map(|n| n as usize);
    if count == Some(0) {
        return Err(err("landmark_count", "landmark_count must be at least 1"));
    }
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
            let id = x.at_most(u32::MAX as u64, &p)? as usize;
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
    fn unbounded_channel_bounds_are_read_and_written_back() {
        let mut v = small();
        v["inputs"]["heading"] = json!({"lo": ["-inf", 0.1], "hi": [0.0, "inf"]});
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.inputs[1][0], Interval::new(f64::NEG_INFINITY, 0.0));
        assert_eq!(m.inputs[1][1], Interval::new(0.1, f64::INFINITY));
        let back = m.to_value();
        assert_eq!(back["inputs"]["heading"]["lo"], json!(["-inf", 0.1]));
        assert_eq!(back["inputs"]["heading"]["hi"], json!([0.0, "inf"]));
        assert_eq!(Mission::from_value(&back).unwrap(), m);
        // A value and error that overflow are written back as bounds too.
        v["inputs"]["speed"] = json!({"value": [1.0, 1e308], "error": 1e308});
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.inputs[0][1].hi(), f64::INFINITY);
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
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
                |v| v["inputs"]["heading"]["lo"] = json!(["inf", 0.1]),
                "inputs.heading.lo[0]: lower bound inf is above upper bound 0",
            ),
            (
                |v| v["inputs"]["heading"] = json!({"lo": [0, "inf"], "hi": [1, "inf"]}),
                "inputs.heading.lo[1]: a lower bound of inf holds no real number",
            ),
            (
                |v| v["inputs"]["heading"] = json!({"lo": ["-inf", 0], "hi": ["-inf", 1]}),
                "inputs.heading.hi[0]: an upper bound of -inf holds no real number",
            ),
            (
                |v| v["inputs"]["heading"]["hi"] = json!([0, "infinity"]),
                "inputs.heading.hi[1]",
            ),
            (
                |v| v["inputs"]["speed"] = json!(3),
                "inputs.speed: expected an object, found a number",
            ),
            (
                |v| v["inputs"]["speed"] = json!({"x": [1, 2]}),
                "inputs.speed.x: unknown field `x` (expected one of: value, error, lo, hi)",
            ),
            (
                |v| v["inputs"]["speed"] = json!({}),
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

    fn odometry() -> Value {
        json!({
            "format": "nvector-mission/1",
            "model": "odometry2d",
            "dt": 0.1,
            "steps": 2,
            "initial_position": [[0, 0], [0, 0]],
            "initial_heading": [-0.01, 0.01],
            "inputs": {
                "speed": {"value": [1.0, -0.5], "error": 0.05},
                "turn_rate": {"value": [0.2, 0.1], "error": 0.01}
            },
            "heading_error": [0.001, 0.002],
            "sensor_offset": [0.3, 0],
            "detections": [
                {"step": 1, "range": [2, 3], "bearing": [0.1, 0.2], "scan": 0},
                {"step": 1, "range": [4, 5], "bearing": [1.1, 1.2], "scan": 0}
            ],
            "landmark_min_separation": 1.33,
            "truth": {
                "positions": [[0, 0], null, [0.15, 0.01]],
                "landmarks": [[2.5, 0.3], [2, 4]],
                "matching": [0, 1],
                "headings": [0.0, null, 0.03]
            }
        })
    }

    /// The fields of docs/formats.md for robots without a heading sensor
    /// (issue 20): parsed into the mission, written back, and accepted by
    /// `unsupported` (the solver handles them).
    #[test]
    fn odometry2d_offset_scan_separation_and_null_truth_parse() {
        let m = Mission::from_value(&odometry()).unwrap();
        assert_eq!(m.model, Model::Odometry2d);
        assert_eq!(m.inputs.len(), 2);
        assert!(m.inputs[0][1].contains(-0.5) && m.inputs[1][0].contains(0.21));
        assert_eq!(m.initial_heading, Some(Interval::new(-0.01, 0.01)));
        assert_eq!(m.final_heading, None);
        assert_eq!(m.heading_error, vec![0.001, 0.002]);
        assert_eq!(m.sensor_offset, Some([0.3, 0.0]));
        assert_eq!(m.landmark_min_separation, 1.33);
        assert_eq!(
            m.detections.iter().map(|d| d.scan).collect::<Vec<_>>(),
            vec![Some(0), Some(0)]
        );
        let t = m.truth.as_ref().unwrap();
        assert_eq!(t.positions_known, Some(vec![true, false, true]));
        assert_eq!(&t.positions[2], &[0.15, 0.01][..]);
        assert_eq!(&t.positions[1], &[0.0, 0.0][..]);
        assert_eq!(t.headings, Some(vec![Some(0.0), None, Some(0.03)]));
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
        assert_eq!(m.to_value()["truth"]["positions"][1], Value::Null);
        assert_eq!(Mission::from_json(&odometry().to_string()).unwrap(), m);
        // heading_error absent: 0; final_heading given.
        let mut v = odometry();
        v.as_object_mut().unwrap().remove("heading_error");
        v["final_heading"] = json!(0.5);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.heading_error, vec![0.0, 0.0]);
        assert_eq!(m.final_heading, Some(Interval::point(0.5)));
        assert!(m.heading_drift.is_empty());
        assert!(m.to_value().get("heading_drift").is_none());
        // heading_drift: windows kept as given, a window longer than N
        // (even huge) included; written back.
        let mut v = odometry();
        v["heading_drift"] = json!([
            {"steps": 1, "error": 0.0},
            {"steps": 2, "error": 0.25},
            {"steps": 18446744073709551615u64, "error": 3}
        ]);
        let m = Mission::from_value(&v).unwrap();
        let plain = DriftWindow::plain;
        assert_eq!(
            m.heading_drift,
            vec![plain(1, 0.0), plain(2, 0.25), plain(u64::MAX, 3.0)]
        );
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
        assert_eq!(Mission::from_json(&v.to_string()).unwrap(), m);
        // exempt_above: kept, written back only when given; eight
        // distinct values (and repeats of them) accepted.
        let mut v = odometry();
        let mut w: Vec<Value> = (0..8)
            .map(|x| json!({"steps": 2, "error": 0.1, "exempt_above": 0.01 * x as f64}))
            .collect();
        w.push(json!({"steps": 3, "error": 0.2, "exempt_above": 0.07}));
        w.push(json!({"steps": 3, "error": 0.2, "exempt_above": null}));
        w.push(json!({"steps": 1, "error": 0.2}));
        v["heading_drift"] = Value::Array(w);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.heading_drift[1].exempt_above, Some(0.01));
        assert_eq!(m.heading_drift[8].exempt_above, Some(0.07));
        assert_eq!(m.heading_drift[9], DriftWindow::plain(3, 0.2));
        assert_eq!(m.heading_drift[10], DriftWindow::plain(1, 0.2));
        let back = m.to_value();
        assert_eq!(back["heading_drift"][3]["exempt_above"], json!(0.03));
        assert!(back["heading_drift"][10].get("exempt_above").is_none());
        assert_eq!(Mission::from_value(&back).unwrap(), m);
        // motion_drift: windows kept as given (a huge k included), written
        // back; absent: empty and not written.
        assert!(m.motion_drift.is_empty());
        assert!(back.get("motion_drift").is_none());
        let mut v = odometry();
        v["motion_drift"] = json!([
            {"steps": 3, "error": 0.0},
            {"steps": 18446744073709551615u64, "error": 0.4}
        ]);
        let m = Mission::from_value(&v).unwrap();
        let w = MotionWindow::plain;
        assert_eq!(m.motion_drift, vec![w(3, 0.0), w(u64::MAX, 0.4)]);
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
        // exempt_above: kept and written back.
        v["motion_drift"][1]["exempt_above"] = json!(0.025);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.motion_drift[1].exempt_above, Some(0.025));
        assert_eq!(
            m.to_value()["motion_drift"][1]["exempt_above"],
            json!(0.025)
        );
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
        // sensor_offset on unicycle2d: parsed.
        let mut v = small();
        v["sensor_offset"] = json!([0.2, -0.1]);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(m.sensor_offset, Some([0.2, -0.1]));
        // scan and landmark_min_separation only add evidence: accepted.
        let mut v = small();
        v["detections"][0]["scan"] = json!(7);
        v["landmark_min_separation"] = json!(2);
        let m = Mission::from_value(&v).unwrap();
        assert_eq!(
            (m.detections[0].scan, m.landmark_min_separation),
            (Some(7), 2.0)
        );
        assert_eq!(Mission::from_value(&m.to_value()).unwrap(), m);
    }

    #[test]
    fn bad_new_fields_name_their_path() {
        type Edit = fn(&mut Value);
        let odo: Vec<(Edit, &str)> = vec![
            (
                |v| {
                    v.as_object_mut().unwrap().remove("initial_heading");
                },
                "initial_heading: missing required field",
            ),
            (
                |v| v["initial_heading"] = json!([1, 0]),
                "initial_heading: lower bound 1 is above upper bound 0",
            ),
            (
                |v| v["final_heading"] = json!("north"),
                "final_heading: expected an interval [lo, hi] or a number, found a string",
            ),
            (
                |v| v["heading_error"] = json!([0.1, -0.1]),
                "heading_error[1]: the heading error must be >= 0, found -0.1",
            ),
            (
                |v| v["heading_error"] = json!([0.1]),
                "heading_error: expected 2 values (one per step), found 1",
            ),
            (
                |v| v["inputs"]["heading"] = json!({"value": [0, 0], "error": 0}),
                "inputs.heading: unknown field `heading` (expected one of: speed, turn_rate)",
            ),
            (
                |v| {
                    v["inputs"].as_object_mut().unwrap().remove("turn_rate");
                },
                "inputs.turn_rate: missing required field",
            ),
            (
                |v| v["sensor_offset"] = json!([1]),
                "sensor_offset: expected 2 numbers [forward, left], found 1",
            ),
            (
                |v| v["sensor_offset"] = json!(["a", 0]),
                "sensor_offset[0]: expected a finite number, found a string",
            ),
            (
                |v| v["detections"][1]["scan"] = json!(-1),
                "detections[1].scan: expected a non-negative integer, found -1",
            ),
            (
                |v| v["detections"][1]["scan"] = json!(0.5),
                "detections[1].scan: expected a non-negative integer, found 0.5",
            ),
            (
                |v| v["landmark_min_separation"] = json!(-1),
                "landmark_min_separation: the separation must be >= 0, found -1",
            ),
            (
                |v| v["landmark_min_separation"] = json!([1]),
                "landmark_min_separation: expected a finite number, found an array",
            ),
            (
                |v| v["truth"]["headings"] = json!([0, 0]),
                "truth.headings: expected 3 headings (steps + 1), found 2",
            ),
            (
                |v| v["truth"]["headings"][2] = json!("x"),
                "truth.headings[2]: expected a finite number, found a string",
            ),
            (
                |v| v["truth"]["positions"][1] = json!([1]),
                "truth.positions[1]: expected a point of dimension 2, found 1 coordinates",
            ),
            (
                |v| v["truth"]["landmarks"][1] = Value::Null,
                "truth.landmarks[1]: expected an array, found null",
            ),
            (
                |v| {
                    v["heading_drift"] =
                        json!([{"steps": 10, "error": 0.1}, {"steps": 0, "error": 0.1}])
                },
                "heading_drift[1].steps: a window must span at least 1 step, found 0",
            ),
            (
                |v| v["motion_drift"] = json!([{"steps": 4, "error": 0.1}, {"steps": 0, "error": 0.1}]),
                "motion_drift[1].steps: a window must span at least 1 step, found 0",
            ),
            (
                |v| v["motion_drift"] = json!([{"steps": 2, "error": -0.1}]),
                "motion_drift[0].error: the drift bound must be >= 0, found -0.1",
            ),
            (
                |v| v["motion_drift"] = json!([{"steps": 2}]),
                "motion_drift[0].error: missing",
            ),
            (
                |v| v["motion_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": -0.1}]),
                "motion_drift[0].exempt_above: the exemption threshold must be >= 0, found -0.1",
            ),
            (
                |v| v["motion_drift"] = json!([{"steps": 2, "error": 1, "t": 0.1}]),
                "motion_drift[0].t: unknown field",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": -3, "error": 0.1}]),
                "heading_drift[0].steps: expected a non-negative integer, found -3",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2.5, "error": 0.1}]),
                "heading_drift[0].steps: expected a non-negative integer, found 2.5",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2, "error": -0.1}]),
                "heading_drift[0].error: the drift bound must be >= 0, found -0.1",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2, "error": "NaN"}]),
                "heading_drift[0].error: expected a finite number, found a string",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2}]),
                "heading_drift[0].error: missing",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "k": 3}]),
                "heading_drift[0].k: unknown field",
            ),
            (
                |v| v["heading_drift"] = json!({"steps": 2, "error": 1}),
                "heading_drift: expected an array, found an object",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": -0.5}]),
                "heading_drift[0].exempt_above: the exemption threshold must be >= 0, found -0.5",
            ),
            (
                |v| v["heading_drift"] = json!([{"steps": 2, "error": 1, "exempt_above": "NaN"}]),
                "heading_drift[0].exempt_above: expected a finite number, found a string",
            ),
            (
                |v| {
                    let w: Vec<Value> = (0..9)
                        .map(|x| json!({"steps": 2, "error": 1, "exempt_above": x}))
                        .collect();
                    v["heading_drift"] = Value::Array(w);
                },
                "heading_drift[8].exempt_above: at most 8 distinct exempt_above values over the windows (one prefix array each), found a 9th: 8",
            ),
            (
                |v| v["model"] = json!("odometry3d"),
                "model: expected \"unicycle2d\", \"auv3d\" or \"odometry2d\", found \"odometry3d\"",
            ),
        ];
        let uni: Vec<(Edit, &str)> = vec![
            (
                |v| v["initial_heading"] = json!(0),
                "initial_heading: initial_heading is only for odometry2d missions",
            ),
            (
                |v| v["heading_error"] = json!(0),
                "heading_error: heading_error is only for odometry2d missions",
            ),
            (
                |v| v["heading_drift"] = json!([]),
                "heading_drift: heading_drift is only for odometry2d missions",
            ),
            (
                |v| v["motion_drift"] = json!([]),
                "motion_drift: motion_drift is only for odometry2d missions",
            ),
            (
                |v| v["truth"] = json!({"positions": [[0, 0], [1, 0], [2, 0]], "landmarks": [[1, 1]], "matching": [0], "headings": [0, 0, 0]}),
                "truth.headings: truth.headings is only for odometry2d missions",
            ),
        ];
        for (base, cases) in [(odometry(), odo), (small(), uni)] {
            for (edit, expected) in cases {
                let mut v = base.clone();
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
        // auv3d: no sensor offset.
        let mut o =
            crate::slam::simulate::SimulateOptions::new(crate::slam::simulate::Scenario::Auv, 1);
        o.steps = Some(5);
        let mut v = crate::slam::simulate::simulate(&o);
        v["sensor_offset"] = json!([0, 0]);
        let e = Mission::from_value(&v).unwrap_err().to_string();
        assert!(
            e.starts_with("sensor_offset: sensor_offset is only for the 2-D models"),
            "{e}"
        );
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
