//! `nvector-tdoa/1` as JSON (docs/formats.md, "TDOA passive location"):
//! what each field looks like. As for missions every field is optional
//! here so that the validation (`tdoa::problem::TdoaProblem::from_doc`)
//! names a missing one by its path; unknown fields are refused, naming the
//! field, except inside `meta`. The same types write a problem
//! (`leaf::ToJson`: the radar scenario), absent fields left out.

use super::leaf::{BoxIn, Finite, Integer, IntervalIn, List};
use super::present;
use serde::Deserialize;
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
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
pub struct TdoaDoc {
    /// `"nvector-tdoa/1"` (any JSON, checked by the validation).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(
        feature = "openapi",
        schema(required = true, nullable = false, value_type = String, pattern = "^nvector-tdoa/1$")
    )]
    pub format: Option<Value>,
    /// Name (default `"tdoa"`).
    pub name: Option<String>,
    /// Interval of the propagation speed c (m/s).
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub propagation_speed: Option<IntervalIn>,
    /// The receivers.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<ReceiverDoc>>))]
    pub receivers: Option<List<ReceiverDoc>>,
    /// The pulses.
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<PulseDoc>>))]
    pub pulses: Option<List<PulseDoc>>,
    /// n (atmost_nvector over the pulses' positions).
    pub emitter_count: Option<Integer>,
    /// Box of every emitter.
    pub emitter_region: Option<BoxIn>,
    /// q, counted in arrivals.
    pub max_outliers: Option<Integer>,
    /// Free-form metadata (an object, checked by the validation).
    pub meta: Option<Value>,
    /// Ground truth.
    pub truth: Option<TdoaTruthDoc>,
}

/// One receiver.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ReceiverDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub position: Option<BoxIn>,
    pub clock_bias: Option<IntervalIn>,
}

/// One pulse.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct PulseDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<ArrivalDoc>>))]
    pub arrivals: Option<List<ArrivalDoc>>,
    pub altitude: Option<IntervalIn>,
    pub region: Option<BoxIn>,
    pub emitter: Option<Integer>,
    pub distance_from: Option<DistanceFromDoc>,
}

/// A distance cut: the emitter is at a distance in `range` from a point
/// in the box `point` (an altitude on a curved Earth: the Earth's centre).
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct DistanceFromDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub point: Option<BoxIn>,
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub range: Option<IntervalIn>,
}

/// One arrival.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct ArrivalDoc {
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub receiver: Option<Integer>,
    #[serde(default, deserialize_with = "present")]
    #[cfg_attr(feature = "openapi", schema(required = true, nullable = false))]
    pub time: Option<IntervalIn>,
}

/// The `truth` object.
#[derive(Debug, Default, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(remote = "Self", deny_unknown_fields, expecting = "an object")]
#[allow(missing_docs)]
pub struct TdoaTruthDoc {
    /// One point per pulse (`null` where unknown).
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Option<Vec<f64>>>>))]
    pub positions: Option<List<Option<List<Finite>>>>,
    /// One point per emitter.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Vec<f64>>>))]
    pub emitters: Option<List<List<Finite>>>,
    /// One emitter id per pulse (`null`: unknown).
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Vec<Option<u64>>>))]
    pub matching: Option<List<Option<Integer>>>,
}

object_only!(TdoaDoc);
to_json_fields!(TdoaDoc {
    format,
    name,
    propagation_speed,
    receivers,
    pulses,
    emitter_count,
    emitter_region,
    max_outliers,
    meta,
    truth
});
object_only!(ReceiverDoc);
to_json_fields!(ReceiverDoc {
    position,
    clock_bias
});
object_only!(PulseDoc);
to_json_fields!(PulseDoc {
    arrivals,
    altitude,
    region,
    emitter,
    distance_from
});
object_only!(ArrivalDoc);
to_json_fields!(ArrivalDoc { receiver, time });
object_only!(DistanceFromDoc);
to_json_fields!(DistanceFromDoc { point, range });
object_only!(TdoaTruthDoc);
to_json_fields!(TdoaTruthDoc {
    positions,
    emitters,
    matching
});
