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
// `chapter` and `logs` features, Cargo.toml); the conversion helpers
// ([`values`], [`objects`], [`plain`], [`guarded`]), and the
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
mod objects;
pub mod plain;
#[cfg(feature = "logs")]
pub mod real_log;
#[cfg(feature = "chapter")]
pub mod sensor_fusion;
#[cfg(feature = "chapter")]
pub mod two_cell_table;
mod values;

pub(crate) use objects::*;
pub(crate) use values::*;

#[wasm_bindgen]
extern "C" {
    /// The host's monotonic clock, declared with `catch` (browsers and Node
    /// both have `performance.now`): the core has no clock of its own in
    /// wasm, and an exception unwinding through a binding that holds a
    /// session borrowed would leave it so.
    #[wasm_bindgen(catch, js_namespace = performance, js_name = now)]
    fn performance_now() -> Result<f64, JsValue>;
}

/// Milliseconds on the host's clock; NaN (a time of "unknown") on a host
/// without `performance.now`, rather than an exception through wasm.
pub(crate) fn now_ms() -> f64 {
    performance_now().unwrap_or(f64::NAN)
}

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
        crate::render::viewport::render_grid_rgba(grid, &mut self.0)
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
