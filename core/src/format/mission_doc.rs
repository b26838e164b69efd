//! `nvector-mission/1` as JSON (docs/formats.md, "Mission"): what each field
//! looks like. Every field is optional here so that the validation
//! (`slam::mission::Mission::from_doc`) can name a missing one by its path;
//! `null` is absence for an optional field and refused for a required one
//! (those read through [`present`]). Unknown fields are refused, naming
//! the field, except inside `meta`. The same types write a mission
//! (`leaf::ToJson`, `format::to_value`: the simulators, `Mission::to_value`,
//! the importers): a field absent is left out, but `final_position`, which
//! is written `null`.

use super::leaf::{Bounds, BoxIn, Finite, Integer, IntervalIn, List, Numbers, PerStep, PointsIn};
#[cfg(feature = "openapi")]
use super::openapi::mission as oa;
use super::present;
use serde::Deserialize;
use serde_json::Value;

/// A mission (`nvector-mission/1`), the input of a SLAM job.
///
/// Rules beyond the schema (core refuses each with 422 naming the JSON
/// path): boxes and points have the model's dimension; `inputs` holds
/// exactly the model's channels; every per-step array has `steps` entries;
/// intervals have lo <= hi; `detections[i].step <= steps`; `depth` only
/// for auv3d; `landmark < landmark_count`; the truth's sizes (see
/// `Truth`). Numbers are JSON numbers; integers are written without a
/// fraction or exponent.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = Mission, example = json!({
    "format": "nvector-mission/1",
    "name": "two-steps",
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
})))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct MissionDoc {
    /// `"nvector-mission/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::format, required = true))]
    pub format: Option<Value>,
    /// A name (default `"mission"`).
    pub name: Option<String>,
    /// Motion model name (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::model, required = true))]
    pub model: Option<Value>,
    /// The time step (s).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = f64, exclusive_minimum = 0, required = true)
    )]
    pub dt: Option<Finite>,
    /// N: there are N+1 positions and N input samples per channel.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = u64, minimum = 1, maximum = 2000000, required = true)
    )]
    pub steps: Option<Integer>,
    /// The box of p(0).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(schema_with = oa::initial_position, required = true)
    )]
    pub initial_position: Option<BoxIn>,
    /// The box of p(N), when known.
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::final_position))]
    pub final_position: Option<BoxIn>,
    /// odometry2d: interval of th(0). Rule: required for odometry2d, refused
    /// for the other models.
    pub initial_heading: Option<IntervalIn>,
    /// odometry2d: interval of th(N). Rule: odometry2d only.
    pub final_heading: Option<IntervalIn>,
    /// The input channels.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(value_type = InputsDoc, required = true))]
    pub inputs: Option<InputsDoc>,
    /// The bound on the per-step integration error, per axis (default 0).
    pub motion_error: Option<PerStep>,
    /// odometry2d: per-step heading error (default 0). Rule: odometry2d
    /// only.
    pub heading_error: Option<PerStep>,
    /// odometry2d: bounds on the heading drift over windows of k steps
    /// (optional): for every window and every i with i + k <= N,
    /// `|th(i+k) - th(i) - sum_{j=i}^{i+k-1} dt turn_rate(j)| <= error`.
    /// Rule: odometry2d only; `steps` >= 1 (a window longer than N
    /// constrains nothing), `error` >= 0.
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<Vec<DriftWindowDoc>>, max_items = 1000)
    )]
    pub heading_drift: Option<List<DriftWindowDoc>>,
    /// odometry2d: bounds on the position drift over windows of k steps
    /// (optional): for every window and every i with i + k <= N, the
    /// Euclidean norm `|p(i+k) - p(i) - sum_{j=i}^{i+k-1} dt speed(j)
    /// (cos th(j), sin th(j))| <= error`. Rule: odometry2d only; `steps`
    /// >= 1 (a window longer than N constrains nothing), `error` >= 0.
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<Vec<DriftWindowDoc>>, max_items = 1000)
    )]
    pub motion_drift: Option<List<DriftWindowDoc>>,
    /// Where the sensor sits in the body frame, `[forward, left]` metres
    /// (default `[0, 0]`). Rule: 2-D models only.
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<Vec<f64>>, min_items = 2, max_items = 2)
    )]
    pub sensor_offset: Option<List<Finite>>,
    /// The detections, in any order.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Vec<DetectionDoc>, max_items = 100000, required = true)
    )]
    pub detections: Option<List<DetectionDoc>>,
    /// n, the known number of landmarks (enables atmost_nvector).
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<u32>, minimum = 1, maximum = 4294967295u32)
    )]
    pub landmark_count: Option<Integer>,
    /// A box that holds every landmark.
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::landmark_region))]
    pub landmark_region: Option<BoxIn>,
    /// Distinct landmarks are at least this far apart (metres, default 0).
    #[cfg_attr(feature = "openapi", schema(value_type = Option<f64>, minimum = 0))]
    pub landmark_min_separation: Option<Finite>,
    /// At most this many detections may be false (default 0).
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<u32>, minimum = 0, maximum = 4294967295u32)
    )]
    pub max_outliers: Option<Integer>,
    /// Free-form metadata (an object, checked by the validation).
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::meta))]
    pub meta: Option<Value>,
    /// Ground truth (never read by the solver).
    pub truth: Option<TruthDoc>,
}

/// The input channels of the model, N samples each.
///
/// Rule: exactly the model's channels: `speed` and `heading` for
/// unicycle2d; `roll`, `pitch`, `yaw`, `vx`, `vy`, `vz` for auv3d.
// Read: every channel of every model (the validation refuses those of
// another model, naming them).
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = Inputs))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct InputsDoc {
    /// Speed (m/s), unicycle2d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub speed: Option<ChannelDoc>,
    /// Heading (rad), unicycle2d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub heading: Option<ChannelDoc>,
    /// Turn rate (rad/s), odometry2d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub turn_rate: Option<ChannelDoc>,
    /// Roll (rad), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub roll: Option<ChannelDoc>,
    /// Pitch (rad), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub pitch: Option<ChannelDoc>,
    /// Yaw (rad), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub yaw: Option<ChannelDoc>,
    /// Body-frame velocity x (m/s), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub vx: Option<ChannelDoc>,
    /// Body-frame velocity y (m/s), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub vy: Option<ChannelDoc>,
    /// Body-frame velocity z (m/s), auv3d.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(nullable = false))]
    pub vz: Option<ChannelDoc>,
}

impl InputsDoc {
    /// The place of the channel named `name` (`None` when not a channel
    /// name).
    pub fn slot(&mut self, name: &str) -> Option<&mut Option<ChannelDoc>> {
        Some(match name {
            "speed" => &mut self.speed,
            "heading" => &mut self.heading,
            "turn_rate" => &mut self.turn_rate,
            "roll" => &mut self.roll,
            "pitch" => &mut self.pitch,
            "yaw" => &mut self.yaw,
            "vx" => &mut self.vx,
            "vy" => &mut self.vy,
            "vz" => &mut self.vz,
            _ => return None,
        })
    }

    /// The channel named `name`, taken out (`None` when absent or not a
    /// channel name).
    pub fn take(&mut self, name: &str) -> Option<ChannelDoc> {
        self.slot(name).and_then(Option::take)
    }

    /// The inputs from named channels (a name that is no channel's is
    /// left out).
    pub fn of(channels: impl IntoIterator<Item = (&'static str, ChannelDoc)>) -> InputsDoc {
        let mut inputs = InputsDoc::default();
        for (name, ch) in channels {
            if let Some(slot) = inputs.slot(name) {
                *slot = Some(ch);
            }
        }
        inputs
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
/// validation says which fields go together; its OpenAPI schema, the two
/// shapes, is written by hand in `format::openapi`).
#[derive(Debug, Default, Deserialize)]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ChannelDoc {
    #[serde(default, deserialize_with = "present")]
    pub value: Option<Numbers>,
    #[serde(default, deserialize_with = "present")]
    pub error: Option<PerStep>,
    #[serde(default, deserialize_with = "present")]
    pub lo: Option<Bounds>,
    #[serde(default, deserialize_with = "present")]
    pub hi: Option<Bounds>,
}

impl ChannelDoc {
    /// `{"value", "error"}`: measured values within one error.
    pub fn measured(value: Vec<f64>, error: f64) -> ChannelDoc {
        ChannelDoc {
            value: Some(Numbers(value)),
            error: Some(PerStep::One(error)),
            ..ChannelDoc::default()
        }
    }

    /// `{"lo", "hi"}`: the bounds of each sample.
    pub fn bounds(lo: Vec<f64>, hi: Vec<f64>) -> ChannelDoc {
        ChannelDoc {
            lo: Some(Bounds(lo)),
            hi: Some(Bounds(hi)),
            ..ChannelDoc::default()
        }
    }
}

/// One landmark detection.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = Detection))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct DetectionDoc {
    /// The step of the robot's position p(step). Rule: `step <= steps`.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = u64, minimum = 0, maximum = 18446744073709551615u64, required = true)
    )]
    pub step: Option<Integer>,
    /// The measured range to the landmark.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::range, required = true))]
    pub range: Option<IntervalIn>,
    /// The angle of the landmark relative to the heading (unicycle2d) or
    /// the yaw (auv3d), counter-clockwise, radians.
    pub bearing: Option<IntervalIn>,
    /// A box known to hold the landmark.
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::region))]
    pub region: Option<BoxIn>,
    /// The landmark's z. Rule: auv3d only.
    pub depth: Option<IntervalIn>,
    /// The operator's matching: a 0-based landmark id. Rule: below
    /// `landmark_count` when that is given.
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<u32>, minimum = 0, maximum = 4294967295u32)
    )]
    pub landmark: Option<Integer>,
    /// The scan's index (detections of one scan see distinct landmarks).
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Option<u64>, minimum = 0, maximum = 18446744073709551615u64)
    )]
    pub scan: Option<Integer>,
}

/// One drift window of an odometry2d mission (`heading_drift`,
/// `motion_drift`): over any `steps` consecutive steps the residual
/// against the odometry is at most `error`, plus the per-step error of
/// each step above `exempt_above` when given. For `heading_drift` the
/// residual is the heading's against the integrated turn rate (radians;
/// an exempt step adds its `heading_error`); for `motion_drift` it is the
/// Euclidean norm of the position's against the displacement of speed
/// and true heading, no per-step error (metres; an exempt step adds its
/// `motion_error` × √2).
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = DriftWindow))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct DriftWindowDoc {
    /// k, the window's length in steps. Rule: >= 1.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = u64, minimum = 1, maximum = 18446744073709551615u64, required = true)
    )]
    pub steps: Option<Integer>,
    /// The bound on the residual over the window (radians for
    /// `heading_drift`, metres for `motion_drift`). Rule: >= 0.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = f64, minimum = 0, required = true)
    )]
    pub error: Option<Finite>,
    /// The steps whose per-step error (`heading_error`, `motion_error`) is
    /// above this are exempt: each adds its own (`motion_error` × √2 for
    /// `motion_drift`) to `error` instead of counting in it (default: none
    /// exempt). Rules: >= 0; at most 8 distinct values over the windows.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<f64>, minimum = 0))]
    pub exempt_above: Option<Finite>,
}

/// Ground truth of a simulated mission (scoring and drawing only).
///
/// Rules: `positions` has `steps + 1` points, `matching` one entry per
/// detection, each `null` (a false detection) or below the number of
/// `landmarks`.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[cfg_attr(feature = "openapi", schema(as = Truth))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct TruthDoc {
    /// N+1 points, `null` where unknown.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::positions, required = true))]
    pub positions: Option<PointsIn>,
    /// The true landmark positions.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(schema_with = oa::landmarks, required = true))]
    pub landmarks: Option<PointsIn>,
    /// For each detection, its true landmark, or `null` for a false one.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(value_type = Vec<Option<u32>>, required = true)
    )]
    pub matching: Option<List<Option<Integer>>>,
    /// odometry2d: N+1 headings, `null` where unknown. Rule: odometry2d
    /// only, `steps + 1` entries.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Option<f64>>>))]
    pub headings: Option<List<Option<Finite>>>,
}

#[cfg(feature = "openapi")]
impl utoipa::PartialSchema for ChannelDoc {
    fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
        super::openapi::channel()
    }
}

#[cfg(feature = "openapi")]
impl utoipa::ToSchema for ChannelDoc {
    fn name() -> std::borrow::Cow<'static, str> {
        std::borrow::Cow::Borrowed("Channel")
    }
    fn schemas(
        schemas: &mut Vec<(
            String,
            utoipa::openapi::RefOr<utoipa::openapi::schema::Schema>,
        )>,
    ) {
        super::openapi::channel_schemas(schemas);
    }
}

object_only!(MissionDoc);
to_json_fields!(MissionDoc {
    format, name, model, dt, steps, initial_position, initial_heading, final_heading, inputs,
    motion_error, heading_error, heading_drift, motion_drift, sensor_offset, detections,
    landmark_count, landmark_region, landmark_min_separation, max_outliers, meta, truth
} always { final_position });
object_only!(InputsDoc);
to_json_fields!(InputsDoc {
    speed,
    heading,
    turn_rate,
    roll,
    pitch,
    yaw,
    vx,
    vy,
    vz
});
object_only!(ChannelDoc);
to_json_fields!(ChannelDoc {
    value,
    error,
    lo,
    hi
});
object_only!(DetectionDoc);
to_json_fields!(DetectionDoc {
    step,
    range,
    bearing,
    region,
    depth,
    landmark,
    scan
});
object_only!(DriftWindowDoc);
to_json_fields!(DriftWindowDoc {
    steps,
    error,
    exempt_above
});
object_only!(TruthDoc);
to_json_fields!(TruthDoc {
    positions,
    landmarks,
    matching,
    headings
});
