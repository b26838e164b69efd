//! The OpenAPI schemas of the leaf types of [`super::leaf`] (feature
//! `openapi`, the server's document only; never in the wasm build), so
//! that the formats' real serde types derive theirs (`nvector-tdoa/1`:
//! [`super::tdoa`]). Their serde readers accept more spellings than a
//! derive could say (a bound is a number or `"inf"`, an interval a pair or
//! a bare number), hence these small hand-written schemas next to them.

use super::leaf::{BoxIn, Finite, Integer, IntervalIn};
use std::borrow::Cow;
use utoipa::openapi::schema::{ArrayBuilder, ObjectBuilder, OneOfBuilder, Schema, Type};
use utoipa::openapi::RefOr;
use utoipa::{PartialSchema, ToSchema};

fn number() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Number)
}

/// A bound: a number or one of the infinities' spellings.
fn bound() -> OneOfBuilder {
    OneOfBuilder::new().item(number()).item(
        ObjectBuilder::new()
            .schema_type(Type::String)
            .enum_values(Some(["-inf", "inf", "+inf"])),
    )
}

impl PartialSchema for Finite {
    fn schema() -> RefOr<Schema> {
        number().description(Some("A finite number.")).into()
    }
}
impl ToSchema for Finite {}

impl PartialSchema for Integer {
    fn schema() -> RefOr<Schema> {
        ObjectBuilder::new()
            .schema_type(Type::Integer)
            .minimum(Some(0))
            .description(Some("A non-negative integer (3, 3.0 and 3e0 alike)."))
            .into()
    }
}
impl ToSchema for Integer {}

impl PartialSchema for IntervalIn {
    fn schema() -> RefOr<Schema> {
        OneOfBuilder::new()
            .description(Some(
                "An interval [lo, hi] (a bound: a number, or \"-inf\" / \"inf\"), or a \
                 number x meaning [x, x]. Rules: lo <= hi, and the interval holds a real \
                 number.",
            ))
            .item(number())
            .item(
                ArrayBuilder::new()
                    .items(bound())
                    .min_items(Some(2))
                    .max_items(Some(2)),
            )
            .into()
    }
}
impl ToSchema for IntervalIn {
    fn name() -> Cow<'static, str> {
        Cow::Borrowed("IntervalIn")
    }
}

impl PartialSchema for BoxIn {
    fn schema() -> RefOr<Schema> {
        ArrayBuilder::new()
            .items(IntervalIn::schema())
            .min_items(Some(1))
            .description(Some(
                "A box: one interval per axis. Rules: as many axes as the format asks.",
            ))
            .into()
    }
}
impl ToSchema for BoxIn {
    fn name() -> Cow<'static, str> {
        Cow::Borrowed("BoxIn")
    }
}
