//! Bindings for real CARMEN logs: the session behind Map Weaver's
//! real-log mode ([`RealLogSession`], the same name as the core session it
//! wraps), and the zip packing of an exported map pair that every widget's
//! "Export map" button uses ([`zip_map_pair`]). Every method converts its
//! JavaScript arguments to plain Rust values first, then makes one call
//! into the core session.

use super::{
    budget_from_js, bytes_from_js, coordinate_from_js, index_from_js, map_pair_to_js,
    number_from_js, object_from_js, string_from_js, to_js,
};
use crate::apps::real_log::{self as app, LogMapSettings, SettingLimits};
use wasm_bindgen::prelude::*;

/// What a log's bytes may come as.
pub(crate) const LOG_BYTES: &str = "the bytes of a log file: a Uint8Array or an ArrayBuffer";

/// A log being read and mapped step by step, one pane per pose source:
/// [`app::RealLogSession`]. Methods about one map take its pane index first
/// (0 is the pane the reader operates; `state().panes` lists them).
#[wasm_bindgen]
pub struct RealLogSession {
    session: app::RealLogSession,
}

/// A log's file name: a string, or `undefined` / `null` for `log`.
fn optional_name(value: &JsValue) -> Result<String, JsError> {
    if value.is_undefined() || value.is_null() {
        Ok("log".into())
    } else {
        string_from_js("name", value, "a file name, or nothing")
    }
}

/// A cell budget: a whole number, `Infinity` (or past `u64`) for no limit.
fn cells_from_js(field: &str, value: &JsValue) -> Result<u64, JsError> {
    let cells = budget_from_js(field, value)?;
    Ok(if cells == usize::MAX {
        u64::MAX
    } else {
        cells as u64
    })
}

/// One arrow key's step along an axis: -1, 0 or 1.
fn direction_from_js(field: &str, value: &JsValue) -> Result<i8, JsError> {
    let d = number_from_js(field, value)?;
    if d == -1.0 || d == 0.0 || d == 1.0 {
        Ok(d as i8)
    } else {
        Err(JsError::new(&format!(
            "invalid {field}: {} (expected -1, 0 or 1: one arrow key)",
            crate::error::show(d)
        )))
    }
}

#[wasm_bindgen]
impl RealLogSession {
    /// Takes the bytes of a log file (a `Uint8Array` or `ArrayBuffer` of
    /// gzip or plain text) to read with [`Self::read`], and optionally the
    /// file's name (`log` without one); [`Self::open`] gives the session
    /// the next log.
    #[wasm_bindgen(constructor)]
    pub fn new(bytes: JsValue, name: JsValue) -> Result<RealLogSession, JsError> {
        let bytes = bytes_from_js("bytes", &bytes, LOG_BYTES)?;
        let name = optional_name(&name)?;
        let mut session = app::RealLogSession::idle();
        session.open(bytes, &name);
        Ok(Self { session })
    }

    /// The real-log defaults: `{ resolution, rangeCap, alpha, lOcc, lFree,
    /// clamp, margin, noReturnReach, walls, poses, seed, model,
    /// compareModel, betweenBeams }` (`model` one of `hit-counting`,
    /// `log-odds`, `hit-miss-odds`; `compareModel` another, or `null`).
    #[wasm_bindgen(js_name = defaultSettings)]
    pub fn default_settings() -> Result<JsValue, JsError> {
        to_js(&LogMapSettings::default())
    }

    /// The bounds the controls keep to at `resolution` metres per cell:
    /// `{ resolution, rangeCapMax, reachCells, seedMax }`.
    pub fn limits(resolution: JsValue) -> Result<JsValue, JsError> {
        let resolution = number_from_js("resolution", &resolution)?;
        to_js(&SettingLimits::at(resolution)?)
    }

    /// Starts reading another log (the bytes and name as the constructor
    /// takes them); the maps of the previous log stay until this one is
    /// read.
    pub fn open(&mut self, bytes: JsValue, name: JsValue) -> Result<(), JsError> {
        let bytes = bytes_from_js("bytes", &bytes, LOG_BYTES)?;
        let name = optional_name(&name)?;
        self.session.open(bytes, &name);
        Ok(())
    }

    /// Reads up to `maxScans` more laser lines (a whole number; `Infinity`
    /// for the rest of the log) and returns `{ lines, scans, beams,
    /// bytesRead, bytesTotal, finished, warning }`.
    pub fn read(&mut self, max_scans: JsValue) -> Result<JsValue, JsError> {
        let max_scans = budget_from_js("maxScans", &max_scans)?;
        to_js(&self.session.read(max_scans)?)
    }

    /// Walks up to `maxScans` more scans (a whole number) of the planning
    /// of the panes after new settings (state `planning`); returns `{ work,
    /// finished }`, `work` the scans walked.
    pub fn plan(&mut self, max_scans: JsValue) -> Result<JsValue, JsError> {
        let max_scans = budget_from_js("maxScans", &max_scans)?;
        to_js(&self.session.plan(max_scans)?)
    }

    /// New settings (a partial object: missing fields keep the defaults;
    /// unknown fields are errors). Returns the first pane's geometry, or
    /// `null` while there is no map. On error nothing changes.
    pub fn configure(&mut self, settings: JsValue) -> Result<JsValue, JsError> {
        let settings: LogMapSettings = object_from_js("settings", settings)?;
        to_js(&self.session.configure(settings)?)
    }

    /// The one state a panel renders: `{ state, error, progress, read,
    /// scansDone, scansTarget, scansTotal, cellUpdates, beams, finished,
    /// panes: [{ poses, caption, scansDone, ... }], settings, limits }`,
    /// `state` one of idle, reading, awaiting-settings, building, done,
    /// failed.
    pub fn state(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.state())
    }

    /// Advances every pane within one budget of `maxCells` units of work
    /// (a cell update each, or two cells visited: `state().work`; a
    /// whole number; the scan that reaches it is finished, and at least
    /// one scan is integrated while any is left; `Infinity` for the whole
    /// build): a call's work, and so its time, is bounded whatever the
    /// scans are like. Returns the state.
    #[wasm_bindgen(js_name = buildSlice)]
    pub fn build_slice(&mut self, max_cells: JsValue) -> Result<JsValue, JsError> {
        let max_cells = cells_from_js("maxCells", &max_cells)?;
        to_js(&self.session.build_slice(max_cells)?)
    }

    /// Scrubs every pane to `scans` integrated scans; `buildSlice` then
    /// does the work (going back restarts from the first scan).
    pub fn seek(&mut self, scans: JsValue) -> Result<(), JsError> {
        let scans = index_from_js("scan", &scans)?;
        Ok(self.session.seek(scans)?)
    }

    /// `{ width, height, resolution, originX, originY }` of pane `pane`'s map.
    pub fn geometry(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(&self.session.geometry(pane)?)
    }

    /// The size of the output pane `pane` is drawn into, device pixels
    /// (whole numbers, 1 to 8192 each, at most 4,194,304 in all). The view
    /// keeps its centre and zoom.
    #[wasm_bindgen(js_name = setViewSize)]
    pub fn set_view_size(
        &mut self,
        pane: JsValue,
        width: JsValue,
        height: JsValue,
    ) -> Result<(), JsError> {
        let (pane, w, h) = (
            index_from_js("pane", &pane)?,
            index_from_js("width", &width)?,
            index_from_js("height", &height)?,
        );
        Ok(self.session.pane_mut(pane)?.set_view_size(w, h)?)
    }

    /// Shows pane `pane`'s whole map, keeping the keyboard cursor (placed
    /// at the view's centre if there was none); returns the cell under it.
    #[wasm_bindgen(js_name = fitView)]
    pub fn fit_view(&mut self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(&self.session.pane_mut(pane)?.fit_at_cursor())
    }

    /// Zooms pane `pane` by `factor` (above 1 closer) about output pixel
    /// `(x, y)`: the point under it stays under it.
    #[wasm_bindgen(js_name = zoomAt)]
    pub fn zoom_at(
        &mut self,
        pane: JsValue,
        x: JsValue,
        y: JsValue,
        factor: JsValue,
    ) -> Result<(), JsError> {
        let (pane, x, y, factor) = (
            index_from_js("pane", &pane)?,
            number_from_js("x", &x)?,
            number_from_js("y", &y)?,
            number_from_js("factor", &factor)?,
        );
        Ok(self.session.pane_mut(pane)?.zoom_view(x, y, factor)?)
    }

    /// Moves pane `pane`'s map by `(dx, dy)` output pixels (a drag).
    #[wasm_bindgen(js_name = panBy)]
    pub fn pan_by(&mut self, pane: JsValue, dx: JsValue, dy: JsValue) -> Result<(), JsError> {
        let (pane, dx, dy) = (
            index_from_js("pane", &pane)?,
            number_from_js("dx", &dx)?,
            number_from_js("dy", &dy)?,
        );
        Ok(self.session.pane_mut(pane)?.pan_view(dx, dy)?)
    }

    /// `{ mapWidth, mapHeight, width, height, u0, v0, scale }` of pane
    /// `pane`: output pixel `(x, y)` shows map image point `(u0 + x /
    /// scale, v0 + y / scale)` (image units: one per cell, row 0 at the top).
    pub fn view(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(self.session.pane(pane)?.view())
    }

    /// Pane `pane`'s scale as the panel states it, for a canvas of
    /// `devicePixelRatio` device pixels per screen pixel: `{
    /// screenPixelsPerCell, metresPerScreenPixel, widthMetres,
    /// heightMetres, text }`.
    #[wasm_bindgen(js_name = viewLegend)]
    pub fn view_legend(
        &self,
        pane: JsValue,
        device_pixel_ratio: JsValue,
    ) -> Result<JsValue, JsError> {
        let (pane, dpr) = (
            index_from_js("pane", &pane)?,
            number_from_js("devicePixelRatio", &device_pixel_ratio)?,
        );
        to_js(&self.session.pane(pane)?.legend(dpr)?)
    }

    /// Draws pane `pane`'s view (north up, white free, black occupied,
    /// mid-gray unknown, blue-gray off the map) and returns the address of
    /// its `width * height * 4` RGBA bytes in wasm memory.
    #[wasm_bindgen(js_name = renderView)]
    pub fn render_view(&mut self, pane: JsValue) -> Result<usize, JsError> {
        let pane = index_from_js("pane", &pane)?;
        Ok(self.session.pane_mut(pane)?.render_view().as_ptr() as usize)
    }

    /// Draws a band of pane `pane`'s view, at most `maxSamples` map cells
    /// sampled (a whole number; whole rows, at least one), and returns
    /// true once the picture is whole: `viewPixels` then holds it. Until
    /// then the last whole picture stays, so a page can draw a large view
    /// over several tasks and show it when done. A `quick` picture (of a
    /// map still being built) samples one cell per pixel.
    #[wasm_bindgen(js_name = renderViewWithin)]
    pub fn render_view_within(
        &mut self,
        pane: JsValue,
        max_samples: JsValue,
        quick: JsValue,
    ) -> Result<bool, JsError> {
        let pane = index_from_js("pane", &pane)?;
        let max_samples = budget_from_js("maxSamples", &max_samples)?;
        let quick = quick.as_bool().ok_or_else(|| {
            JsError::new(&format!(
                "invalid quick: {} (expected true or false)",
                super::describe(&quick)
            ))
        })?;
        Ok(self
            .session
            .pane_mut(pane)?
            .render_view_within(max_samples, quick))
    }

    /// The address of pane `pane`'s last whole picture (the view's
    /// `width * height * 4` RGBA bytes), as `renderView` or
    /// `renderViewWithin` left it; nothing is drawn.
    #[wasm_bindgen(js_name = viewPixels)]
    pub fn view_pixels(&self, pane: JsValue) -> Result<usize, JsError> {
        let pane = index_from_js("pane", &pane)?;
        Ok(self.session.pane(pane)?.view_pixels().as_ptr() as usize)
    }

    /// The cell under output position `(x, y)` of pane `pane`'s view
    /// (pixels): `{ ix, iy, x, y, l, p, updates, unknown }`, or `null` off
    /// the map.
    #[wasm_bindgen(js_name = cellAtView)]
    pub fn cell_at_view(&self, pane: JsValue, x: JsValue, y: JsValue) -> Result<JsValue, JsError> {
        let (pane, x, y) = (
            index_from_js("pane", &pane)?,
            number_from_js("x", &x)?,
            number_from_js("y", &y)?,
        );
        to_js(&self.session.pane(pane)?.readout_at_view(x, y)?)
    }

    /// The cell under image pixel `(col, row)` of pane `pane` (row 0 at the
    /// top; whole numbers), or `null` outside the map.
    #[wasm_bindgen(js_name = cellAt)]
    pub fn cell_at(&self, pane: JsValue, col: JsValue, row: JsValue) -> Result<JsValue, JsError> {
        let (pane, col, row) = (
            index_from_js("pane", &pane)?,
            coordinate_from_js("col", &col)?,
            coordinate_from_js("row", &row)?,
        );
        to_js(&self.session.pane(pane)?.readout_at_pixel(col, row))
    }

    /// Moves pane `pane`'s keyboard cursor one arrow key's way (`dx`, `dy`
    /// each -1, 0 or 1; `long` true for ten steps), from the view's centre
    /// the first time; the view follows it. Returns the cell under it.
    #[wasm_bindgen(js_name = moveCursor)]
    pub fn move_cursor(
        &mut self,
        pane: JsValue,
        dx: JsValue,
        dy: JsValue,
        long: JsValue,
    ) -> Result<JsValue, JsError> {
        let (pane, dx, dy, long) = (
            index_from_js("pane", &pane)?,
            direction_from_js("dx", &dx)?,
            direction_from_js("dy", &dy)?,
            long.is_truthy(),
        );
        to_js(&self.session.pane_mut(pane)?.move_cursor(dx, dy, long)?)
    }

    /// Zooms pane `pane` by `factor` about its keyboard cursor (placed at
    /// the view's centre if there is none); returns the cell under it.
    #[wasm_bindgen(js_name = zoomAtCursor)]
    pub fn zoom_at_cursor(&mut self, pane: JsValue, factor: JsValue) -> Result<JsValue, JsError> {
        let (pane, factor) = (
            index_from_js("pane", &pane)?,
            number_from_js("factor", &factor)?,
        );
        to_js(&self.session.pane_mut(pane)?.zoom_at_cursor(factor)?)
    }

    /// Pane `pane`'s keyboard cursor `{ col, row }` (an image cell), or
    /// `null`.
    pub fn cursor(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(&self.session.pane(pane)?.cursor())
    }

    /// Forgets pane `pane`'s keyboard cursor.
    #[wasm_bindgen(js_name = clearCursor)]
    pub fn clear_cursor(&mut self, pane: JsValue) -> Result<(), JsError> {
        let pane = index_from_js("pane", &pane)?;
        self.session.pane_mut(pane)?.clear_cursor();
        Ok(())
    }

    /// `{ occupied, free, unknown, cells, occupiedThresh, freeThresh }` of
    /// pane `pane` now, counted as the exported map holds them: occupied
    /// `p > occupiedThresh`, free `p < freeThresh`, unknown the rest.
    pub fn counts(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(&self.session.pane(pane)?.counts())
    }

    /// The laser positions of all scans on pane `pane` in image pixels,
    /// `[x0, y0, ...]`.
    #[wasm_bindgen(js_name = pathPixels)]
    pub fn path_pixels(&self, pane: JsValue) -> Result<Vec<f32>, JsError> {
        let pane = index_from_js("pane", &pane)?;
        Ok(self.session.pane(pane)?.path_in_pixels())
    }

    /// The robot at scan `k` over pane `pane`: `{ x, y, heading }` in image
    /// units, the heading an image angle (radians clockwise on screen).
    #[wasm_bindgen(js_name = robotAt)]
    pub fn robot_at(&self, pane: JsValue, k: JsValue) -> Result<JsValue, JsError> {
        let (pane, k) = (index_from_js("pane", &pane)?, index_from_js("scan", &k)?);
        let robot = self.session.pane(pane)?.robot_at(k);
        to_js(&robot.ok_or_else(|| crate::error::invalid("scan", k, "a scan of the log"))?)
    }

    /// What pane `pane`'s last scan match did, for a scan-matched pane
    /// (`null` for the others, and before the first scan): `{ scan,
    /// accepted, score, predictedScore, overlap, predicted: { x, y,
    /// heading }, pose: { x, y, heading }, correctionM, correctionDeg,
    /// points: [u0, v0, ...] }`, the robot and the matched points in image
    /// units.
    #[wasm_bindgen(js_name = matchView)]
    pub fn match_view(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        to_js(&self.session.pane(pane)?.match_view())
    }

    /// The poses pane `pane`'s map so far was built with, one line per
    /// scan: `scan x y theta` (metres, radians): a `poses.tsv` file.
    #[wasm_bindgen(js_name = posesTsv)]
    pub fn poses_tsv(&self, pane: JsValue) -> Result<String, JsError> {
        let pane = index_from_js("pane", &pane)?;
        Ok(self.session.pane(pane)?.poses_tsv())
    }

    /// The file stem pane `pane`'s export takes for a log file named
    /// `fileName`: `intel-corrected-map`, or
    /// `intel-corrected-dead-reckoning-map` for dead reckoning
    /// (`-scan-matched-map` for scan matching).
    #[wasm_bindgen(js_name = exportStem)]
    pub fn export_stem(&self, pane: JsValue, file_name: JsValue) -> Result<String, JsError> {
        let (pane, name) = (
            index_from_js("pane", &pane)?,
            string_from_js("fileName", &file_name, "a file name")?,
        );
        Ok(self.session.pane(pane)?.export_stem(&name))
    }

    /// Pane `pane`'s map as a ROS `map_server` pair `{ pgm: Uint8Array,
    /// yaml }`, the YAML naming the image `NAME.pgm` (`name` a string;
    /// `undefined` or `null` for `map.pgm`) and, for poses other than the
    /// log's own, saying which in a comment line.
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(&self, pane: JsValue, name: JsValue) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        let name = if name.is_undefined() || name.is_null() {
            None
        } else {
            Some(string_from_js(
                "name",
                &name,
                "a file name, or nothing for map.pgm",
            )?)
        };
        map_pair_to_js(&self.session.pane(pane)?.export_map(name.as_deref()))
    }
}
