//! Bindings for real CARMEN logs: the session behind Map Weaver's
//! real-log mode ([`RealLogSession`], the same name as the core session it
//! wraps): reading, settings, the build, the robot and the exports here,
//! the view and the keyboard cursor of a pane in [`view`], the pose graph
//! and the pose error of a pane in [`slam_view`]. Every method
//! converts its JavaScript arguments to plain Rust values first, then
//! delegates: one call into the core session, or into the pane it picks
//! by index ([`app::RealLogSession::pane`]).

mod slam_view;
mod view;

use super::{
    budget_from_js, bytes_from_js, index_from_js, map_pair_to_js, now_ms, number_from_js,
    object_from_js, optional_number_from_js, string_from_js, to_js,
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
        Ok(Self {
            session: app::RealLogSession::with_log(bytes, &name),
        })
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

    /// Names the topics of a ROS 2 bag to map, before its first read:
    /// `scanTopic` (its LaserScan topic) and `odomTopic` (its Odometry
    /// topic), each a string, or `undefined` / `null` for the bag's only
    /// one.
    #[wasm_bindgen(js_name = chooseTopics)]
    pub fn choose_topics(
        &mut self,
        scan_topic: JsValue,
        odom_topic: JsValue,
    ) -> Result<(), JsError> {
        let topic = |field: &str, v: &JsValue| -> Result<Option<String>, JsError> {
            if v.is_undefined() || v.is_null() {
                Ok(None)
            } else {
                string_from_js(field, v, "a topic name, or nothing").map(Some)
            }
        };
        let scan = topic("scanTopic", &scan_topic)?;
        let odom = topic("odomTopic", &odom_topic)?;
        Ok(self.session.choose_topics(scan, odom)?)
    }

    /// The poses the log just opened is mapped at when the reader names
    /// none (`corrected` for a CARMEN log, `odometry` for a ROS 2 bag), or
    /// `undefined` once it is read.
    #[wasm_bindgen(js_name = ownPoses)]
    pub fn own_poses(&self) -> Option<String> {
        self.session.own_poses().map(|k| k.name().to_string())
    }

    /// Reads up to `maxScans` more scans (a whole number; `Infinity` for
    /// the rest of the log) and returns `{ records, recordName, scans,
    /// beams, bytesRead, bytesTotal, finished, warning }` (`recordName` is
    /// what the log's format calls its records: a CARMEN log's `lines`).
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
    /// panes: [{ poses, caption, scansDone, ... }], topics, settings, limits
    /// }` (`topics`, after a bag's read refused for want of a topic
    /// choice: `{ scanTopics, odomTopics }`, each `[{ topic, type,
    /// messages }]`; else `null`),
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
    /// scans are like. With `withinMs` (milliseconds, more than 0), the
    /// call also stops after the first step that ends that long after it
    /// began on the host's clock (`performance.now`), so that it ends
    /// within a step of its time whatever a unit of work costs on this
    /// machine; `undefined` or `null` for no time bound. Where a call stops
    /// does not change the maps. Returns the state.
    #[wasm_bindgen(js_name = buildSlice)]
    pub fn build_slice(
        &mut self,
        max_cells: JsValue,
        within_ms: JsValue,
    ) -> Result<JsValue, JsError> {
        let max_cells = cells_from_js("maxCells", &max_cells)?;
        let state = match optional_number_from_js("withinMs", &within_ms)? {
            None => self.session.build_slice(max_cells)?,
            Some(within) if within.is_nan() || within <= 0.0 => {
                return Err(JsError::new(&format!(
                    "invalid withinMs: {within} (expected milliseconds more than 0)"
                )));
            }
            Some(within) => {
                let start = now_ms();
                // A clock that reads NaN (no `performance.now`) never says
                // the time is up: the budget of work still bounds the call.
                self.session
                    .build_slice_until(max_cells, || now_ms() - start >= within)?
            }
        };
        to_js(&state)
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

    /// The laser positions of scans `from..to` on pane `pane` (clipped to
    /// its scans), `[x0, y0, ...]`: a growing path's new part.
    #[wasm_bindgen(js_name = pathPixelsBetween)]
    pub fn path_pixels_between(
        &self,
        pane: JsValue,
        from: JsValue,
        to: JsValue,
    ) -> Result<Vec<f32>, JsError> {
        let pane = index_from_js("pane", &pane)?;
        let from = index_from_js("from", &from)?;
        let to = index_from_js("to", &to)?;
        Ok(self.session.pane(pane)?.path_in_pixels_between(from, to))
    }

    /// The robot at scan `k` over pane `pane`: `{ x, y, heading }` in image
    /// units, the heading an image angle (radians clockwise on screen).
    #[wasm_bindgen(js_name = robotAt)]
    pub fn robot_at(&self, pane: JsValue, k: JsValue) -> Result<JsValue, JsError> {
        let (pane, k) = (index_from_js("pane", &pane)?, index_from_js("scan", &k)?);
        to_js(&self.session.robot_at(pane, k)?)
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
    /// log's own, saying which in a comment line; the YAML's comments say
    /// how the map was made, naming the log as `logFile` (a string, or
    /// `undefined` when the page has no name for it).
    #[wasm_bindgen(js_name = exportMap)]
    pub fn export_map(
        &self,
        pane: JsValue,
        name: JsValue,
        log_file: JsValue,
    ) -> Result<JsValue, JsError> {
        let pane = index_from_js("pane", &pane)?;
        let optional = |field: &str, v: &JsValue, what: &str| {
            if v.is_undefined() || v.is_null() {
                Ok(None)
            } else {
                string_from_js(field, v, what).map(Some)
            }
        };
        let name = optional("name", &name, "a file name, or nothing for map.pgm")?;
        let log_file = optional("logFile", &log_file, "the log's file name, or nothing")?;
        map_pair_to_js(
            &self
                .session
                .pane(pane)?
                .export_map_of(name.as_deref(), log_file.as_deref()),
        )
    }
}
