//! The JavaScript surface: one file per widget, each a thin wrapper that
//! converts types, and turns [`crate::OccError`] into a JavaScript `Error`
//! through `?` (`JsError` takes any `std::error::Error`). No algorithm lives
//! here. The core validates every value; the bindings check only what
//! JavaScript's loose types can break before a value reaches it (a number
//! where a string belongs, an array for a settings object, a fractional or
//! negative index), with the helpers below, so that those too come back as
//! an `Error` naming the parameter.
//!
//! Every parameter is declared as `JsValue` and read by these helpers,
//! never as `f64`, `bool` or `&str`: for those the generated glue converts
//! the argument with JavaScript's own coercion (`valueOf`, `toString`,
//! `Symbol.toPrimitive`) after it has taken the instance's pointer, so an
//! object whose `valueOf` calls `free()` on that instance would leave the
//! call running on freed memory. The helpers read a value by its type
//! alone, and reach into objects only through [`guarded`], so that nothing
//! JavaScript throws unwinds through the core.

use wasm_bindgen::prelude::*;

// Each widget's bindings belong to one of the two wasm modules (the
// `chapter` and `logs` features, Cargo.toml); the helpers below, and the
// map archive every export button uses, to both.
#[cfg(feature = "bench")]
pub mod bench;
#[cfg(feature = "chapter")]
pub mod cell_filter;
#[cfg(feature = "chapter")]
pub mod doorway_trap;
pub mod guarded;
#[cfg(feature = "chapter")]
pub mod inverse_workbench;
pub mod map_files;
#[cfg(feature = "chapter")]
pub mod map_weaver;
pub mod plain;
#[cfg(feature = "logs")]
pub mod real_log;
#[cfg(feature = "chapter")]
pub mod sensor_fusion;
#[cfg(feature = "chapter")]
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
#[cfg(feature = "chapter")]
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

/// An error about `what` (`scene`), at `path` inside it (`lidar.beams`,
/// `[2]`, or empty for the value itself).
fn invalid_at(what: &str, path: &str, reason: &str) -> JsError {
    if path.is_empty() {
        JsError::new(&format!("invalid {what}: {reason}"))
    } else {
        JsError::new(&format!(
            "invalid {}: {reason}",
            plain::path_under(what, path)
        ))
    }
}

/// Reads a value from JavaScript, naming what it is and, when one field of
/// it is wrong, the path to that field (`invalid scene.sonar.sub_rays:
/// ...`). Use [`object_from_js`] for settings objects; this one is for
/// values that may legitimately be strings or numbers (an enum's name).
pub(crate) fn from_js<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
) -> Result<T, JsError> {
    let value =
        plain::plain_copy(&value).map_err(|(path, reason)| invalid_at(what, &path, &reason))?;
    plain::read_strict(value).map_err(|(path, reason)| invalid_at(what, &path, &reason))
}

/// Refuses anything but a plain object of named fields (a string, a
/// number, `null`, an array; a revoked Proxy by what asking it threw).
fn check_object(what: &str, value: &JsValue) -> Result<(), JsError> {
    match guarded::is_array(value) {
        Ok(false) if value.is_object() => Ok(()),
        Err(reason) => Err(invalid_at(what, "", &reason)),
        _ => Err(JsError::new(&format!(
            "invalid {what}: {} (expected an object of named settings)",
            describe(value)
        ))),
    }
}

/// Reads a settings object: a plain object of named fields. Anything else
/// is refused first (see [`check_object`]): the deserializer would read an
/// array's missing named fields as absent and quietly take every default.
pub(crate) fn object_from_js<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
) -> Result<T, JsError> {
    check_object(what, &value)?;
    from_js(what, value)
}

/// Reads a patch of settings: an object of some of `current`'s fields,
/// each replacing that field (`null` clears an optional one); the fields
/// left out keep their values. The result is read as strictly as a whole
/// settings object, so a misspelt field is refused by name.
#[cfg(feature = "chapter")]
pub(crate) fn patch_from_js<T: serde::Serialize + serde::de::DeserializeOwned>(
    what: &str,
    current: &T,
    patch: JsValue,
) -> Result<T, JsError> {
    check_object(what, &patch)?;
    let patch =
        plain::plain_copy(&patch).map_err(|(path, reason)| invalid_at(what, &path, &reason))?;
    let merged = to_js(current)?;
    let cannot = |_: JsValue| JsError::new(&format!("cannot apply the {what} patch"));
    let patch: &js_sys::Object = patch.unchecked_ref();
    for key in js_sys::Object::keys(patch).iter() {
        let value = js_sys::Reflect::get(patch, &key).map_err(cannot)?;
        plain::define_field(merged.unchecked_ref(), &key, &value).map_err(cannot)?;
    }
    plain::read_strict(merged).map_err(|(path, reason)| invalid_at(what, &path, &reason))
}

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
#[cfg(feature = "chapter")]
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

/// An RGBA image of a map, kept in wasm memory so that a widget draws it
/// through a `Uint8ClampedArray` view over `memory.buffer` instead of
/// copying cells one by one (rebuild the view when `memory.buffer` changes).
#[cfg(feature = "chapter")]
#[derive(Default)]
pub(crate) struct Pixels(Vec<u8>);

#[cfg(feature = "chapter")]
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
#[cfg(feature = "chapter")]
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
