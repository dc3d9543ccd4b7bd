//! The JavaScript surface: one file per widget, each a thin wrapper that
//! converts types, and turns [`crate::OccError`] into a JavaScript `Error`
//! through `?` (`JsError` takes any `std::error::Error`). No algorithm lives
//! here. The core validates every value; the bindings check only what
//! JavaScript's loose types can break before a value reaches it (a number
//! where a string belongs, an array for a settings object, a fractional or
//! negative index), with the helpers below, so that those too come back as
//! an `Error` naming the parameter.

use wasm_bindgen::prelude::*;

#[cfg(feature = "bench")]
pub mod bench;
pub mod cell_filter;
pub mod doorway_trap;
pub mod inverse_workbench;
pub mod map_weaver;
pub mod plain;
pub mod real_log;
pub mod sensor_fusion;
pub mod two_cell_table;

#[wasm_bindgen(start)]
fn start() {
    // A panic would be a bug (every input path returns errors); if one ever
    // happens, make its message readable in the console.
    console_error_panic_hook::set_once();
}

/// The model values the widgets keep to (`crate::apps::Constants`): `{
/// cellFilter: { workedExample, l0Lesson }, inverseWorkbench: { zMax,
/// maxDensity }, sensorFusion: { defaultLidarBeams, maxLidarBeams },
/// twoCellTable: { maxRange, halfConeDeg } }`, each preset `{ pOcc, pFree,
/// prior, clamp, readings, subtractPrior }`.
#[wasm_bindgen]
pub fn constants() -> Result<JsValue, JsError> {
    to_js(&crate::apps::Constants::chapter())
}

/// Serialises a small readout for JavaScript (plain objects, not Maps).
pub(crate) fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let serializer = serde_wasm_bindgen::Serializer::json_compatible();
    value
        .serialize(&serializer)
        .map_err(|e| JsError::new(&format!("cannot pass a readout to JavaScript: {e}")))
}

/// Reads a value from JavaScript, naming what it is and, when one field of
/// it is wrong, the path to that field (`invalid scene.sonar.sub_rays:
/// ...`). Use [`object_from_js`] for settings objects; this one is for
/// values that may legitimately be strings or numbers (an enum's name).
pub(crate) fn from_js<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
) -> Result<T, JsError> {
    let value = plain::plain_copy(&value)
        .map_err(|reason| JsError::new(&format!("invalid {what}: {reason}")))?;
    plain::read_strict(value).map_err(|(path, reason)| {
        if path.is_empty() {
            JsError::new(&format!("invalid {what}: {reason}"))
        } else {
            JsError::new(&format!("invalid {what}.{path}: {reason}"))
        }
    })
}

/// Reads a settings object: a plain object of named fields. Anything else
/// (a string, a number, `null`, an array) is refused first: the
/// deserializer would read an array's missing named fields as absent and
/// quietly take every default.
pub(crate) fn object_from_js<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
) -> Result<T, JsError> {
    if !value.is_object() || js_sys::Array::is_array(&value) {
        return Err(JsError::new(&format!(
            "invalid {what}: {} (expected an object of named settings)",
            describe(&value)
        )));
    }
    from_js(what, value)
}

/// A JavaScript value as a reader would write it: its JSON (cut short
/// when long), or its type when it has no JSON (`undefined`, a function).
pub(crate) fn describe(value: &JsValue) -> String {
    const LONG: usize = 60;
    // JSON writes NaN and the infinities as null.
    if let Some(v) = value.as_f64() {
        return crate::error::show(v);
    }
    match js_sys::JSON::stringify(value)
        .ok()
        .and_then(|s| s.as_string())
    {
        Some(text) if text.chars().count() > LONG => {
            let head: String = text.chars().take(LONG).collect();
            format!("{head}...")
        }
        Some(text) => text,
        None if value.is_undefined() => "undefined".into(),
        None => value
            .js_typeof()
            .as_string()
            .map_or_else(|| "a value".into(), |t| format!("a {t}")),
    }
}

/// A number parameter from JavaScript, exactly as JavaScript holds it.
///
/// Every number parameter of the bindings is declared as `JsValue` and read
/// here, never as `f64`: for an `f64` the generated glue converts the
/// argument with JavaScript's `ToNumber` after it has taken the instance's
/// pointer, so an object whose `valueOf` calls `free()` on that instance
/// would leave the call running on freed memory. `as_f64` reads a number
/// and nothing else (no `valueOf`, no string parsing); NaN and the
/// infinities pass, for the core to judge by name.
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

/// A string parameter from JavaScript. Declared as `JsValue` rather than
/// `&str`: the glue's own string conversion fails on a number or an object
/// with a `TypeError` (or worse) that names nothing.
pub(crate) fn string_from_js(
    field: &str,
    value: &JsValue,
    expected: &str,
) -> Result<String, JsError> {
    value.as_string().ok_or_else(|| {
        JsError::new(&format!(
            "invalid {field}: {} (expected {expected})",
            describe(value)
        ))
    })
}

/// Bytes from JavaScript: a `Uint8Array` (a Node `Buffer` is one) or an
/// `ArrayBuffer`. Declared as `JsValue` rather than `&[u8]`: the glue's own
/// copy reads any array-like without a word (a string as its characters'
/// numbers, a number or an object as no bytes at all).
pub(crate) fn bytes_from_js(
    field: &str,
    value: &JsValue,
    expected: &str,
) -> Result<Vec<u8>, JsError> {
    if let Some(bytes) = value.dyn_ref::<js_sys::Uint8Array>() {
        Ok(bytes.to_vec())
    } else if value.is_instance_of::<js_sys::ArrayBuffer>() {
        Ok(js_sys::Uint8Array::new(value).to_vec())
    } else {
        Err(JsError::new(&format!(
            "invalid {field}: {} (expected {expected})",
            describe(value)
        )))
    }
}

/// An RGBA image of a map, kept in wasm memory so that a widget draws it
/// through a `Uint8ClampedArray` view over `memory.buffer` instead of
/// copying cells one by one (rebuild the view when `memory.buffer` changes).
#[derive(Default)]
pub(crate) struct Pixels(Vec<u8>);

impl Pixels {
    /// Renders `grid` (north up) and returns the address of its pixels.
    pub(crate) fn render(&mut self, grid: &crate::grid::LogOddsGrid) -> *const u8 {
        let n = grid.geometry().len() * 4;
        self.0.resize(n, 0);
        crate::render::gray::render_grid_rgba(grid, &mut self.0)
            .expect("the buffer was just sized to the grid");
        self.0.as_ptr()
    }
}

/// A ROS `map_server` pair for JavaScript: `{ pgm: Uint8Array, yaml: string }`.
pub(crate) fn map_pair_to_js(
    pair: &crate::io::map_server::MapServerPair,
) -> Result<JsValue, JsError> {
    let out = js_sys::Object::new();
    let set = |key: &str, value: JsValue| {
        js_sys::Reflect::set(&out, &JsValue::from_str(key), &value)
            .map(|_| ())
            .map_err(|_| JsError::new("cannot build the export object"))
    };
    set("pgm", js_sys::Uint8Array::from(pair.pgm.as_slice()).into())?;
    set("yaml", JsValue::from_str(&pair.yaml))?;
    Ok(out.into())
}

/// Optional settings: `undefined` or `null` take `default()`, anything else
/// must be an object of named settings (see [`object_from_js`]).
pub(crate) fn object_or_default<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
    default: impl FnOnce() -> T,
) -> Result<T, JsError> {
    if value.is_undefined() || value.is_null() {
        Ok(default())
    } else {
        object_from_js(what, value)
    }
}
