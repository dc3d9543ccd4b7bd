//! Bindings of `<occgrid-sensor-fusion>`: the table scene, one grid per
//! sensor, max fusion (eq. 9.9) against summation. The widget steps the
//! core, draws the four maps from wasm memory and reads small readouts.

use super::{
    budget_from_js, index_from_js, map_pair_to_js, number_from_js, object_or_default,
    string_from_js, to_js, Pixels,
};
use crate::apps::sensor_fusion::{FusionModels, TableFusion};
use crate::grid::LogOddsGrid;
use crate::io::map_server as export;
use crate::scenes::table::TableScene;
use wasm_bindgen::prelude::*;

/// The table-scene fusion experiment held in wasm memory.
#[wasm_bindgen]
pub struct SensorFusion {
    fusion: TableFusion,
    pixels: [Pixels; 4],
}

/// The four maps, in the order of `pixels`.
const MAPS: [&str; 4] = ["sonar", "lidar", "max", "sum"];

#[wasm_bindgen]
impl SensorFusion {
    /// Builds the scene. `scene` may be `undefined` (the chapter's scene) or
    /// an object overriding any field of the scene (`{ seed: 3, lidar: {
    /// beams: 90 } }`); `models` likewise overrides the inverse models
    /// (`{ sonar_p_occ: 0.75 }`).
    #[wasm_bindgen(constructor)]
    pub fn new(scene: JsValue, models: JsValue) -> Result<SensorFusion, JsError> {
        let scene: TableScene = object_or_default("scene", scene, TableScene::default)?;
        let models: FusionModels = object_or_default("models", models, FusionModels::default)?;
        Ok(SensorFusion {
            fusion: TableFusion::with_models(&scene, models)?,
            pixels: Default::default(),
        })
    }

    /// Integrates the next step into all four maps (after any rebuild under
    /// way, at once); false at the end.
    pub fn step(&mut self) -> bool {
        self.fusion.step()
    }

    /// Integrates up to `steps` steps for about `budget` cell visits (whole
    /// numbers, `Infinity` for no limit; at least one piece of a step while
    /// the lap lasts, past the budget by at most one piece: a step left
    /// under way is finished by the next calls, and the maps and readouts
    /// change only when a step is whole), then refreshes the fused map
    /// once: the call a page makes per animation frame. A rebuild after
    /// `setLidarBeams` comes first and `steps` new steps only after it.
    /// Returns `{ steps, rebuilt, cellVisits, step, rebuilding, underWay,
    /// done }`.
    pub fn work(&mut self, steps: JsValue, budget: JsValue) -> Result<JsValue, JsError> {
        let steps = budget_from_js("steps", &steps)?;
        let budget = budget_from_js("budget", &budget)? as u64;
        to_js(&self.fusion.work(steps, budget))
    }

    /// Runs to the end of the lap; returns the number of steps taken.
    #[wasm_bindgen(js_name = runToEnd)]
    pub fn run_to_end(&mut self) -> usize {
        self.fusion.run_to_end()
    }

    pub fn reset(&mut self) {
        self.fusion.reset();
    }

    /// Changes only the LiDAR's beam count and empties the LiDAR's own and
    /// the summed map, which the next `work` calls rebuild over the steps so
    /// far within their budgets (`readout().rebuilding` counts the steps
    /// they still lack), before any new step. `beams` must be a whole
    /// number from 1 to 2048; a refused one changes nothing.
    #[wasm_bindgen(js_name = setLidarBeams)]
    pub fn set_lidar_beams(&mut self, beams: JsValue) -> Result<(), JsError> {
        let beams = number_from_js("lidar.beams", &beams)?;
        if !(beams.is_finite() && beams >= 0.0 && beams.fract() == 0.0 && beams <= 1e9) {
            return Err(JsError::new(&format!(
                "invalid lidar.beams: {beams} (expected a whole number of beams)"
            )));
        }
        Ok(self.fusion.stage_lidar_beams(beams as usize)?)
    }

    /// `{ step, steps, lidarBeams, sonarCount, footprintCells, footprint:
    /// { sonar, lidar, max, sum }, pose: { x, y, theta }, rebuilding,
    /// scansSimulated }`.
    pub fn readout(&self) -> Result<JsValue, JsError> {
        to_js(&self.fusion.readout())
    }

    /// The cell under image pixel `(col, row)` of the north-up maps (whole
    /// numbers, row 0 at the top): `{ sonar, lidar, sum }` each `{ ix, iy,
    /// x, y, l, p, updates, unknown }`, `max` (eq. 9.9's p) and `footprint`
    /// (under the table top); `null` off the map.
    #[wasm_bindgen(js_name = cellAt)]
    pub fn cell_at(&self, col: JsValue, row: JsValue) -> Result<JsValue, JsError> {
        let col = index_from_js("col", &col)?;
        let row = index_from_js("row", &row)?;
        match self.fusion.cell_at_pixel(col, row) {
            Some(c) => to_js(&c),
            None => Ok(JsValue::NULL),
        }
    }

    /// `{ robot: [u, v, theta], footprint: [u0, v0, u1, v1],
    /// sonarHalfWidth, sonar: [{ angle, range }], lidar: [u0, v0, ...] }`
    /// in grid cells (v north).
    #[wasm_bindgen(js_name = sceneView)]
    pub fn scene_view(&self) -> Result<JsValue, JsError> {
        to_js(&self.fusion.scene_view())
    }

    #[wasm_bindgen(getter)]
    pub fn width(&self) -> usize {
        self.fusion.sonar().geometry().width()
    }

    #[wasm_bindgen(getter)]
    pub fn height(&self) -> usize {
        self.fusion.sonar().geometry().height()
    }

    /// Renders one map (`"sonar"`, `"lidar"`, `"max"` or `"sum"`) to RGBA,
    /// north up, and returns the address of its `width * height * 4` bytes
    /// in wasm memory.
    pub fn render(&mut self, which: JsValue) -> Result<usize, JsError> {
        let k = map_index(&which)?;
        let grid = map_of(&self.fusion, k);
        let slot = self
            .pixels
            .get_mut(k)
            .ok_or_else(|| JsError::new("no such map"))?;
        Ok(slot.render(grid) as usize)
    }

    /// One map as a ROS `map_server` pair: `{ pgm: Uint8Array, yaml }`.
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(&self, which: JsValue) -> Result<JsValue, JsError> {
        let k = map_index(&which)?;
        let name = format!("table-{}.pgm", MAPS[k]);
        let pair = export::map_server_pair(map_of(&self.fusion, k), &name);
        map_pair_to_js(&pair)
    }
}

/// The index in [`MAPS`] of the map JavaScript named.
fn map_index(which: &JsValue) -> Result<usize, JsError> {
    const EXPECTED: &str = "\"sonar\", \"lidar\", \"max\" or \"sum\"";
    let which = string_from_js("map", which, EXPECTED)?;
    MAPS.iter()
        .position(|&m| m == which)
        .ok_or_else(|| JsError::new(&format!("invalid map: {which:?} (expected {EXPECTED})")))
}

fn map_of(f: &TableFusion, k: usize) -> &LogOddsGrid {
    match k {
        0 => f.sonar(),
        1 => f.lidar(),
        2 => f.fused(),
        _ => f.summed(),
    }
}
