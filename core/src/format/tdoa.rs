//! `nvector-tdoa/1` as JSON (docs/formats.md, "TDOA passive location"):
//! what each field looks like. As for missions every field is optional
//! here so that the validation (`tdoa::problem::TdoaProblem::from_doc`)
//! names a missing one by its path; unknown fields are refused, naming the
//! field, except inside `meta`.

use super::leaf::{BoxIn, Finite, Integer, IntervalIn, List};
use super::present;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// A TDOA problem document (`nvector-tdoa/1`, docs/formats.md, "TDOA
/// passive location").
///
/// Rules (beyond the schema): every box has 3 axes (x east, y north, z up,
/// metres); every interval has lo <= hi; `propagation_speed` > 0; an
/// arrival's `receiver` is below the number of receivers; a pulse's
/// `emitter` is below `emitter_count` (or the number of pulses without
/// it); `emitter_count` is in 1..=1,048,576 (2^20); `max_outliers` is at most the
/// number of arrivals; `meta` is an object; `truth.positions` and
/// `truth.matching` have one entry per pulse, every truth point 3
/// coordinates, and a matching id is below the number of truth emitters
/// (or of pulses, if more).
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct TdoaDoc {
    /// `"nvector-tdoa/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(required = true, nullable = false, value_type = String, pattern = "^nvector-tdoa/1$")
    )]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub format: Option<Value>,
    /// Name (default `"tdoa"`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Interval of the propagation speed c (m/s).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub propagation_speed: Option<IntervalIn>,
    /// The receivers.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<ReceiverDoc>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub receivers: Option<List<ReceiverDoc>>,
    /// The pulses.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<PulseDoc>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pulses: Option<List<PulseDoc>>,
    /// n (atmost_nvector over the pulses' positions).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emitter_count: Option<Integer>,
    /// Box of every emitter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emitter_region: Option<BoxIn>,
    /// q, counted in arrivals.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_outliers: Option<Integer>,
    /// Free-form metadata (an object, checked by the validation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub meta: Option<Value>,
    /// Ground truth.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub truth: Option<TdoaTruthDoc>,
}

/// One receiver.
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ReceiverDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub position: Option<BoxIn>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clock_bias: Option<IntervalIn>,
}

/// One pulse.
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct PulseDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<ArrivalDoc>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arrivals: Option<List<ArrivalDoc>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub altitude: Option<IntervalIn>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region: Option<BoxIn>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emitter: Option<Integer>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_from: Option<DistanceFromDoc>,
}

/// A distance cut: the emitter is at a distance in `range` from a point
/// in the box `point` (an altitude on a curved Earth: the Earth's centre).
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct DistanceFromDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub point: Option<BoxIn>,
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub range: Option<IntervalIn>,
}

/// One arrival.
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ArrivalDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub receiver: Option<Integer>,
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<IntervalIn>,
}

/// The `truth` object.
#[derive(Debug, Default, Deserialize, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct TdoaTruthDoc {
    /// One point per pulse (`null` where unknown).
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Option<Vec<f64>>>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub positions: Option<List<Option<List<Finite>>>>,
    /// One point per emitter.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Vec<f64>>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emitters: Option<List<List<Finite>>>,
    /// One emitter id per pulse (`null`: unknown).
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Option<u64>>>))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub matching: Option<List<Option<Integer>>>,
}

object_only!(TdoaDoc);
serialize_self!(TdoaDoc);
object_only!(ReceiverDoc);
serialize_self!(ReceiverDoc);
object_only!(PulseDoc);
serialize_self!(PulseDoc);
object_only!(ArrivalDoc);
serialize_self!(ArrivalDoc);
object_only!(DistanceFromDoc);
serialize_self!(DistanceFromDoc);
object_only!(TdoaTruthDoc);
serialize_self!(TdoaTruthDoc);
