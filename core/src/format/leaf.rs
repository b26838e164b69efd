//! The leaf values of the formats (docs/formats.md, "Numbers, intervals,
//! boxes"): finite numbers, non-negative integers, bounds, intervals,
//! boxes, per-step numbers and arrays of points, each read straight from
//! the JSON (the large arrays of a 10^6-step mission never become JSON
//! values) with the project's messages.

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use serde::de::{self, Deserialize, Deserializer, IgnoredAny, SeqAccess, Unexpected, Visitor};
use serde_json::Value;
use std::fmt;
use std::marker::PhantomData;

/// Capacity to reserve for a sequence: its size hint, capped so that no
/// input number sizes an allocation (the text's own length bounds it).
fn capacity(hint: Option<usize>) -> usize {
    hint.unwrap_or(0).min(1 << 20)
}

/// A JSON number as text, as serde_json writes it (`-3.0`, `1.5`).
fn number_text(x: f64) -> String {
    serde_json::Number::from_f64(x).map_or_else(|| x.to_string(), |n| n.to_string())
}

/// A finite JSON number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Finite(pub f64);

struct FiniteVisitor;

impl Visitor<'_> for FiniteVisitor {
    type Value = Finite;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Finite, E> {
        if v.is_finite() {
            Ok(Finite(v))
        } else {
            Err(E::custom("expected a finite number"))
        }
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Finite, E> {
        Ok(Finite(v as f64))
    }
}

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Finite, D::Error> {
        d.deserialize_any(FiniteVisitor)
    }
}

/// An integer field's value as read: a non-negative integer, however
/// written (`3`, `3.0`, `3e0`: JSON Schema's `integer`, which the OpenAPI
/// document states), or anything else kept as what it is. Every rule of
/// the field (its type, its least and its largest value) is checked by
/// the validation in one place ([`Integer::in_range`]), so that one rule
/// gives one message: `landmark_count` -3, 0, 1.5 and `"x"` are all
/// "expected an integer from 1 to 4294967295".
#[derive(Debug, Clone, PartialEq)]
pub enum Integer {
    /// A whole number below 2^64.
    Value(u64),
    /// A whole float at or above 2^64 (above every limit).
    Huge(f64),
    /// Not a non-negative integer: what was found (`-3`, `1.5`, `a
    /// string`), for the message.
    Invalid(String),
}

impl Integer {
    /// The value when it is an integer in `min..=max`, else the field's
    /// one message at `path`: `expected an integer from MIN to MAX, found
    /// X`.
    pub fn in_range(&self, min: u64, max: u64, path: &str) -> Result<u64, InputError> {
        let found = match self {
            Integer::Value(x) if (min..=max).contains(x) => return Ok(*x),
            Integer::Value(x) => x.to_string(),
            Integer::Huge(x) => number_text(*x),
            Integer::Invalid(what) => what.clone(),
        };
        Err(InputError::new(
            path,
            format!("expected an integer from {min} to {max}, found {found}"),
        ))
    }

    /// [`Integer::in_range`] from 0.
    pub fn at_most(&self, max: u64, path: &str) -> Result<u64, InputError> {
        self.in_range(0, max, path)
    }
}

struct IntegerVisitor;

impl<'de> Visitor<'de> for IntegerVisitor {
    type Value = Integer;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an integer")
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Integer, E> {
        Ok(Integer::Value(v))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Integer, E> {
        Ok(u64::try_from(v).map_or_else(|_| Integer::Invalid(v.to_string()), Integer::Value))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Integer, E> {
        /// 2^64: whole floats below it convert to u64 exactly.
        const TWO_TO_64: f64 = 18_446_744_073_709_551_616.0;
        Ok(if v.is_finite() && v.fract() == 0.0 && v >= 0.0 {
            if v < TWO_TO_64 {
                Integer::Value(v as u64)
            } else {
                Integer::Huge(v)
            }
        } else {
            Integer::Invalid(number_text(v))
        })
    }
    fn visit_str<E: de::Error>(self, _: &str) -> Result<Integer, E> {
        Ok(Integer::Invalid("a string".into()))
    }
    fn visit_bool<E: de::Error>(self, _: bool) -> Result<Integer, E> {
        Ok(Integer::Invalid("a boolean".into()))
    }
    fn visit_unit<E: de::Error>(self) -> Result<Integer, E> {
        Ok(Integer::Invalid("null".into()))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Integer, A::Error> {
        while seq.next_element::<IgnoredAny>()?.is_some() {}
        Ok(Integer::Invalid("an array".into()))
    }
    fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<Integer, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(Integer::Invalid("an object".into()))
    }
}

impl<'de> Deserialize<'de> for Integer {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Integer, D::Error> {
        d.deserialize_any(IntegerVisitor)
    }
}

/// A bound: a number or `"-inf"` / `"inf"` (`"+inf"`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound(pub f64);

struct BoundVisitor;

impl Visitor<'_> for BoundVisitor {
    type Value = Bound;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number, \"-inf\" or \"inf\"")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Bound, E> {
        if v.is_finite() {
            Ok(Bound(v))
        } else {
            Err(E::custom("number out of range"))
        }
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Bound, E> {
        Ok(Bound(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Bound, E> {
        Ok(Bound(v as f64))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Bound, E> {
        match v {
            "inf" | "+inf" => Ok(Bound(f64::INFINITY)),
            "-inf" => Ok(Bound(f64::NEG_INFINITY)),
            _ => Err(E::invalid_type(Unexpected::Str(v), &self)),
        }
    }
}

impl<'de> Deserialize<'de> for Bound {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Bound, D::Error> {
        d.deserialize_any(BoundVisitor)
    }
}

fn fmt_bound(x: f64) -> String {
    if x == f64::INFINITY {
        "inf".into()
    } else if x == f64::NEG_INFINITY {
        "-inf".into()
    } else {
        format!("{x}")
    }
}

/// An input interval: `[lo, hi]` with `lo <= hi` holding a real number, or
/// a bare number `x` (= `[x, x]`); `"empty"` is refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalIn(pub Interval);

struct IntervalVisitor;

impl<'de> Visitor<'de> for IntervalVisitor {
    type Value = IntervalIn;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an interval [lo, hi] or a number")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<IntervalIn, E> {
        FiniteVisitor
            .visit_f64(v)
            .map(|x| IntervalIn(Interval::point(x.0)))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<IntervalIn, E> {
        Ok(IntervalIn(Interval::point(v as f64)))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<IntervalIn, E> {
        Ok(IntervalIn(Interval::point(v as f64)))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<IntervalIn, E> {
        if v == "empty" {
            Err(E::custom("an input interval may not be empty"))
        } else {
            Err(E::invalid_type(Unexpected::Str(v), &self))
        }
    }
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<IntervalIn, A::Error> {
        bounds_pair(seq).map(IntervalIn)
    }
}

/// The elements of `[lo, hi]`: two bounds, lo <= hi, holding a real
/// number (the input intervals' and the result's).
pub(super) fn bounds_pair<'de, A: SeqAccess<'de>>(mut seq: A) -> Result<Interval, A::Error> {
    let lo = seq.next_element::<Bound>()?;
    let hi = match lo {
        Some(_) => seq.next_element::<Bound>()?,
        None => None,
    };
    let mut count = usize::from(lo.is_some()) + usize::from(hi.is_some());
    if hi.is_some() {
        while seq.next_element::<IgnoredAny>()?.is_some() {
            count += 1;
        }
    }
    let (Some(Bound(lo)), Some(Bound(hi)), 2) = (lo, hi, count) else {
        return Err(de::Error::custom(format!(
            "an interval is [lo, hi]: expected 2 bounds, found {count}"
        )));
    };
    if lo > hi {
        return Err(de::Error::custom(format!(
            "lower bound {} is above upper bound {}",
            fmt_bound(lo),
            fmt_bound(hi)
        )));
    }
    let x = Interval::new(lo, hi);
    if x.is_empty() {
        return Err(de::Error::custom("an interval must hold a real number"));
    }
    Ok(x)
}

impl<'de> Deserialize<'de> for IntervalIn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<IntervalIn, D::Error> {
        d.deserialize_any(IntervalVisitor)
    }
}

/// An input box: an array of input intervals (`"empty"` refused); its
/// dimension is checked by the validation ([`BoxIn::dim`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BoxIn(pub Vec<Interval>);

impl BoxIn {
    /// The box, of dimension `dim` (any dimension >= 1 when `None`), or an
    /// error at `path`.
    pub fn dim(&self, path: &str, dim: Option<usize>) -> Result<IntervalBox, InputError> {
        match dim {
            Some(d) if self.0.len() != d => Err(InputError::new(
                path,
                format!(
                    "expected a box of dimension {d}, found {} axes",
                    self.0.len()
                ),
            )),
            None if self.0.is_empty() => {
                Err(InputError::new(path, "a box needs at least one axis"))
            }
            _ => Ok(IntervalBox::new(&self.0)),
        }
    }
}

struct BoxVisitor;

impl<'de> Visitor<'de> for BoxVisitor {
    type Value = BoxIn;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a box (an array of intervals)")
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<BoxIn, E> {
        if v == "empty" {
            Err(E::custom("an input box may not be empty"))
        } else {
            Err(E::invalid_type(Unexpected::Str(v), &self))
        }
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<BoxIn, A::Error> {
        let mut axes = Vec::with_capacity(capacity(seq.size_hint()).min(16));
        while let Some(IntervalIn(x)) = seq.next_element()? {
            axes.push(x);
        }
        Ok(BoxIn(axes))
    }
}

impl<'de> Deserialize<'de> for BoxIn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<BoxIn, D::Error> {
        d.deserialize_any(BoxVisitor)
    }
}

/// A JSON array read as `Vec<T>` (serde's own says "a sequence").
#[derive(Debug, Clone, PartialEq)]
pub struct List<T>(pub Vec<T>);

struct ListVisitor<T>(PhantomData<T>);

impl<'de, T: Deserialize<'de>> Visitor<'de> for ListVisitor<T> {
    type Value = List<T>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<List<T>, A::Error> {
        let mut out = Vec::with_capacity(capacity(seq.size_hint()));
        while let Some(x) = seq.next_element()? {
            out.push(x);
        }
        Ok(List(out))
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for List<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<List<T>, D::Error> {
        d.deserialize_seq(ListVisitor(PhantomData))
    }
}

impl<T: serde::Serialize> serde::Serialize for List<T> {
    fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(ser)
    }
}

/// An array of finite numbers, packed as floats.
#[derive(Debug, Clone, PartialEq)]
pub struct Numbers(pub Vec<f64>);

impl<'de> Deserialize<'de> for Numbers {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Numbers, D::Error> {
        let List(v) = List::<Finite>::deserialize(d)?;
        Ok(Numbers(v.into_iter().map(|x| x.0).collect()))
    }
}

/// An array of bounds (numbers, `"-inf"`, `"inf"`), packed as floats: the
/// `lo` and `hi` of an input channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds(pub Vec<f64>);

impl<'de> Deserialize<'de> for Bounds {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Bounds, D::Error> {
        let List(v) = List::<Bound>::deserialize(d)?;
        Ok(Bounds(v.into_iter().map(|x| x.0).collect()))
    }
}

/// A number, or an array of numbers (one per step).
#[derive(Debug, Clone, PartialEq)]
pub enum PerStep {
    /// One number for every step.
    One(f64),
    /// One number per step.
    Each(Vec<f64>),
}

impl PerStep {
    /// `n` numbers, each >= 0 (`what` names them in the error), or an
    /// error at `path` (or at the offending entry).
    pub fn non_negative(self, path: &str, n: usize, what: &str) -> Result<Vec<f64>, InputError> {
        let negative =
            |x: f64, p: String| InputError::new(p, format!("{what} must be >= 0, found {x}"));
        match self {
            PerStep::One(x) if x < 0.0 => Err(negative(x, path.to_string())),
            PerStep::One(x) => Ok(vec![x; n]),
            PerStep::Each(a) => {
                if a.len() != n {
                    return Err(wrong_count(path, n, a.len()));
                }
                match a.iter().position(|&x| x < 0.0) {
                    Some(i) => Err(negative(a[i], format!("{path}[{i}]"))),
                    None => Ok(a),
                }
            }
        }
    }
}

/// "expected n values (one per step), found m".
pub fn wrong_count(path: &str, n: usize, found: usize) -> InputError {
    InputError::new(
        path,
        format!("expected {n} values (one per step), found {found}"),
    )
}

struct PerStepVisitor;

impl<'de> Visitor<'de> for PerStepVisitor {
    type Value = PerStep;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a finite number or an array of numbers")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<PerStep, E> {
        FiniteVisitor.visit_f64(v).map(|x| PerStep::One(x.0))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<PerStep, E> {
        Ok(PerStep::One(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<PerStep, E> {
        Ok(PerStep::One(v as f64))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<PerStep, A::Error> {
        let List(v) = ListVisitor::<Finite>(PhantomData).visit_seq(seq)?;
        Ok(PerStep::Each(v.into_iter().map(|x| x.0).collect()))
    }
}

impl<'de> Deserialize<'de> for PerStep {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<PerStep, D::Error> {
        d.deserialize_any(PerStepVisitor)
    }
}

/// A point as read: its first three coordinates and how many it has (the
/// validation checks the count against the model's dimension).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// The first coordinates (up to 3).
    pub x: [f64; 3],
    /// How many coordinates the point has.
    pub len: usize,
}

struct RowVisitor;

impl<'de> Visitor<'de> for RowVisitor {
    type Value = Row;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Row, A::Error> {
        let mut row = Row {
            x: [0.0; 3],
            len: 0,
        };
        while let Some(Finite(x)) = seq.next_element()? {
            if row.len < 3 {
                row.x[row.len] = x;
            }
            row.len += 1;
        }
        Ok(row)
    }
}

impl<'de> Deserialize<'de> for Row {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Row, D::Error> {
        d.deserialize_seq(RowVisitor)
    }
}

/// An array of points, packed: the coordinates of every point given, in
/// order, with the first point's length as the width (a point of another
/// length is kept as the first mismatch, for the validation to name);
/// `null` entries (unknown points) are listed by index and take no room.
/// A 10^6-point trajectory takes 16 MB (2-D), not one allocation per point.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PointsIn {
    /// Number of entries (points and nulls).
    pub count: usize,
    /// Coordinates per point (the first point's; 0 when there is none).
    pub width: usize,
    /// The coordinates of the points given, `width` each.
    pub flat: Vec<f64>,
    /// The first point whose length is not `width`: (index, length).
    pub mismatch: Option<(usize, usize)>,
    /// Indices of the `null` entries, increasing.
    pub nulls: Vec<usize>,
}

struct PointsVisitor;

impl<'de> Visitor<'de> for PointsVisitor {
    type Value = PointsIn;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PointsIn, A::Error> {
        let mut p = PointsIn {
            flat: Vec::with_capacity(capacity(seq.size_hint()).saturating_mul(2)),
            ..PointsIn::default()
        };
        let mut first = true;
        while let Some(row) = seq.next_element::<Option<Row>>()? {
            match row {
                None => p.nulls.push(p.count),
                Some(r) => {
                    if first {
                        p.width = r.len;
                        first = false;
                    }
                    if r.len != p.width {
                        p.mismatch.get_or_insert((p.count, r.len));
                    } else if r.len <= 3 {
                        p.flat.extend_from_slice(&r.x[..r.len]);
                    }
                }
            }
            p.count += 1;
        }
        Ok(p)
    }
}

impl<'de> Deserialize<'de> for PointsIn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<PointsIn, D::Error> {
        d.deserialize_seq(PointsVisitor)
    }
}

/// A value of the formats written as JSON, in the form it is read in
/// (so that a document built from these types and written reads back as
/// it was): finite numbers as serde_json writes an `f64`; bounds,
/// intervals and boxes as a result's are (`super::result::BoundOut`: a
/// zero bound as `0.0`, never `-0.0`; an unbounded one as `"-inf"` /
/// `"inf"`). Written by hand, not by serde's `Serialize`: serde's writer,
/// instantiated per field type, costs the page's simulators' module
/// (scripts/web.sh) about 2 KB of brotli more than these functions.
pub trait ToJson {
    /// The value as JSON.
    fn to_json(&self) -> Value;
}

/// Inserts `key: value` into `o` (one copy of the map's insertion for
/// every field of every document, not one per field).
#[inline(never)]
pub fn put(o: &mut serde_json::Map<String, Value>, key: &str, value: Value) {
    o.insert(key.into(), value);
}

/// An interval: `[lo, hi]`, or `"empty"`.
fn interval_json(x: Interval) -> Value {
    if x.is_empty() {
        Value::from("empty")
    } else {
        Value::Array(vec![
            crate::json::bound_to_json(x.lo()),
            crate::json::bound_to_json(x.hi()),
        ])
    }
}

/// Numbers as an array (a non-finite one as `null`, as serde_json
/// writes it).
fn numbers_json(x: &[f64]) -> Value {
    Value::Array(x.iter().map(|&x| Value::from(x)).collect())
}

impl ToJson for Finite {
    fn to_json(&self) -> Value {
        Value::from(self.0)
    }
}

/// A whole number as itself (only values are ever written: `Huge` as its
/// float, `Invalid` as `null`).
impl ToJson for Integer {
    fn to_json(&self) -> Value {
        match self {
            Integer::Value(x) => Value::from(*x),
            Integer::Huge(x) => Value::from(*x),
            Integer::Invalid(_) => Value::Null,
        }
    }
}

impl ToJson for IntervalIn {
    fn to_json(&self) -> Value {
        interval_json(self.0)
    }
}

/// The axes, or `"empty"` when one is.
impl ToJson for BoxIn {
    fn to_json(&self) -> Value {
        if self.0.iter().any(|x| x.is_empty()) {
            return Value::from("empty");
        }
        Value::Array(self.0.iter().map(|&x| interval_json(x)).collect())
    }
}

impl ToJson for Numbers {
    fn to_json(&self) -> Value {
        numbers_json(&self.0)
    }
}

impl ToJson for Bounds {
    fn to_json(&self) -> Value {
        Value::Array(
            self.0
                .iter()
                .map(|&x| crate::json::bound_to_json(x))
                .collect(),
        )
    }
}

impl ToJson for PerStep {
    fn to_json(&self) -> Value {
        match self {
            PerStep::One(x) => Value::from(*x),
            PerStep::Each(v) => numbers_json(v),
        }
    }
}

/// The points in order, `null` at each index of `nulls`.
impl ToJson for PointsIn {
    fn to_json(&self) -> Value {
        let mut rows = self.flat.chunks(self.width.max(1));
        let mut nulls = self.nulls.iter().peekable();
        Value::Array(
            (0..self.count)
                .map(|i| match nulls.next_if_eq(&&i) {
                    Some(_) => Value::Null,
                    None => numbers_json(rows.next().unwrap_or(&[])),
                })
                .collect(),
        )
    }
}

impl<T: ToJson> ToJson for List<T> {
    fn to_json(&self) -> Value {
        Value::Array(self.0.iter().map(ToJson::to_json).collect())
    }
}

/// `null` for `None`.
impl<T: ToJson> ToJson for Option<T> {
    fn to_json(&self) -> Value {
        self.as_ref().map_or(Value::Null, ToJson::to_json)
    }
}

impl ToJson for Value {
    fn to_json(&self) -> Value {
        self.clone()
    }
}

impl ToJson for String {
    fn to_json(&self) -> Value {
        Value::from(self.as_str())
    }
}

impl PointsIn {
    /// Known points of `width` coordinates each, given point after point
    /// (`flat.len()` a multiple of `width`; `as_flattened` of an array of
    /// points).
    pub fn rows(width: usize, flat: &[f64]) -> PointsIn {
        PointsIn {
            count: flat.len().checked_div(width).unwrap_or(0),
            width,
            flat: flat.to_vec(),
            mismatch: None,
            nulls: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::from_value;
    use serde_json::json;

    #[test]
    fn interval_errors_name_the_path() {
        let e = from_value::<IntervalIn>(&json!([5, 4])).unwrap_err();
        assert_eq!(e.to_string(), "lower bound 5 is above upper bound 4");
        let e = from_value::<IntervalIn>(&json!([1, "x"])).unwrap_err();
        assert_eq!(e.path, "[1]");
        assert_eq!(
            e.message,
            "expected a number, \"-inf\" or \"inf\", found a string"
        );
        let e = from_value::<IntervalIn>(&json!([1, 2, 3])).unwrap_err();
        assert_eq!(
            e.message,
            "an interval is [lo, hi]: expected 2 bounds, found 3"
        );
        assert!(from_value::<IntervalIn>(&json!(["inf", "inf"])).is_err());
        assert!(from_value::<IntervalIn>(&json!("empty")).is_err());
        assert_eq!(
            from_value::<IntervalIn>(&json!(["-inf", 3])).unwrap().0,
            Interval::new(f64::NEG_INFINITY, 3.0)
        );
    }

    /// Regression (found by the schema-driven fuzzer): `3.0` is the integer 3.
    #[test]
    fn whole_floats_are_integers() {
        let int = |v| from_value::<Integer>(&v).unwrap();
        assert_eq!(int(json!(3.0)), Integer::Value(3));
        assert_eq!(int(json!(-0.0)), Integer::Value(0));
        let msg = |v, min, max| int(v).in_range(min, max, "n").unwrap_err().message;
        assert_eq!(
            msg(json!(2.5), 0, 10),
            "expected an integer from 0 to 10, found 2.5"
        );
        assert_eq!(
            msg(json!(-3.0), 0, 10),
            "expected an integer from 0 to 10, found -3.0"
        );
        assert_eq!(
            msg(json!(-1), 0, 10),
            "expected an integer from 0 to 10, found -1"
        );
        assert_eq!(
            msg(json!(12), 0, 10),
            "expected an integer from 0 to 10, found 12"
        );
        assert_eq!(
            msg(json!(0), 1, 10),
            "expected an integer from 1 to 10, found 0"
        );
        assert_eq!(
            msg(json!("3"), 1, 10),
            "expected an integer from 1 to 10, found a string"
        );
        assert_eq!(
            msg(json!([1]), 1, 10),
            "expected an integer from 1 to 10, found an array"
        );
        assert!(msg(json!(1e300), 0, u64::MAX)
            .starts_with("expected an integer from 0 to 18446744073709551615, found 1"));
        assert_eq!(int(json!(7)).in_range(7, 7, "n").unwrap(), 7);
    }

    #[test]
    fn box_dimension_is_checked() {
        let b = from_value::<BoxIn>(&json!([[0, 1]])).unwrap();
        assert!(b
            .dim("b", Some(2))
            .unwrap_err()
            .message
            .contains("dimension 2"));
        assert!(from_value::<BoxIn>(&json!([]))
            .unwrap()
            .dim("b", None)
            .is_err());
    }
}
