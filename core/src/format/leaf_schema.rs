//! The OpenAPI schemas of the leaf types of [`super::leaf`] (feature
//! `openapi`, the server's document only; never in the wasm build), so
//! that the formats' real serde types derive theirs (`nvector-tdoa/1`:
//! [`super::tdoa`]). Their serde readers accept more spellings than a
//! derive could say (a bound is a number or `"inf"`, an interval a pair or
//! a bare number), hence these small hand-written schemas next to them.

use super::leaf::{Finite, Integer};
use utoipa::openapi::schema::{ObjectBuilder, Schema, Type};
use utoipa::openapi::RefOr;
use utoipa::{PartialSchema, ToSchema};

fn number() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Number)
}

// `IntervalIn` and `BoxIn`: in `openapi.rs`, with the bound and the
// narrower forms of the mission's fields.

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
