//! The real-log session behind Map Weaver's real-log mode: a CARMEN log read
//! a few lines at a time, then mapped a few scans at a time with the ray
//! traversal (Table 9.1) and the hand-crafted model (Table 9.2), so that a
//! page shows progress, stays responsive, and can scrub through the build.
//!
//! [`RealLogSession`] is the state machine a page drives (reading →
//! waiting for settings that fit → building); [`LogMapBuild`] the build
//! itself; [`LogMapSettings`] what a reader chooses.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::raster::{Cursor as RasterCursor, Walk};
use crate::geometry::GridGeometry;
use crate::grid::readout::CellReadout;
use crate::grid::tiled::{
    budget_message, tiles_of, TiledGrid, DEFAULT_TILE_BUDGET_CELLS, TILE_SIDE,
};
use crate::grid::FilterSettings;
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::io::carmen::{LaserScans, LoadProgress, LogBudget, LogLoader};
use crate::io::map_server::{self, ExportCounts, MapServerPair};
use crate::mapping::traversal::{BeamBand, RayMapper, MAX_REACH_CELLS};
use crate::mapping::walls::{beam_bands, WallModel};
use crate::render::overlay::RobotMark;
use crate::render::viewport::{render_tiled_view, MapViewport};
use crate::sensors::odometry::OdometryParams;
use std::io::Cursor;

/// Where the scans are put on the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum PoseSource {
    /// The log's own (corrected) laser poses: the pose oracle.
    #[default]
    #[serde(rename = "corrected")]
    Corrected,
    /// Dead reckoning: the log's motion increments between consecutive
    /// laser poses, each corrupted with the odometry noise of Table 5.6
    /// ([`OdometryParams::WHEELS`], drawn from `seed`) and integrated from
    /// the first pose. The corrected logs carry no raw odometry (their
    /// odometry fields repeat the corrected poses), so the noise is made
    /// here: the chapter's "pose oracle off" on a real building.
    #[serde(rename = "dead-reckoning")]
    DeadReckoning,
}

impl PoseSource {
    /// The names a page and the CLI use.
    pub const NAMES: [&'static str; 2] = ["corrected", "dead-reckoning"];
}

/// What the reader of a log chooses for its map: the grid's resolution,
/// the inverse model of Table 9.2, how far a no-return clears, how free
/// evidence ends near a wall ([`WallModel`]), the filter's clamp and where
/// the scans are put ([`PoseSource`], with the seed of its noise). The
/// defaults keep walls and the outside of a building gray
/// ([`crate::mapping::walls`]); [`Self::chapter`] is Table 9.2 with the
/// chapter's clamp, exactly workload W1 (BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase", deny_unknown_fields)]
pub struct LogMapSettings {
    /// Metres per cell.
    pub resolution: f64,
    /// The model's `z_max`, metres: readings at or beyond it are
    /// no-returns (they carve free space out to it and mark nothing), and
    /// only endpoints closer than it decide the grid's extent.
    pub range_cap: f64,
    /// Obstacle thickness `alpha`, metres.
    pub alpha: f64,
    /// Evidence at the reading, log odds.
    pub l_occ: f64,
    /// Evidence in front of the reading, log odds.
    pub l_free: f64,
    /// Saturation `|l| <= clamp`, log odds.
    pub clamp: f64,
    /// Free border around the log's extent, metres.
    pub margin: f64,
    /// How far a no-return (a reading at or beyond `rangeCap`) clears free
    /// space, metres (at most `rangeCap`).
    pub no_return_reach: f64,
    /// How a beam's free evidence ends before its reading.
    pub walls: WallModel,
    /// The poses the scans are mapped at.
    pub poses: PoseSource,
    /// The seed of dead reckoning's noise (one seed, one path; unused for
    /// the corrected poses).
    pub seed: u64,
}

/// The default no-return reach, metres (Cartographer's
/// `missing_data_ray_length` default).
pub const NO_RETURN_REACH: f64 = 5.0;

/// The largest seed: the largest whole number a JavaScript number holds
/// exactly.
pub const MAX_SEED: u64 = (1 << 53) - 1;

impl Default for LogMapSettings {
    fn default() -> Self {
        let laser = HandCraftedParams::laser(30.0);
        Self {
            resolution: 0.05,
            range_cap: laser.z_max,
            alpha: laser.alpha,
            l_occ: laser.l_occ,
            l_free: laser.l_free,
            clamp: 3.5,
            margin: 1.0,
            no_return_reach: NO_RETURN_REACH,
            walls: WallModel::Incidence,
            poses: PoseSource::Corrected,
            seed: 1,
        }
    }
}

impl LogMapSettings {
    /// The field names as a page spells them (the serde names).
    pub const FIELDS: [&'static str; 11] = [
        "resolution",
        "rangeCap",
        "alpha",
        "lOcc",
        "lFree",
        "clamp",
        "margin",
        "noReturnReach",
        "walls",
        "poses",
        "seed",
    ];

    /// Table 9.2 with the chapter's clamp, no-returns carving out to
    /// `z_max`: workload W1's map, and the lesson of walls that wear away.
    pub fn chapter() -> Self {
        Self {
            no_return_reach: 30.0,
            walls: WallModel::Table92,
            ..Self::default()
        }
    }

    /// The grid covering `extent` (from [`LaserScans::endpoint_bounds`]) plus the
    /// margin, its corners on whole multiples of the resolution (so that
    /// maps of one log at one resolution line up cell for cell). Its cells
    /// are allocated in tiles as the beams reach them, so the bounding box
    /// is limited only by its export ([`GridGeometry::sparse`]).
    pub fn geometry(&self, extent: [f64; 4]) -> Result<GridGeometry> {
        let r = error::positive("resolution", self.resolution)?;
        let m = error::non_negative("margin", self.margin)?;
        let [x0, y0, x1, y1] = extent;
        let (i0, j0) = (((x0 - m) / r).floor(), ((y0 - m) / r).floor());
        let (i1, j1) = (((x1 + m) / r).floor() + 1.0, ((y1 + m) / r).floor() + 1.0);
        let (w, h) = (i1 - i0, j1 - j0);
        // Written so that a NaN (cells so small that both edges overflow to
        // the same infinity) is refused too; `GridGeometry::sparse` then says what
        // the size would weigh.
        if !(w >= 1.0 && h >= 1.0 && w * h <= 1e15) {
            return Err(invalid(
                "width x height",
                format!("{w} x {h}"),
                "at most 268435456 cells (a 256 MiB image): a coarser resolution",
            ));
        }
        // Rounded to a nanometre: -418 cells of 0.05 m is -20.900000000000002
        // in binary, and the exported YAML should read -20.9.
        let round = |v: f64| (v * 1e9).round() / 1e9;
        let (ox, oy) = (round(i0 * r), round(j0 * r));
        // Absurdly large cells put the corners beyond f64 (the rounding
        // above overflows first): the page sent a resolution, so name it.
        let corners = [ox, oy, ox + w * r, oy + h * r];
        if !corners.iter().all(|c| c.is_finite()) {
            return Err(invalid(
                "resolution",
                error::show(r),
                "cells small enough that the map's corners are finite numbers of metres",
            ));
        }
        GridGeometry::sparse(w as usize, h as usize, r, ox, oy)
    }

    fn model_params(&self) -> HandCraftedParams {
        HandCraftedParams {
            alpha: self.alpha,
            l_occ: self.l_occ,
            l_free: self.l_free,
            ..HandCraftedParams::laser(self.range_cap)
        }
    }

    fn filter(&self) -> FilterSettings {
        FilterSettings {
            prior: 0.5,
            clamp: self.clamp,
        }
    }

    /// Checks every field, naming the first bad one as a page spells it
    /// (the serde names).
    pub fn validate(&self) -> Result<()> {
        error::positive("resolution", self.resolution)?;
        error::positive("rangeCap", self.range_cap)?;
        error::positive("alpha", self.alpha)?;
        error::finite("lOcc", self.l_occ)?;
        error::finite("lFree", self.l_free)?;
        error::non_negative("margin", self.margin)?;
        error::positive("noReturnReach", self.no_return_reach)?;
        // A page sends the seed as a JavaScript number: past 2^53 two seeds
        // would be the same number there.
        if self.seed > MAX_SEED {
            return Err(invalid(
                "seed",
                self.seed,
                "a whole number from 0 to 9007199254740991 (2^53 - 1)",
            ));
        }
        // Free evidence lowers a cell and occupied evidence raises it: the
        // traversal gathers them as two flags.
        // (Compared as the f32 the map stores: 1e-50 is 0 there.)
        if !((self.l_occ as f32) > 0.0) {
            return Err(invalid(
                "lOcc",
                error::show(self.l_occ),
                "log odds above 0 (at least 1e-38)",
            ));
        }
        if !((self.l_free as f32) < 0.0) {
            return Err(invalid(
                "lFree",
                error::show(self.l_free),
                "log odds below 0 (at most -1e-38)",
            ));
        }
        // The model checks what is left of it (evidence past f32) under its
        // own names: report them as the page spells them.
        HandCrafted::new(self.model_params()).map_err(Self::page_names)?;
        // What is left to check (the clamp) is named alike by the filter.
        self.filter().validate()
    }

    /// A Table 9.2 model error under the name the page used for the field.
    fn page_names(e: OccError) -> OccError {
        match e {
            OccError::InvalidParameter {
                field,
                value,
                expected,
            } => {
                let field = match field.as_str() {
                    "z_max" => "rangeCap".to_string(),
                    "l_occ" => "lOcc".to_string(),
                    "l_free" => "lFree".to_string(),
                    _ => field,
                };
                OccError::InvalidParameter {
                    field,
                    value,
                    expected,
                }
            }
            other => other,
        }
    }
}

/// How far a [`LogMapBuild`] has got.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BuildProgress {
    /// Scans integrated into the map so far (the map shows scans
    /// `0..scans_done`).
    pub scans_done: usize,
    /// Where the build is heading (all scans, or a scrub position).
    pub scans_target: usize,
    pub scans_total: usize,
    /// Cell updates since the map was last reset.
    pub cell_updates: u64,
    /// Beams traced since the map was last reset.
    pub beams: u64,
    pub finished: bool,
    /// Cells allocated in tiles (what the beams have reached, in whole
    /// tiles), of the `cells` of the bounding box.
    pub cells_allocated: usize,
    pub bytes_allocated: usize,
    pub cells: usize,
}

/// A map built from a log a few scans at a time. The build heads for a
/// target scan count: all scans at first, or any scrub position; going back
/// resets the map and rebuilds from the first scan (the build is fast, and
/// keeping snapshots of a million-cell map would cost more memory than the
/// whole log).
pub struct LogMapBuild {
    /// The log's scans, at the poses the settings choose.
    scans: LaserScans,
    /// The log's own laser poses, kept for a change of pose source.
    corrected: Vec<crate::geometry::Pose>,
    /// The odometry noise dead reckoning adds.
    odometry: OdometryParams,
    settings: LogMapSettings,
    grid: TiledGrid,
    model: HandCrafted,
    mapper: RayMapper,
    /// Most cells the map's tiles may hold.
    budget_cells: usize,
    /// Why the build stopped short (the tile budget), once it has.
    failure: Option<OccError>,
    /// Scratch: the current scan's beam bands.
    bands: Vec<Option<BeamBand>>,
    done: usize,
    target: usize,
    cell_updates: u64,
    beams: u64,
}

impl LogMapBuild {
    /// A fresh map over the log's extent, heading for all scans.
    pub fn new(scans: LaserScans, settings: LogMapSettings) -> Result<Self> {
        Self::with_tile_budget(scans, settings, DEFAULT_TILE_BUDGET_CELLS)
    }

    /// [`Self::new`] with at most `budget_cells` cells allocated in tiles
    /// (the default is [`DEFAULT_TILE_BUDGET_CELLS`]).
    pub fn with_tile_budget(
        scans: LaserScans,
        settings: LogMapSettings,
        budget_cells: usize,
    ) -> Result<Self> {
        Self::try_build(scans, settings, OdometryParams::WHEELS, budget_cells).map_err(|(e, _)| e)
    }

    /// [`Self::new`] with dead reckoning's noise chosen by the caller
    /// ([`OdometryParams::EXACT`] maps the corrected poses again, through
    /// the integration).
    pub fn with_odometry(
        scans: LaserScans,
        settings: LogMapSettings,
        odometry: OdometryParams,
    ) -> Result<Self> {
        Self::try_build(scans, settings, odometry, DEFAULT_TILE_BUDGET_CELLS).map_err(|(e, _)| e)
    }

    /// [`Self::new`], giving the scans back with the error when the
    /// settings cannot map them: a session keeps them for settings that
    /// fit, and the extent is found once, not checked first and found
    /// again.
    pub fn try_new(
        scans: LaserScans,
        settings: LogMapSettings,
    ) -> std::result::Result<Self, (OccError, LaserScans)> {
        Self::try_build(
            scans,
            settings,
            OdometryParams::WHEELS,
            DEFAULT_TILE_BUDGET_CELLS,
        )
    }

    fn try_build(
        mut scans: LaserScans,
        settings: LogMapSettings,
        odometry: OdometryParams,
        budget_cells: usize,
    ) -> std::result::Result<Self, (OccError, LaserScans)> {
        if let Err(e) = odometry.validate() {
            return Err((e, scans));
        }
        let corrected = scans.poses().to_vec();
        // One pose per scan: setting them cannot fail.
        let _ = scans.set_poses(&Self::poses_for(&corrected, &settings, &odometry));
        let (grid, model) = match Self::prepare(&scans, &settings, budget_cells) {
            Ok(prepared) => prepared,
            Err(e) => {
                let _ = scans.set_poses(&corrected);
                return Err((e, scans));
            }
        };
        let target = scans.len();
        Ok(Self {
            scans,
            corrected,
            odometry,
            settings,
            grid,
            model,
            mapper: RayMapper::new(),
            budget_cells,
            failure: None,
            bands: Vec::new(),
            done: 0,
            target,
            cell_updates: 0,
            beams: 0,
        })
    }

    /// The grid `settings` would give `scans`, without allocating it: an
    /// error if the settings are invalid, the log has no laser scans, or
    /// the grid would be too large. A caller can check before handing its
    /// scans over to [`Self::new`].
    pub fn check(scans: &LaserScans, settings: &LogMapSettings) -> Result<GridGeometry> {
        settings.validate()?;
        if settings.poses == PoseSource::DeadReckoning {
            // The dead-reckoned path wanders: its extent is its own.
            let mut placed = scans.clone();
            let poses = Self::poses_for(scans.poses(), settings, &OdometryParams::WHEELS);
            placed.set_poses(&poses)?;
            return Self::check_placed(&placed, settings);
        }
        Self::check_placed(scans, settings)
    }

    /// The laser poses `settings` put the scans at, given the log's own.
    fn poses_for(
        corrected: &[crate::geometry::Pose],
        settings: &LogMapSettings,
        odometry: &OdometryParams,
    ) -> Vec<crate::geometry::Pose> {
        match settings.poses {
            PoseSource::Corrected => corrected.to_vec(),
            PoseSource::DeadReckoning => odometry.dead_reckon_path(corrected, settings.seed),
        }
    }

    /// [`Self::check`] for scans already at the settings' poses.
    fn check_placed(scans: &LaserScans, settings: &LogMapSettings) -> Result<GridGeometry> {
        settings.validate()?;
        let extent = scans.endpoint_bounds(settings.range_cap).ok_or_else(|| {
            invalid(
                "log",
                "no FLASER or ROBOTLASER1 lines",
                "at least one laser scan",
            )
        })?;
        let extent = settings.geometry(extent)?;
        // A scan is gathered in a window as wide as its longest beam: that
        // window's scratch is what bounds the reach in cells.
        if !(settings.range_cap / settings.resolution <= MAX_REACH_CELLS) {
            return Err(invalid(
                "rangeCap",
                error::show(settings.range_cap),
                "at most 2045 cells of the resolution (102 m at 5 cm, 51 m at 2.5 cm)",
            ));
        }
        Ok(extent)
    }

    fn prepare(
        scans: &LaserScans,
        s: &LogMapSettings,
        budget_cells: usize,
    ) -> Result<(TiledGrid, HandCrafted)> {
        let grid = TiledGrid::new(Self::check_placed(scans, s)?, s.filter(), budget_cells)?;
        Ok((grid, HandCrafted::new(s.model_params())?))
    }

    /// New settings: a new grid (the extent depends on the range cap and
    /// margin) and a rebuild from the first scan towards the same target.
    /// On error nothing changes.
    pub fn configure(&mut self, settings: LogMapSettings) -> Result<()> {
        let before = self.scans.poses().to_vec();
        self.scans
            .set_poses(&Self::poses_for(&self.corrected, &settings, &self.odometry))?;
        let (grid, model) = match Self::prepare(&self.scans, &settings, self.budget_cells) {
            Ok(prepared) => prepared,
            Err(e) => {
                self.scans.set_poses(&before)?;
                return Err(e);
            }
        };
        self.settings = settings;
        self.grid = grid;
        self.model = model;
        self.restart();
        Ok(())
    }

    fn restart(&mut self) {
        self.grid.reset();
        self.failure = None;
        self.done = 0;
        self.cell_updates = 0;
        self.beams = 0;
    }

    /// Heads the build for `scans` integrated scans (a scrub position).
    /// Going back resets the map; [`Self::advance`] then does the work.
    pub fn seek(&mut self, scans: usize) -> Result<()> {
        if scans > self.scans.len() {
            return Err(invalid(
                "scan",
                scans,
                "at most the number of scans in the log",
            ));
        }
        if scans < self.done {
            self.restart();
        }
        self.target = scans;
        Ok(())
    }

    /// Integrates up to `max_scans` more scans towards the target. A scan
    /// whose beams reach past the tile budget stops the build there:
    /// [`Self::failure`] then says how much the whole log would need.
    pub fn advance(&mut self, max_scans: usize) -> BuildProgress {
        self.advance_within(max_scans, u64::MAX)
    }

    /// Integrates up to `max_scans` more scans towards the target, and
    /// stops after the scan whose cell updates bring this call's to
    /// `max_cells` or more: the work of a call is bounded by what it does
    /// (a scan down a long corridor updates ten times the cells of one in
    /// an office), so a page that sizes the next call from the last one's
    /// duration keeps every call near its time slice. At least one scan is
    /// integrated when any is left.
    pub fn advance_within(&mut self, max_scans: usize, max_cells: u64) -> BuildProgress {
        let end = self.target.min(self.done.saturating_add(max_scans));
        let cap = self.settings.range_cap;
        let start_updates = self.cell_updates;
        while self.done < end
            && self.failure.is_none()
            && self.cell_updates - start_updates < max_cells
        {
            let k = self.done;
            if let Some(scan) = self.scans.scan(k) {
                let laser_max = self.scans.max_range(k).unwrap_or(f64::INFINITY);
                // A laser that says its own maximum range is shorter than the
                // cap reports no-returns at that maximum: the model must
                // treat them as no-returns, not as walls at the maximum.
                let short = (laser_max < cap)
                    .then(|| {
                        HandCrafted::new(HandCraftedParams {
                            z_max: laser_max,
                            ..self.settings.model_params()
                        })
                        .ok()
                    })
                    .flatten();
                let model = short.as_ref().unwrap_or(&self.model);
                let res = self.grid.extent().resolution();
                let s = &self.settings;
                beam_bands(
                    &scan,
                    model,
                    s.no_return_reach,
                    s.walls,
                    res,
                    &mut self.bands,
                );
                let (free, occupied) = (
                    (s.l_free - model.params().l0) as f32,
                    (s.l_occ - model.params().l0) as f32,
                );
                let stats = self.mapper.integrate_bands_tiled(
                    &mut self.grid,
                    &scan,
                    &self.bands,
                    free,
                    occupied,
                );
                if self.grid.refused() {
                    let needed = self.tiles_reached();
                    self.failure = Some(OccError::State(budget_message(
                        self.grid.extent(),
                        needed,
                        self.budget_cells,
                    )));
                    break;
                }
                self.cell_updates += stats.cells_updated as u64;
                self.beams += scan.len() as u64;
            }
            self.done += 1;
        }
        self.progress()
    }

    pub fn progress(&self) -> BuildProgress {
        BuildProgress {
            scans_done: self.done,
            scans_target: self.target,
            scans_total: self.scans.len(),
            cell_updates: self.cell_updates,
            beams: self.beams,
            finished: self.done == self.target,
            cells_allocated: self.grid.cells_allocated(),
            bytes_allocated: self.grid.bytes_allocated(),
            cells: self.grid.extent().len(),
        }
    }

    /// Why the build stopped short of its target (the tile budget), if it did.
    pub fn failure(&self) -> Option<&OccError> {
        self.failure.as_ref()
    }

    /// The tiles the beams of every scan reach, walked on the grid of tiles
    /// (a tile holding a cell a beam crosses is one the beam crosses): what
    /// the whole log would allocate, said when the budget refuses it.
    fn tiles_reached(&self) -> usize {
        let e = *self.grid.extent();
        let (tx, ty) = tiles_of(&e);
        let mut marks = vec![false; tx * ty];
        let mut bands = Vec::new();
        let per_tile = 1.0 / (e.resolution() * TILE_SIDE as f64);
        for k in 0..self.scans.len() {
            let Some(scan) = self.scans.scan(k) else {
                continue;
            };
            let s = &self.settings;
            beam_bands(
                &scan,
                &self.model,
                s.no_return_reach,
                s.walls,
                e.resolution(),
                &mut bands,
            );
            let p = scan.pose();
            let (su, sv) = e.world_to_grid(p.x, p.y);
            let start = (su / TILE_SIDE as f64, sv / TILE_SIDE as f64);
            for (band, &b) in bands.iter().zip(scan.bearings()) {
                let Some(band) = band else { continue };
                let (sn, cs) = (p.theta + b).sin_cos();
                let end = (
                    start.0 + band.reach * per_tile * cs,
                    start.1 + band.reach * per_tile * sn,
                );
                if let Some(walk) = Walk::new(tx, ty, start, end) {
                    let mut m = TileMarks {
                        at: walk.start,
                        step: walk.step,
                        width: tx,
                        marks: &mut marks,
                    };
                    walk.run(&mut m);
                }
            }
        }
        marks.iter().filter(|&&m| m).count()
    }

    pub fn grid(&self) -> &TiledGrid {
        &self.grid
    }

    /// The log's scans, at the poses of the settings.
    pub fn scans(&self) -> &LaserScans {
        &self.scans
    }

    /// The log's scans at its own (corrected) poses.
    pub fn corrected_scans(&self) -> Result<LaserScans> {
        let mut scans = self.scans.clone();
        scans.set_poses(&self.corrected)?;
        Ok(scans)
    }

    pub fn settings(&self) -> &LogMapSettings {
        &self.settings
    }

    /// How many cells are occupied, free and unknown now, counted with the
    /// thresholds of the exported file (what the PGM would show and
    /// `map_server` load), which the counts carry.
    pub fn counts(&self) -> ExportCounts {
        map_server::tiled_export_counts(&self.grid)
    }

    /// The laser positions of all scans in image units (x to the right, y
    /// down, pixel `(c, r)` spanning `[c, c+1) x [r, r+1)`), as
    /// `[x0, y0, x1, y1, ...]`: a page draws the robot's path from it.
    pub fn path_in_pixels(&self) -> Vec<f32> {
        let g = self.grid.extent();
        (0..self.scans.len())
            .filter_map(|k| self.scans.pose(k))
            .flat_map(|p| g.world_to_image(p.x, p.y).map(|c| c as f32))
            .collect()
    }

    /// The robot at scan `k` in image units, heading as an image angle
    /// (see [`crate::render::overlay`]), or `None` past the last scan.
    pub fn robot_at(&self, k: usize) -> Option<RobotMark> {
        Some(RobotMark::at(self.grid.extent(), &self.scans.pose(k)?))
    }

    /// The cell under image pixel `(col, row)` (row 0 at the top, north
    /// up), or `None` outside the map.
    pub fn readout_at_pixel(&self, col: usize, row: usize) -> Option<CellReadout> {
        let h = self.grid.extent().height();
        if row >= h {
            return None;
        }
        self.grid.readout_at_cell(col, h - 1 - row)
    }
}

/// Marks the tiles a walk on the grid of tiles visits.
struct TileMarks<'a> {
    at: (usize, usize),
    step: (i8, i8),
    width: usize,
    marks: &'a mut [bool],
}

impl RasterCursor for TileMarks<'_> {
    fn visit(&mut self) {
        if let Some(m) = self.marks.get_mut(self.at.1 * self.width + self.at.0) {
            *m = true;
        }
    }
    fn step_x(&mut self) {
        self.at.0 = self.at.0.wrapping_add_signed(self.step.0 as isize);
    }
    fn step_y(&mut self) {
        self.at.1 = self.at.1.wrapping_add_signed(self.step.1 as isize);
    }
    fn unstep_x(&mut self) {
        self.at.0 = self.at.0.wrapping_add_signed(-(self.step.0 as isize));
    }
}

/// What the read of a log reports: its progress and the file's size.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ReadReport {
    #[serde(flatten)]
    pub progress: LoadProgress,
    pub bytes_total: usize,
}

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

/// A log being read and mapped, step by step:
///
/// 1. [`Self::new`] takes the file's bytes (gzip or plain);
/// 2. [`Self::read`] reads up to `n` more laser lines per call, until
///    finished (then the map is set up with the current settings);
/// 3. [`Self::build_chunk`] integrates up to `n` more scans per call;
/// 4. [`Self::seek`] scrubs to `k` scans, and [`Self::configure`] restarts
///    the build with new settings.
pub struct RealLogSession {
    /// The reader over the file's bytes, dropped (with the bytes) once the
    /// whole log is read.
    loader: Option<LogLoader<Cursor<Vec<u8>>>>,
    /// Scans read whose map the current settings cannot make (a grid too
    /// large): kept until `configure` brings settings that fit.
    pending: Option<LaserScans>,
    /// How the read ended, once it has.
    read_summary: Option<LoadProgress>,
    /// Why the read was refused, once it has been (the file is freed).
    read_failure: Option<OccError>,
    bytes_total: usize,
    settings: LogMapSettings,
    build: Option<LogMapBuild>,
    /// What part of the map is on screen (once there is a map), and the
    /// output size it is drawn at.
    view: Option<MapViewport>,
    view_size: (usize, usize),
}

impl RealLogSession {
    pub fn new(bytes: Vec<u8>) -> Self {
        Self::with_budget(bytes, LogBudget::default())
    }

    /// A session whose reader has its own budget (a test's smaller one).
    pub fn with_budget(bytes: Vec<u8>, budget: LogBudget) -> Self {
        Self {
            bytes_total: bytes.len(),
            loader: Some(LogLoader::with_budget(Cursor::new(bytes), budget)),
            pending: None,
            read_summary: None,
            read_failure: None,
            settings: LogMapSettings::default(),
            build: None,
            view: None,
            view_size: (480, 360),
        }
    }

    /// Reads up to `max_scans` more laser lines (and at most the reader's
    /// budget of lines and bytes per call: [`LogBudget`]). When the log is
    /// finished the map is set up; a malformed line is an error naming its
    /// line number, and so is a log past the budget or without laser lines:
    /// the file and the scans read are then freed, and every later call
    /// gives the same error (the session stays usable: settings, and a new
    /// session for another file). A log cut short is read up to the cut,
    /// with the report's `warning` naming the line. If the settings make too
    /// large a grid for this log, that is an error too, and the scans wait
    /// ([`Self::awaiting_settings`]) for a [`Self::configure`] that fits.
    pub fn read(&mut self, max_scans: usize) -> Result<ReadReport> {
        if let Some(e) = &self.read_failure {
            return Err(e.clone());
        }
        let Some(loader) = self.loader.as_mut() else {
            return Err(OccError::State("the log has been read already".into()));
        };
        let progress = match loader.read(max_scans) {
            Ok(p) => p,
            Err(e) => return Err(self.read_failed(e)),
        };
        if progress.finished {
            self.read_summary = Some(progress.clone());
            if let Some(loader) = self.loader.take() {
                let scans = loader.into_scans();
                if scans.is_empty() {
                    let lines = match progress.lines {
                        1 => "1 line read".to_string(),
                        n => format!("{n} lines read"),
                    };
                    let e = OccError::State(format!(
                        "the file has no FLASER or ROBOTLASER1 lines ({lines}): no laser scans to map"
                    ));
                    return Err(self.read_failed(e));
                }
                match LogMapBuild::try_new(scans, self.settings) {
                    Ok(build) => self.build = Some(build),
                    Err((e, scans)) => {
                        self.pending = Some(scans);
                        return Err(e);
                    }
                }
                self.refit_view();
            }
        }
        Ok(ReadReport {
            progress,
            bytes_total: self.bytes_total,
        })
    }

    /// Frees the file and the scans read, and keeps `e` for later calls.
    fn read_failed(&mut self, e: OccError) -> OccError {
        self.loader = None;
        self.read_failure = Some(e.clone());
        e
    }

    /// New settings: restarts the build towards the same scan count and
    /// returns the map's geometry (`None` while the log is still being
    /// read). On error nothing changes.
    pub fn configure(&mut self, settings: LogMapSettings) -> Result<Option<GeometryReport>> {
        settings.validate()?;
        if let Some(build) = self.build.as_mut() {
            let before = *build.grid().extent();
            build.configure(settings)?;
            if *build.grid().extent() != before {
                self.refit_view();
            }
        } else if let Some(scans) = self.pending.take() {
            match LogMapBuild::try_new(scans, settings) {
                Ok(build) => self.build = Some(build),
                Err((e, scans)) => {
                    self.pending = Some(scans);
                    return Err(e);
                }
            }
            self.refit_view();
        }
        self.settings = settings;
        Ok(self.geometry())
    }

    /// How the read ended (also when setting up the map failed), or `None`.
    pub fn read_summary(&self) -> Option<ReadReport> {
        self.read_summary.clone().map(|progress| ReadReport {
            progress,
            bytes_total: self.bytes_total,
        })
    }

    /// True when the whole log has been read but the settings made too large
    /// a grid for it.
    pub fn awaiting_settings(&self) -> bool {
        self.pending.is_some()
    }

    /// The map's limits, or `None` before the log is read.
    pub fn geometry(&self) -> Option<GeometryReport> {
        self.build.as_ref().map(|b| {
            let g = b.grid().extent();
            let [origin_x, origin_y] = g.origin();
            GeometryReport {
                width: g.width(),
                height: g.height(),
                resolution: g.resolution(),
                origin_x,
                origin_y,
            }
        })
    }

    /// The build, once the log is read and the settings fit.
    pub fn build(&self) -> Result<&LogMapBuild> {
        self.build
            .as_ref()
            .ok_or_else(|| OccError::State("the log has not been read yet".into()))
    }

    fn build_mut(&mut self) -> Result<&mut LogMapBuild> {
        self.build
            .as_mut()
            .ok_or_else(|| OccError::State("the log has not been read yet".into()))
    }

    /// Integrates up to `max_scans` more scans; an error once the beams
    /// reach past the tile budget (saying how much the log would need).
    pub fn build_chunk(&mut self, max_scans: usize) -> Result<BuildProgress> {
        let build = self.build_mut()?;
        let p = build.advance(max_scans);
        match build.failure() {
            Some(e) => Err(e.clone()),
            None => Ok(p),
        }
    }

    /// The whole map in a view of the current output size.
    fn refit_view(&mut self) {
        self.view = self.build.as_ref().and_then(|b| {
            let e = b.grid().extent();
            MapViewport::new(e.width(), e.height(), self.view_size.0, self.view_size.1).ok()
        });
    }

    /// The view, once there is a map.
    pub fn view(&self) -> Result<&MapViewport> {
        self.view
            .as_ref()
            .ok_or_else(|| OccError::State("the log has not been mapped yet".into()))
    }

    fn view_mut(&mut self) -> Result<&mut MapViewport> {
        self.view
            .as_mut()
            .ok_or_else(|| OccError::State("the log has not been mapped yet".into()))
    }

    /// The output's size in pixels (the canvas's device pixels): the view
    /// keeps its centre and zoom (and stays fitted if it was).
    pub fn set_view_size(&mut self, width: usize, height: usize) -> Result<()> {
        match self.view.as_mut() {
            Some(v) => v.resize(width, height)?,
            None => {
                MapViewport::new(1, 1, width, height)?;
            }
        }
        self.view_size = (width, height);
        Ok(())
    }

    /// Shows the whole map.
    pub fn fit_view(&mut self) -> Result<()> {
        self.view_mut()?.fit();
        Ok(())
    }

    /// Zooms by `factor` about output pixel `(x, y)` ([`MapViewport::zoom_at`]).
    pub fn zoom_view(&mut self, x: f64, y: f64, factor: f64) -> Result<()> {
        self.view_mut()?.zoom_at(x, y, factor)
    }

    /// Moves the map by `(dx, dy)` output pixels.
    pub fn pan_view(&mut self, dx: f64, dy: f64) -> Result<()> {
        self.view_mut()?.pan_by(dx, dy)
    }

    /// Draws the view into `out` (its `width * height * 4` RGBA bytes).
    pub fn render_view(&self, out: &mut Vec<u8>) -> Result<()> {
        render_tiled_view(self.build()?.grid(), self.view()?, out);
        Ok(())
    }

    /// The cell under output position `(x, y)` (pixels), or `None` off the map.
    pub fn readout_at_view(&self, x: f64, y: f64) -> Result<Option<CellReadout>> {
        let b = self.build()?;
        Ok(self
            .view()?
            .cell_at(x, y)
            .and_then(|(c, r)| b.readout_at_pixel(c, r)))
    }

    /// Integrates scans until this call's cell updates reach `max_cells`
    /// ([`LogMapBuild::advance_within`]).
    pub fn build_slice(&mut self, max_cells: u64) -> Result<BuildProgress> {
        let build = self.build_mut()?;
        let p = build.advance_within(usize::MAX, max_cells);
        match build.failure() {
            Some(e) => Err(e.clone()),
            None => Ok(p),
        }
    }

    /// A second session over the same log, already read, with its own map
    /// under `settings` (the corrected map beside a dead-reckoned one): the
    /// scans are copied, not read again.
    pub fn fork(&self, settings: LogMapSettings) -> Result<RealLogSession> {
        settings.validate()?;
        let scans = self.build()?.corrected_scans()?;
        let build = LogMapBuild::new(scans, settings)?;
        let mut fork = RealLogSession {
            loader: None,
            pending: None,
            read_summary: self.read_summary.clone(),
            read_failure: None,
            bytes_total: self.bytes_total,
            settings,
            build: Some(build),
            view: None,
            view_size: self.view_size,
        };
        fork.refit_view();
        Ok(fork)
    }

    /// Scrubs to `scans` integrated scans; [`Self::build_chunk`] then does
    /// the work (going back restarts from the first scan).
    pub fn seek(&mut self, scans: usize) -> Result<()> {
        self.build_mut()?.seek(scans)
    }

    /// The robot at scan `k` over the map, in image units.
    pub fn robot_at(&self, k: usize) -> Result<RobotMark> {
        self.build()?
            .robot_at(k)
            .ok_or_else(|| invalid("scan", k, "a scan of the log"))
    }

    /// The map as a ROS `map_server` pair, the YAML naming the image
    /// `NAME.pgm` (`map.pgm` without a name).
    pub fn export_map(&self, name: Option<&str>) -> Result<MapServerPair> {
        let stem = map_server::file_stem(name.unwrap_or(""));
        Ok(map_server::tiled_map_server_pair(
            self.build()?.grid(),
            &format!("{stem}.pgm"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeking_back_rebuilds_the_same_map() {
        let mut text = String::new();
        for k in 0..6 {
            text.push_str(&format!(
                "FLASER 4 1.0 1.5 2.0 2.5 {} 0.0 0.3 0 0 0 0 h 0\n",
                k as f64 * 0.2
            ));
        }
        let scans = LaserScans::read(text.as_bytes()).unwrap();
        let settings = LogMapSettings {
            resolution: 0.1,
            ..Default::default()
        };
        let mut a = LogMapBuild::new(scans.clone(), settings).unwrap();
        a.seek(3).unwrap();
        let p = a.advance(100);
        assert_eq!((p.scans_done, p.finished), (3, true));
        let at3 = a.grid().clone();
        a.seek(6).unwrap();
        a.advance(2);
        a.advance(2);
        assert!(a.progress().finished && a.progress().scans_done == 6);
        a.seek(3).unwrap();
        assert_eq!(a.progress().scans_done, 0, "going back resets");
        a.advance(10);
        assert_eq!(a.grid(), &at3);
        assert!(a.seek(7).is_err());
    }
}
