//! Bindings of `<occgrid-doorway-trap>`: the literal Table 9.1 sweep and the
//! MAP search of Table 9.3 on the doorway scene, stepped by the widget, and
//! the exact joint posterior of the two-cell table (SPEC §6, §7).

use super::{
    budget_from_js, map_pair_to_js, object_from_js, object_or_default, string_from_js, to_js,
    Pixels,
};
use crate::apps::doorway_trap::DoorwaySweep;
use crate::grid::LogOddsGrid;
use crate::io::map_server as export;
use crate::mapping::joint::{JointPosterior, JointQuery};
use crate::mapping::map_search::MapSearch;
use crate::scenes::doorway::DoorwayScene;
use wasm_bindgen::prelude::*;

/// Saturation of the exported MAP map, log odds: far past both YAML
/// thresholds, so every decided cell exports as occupied or free.
const EXPORT_CLAMP: f64 = 12.0;

/// The doorway experiment held in wasm memory.
#[wasm_bindgen]
pub struct DoorwayTrap {
    scene: DoorwayScene,
    sweep: DoorwaySweep,
    search: MapSearch,
    sweep_pixels: Pixels,
    /// The MAP map's RGBA image (binary, so not a `LogOddsGrid` render).
    map_pixels: Vec<u8>,
}

#[wasm_bindgen]
impl DoorwayTrap {
    /// Builds the scene: `undefined` for the chapter's, or an object
    /// overriding any of its fields (`{ seed: 3 }`).
    #[wasm_bindgen(constructor)]
    pub fn new(scene: JsValue) -> Result<DoorwayTrap, JsError> {
        let scene: DoorwayScene = object_or_default("scene", scene, DoorwayScene::standard)?;
        Ok(DoorwayTrap {
            sweep: DoorwaySweep::new(&scene)?,
            search: crate::apps::doorway_trap::map_search(&scene)?,
            scene,
            sweep_pixels: Pixels::default(),
            map_pixels: Vec::new(),
        })
    }

    #[wasm_bindgen(getter)]
    pub fn width(&self) -> usize {
        self.scene_grid().geometry().width()
    }

    #[wasm_bindgen(getter)]
    pub fn height(&self) -> usize {
        self.scene_grid().geometry().height()
    }

    /// Walls, door, poses and every reading in grid cells (see
    /// `DoorwayView`).
    pub fn view(&self) -> Result<JsValue, JsError> {
        to_js(&self.scene.view()?)
    }

    /// Sweeps the next scan; returns `{ scan, cellsVisited, cellsUpdated }`
    /// or `null` once every scan is in.
    #[wasm_bindgen(js_name = sweepStep)]
    pub fn sweep_step(&mut self) -> Result<JsValue, JsError> {
        match self.sweep.step() {
            None => Ok(JsValue::NULL),
            Some(stats) => {
                #[derive(serde::Serialize)]
                #[serde(rename_all = "camelCase")]
                struct Step {
                    scan: usize,
                    cells_visited: usize,
                    cells_updated: usize,
                }
                to_js(&Step {
                    scan: self.sweep.scans_done(),
                    cells_visited: stats.cells_visited,
                    cells_updated: stats.cells_updated,
                })
            }
        }
    }

    #[wasm_bindgen(js_name = sweepReset)]
    pub fn sweep_reset(&mut self) {
        self.sweep.reset();
    }

    /// Renders the swept grid (north up) and returns the address of its
    /// `width * height * 4` RGBA bytes.
    #[wasm_bindgen(js_name = sweepRender)]
    pub fn sweep_render(&mut self) -> usize {
        self.sweep_pixels.render(self.sweep.grid()) as usize
    }

    /// One steepest-ascent flip: the annotated flip (`{ number, cell, ix,
    /// iy, toOccupied, gain, priorTerm, objective, beams: [{ beam, before,
    /// after, delta, expectedRange }] }`) or `null` at a local maximum.
    #[wasm_bindgen(js_name = mapStep)]
    pub fn map_step(&mut self) -> Result<JsValue, JsError> {
        match self.search.step() {
            Some(flip) => to_js(flip),
            None => Ok(JsValue::NULL),
        }
    }

    #[wasm_bindgen(js_name = mapReset)]
    pub fn map_reset(&mut self) {
        self.search.reset();
    }

    /// Runs the climb to its end (at most `maxFlips` more flips, a whole
    /// number; `Infinity` for no limit); returns the number of flips made.
    #[wasm_bindgen(js_name = mapRun)]
    pub fn map_run_js(&mut self, max_flips: f64) -> Result<u32, JsError> {
        let max_flips = budget_from_js("maxFlips", max_flips)?;
        Ok(self.map_run(u32::try_from(max_flips).unwrap_or(u32::MAX)))
    }

    /// Renders the MAP map (black occupied, white free) and returns the
    /// address of its RGBA bytes.
    #[wasm_bindgen(js_name = mapRender)]
    pub fn map_render(&mut self) -> Result<usize, JsError> {
        let n = self.search.geometry().len() * 4;
        self.map_pixels.resize(n, 0);
        crate::render::gray::render_binary_rgba(
            self.search.geometry(),
            self.search.occupied(),
            &mut self.map_pixels,
        )?;
        Ok(self.map_pixels.as_ptr() as usize)
    }

    /// `{ flips: [...], history: [J_0, J_1, ...], objective, converged,
    /// occupied, l0, beams }`.
    #[wasm_bindgen(js_name = mapState)]
    pub fn map_state(&self) -> Result<JsValue, JsError> {
        #[derive(serde::Serialize)]
        struct State<'a> {
            flips: &'a [crate::mapping::map_search::Flip],
            history: &'a [f64],
            objective: f64,
            converged: bool,
            occupied: usize,
            l0: f64,
            beams: usize,
        }
        to_js(&State {
            flips: self.search.flips(),
            history: self.search.history(),
            objective: self.search.objective(),
            converged: self.search.is_converged(),
            occupied: self.search.occupied_count(),
            l0: self.search.l0(),
            beams: self.search.beams().len(),
        })
    }

    /// `{ doorCells, sweepClosed, mapInDoorway, mapOnFarWall, scansDone,
    /// scans }`.
    pub fn report(&self) -> Result<JsValue, JsError> {
        let r = crate::apps::doorway_trap::door_report(
            &self.scene,
            self.sweep.grid(),
            self.search.occupied(),
        )?;
        #[derive(serde::Serialize)]
        #[serde(rename_all = "camelCase")]
        struct Report {
            #[serde(flatten)]
            door: crate::apps::doorway_trap::DoorReport,
            scans_done: usize,
            scans: usize,
        }
        to_js(&Report {
            door: r,
            scans_done: self.sweep.scans_done(),
            scans: self.sweep.scan_count(),
        })
    }

    /// The hover readout of cell `(ix, iy)`: `{ ix, iy, l, p, updates,
    /// occupied, sensitivity, beams }` (swept log odds and probability, the
    /// MAP cell and its objective change if flipped, the cones through it).
    #[wasm_bindgen(js_name = cellInfo)]
    pub fn cell_info(&self, ix: f64, iy: f64) -> Result<JsValue, JsError> {
        let g = *self.search.geometry();
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
        let (ix, iy) = (ix as usize, iy as usize);
        let i = g.index(ix, iy);
        let grid = self.sweep.grid();
        #[derive(serde::Serialize)]
        struct Info {
            ix: usize,
            iy: usize,
            l: f32,
            p: f64,
            updates: u32,
            occupied: bool,
            sensitivity: f64,
            beams: usize,
        }
        to_js(&Info {
            ix,
            iy,
            l: grid.log_odds()[i],
            p: grid.probability_at(i),
            updates: grid.update_counts()[i],
            occupied: self.search.occupied()[i],
            sensitivity: self.search.sensitivity()[i],
            beams: self.search.beams_through(i),
        })
    }

    /// One map (`"sweep"` or `"map"`) as a ROS `map_server` pair:
    /// `{ pgm: Uint8Array, yaml }`.
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(&self, which: JsValue) -> Result<JsValue, JsError> {
        let which = string_from_js("map", &which, "\"sweep\" or \"map\"")?;
        let name = format!("doorway-{which}.pgm");
        let pair = match which.as_str() {
            "sweep" => export::map_server_pair(self.sweep.grid(), &name),
            "map" => export::map_server_pair(&self.search.to_grid(EXPORT_CLAMP)?, &name),
            _ => {
                return Err(JsError::new(&format!(
                    "invalid map: \"{which}\" (expected \"sweep\" or \"map\")"
                )))
            }
        };
        map_pair_to_js(&pair)
    }
}

/// Typed entry points for Rust callers.
impl DoorwayTrap {
    /// [`Self::map_run_js`] for Rust callers.
    pub fn map_run(&mut self, max_flips: u32) -> u32 {
        self.search.run(max_flips as usize) as u32
    }

    fn scene_grid(&self) -> &LogOddsGrid {
        self.sweep.grid()
    }
}

/// The exact joint posterior of a query `{ prior, beta_deg, cells: [{ range,
/// bearing_deg }], readings, model? }`, with everything the two-cell table
/// prints: `{ joint, marginals, allFreeTrue, allFreeFactored, allFreeRatio,
/// mutualInformationBits, table: [{ index, occupied, expectedRange,
/// likelihood, joint, factored }] }`.
#[wasm_bindgen(js_name = jointPosterior)]
pub fn joint_posterior(query: JsValue) -> Result<JsValue, JsError> {
    let q: JointQuery = object_from_js("joint query", query)?;
    to_js(&JointPosterior::compute(&q)?.report())
}

/// The numbers script's answer to a query: exactly `{ joint, marginals,
/// allFreeTrue, allFreeFactored }`.
#[wasm_bindgen(js_name = jointAnswer)]
pub fn joint_answer(query: JsValue) -> Result<JsValue, JsError> {
    let q: JointQuery = object_from_js("joint query", query)?;
    to_js(&JointPosterior::compute(&q)?.answer())
}

/// The chapter's two-cell query (SPEC §6), as data.
#[wasm_bindgen(js_name = chapterTwoCellQuery)]
pub fn chapter_two_cell_query() -> Result<JsValue, JsError> {
    to_js(&JointQuery::chapter_two_cells())
}
