//! Bindings of `<occgrid-map-weaver>`: the apartment lap feeding two maps
//! ([`crate::apps::map_weaver::Weaver`]), and the W2/W3 benchmark workloads
//! ([`crate::world::weaver_workloads`]) for the wasm run under Node.

use super::{
    bool_from_js, budget_from_js, coordinate_from_js, index_from_js, map_pair_to_js, now_ms,
    number_from_js, object_or_default, patch_from_js, to_js,
};
use crate::apps::map_weaver::{Weaver, WeaverSettings, WeaverStart};
use wasm_bindgen::prelude::*;

/// A Map Weaver run held in wasm memory.
#[wasm_bindgen]
pub struct MapWeaver(Weaver);

#[wasm_bindgen]
impl MapWeaver {
    /// Builds a run (and trains the learned model). `settings` may be
    /// `undefined` (the chapter's run) or an object overriding any field:
    /// `{ seed: 3, person: false, laps: 1, panes: [{...}, {...}] }`.
    #[wasm_bindgen(constructor)]
    pub fn new(settings: JsValue) -> Result<MapWeaver, JsError> {
        let settings = object_or_default("settings", settings, WeaverSettings::default)?;
        let mut weaver = WeaverStart::run(settings)?;
        weaver.set_clock(Some(now_ms));
        Ok(MapWeaver(weaver))
    }

    /// Pane `pane`'s map size in cells, `[width, height]`.
    #[wasm_bindgen(js_name = paneSize)]
    pub fn pane_size(&self, pane: JsValue) -> Result<Vec<usize>, JsError> {
        let g = self.0.pane_geometry(pane_from_js(&pane)?)?;
        Ok(vec![g.width(), g.height()])
    }

    /// Changes knobs of pane `pane`, the one way to turn any of them: a
    /// patch of its settings `{ model, pose, clamp, strength, mapper,
    /// sensor, betaDeg, beams, resolution, forgetL0 }`, each field given
    /// replacing that knob (`null` for `beams` or `resolution`: the
    /// default), the others kept. The pane is emptied here: `work`
    /// rebuilds it over the scans so far in budgeted calls, before any new
    /// scan. Returns false when the patch changed nothing. A refused patch
    /// changes nothing.
    #[wasm_bindgen(js_name = stagePane)]
    pub fn stage_pane(&mut self, pane: JsValue, patch: JsValue) -> Result<bool, JsError> {
        let pane = pane_from_js(&pane)?;
        let current = self.0.pane_settings(pane)?;
        let settings = patch_from_js(&format!("panes[{pane}]"), &current, patch)?;
        Ok(self.0.stage_pane(pane, settings)?)
    }

    /// Works for about `budget` cell visits (a whole number; `Infinity`
    /// for no limit): first the scans a pane lacks (a rebuild, a sweep
    /// spread over calls), then up to `scans` new scans. A page playing the
    /// lap calls this once a frame with a budget sized from the last call's
    /// time. Returns `{ scans, cellVisits, behind: [left, right], done }`:
    /// new scans taken, the visits spent, the scans each pane still lacks,
    /// and whether the run is over with both panes caught up.
    pub fn work(&mut self, scans: JsValue, budget: JsValue) -> Result<JsValue, JsError> {
        let scans = budget_from_js("scans", &scans)?;
        let budget = budget_from_js("budget", &budget)? as u64;
        to_js(&self.0.work(scans, budget)?)
    }

    /// Where the work stands (`work`'s answer, with nothing done).
    pub fn progress(&self) -> Result<JsValue, JsError> {
        to_js(&self.0.progress())
    }

    /// Map width in cells (= image width in pixels).
    #[wasm_bindgen(getter)]
    pub fn width(&self) -> usize {
        self.0.geometry().width()
    }
    /// Map height in cells.
    #[wasm_bindgen(getter)]
    pub fn height(&self) -> usize {
        self.0.geometry().height()
    }
    /// Metres per cell.
    #[wasm_bindgen(getter)]
    pub fn resolution(&self) -> f64 {
        self.0.geometry().resolution()
    }

    /// Simulates and integrates up to `scans` scans (a whole number;
    /// `Infinity` for the rest of the run); returns how many were taken (0
    /// once the run's laps are done).
    pub fn advance(&mut self, scans: JsValue) -> Result<usize, JsError> {
        Ok(self.0.advance(budget_from_js("scans", &scans)?)?)
    }

    /// How many scans `advance` will take for a request of `scans` before
    /// the first frame (a whole number), or an error naming `scans` when
    /// that is more work than the core's budget
    /// ([`crate::apps::map_weaver::MAX_FAST_FORWARD_WORK`]). A page checks
    /// this first, then advances in slices.
    #[wasm_bindgen(js_name = checkFastForward)]
    pub fn check_fast_forward(&self, scans: JsValue) -> Result<usize, JsError> {
        Ok(self.0.check_fast_forward(index_from_js("scans", &scans)?)?)
    }

    /// Address of pane `pane`'s RGBA pixels (north up) as of the last scan.
    pub fn pixels(&self, pane: JsValue) -> Result<usize, JsError> {
        Ok(self.0.view(pane_from_js(&pane)?)?.rgba().as_ptr() as usize)
    }

    /// Address of the per-cell Brier difference image (RGBA, north up),
    /// drawn now; 0 when the panes map different cells.
    #[wasm_bindgen(js_name = brierPixels)]
    pub fn brier_pixels(&mut self) -> usize {
        self.0
            .draw_brier_difference()
            .map_or(0, |px| px.as_ptr() as usize)
    }

    /// `{ scans, scansPerLap, lap, time, done, person, frameMs, panes: [...] }`.
    pub fn readout(&self) -> Result<JsValue, JsError> {
        to_js(&self.0.readout())
    }

    /// The time of each point of the curves, seconds (the empty map, then
    /// after each scan), at the scene's scan rate.
    /// Scans per second of driving: playback at speed 1 is real time.
    #[wasm_bindgen(getter, js_name = scanRate)]
    pub fn scan_rate(&self) -> f64 {
        self.0.settings().scene.scan_rate
    }

    #[wasm_bindgen(js_name = curveTimes)]
    pub fn curve_times(&self) -> Vec<f64> {
        self.0.curve_times()
    }

    /// Entropy (bits) after each scan, from the empty map on.
    #[wasm_bindgen(js_name = entropyCurve)]
    pub fn entropy_curve(&self, pane: JsValue) -> Result<Vec<f64>, JsError> {
        Ok(self.0.entropy_curve(pane_from_js(&pane)?)?.to_vec())
    }

    /// Brier score over the surveyed rooms after each scan.
    #[wasm_bindgen(js_name = brierCurve)]
    pub fn brier_curve(&self, pane: JsValue) -> Result<Vec<f64>, JsError> {
        Ok(self.0.brier_curve(pane_from_js(&pane)?)?.to_vec())
    }

    /// The three tracked cells' log odds after each scan, interleaved:
    /// `[wall0, floor0, closet0, wall1, ...]`.
    #[wasm_bindgen(js_name = trackedHistory)]
    pub fn tracked_history(&self, pane: JsValue) -> Result<Vec<f32>, JsError> {
        Ok(self
            .0
            .tracked_history(pane_from_js(&pane)?)?
            .iter()
            .flatten()
            .copied()
            .collect())
    }

    /// The tracked cells of pane `pane` (0 when left out): `[{ name, at:
    /// [x, y], ix, iy, col, row }]` (world metres, grid indices, and the
    /// image cell, row 0 at the top).
    #[wasm_bindgen(js_name = trackedCells)]
    pub fn tracked_cells(&self, pane: JsValue) -> Result<JsValue, JsError> {
        let pane = if pane.is_undefined() {
            0
        } else {
            pane_from_js(&pane)?
        };
        to_js(&self.0.tracked_readout(pane)?)
    }

    /// The cell under image column `col`, row `row` (whole numbers) of
    /// pane `pane`: `{ ix, iy, x, y, l, p, updates, occupied, unknown }`, or
    /// `null` outside the map.
    #[wasm_bindgen(js_name = cellInfo)]
    pub fn cell_info(&self, pane: JsValue, col: JsValue, row: JsValue) -> Result<JsValue, JsError> {
        let pane = pane_from_js(&pane)?;
        let (col, row) = (
            coordinate_from_js("col", &col)?,
            coordinate_from_js("row", &row)?,
        );
        match self.0.cell_info(pane, col, row)? {
            Some(info) => to_js(&info),
            None => Ok(JsValue::NULL),
        }
    }

    /// What to draw over pane `pane`, in image units:
    /// `{ robot, nose, truth, beams, hits, person }`.
    pub fn overlay(&self, pane: JsValue) -> Result<JsValue, JsError> {
        to_js(&self.0.overlay(pane_from_js(&pane)?)?)
    }

    /// Puts the person into the corridor (`true`) or takes them out
    /// (`false`) from the next scan on.
    #[wasm_bindgen(js_name = setPerson)]
    pub fn set_person(&mut self, on: JsValue) -> Result<(), JsError> {
        self.0.set_person(bool_from_js("person", &on)?);
        Ok(())
    }

    /// Starts the lap again with the current knobs.
    pub fn reset(&mut self) -> Result<(), JsError> {
        Ok(self.0.reset()?)
    }

    /// Records one frame's duration (ms, timed by the page) for the readout.
    #[wasm_bindgen(js_name = recordFrameMs)]
    pub fn record_frame_ms(&mut self, ms: JsValue) -> Result<(), JsError> {
        // NaN, a negative or an endless duration would skew the median.
        let ms = crate::error::non_negative("ms", number_from_js("ms", &ms)?)?;
        self.0.record_frame_ms(ms);
        Ok(())
    }

    /// Pane `pane`'s map as a ROS `map_server` pair `{ pgm: Uint8Array,
    /// yaml }`, the YAML naming the image `apartment-left.pgm` or
    /// `apartment-right.pgm`.
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(&self, pane: JsValue) -> Result<JsValue, JsError> {
        map_pair_to_js(&self.0.export_map(pane_from_js(&pane)?)?)
    }
}

/// A Map Weaver run being made ([`WeaverStart`]): the learned model
/// trained in calls of a bounded amount of work (`work`), then the run's
/// maps drawn in calls of a bounded number of cells (`build`), then the run
/// (`finish`), so that a page keeps its frames while the model trains and a
/// large scene is drawn. The model is the one `new MapWeaver(settings)`
/// trains, bit for bit, and is kept for the page's later runs as that one
/// is; the run is the one `new MapWeaver(settings)` makes, bit for bit.
#[wasm_bindgen]
pub struct MapWeaverStart(WeaverStart);

#[wasm_bindgen]
impl MapWeaverStart {
    /// Checks `settings` as `new MapWeaver(settings)` does (a refusal
    /// names the field), before any training.
    #[wasm_bindgen(constructor)]
    pub fn new(settings: JsValue) -> Result<MapWeaverStart, JsError> {
        let settings = object_or_default("settings", settings, WeaverSettings::default)?;
        Ok(MapWeaverStart(WeaverStart::new(settings)?))
    }

    /// True once the model is trained.
    #[wasm_bindgen(getter)]
    pub fn trained(&self) -> bool {
        self.0.trained()
    }

    /// Trains for about `budget` units (a triplet drawn or an SGD update; a
    /// whole number, or `Infinity`); returns true once the model is
    /// trained.
    pub fn work(&mut self, budget: JsValue) -> Result<bool, JsError> {
        Ok(self.0.train(budget_from_js("budget", &budget)?)?)
    }

    /// Draws the run's maps for about `budget` cells (a whole number, or
    /// `Infinity`), the model trained first if it is not yet: at least one
    /// band of rows, past the budget by at most one piece. Returns `{
    /// cells, done }`: the cells drawn, and whether every map is.
    pub fn build(&mut self, budget: JsValue) -> Result<JsValue, JsError> {
        let budget = budget_from_js("budget", &budget)? as u64;
        to_js(&self.0.build(budget)?)
    }

    /// The run, what is left of the training and of the maps done first.
    pub fn finish(&mut self) -> Result<MapWeaver, JsError> {
        let mut weaver = self.0.finish()?;
        weaver.set_clock(Some(now_ms));
        Ok(MapWeaver(weaver))
    }
}

/// A pane index from JavaScript: 0 (left) or 1 (right), checked here with
/// the value as JavaScript sent it (the core checks the range again).
fn pane_from_js(pane: &JsValue) -> Result<usize, JsError> {
    let pane = number_from_js("pane", pane)?;
    if pane == 0.0 || pane == 1.0 {
        Ok(pane as usize)
    } else {
        Err(JsError::new(&format!(
            "invalid pane: {} (expected 0 (left) or 1 (right))",
            crate::error::show(pane)
        )))
    }
}
