//! Reading values from JavaScript without letting JavaScript throw through
//! the core.
//!
//! An exception that unwinds through wasm skips the exits of every Rust
//! frame on the way: the instance a method borrowed stays borrowed (each
//! later call fails with "recursive use of an object"), and the stack
//! those frames took is never given back (enough such calls and the core
//! writes past its stack: "memory access out of bounds"). So every call
//! this layer makes on a value from JavaScript is one that cannot throw
//! (`typeof` tests) or one declared with `catch`, whose exception comes
//! back as a value (`Reflect`, and the imports below). The settings reader
//! ([`super::plain`]) and the parameter helpers of [`super`] are built on
//! these; no binding calls a plain `js_sys` accessor on what JavaScript sent.
//!
//! Reading can still run the page's code (a getter, a Proxy trap): what
//! that code throws is caught the same way, and what it does to the
//! instance being called (`free()`, another call) is refused by the glue,
//! since the instance is borrowed for the whole call.

use js_sys::{
    Array, ArrayBuffer, DataView, Function, JsString, Object, Reflect, Symbol, Uint8Array,
};
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
extern "C" {
    /// `Array.isArray`, which throws on a revoked Proxy.
    #[wasm_bindgen(catch, js_namespace = Array, js_name = isArray)]
    fn array_is_array(value: &JsValue) -> Result<bool, JsValue>;

    /// A view of wasm memory that bytes are copied into.
    #[wasm_bindgen(extends = Uint8Array)]
    type MemoryView;

    /// `view.set(source)`: copies a genuine typed array by its internal
    /// slots (no code of the source runs).
    #[wasm_bindgen(catch, method, js_name = set)]
    fn set_from(view: &MemoryView, source: &Uint8Array) -> Result<(), JsValue>;
}

/// The longest text of a thrown message kept in an error, characters.
const THROWN_TEXT: u32 = 200;

/// Why reading a value failed, from what reading it threw: the message of
/// the thrown `Error` (read with `Reflect`, so that a getter on it cannot
/// throw again), cut short, or "an exception".
pub(crate) fn thrown(e: JsValue) -> String {
    let message = if e.is_object() {
        Reflect::get(&e, &JsValue::from_str("message")).unwrap_or(JsValue::UNDEFINED)
    } else {
        e
    };
    let text = short_string(&message, THROWN_TEXT).unwrap_or_else(|| "an exception".into());
    format!("reading it threw: {text}")
}

/// The first `max` characters of a string (`...` marking a cut), or `None`
/// for anything that is not a string. A string of millions of characters is
/// cut in JavaScript, before anything is copied into wasm memory.
pub(crate) fn short_string(value: &JsValue, max: u32) -> Option<String> {
    let text: &JsString = value.dyn_ref()?;
    if text.length() <= max {
        Some(String::from(text))
    } else {
        Some(format!("{}...", String::from(text.slice(0, max))))
    }
}

/// True for an array (or a Proxy of one); an error naming what it threw
/// for a value that cannot say (a revoked Proxy).
pub(crate) fn is_array(value: &JsValue) -> Result<bool, String> {
    if !value.is_object() {
        return Ok(false);
    }
    array_is_array(value).map_err(thrown)
}

/// The length of an array (or of a Proxy of one), or `None` for anything
/// else; an error when asking throws or the length is no count.
pub(crate) fn array_length(value: &JsValue) -> Result<Option<usize>, String> {
    if !is_array(value)? {
        return Ok(None);
    }
    let length = Reflect::get(value, &JsValue::from_str("length")).map_err(thrown)?;
    match length.as_f64() {
        Some(n) if n >= 0.0 && n.fract() == 0.0 && n <= u32::MAX as f64 => Ok(Some(n as usize)),
        _ => Err("its length is not a count".into()),
    }
}

/// Item `i` of an array (or of a Proxy of one: its trap runs, caught).
pub(crate) fn array_item(array: &JsValue, i: usize) -> Result<JsValue, String> {
    Reflect::get_f64(array, i as f64).map_err(thrown)
}

/// The getter a built-in prototype has for `key`. Called on another value
/// it reads that value's internal slot: no code of the value runs, and a
/// value without the slot (a Proxy, a look-alike object) is told apart.
fn builtin_getter(prototype: &Object, key: &JsValue) -> Option<Function> {
    let descriptor = Reflect::get_own_property_descriptor(prototype, key).ok()?;
    Reflect::get(&descriptor, &JsValue::from_str("get"))
        .ok()?
        .dyn_into()
        .ok()
}

/// `getter` called on `this`, or `None` when it throws (a value without
/// the getter's slot).
fn call_getter(getter: &Function, this: &JsValue) -> Option<JsValue> {
    Reflect::apply(getter, this, &Array::new()).ok()
}

/// A length read by a built-in getter, as a count.
fn as_count(value: JsValue) -> Option<usize> {
    value
        .as_f64()
        .filter(|n| *n >= 0.0 && n.fract() == 0.0)
        .map(|n| n as usize)
}

/// Binary data JavaScript sent, told by its internal slots (no code of the
/// value runs, and a Proxy or an object dressed as one is none): its kind
/// (`Uint8Array`, any other typed array, `ArrayBuffer`, `DataView`) and its
/// length, items of a typed array and bytes of the others. Read without
/// touching its items or keys: a view of millions of bytes answers at once.
#[inline(never)]
pub(crate) fn binary_data(value: &JsValue) -> Option<(String, usize)> {
    if !value.is_object() {
        return None;
    }
    // %TypedArray%.prototype, two levels above a Uint8Array, holds the
    // typed arrays' getters: its tag getter names a typed array's kind,
    // and is undefined for anything else.
    let typed = |key: &JsValue| slot(Uint8Array::new_with_length(0).into(), 2, key, value);
    if let Some(kind) = typed(&Symbol::to_string_tag())?.as_string() {
        return Some((kind, as_count(typed(&"length".into())?)?));
    }
    let byte_length = "byteLength".into();
    let bytes = |kind: &str, instance: JsValue| {
        Some((
            kind.into(),
            as_count(slot(instance, 1, &byte_length, value)?)?,
        ))
    };
    bytes("ArrayBuffer", ArrayBuffer::new(0).into()).or_else(|| {
        let view = DataView::new(&ArrayBuffer::new(0), 0, 0);
        bytes("DataView", view.into())
    })
}

/// What the getter for `key` on the prototype `up` levels above
/// `instance` reads of `value`'s internal slot; `None` when `value` has no
/// such slot.
fn slot(instance: JsValue, up: usize, key: &JsValue, value: &JsValue) -> Option<JsValue> {
    let mut prototype = instance;
    for _ in 0..up {
        prototype = Reflect::get_prototype_of(&prototype).ok()?.into();
    }
    call_getter(&builtin_getter(prototype.unchecked_ref(), key)?, value)
}

/// [`binary_data`] as a reader would say it: "a Uint8Array of 50,000,000
/// items", "an ArrayBuffer of 16 bytes".
#[inline(never)]
pub(crate) fn describe_binary(value: &JsValue) -> Option<String> {
    let (kind, len) = binary_data(value)?;
    let article = match kind.as_bytes().first() {
        Some(b'A' | b'I') => "an",
        _ => "a",
    };
    let unit = if kind.ends_with("Array") {
        "items"
    } else {
        "bytes"
    };
    let mut grouped = len.to_string();
    let mut at = grouped.len();
    while at > 3 {
        at -= 3;
        grouped.insert(at, ',');
    }
    Some(format!("{article} {kind} of {grouped} {unit}"))
}

/// Bytes JavaScript sent, checked by their internal slots
/// ([`binary_data`]): a genuine `Uint8Array` (a Node `Buffer` is one) or
/// a genuine `ArrayBuffer`, with its length. `None` for anything else, a
/// Proxy of either and an object dressed as one included: their `length`
/// would be whatever their code says, and copying trusts it.
pub(crate) fn byte_source(value: &JsValue) -> Option<(Uint8Array, usize)> {
    let (kind, len) = binary_data(value)?;
    match kind.as_str() {
        "Uint8Array" => Some((value.clone().unchecked_into(), len)),
        // A detached buffer reads as empty; no view can be made over it.
        "ArrayBuffer" if len == 0 => Some((Uint8Array::new_with_length(0), 0)),
        "ArrayBuffer" => Some((Uint8Array::new(value), len)),
        _ => None,
    }
}

/// Copies `len` bytes of `source` (from [`byte_source`]) into wasm memory;
/// an error when there is no room for them.
pub(crate) fn copy_bytes(source: &Uint8Array, len: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    out.try_reserve_exact(len)
        .map_err(|_| format!("{len} bytes, more than the memory left"))?;
    out.resize(len, 0);
    if len > 0 {
        // Safety: the view is used at once, before anything could allocate
        // (and so move) wasm memory.
        let view: MemoryView =
            unsafe { Uint8Array::view_mut_raw(out.as_mut_ptr(), len) }.unchecked_into();
        view.set_from(source).map_err(thrown)?;
    }
    Ok(out)
}
