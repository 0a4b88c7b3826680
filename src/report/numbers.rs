//! Typed results into the envelope's number maps. A family declares its result keys once, as
//! the fields of `#[derive(Serialize)]` structs (field name = key with its unit suffix, a doc
//! comment per field), and [`number_map`] turns a value of such a struct into the
//! `design`/`objectives`/`errors`/`derived`/baseline map of a [`super::SolveResult`].
//!
//! A serde serializer of its own rather than `serde_json::to_value`: JSON has no inf or NaN,
//! and the envelope must still see a figure that is not finite to reject it
//! (`families::solve_scene`).

use serde::ser::{self, Impossible, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// Why a value is not a struct of numbers (a programming error in a family's result type).
#[derive(Debug, thiserror::Error)]
#[error("not a struct of numbers: {0}")]
pub struct NotNumbers(String);

impl ser::Error for NotNumbers {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        NotNumbers(msg.to_string())
    }
}

/// The fields of `v` (a struct or map of `f64`, integers and `Option`s of them; nested
/// structs through `#[serde(flatten)]`) as a key → number map. `None` fields are left out;
/// inf and NaN are kept. Panics if `v` is not such a struct: a family's result type is
/// plain numbers by construction, and every family's tests serialise it.
pub fn number_map<T: Serialize + ?Sized>(v: &T) -> BTreeMap<String, f64> {
    try_number_map(v).unwrap_or_else(|e| panic!("{e}"))
}

/// [`number_map`], the error returned.
pub fn try_number_map<T: Serialize + ?Sized>(v: &T) -> Result<BTreeMap<String, f64>, NotNumbers> {
    let mut m = BTreeMap::new();
    v.serialize(Fields(&mut m))?;
    Ok(m)
}

/// The keys `v` declares, including those of `None` fields (to check that a key named
/// elsewhere, such as a family's key objective, is one of the struct's fields).
pub fn declared_keys<T: Serialize + ?Sized>(v: &T) -> Vec<String> {
    let mut keys = Vec::new();
    let _ = v.serialize(KeyNames(&mut keys));
    keys
}

/// The result key of field `$field` of the typed result struct `$t`, checked by the compiler
/// (a misspelt or removed field does not compile): `key!(Derived, k)` is `"k"`,
/// `key!("derived", Derived, k)` is `"derived.k"`. For naming a key outside its struct (the
/// key objective, a headline, a paper check, a study's lookup) without writing it twice.
// Exported (as `cwsynth::key!`) for the tests in tests/unit_report.rs
#[doc(hidden)]
#[macro_export]
macro_rules! key {
    ($t:ty, $field:ident) => {{
        let _ = |v: &$t| {
            let _ = &v.$field;
        };
        stringify!($field)
    }};
    ($section:literal, $t:ty, $field:ident) => {{
        let _ = |v: &$t| {
            let _ = &v.$field;
        };
        concat!($section, ".", stringify!($field))
    }};
}
pub(crate) use key;

/// The top level: a struct or a map, whose entries go into the map.
struct Fields<'a>(&'a mut BTreeMap<String, f64>);

/// One entry's value: a number, or nothing (`None`).
struct Number;

/// The top level, collecting every field name (for [`declared_keys`]).
struct KeyNames<'a>(&'a mut Vec<String>);

fn unsupported<T>(what: &str) -> Result<T, NotNumbers> {
    Err(NotNumbers(format!("a {what} is not a number")))
}

/// The `serialize_*` methods of a serializer that accepts none of these types.
macro_rules! reject {
    ($($m:ident($($t:ty),*) $what:literal;)*) => {
        $(fn $m(self $(, _: $t)*) -> Result<Self::Ok, NotNumbers> {
            unsupported($what)
        })*
    };
}

impl ser::Serializer for Number {
    type Ok = Option<f64>;
    type Error = NotNumbers;
    type SerializeSeq = Impossible<Option<f64>, NotNumbers>;
    type SerializeTuple = Impossible<Option<f64>, NotNumbers>;
    type SerializeTupleStruct = Impossible<Option<f64>, NotNumbers>;
    type SerializeTupleVariant = Impossible<Option<f64>, NotNumbers>;
    type SerializeMap = Impossible<Option<f64>, NotNumbers>;
    type SerializeStruct = Impossible<Option<f64>, NotNumbers>;
    type SerializeStructVariant = Impossible<Option<f64>, NotNumbers>;

    fn serialize_f64(self, v: f64) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v))
    }
    fn serialize_f32(self, v: f32) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v.into()))
    }
    fn serialize_i64(self, v: i64) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v as f64))
    }
    fn serialize_u64(self, v: u64) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v as f64))
    }
    fn serialize_i32(self, v: i32) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v.into()))
    }
    fn serialize_u32(self, v: u32) -> Result<Option<f64>, NotNumbers> {
        Ok(Some(v.into()))
    }
    fn serialize_none(self) -> Result<Option<f64>, NotNumbers> {
        Ok(None)
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<Option<f64>, NotNumbers> {
        v.serialize(self)
    }
    reject! {
        serialize_bool(bool) "bool";
        serialize_i8(i8) "i8";
        serialize_i16(i16) "i16";
        serialize_u8(u8) "u8";
        serialize_u16(u16) "u16";
        serialize_char(char) "char";
        serialize_str(&str) "string";
        serialize_bytes(&[u8]) "byte string";
        serialize_unit() "unit";
        serialize_unit_struct(&'static str) "unit struct";
        serialize_unit_variant(&'static str, u32, &'static str) "enum";
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<Option<f64>, NotNumbers> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Option<f64>, NotNumbers> {
        unsupported("enum")
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotNumbers> {
        unsupported("sequence")
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, NotNumbers> {
        unsupported("tuple")
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, NotNumbers> {
        unsupported("tuple struct")
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotNumbers> {
        unsupported("enum")
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotNumbers> {
        unsupported("map")
    }
    fn serialize_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStruct, NotNumbers> {
        unsupported("struct")
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotNumbers> {
        unsupported("enum")
    }
}

/// A map key: a string.
struct Key;

impl ser::Serializer for Key {
    type Ok = String;
    type Error = NotNumbers;
    type SerializeSeq = Impossible<String, NotNumbers>;
    type SerializeTuple = Impossible<String, NotNumbers>;
    type SerializeTupleStruct = Impossible<String, NotNumbers>;
    type SerializeTupleVariant = Impossible<String, NotNumbers>;
    type SerializeMap = Impossible<String, NotNumbers>;
    type SerializeStruct = Impossible<String, NotNumbers>;
    type SerializeStructVariant = Impossible<String, NotNumbers>;

    fn serialize_str(self, v: &str) -> Result<String, NotNumbers> {
        Ok(v.into())
    }
    fn serialize_unit_variant(
        self,
        _: &'static str,
        _: u32,
        v: &'static str,
    ) -> Result<String, NotNumbers> {
        Ok(v.into())
    }
    reject! {
        serialize_bool(bool) "key bool";
        serialize_i8(i8) "key i8";
        serialize_i16(i16) "key i16";
        serialize_i32(i32) "key i32";
        serialize_i64(i64) "key i64";
        serialize_u8(u8) "key u8";
        serialize_u16(u16) "key u16";
        serialize_u32(u32) "key u32";
        serialize_u64(u64) "key u64";
        serialize_f32(f32) "key f32";
        serialize_f64(f64) "key f64";
        serialize_char(char) "key char";
        serialize_bytes(&[u8]) "key byte string";
        serialize_none() "key none";
        serialize_unit() "key unit";
        serialize_unit_struct(&'static str) "key unit struct";
    }
    fn serialize_some<T: Serialize + ?Sized>(self, _: &T) -> Result<String, NotNumbers> {
        unsupported("key option")
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        v: &T,
    ) -> Result<String, NotNumbers> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<String, NotNumbers> {
        unsupported("key enum")
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotNumbers> {
        unsupported("key sequence")
    }
    fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, NotNumbers> {
        unsupported("key tuple")
    }
    fn serialize_tuple_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleStruct, NotNumbers> {
        unsupported("key tuple struct")
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeTupleVariant, NotNumbers> {
        unsupported("key enum")
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotNumbers> {
        unsupported("key map")
    }
    fn serialize_struct(
        self,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStruct, NotNumbers> {
        unsupported("key struct")
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Self::SerializeStructVariant, NotNumbers> {
        unsupported("key enum")
    }
}

/// What the top level of [`Fields`] and [`KeyNames`] does with one entry.
trait Collect {
    fn entry(&mut self, key: String, value: Option<f64>);
}

impl Collect for Fields<'_> {
    fn entry(&mut self, key: String, value: Option<f64>) {
        if let Some(v) = value {
            self.0.insert(key, v);
        }
    }
}

impl Collect for KeyNames<'_> {
    fn entry(&mut self, key: String, _: Option<f64>) {
        self.0.push(key);
    }
}

/// The top-level serializer of [`Fields`] and [`KeyNames`]: a struct, a map, or an `Option`
/// of one (nothing for `None`).
macro_rules! top_level {
    ($t:ident) => {
        impl<'a> ser::Serializer for $t<'a> {
            type Ok = ();
            type Error = NotNumbers;
            type SerializeSeq = Impossible<(), NotNumbers>;
            type SerializeTuple = Impossible<(), NotNumbers>;
            type SerializeTupleStruct = Impossible<(), NotNumbers>;
            type SerializeTupleVariant = Impossible<(), NotNumbers>;
            type SerializeMap = Entries<$t<'a>>;
            type SerializeStruct = Entries<$t<'a>>;
            type SerializeStructVariant = Impossible<(), NotNumbers>;

            fn serialize_struct(
                self,
                _: &'static str,
                _: usize,
            ) -> Result<Self::SerializeStruct, NotNumbers> {
                Ok(Entries(self, None))
            }
            fn serialize_map(self, _: Option<usize>) -> Result<Self::SerializeMap, NotNumbers> {
                Ok(Entries(self, None))
            }
            fn serialize_none(self) -> Result<(), NotNumbers> {
                Ok(())
            }
            fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), NotNumbers> {
                v.serialize(self)
            }
            fn serialize_newtype_struct<T: Serialize + ?Sized>(
                self,
                _: &'static str,
                v: &T,
            ) -> Result<(), NotNumbers> {
                v.serialize(self)
            }
            reject! {
                serialize_bool(bool) "top-level bool";
                serialize_i8(i8) "top-level i8";
                serialize_i16(i16) "top-level i16";
                serialize_i32(i32) "top-level i32";
                serialize_i64(i64) "top-level i64";
                serialize_u8(u8) "top-level u8";
                serialize_u16(u16) "top-level u16";
                serialize_u32(u32) "top-level u32";
                serialize_u64(u64) "top-level u64";
                serialize_f32(f32) "top-level f32";
                serialize_f64(f64) "top-level f64";
                serialize_char(char) "top-level char";
                serialize_str(&str) "top-level string";
                serialize_bytes(&[u8]) "top-level byte string";
                serialize_unit() "top-level unit";
                serialize_unit_struct(&'static str) "top-level unit struct";
                serialize_unit_variant(&'static str, u32, &'static str) "top-level enum";
            }
            fn serialize_newtype_variant<T: Serialize + ?Sized>(
                self,
                _: &'static str,
                _: u32,
                _: &'static str,
                _: &T,
            ) -> Result<(), NotNumbers> {
                unsupported("top-level enum")
            }
            fn serialize_seq(self, _: Option<usize>) -> Result<Self::SerializeSeq, NotNumbers> {
                unsupported("top-level sequence")
            }
            fn serialize_tuple(self, _: usize) -> Result<Self::SerializeTuple, NotNumbers> {
                unsupported("top-level tuple")
            }
            fn serialize_tuple_struct(
                self,
                _: &'static str,
                _: usize,
            ) -> Result<Self::SerializeTupleStruct, NotNumbers> {
                unsupported("top-level tuple struct")
            }
            fn serialize_tuple_variant(
                self,
                _: &'static str,
                _: u32,
                _: &'static str,
                _: usize,
            ) -> Result<Self::SerializeTupleVariant, NotNumbers> {
                unsupported("top-level enum")
            }
            fn serialize_struct_variant(
                self,
                _: &'static str,
                _: u32,
                _: &'static str,
                _: usize,
            ) -> Result<Self::SerializeStructVariant, NotNumbers> {
                unsupported("top-level enum")
            }
        }
    };
}
top_level!(Fields);
top_level!(KeyNames);

/// The entries of a top-level struct or map (the pending key of a map in `.1`).
struct Entries<C>(C, Option<String>);

impl<C: Collect> ser::SerializeStruct for Entries<C> {
    type Ok = ();
    type Error = NotNumbers;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        v: &T,
    ) -> Result<(), NotNumbers> {
        let n = v
            .serialize(Number)
            .map_err(|e| NotNumbers(format!("field {key}: {}", e.0)))?;
        self.0.entry(key.into(), n);
        Ok(())
    }
    fn skip_field(&mut self, key: &'static str) -> Result<(), NotNumbers> {
        self.0.entry(key.into(), None);
        Ok(())
    }
    fn end(self) -> Result<(), NotNumbers> {
        Ok(())
    }
}

impl<C: Collect> ser::SerializeMap for Entries<C> {
    type Ok = ();
    type Error = NotNumbers;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), NotNumbers> {
        self.1 = Some(key.serialize(Key)?);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), NotNumbers> {
        let key = self.1.take().unwrap_or_default();
        let n = v
            .serialize(Number)
            .map_err(|e| NotNumbers(format!("entry {key}: {}", e.0)))?;
        self.0.entry(key, n);
        Ok(())
    }
    fn end(self) -> Result<(), NotNumbers> {
        Ok(())
    }
}
