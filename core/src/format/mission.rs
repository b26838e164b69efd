//! `nvector-mission/1` as JSON (docs/formats.md, "Mission"): what each field
//! looks like. Every field is optional here so that the validation
//! (`slam::mission::Mission::from_doc`) can name a missing one by its path;
//! `null` is absence for an optional field and refused for a required one
//! (those read through [`present`]). Unknown fields are refused, naming
//! the field, except inside `meta`.

use super::leaf::{BoxIn, Finite, Integer, IntervalIn, List, Numbers, PerStep, PointsIn};
use super::present;
use serde::Deserialize;
use serde_json::Value;

/// A mission document.
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct MissionDoc {
    /// `"nvector-mission/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    pub format: Option<Value>,
    /// Name (default `"mission"`).
    pub name: Option<String>,
    /// Motion model name (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    pub model: Option<Value>,
    /// Time step.
    #[serde(default, deserialize_with = "present")]
    pub dt: Option<Finite>,
    /// N.
    #[serde(default, deserialize_with = "present")]
    pub steps: Option<Integer>,
    /// Box of p(0).
    #[serde(default, deserialize_with = "present")]
    pub initial_position: Option<BoxIn>,
    /// Box of p(N).
    pub final_position: Option<BoxIn>,
    /// odometry2d: interval of th(0).
    pub initial_heading: Option<IntervalIn>,
    /// odometry2d: interval of th(N).
    pub final_heading: Option<IntervalIn>,
    /// Input channels.
    #[serde(default, deserialize_with = "present")]
    pub inputs: Option<InputsDoc>,
    /// Per-step motion error.
    pub motion_error: Option<PerStep>,
    /// odometry2d: per-step heading error.
    pub heading_error: Option<PerStep>,
    /// Where the sensor sits in the body frame (2-D models).
    pub sensor_offset: Option<List<Finite>>,
    /// Detections.
    #[serde(default, deserialize_with = "present")]
    pub detections: Option<List<DetectionDoc>>,
    /// n.
    pub landmark_count: Option<Integer>,
    /// Box of every landmark.
    pub landmark_region: Option<BoxIn>,
    /// Distinct landmarks are at least this far apart.
    pub landmark_min_separation: Option<Finite>,
    /// q.
    pub max_outliers: Option<Integer>,
    /// Free-form metadata (an object, checked by the validation).
    pub meta: Option<Value>,
    /// Ground truth.
    pub truth: Option<TruthDoc>,
}

/// The `inputs` object: every channel of every model (the validation
/// refuses those of another model, naming them).
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct InputsDoc {
    #[serde(default, deserialize_with = "present")]
    pub speed: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub heading: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub turn_rate: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub roll: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub pitch: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub yaw: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub vx: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub vy: Option<ChannelDoc>,
    #[serde(default, deserialize_with = "present")]
    pub vz: Option<ChannelDoc>,
}

impl InputsDoc {
    /// The channel named `name`, taken out (`None` when absent or not a
    /// channel name).
    pub fn take(&mut self, name: &str) -> Option<ChannelDoc> {
        match name {
            "speed" => self.speed.take(),
            "heading" => self.heading.take(),
            "turn_rate" => self.turn_rate.take(),
            "roll" => self.roll.take(),
            "pitch" => self.pitch.take(),
            "yaw" => self.yaw.take(),
            "vx" => self.vx.take(),
            "vy" => self.vy.take(),
            "vz" => self.vz.take(),
            _ => None,
        }
    }

    /// The names of the channels present, in the spec's order.
    pub fn names(&self) -> Vec<&'static str> {
        [
            ("speed", self.speed.is_some()),
            ("heading", self.heading.is_some()),
            ("turn_rate", self.turn_rate.is_some()),
            ("roll", self.roll.is_some()),
            ("pitch", self.pitch.is_some()),
            ("yaw", self.yaw.is_some()),
            ("vx", self.vx.is_some()),
            ("vy", self.vy.is_some()),
            ("vz", self.vz.is_some()),
        ]
        .into_iter()
        .filter_map(|(n, p)| p.then_some(n))
        .collect()
    }
}

/// An input channel: `{"value", "error"}` or `{"lo", "hi"}` (the
/// validation says which fields go together).
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ChannelDoc {
    #[serde(default, deserialize_with = "present")]
    pub value: Option<Numbers>,
    #[serde(default, deserialize_with = "present")]
    pub error: Option<PerStep>,
    #[serde(default, deserialize_with = "present")]
    pub lo: Option<Numbers>,
    #[serde(default, deserialize_with = "present")]
    pub hi: Option<Numbers>,
}

/// One detection.
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct DetectionDoc {
    #[serde(default, deserialize_with = "present")]
    pub step: Option<Integer>,
    #[serde(default, deserialize_with = "present")]
    pub range: Option<IntervalIn>,
    pub bearing: Option<IntervalIn>,
    pub region: Option<BoxIn>,
    pub depth: Option<IntervalIn>,
    pub landmark: Option<Integer>,
    pub scan: Option<Integer>,
}

/// The `truth` object.
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct TruthDoc {
    /// N+1 points, `null` where unknown.
    #[serde(default, deserialize_with = "present")]
    pub positions: Option<PointsIn>,
    #[serde(default, deserialize_with = "present")]
    pub landmarks: Option<PointsIn>,
    /// One landmark id (or `null`, a false detection) per detection.
    #[serde(default, deserialize_with = "present")]
    pub matching: Option<List<Option<Integer>>>,
    /// odometry2d: N+1 headings, `null` where unknown.
    pub headings: Option<List<Option<Finite>>>,
}

object_only!(MissionDoc);
object_only!(InputsDoc);
object_only!(ChannelDoc);
object_only!(DetectionDoc);
object_only!(TruthDoc);
