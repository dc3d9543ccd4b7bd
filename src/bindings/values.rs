//! Single values from JavaScript (numbers, indices, budgets, strings,
//! bytes), read by their type alone with no coercion (see the module doc of
//! [`super`]), and any value described as a reader would write it.

use super::{guarded, plain};
use wasm_bindgen::prelude::*;

/// The longest text of a value [`describe`] shows, characters.
const DESCRIBED: u32 = 60;

/// How much of an object [`describe`] copies to show it.
const DESCRIBED_OBJECT: plain::Budget = plain::Budget {
    nodes: 40,
    depth: 4,
};

/// A JavaScript value as a reader would write it: its JSON (cut short
/// when long), or its type when it has no JSON (`undefined`, a function).
/// No code of the value runs but its getters and Proxy traps (an object
/// is shown from a small plain copy, never through its own `toJSON` or
/// `valueOf`), and a long string is cut before it is copied into wasm
/// memory.
pub(crate) fn describe(value: &JsValue) -> String {
    // JSON writes NaN and the infinities as null.
    if let Some(v) = value.as_f64() {
        return crate::error::show(v);
    }
    if value.is_undefined() {
        return "undefined".into();
    }
    let shown = |json: Result<js_sys::JsString, JsValue>| {
        json.ok()
            .and_then(|text| guarded::short_string(&text.into(), DESCRIBED))
    };
    // Typed arrays and buffers by their kind and length: their keys are
    // their items, millions of them.
    if let Some(binary) = guarded::describe_binary(value) {
        return binary;
    }
    let text = if value.is_object() {
        match plain::copy_within(value, DESCRIBED_OBJECT) {
            Ok(copy) => shown(js_sys::JSON::stringify(&copy)),
            Err(_) => json_head(value),
        }
    } else if let Some(text) = value.dyn_ref::<js_sys::JsString>() {
        // One character past what is shown, so that the cut is marked.
        shown(js_sys::JSON::stringify(&text.slice(0, DESCRIBED + 1)))
    } else if value.is_null() || value.as_bool().is_some() {
        shown(js_sys::JSON::stringify(value))
    } else {
        None
    };
    match text {
        Some(text) => text,
        None if value.is_object() => match guarded::is_array(value) {
            Ok(true) => "an array".into(),
            _ => "an object".into(),
        },
        None => value
            .js_typeof()
            .as_string()
            .map_or_else(|| "a value".into(), |t| format!("a {t}")),
    }
}

/// The JSON of the first items of an array too large to copy whole for
/// [`describe`], cut where more follows: `[1,1,1,...`. `None` for an
/// object (reading even its keys may be costly: it is shown as "an
/// object").
fn json_head(value: &JsValue) -> Option<String> {
    const ITEMS: usize = 20;
    const ITEM: plain::Budget = plain::Budget { nodes: 8, depth: 2 };
    let len = guarded::array_length(value).ok()??;
    let items = js_sys::Array::new();
    for i in 0..len.min(ITEMS) {
        let item = guarded::array_item(value, i)
            .ok()
            .and_then(|v| plain::copy_within(&v, ITEM).ok())
            .unwrap_or(JsValue::NULL);
        items.push(&item);
    }
    let text = js_sys::JSON::stringify(&items).ok()?;
    // Without the closing bracket: more follows.
    let open = text.length().saturating_sub(1).min(DESCRIBED);
    Some(format!("{}...", String::from(text.slice(0, open))))
}

/// A true-or-false parameter from JavaScript: `true` or `false` and
/// nothing else (no truthiness: `"false"` is a string, not false).
pub(crate) fn bool_from_js(field: &str, value: &JsValue) -> Result<bool, JsError> {
    value.as_bool().ok_or_else(|| {
        JsError::new(&format!(
            "invalid {field}: {} (expected true or false)",
            describe(value)
        ))
    })
}

/// A number parameter from JavaScript, exactly as JavaScript holds it:
/// `as_f64` reads a number and nothing else (no `valueOf`, no string
/// parsing; see the module doc); NaN and the infinities pass, for the core
/// to judge by name.
pub(crate) fn number_from_js(field: &str, value: &JsValue) -> Result<f64, JsError> {
    value.as_f64().ok_or_else(|| {
        JsError::new(&format!(
            "invalid {field}: {} (expected a number)",
            describe(value)
        ))
    })
}

/// An optional number parameter: `undefined` or `null` is `None`, anything
/// else must be a number (see [`number_from_js`]).
pub(crate) fn optional_number_from_js(
    field: &str,
    value: &JsValue,
) -> Result<Option<f64>, JsError> {
    if value.is_undefined() || value.is_null() {
        Ok(None)
    } else {
        number_from_js(field, value).map(Some)
    }
}

/// True for a finite number without a fractional part.
fn is_whole(value: f64) -> bool {
    value.is_finite() && value.fract() == 0.0
}

/// An index from JavaScript (a pane, a scan, a map): a whole number from 0
/// up. A JavaScript number reaches wasm as it is; converting it to an
/// integer type in the glue would wrap -1 or 1e20 silently.
pub(crate) fn index_from_js(field: &str, value: &JsValue) -> Result<usize, JsError> {
    let value = number_from_js(field, value)?;
    if is_whole(value) && value >= 0.0 && value <= usize::MAX as f64 {
        Ok(value as usize)
    } else {
        Err(JsError::new(&format!(
            "invalid {field}: {} (expected a whole number from 0 to {})",
            crate::error::show(value),
            usize::MAX
        )))
    }
}

/// A budget from JavaScript (scans to read, flips to make): a whole number
/// from 0 up, where `Infinity`, or anything larger than the work there is,
/// means "as many as there are".
pub(crate) fn budget_from_js(field: &str, value: &JsValue) -> Result<usize, JsError> {
    let value = number_from_js(field, value)?;
    if value == f64::INFINITY || (is_whole(value) && value >= 0.0) {
        // `as` saturates: past usize::MAX is "no limit" too.
        Ok(value as usize)
    } else {
        Err(JsError::new(&format!(
            "invalid {field}: {} (expected a whole number of at least 0, or Infinity)",
            crate::error::show(value)
        )))
    }
}

/// A pixel or cell coordinate from JavaScript (a pointer position): a whole
/// number. One outside every map (negative, or past `usize`) comes back as
/// `usize::MAX`, which no map holds, so the caller answers "outside".
pub(crate) fn coordinate_from_js(field: &str, value: &JsValue) -> Result<usize, JsError> {
    let value = number_from_js(field, value)?;
    if !is_whole(value) {
        return Err(JsError::new(&format!(
            "invalid {field}: {} (expected a whole number)",
            crate::error::show(value)
        )));
    }
    Ok(if value < 0.0 || value > usize::MAX as f64 {
        usize::MAX
    } else {
        value as usize
    })
}

/// The longest string parameter, characters: names of maps, presets and
/// files are a few dozen.
pub(crate) const MAX_STRING: u32 = 4096;

/// A string parameter from JavaScript. Declared as `JsValue` rather than
/// `&str`: the glue's own string conversion calls `toString` on anything
/// that is not a string. A string longer than [`MAX_STRING`] is refused
/// before it is copied into wasm memory.
pub(crate) fn string_from_js(
    field: &str,
    value: &JsValue,
    expected: &str,
) -> Result<String, JsError> {
    match value.dyn_ref::<js_sys::JsString>() {
        Some(text) if text.length() <= MAX_STRING => Ok(String::from(text)),
        Some(text) => Err(JsError::new(&format!(
            "invalid {field}: {} (expected {expected}, at most {MAX_STRING} characters; this has {})",
            describe(value),
            text.length()
        ))),
        None => Err(JsError::new(&format!(
            "invalid {field}: {} (expected {expected})",
            describe(value)
        ))),
    }
}

/// Bytes from JavaScript: a `Uint8Array` (a Node `Buffer` is one) or an
/// `ArrayBuffer`, told apart by their internal slots
/// ([`guarded::byte_source`]). Declared as `JsValue` rather than `&[u8]`:
/// the glue's own copy reads any array-like without a word (a string as
/// its characters' numbers, a number or an object as no bytes at all), and
/// trusts a `length` that a Proxy or a look-alike object makes up.
pub(crate) fn bytes_from_js(
    field: &str,
    value: &JsValue,
    expected: &str,
) -> Result<Vec<u8>, JsError> {
    let (source, len) = guarded::byte_source(value).ok_or_else(|| {
        JsError::new(&format!(
            "invalid {field}: {} (expected {expected})",
            describe(value)
        ))
    })?;
    guarded::copy_bytes(&source, len)
        .map_err(|reason| JsError::new(&format!("invalid {field}: {reason}")))
}
