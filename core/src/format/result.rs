//! `nvector-result/1` as JSON (docs/formats.md, "Result"): the output of a
//! SLAM job, both ways. `slam::result` writes it (streamed, through the
//! leaf writers and the `metrics`, `options` and `score` types here); the
//! figure (`figure::describe`), `nvector plot` and Python read it back
//! through [`ResultDoc`] ([`read`], [`read_value`]): the shape by serde,
//! then the rules between fields by [`ResultDoc::check`], every fault
//! named by its JSON path.
//!
//! What the writer writes, the reader takes: bounds as numbers, `"inf"`
//! or `"-inf"`; a box as `"empty"` or its axes; a diameter as a number or
//! `"inf"`. A result read and written again is the same bytes
//! (`slam::result`'s test). Unknown top-level fields are refused.

use super::leaf::{bounds_pair, List};
use crate::error::InputError;
use crate::interval::Interval;
use serde::de::{self, Deserializer, SeqAccess, Unexpected, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use serde_json::Value;
use std::fmt;

/// The `format` of a result.
pub const FORMAT: &str = "nvector-result/1";

/// A bound written: a number (one zero: `-0.0` is written `0.0`), or
/// `"inf"` / `"-inf"`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundOut(pub f64);

impl Serialize for BoundOut {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        if self.0.is_finite() {
            ser.serialize_f64(self.0 + 0.0)
        } else if self.0 > 0.0 {
            ser.serialize_str("inf")
        } else {
            ser.serialize_str("-inf")
        }
    }
}

/// A box written from its axes: an array of `[lo, hi]`, or `"empty"` when
/// an axis is empty.
pub struct BoxView<'a>(pub &'a [Interval]);

impl Serialize for BoxView<'_> {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        if self.0.iter().any(|x| x.is_empty()) {
            return ser.serialize_str("empty");
        }
        ser.collect_seq(self.0.iter().map(|x| [BoundOut(x.lo()), BoundOut(x.hi())]))
    }
}

/// An output interval: `[lo, hi]` (lo <= hi, holding a real number), or
/// `"empty"` ([`Interval::EMPTY`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalOut(pub Interval);

impl Serialize for IntervalOut {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        if self.0.is_empty() {
            return ser.serialize_str("empty");
        }
        [BoundOut(self.0.lo()), BoundOut(self.0.hi())].serialize(ser)
    }
}

/// Reads `[lo, hi]`, and `"empty"` when `empty` allows it.
struct IntervalOutVisitor {
    empty: bool,
}

impl<'de> Visitor<'de> for IntervalOutVisitor {
    type Value = Interval;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(if self.empty {
            "an interval [lo, hi] or \"empty\""
        } else {
            "an interval [lo, hi]"
        })
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Interval, E> {
        if self.empty && v == "empty" {
            Ok(Interval::EMPTY)
        } else {
            Err(E::invalid_type(Unexpected::Str(v), &self))
        }
    }
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Interval, A::Error> {
        bounds_pair(seq)
    }
}

impl<'de> Deserialize<'de> for IntervalOut {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<IntervalOut, D::Error> {
        d.deserialize_any(IntervalOutVisitor { empty: true })
            .map(IntervalOut)
    }
}

/// One axis of a non-empty box: `[lo, hi]`.
struct Axis(Interval);

impl<'de> Deserialize<'de> for Axis {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Axis, D::Error> {
        d.deserialize_any(IntervalOutVisitor { empty: false })
            .map(Axis)
    }
}

/// An output box: `"empty"`, or an array of intervals `[lo, hi]` (its
/// dimension is checked by [`ResultDoc::check`]).
#[derive(Debug, Clone, PartialEq)]
pub enum BoxOut {
    /// `"empty"`.
    Empty,
    /// The axes, each holding a real number.
    Axes(Vec<Interval>),
}

impl BoxOut {
    /// The axes (`None` for `"empty"`).
    pub fn axes(&self) -> Option<&[Interval]> {
        match self {
            BoxOut::Empty => None,
            BoxOut::Axes(a) => Some(a),
        }
    }
}

impl Serialize for BoxOut {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        match self {
            BoxOut::Empty => ser.serialize_str("empty"),
            BoxOut::Axes(a) => BoxView(a).serialize(ser),
        }
    }
}

struct BoxOutVisitor;

impl<'de> Visitor<'de> for BoxOutVisitor {
    type Value = BoxOut;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a box (an array of intervals) or \"empty\"")
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<BoxOut, E> {
        if v == "empty" {
            Ok(BoxOut::Empty)
        } else {
            Err(E::invalid_type(Unexpected::Str(v), &self))
        }
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<BoxOut, A::Error> {
        let mut axes = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4));
        while let Some(Axis(x)) = seq.next_element()? {
            axes.push(x);
        }
        Ok(BoxOut::Axes(axes))
    }
}

impl<'de> Deserialize<'de> for BoxOut {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<BoxOut, D::Error> {
        d.deserialize_any(BoxOutVisitor)
    }
}

/// A diameter: a number, or `"inf"` when unbounded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diameter(pub f64);

#[cfg(feature = "openapi")]
impl utoipa::PartialSchema for Diameter {
    fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
        super::openapi::output::diameter()
    }
}

#[cfg(feature = "openapi")]
impl utoipa::ToSchema for Diameter {}

impl Serialize for Diameter {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        if self.0.is_finite() {
            ser.serialize_f64(self.0)
        } else {
            ser.serialize_str("inf")
        }
    }
}

struct DiameterVisitor;

impl Visitor<'_> for DiameterVisitor {
    type Value = Diameter;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number >= 0 or \"inf\"")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Diameter, E> {
        if v >= 0.0 && v.is_finite() {
            Ok(Diameter(v))
        } else {
            Err(E::invalid_value(Unexpected::Float(v), &self))
        }
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Diameter, E> {
        Ok(Diameter(v as f64))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Diameter, E> {
        self.visit_f64(v as f64)
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Diameter, E> {
        if v == "inf" {
            Ok(Diameter(f64::INFINITY))
        } else {
            Err(E::invalid_type(Unexpected::Str(v), &self))
        }
    }
}

impl<'de> Deserialize<'de> for Diameter {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Diameter, D::Error> {
        d.deserialize_any(DiameterVisitor)
    }
}

/// The `format` field: the string `"nvector-result/1"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ResultFormat;

impl Serialize for ResultFormat {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        ser.serialize_str(FORMAT)
    }
}

impl<'de> Deserialize<'de> for ResultFormat {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<ResultFormat, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = ResultFormat;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "\"{FORMAT}\"")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ResultFormat, E> {
                if v == FORMAT {
                    Ok(ResultFormat)
                } else {
                    Err(E::custom(format!("expected \"{FORMAT}\", found \"{v}\"")))
                }
            }
        }
        d.deserialize_str(V)
    }
}

/// What happened to the job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// A fixpoint with no empty domain.
    Consistent,
    /// A domain became empty (`reason` says which).
    Infeasible,
    /// Before the fixpoint (round cap or time limit); the boxes are sound.
    Stopped,
}

impl Status {
    /// As written.
    pub fn name(self) -> &'static str {
        match self {
            Status::Consistent => "consistent",
            Status::Infeasible => "infeasible",
            Status::Stopped => "stopped",
        }
    }
}

/// Figures of a SLAM result.
// `metrics`, fields in sorted order (as the writer writes them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = SlamMetrics))]
#[serde(remote = "Self", expecting = "an object")]
pub struct Metrics {
    /// Contractor calls.
    pub contractions: u64,
    /// Wall time (ms).
    pub elapsed_ms: f64,
    /// With `max_outliers` > 0: the detections proved false (their boxes
    /// are empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<u64>, nullable = false))]
    pub false_detections: Option<usize>,
    /// Detections in a proved group.
    #[cfg_attr(feature = "openapi", schema(value_type = u64))]
    pub matched_detections: usize,
    /// Largest detection box diameter.
    pub max_detection_diameter: Diameter,
    /// odometry2d only: the widest heading interval.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub max_heading_width: Option<Diameter>,
    /// Largest trajectory box diameter.
    pub max_trajectory_diameter: Diameter,
    /// Mean trajectory box diameter.
    pub mean_trajectory_diameter: Diameter,
    /// With `max_outliers` > 0: the drops of `max_outliers` that nothing
    /// proved accounts for (neither detections proved false nor sets of
    /// which every reading drops one). While above 0, every detection is
    /// dropped by some reading, so `matching` is empty.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<u64>, nullable = false))]
    pub open_outliers: Option<usize>,
    /// Propagation rounds.
    #[cfg_attr(feature = "openapi", schema(value_type = u64))]
    pub rounds: u32,
}

/// The options a SLAM job ran with.
// `options`, fields in sorted order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = SlamOptions))]
#[serde(remote = "Self", expecting = "an object")]
pub struct Options {
    /// The association mode.
    pub contractor: String,
    /// The round cap.
    #[cfg_attr(feature = "openapi", schema(value_type = u64))]
    pub max_rounds: u32,
    /// The change below which a bound counts as fixed.
    pub tolerance: f64,
}

/// A result against the mission's truth.
// `score`, fields in sorted order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = SlamScore))]
#[serde(remote = "Self", expecting = "an object")]
pub struct Score {
    /// Pairs grouped that truth says differ.
    #[cfg_attr(feature = "openapi", schema(value_type = u64))]
    pub matching_errors: usize,
    /// The fraction of detections in a group of size >= 2.
    pub matching_recall: f64,
    /// Every true position and landmark lies in its box.
    pub truth_inside: bool,
}

/// A result (`nvector-result/1`) read back; fields in the order written
/// (sorted). Its OpenAPI schema is `slam::result::SlamResult`'s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct ResultDoc {
    /// One box per input detection.
    pub detections: List<BoxOut>,
    /// `"nvector-result/1"`.
    pub format: ResultFormat,
    /// odometry2d only: N+1 heading intervals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub headings: Option<List<IntervalOut>>,
    /// With the shapes contractor: one paving per entry of `landmarks`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub landmark_regions: Option<List<List<BoxOut>>>,
    /// One box per group of `matching`.
    pub landmarks: List<BoxOut>,
    /// Groups of detection indices proved to be one landmark.
    pub matching: List<List<usize>>,
    /// Figures.
    pub metrics: Metrics,
    /// The mission's name.
    pub mission: String,
    /// The options.
    pub options: Options,
    /// Why it is infeasible (with `infeasible` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Against the truth, when the mission has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub score: Option<Score>,
    /// What happened.
    pub status: Status,
    /// N+1 position boxes.
    pub trajectory: List<BoxOut>,
}

object_only!(Metrics);
object_only!(Options);
object_only!(Score);
object_only!(ResultDoc);
serialize_self!(Metrics);
serialize_self!(Options);
serialize_self!(Score);
serialize_self!(ResultDoc);

/// Reads a result from JSON text: its shape, then [`ResultDoc::check`].
pub fn read(text: &str) -> Result<ResultDoc, InputError> {
    let doc: ResultDoc = super::from_str(text)?;
    doc.check()?;
    Ok(doc)
}

/// Reads a result from a parsed JSON value (as [`read`]).
pub fn read_value(v: &Value) -> Result<ResultDoc, InputError> {
    let doc: ResultDoc = super::from_value(v)?;
    doc.check()?;
    Ok(doc)
}

/// The dimension shared by every box: 2 or 3, fixed by the first box
/// that is not empty.
struct Dim(Option<usize>);

impl Dim {
    /// Checks the boxes at `path` (`path[i]`); returns their count.
    fn boxes(&mut self, boxes: &[BoxOut], path: &str) -> Result<usize, InputError> {
        for (i, b) in boxes.iter().enumerate() {
            let Some(axes) = b.axes() else { continue };
            let n = axes.len();
            match self.0 {
                None if matches!(n, 2 | 3) => self.0 = Some(n),
                None => {
                    return Err(InputError::new(
                        format!("{path}[{i}]"),
                        format!("a box of dimension {n}, expected 2 or 3"),
                    ))
                }
                Some(d) if d != n => {
                    return Err(InputError::new(
                        format!("{path}[{i}]"),
                        format!("a box of dimension {n}, expected {d} as the boxes before it"),
                    ))
                }
                Some(_) => {}
            }
        }
        Ok(boxes.len())
    }
}

impl ResultDoc {
    /// The rules between fields, each fault named by its path: every box
    /// of one dimension (2 or 3); at least one trajectory box; one heading
    /// per trajectory box; one landmark box (and one paving) per group of
    /// `matching`; each group's members detection indices; `reason` with
    /// status `infeasible` only.
    pub fn check(&self) -> Result<(), InputError> {
        let mut dim = Dim(None);
        let steps = dim.boxes(&self.trajectory.0, "trajectory")?;
        if steps == 0 {
            return Err(InputError::new(
                "trajectory",
                "expected N+1 boxes, found none",
            ));
        }
        let detections = dim.boxes(&self.detections.0, "detections")?;
        let landmarks = dim.boxes(&self.landmarks.0, "landmarks")?;
        if self.matching.0.len() != landmarks {
            return Err(InputError::new(
                "landmarks",
                format!(
                    "{landmarks} boxes for {} groups of matching (one box per group)",
                    self.matching.0.len()
                ),
            ));
        }
        for (g, group) in self.matching.0.iter().enumerate() {
            if let Some(x) = group.0.iter().position(|&j| j >= detections) {
                return Err(InputError::new(
                    format!("matching[{g}][{x}]"),
                    format!(
                        "expected a detection index below {detections}, found {}",
                        group.0[x]
                    ),
                ));
            }
        }
        if let Some(h) = &self.headings {
            if h.0.len() != steps {
                return Err(InputError::new(
                    "headings",
                    format!(
                        "{} intervals for {steps} trajectory boxes (one per step)",
                        h.0.len()
                    ),
                ));
            }
        }
        if let Some(r) = &self.landmark_regions {
            if r.0.len() != landmarks {
                return Err(InputError::new(
                    "landmark_regions",
                    format!("{} pavings for {landmarks} landmarks", r.0.len()),
                ));
            }
            for (i, p) in r.0.iter().enumerate() {
                dim.boxes(&p.0, &format!("landmark_regions[{i}]"))?;
            }
        }
        match (self.status, &self.reason) {
            (Status::Infeasible, None) => Err(InputError::new(
                "reason",
                "missing (an infeasible result says why)",
            )),
            (Status::Consistent | Status::Stopped, Some(_)) => Err(InputError::new(
                "reason",
                format!(
                    "only with status \"infeasible\", not \"{}\"",
                    self.status.name()
                ),
            )),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A result with every optional field, as the writer writes it.
    fn good() -> Value {
        json!({
            "detections": [[[2.0, 3.0], [2.0, 3.0]], "empty", [[2.5, 3.0], [2.0, 2.5]]],
            "format": "nvector-result/1",
            "headings": [[0.0, 1.0], ["-inf", "inf"], "empty"],
            "landmark_regions": [[[[2.5, 3.0], [2.0, 2.5]], [[2.0, 2.5], [2.5, 3.0]]]],
            "landmarks": [[[2.0, 3.0], [2.0, 3.0]]],
            "matching": [[0, 2]],
            "metrics": {"contractions": 12, "elapsed_ms": 1.5, "false_detections": 1,
                "matched_detections": 2, "max_detection_diameter": 1.0,
                "max_heading_width": "inf", "max_trajectory_diameter": "inf",
                "mean_trajectory_diameter": 0.5, "open_outliers": 0, "rounds": 3},
            "mission": "m",
            "options": {"contractor": "best", "max_rounds": 10, "tolerance": 1e-9},
            "reason": "detection 1: empty",
            "score": {"matching_errors": 0, "matching_recall": 1.0, "truth_inside": true},
            "status": "infeasible",
            "trajectory": [[[0.0, 1.0], [0.0, 1.0]], [[0.0, "inf"], ["-inf", 1.0]], "empty"]
        })
    }

    /// Every field read and written again: the same text.
    #[test]
    fn a_whole_result_reads_and_writes_the_same_text() {
        let text = good().to_string();
        let doc = read(&text).unwrap();
        assert_eq!(serde_json::to_string(&doc).unwrap(), text);
        assert_eq!(doc.status, Status::Infeasible);
        assert_eq!(doc.trajectory.0[2], BoxOut::Empty);
        assert_eq!(doc.headings.as_ref().unwrap().0[2].0, Interval::EMPTY);
        assert_eq!(doc.metrics.max_trajectory_diameter.0, f64::INFINITY);
        assert_eq!(read_value(&good()), Ok(doc));
    }

    /// Each fault is refused, named by its JSON path, from the text and
    /// from the value alike.
    #[test]
    fn each_fault_is_named_by_its_path() {
        type Edit = Box<dyn Fn(&mut Value)>;
        let remove = |k: &'static str| -> Edit {
            Box::new(move |v: &mut Value| {
                v.as_object_mut().unwrap().remove(k);
            })
        };
        let cases: Vec<(Edit, &str)> = vec![
            (Box::new(|v| v["bogus"] = json!(1)), "bogus: unknown field"),
            (
                Box::new(|v| v["status"] = json!("weird")),
                "status: unknown variant",
            ),
            (
                Box::new(|v| v["trajectory"][1][0] = json!([3, 2])),
                "trajectory[1][0]: lower bound 3",
            ),
            (
                Box::new(|v| v["trajectory"][0] = json!([[0, 1], [0, 1], [0, 1]])),
                "trajectory[1]: a box of dimension 2, expected 3",
            ),
            (
                Box::new(|v| v["trajectory"][0] = json!([[0, 1]])),
                "trajectory[0]: a box of dimension 1, expected 2 or 3",
            ),
            (
                Box::new(|v| v["trajectory"][0] = json!("abc")),
                "trajectory[0]: expected a box",
            ),
            (
                Box::new(|v| v["trajectory"][0][0] = json!("empty")),
                "trajectory[0][0]: expected an interval [lo, hi]",
            ),
            (
                Box::new(|v| v["trajectory"] = json!([])),
                "trajectory: expected N+1",
            ),
            (remove("trajectory"), "missing field `trajectory`"),
            (remove("metrics"), "missing field `metrics`"),
            (remove("reason"), "reason: missing"),
            (
                Box::new(|v| v["status"] = json!("stopped")),
                "reason: only with",
            ),
            (
                Box::new(|v| v["matching"][0][1] = json!(3)),
                "matching[0][1]: expected a detection index below 3",
            ),
            (
                Box::new(|v| v["matching"][0][1] = json!(-1)),
                "matching[0][1]:",
            ),
            (
                Box::new(|v| v["headings"] = json!([[0, 1]])),
                "headings: 1 intervals for 3",
            ),
            (
                Box::new(|v| v["headings"][0] = json!([1, 0])),
                "headings[0]: lower bound 1",
            ),
            (
                Box::new(|v| v["headings"][0] = json!(1)),
                "headings[0]: expected an interval",
            ),
            (
                Box::new(|v| v["landmarks"] = json!([])),
                "landmarks: 0 boxes for 1 groups",
            ),
            (
                Box::new(|v| v["landmark_regions"] = json!([])),
                "landmark_regions: 0 pavings for 1",
            ),
            (
                Box::new(|v| v["landmark_regions"][0][1] = json!([[0, 1], [0, 1], [0, 1]])),
                "landmark_regions[0][1]: a box of dimension 3, expected 2",
            ),
            (
                Box::new(|v| v["detections"][0][1] = json!([0, "nan"])),
                "detections[0][1][1]: expected a number",
            ),
            (
                Box::new(|v| v["format"] = json!("nvector-result/2")),
                "format: expected \"nvector-result/1\"",
            ),
            (
                Box::new(|v| v["metrics"]["max_detection_diameter"] = json!(-1)),
                "metrics.max_detection_diameter:",
            ),
            (
                Box::new(|v| v["metrics"]["rounds"] = json!("x")),
                "metrics.rounds: expected u32",
            ),
            (
                Box::new(|v| v["options"] = json!([])),
                "options: expected an object",
            ),
            (
                Box::new(|v| v["score"]["truth_inside"] = json!(1)),
                "score.truth_inside: expected a boolean",
            ),
        ];
        for (edit, want) in cases {
            let mut v = good();
            edit(&mut v);
            for err in [read_value(&v), read(&v.to_string())] {
                let err = err.expect_err(want).to_string();
                assert!(err.starts_with(want), "{err} (wanted {want})");
            }
        }
    }
}
