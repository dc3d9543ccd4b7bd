//! What a pane mapped without the log's poses shows besides its map, for
//! [`RealLogSession`]: the pose graph of a SLAM pane and the pose error
//! against the log's corrected poses. Every method converts the pane
//! index, then calls the pane it picks.

use super::RealLogSession;
use crate::bindings::index_from_js;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
impl RealLogSession {
    /// Pane `pane`'s pose graph over the scans placed so far, in image
    /// units, or `undefined` for a pane without one (any source but SLAM): a
    /// Float32Array `[nodes, locals, loops, u, v, … (nodes points), u0,
    /// v0, u1, v1, … (locals segments, then loops segments)]`.
    #[wasm_bindgen(js_name = poseGraph)]
    pub fn pose_graph(&self, pane: JsValue) -> Result<Option<Vec<f32>>, JsError> {
        let pane = index_from_js("pane", &pane)?;
        Ok(self.session.pane(pane)?.pose_graph_pixels())
    }

    /// Pane `pane`'s pose error against the log's corrected poses over the
    /// scans placed so far: a Float64Array `[scans, placed, ateM,
    /// scanErrorM]` (the aligned absolute trajectory error, and the last
    /// counted scan's position error under that alignment, metres; `scans`
    /// of `placed` counted, a bounded number more each call), or `undefined`
    /// when the log has no corrected poses, for the pane at them, and
    /// before its first scan.
    #[wasm_bindgen(js_name = poseError)]
    pub fn pose_error(&mut self, pane: JsValue) -> Result<Option<Vec<f64>>, JsError> {
        let pane = index_from_js("pane", &pane)?;
        let view = self.session.pane_mut(pane)?.pose_error();
        Ok(view.map(|v| v.to_array().to_vec()))
    }
}
