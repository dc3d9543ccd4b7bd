//! The map archive every widget's "Export map" button downloads: one zip
//! holding the `map_server` pair (widgets/lib/export.js). In both wasm
//! modules: the chapter's widgets and the real-log panel export alike.

use super::{bytes_from_js, string_from_js};
use crate::io::map_server as export;
use wasm_bindgen::prelude::*;

/// Packs an exported pair into one zip download for `downloadMapPair`
/// (widgets/lib/export.js): `{ fileName, bytes: Uint8Array }`, the archive
/// holding `STEM.pgm` and `STEM.yaml` with the YAML's `image:` pointing at
/// the PGM. `name` and `yaml` are strings, `pgm` a `Uint8Array`.
#[wasm_bindgen(js_name = zipMapPair)]
pub fn zip_map_pair(name: JsValue, pgm: JsValue, yaml: JsValue) -> Result<JsValue, JsError> {
    let name = string_from_js("name", &name, "a file name")?;
    let pgm = bytes_from_js("pgm", &pgm, "the Uint8Array of an exported pair")?;
    let yaml = string_from_js("yaml", &yaml, "the YAML text of an exported pair")?;
    let (file_name, bytes) = export::zip_pair(&export::MapServerPair { pgm, yaml }, &name);
    let out = js_sys::Object::new();
    js_sys::Reflect::set(&out, &"fileName".into(), &JsValue::from_str(&file_name))
        .and_then(|_| {
            js_sys::Reflect::set(
                &out,
                &"bytes".into(),
                &js_sys::Uint8Array::from(bytes.as_slice()).into(),
            )
        })
        .map_err(|_| JsError::new("cannot build the zip object"))?;
    Ok(out.into())
}
