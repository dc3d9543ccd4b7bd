//! The view of a real-log pane and its keyboard cursor, for
//! [`RealLogSession`]: zoom, pan, the output size, the pictures drawn, the
//! cells under the pointer and the cursor. Every method converts its
//! JavaScript arguments, then calls the pane the index picks.

use super::RealLogSession;
use crate::bindings::{
    bool_from_js, budget_from_js, coordinate_from_js, index_from_js, number_from_js, to_js,
};
use wasm_bindgen::prelude::*;

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
        // A pointer is always somewhere: a point that is no number is a
        // caller's mistake, not the view's centre.
        for (field, at) in [("x", x), ("y", y)] {
            crate::error::finite(field, at)?;
        }
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
        let quick = bool_from_js("quick", &quick)?;
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
}
