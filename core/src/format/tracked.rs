//! A reader of a parsed JSON value that knows where it is: a
//! `serde::Deserializer` over `&serde_json::Value` that behaves as
//! serde_json's own (`&Value` as a deserializer: the same `visit_*` calls,
//! the same errors) and records the JSON path of the first value whose
//! read fails, as serde_path_to_error does (`detections[3].range`).
//!
//! Why not serde_path_to_error over serde_json's `&Value`: that wraps every
//! visitor, seed, sequence and map access in a tracking copy, one per
//! visitor type, around serde_json's own deserializer (26,901 bytes of wasm
//! in the solver's module, 6,522 with brotli, BENCHMARKS.md "The page's
//! wasm transfer"). Here the deserializer itself tracks the path: each
//! visitor type is read by one deserializer, not by two stacked.
//!
//! The path is the one serde_path_to_error gives (the differential test
//! `tests/format/paths.rs` runs both over many bad documents): an error
//! leaving the read of a value is pinned to that value's path unless a
//! deeper read already pinned it (the first pin wins); an error reading a
//! map key (an unknown field) is pinned to the key's path. Paths are
//! written `a.b[2].c`, empty at the root.
//!
//! Cost: only the failed read of a document runs through it natively (the
//! untracked read comes first, `format::from_value`); on wasm32 every read
//! does, one `Chain` link on the stack per level of nesting.

use serde::de::value::BorrowedStrDeserializer;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::{Error, Map, Value};
use std::cell::RefCell;
use std::fmt::Write as _;

/// Where a value sits: a linked list up to the root, on the stack.
#[derive(Clone, Copy)]
enum Chain<'a> {
    Root,
    Index(&'a Chain<'a>, usize),
    Key(&'a Chain<'a>, &'a str),
}

impl Chain<'_> {
    /// The path as text (`a.b[2]`; empty at the root).
    fn write(&self, out: &mut String) {
        match *self {
            Chain::Root => {}
            Chain::Index(parent, i) => {
                parent.write(out);
                let _ = write!(out, "[{i}]");
            }
            Chain::Key(parent, key) => {
                parent.write(out);
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(key);
            }
        }
    }
}

/// The path of the first failed read, once one failed.
#[derive(Default)]
pub(super) struct Track(RefCell<Option<String>>);

impl Track {
    /// Pins `err` to `chain` unless an error was pinned already.
    fn pin(&self, chain: &Chain, err: Error) -> Error {
        let mut path = self.0.borrow_mut();
        if path.is_none() {
            let mut s = String::new();
            chain.write(&mut s);
            *path = Some(s);
        }
        err
    }

    /// The path pinned (empty when none was).
    pub(super) fn path(self) -> String {
        self.0.into_inner().unwrap_or_default()
    }
}

/// A value to read, where it sits, and the track of the whole read.
#[derive(Clone, Copy)]
pub(super) struct Tracked<'a, 'de> {
    value: &'de Value,
    chain: &'a Chain<'a>,
    track: &'a Track,
}

impl<'a, 'de> Tracked<'a, 'de> {
    /// The reader of a whole document.
    pub(super) fn root(value: &'de Value, track: &'a Track) -> Self {
        Tracked {
            value,
            chain: &Chain::Root,
            track,
        }
    }

    /// serde_json's "invalid type" error for this value.
    fn invalid_type(&self, exp: &dyn de::Expected) -> Error {
        let unexpected = match self.value {
            Value::Null => de::Unexpected::Unit,
            Value::Bool(b) => de::Unexpected::Bool(*b),
            Value::Number(n) => match (n.as_u64(), n.as_i64(), n.as_f64()) {
                (Some(u), _, _) => de::Unexpected::Unsigned(u),
                (None, Some(i), _) => de::Unexpected::Signed(i),
                (None, None, f) => de::Unexpected::Float(f.unwrap_or(f64::NAN)),
            },
            Value::String(s) => de::Unexpected::Str(s),
            Value::Array(_) => de::Unexpected::Seq,
            Value::Object(_) => de::Unexpected::Map,
        };
        de::Error::invalid_type(unexpected, exp)
    }

    /// Pins an error leaving this value's read to its path.
    fn pinned<T>(&self, r: Result<T, Error>) -> Result<T, Error> {
        r.map_err(|e| self.track.pin(self.chain, e))
    }

    /// `deserialize_any`, unpinned.
    fn any<V: Visitor<'de>>(&self, visitor: V) -> Result<V::Value, Error> {
        match self.value {
            Value::Null => visitor.visit_unit(),
            Value::Bool(b) => visitor.visit_bool(*b),
            Value::Number(n) => n.deserialize_any(visitor),
            Value::String(s) => visitor.visit_borrowed_str(s),
            Value::Array(a) => self.array(a, visitor),
            Value::Object(m) => self.object(m, visitor),
        }
    }

    /// An array, as serde_json reads it: every element must be read.
    fn array<V: Visitor<'de>>(&self, a: &'de [Value], visitor: V) -> Result<V::Value, Error> {
        let mut seq = Elements {
            items: a.iter(),
            index: 0,
            chain: self.chain,
            track: self.track,
        };
        let out = visitor.visit_seq(&mut seq)?;
        if seq.items.len() == 0 {
            Ok(out)
        } else {
            Err(de::Error::invalid_length(
                a.len(),
                &"fewer elements in array",
            ))
        }
    }

    /// An object, as serde_json reads it: every entry must be read.
    fn object<V: Visitor<'de>>(
        &self,
        m: &'de Map<String, Value>,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let mut map = Entries {
            entries: m.iter(),
            value: None,
            chain: self.chain,
            track: self.track,
        };
        let out = visitor.visit_map(&mut map)?;
        if map.entries.len() == 0 {
            Ok(out)
        } else {
            Err(de::Error::invalid_length(m.len(), &"fewer elements in map"))
        }
    }

    /// A string (`deserialize_str`), unpinned.
    fn str<V: Visitor<'de>>(&self, visitor: V) -> Result<V::Value, Error> {
        match self.value {
            Value::String(s) => visitor.visit_borrowed_str(s),
            _ => Err(self.invalid_type(&visitor)),
        }
    }
}

/// serde_json's number methods of `&Value`: a number, else "invalid type".
macro_rules! number {
    ($($method:ident)*) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            let r = match self.value {
                Value::Number(n) => n.deserialize_any(visitor),
                _ => Err(self.invalid_type(&visitor)),
            };
            self.pinned(r)
        }
    )*};
}

impl<'de> Deserializer<'de> for Tracked<'_, 'de> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = self.any(visitor);
        self.pinned(r)
    }

    number!(deserialize_i8 deserialize_i16 deserialize_i32 deserialize_i64 deserialize_i128
        deserialize_u8 deserialize_u16 deserialize_u32 deserialize_u64 deserialize_u128
        deserialize_f32 deserialize_f64);

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Null => visitor.visit_none(),
            _ => visitor.visit_some(self),
        };
        self.pinned(r)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        // The formats' enums are names (unit variants): serde_json's own
        // read, pinned here (a variant's content is not tracked deeper).
        let r = self.value.deserialize_enum(name, variants, visitor);
        self.pinned(r)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        let r = visitor.visit_newtype_struct(self);
        self.pinned(r)
    }

    fn deserialize_bool<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Bool(b) => visitor.visit_bool(*b),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_char<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = self.str(visitor);
        self.pinned(r)
    }

    fn deserialize_str<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = self.str(visitor);
        self.pinned(r)
    }

    fn deserialize_string<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = self.str(visitor);
        self.pinned(r)
    }

    fn deserialize_identifier<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = self.str(visitor);
        self.pinned(r)
    }

    fn deserialize_bytes<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::String(s) => visitor.visit_borrowed_str(s),
            Value::Array(a) => self.array(a, visitor),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_byte_buf<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        self.deserialize_bytes(visitor)
    }

    fn deserialize_unit<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Null => visitor.visit_unit(),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.deserialize_unit(visitor)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Array(a) => self.array(a, visitor),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_tuple<V: Visitor<'de>>(
        self,
        _len: usize,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.deserialize_seq(visitor)
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _len: usize,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.deserialize_seq(visitor)
    }

    fn deserialize_map<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Object(m) => self.object(m, visitor),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        let r = match self.value {
            Value::Array(a) => self.array(a, visitor),
            Value::Object(m) => self.object(m, visitor),
            _ => Err(self.invalid_type(&visitor)),
        };
        self.pinned(r)
    }

    fn deserialize_ignored_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        let r = visitor.visit_unit();
        self.pinned(r)
    }
}

/// The elements of an array, each read where it sits (`[i]`).
struct Elements<'a, 'de> {
    items: std::slice::Iter<'de, Value>,
    index: usize,
    chain: &'a Chain<'a>,
    track: &'a Track,
}

impl<'de> SeqAccess<'de> for Elements<'_, 'de> {
    type Error = Error;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Error> {
        let Some(value) = self.items.next() else {
            return Ok(None);
        };
        let chain = Chain::Index(self.chain, self.index);
        self.index += 1;
        seed.deserialize(Tracked {
            value,
            chain: &chain,
            track: self.track,
        })
        .map(Some)
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len())
    }
}

/// The entries of an object: a key read as a borrowed string (pinned to
/// the key's path when it fails: an unknown field), its value where it
/// sits (`.key`).
struct Entries<'a, 'de> {
    entries: serde_json::map::Iter<'de>,
    value: Option<(&'de str, &'de Value)>,
    chain: &'a Chain<'a>,
    track: &'a Track,
}

impl<'de> MapAccess<'de> for Entries<'_, 'de> {
    type Error = Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        let Some((key, value)) = self.entries.next() else {
            return Ok(None);
        };
        self.value = Some((key, value));
        let de = BorrowedStrDeserializer::<Error>::new(key);
        seed.deserialize(de)
            .map(Some)
            .map_err(|e| self.track.pin(&Chain::Key(self.chain, key), e))
    }

    fn next_value_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<T::Value, Error> {
        let Some((key, value)) = self.value.take() else {
            return Err(de::Error::custom("value is missing"));
        };
        let chain = Chain::Key(self.chain, key);
        seed.deserialize(Tracked {
            value,
            chain: &chain,
            track: self.track,
        })
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.entries.len())
    }
}
