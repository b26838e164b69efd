//! The OpenAPI schemas of the formats' leaf values (`openapi` feature
//! only; the page's wasm is built without it): what serde's derive cannot
//! say of this module's hand-written readers, written next to them. A bound
//! is a number or a string, an interval a number or a pair, a channel one
//! of two shapes, and one reader ([`BoxIn`], [`IntervalIn`]) serves fields
//! with different rules (a position box has 2 or 3 axes, a range is >= 0):
//! the types implement [`ToSchema`] for their general form, and the fields
//! with narrower rules name one of the `schema_with` functions below
//! (`#[schema(schema_with = ...)]` on the field of the format type).
//!
//! Every optional field may be absent or `null` (null means absent), hence
//! the nullable variants; every rule JSON Schema cannot state is listed in
//! the description of the schema it constrains, and the fuzzer of `make
//! test` (scripts/fuzz/) checks both the schema and those rules against
//! the service.

use super::leaf::{Bound, BoxIn, IntervalIn, PerStep};
use std::borrow::Cow;
use utoipa::openapi::schema::{
    AdditionalProperties, ArrayBuilder, KnownFormat, ObjectBuilder, OneOfBuilder, Ref, Schema,
    SchemaFormat, SchemaType, Type,
};
use utoipa::openapi::RefOr;
use utoipa::{PartialSchema, ToSchema};

fn number() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Number)
}

fn strings(values: &[&str]) -> ObjectBuilder {
    ObjectBuilder::new()
        .schema_type(Type::String)
        .enum_values(Some(values.iter().copied()))
}

fn doubles() -> ArrayBuilder {
    ArrayBuilder::new().items(number().format(Some(SchemaFormat::KnownFormat(KnownFormat::Double))))
}

/// An array of [`Bound`]s (a channel's `lo` or `hi`).
fn bound_list() -> ArrayBuilder {
    ArrayBuilder::new().items(Ref::from_schema_name("Bound"))
}

/// `{"type": "null"}`.
fn null() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Null)
}

/// `schema` or `null`, described.
pub(crate) fn nullable(schema: impl Into<RefOr<Schema>>, description: &str) -> RefOr<Schema> {
    OneOfBuilder::new()
        .item(null())
        .item(schema)
        .description(Some(description))
        .into()
}

/// A reference to the schema `name`, with the description of the field
/// that holds it.
pub fn described(name: impl Into<String>, description: &str) -> Ref {
    let mut r = Ref::from_schema_name(name);
    r.description = description.into();
    r
}

/// A format tag: the one string `tag`.
fn tag(tag: &str, description: &str) -> RefOr<Schema> {
    strings(&[tag]).description(Some(description)).into()
}

impl PartialSchema for Bound {
    fn schema() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "A bound: a number, or \"-inf\" / \"inf\" (\"+inf\" is read as \"inf\").",
            ))
            .item(number())
            .item(strings(&["-inf", "inf", "+inf"]))
            .into()
    }
}

impl ToSchema for Bound {}

impl PartialSchema for IntervalIn {
    fn schema() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "An interval [lo, hi], or a number x meaning [x, x]. \
                 Rules: lo <= hi, and the interval holds a real number \
                 ([\"inf\", \"inf\"] and [\"-inf\", \"-inf\"] are refused).",
            ))
            .item(number())
            .item(
                ArrayBuilder::new()
                    .items(Ref::from_schema_name("Bound"))
                    .min_items(Some(2))
                    .max_items(Some(2)),
            )
            .into()
    }
}

impl ToSchema for IntervalIn {
    fn name() -> Cow<'static, str> {
        Cow::Borrowed("Interval")
    }
    fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
        schemas.push((Bound::name().into(), Bound::schema()));
    }
}

impl PartialSchema for BoxIn {
    fn schema() -> RefOr<Schema> {
        ArrayBuilder::new()
            .description(Some("A box: one interval per axis (d >= 1)."))
            .items(Ref::from_schema_name(IntervalIn::name()))
            .min_items(Some(1))
            .into()
    }
}

impl ToSchema for BoxIn {
    fn name() -> Cow<'static, str> {
        Cow::Borrowed("IntervalBox")
    }
    fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
        schemas.push((IntervalIn::name().into(), IntervalIn::schema()));
        <IntervalIn as ToSchema>::schemas(schemas);
    }
}

impl PartialSchema for PerStep {
    fn schema() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "A number >= 0 for every step, or an array of them, one per step. \
                 Rule: an array has `steps` entries.",
            ))
            .item(number().minimum(Some(0)))
            .item(ArrayBuilder::new().items(number().minimum(Some(0))))
            .into()
    }
}

impl ToSchema for PerStep {}

/// The schema of `mission_doc::ChannelDoc` (named `Channel`): the channel's
/// two shapes (the validation refuses any other mix of its four fields,
/// naming them).
pub fn channel() -> RefOr<Schema> {
    let value = ObjectBuilder::new()
        .title(Some("ValueChannel"))
        .description(Some(
            "An input channel given as measured values and a symmetric error bound: \
                 `{\"value\": [...], \"error\": e}`.",
        ))
        .property(
            "value",
            doubles().description(Some("One measured value per step. Rule: `steps` entries.")),
        )
        .required("value")
        .property(
            "error",
            described(
                PerStep::name(),
                "The error bound: a number >= 0, or one per step.",
            ),
        )
        .required("error")
        .additional_properties(Some(AdditionalProperties::<Schema>::FreeForm(false)));
    let bounds = ObjectBuilder::new()
        .title(Some("BoundsChannel"))
        .description(Some(
            "An input channel given as explicit bounds: `{\"lo\": [...], \"hi\": [...]}`.",
        ))
        .property(
            "lo",
            bound_list().description(Some(
                "Lower bounds, one per step: numbers, or \"-inf\" (unbounded below). \
                 Rules: `steps` entries, `lo[i] <= hi[i]`, no `lo[i]` of \"inf\".",
            )),
        )
        .required("lo")
        .property(
            "hi",
            bound_list().description(Some(
                "Upper bounds, one per step: numbers, or \"inf\" (unbounded above). \
                 Rules: `steps` entries, no `hi[i]` of \"-inf\".",
            )),
        )
        .required("hi")
        .additional_properties(Some(AdditionalProperties::<Schema>::FreeForm(false)));
    OneOfBuilder::new()
        .description(Some(
            "An input channel: values with an error bound, or explicit bounds.",
        ))
        .item(value)
        .item(bounds)
        .into()
}

/// The schemas [`channel`] refers to.
pub fn channel_schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
    schemas.push((PerStep::name().into(), PerStep::schema()));
}

/// A box of a mission's position space.
fn position_box(description: &str) -> ArrayBuilder {
    ArrayBuilder::new()
        .description(Some(format!(
            "{description} A box of the model's position space. \
             Rule: 2 intervals for unicycle2d and odometry2d, 3 for auv3d."
        )))
        .items(Ref::from_schema_name(IntervalIn::name()))
        .min_items(Some(2))
        .max_items(Some(3))
}

/// A point of a mission's position space.
fn point() -> ArrayBuilder {
    ArrayBuilder::new()
        .description(Some(
            "A point. Rule: 2 coordinates for unicycle2d and odometry2d, 3 for auv3d.",
        ))
        .items(number())
        .min_items(Some(2))
        .max_items(Some(3))
}

/// `schema_with` functions of the mission's fields (their descriptions are
/// here: a `schema_with` field takes no doc comment).
pub mod mission {
    use super::*;

    /// `format`.
    pub fn format() -> RefOr<Schema> {
        tag("nvector-mission/1", "Always `\"nvector-mission/1\"`.")
    }

    /// `model`.
    pub fn model() -> RefOr<Schema> {
        strings(&["unicycle2d", "auv3d", "odometry2d"])
            .description(Some(
                "The motion model: unicycle2d (planar unicycle: p = (x, y), inputs \
                 `speed`, `heading`), auv3d (3-D AUV: p = (x, y, z), z down, inputs \
                 `roll`, `pitch`, `yaw`, `vx`, `vy`, `vz`, body frame) or odometry2d \
                 (p = (x, y) and an integrated heading th, inputs `speed`, `turn_rate`; \
                 `initial_heading` required).",
            ))
            .into()
    }

    /// `initial_position`.
    pub fn initial_position() -> RefOr<Schema> {
        position_box("The box of p(0).").into()
    }

    /// `final_position`.
    pub fn final_position() -> RefOr<Schema> {
        let d = "The box of p(N), when known.";
        nullable(position_box(d), d)
    }

    /// `landmark_region`.
    pub fn landmark_region() -> RefOr<Schema> {
        let d = "A box that holds every landmark.";
        nullable(position_box(d), d)
    }

    /// `detections[i].region`.
    pub fn region() -> RefOr<Schema> {
        let d = "A box known to hold the landmark.";
        nullable(position_box(d), d)
    }

    /// `detections[i].range`.
    pub fn range() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "The measured range to the landmark: [lo, hi] with 0 <= lo <= hi (hi may be \
                 \"inf\"), or a number x >= 0 meaning [x, x]. \
                 Rules: lo <= hi, and [\"inf\", \"inf\"] is refused.",
            ))
            .item(number().minimum(Some(0)))
            .item(
                ArrayBuilder::new()
                    .items(
                        OneOfBuilder::new()
                            .item(number().minimum(Some(0)))
                            .item(strings(&["inf", "+inf"])),
                    )
                    .min_items(Some(2))
                    .max_items(Some(2)),
            )
            .into()
    }

    /// `meta`.
    pub fn meta() -> RefOr<Schema> {
        ObjectBuilder::new()
            .schema_type(SchemaType::from_iter([Type::Object, Type::Null]))
            .description(Some(
                "Free-form metadata, carried through untouched (null means {}).",
            ))
            .into()
    }

    /// `truth.positions`.
    pub fn positions() -> RefOr<Schema> {
        ArrayBuilder::new()
            .description(Some(
                "The true positions p(0..=N), `null` where unknown (not scored).",
            ))
            .items(OneOfBuilder::new().item(point()).item(null()))
            .into()
    }

    /// `truth.landmarks`.
    pub fn landmarks() -> RefOr<Schema> {
        ArrayBuilder::new()
            .description(Some("The true landmark positions."))
            .items(point())
            .into()
    }
}

/// `schema_with` functions of the contraction request's fields.
pub mod contract {
    use super::*;

    /// `format`.
    pub fn format() -> RefOr<Schema> {
        tag("nvector-contract/1", "Always `\"nvector-contract/1\"`.")
    }

    /// `contractor`: core's `Contractor` schema, registered by name.
    pub fn contractor() -> RefOr<Schema> {
        nullable(
            Ref::from_schema_name("Contractor"),
            "The contractor (default `best`).",
        )
    }
}

/// The output leaf values (`json::box_to_json` and the result's views).
pub mod output {
    use super::*;

    /// An output interval: `[lo, hi]` or `"empty"`.
    pub fn interval() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "[lo, hi] (bounds are numbers, \"-inf\" or \"inf\"), or \"empty\".",
            ))
            .item(
                ArrayBuilder::new()
                    .items(
                        OneOfBuilder::new()
                            .item(number())
                            .item(strings(&["-inf", "inf"])),
                    )
                    .min_items(Some(2))
                    .max_items(Some(2)),
            )
            .item(strings(&["empty"]))
            .into()
    }

    /// An output box: one output interval per axis, or `"empty"`.
    pub fn ibox() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some("A box (one interval per axis), or \"empty\"."))
            .item(ArrayBuilder::new().items(Ref::from_schema_name("OutputInterval")))
            .item(strings(&["empty"]))
            .into()
    }

    /// An array of output boxes, described.
    pub fn boxes(description: &str) -> RefOr<Schema> {
        ArrayBuilder::new()
            .description(Some(description))
            .items(Ref::from_schema_name("OutputBox"))
            .into()
    }

    /// A diameter: a number, or `"inf"`.
    pub fn diameter() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some("A number >= 0, or \"inf\" for an unbounded box."))
            .item(number())
            .item(strings(&["inf"]))
            .into()
    }

    /// The named output schemas the others refer to.
    pub fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
        schemas.push(("OutputBox".into(), ibox()));
        schemas.push(("OutputInterval".into(), interval()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// The leaf schemas serialize to what their descriptions say, and a
    /// box brings the schemas it refers to (moved from the server's former
    /// `formats.rs`).
    #[test]
    fn leaf_schemas_are_unions() {
        let b = serde_json::to_value(Bound::schema()).unwrap();
        assert_eq!(b["oneOf"][0]["type"], "number");
        assert_eq!(b["oneOf"][1]["enum"], json!(["-inf", "inf", "+inf"]));
        let i = serde_json::to_value(IntervalIn::schema()).unwrap();
        assert_eq!(i["oneOf"][1]["items"]["$ref"], "#/components/schemas/Bound");
        assert_eq!(i["oneOf"][1]["minItems"], 2);
        let mut deps = Vec::new();
        <BoxIn as ToSchema>::schemas(&mut deps);
        let names: Vec<&str> = deps.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["Interval", "Bound"]);
        let c = serde_json::to_value(channel()).unwrap();
        assert_eq!(c["oneOf"][0]["required"], json!(["value", "error"]));
        assert_eq!(c["oneOf"][1]["required"], json!(["lo", "hi"]));
        assert_eq!(c["oneOf"][1]["additionalProperties"], false);
    }
}
