//! What a [`LogPane`] shows a reader: the window onto its map (zoom, pan,
//! the output size), the keyboard cursor, the cell readouts, the legend of
//! the view's scale, the robot and its path in image units, the counts and
//! the `map_server` export. Every number a panel prints about a pane is
//! computed here; the page forwards pointer and key input and draws.

use super::pane::LogPane;
use super::provenance::Provenance;
use crate::error::{invalid, Result};
use crate::grid::readout::CellReadout;
use crate::grid::storage::TILE_CELLS;
use crate::io::map_server::{self, ExportCounts, MapServerPair};
use crate::render::overlay::{ImageCell, RobotMark};
use crate::render::viewport::MapViewport;

/// Output pixels one arrow-key press moves the cursor at any zoom (at
/// least one cell): a step a reader sees on a zoomed-out map and one cell
/// at a time when zoomed in.
pub const CURSOR_STEP_PX: f64 = 16.0;
/// Arrow keys with the modifier for long steps move this many steps.
pub const CURSOR_LONG_STEPS: usize = 10;
/// The share of the view's smaller side within which the cursor counts as
/// at the edge: the view re-centres on it there.
const CURSOR_EDGE: f64 = 0.05;

/// The map's limits as a page shows them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GeometryReport {
    pub width: usize,
    pub height: usize,
    /// Metres per cell.
    pub resolution: f64,
    /// World position of the map's lower-left corner, metres.
    pub origin_x: f64,
    pub origin_y: f64,
}

/// The view's scale as a panel states it, for an output whose device
/// pixels are `device_pixels_per_screen_pixel` to a screen (CSS) pixel.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ViewLegend {
    /// Screen pixels one cell spans (below 1 when zoomed out).
    pub screen_pixels_per_cell: f64,
    /// Metres one screen pixel spans.
    pub metres_per_screen_pixel: f64,
    /// The part of the map on screen, metres.
    pub width_metres: f64,
    pub height_metres: f64,
    /// `"2.8 cells per screen pixel, 58.1 m × 58.4 m shown"`, or `"4.0
    /// screen pixels per cell, ..."` when a cell spans a pixel or more.
    pub text: String,
}

impl LogPane {
    /// The map's limits.
    pub fn geometry(&self) -> GeometryReport {
        let g = self.grid().geometry();
        let [origin_x, origin_y] = g.origin();
        GeometryReport {
            width: g.width(),
            height: g.height(),
            resolution: g.resolution(),
            origin_x,
            origin_y,
        }
    }

    /// The caption of this pane: its pose source, and its cell model when
    /// the session compares two.
    pub fn caption(&self) -> String {
        let poses = self.source().caption(self.settings().seed);
        match self.settings().compare_model {
            None => poses,
            Some(_) => format!("{poses}, {}", self.model().caption()),
        }
    }

    /// How many cells are occupied, free and unknown now, counted with the
    /// thresholds of the exported file (what the PGM would show and
    /// `map_server` load), which the counts carry.
    ///
    /// Kept per tile as the build writes them
    /// ([`crate::grid::stats::TileTally`]): a tile is
    /// recounted once per call of the build that wrote it, so that the
    /// counts of a finished map walk no cell.
    pub fn counts(&self) -> ExportCounts {
        ExportCounts::from_states(self.map.counts(&self.tally))
    }

    /// Brings the counts kept per tile up to date with the tiles written
    /// since the last call; returns the cells recounted.
    pub(super) fn refresh_counts(&mut self) -> usize {
        self.map.refresh(&mut self.tally)
    }

    /// The cells a refresh of the counts would recount now: the tiles
    /// written since it last ran.
    pub fn counts_pending(&self) -> usize {
        self.map.tiles_touched() * TILE_CELLS
    }

    /// The laser positions of all scans in image units (x to the right, y
    /// down, pixel `(c, r)` spanning `[c, c+1) x [r, r+1)`), as
    /// `[x0, y0, x1, y1, ...]`: a page draws the robot's path from it.
    pub fn path_in_pixels(&self) -> Vec<f32> {
        self.map.path_pixels(self.poses())
    }

    /// The laser positions of scans `from..to` alone (clipped to the
    /// scans there are), as [`Self::path_in_pixels`] gives them: a page
    /// that keeps a growing path asks only for the scans located since it
    /// last asked, not for every scan at every drawing.
    pub fn path_in_pixels_between(&self, from: usize, to: usize) -> Vec<f32> {
        let poses = self.poses();
        let to = to.min(poses.len());
        self.map.path_pixels(&poses[from.min(to)..to])
    }

    /// The robot at scan `k` in image units, heading as an image angle
    /// (see [`crate::render::overlay`]), or `None` past the last scan.
    pub fn robot_at(&self, k: usize) -> Option<RobotMark> {
        let pose = self.poses().get(k)?;
        Some(self.map.robot_at(pose))
    }

    /// The cell under image pixel `(col, row)` (row 0 at the top, north
    /// up), or `None` outside the map.
    pub fn readout_at_pixel(&self, col: usize, row: usize) -> Option<CellReadout> {
        self.map.readout_at_pixel(col, row)
    }

    pub fn view(&self) -> &MapViewport {
        &self.map.view().viewport
    }

    fn viewport_mut(&mut self) -> &mut MapViewport {
        &mut self.map.view_mut().viewport
    }

    /// The output's size in pixels (the canvas's device pixels): the view
    /// keeps its centre and zoom (and stays fitted if it was).
    pub fn set_view_size(&mut self, width: usize, height: usize) -> Result<()> {
        self.viewport_mut().resize(width, height)
    }

    /// Shows the whole map.
    pub fn fit_view(&mut self) {
        self.viewport_mut().fit();
    }

    /// Zooms by `factor` about output pixel `(x, y)` ([`MapViewport::zoom_at`]).
    pub fn zoom_view(&mut self, x: f64, y: f64, factor: f64) -> Result<()> {
        self.viewport_mut().zoom_at(x, y, factor)
    }

    /// Moves the map by `(dx, dy)` output pixels.
    pub fn pan_view(&mut self, dx: f64, dy: f64) -> Result<()> {
        self.viewport_mut().pan_by(dx, dy)
    }

    /// Draws the view into `out` (its `width * height * 4` RGBA bytes).
    pub fn render_view(&mut self) -> &[u8] {
        self.map.pixels()
    }

    /// Draws the view a band of rows at a time, at most `max_samples` map
    /// cells sampled per call (whole rows, at least one; a `quick` picture
    /// one cell per pixel: see
    /// [`crate::apps::pane::ScreenView::refresh_within`]); true once the
    /// picture is whole, when [`Self::view_pixels`] holds it. The last
    /// whole picture stays until then.
    pub fn render_view_within(&mut self, max_samples: usize, quick: bool) -> bool {
        self.map.pixels_within(max_samples, quick)
    }

    /// The last view drawn whole (RGBA, `width * height * 4` bytes of the
    /// view it was drawn at; empty before the first).
    pub fn view_pixels(&self) -> &[u8] {
        self.map.view().pixels()
    }

    /// The cell under output position `(x, y)` (pixels, finite), or `None`
    /// off the map.
    pub fn readout_at_view(&self, x: f64, y: f64) -> Result<Option<CellReadout>> {
        if !(x.is_finite() && y.is_finite()) {
            return Err(invalid(
                "view position",
                format!("({x}, {y})"),
                "finite pixels",
            ));
        }
        Ok(self.map.readout_at_view(x, y))
    }

    /// The view's scale in words and numbers, for an output of
    /// `device_pixels_per_screen_pixel` device pixels per screen pixel (a
    /// page's device pixel ratio, as the canvas is sized; positive).
    pub fn legend(&self, device_pixels_per_screen_pixel: f64) -> Result<ViewLegend> {
        let dpr = device_pixels_per_screen_pixel;
        if !(dpr.is_finite() && dpr > 0.0) {
            return Err(invalid(
                "devicePixelRatio",
                crate::error::show(dpr),
                "a positive number of device pixels per screen pixel",
            ));
        }
        let v = self.view();
        let res = self.grid().geometry().resolution();
        let per_cell = v.scale / dpr;
        let (width_metres, height_metres) = (
            v.width as f64 / v.scale * res,
            v.height as f64 / v.scale * res,
        );
        let scale = if per_cell >= 1.0 {
            format!("{:.1} screen pixels per cell", per_cell)
        } else {
            format!("{:.1} cells per screen pixel", 1.0 / per_cell)
        };
        Ok(ViewLegend {
            screen_pixels_per_cell: per_cell,
            metres_per_screen_pixel: res / per_cell,
            width_metres,
            height_metres,
            text: format!("{scale}, {width_metres:.1} m \u{d7} {height_metres:.1} m shown"),
        })
    }

    /// The keyboard cursor's cell, if the reader has placed one.
    pub fn cursor(&self) -> Option<ImageCell> {
        self.cursor.map(|(col, row)| ImageCell { col, row })
    }

    /// Forgets the keyboard cursor (the map lost focus, or the pointer
    /// took over).
    pub fn clear_cursor(&mut self) {
        self.cursor = None;
    }

    /// The cursor's cell, or the cell at the view's centre when there is
    /// no cursor yet.
    fn cursor_or_centre(&self) -> (usize, usize) {
        self.cursor.unwrap_or_else(|| {
            let v = self.view();
            let clamp = |a: f64, n: usize| (a.floor().max(0.0) as usize).min(n - 1);
            (
                clamp(v.u0 + v.width as f64 / (2.0 * v.scale), v.map_width),
                clamp(v.v0 + v.height as f64 / (2.0 * v.scale), v.map_height),
            )
        })
    }

    /// The output position of the centre of image cell `(col, row)`.
    fn output_of(&self, (col, row): (usize, usize)) -> (f64, f64) {
        let v = self.view();
        (
            (col as f64 + 0.5 - v.u0) * v.scale,
            (row as f64 + 0.5 - v.v0) * v.scale,
        )
    }

    /// Moves the keyboard cursor by `(dx, dy)` steps (each −1, 0 or 1:
    /// an arrow key; `long` for [`CURSOR_LONG_STEPS`] steps), starting at
    /// the view's centre the first time. A step is [`CURSOR_STEP_PX`]
    /// output pixels at the current zoom, at least one cell; the cursor
    /// stays on the map, and a cursor near the view's edge brings the view
    /// back to centre on it. Returns the cell under the cursor.
    pub fn move_cursor(&mut self, dx: i8, dy: i8, long: bool) -> Result<Option<CellReadout>> {
        for (name, d) in [("dx", dx), ("dy", dy)] {
            if !(-1..=1).contains(&d) {
                return Err(invalid(name, d, "-1, 0 or 1 (one arrow key)"));
            }
        }
        let (col, row) = self.cursor_or_centre();
        let steps = if long { CURSOR_LONG_STEPS } else { 1 };
        let v = *self.view();
        let step = ((CURSOR_STEP_PX / v.scale).round() as usize).max(1) * steps;
        let go = |at: usize, d: i8, n: usize| match d {
            -1 => at.saturating_sub(step),
            1 => at.saturating_add(step).min(n - 1),
            _ => at,
        };
        let to = (go(col, dx, v.map_width), go(row, dy, v.map_height));
        self.cursor = Some(to);
        let (x, y) = self.output_of(to);
        let m = v.width.min(v.height) as f64 * CURSOR_EDGE;
        if x < m || y < m || x > v.width as f64 - m || y > v.height as f64 - m {
            self.viewport_mut()
                .pan_by(v.width as f64 / 2.0 - x, v.height as f64 / 2.0 - y)?;
        }
        Ok(self.readout_at_pixel(to.0, to.1))
    }

    /// Zooms by `factor` about the keyboard cursor (placed at the view's
    /// centre if there is none yet); returns the cell under it.
    pub fn zoom_at_cursor(&mut self, factor: f64) -> Result<Option<CellReadout>> {
        let here = self.cursor_or_centre();
        let (x, y) = self.output_of(here);
        self.viewport_mut().zoom_at(x, y, factor)?;
        self.cursor = Some(here);
        Ok(self.readout_at_pixel(here.0, here.1))
    }

    /// Shows the whole map, keeping the keyboard cursor (placed at the
    /// view's centre if there is none yet); returns the cell under it.
    pub fn fit_at_cursor(&mut self) -> Option<CellReadout> {
        let here = self.cursor_or_centre();
        self.viewport_mut().fit();
        self.cursor = Some(here);
        self.readout_at_pixel(here.0, here.1)
    }

    /// The file stem of this pane's export for a log file named
    /// `file_name`: `intel-corrected.log.gz` gives `intel-corrected-map`
    /// for the corrected poses and `intel-corrected-dead-reckoning-map`
    /// for dead reckoning.
    pub fn export_stem(&self, file_name: &str) -> String {
        let lower = file_name.to_ascii_lowercase();
        let mut stem = file_name;
        if lower.ends_with(".gz") {
            stem = &stem[..stem.len() - 3];
        }
        let lower = stem.to_ascii_lowercase();
        for ext in [".log", ".clf", ".txt"] {
            if lower.ends_with(ext) {
                stem = &stem[..stem.len() - ext.len()];
                break;
            }
        }
        let stem = if stem.is_empty() { "log" } else { stem };
        match self.source().info().export_suffix {
            None => format!("{stem}-map"),
            Some(suffix) => format!("{stem}-{suffix}-map"),
        }
    }

    /// The map as a ROS `map_server` pair, the YAML naming the image
    /// `NAME.pgm` (`map.pgm` without a name). A map at other poses than the
    /// log's own says which in a comment line of the YAML: the file alone
    /// then tells a dead-reckoned map from the corrected one.
    pub fn export_map(&self, name: Option<&str>) -> MapServerPair {
        self.export_map_of(name, None)
    }

    /// [`Self::export_map`] of the log opened as `log_file` (its name
    /// only): the YAML's comments say how the map was made
    /// (`apps/real_log/provenance.rs`), the log's name among them when given.
    pub fn export_map_of(&self, name: Option<&str>, log_file: Option<&str>) -> MapServerPair {
        let stem = map_server::file_stem(name.unwrap_or(""));
        let mut pair = self.map.export(&format!("{stem}.pgm"));
        if let Some(poses) = self.source().described(self.settings().seed) {
            pair.yaml.push_str(&format!("# poses: {poses}\n"));
        }
        let provenance = Provenance {
            log_file,
            source: self.source(),
            model: self.model(),
            settings: self.settings(),
        };
        pair.yaml.push_str(&provenance.yaml_comments());
        pair
    }
}
