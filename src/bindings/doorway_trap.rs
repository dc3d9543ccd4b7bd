//! Bindings of `<occgrid-doorway-trap>`: the literal Table 9.1 sweep and the
//! MAP search of Table 9.3 on the doorway scene, stepped by the widget.
//! The two-cell table is [`super::two_cell_table`].

use super::{
    budget_from_js, map_pair_to_js, number_from_js, object_or_default, string_from_js, to_js,
    Pixels,
};
use crate::apps::doorway_trap::{DoorwayTrapSession, DoorwayTrapStart};
use crate::scenes::doorway::DoorwayScene;
use wasm_bindgen::prelude::*;

/// The doorway experiment held in wasm memory: [`DoorwayTrapSession`].
#[wasm_bindgen]
pub struct DoorwayTrap {
    session: DoorwayTrapSession,
    sweep_pixels: Pixels,
    /// The MAP map's RGBA image (binary, so not a `LogOddsGrid` render).
    map_pixels: Vec<u8>,
}

/// The doorway experiment being made ([`DoorwayTrapStart`]): the MAP
/// search set up in calls of bounded work (`work`), then the experiment
/// (`finish`), the one `new DoorwayTrap(scene)` makes bit for bit.
#[wasm_bindgen(js_name = DoorwayTrapStart)]
pub struct DoorwayTrapStarting(Option<DoorwayTrapStart>);

/// What one `DoorwayTrapStart.work` call did: the units spent (a raster
/// step of a beam's sub-rays; a cell's gain counts a fraction of one), and
/// whether the setup is done.
#[derive(serde::Serialize)]
struct StartReport {
    units: u64,
    done: bool,
}

#[wasm_bindgen(js_class = DoorwayTrapStart)]
impl DoorwayTrapStarting {
    /// Checks the scene as `new DoorwayTrap(scene)` does (a refusal names
    /// the field), before any work.
    #[wasm_bindgen(constructor)]
    pub fn new(scene: JsValue) -> Result<DoorwayTrapStarting, JsError> {
        let scene: DoorwayScene = object_or_default("scene", scene, DoorwayScene::standard)?;
        Ok(DoorwayTrapStarting(Some(DoorwayTrapStart::new(scene)?)))
    }

    /// True once the search is set up (or the experiment was made).
    #[wasm_bindgen(getter)]
    pub fn done(&self) -> bool {
        self.0.as_ref().is_none_or(DoorwayTrapStart::done)
    }

    /// Works for about `budget` units (a whole number, or `Infinity`): at
    /// least one piece, past the budget by at most one. Returns `{ units,
    /// done }`.
    pub fn work(&mut self, budget: JsValue) -> Result<JsValue, JsError> {
        let budget = budget_from_js("budget", &budget)? as u64;
        let start = self.started()?;
        let units = start.work(budget);
        to_js(&StartReport {
            units,
            done: start.done(),
        })
    }

    /// The experiment, what is left of the setup done first.
    pub fn finish(&mut self) -> Result<DoorwayTrap, JsError> {
        let Some(start) = self.0.take() else {
            return Err(JsError::new("the doorway trap was already finished"));
        };
        Ok(DoorwayTrap {
            session: start.finish()?,
            sweep_pixels: Pixels::default(),
            map_pixels: Vec::new(),
        })
    }

    fn started(&mut self) -> Result<&mut DoorwayTrapStart, JsError> {
        self.0
            .as_mut()
            .ok_or_else(|| JsError::new("the doorway trap was already finished"))
    }
}

#[wasm_bindgen]
impl DoorwayTrap {
    /// Builds the scene: `undefined` for the chapter's, or an object
    /// overriding any of its fields (`{ seed: 3 }`).
    #[wasm_bindgen(constructor)]
    pub fn new(scene: JsValue) -> Result<DoorwayTrap, JsError> {
        let scene: DoorwayScene = object_or_default("scene", scene, DoorwayScene::standard)?;
        Ok(DoorwayTrap {
            session: DoorwayTrapSession::new(scene)?,
            sweep_pixels: Pixels::default(),
            map_pixels: Vec::new(),
        })
    }

    #[wasm_bindgen(getter)]
    pub fn width(&self) -> usize {
        self.session.search().geometry().width()
    }

    #[wasm_bindgen(getter)]
    pub fn height(&self) -> usize {
        self.session.search().geometry().height()
    }

    /// Walls, door, poses and every reading in image units (see
    /// `DoorwayView`).
    pub fn view(&self) -> Result<JsValue, JsError> {
        to_js(&crate::apps::doorway_trap::view(self.session.scene())?)
    }

    /// Sweeps the next scan; returns `{ scan, cellsVisited, cellsUpdated }`
    /// or `null` once every scan is in.
    #[wasm_bindgen(js_name = sweepStep)]
    pub fn sweep_step(&mut self) -> Result<JsValue, JsError> {
        to_js(&self.session.sweep_step())
    }

    #[wasm_bindgen(js_name = sweepReset)]
    pub fn sweep_reset(&mut self) {
        self.session.sweep_reset();
    }

    /// Renders the swept grid (north up) and returns the address of its
    /// `width * height * 4` RGBA bytes.
    #[wasm_bindgen(js_name = sweepRender)]
    pub fn sweep_render(&mut self) -> usize {
        self.sweep_pixels.render(self.session.sweep().grid()) as usize
    }

    /// One steepest-ascent flip: the annotated flip (`{ number, cell, ix,
    /// iy, toOccupied, gain, priorTerm, objective, beams: [{ beam, before,
    /// after, delta, expectedRange }] }`) or `null` at a local maximum.
    #[wasm_bindgen(js_name = mapStep)]
    pub fn map_step(&mut self) -> Result<JsValue, JsError> {
        to_js(&self.session.map_step())
    }

    #[wasm_bindgen(js_name = mapReset)]
    pub fn map_reset(&mut self) {
        self.session.map_reset();
    }

    /// Runs the climb to its end (at most `maxFlips` more flips, a whole
    /// number; `Infinity` for no limit); returns the number of flips made.
    #[wasm_bindgen(js_name = mapRun)]
    pub fn map_run(&mut self, max_flips: JsValue) -> Result<u32, JsError> {
        let max_flips = budget_from_js("maxFlips", &max_flips)?;
        let max_flips = u32::try_from(max_flips).unwrap_or(u32::MAX);
        Ok(self.session.map_run(max_flips as usize) as u32)
    }

    /// Renders the MAP map (black occupied, white free, mid-gray where no
    /// cone reached) and returns the address of its RGBA bytes.
    #[wasm_bindgen(js_name = mapRender)]
    pub fn map_render(&mut self) -> Result<usize, JsError> {
        self.session.map_render(&mut self.map_pixels)?;
        Ok(self.map_pixels.as_ptr() as usize)
    }

    /// Cells no reading's cone crosses (drawn gray in the MAP pane).
    #[wasm_bindgen(js_name = unreachedCells)]
    pub fn unreached_cells(&self) -> usize {
        self.session.unreached_cells()
    }

    /// `{ flips: [...], history: [J_0, J_1, ...], objective, converged,
    /// occupied, l0, beams }`.
    #[wasm_bindgen(js_name = mapState)]
    pub fn map_state(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.map_state())
    }

    /// `{ doorCells, sweepClosed, mapInDoorway, mapOnFarWall, scansDone,
    /// scans }`.
    pub fn report(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.report()?)
    }

    /// The hover readout of the cell under image pixel `(col, row)` (whole
    /// numbers, row 0 at the top): `{ ix, iy, x, y, l, p, updates, unknown,
    /// occupied, sensitivity, beams }`.
    #[wasm_bindgen(js_name = cellInfo)]
    pub fn cell_info(&self, ix: JsValue, iy: JsValue) -> Result<JsValue, JsError> {
        let (ix, iy) = (number_from_js("ix", &ix)?, number_from_js("iy", &iy)?);
        let g = *self.session.search().geometry();
        let inside = |v: f64, n: usize| v.fract() == 0.0 && v >= 0.0 && v < n as f64;
        if !(inside(ix, g.width()) && inside(iy, g.height())) {
            return Err(JsError::new(&format!(
                "invalid cell: ({}, {}) (expected whole numbers naming a cell of the {} x {} map)",
                crate::error::show(ix),
                crate::error::show(iy),
                g.width(),
                g.height()
            )));
        }
        to_js(&self.session.cell_info(ix as usize, iy as usize)?)
    }

    /// One map (`"sweep"` or `"map"`) as a ROS `map_server` pair:
    /// `{ pgm: Uint8Array, yaml }`.
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(&self, which: JsValue) -> Result<JsValue, JsError> {
        let which = string_from_js("map", &which, "\"sweep\" or \"map\"")?;
        map_pair_to_js(&self.session.export_map(&which)?)
    }
}
