//! Settings objects from JavaScript: read strictly through a plain copy
//! ([`super::plain`]), a refusal naming the path to the wrong field.

use super::{describe, guarded, plain};
use wasm_bindgen::prelude::*;

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
/// number, `null`, an array, a typed array or a buffer; a revoked Proxy by
/// what asking it threw).
fn check_object(what: &str, value: &JsValue) -> Result<(), JsError> {
    match guarded::is_array(value) {
        Ok(false) if value.is_object() && guarded::binary_data(value).is_none() => Ok(()),
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
    let merged = super::to_js(current)?;
    let cannot = |_: JsValue| JsError::new(&format!("cannot apply the {what} patch"));
    let patch: &js_sys::Object = patch.unchecked_ref();
    for key in js_sys::Object::keys(patch).iter() {
        let value = js_sys::Reflect::get(patch, &key).map_err(cannot)?;
        plain::define_field(merged.unchecked_ref(), &key, &value).map_err(cannot)?;
    }
    plain::read_strict(merged).map_err(|(path, reason)| invalid_at(what, &path, &reason))
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
