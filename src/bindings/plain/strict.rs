//! Step 2 of [`super`]: the plain copy read with serde, strictly, any
//! field the Rust struct does not have refused at any depth, and the path
//! to the field an error is about kept on the way out.

use crate::bindings::guarded::is_array;
use js_sys::{Array, Object, Reflect};
use serde::de::{
    self, DeserializeSeed, Deserializer, IntoDeserializer, MapAccess, SeqAccess, Visitor,
};
use serde_wasm_bindgen::Error;
use wasm_bindgen::{JsCast, JsValue};

/// Marks an error message that already carries a path: `PATH` + the path +
/// `REASON` + the reason. Built up one field at a time on the way out.
const PATH: char = '\u{1}';
const REASON: char = '\u{2}';

/// An error's text without the "Error: " a JavaScript error's text has.
fn message(e: &Error) -> String {
    let text = e.to_string();
    text.strip_prefix("Error: ").unwrap_or(&text).to_string()
}

/// `e`, one path segment deeper (`key` or `[i]`).
#[inline(never)]
fn under(segment: &str, e: Error) -> Error {
    let text = message(&e);
    let inner = match text.strip_prefix(PATH) {
        Some(rest) if rest.starts_with('[') => format!("{segment}{rest}"),
        Some(rest) => format!("{segment}.{rest}"),
        None => format!("{segment}{REASON}{text}"),
    };
    <Error as de::Error>::custom(format!("{PATH}{inner}"))
}

/// Reads `value` (a plain copy) as `T`, strictly; on error the path to the
/// field (empty at the top) and the reason.
pub fn read_strict<T: serde::de::DeserializeOwned>(value: JsValue) -> Result<T, (String, String)> {
    T::deserialize(Strict(value)).map_err(|e| {
        let text = message(&e);
        match text
            .strip_prefix(PATH)
            .and_then(|rest| rest.split_once(REASON))
        {
            Some((path, reason)) => (path.to_string(), reason.to_string()),
            None => (String::new(), text),
        }
    })
}

/// The fields of a plain object, refusing one the struct does not have.
/// Kept out of line: it is the same for every settings type, and each
/// type's reader would otherwise carry its own copy.
#[inline(never)]
fn known_fields(value: &JsValue, fields: &[&str]) -> Result<Vec<(String, JsValue)>, Error> {
    let object: &Object = value.unchecked_ref();
    let keys = Object::keys(object);
    let mut entries = Vec::with_capacity(keys.length() as usize);
    for key in keys.iter() {
        let key = key.as_string().unwrap_or_default();
        if !fields.contains(&key.as_str()) {
            return Err(<Error as de::Error>::custom(format!(
                "unknown field \"{key}\" (expected {})",
                fields.join(", ")
            )));
        }
        let Ok(item) = Reflect::get(value, &JsValue::from_str(&key)) else {
            return Err(<Error as de::Error>::custom(format!(
                "cannot read field \"{key}\""
            )));
        };
        entries.push((key, item));
    }
    Ok(entries)
}

/// A serde deserializer over a plain copy that refuses unknown fields.
pub struct Strict(pub JsValue);

impl Strict {
    fn loose(self) -> serde_wasm_bindgen::Deserializer {
        serde_wasm_bindgen::Deserializer::from(self.0)
    }

    /// "invalid type: ..., expected ...", without handing the value to the
    /// loose deserializer (which would read it a second way, in more code).
    #[inline(never)]
    fn unexpected(&self, expected: &dyn de::Expected) -> Error {
        let what = crate::bindings::describe(&self.0);
        <Error as de::Error>::invalid_type(de::Unexpected::Other(&what), expected)
    }
}

macro_rules! delegate {
    ($($method:ident),*) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            self.loose().$method(visitor)
        }
    )*};
}

/// Like `delegate`, for a value that `null` is not: refused here as
/// "null" (the loose reader says "unit value").
macro_rules! delegate_not_null {
    ($($method:ident),*) => {$(
        fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
            if self.0.is_null() {
                return Err(self.unexpected(&visitor));
            }
            self.loose().$method(visitor)
        }
    )*};
}

impl<'de> Deserializer<'de> for Strict {
    type Error = Error;

    delegate!(
        deserialize_any,
        deserialize_unit,
        deserialize_identifier,
        deserialize_ignored_any,
        deserialize_map
    );
    delegate_not_null!(
        deserialize_bool,
        deserialize_i8,
        deserialize_i16,
        deserialize_i32,
        deserialize_i64,
        deserialize_u8,
        deserialize_u16,
        deserialize_u32,
        deserialize_u64,
        deserialize_f32,
        deserialize_f64,
        deserialize_char,
        deserialize_str,
        deserialize_string,
        deserialize_bytes,
        deserialize_byte_buf
    );

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        if self.0.is_undefined() || self.0.is_null() {
            visitor.visit_none()
        } else {
            visitor.visit_some(self)
        }
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        self.loose().deserialize_unit_struct(name, visitor)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, Error> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, Error> {
        if !is_array(&self.0).map_err(<Error as de::Error>::custom)? {
            return Err(self.unexpected(&visitor));
        }
        let items: Vec<JsValue> = self.0.unchecked_into::<Array>().iter().collect();
        visitor.visit_seq(Items(items.into_iter().enumerate()))
    }

    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, Error> {
        exactly(&self.0, len)?;
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

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        if !self.0.is_object() || is_array(&self.0).map_err(<Error as de::Error>::custom)? {
            return Err(self.unexpected(&visitor));
        }
        let entries = known_fields(&self.0, fields)?;
        visitor.visit_map(Fields {
            entries: entries.into_iter(),
            key: String::new(),
            value: None,
        })
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Error> {
        // A name, or an object for a variant with data; anything else is
        // refused with the names (the loose reader would name only the
        // Rust type).
        let data =
            self.0.is_object() && !is_array(&self.0).map_err(<Error as de::Error>::custom)?;
        if self.0.is_string() || data {
            return self.loose().deserialize_enum(name, variants, visitor);
        }
        let names: Vec<String> = variants.iter().map(|v| format!("\"{v}\"")).collect();
        let expected = format!("one of {}", names.join(", "));
        Err(self.unexpected(&expected.as_str()))
    }
}

/// Refuses an array of other than `len` items where a fixed number
/// belongs (Map Weaver's two panes): serde reads `len` of them and would
/// drop any past them unread. Out of line, as [`known_fields`] is.
#[inline(never)]
fn exactly(value: &JsValue, len: usize) -> Result<(), Error> {
    // A plain copy's arrays are genuine: their length is no code's answer.
    match is_array(value).map_err(<Error as de::Error>::custom)? {
        true => match value.unchecked_ref::<Array>().length() as usize {
            n if n != len => Err(<Error as de::Error>::custom(format!(
                "an array of {n} (expected exactly {len} items)"
            ))),
            _ => Ok(()),
        },
        false => Ok(()),
    }
}

struct Items(std::iter::Enumerate<std::vec::IntoIter<JsValue>>);

impl<'de> SeqAccess<'de> for Items {
    type Error = Error;
    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Error> {
        match self.0.next() {
            None => Ok(None),
            Some((i, v)) => seed
                .deserialize(Strict(v))
                .map(Some)
                .map_err(|e| under(&format!("[{i}]"), e)),
        }
    }
}

struct Fields {
    entries: std::vec::IntoIter<(String, JsValue)>,
    /// The field being read, and its value until it is read.
    key: String,
    value: Option<JsValue>,
}

impl<'de> MapAccess<'de> for Fields {
    type Error = Error;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        match self.entries.next() {
            None => Ok(None),
            Some((key, value)) => {
                self.value = Some(value);
                // Kept for the path of an error about the value.
                self.key = key;
                let key: de::value::StrDeserializer<Error> = self.key.as_str().into_deserializer();
                seed.deserialize(key).map(Some)
            }
        }
    }
    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, Error> {
        seed.deserialize(Strict(self.value.take().unwrap_or(JsValue::UNDEFINED)))
            .map_err(|e| under(&self.key, e))
    }
}
