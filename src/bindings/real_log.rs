//! Bindings for real CARMEN logs: the chunked map build behind Map Weaver's
//! real-log mode ([`LogMapSession`]), and the zip packing of an exported map pair that
//! every widget's "Export map" button uses ([`zip_map_pair`]).

use super::{
    budget_from_js, bytes_from_js, coordinate_from_js, index_from_js, map_pair_to_js,
    number_from_js, object_from_js, string_from_js, to_js,
};
use crate::apps::real_log::{LogMapSettings, RealLogSession};
use crate::io::map_server as export;
use wasm_bindgen::prelude::*;

/// What a log's bytes may come as.
pub(crate) const LOG_BYTES: &str = "the bytes of a log file: a Uint8Array or an ArrayBuffer";

/// A log being read and mapped step by step: [`RealLogSession`].
#[wasm_bindgen]
pub struct LogMapSession {
    session: RealLogSession,
    /// The last view drawn: its RGBA bytes, the view's size (bounded by
    /// `MapViewport`), never the map's.
    view_pixels: Vec<u8>,
}

#[wasm_bindgen]
impl LogMapSession {
    /// Takes the bytes of a log file (a `Uint8Array` or `ArrayBuffer` of
    /// gzip or plain text); nothing is read until [`Self::read`].
    #[wasm_bindgen(constructor)]
    pub fn new_js(bytes: JsValue) -> Result<LogMapSession, JsError> {
        Ok(Self::new(bytes_from_js("bytes", &bytes, LOG_BYTES)?))
    }

    /// The real-log defaults: `{ resolution, rangeCap, alpha, lOcc, lFree,
    /// clamp, margin, noReturnReach, walls, poses, seed }`.
    #[wasm_bindgen(js_name = defaultSettings)]
    pub fn default_settings() -> Result<JsValue, JsError> {
        to_js(&LogMapSettings::default())
    }

    /// Reads up to `maxScans` more laser lines (a whole number; `Infinity`
    /// for the rest of the log) and returns `{ lines, scans, beams,
    /// bytesRead, bytesTotal, finished }` ([`RealLogSession::read`]).
    #[wasm_bindgen(js_name = read)]
    pub fn read_js(&mut self, max_scans: JsValue) -> Result<JsValue, JsError> {
        self.read(budget_from_js("maxScans", &max_scans)?)
    }

    /// New settings (a partial object: missing fields keep the defaults;
    /// unknown fields are errors). Returns the map's geometry, or `null`
    /// while the log is still being read. On error nothing changes.
    pub fn configure(&mut self, settings: JsValue) -> Result<JsValue, JsError> {
        let settings: LogMapSettings = object_from_js("settings", settings)?;
        to_js(&self.session.configure(settings)?)
    }

    /// The finished read's report (also when setting up the map failed),
    /// or `null`.
    #[wasm_bindgen(js_name = readSummary)]
    pub fn read_summary(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.read_summary())
    }

    /// True when the whole log has been read but the settings made too large
    /// a grid for it: `configure` with settings that fit builds the map.
    #[wasm_bindgen(getter, js_name = awaitingSettings)]
    pub fn awaiting_settings(&self) -> bool {
        self.session.awaiting_settings()
    }

    /// `{ width, height, resolution, originX, originY }` of the map, or
    /// `null` before the log is read.
    pub fn geometry(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.geometry())
    }

    /// Integrates up to `maxScans` more scans (a whole number; `Infinity`
    /// for all) and returns `{ scansDone, scansTarget, scansTotal,
    /// cellUpdates, beams, finished }`.
    #[wasm_bindgen(js_name = buildChunk)]
    pub fn build_chunk_js(&mut self, max_scans: JsValue) -> Result<JsValue, JsError> {
        self.build_chunk(budget_from_js("maxScans", &max_scans)?)
    }

    /// Integrates scans until this call has made `maxCells` cell updates
    /// (a whole number; the scan that reaches it is finished, and at least
    /// one scan is integrated): a call's work, and so its time, is bounded
    /// whatever the scans are like. Returns what `buildChunk` returns.
    #[wasm_bindgen(js_name = buildSlice)]
    pub fn build_slice_js(&mut self, max_cells: JsValue) -> Result<JsValue, JsError> {
        let cells = budget_from_js("maxCells", &max_cells)?;
        // Infinity (usize::MAX) is no limit on any target.
        let cells = if cells == usize::MAX {
            u64::MAX
        } else {
            cells as u64
        };
        to_js(&self.session.build_slice(cells)?)
    }

    /// A second session over the same log, already read (the scans are
    /// copied, not read again), mapped under `settings` (a partial object,
    /// as `configure` takes): the corrected map beside a dead-reckoned one.
    pub fn fork(&self, settings: JsValue) -> Result<LogMapSession, JsError> {
        let settings: LogMapSettings = object_from_js("settings", settings)?;
        Ok(LogMapSession {
            session: self.session.fork(settings)?,
            view_pixels: Vec::new(),
        })
    }

    /// The build's progress without doing any work.
    pub fn progress(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.build()?.progress())
    }

    /// Scrubs to `scans` integrated scans; `buildChunk` then does the work
    /// (going back restarts from the first scan).
    pub fn seek(&mut self, scans: JsValue) -> Result<(), JsError> {
        Ok(self.session.seek(index_from_js("scan", &scans)?)?)
    }

    /// The size of the output the map is drawn into, device pixels (whole
    /// numbers, 1 to 8192 each, at most 4,194,304 in all). The view keeps
    /// its centre and zoom.
    #[wasm_bindgen(js_name = setViewSize)]
    pub fn set_view_size(&mut self, width: JsValue, height: JsValue) -> Result<(), JsError> {
        let (w, h) = (
            index_from_js("width", &width)?,
            index_from_js("height", &height)?,
        );
        Ok(self.session.set_view_size(w, h)?)
    }

    /// Shows the whole map.
    #[wasm_bindgen(js_name = fitView)]
    pub fn fit_view(&mut self) -> Result<(), JsError> {
        Ok(self.session.fit_view()?)
    }

    /// Zooms by `factor` (above 1 closer) about output pixel `(x, y)`: the
    /// point under it stays under it.
    #[wasm_bindgen(js_name = zoomAt)]
    pub fn zoom_at(&mut self, x: JsValue, y: JsValue, factor: JsValue) -> Result<(), JsError> {
        let (x, y, factor) = (
            number_from_js("x", &x)?,
            number_from_js("y", &y)?,
            number_from_js("factor", &factor)?,
        );
        Ok(self.session.zoom_view(x, y, factor)?)
    }

    /// Moves the map by `(dx, dy)` output pixels (a drag).
    #[wasm_bindgen(js_name = panBy)]
    pub fn pan_by(&mut self, dx: JsValue, dy: JsValue) -> Result<(), JsError> {
        let (dx, dy) = (number_from_js("dx", &dx)?, number_from_js("dy", &dy)?);
        Ok(self.session.pan_view(dx, dy)?)
    }

    /// `{ mapWidth, mapHeight, width, height, u0, v0, scale }`: output
    /// pixel `(x, y)` shows map image point `(u0 + x / scale, v0 + y /
    /// scale)` (image units: one per cell, row 0 at the top).
    pub fn view(&self) -> Result<JsValue, JsError> {
        to_js(self.session.view()?)
    }

    /// Draws the view (north up, white free, black occupied, mid-gray
    /// unknown, blue-gray off the map) and returns the address of its
    /// `width * height * 4` RGBA bytes in wasm memory.
    #[wasm_bindgen(js_name = renderView)]
    pub fn render_view(&mut self) -> Result<usize, JsError> {
        self.session.render_view(&mut self.view_pixels)?;
        Ok(self.view_pixels.as_ptr() as usize)
    }

    /// The cell under output position `(x, y)` of the view (pixels):
    /// `{ ix, iy, x, y, l, p, updates, unknown }`, or `null` off the map.
    #[wasm_bindgen(js_name = cellAtView)]
    pub fn cell_at_view(&self, x: JsValue, y: JsValue) -> Result<JsValue, JsError> {
        let (x, y) = (number_from_js("x", &x)?, number_from_js("y", &y)?);
        if !(x.is_finite() && y.is_finite()) {
            return Err(JsError::new(&format!(
                "invalid view position: ({x}, {y}) (expected finite pixels)"
            )));
        }
        to_js(&self.session.readout_at_view(x, y)?)
    }

    /// The cell under image pixel `(col, row)` (row 0 at the top; whole
    /// numbers): `{ ix, iy, x, y, l, p, updates, unknown }`, or `null`
    /// outside the map.
    #[wasm_bindgen(js_name = cellAt)]
    pub fn cell_at(&self, col: JsValue, row: JsValue) -> Result<JsValue, JsError> {
        let (col, row) = (
            coordinate_from_js("col", &col)?,
            coordinate_from_js("row", &row)?,
        );
        to_js(&self.session.build()?.readout_at_pixel(col, row))
    }

    /// `{ occupied, free, unknown, cells, occupiedThresh, freeThresh }` now,
    /// counted as the exported map holds them: occupied `p > occupiedThresh`,
    /// free `p < freeThresh`, unknown the rest (the YAML's thresholds).
    pub fn counts(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.build()?.counts())
    }

    /// The laser positions of all scans in image pixels, `[x0, y0, ...]`.
    #[wasm_bindgen(js_name = pathPixels)]
    pub fn path_pixels(&self) -> Result<Vec<f32>, JsError> {
        Ok(self.session.build()?.path_in_pixels())
    }

    /// The robot at scan `k` over the map: `{ x, y, heading }` in image
    /// units, the heading an image angle (radians clockwise on screen).
    #[wasm_bindgen(js_name = robotAt)]
    pub fn robot_at(&self, k: JsValue) -> Result<JsValue, JsError> {
        to_js(&self.session.robot_at(index_from_js("scan", &k)?)?)
    }

    /// The map as a ROS `map_server` pair `{ pgm: Uint8Array, yaml }`, the
    /// YAML naming the image `NAME.pgm` (`name` a string; `undefined` or
    /// `null` for `map.pgm`).
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map_js(&self, name: JsValue) -> Result<JsValue, JsError> {
        let name = if name.is_undefined() || name.is_null() {
            None
        } else {
            Some(string_from_js(
                "name",
                &name,
                "a file name, or nothing for map.pgm",
            )?)
        };
        self.export_map(name)
    }
}

/// Typed entry points for Rust callers (the JavaScript surface above
/// checks what JavaScript sends, then calls these).
impl LogMapSession {
    /// [`Self::new_js`] for Rust callers.
    pub fn new(bytes: Vec<u8>) -> LogMapSession {
        LogMapSession {
            session: RealLogSession::new(bytes),
            view_pixels: Vec::new(),
        }
    }

    /// [`Self::read_js`] for Rust callers, with the budget already a count.
    pub fn read(&mut self, max_scans: usize) -> Result<JsValue, JsError> {
        to_js(&self.session.read(max_scans)?)
    }

    /// [`Self::build_chunk_js`] for Rust callers.
    pub fn build_chunk(&mut self, max_scans: usize) -> Result<JsValue, JsError> {
        to_js(&self.session.build_chunk(max_scans)?)
    }

    /// [`Self::export_map_js`] for Rust callers.
    pub fn export_map(&self, name: Option<String>) -> Result<JsValue, JsError> {
        map_pair_to_js(&self.session.export_map(name.as_deref())?)
    }
}

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
