//! The JSON formats of docs/formats.md, defined once as serde types (this
//! module, below every other one of core: it imports only the numbers,
//! intervals and the error type), and the one way to read them: with the
//! JSON path of the bad value in every error ([`from_str`],
//! [`from_value`]). Validation into the domain types (a mission's steps,
//! dimensions, ids) is a separate step, in the modules that own those
//! types (`slam::mission`): these types only say what the JSON looks like.
//! The exception is a result ([`result`]): it is read back for drawing,
//! into no domain type, so its few rules between fields are checked
//! beside its types (`ResultDoc::check`).
//!
//! Messages: serde's own wording is rewritten to the project's ("expected
//! an object, found an array", "unknown field `x` (expected one of: a,
//! b)"); the leaf types of [`leaf`] write theirs directly.

/// `Deserialize` for a struct derived with `#[serde(remote = "Self")]`
/// that reads a JSON object only (a derived struct also reads an array of
/// its fields in order, which the formats do not allow).
macro_rules! object_only {
    ($t:ident) => {
        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<$t, D::Error> {
                struct V;
                impl<'de> serde::de::Visitor<'de> for V {
                    type Value = $t;
                    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                        f.write_str("an object")
                    }
                    fn visit_map<A: serde::de::MapAccess<'de>>(
                        self,
                        map: A,
                    ) -> Result<$t, A::Error> {
                        $t::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    }
                }
                d.deserialize_map(V)
            }
        }
    };
}

/// A derived `Serialize` of a struct with `#[serde(remote = "Self")]` as
/// the trait (the derive then writes an inherent function).
macro_rules! serialize_self {
    ($t:ident) => {
        impl serde::Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
                $t::serialize(self, ser)
            }
        }
    };
}

/// [`leaf::ToJson`] for a document type: an object of its fields that are
/// present (those after `always` written even when absent, as `null`),
/// each named as serde reads it. Every field of the struct must be listed
/// (the destructuring fails to compile otherwise).
macro_rules! to_json_fields {
    ($t:ident { $($f:ident),* } $(always { $($a:ident),* })?) => {
        impl $crate::format::leaf::ToJson for $t {
            fn to_json(&self) -> serde_json::Value {
                let $t { $($f,)* $($($a,)*)? } = self;
                let mut o = serde_json::Map::new();
                $(
                    if let Some(v) = $f {
                        $crate::format::leaf::put(&mut o, stringify!($f), $crate::format::leaf::ToJson::to_json(v));
                    }
                )*
                $($(
                    $crate::format::leaf::put(&mut o, stringify!($a), $crate::format::leaf::ToJson::to_json($a));
                )*)?
                serde_json::Value::Object(o)
            }
        }
    };
}

pub mod contract;
pub mod leaf;
#[cfg(feature = "openapi")]
mod leaf_schema;
pub mod mission_doc;
#[cfg(feature = "openapi")]
pub mod openapi;
pub mod result;
pub mod tdoa;
mod tracked;

use crate::error::InputError;
use serde::de::{DeserializeOwned, IgnoredAny};
use serde_json::Value;

/// Parses JSON text as `T`. A text that is not JSON at all gets
/// serde_json's message for the whole document ("invalid JSON: ..."),
/// whatever it holds before the syntax error; otherwise the first value
/// that does not fit `T` is named by its JSON path.
pub fn from_str<T: DeserializeOwned>(text: &str) -> Result<T, InputError> {
    // The fast path: a valid document is read once, untracked (tracking
    // the path of every array element costs ~10% on a 10^6-step mission);
    // only a failed read is read again with its path tracked.
    if let Ok(t) = serde_json::from_str::<T>(text) {
        return Ok(t);
    }
    let mut de = serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, T>(&mut de) {
        Ok(t) => match de.end() {
            Ok(()) => Ok(t),
            Err(e) => Err(syntax(text, &e)),
        },
        Err(e) => {
            if !e.inner().is_data() {
                return Err(syntax(text, e.inner()));
            }
            // JSON syntax first: a value of the wrong shape in a text that
            // is not JSON reports the syntax error.
            if let Err(s) = serde_json::from_str::<IgnoredAny>(text) {
                return Err(syntax(text, &s));
            }
            let path = e.path().to_string();
            Err(data_error(path, e.inner()))
        }
    }
}

/// Reads a parsed JSON value as `T` (same checks and messages as
/// [`from_str`] of its text).
///
/// Natively a valid value is read untracked first (the fast path of
/// [`from_str`]). On wasm32 it is read once, tracked: each format type's
/// reader is then compiled once instead of twice (untracked and tracked),
/// which keeps the page's download under its budget (scripts/web.sh); the
/// result and every message are the same. The tracked read is
/// [`tracked`]'s (the paths serde_path_to_error gives, without its
/// per-visitor wrappers).
pub fn from_value<T: DeserializeOwned>(v: &Value) -> Result<T, InputError> {
    #[cfg(not(target_arch = "wasm32"))]
    if let Ok(t) = T::deserialize(v) {
        return Ok(t);
    }
    let track = tracked::Track::default();
    let r = T::deserialize(tracked::Tracked::root(v, &track));
    r.map_err(|e| data_error(track.path(), &e))
}

/// A document built from these types as a JSON value (keys in sorted
/// order, as every `Value` of the project).
pub fn to_value<T: leaf::ToJson>(doc: &T) -> Value {
    doc.to_json()
}

/// [`from_value`] as it was before [`tracked`]: serde_path_to_error over
/// serde_json's `&Value`. Native only, for the differential test
/// (`core/tests/format/paths.rs`) that holds the two to the same results
/// and messages; never in a wasm module.
#[cfg(not(target_arch = "wasm32"))]
#[doc(hidden)]
pub fn from_value_reference<T: DeserializeOwned>(v: &Value) -> Result<T, InputError> {
    serde_path_to_error::deserialize::<_, T>(v)
        .map_err(|e| data_error(e.path().to_string(), e.inner()))
}

fn invalid_json(text: &str, e: &serde_json::Error) -> InputError {
    InputError::new(
        syntax_path(text, e.line(), e.column()),
        format!("invalid JSON: {e}"),
    )
}

/// The syntax error of the text, as a parse into a JSON value reports it
/// (the typed parse may stop at the same place with another message; this
/// makes it the same whatever `T` is). Only on the error path.
fn syntax(text: &str, e: &serde_json::Error) -> InputError {
    match serde_json::from_str::<Value>(text) {
        Err(s) => invalid_json(text, &s),
        Ok(_) => invalid_json(text, e),
    }
}

/// One level of [`syntax_path`]'s scan: an object (the key being read,
/// `None` while a key is expected) or an array (the element's index).
enum Level {
    Key(Option<String>),
    Index(usize),
}

/// The JSON path of the value being read where a syntax error stopped the
/// parse, `line` and `column` as serde_json reports them (1-based; line 0:
/// no position, ""): `dt` for `{"dt": NaN}`, `detections[3].range[1]` for
/// `1e400` there, the enclosing object's path where a key is expected, ""
/// at the top. So a NaN or Infinity literal, a number out of range or a
/// truncated body is named by its path like any other bad value. One scan
/// of the text up to that position (strings and their escapes skipped);
/// O(length).
pub fn syntax_path(text: &str, line: usize, column: usize) -> String {
    if line == 0 {
        return String::new();
    }
    let bytes = text.as_bytes();
    let mut end = bytes.len();
    let mut at_line = 1;
    for (i, &b) in bytes.iter().enumerate() {
        if at_line == line {
            end = (i + column.saturating_sub(1)).min(bytes.len());
            break;
        }
        if b == b'\n' {
            at_line += 1;
        }
    }
    let mut stack: Vec<Level> = Vec::new();
    let (mut i, mut expect_key) = (0, false);
    while i < end {
        match bytes[i] {
            b'{' => {
                stack.push(Level::Key(None));
                expect_key = true;
            }
            b'[' => stack.push(Level::Index(0)),
            b'}' | b']' => {
                stack.pop();
            }
            b',' => match stack.last_mut() {
                Some(Level::Index(k)) => *k += 1,
                Some(Level::Key(key)) => {
                    *key = None;
                    expect_key = true;
                }
                None => {}
            },
            b'"' => {
                let start = i + 1;
                i += 1;
                while i < end && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                if let (true, Some(Level::Key(key))) = (expect_key, stack.last_mut()) {
                    let s = &bytes[start.min(end)..i.min(end)];
                    *key = Some(String::from_utf8_lossy(s).into_owned());
                }
                expect_key = false;
            }
            _ => {}
        }
        i += 1;
    }
    level_path(&stack)
}

/// The JSON path of the first key that appears twice in one object of
/// `text`, outside the top-level `meta` (free-form): `dt`,
/// `detections[2].range`. `None` when every object's keys are distinct or
/// the text is not JSON. A typed read ([`from_str`]) refuses a repeated
/// field of a format type ("duplicate field"), while a text first read as
/// a `serde_json::Value` keeps the last value silently: the service
/// checks this first, so that both refuse the same documents. One pass,
/// nothing kept but each open object's keys.
pub fn duplicate_key(text: &str) -> Option<String> {
    let mut de = serde_json::Deserializer::from_str(text);
    let mut found = None;
    let seed = DupSeed {
        path: &mut Vec::new(),
        found: &mut found,
    };
    let _ = serde::de::DeserializeSeed::deserialize(seed, &mut de);
    found
}

/// A valid JSON text without the whitespace between its tokens (the
/// text inside strings kept byte for byte): what a store keeps of an
/// uploaded document. In place, in one pass (only ASCII whitespace is
/// dropped, so the text stays UTF-8): no second copy of a large upload,
/// no JSON tree. O(n).
pub fn compact_json(text: String) -> String {
    let mut bytes = text.into_bytes();
    let (mut in_string, mut escaped, mut kept) = (false, false, 0);
    for i in 0..bytes.len() {
        let c = bytes[i];
        if in_string {
            if escaped {
                escaped = false;
            } else if c == b'\\' {
                escaped = true;
            } else if c == b'"' {
                in_string = false;
            }
        } else if matches!(c, b' ' | b'\t' | b'\n' | b'\r') {
            continue;
        } else {
            in_string = c == b'"';
        }
        bytes[kept] = c;
        kept += 1;
    }
    bytes.truncate(kept);
    bytes.shrink_to_fit();
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// [`duplicate_key`]'s walk: the path so far and what it found.
struct DupSeed<'a> {
    path: &'a mut Vec<Level>,
    found: &'a mut Option<String>,
}

/// The JSON path (`a.b[2].c`) of the open keys and indices, up to the
/// first unnamed key.
fn level_path(levels: &[Level]) -> String {
    let mut path = String::new();
    for level in levels {
        match level {
            Level::Key(Some(k)) => {
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
            }
            Level::Key(None) => break,
            Level::Index(k) => {
                path.push('[');
                path.push_str(&k.to_string());
                path.push(']');
            }
        }
    }
    path
}

impl<'de> serde::de::DeserializeSeed<'de> for DupSeed<'_> {
    type Value = ();
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> serde::de::Visitor<'de> for DupSeed<'_> {
    type Value = ();
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0;
        loop {
            self.path.push(Level::Index(i));
            let seed = DupSeed {
                path: &mut *self.path,
                found: &mut *self.found,
            };
            let more = seq.next_element_seed(seed)?;
            self.path.pop();
            if more.is_none() {
                return Ok(());
            }
            i += 1;
        }
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = std::collections::BTreeSet::new();
        while let Some(key) = map.next_key::<String>()? {
            self.path.push(Level::Key(Some(key.clone())));
            if !seen.insert(key) {
                *self.found = Some(level_path(self.path));
                return Err(serde::de::Error::custom("duplicate key"));
            }
            if self.path.len() == 1 && map_key_is_meta(self.path) {
                map.next_value::<IgnoredAny>()?;
            } else {
                let seed = DupSeed {
                    path: &mut *self.path,
                    found: &mut *self.found,
                };
                map.next_value_seed(seed)?;
            }
            self.path.pop();
        }
        Ok(())
    }
}

fn map_key_is_meta(path: &[Level]) -> bool {
    matches!(path.last(), Some(Level::Key(Some(k))) if k == "meta")
}

/// A data error at `path` (serde_path_to_error's "." for the root is the
/// empty path), without serde_json's position, in the project's words.
fn data_error(path: String, inner: &serde_json::Error) -> InputError {
    let path = if path == "." { String::new() } else { path };
    let mut msg = inner.to_string();
    if inner.line() > 0 {
        let at = format!(" at line {} column {}", inner.line(), inner.column());
        if let Some(m) = msg.strip_suffix(&at) {
            msg = m.to_string();
        }
    }
    InputError::new(path, translate(&msg))
}

/// serde's messages in the project's words.
fn translate(msg: &str) -> String {
    if let Some(rest) = msg.strip_prefix("invalid type: ") {
        if let Some((unexpected, expected)) = rest.rsplit_once(", expected ") {
            return format!("expected {expected}, found {}", kind_of(unexpected));
        }
    }
    if let Some(rest) = msg.strip_prefix("unknown field `") {
        if let Some((name, tail)) = rest.split_once('`') {
            let list = tail
                .strip_prefix(", expected one of ")
                .or_else(|| tail.strip_prefix(", expected "));
            if let Some(list) = list {
                return format!(
                    "unknown field `{name}` (expected one of: {})",
                    list.replace('`', "")
                );
            }
        }
    }
    msg.to_string()
}

/// serde's `Unexpected` as a JSON kind ("a string", "an array", ...).
fn kind_of(unexpected: &str) -> String {
    const KINDS: [(&str, &str); 9] = [
        ("boolean", "a boolean"),
        ("integer", "a number"),
        ("floating point", "a number"),
        ("string", "a string"),
        ("null", "null"),
        ("unit value", "null"),
        ("sequence", "an array"),
        ("map", "an object"),
        ("Option value", "null"),
    ];
    KINDS
        .iter()
        .find(|(serde, _)| unexpected.starts_with(serde))
        .map_or_else(|| unexpected.to_string(), |(_, k)| k.to_string())
}

/// A `T` read from a JSON object only (a derived struct also reads an
/// array of its fields in order, which the formats do not allow): for the
/// front ends' own request types.
#[derive(Debug, Clone, PartialEq)]
pub struct Object<T>(pub T);

impl<'de, T: serde::Deserialize<'de>> serde::Deserialize<'de> for Object<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Object<T>, D::Error> {
        struct V<T>(std::marker::PhantomData<T>);
        impl<'de, T: serde::Deserialize<'de>> serde::de::Visitor<'de> for V<T> {
            type Value = Object<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Object<T>, A::Error> {
                T::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(Object)
            }
        }
        d.deserialize_map(V(std::marker::PhantomData))
    }
}

/// For `#[serde(default, deserialize_with = "present")]` on a field that is
/// `Option<T>` only so that its absence can be named: absent is `None`, a
/// `null` is read as a `T` (and so refused with "expected ..., found null").
pub fn present<'de, D, T>(d: D) -> Result<Option<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: serde::Deserialize<'de>,
{
    T::deserialize(d).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Repeated keys are found with their path, outside `meta` only.
    #[test]
    fn compact_json_drops_the_whitespace_between_tokens_only() {
        let text = "{ \"a b\" : [ 1 ,\n\t2.5e3 ],\r\n \"s\": \"x \\\" y\\\\\", \"t\" : \" \" }";
        let compact = compact_json(text.to_string());
        assert_eq!(compact, r#"{"a b":[1,2.5e3],"s":"x \" y\\","t":" "}"#);
        assert_eq!(
            compact_json("[\"é \\u00e9\", \"ü\"]".into()),
            "[\"é \\u00e9\",\"ü\"]"
        );
        let (a, b): (Value, Value) = (
            serde_json::from_str(text).unwrap(),
            serde_json::from_str(&compact).unwrap(),
        );
        assert_eq!(a, b);
    }

    #[test]
    fn duplicate_keys_are_found_with_their_path() {
        assert_eq!(
            duplicate_key(r#"{"dt": 1, "steps": 2, "dt": 3}"#).as_deref(),
            Some("dt")
        );
        assert_eq!(
            duplicate_key(
                r#"{"detections": [{"step": 1}, {"range": [1, 2], "step": 0, "range": 3}]}"#
            )
            .as_deref(),
            Some("detections[1].range")
        );
        assert_eq!(
            duplicate_key(r#"{"meta": {"a": 1, "a": 2}, "b": [{"a": 1}, {"a": 2}]}"#),
            None
        );
        assert_eq!(
            duplicate_key(r#"{"x": {"meta": {"a": 1, "a": 2}}}"#).as_deref(),
            Some("x.meta.a")
        );
        assert_eq!(duplicate_key("[1, {\"a\": [], \"b\": {}}]"), None);
        assert_eq!(duplicate_key("{\"a\": NaN}"), None);
        let text = r#"{"format": "nvector-contract/1", "n": 1, "n": 2, "boxes": [[[0, 1]]]}"#;
        assert!(from_str::<Value>(text).is_ok());
        assert_eq!(duplicate_key(text).as_deref(), Some("n"));
    }

    /// A syntax error is named by the path of the value being read: the
    /// NaN and Infinity literals, a number out of range, a truncated text
    /// (before, the path was always "").
    #[test]
    fn syntax_errors_name_the_value_being_read() {
        let path = |text: &str| {
            let e = serde_json::from_str::<Value>(text).unwrap_err();
            let err = from_str::<Value>(text).unwrap_err();
            assert!(err.message.starts_with("invalid JSON: "), "{}", err.message);
            assert_eq!(err.path, syntax_path(text, e.line(), e.column()));
            err.path
        };
        assert_eq!(path(r#"{"format": "x", "dt": NaN}"#), "dt");
        assert_eq!(path("{\n  \"a\": 1,\n  \"dt\": Infinity\n}"), "dt");
        assert_eq!(
            path(r#"{"detections": [{"range": [1, 2]}, {"step": 3, "range": [1, 1e400]}]}"#),
            "detections[1].range[1]"
        );
        assert_eq!(path(r#"{"a\"b": {"c": [0, 1, -]}}"#), "a\\\"b.c[2]");
        assert_eq!(path(r#"{"meta": {"x": 1,}, "b": 2}"#), "meta");
        assert_eq!(
            path(r#"{"inputs": {"speed": {"value": [1, 2"#),
            "inputs.speed.value[1]"
        );
        assert_eq!(path("NaN"), "");
        assert_eq!(path("[1, 2, nope]"), "[2]");
        assert_eq!(syntax_path("{\"a\": x}", 0, 0), "");
    }

    #[test]
    fn serde_messages_are_rewritten() {
        assert_eq!(
            translate("invalid type: sequence, expected an object"),
            "expected an object, found an array"
        );
        assert_eq!(
            translate("invalid type: string \"a, expected b\", expected a finite number"),
            "expected a finite number, found a string"
        );
        assert_eq!(
            translate("unknown field `rnage`, expected one of `step`, `range`"),
            "unknown field `rnage` (expected one of: step, range)"
        );
        assert_eq!(translate("duplicate field `x`"), "duplicate field `x`");
    }
}
