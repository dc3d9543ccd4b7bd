//! Settings objects from JavaScript, read strictly and safely.
//!
//! Two steps, for every settings and scene object a widget sends:
//!
//! 1. [`plain_copy`] copies the value into plain objects, arrays and
//!    primitives through calls that catch what JavaScript throws
//!    ([`super::guarded`]), so a throwing getter, a Proxy (revoked or not)
//!    or a function becomes an error naming the path to it instead of an
//!    exception unwinding through the core (which would leave a session
//!    marked "in use" for good). The copy has a budget of nodes and depth,
//!    and keeps an own `"__proto__"` key as the field it is, for step 2
//!    to refuse by name (an assignment would make it the copy's prototype,
//!    and the field would vanish unread).
//! 2. [`Strict`] reads the copy with serde, refusing any field the Rust
//!    struct does not have, at any depth, and [`read_strict`] names the path
//!    to the field an error is about (`invalid scene.lidar: unknown field
//!    "beems"`, `invalid scene.sonar.sub_rays: ...`). serde-wasm-bindgen
//!    alone reads only the fields it knows, so a misspelt one would pass
//!    unnoticed.

use super::guarded::{describe_binary, is_array, thrown};
use js_sys::{Array, Object, Reflect};
use wasm_bindgen::JsValue;

mod strict;
pub use strict::{read_strict, Strict};

/// The most values (objects, arrays and primitives together) a settings
/// object may hold: scenes carry lists of boxes and rooms, never more than
/// a few thousand values.
pub const MAX_NODES: usize = 100_000;
/// The deepest nesting a settings object may have.
pub const MAX_DEPTH: usize = 32;

/// How much of a value a copy may take.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    /// Values (objects, arrays, primitives and keys together).
    pub nodes: usize,
    /// Levels of nesting below the value itself.
    pub depth: usize,
}

/// The budget of a settings object.
pub const SETTINGS: Budget = Budget {
    nodes: MAX_NODES,
    depth: MAX_DEPTH,
};

/// Why a value has no plain copy: the path to the part that failed (empty
/// for the value itself, `lidar.beams`, `rooms[2]`) and the reason.
pub type CopyError = (String, String);

/// `path`, one segment (`key` or `[i]`) further out.
pub fn path_under(segment: &str, path: &str) -> String {
    if path.is_empty() {
        segment.to_string()
    } else if path.starts_with('[') {
        format!("{segment}{path}")
    } else {
        format!("{segment}.{path}")
    }
}

/// A plain copy of a settings object (see the module doc), or why there is
/// none.
pub fn plain_copy(value: &JsValue) -> Result<JsValue, CopyError> {
    copy_within(value, SETTINGS)
}

/// A plain copy of `value` within `budget`, or why there is none.
pub fn copy_within(value: &JsValue, budget: Budget) -> Result<JsValue, CopyError> {
    let mut nodes = 0;
    copy(value, 0, budget, &mut nodes)
}

fn copy(
    value: &JsValue,
    depth: usize,
    budget: Budget,
    nodes: &mut usize,
) -> Result<JsValue, CopyError> {
    let here = |reason: String| (String::new(), reason);
    *nodes += 1;
    if *nodes > budget.nodes {
        return Err(more_than(budget));
    }
    if depth > budget.depth {
        return Err(here(format!("nested deeper than {} levels", budget.depth)));
    }
    // Functions and symbols are no settings (and a function may be a
    // revoked Proxy, which throws at every question).
    if value.is_function() {
        return Err(here("a function (expected plain data)".into()));
    }
    if value.is_symbol() {
        return Err(here("a symbol (expected plain data)".into()));
    }
    if !value.is_object() {
        return Ok(value.clone());
    }
    if is_array(value).map_err(here)? {
        let len = Reflect::get(value, &JsValue::from_str("length"))
            .map_err(|e| here(thrown(e)))?
            .as_f64()
            .unwrap_or(0.0);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN length is refused too
        if !(len <= budget.nodes as f64) {
            return Err(here(format!(
                "an array longer than {} values",
                budget.nodes
            )));
        }
        let out = Array::new();
        for i in 0..len as u32 {
            let at = |(path, reason): CopyError| (path_under(&format!("[{i}]"), &path), reason);
            let item = Reflect::get_u32(value, i).map_err(|e| at(here(thrown(e))))?;
            out.push(&copy(&item, depth + 1, budget, nodes).map_err(at)?);
        }
        return Ok(out.into());
    }
    // A typed array's keys are its items (millions of them, to walk before
    // refusing), and a buffer's bytes are no keys at all (it would read as
    // `{}`): neither is settings.
    if let Some(binary) = describe_binary(value) {
        return Err(here(format!("{binary} (expected plain data)")));
    }
    let out = Object::new();
    let keys = Reflect::own_keys(value).map_err(|e| here(thrown(e)))?;
    // Each key is a value of the budget: more keys than are left is
    // refused before any is read.
    if keys.length() as usize > budget.nodes - *nodes {
        return Err(more_than(budget));
    }
    for key in keys.iter() {
        // Symbol keys are no settings.
        let Some(name) = key.as_string() else {
            continue;
        };
        *nodes += 1;
        if *nodes > budget.nodes {
            return Err(more_than(budget));
        }
        let at = |(path, reason): CopyError| (path_under(&name, &path), reason);
        let item = Reflect::get(value, &key).map_err(|e| at(here(thrown(e))))?;
        if item.is_undefined() {
            continue;
        }
        let item = copy(&item, depth + 1, budget, nodes).map_err(at)?;
        define_field(&out, &key, &item).map_err(|e| at(here(thrown(e))))?;
    }
    Ok(out.into())
}

/// The refusal of a value with more parts than `budget` allows. Out of
/// line: [`copy`] refuses in three places.
#[inline(never)]
fn more_than(budget: Budget) -> CopyError {
    (String::new(), format!("more than {} values", budget.nodes))
}

/// Gives `target` the own field `key`: defined, not assigned, so that a
/// key "__proto__" is a field like any other rather than the object's new
/// prototype (see the module doc).
pub fn define_field(target: &Object, key: &JsValue, value: &JsValue) -> Result<(), JsValue> {
    let field = Object::new();
    for (flag, on) in [
        ("value", value),
        ("enumerable", &JsValue::TRUE),
        ("writable", &JsValue::TRUE),
        ("configurable", &JsValue::TRUE),
    ] {
        Reflect::set(&field, &JsValue::from_str(flag), on)?;
    }
    Reflect::define_property(target, key, &field).map(|_| ())
}
