//! Reading and writing the numbers, intervals and boxes of the JSON formats
//! (docs/formats.md), with the JSON path of every bad value in errors.

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use serde_json::{Map, Value};

/// `path` + `.field` (or `field` at the root).
pub fn field_path(path: &str, field: &str) -> String {
    if path.is_empty() {
        field.to_string()
    } else {
        format!("{path}.{field}")
    }
}

/// `path` + `[i]`.
pub fn index_path(path: &str, i: usize) -> String {
    format!("{path}[{i}]")
}

/// Short description of a JSON value's type, for messages.
pub fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// The value as an object, or an error naming `path`.
pub fn object<'a>(v: &'a Value, path: &str) -> Result<&'a Map<String, Value>, InputError> {
    v.as_object()
        .ok_or_else(|| InputError::new(path, format!("expected an object, found {}", kind(v))))
}

/// The value as an array, or an error naming `path`.
pub fn array<'a>(v: &'a Value, path: &str) -> Result<&'a Vec<Value>, InputError> {
    v.as_array()
        .ok_or_else(|| InputError::new(path, format!("expected an array, found {}", kind(v))))
}

/// Rejects fields of `obj` not in `allowed` (typos must not pass silently).
pub fn check_fields(
    obj: &Map<String, Value>,
    allowed: &[&str],
    path: &str,
) -> Result<(), InputError> {
    check_keys(obj.keys(), allowed, path)
}

/// Rejects keys not in `allowed`, naming the first of `keys` (in the order
/// given: sorted, for an object's keys) that is not.
pub fn check_keys<'a>(
    keys: impl IntoIterator<Item = &'a String>,
    allowed: &[&str],
    path: &str,
) -> Result<(), InputError> {
    for key in keys {
        if !allowed.contains(&key.as_str()) {
            return Err(InputError::new(
                field_path(path, key),
                format!(
                    "unknown field `{key}` (expected one of: {})",
                    allowed.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// A required field.
pub fn required<'a>(
    obj: &'a Map<String, Value>,
    field: &str,
    path: &str,
) -> Result<&'a Value, InputError> {
    obj.get(field)
        .ok_or_else(|| InputError::new(field_path(path, field), "missing required field"))
}

/// A finite number.
pub fn number(v: &Value, path: &str) -> Result<f64, InputError> {
    match v.as_f64() {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(InputError::new(
            path,
            format!("expected a finite number, found {}", kind(v)),
        )),
    }
}

/// A non-negative integer no larger than `max`. A JSON number whose value
/// is a whole number counts however it is written (`3`, `3.0`, `3e0`), as
/// JSON Schema's `integer` counts it (the OpenAPI document says
/// `integer`; a client that writes 3.0 has written the integer 3).
pub fn integer(v: &Value, path: &str, max: u64) -> Result<u64, InputError> {
    /// 2^64: whole floats below it convert to u64 exactly.
    const TWO_TO_64: f64 = 18_446_744_073_709_551_616.0;
    let whole = v.as_u64().map(Ok).or_else(|| {
        v.as_f64()
            .filter(|x| v.is_f64() && x.fract() == 0.0 && *x >= 0.0)
            .map(|x| if x < TWO_TO_64 { Ok(x as u64) } else { Err(x) })
    });
    match whole {
        Some(Ok(x)) if x <= max => Ok(x),
        Some(Ok(x)) => Err(InputError::new(
            path,
            format!("{x} is above the limit {max}"),
        )),
        Some(Err(x)) => Err(InputError::new(
            path,
            format!("{x} is above the limit {max}"),
        )),
        None => Err(InputError::new(
            path,
            format!("expected a non-negative integer, found {}", describe(v)),
        )),
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Number(n) => n.to_string(),
        _ => kind(v).to_string(),
    }
}

/// A bound: a number or the strings `"-inf"` / `"inf"`.
pub fn bound(v: &Value, path: &str) -> Result<f64, InputError> {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(InputError::new(path, "number out of range")),
        },
        Value::String(s) if s == "inf" || s == "+inf" => Ok(f64::INFINITY),
        Value::String(s) if s == "-inf" => Ok(f64::NEG_INFINITY),
        _ => Err(InputError::new(
            path,
            format!("expected a number, \"-inf\" or \"inf\", found {}", kind(v)),
        )),
    }
}

/// An interval: `[lo, hi]` with `lo <= hi`, or a bare number `x` = `[x, x]`.
pub fn interval(v: &Value, path: &str) -> Result<Interval, InputError> {
    match v {
        Value::Array(a) => {
            if a.len() != 2 {
                return Err(InputError::new(
                    path,
                    format!(
                        "an interval is [lo, hi]: expected 2 bounds, found {}",
                        a.len()
                    ),
                ));
            }
            let lo = bound(&a[0], &index_path(path, 0))?;
            let hi = bound(&a[1], &index_path(path, 1))?;
            if lo > hi {
                return Err(InputError::new(
                    path,
                    format!(
                        "lower bound {} is above upper bound {}",
                        fmt_bound(lo),
                        fmt_bound(hi)
                    ),
                ));
            }
            let x = Interval::new(lo, hi);
            if x.is_empty() {
                return Err(InputError::new(path, "an interval must hold a real number"));
            }
            Ok(x)
        }
        Value::Number(_) => {
            let x = number(v, path)?;
            Ok(Interval::point(x))
        }
        Value::String(s) if s == "empty" => {
            Err(InputError::new(path, "an input interval may not be empty"))
        }
        _ => Err(InputError::new(
            path,
            format!(
                "expected an interval [lo, hi] or a number, found {}",
                kind(v)
            ),
        )),
    }
}

/// A box of `dim` axes (any dimension >= 1 when `dim` is `None`).
pub fn ibox(v: &Value, path: &str, dim: Option<usize>) -> Result<IntervalBox, InputError> {
    let a = match v {
        Value::Array(a) => a,
        Value::String(s) if s == "empty" => {
            return Err(InputError::new(path, "an input box may not be empty"))
        }
        _ => {
            return Err(InputError::new(
                path,
                format!("expected a box (an array of intervals), found {}", kind(v)),
            ))
        }
    };
    if let Some(d) = dim {
        if a.len() != d {
            return Err(InputError::new(
                path,
                format!("expected a box of dimension {d}, found {} axes", a.len()),
            ));
        }
    } else if a.is_empty() {
        return Err(InputError::new(path, "a box needs at least one axis"));
    }
    let mut axes = Vec::with_capacity(a.len());
    for (i, x) in a.iter().enumerate() {
        axes.push(interval(x, &index_path(path, i))?);
    }
    Ok(IntervalBox::new(&axes))
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

/// A bound as JSON: a number, or `"inf"` / `"-inf"`. A zero is written
/// `0.0` whatever its sign (`x + 0.0`): `f64::min`/`max` may give either
/// sign of zero depending on the platform, and the output must be the same
/// bits native and in wasm (signed zeros are one value in core).
pub fn bound_to_json(x: f64) -> Value {
    if x.is_finite() {
        Value::from(x + 0.0)
    } else if x > 0.0 {
        Value::from("inf")
    } else {
        Value::from("-inf")
    }
}

/// An interval as JSON: `[lo, hi]` or `"empty"`.
pub fn interval_to_json(x: Interval) -> Value {
    if x.is_empty() {
        Value::from("empty")
    } else {
        Value::Array(vec![bound_to_json(x.lo()), bound_to_json(x.hi())])
    }
}

/// A box as JSON: an array of intervals, or `"empty"`.
pub fn box_to_json(b: &IntervalBox) -> Value {
    if b.is_empty() {
        Value::from("empty")
    } else {
        Value::Array(b.axes().iter().map(|&x| interval_to_json(x)).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A negative zero bound (from `f64::min`/`max`, whose zero sign is
    /// platform-dependent) was written `-0.0`: native and wasm outputs could
    /// differ in their bits.
    #[test]
    fn signed_zero_bounds_are_written_as_one_zero() {
        let x = Interval::new(-0.0, -0.0);
        assert_eq!(
            serde_json::to_string(&interval_to_json(x)).unwrap(),
            "[0.0,0.0]"
        );
        assert_eq!(bound_to_json(-0.0).to_string(), "0.0");
        assert_eq!(bound_to_json(-1.5).to_string(), "-1.5");
    }

    #[test]
    fn interval_errors_name_the_path() {
        let e = interval(&json!([5, 4]), "detections[12].range").unwrap_err();
        assert_eq!(
            e.to_string(),
            "detections[12].range: lower bound 5 is above upper bound 4"
        );
        let e = interval(&json!([1, "x"]), "r").unwrap_err();
        assert_eq!(e.path, "r[1]");
    }

    #[test]
    fn infinite_bounds_round_trip() {
        let x = interval(&json!(["-inf", 3]), "").unwrap();
        assert_eq!(interval_to_json(x), json!(["-inf", 3.0]));
        assert!(interval(&json!(["inf", "inf"]), "").is_err());
    }

    /// Regression (found by the schema-driven fuzzer): `3.0` is the
    /// integer 3 for JSON Schema, and the OpenAPI document says `integer`;
    /// it was refused.
    #[test]
    fn issue_13_whole_floats_are_integers() {
        assert_eq!(integer(&json!(3.0), "n", 10).unwrap(), 3);
        assert_eq!(integer(&json!(-0.0), "n", 10).unwrap(), 0);
        assert_eq!(integer(&json!(7), "n", 10).unwrap(), 7);
        assert!(integer(&json!(2.5), "n", 10)
            .unwrap_err()
            .message
            .contains("non-negative integer"));
        assert!(integer(&json!(-3.0), "n", 10).is_err());
        assert!(integer(&json!(12.0), "n", 10)
            .unwrap_err()
            .message
            .contains("above the limit"));
        assert!(integer(&json!(1e300), "n", u64::MAX)
            .unwrap_err()
            .message
            .contains("above the limit"));
        assert_eq!(
            integer(&json!(9007199254740992.0), "n", u64::MAX).unwrap(),
            1 << 53
        );
    }

    #[test]
    fn box_dimension_is_checked() {
        let e = ibox(&json!([[0, 1]]), "b", Some(2)).unwrap_err();
        assert!(e.message.contains("dimension 2"));
    }
}
