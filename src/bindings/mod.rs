//! The JavaScript surface: one file per widget, each a thin wrapper that
//! validates nothing itself (the core does), converts types, and turns
//! [`crate::OccError`] into a JavaScript `Error` through `?` (`JsError`
//! takes any `std::error::Error`). No algorithm lives here.

use wasm_bindgen::prelude::*;

pub mod cell_filter;
pub mod doorway_trap;
pub mod inverse_workbench;
pub mod map_weaver;
pub mod real_log;
pub mod sensor_fusion;

#[wasm_bindgen(start)]
fn start() {
    // A panic would be a bug (every input path returns errors); if one ever
    // happens, make its message readable in the console.
    console_error_panic_hook::set_once();
}

/// Serialises a small readout for JavaScript (plain objects, not Maps).
pub(crate) fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let serializer = serde_wasm_bindgen::Serializer::json_compatible();
    value
        .serialize(&serializer)
        .map_err(|e| JsError::new(&format!("cannot pass a readout to JavaScript: {e}")))
}

/// Reads a settings object from JavaScript, naming the object in the error.
pub(crate) fn from_js<T: serde::de::DeserializeOwned>(
    what: &str,
    value: JsValue,
) -> Result<T, JsError> {
    serde_wasm_bindgen::from_value(value).map_err(|e| {
        // The library's message already reads "Error: ..." (it is a JS
        // error's text); keep only the reason.
        let text = e.to_string();
        let reason = text.strip_prefix("Error: ").unwrap_or(&text);
        JsError::new(&format!("invalid {what}: {reason}"))
    })
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
        grid.render_rgba(&mut self.0)
            .expect("the buffer was just sized to the grid");
        self.0.as_ptr()
    }
}
