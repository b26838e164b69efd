//! The JSON formats of docs/formats.md as Rust types, for the OpenAPI
//! document (`openapi.rs`): the mission, the contraction request and
//! response, the SLAM result and the error body, field by field with their
//! types, bounds, required-ness and `additionalProperties: false` where the
//! parsers refuse unknown fields.
//!
//! These types describe; they do not validate. Requests are still read by
//! core's parsers (`Mission::from_value`, `ContractRequest::from_value`),
//! which also enforce what JSON Schema cannot say; each such rule is listed
//! in the description of the schema it constrains ("Rules"), and the fuzzer
//! of `make test` (scripts/fuzz/) checks both sides: a request that meets
//! the schema and the rules is accepted, one that breaks either is refused.
//!
//! Nulls: an optional field may be absent or `null`, and `null` means
//! absent (core's parsers read them so), hence `Option` fields that are
//! nullable and not required.
//!
//! The leaf shapes that serde cannot name (a bound is a number or a
//! string, an interval a number or a pair) implement [`ToSchema`] by hand
//! below.
// Documentation types: built by no code path, only described.
#![allow(dead_code)]

use serde::Deserialize;
use serde_json::Value;
use std::borrow::Cow;
use utoipa::openapi::schema::{
    ArrayBuilder, ObjectBuilder, OneOfBuilder, Ref, Schema, SchemaType, Type,
};
use utoipa::openapi::RefOr;
use utoipa::{PartialSchema, ToSchema};

/// Most steps of a mission in core (`MAX_STEPS`); a service may set less
/// (its document then says its own limit).
pub const MAX_STEPS: u64 = nvector_core::slam::mission::MAX_STEPS as u64;

fn number() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Number)
}

fn strings(values: &[&str]) -> ObjectBuilder {
    ObjectBuilder::new()
        .schema_type(Type::String)
        .enum_values(Some(values.iter().copied()))
}

fn reference(name: &str) -> Ref {
    Ref::from_schema_name(name)
}

/// Implements `ToSchema` for a leaf type from a builder expression and the
/// leaf types it references.
macro_rules! leaf {
    ($ty:ident, [$($dep:ident),*], $schema:expr) => {
        impl PartialSchema for $ty {
            fn schema() -> RefOr<Schema> {
                $schema.into()
            }
        }
        impl ToSchema for $ty {
            fn name() -> Cow<'static, str> {
                Cow::Borrowed(stringify!($ty))
            }
            #[allow(unused_variables)]
            fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
                $(
                    schemas.push(($dep::name().into(), $dep::schema()));
                    <$dep as ToSchema>::schemas(schemas);
                )*
            }
        }
    };
}

/// A bound of an input interval: a number, or `"-inf"` / `"inf"` (`"+inf"`
/// is read as `"inf"`).
#[derive(Deserialize)]
#[serde(transparent)]
pub struct Bound(pub Value);
leaf!(
    Bound,
    [],
    OneOfBuilder::new()
        .description(Some(
            "A bound: a number, or \"-inf\" / \"inf\" (\"+inf\" is read as \"inf\")."
        ))
        .item(number())
        .item(strings(&["-inf", "inf", "+inf"]))
);

/// An input interval: `[lo, hi]` or a bare number `x` = `[x, x]`.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct Interval(pub Value);
leaf!(
    Interval,
    [Bound],
    OneOfBuilder::new()
        .description(Some(
            "An interval [lo, hi], or a number x meaning [x, x]. \
             Rules: lo <= hi, and the interval holds a real number \
             ([\"inf\", \"inf\"] and [\"-inf\", \"-inf\"] are refused)."
        ))
        .item(number())
        .item(
            ArrayBuilder::new()
                .items(reference("Bound"))
                .min_items(Some(2))
                .max_items(Some(2))
        )
);

/// A range interval: as [`Interval`], with `lo >= 0`.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct RangeInterval(pub Value);
leaf!(
    RangeInterval,
    [],
    OneOfBuilder::new()
        .description(Some(
            "A range [lo, hi] with 0 <= lo <= hi (hi may be \"inf\"), or a number x >= 0 \
             meaning [x, x]. Rules: lo <= hi, and [\"inf\", \"inf\"] is refused."
        ))
        .item(number().minimum(Some(0)))
        .item(
            ArrayBuilder::new()
                .items(
                    OneOfBuilder::new()
                        .item(number().minimum(Some(0)))
                        .item(strings(&["inf", "+inf"]))
                )
                .min_items(Some(2))
                .max_items(Some(2))
        )
);

/// A box of any dimension d >= 1: one interval per axis.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct IntervalBox(pub Value);
leaf!(
    IntervalBox,
    [Interval],
    ArrayBuilder::new()
        .description(Some("A box: one interval per axis (d >= 1)."))
        .items(reference("Interval"))
        .min_items(Some(1))
);

/// A box of a mission's position space: 2 axes (`unicycle2d`) or 3
/// (`auv3d`).
#[derive(Deserialize)]
#[serde(transparent)]
pub struct PositionBox(pub Value);
leaf!(
    PositionBox,
    [Interval],
    ArrayBuilder::new()
        .description(Some(
            "A box of the model's position space. Rule: 2 intervals for unicycle2d, 3 for auv3d."
        ))
        .items(reference("Interval"))
        .min_items(Some(2))
        .max_items(Some(3))
);

/// A point of a mission's position space (truth).
#[derive(Deserialize)]
#[serde(transparent)]
pub struct Point(pub Value);
leaf!(
    Point,
    [],
    ArrayBuilder::new()
        .description(Some(
            "A point. Rule: 2 coordinates for unicycle2d, 3 for auv3d."
        ))
        .items(number())
        .min_items(Some(2))
        .max_items(Some(3))
);

/// A non-negative number, or one per step.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct PerStep(pub Value);
leaf!(
    PerStep,
    [],
    OneOfBuilder::new()
        .description(Some(
            "A number >= 0 for every step, or an array of them, one per step. \
             Rule: an array has `steps` entries."
        ))
        .item(number().minimum(Some(0)))
        .item(ArrayBuilder::new().items(number().minimum(Some(0))))
);

/// An output interval: `[lo, hi]` (bounds numbers or `"-inf"` / `"inf"`)
/// or `"empty"`.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct OutputInterval(pub Value);
leaf!(
    OutputInterval,
    [],
    OneOfBuilder::new()
        .description(Some(
            "[lo, hi] (bounds are numbers, \"-inf\" or \"inf\"), or \"empty\"."
        ))
        .item(
            ArrayBuilder::new()
                .items(
                    OneOfBuilder::new()
                        .item(number())
                        .item(strings(&["-inf", "inf"]))
                )
                .min_items(Some(2))
                .max_items(Some(2))
        )
        .item(strings(&["empty"]))
);

/// An output box: one output interval per axis, or `"empty"`.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct OutputBox(pub Value);
leaf!(
    OutputBox,
    [OutputInterval],
    OneOfBuilder::new()
        .description(Some("A box (one interval per axis), or \"empty\"."))
        .item(ArrayBuilder::new().items(reference("OutputInterval")))
        .item(strings(&["empty"]))
);

/// A diameter: a number, or `"inf"` for an unbounded box.
#[derive(Deserialize)]
#[serde(transparent)]
pub struct Diameter(pub Value);
leaf!(
    Diameter,
    [],
    OneOfBuilder::new()
        .description(Some("A number >= 0, or \"inf\" for an unbounded box."))
        .item(number())
        .item(strings(&["inf"]))
);

/// Free-form JSON object (`meta`).
#[derive(Deserialize)]
#[serde(transparent)]
pub struct FreeObject(pub Value);
leaf!(
    FreeObject,
    [],
    ObjectBuilder::new()
        .schema_type(SchemaType::from_iter([Type::Object, Type::Null]))
        .description(Some(
            "Free-form metadata, carried through untouched (null means {})."
        ))
);

/// The error body of every 4xx and 5xx answer (docs/api.md).
#[derive(serde::Serialize, ToSchema)]
#[schema(example = json!({"error": {"code": "invalid_mission", "message": "lower bound 5 is above upper bound 4", "path": "detections[3].range"}}))]
pub struct ErrorBody {
    /// What went wrong.
    pub error: ErrorDetail,
}

/// The error itself.
#[derive(serde::Serialize, ToSchema)]
pub struct ErrorDetail {
    /// A stable, machine-readable code (`invalid_json`, `invalid_mission`,
    /// `not_found`, `queue_full`, `work_limit`, ...).
    pub code: String,
    /// What is wrong, for a person.
    pub message: String,
    /// The JSON path (or query parameter) of the bad value; "" when none.
    pub path: String,
}

/// `format` of a mission.
#[derive(Deserialize, ToSchema)]
pub enum MissionFormat {
    /// Version 1.
    #[serde(rename = "nvector-mission/1")]
    V1,
}

/// The motion model.
#[derive(Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// Planar unicycle: p = (x, y), inputs `speed`, `heading`.
    Unicycle2d,
    /// 3-D AUV: p = (x, y, z), z down, inputs `roll`, `pitch`, `yaw`,
    /// `vx`, `vy`, `vz` (body frame).
    Auv3d,
}

/// An input channel given as measured values and a symmetric error bound.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ValueChannel {
    /// One measured value per step. Rule: `steps` entries.
    pub value: Vec<f64>,
    /// The error bound: a number >= 0, or one per step.
    pub error: PerStep,
}

/// An input channel given as explicit bounds.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct BoundsChannel {
    /// Lower bounds, one per step. Rules: `steps` entries, `lo[i] <= hi[i]`.
    pub lo: Vec<f64>,
    /// Upper bounds, one per step. Rule: `steps` entries.
    pub hi: Vec<f64>,
}

/// An input channel: values with an error bound, or explicit bounds.
#[derive(Deserialize, ToSchema)]
#[serde(untagged)]
pub enum Channel {
    /// `{"value": [...], "error": e}`.
    Value(ValueChannel),
    /// `{"lo": [...], "hi": [...]}`.
    Bounds(BoundsChannel),
}

/// The input channels of the model, N samples each.
///
/// Rule: exactly the model's channels: `speed` and `heading` for
/// unicycle2d; `roll`, `pitch`, `yaw`, `vx`, `vy`, `vz` for auv3d.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Inputs {
    /// Speed (m/s), unicycle2d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub speed: Option<Channel>,
    /// Heading (rad), unicycle2d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub heading: Option<Channel>,
    /// Roll (rad), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub roll: Option<Channel>,
    /// Pitch (rad), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub pitch: Option<Channel>,
    /// Yaw (rad), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub yaw: Option<Channel>,
    /// Body-frame velocity x (m/s), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub vx: Option<Channel>,
    /// Body-frame velocity y (m/s), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub vy: Option<Channel>,
    /// Body-frame velocity z (m/s), auv3d.
    #[serde(default)]
    #[schema(nullable = false)]
    pub vz: Option<Channel>,
}

/// One landmark detection.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Detection {
    /// The step of the robot's position p(step). Rule: `step <= steps`.
    #[schema(minimum = 0, maximum = 18446744073709551615u64)]
    pub step: u64,
    /// The measured range to the landmark.
    pub range: RangeInterval,
    /// The angle of the landmark relative to the heading (unicycle2d) or
    /// the yaw (auv3d), counter-clockwise, radians.
    #[serde(default)]
    pub bearing: Option<Interval>,
    /// A box known to hold the landmark.
    #[serde(default)]
    pub region: Option<PositionBox>,
    /// The landmark's z. Rule: auv3d only.
    #[serde(default)]
    pub depth: Option<Interval>,
    /// The operator's matching: a 0-based landmark id. Rule: below
    /// `landmark_count` when that is given.
    #[serde(default)]
    #[schema(minimum = 0, maximum = 4294967295u32)]
    pub landmark: Option<u32>,
}

/// Ground truth of a simulated mission (scoring and drawing only).
///
/// Rules: `positions` has `steps + 1` points, `matching` one entry per
/// detection, each `null` (a false detection) or below the number of
/// `landmarks`.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Truth {
    /// The true positions p(0..=N).
    pub positions: Vec<Point>,
    /// The true landmark positions.
    pub landmarks: Vec<Point>,
    /// For each detection, its true landmark, or `null` for a false one.
    #[schema(value_type = Vec<Option<u32>>)]
    pub matching: Vec<Option<u32>>,
}

/// A mission (`nvector-mission/1`), the input of a SLAM job.
///
/// Rules beyond the schema (core refuses each with 422 naming the JSON
/// path): boxes and points have the model's dimension; `inputs` holds
/// exactly the model's channels; every per-step array has `steps` entries;
/// intervals have lo <= hi; `detections[i].step <= steps`; `depth` only
/// for auv3d; `landmark < landmark_count`; the truth's sizes (see
/// `Truth`). Numbers are JSON numbers; integers are written without a
/// fraction or exponent.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({
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
}))]
pub struct Mission {
    /// Always `"nvector-mission/1"`.
    pub format: MissionFormat,
    /// A name (default `"mission"`).
    #[serde(default)]
    pub name: Option<String>,
    /// The motion model.
    pub model: Model,
    /// The time step (s).
    #[schema(exclusive_minimum = 0)]
    pub dt: f64,
    /// N: there are N+1 positions and N input samples per channel.
    #[schema(minimum = 1, maximum = 2000000)]
    pub steps: u64,
    /// The box of p(0).
    pub initial_position: PositionBox,
    /// The box of p(N), when known.
    #[serde(default)]
    pub final_position: Option<PositionBox>,
    /// The input channels.
    pub inputs: Inputs,
    /// The bound on the per-step integration error, per axis (default 0).
    #[serde(default)]
    pub motion_error: Option<PerStep>,
    /// The detections, in any order.
    #[schema(max_items = 100000)]
    pub detections: Vec<Detection>,
    /// n, the known number of landmarks (enables atmost_nvector).
    #[serde(default)]
    #[schema(minimum = 1, maximum = 4294967295u32)]
    pub landmark_count: Option<u32>,
    /// A box that holds every landmark.
    #[serde(default)]
    pub landmark_region: Option<PositionBox>,
    /// At most this many detections may be false (default 0).
    #[serde(default)]
    #[schema(minimum = 0, maximum = 4294967295u32)]
    pub max_outliers: Option<u32>,
    /// Free-form metadata.
    #[serde(default)]
    pub meta: Option<FreeObject>,
    /// Ground truth (never read by the solver).
    #[serde(default)]
    pub truth: Option<Truth>,
}

/// `format` of a contraction request.
#[derive(Deserialize, ToSchema)]
pub enum ContractFormat {
    /// Version 1.
    #[serde(rename = "nvector-contract/1")]
    V1,
}

/// One atmost_nvector contraction (`nvector-contract/1`).
///
/// Rules beyond the schema (422 naming the JSON path): every box has the
/// dimension of `boxes[0]`; intervals have lo <= hi; `exact` takes at most
/// 40 boxes, and answers 422 (`work_limit`) when it runs out of its work
/// budget or the request's time limit.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(example = json!({
    "format": "nvector-contract/1",
    "n": 2,
    "boxes": [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]],
    "contractor": "projection"
}))]
pub struct ContractRequest {
    /// Always `"nvector-contract/1"`.
    pub format: ContractFormat,
    /// The most distinct vectors allowed.
    #[schema(minimum = 1, maximum = 4294967295u32)]
    pub n: u32,
    /// The k boxes, all of one dimension.
    #[schema(min_items = 1, max_items = 100000)]
    pub boxes: Vec<IntervalBox>,
    /// The contractor (default `best`).
    #[serde(default)]
    #[schema(value_type = Option<nvector_core::nvector::Contractor>)]
    pub contractor: Option<String>,
}

/// Bounds on the minimum number of distinct vectors.
#[derive(ToSchema)]
pub struct MinDistinct {
    /// A proved lower bound.
    pub lower: u64,
    /// The size of a hitting set that was found.
    pub upper: u64,
}

/// Counters of a contraction.
#[derive(ToSchema)]
pub struct ContractStats {
    /// Rounds to the fixpoint.
    pub rounds: u64,
    /// Wall time (µs).
    pub elapsed_us: u64,
    /// Present (true) when the fixpoint's round cap stopped it with work
    /// pending: the boxes are sound, another contraction may shrink them.
    #[schema(nullable = false)]
    pub stopped: Option<bool>,
}

/// The status of a contraction.
#[derive(ToSchema)]
#[schema(rename_all = "lowercase")]
pub enum ContractStatus {
    /// Some box shrank.
    Contracted,
    /// Nothing changed.
    Unchanged,
    /// The constraint is unsatisfiable; every box is `"empty"`.
    Infeasible,
}

/// The answer of a contraction (`nvector-contract-result/1`).
#[derive(ToSchema)]
pub struct ContractResponse {
    /// Always `"nvector-contract-result/1"`.
    #[schema(pattern = "^nvector-contract-result/1$")]
    pub format: String,
    /// What happened.
    pub status: ContractStatus,
    /// Why it is infeasible (with `infeasible`).
    #[schema(nullable = false)]
    pub reason: Option<String>,
    /// The contracted boxes, in the request's order.
    pub boxes: Vec<OutputBox>,
    /// A partition of the box indices into groups proved equal.
    pub groups: Vec<Vec<u64>>,
    /// Bounds on the minimum number of distinct vectors.
    pub min_distinct: MinDistinct,
    /// Counters.
    pub stats: ContractStats,
}

/// The status of a SLAM result.
#[derive(ToSchema)]
#[schema(rename_all = "lowercase")]
pub enum SlamStatus {
    /// A fixpoint with no empty domain.
    Consistent,
    /// A domain became empty: the data are contradictory (`reason`).
    Infeasible,
    /// Stopped before the fixpoint (round cap or time limit); boxes sound.
    Stopped,
}

/// The options a SLAM job ran with.
#[derive(ToSchema)]
pub struct SlamOptions {
    /// The association mode.
    pub contractor: String,
    /// The round cap.
    pub max_rounds: u64,
    /// The change below which a bound counts as fixed.
    pub tolerance: f64,
}

/// Figures of a SLAM result.
#[derive(ToSchema)]
pub struct SlamMetrics {
    /// Largest trajectory box diameter.
    pub max_trajectory_diameter: Diameter,
    /// Mean trajectory box diameter.
    pub mean_trajectory_diameter: Diameter,
    /// Largest detection box diameter.
    pub max_detection_diameter: Diameter,
    /// Detections in a proved group.
    pub matched_detections: u64,
    /// Propagation rounds.
    pub rounds: u64,
    /// Contractor calls.
    pub contractions: u64,
    /// Wall time (ms).
    pub elapsed_ms: f64,
}

/// A result against the mission's truth.
#[derive(ToSchema)]
pub struct SlamScore {
    /// Every true position and landmark lies in its box.
    pub truth_inside: bool,
    /// Pairs grouped that truth says differ.
    pub matching_errors: u64,
    /// The fraction of detections in a group of size >= 2.
    pub matching_recall: f64,
}

/// The result of a SLAM job (`nvector-result/1`).
#[derive(ToSchema)]
pub struct SlamResult {
    /// Always `"nvector-result/1"`.
    #[schema(pattern = "^nvector-result/1$")]
    pub format: String,
    /// The mission's name.
    pub mission: String,
    /// What happened.
    pub status: SlamStatus,
    /// Why it is infeasible (with `infeasible`).
    #[schema(nullable = false)]
    pub reason: Option<String>,
    /// The options.
    pub options: SlamOptions,
    /// N+1 boxes of p(0..=N).
    pub trajectory: Vec<OutputBox>,
    /// One box per input detection: the detected landmark's position.
    pub detections: Vec<OutputBox>,
    /// One box per group of `matching`.
    pub landmarks: Vec<OutputBox>,
    /// Groups of detection indices proved to be one landmark.
    pub matching: Vec<Vec<u64>>,
    /// Figures.
    pub metrics: SlamMetrics,
    /// Against the truth, when the mission has one.
    #[schema(nullable = false)]
    pub score: Option<SlamScore>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// The leaf schemas serialize to what their descriptions say.
    #[test]
    fn leaf_schemas_are_unions() {
        let b = serde_json::to_value(Bound::schema()).unwrap();
        assert_eq!(b["oneOf"][0]["type"], "number");
        assert_eq!(b["oneOf"][1]["enum"], json!(["-inf", "inf", "+inf"]));
        let i = serde_json::to_value(Interval::schema()).unwrap();
        assert_eq!(i["oneOf"][1]["items"]["$ref"], "#/components/schemas/Bound");
        assert_eq!(i["oneOf"][1]["minItems"], 2);
        let mut deps = Vec::new();
        <IntervalBox as ToSchema>::schemas(&mut deps);
        let names: Vec<&str> = deps.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["Interval", "Bound"]);
    }
}
