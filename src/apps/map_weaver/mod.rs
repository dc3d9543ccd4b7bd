//! Map Weaver's session: one simulated lap feeding two maps side by side.
//!
//! This is the core behind `<occgrid-map-weaver>`, kept out of the
//! bindings so that it is tested natively. Data flow per scan:
//!
//! 1. [`ApartmentSim`] produces the next [`SimScan`] (true pose,
//!    dead-reckoned pose, LiDAR ranges).
//! 2. Each of the two panes (`pane.rs`) turns it into a scan at the pose its
//!    settings ask for and integrates it with its own inverse model,
//!    evidence strength and clamp (Table 9.1), then brings its view, its
//!    curves and its ghost watch (`ghosts.rs`) up to date.
//! 3. The page reads what to show from `readout.rs`, in image units.
//!
//! Every scan is kept, so that any knob of a pane (model, pose source,
//! clamp, strength, mapper, sensor, cone opening, beams, resolution, `l0`
//! forgotten) rebuilds that pane over the same scans: the map shows what
//! that setting gives for the scans so far, and a knob turned and turned
//! back leaves the map as it was (the two panes stay comparable). The work
//! goes in bounded calls (`stepping.rs`), so that a page plays and rebuilds
//! within its frames. What a run may be set to, and the limits the widget
//! shows, are in `settings.rs`.

mod brier_map;
mod building;
mod compare;
mod ghosts;
mod pane;
mod readout;
mod settings;
mod situation;
mod start;
mod stepping;
mod timing;

/// The evidence-strength wrapper lives with the inverse models; named here
/// too for the benchmark workloads that replay Map Weaver's panes.
pub use crate::inverse::Scaled;
pub use brier_map::BrierDifference;
pub use building::{BuildReport, WeaverBuild};
pub use compare::{L0Drift, MapDifference};
pub use ghosts::GhostReadout;
pub use readout::{CellInfo, Leaning, Overlay, PaneReadout, Readout, TrackedCell};
pub use settings::{
    beam_divisors, CheckedWeaverSettings, Choice, MapperKind, ModelKind, PaneChoices, PaneSettings,
    PoseSource, SensorKind, Steps, WeaverDefaults, WeaverLimits, WeaverSettings, CLAMP,
    CONE_BETA_DEG, MAX_FAST_FORWARD_WORK, MAX_LAPS, MAX_READINGS, MAX_TRAINING_UPDATES,
    PANE_RESOLUTIONS, STRENGTH,
};
pub use situation::{Situation, WATCH_GHOST_CELL, WATCH_PAUSE, WATCH_POST};
pub use start::WeaverStart;
pub use stepping::WorkReport;
pub use timing::Clock;

use crate::error::{invalid, Result};
use crate::geometry::GridGeometry;
use crate::grid::LogOddsGrid;
use crate::inverse::training;
use crate::inverse::LearnedInverse;
use crate::io::map_server::{self as export, MapServerPair};
use crate::render::map_view::MapView;
use crate::scenes::apartment::{ApartmentSim, SimScan};
use pane::Pane;
use timing::RecentTimes;

/// A Map Weaver run.
#[derive(Debug, Clone)]
pub struct Weaver {
    settings: WeaverSettings,
    geometry: GridGeometry,
    sim: ApartmentSim,
    tracked_cells: [usize; 3],
    scans_per_lap: usize,
    /// The learned model, trained once per run and kept across resets
    /// (boxed as the panes' copies are).
    learned: Box<LearnedInverse>,
    history: Vec<SimScan>,
    panes: [Pane; 2],
    frame_ms: RecentTimes,
    /// Times each pane's scans when set.
    clock: Option<Clock>,
    /// The per-cell Brier difference image, drawn on request
    /// ([`Weaver::draw_brier_difference`]).
    brier_pixels: Vec<u8>,
}

impl Weaver {
    /// Checks `settings`, trains the learned model and starts a run at
    /// scan 0.
    pub fn new(settings: WeaverSettings) -> Result<Self> {
        // Reject bad settings before spending time on training.
        let settings = settings.check()?;
        let (learned, _, _) = training::train(&settings.settings().training)?;
        WeaverBuild::checked(settings, learned)?.finish()
    }

    /// Like [`Weaver::new`] with an already trained model (a page that
    /// trained one for another widget, or a test that trains once).
    pub fn with_learned(settings: WeaverSettings, learned: LearnedInverse) -> Result<Self> {
        WeaverBuild::new(settings, learned)?.finish()
    }

    /// Sets the clock that times each pane's scans (`None`: no timing).
    pub fn set_clock(&mut self, clock: Option<Clock>) {
        self.clock = clock;
    }

    /// Starts the run again from scan 0 with the current settings (the
    /// person toggle and every pane's knobs as they are now).
    pub fn reset(&mut self) -> Result<()> {
        let mut settings = self.settings.clone();
        settings.person = self.sim.person();
        let clock = self.clock;
        let settings = CheckedWeaverSettings::of_run(settings, self.geometry);
        *self = WeaverBuild::checked(settings, (*self.learned).clone())?.finish()?;
        self.clock = clock;
        Ok(())
    }

    pub fn settings(&self) -> &WeaverSettings {
        &self.settings
    }
    /// The learned model both panes use when set to it.
    pub fn learned(&self) -> &LearnedInverse {
        &self.learned
    }
    /// The scene's grid limits (a pane at another resolution has its own:
    /// [`Weaver::pane_geometry`]).
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// Pane `pane`'s grid limits.
    pub fn pane_geometry(&self, pane: usize) -> Result<&GridGeometry> {
        Ok(&self.pane(pane)?.geometry)
    }
    /// The ground truth at pane `pane`'s resolution.
    pub fn pane_truth(&self, pane: usize) -> Result<&[bool]> {
        Ok(&self.pane(pane)?.truth)
    }
    /// The three tracked cells of pane `pane` (indices into its grid).
    pub fn pane_tracked_cells(&self, pane: usize) -> Result<[usize; 3]> {
        Ok(self.pane(pane)?.tracked_cells)
    }

    pub fn scans_per_lap(&self) -> usize {
        self.scans_per_lap
    }
    /// Scans integrated so far.
    pub fn scans(&self) -> usize {
        self.history.len()
    }
    /// Scans in the whole run: its laps of [`Weaver::scans_per_lap`].
    pub fn total_scans(&self) -> usize {
        self.settings.laps.saturating_mul(self.scans_per_lap)
    }
    /// True once the run's laps are done.
    pub fn done(&self) -> bool {
        self.history.len() >= self.total_scans()
    }
    /// Every scan so far.
    pub fn history(&self) -> &[SimScan] {
        &self.history
    }
    /// The ground truth at the scene's resolution.
    pub fn ground_truth(&self) -> &[bool] {
        self.sim.ground_truth().occupied()
    }
    /// The three tracked cells (indices), in the scene's order.
    pub fn tracked_cells(&self) -> [usize; 3] {
        self.tracked_cells
    }
    pub fn grid(&self, pane: usize) -> Result<&LogOddsGrid> {
        Ok(self.pane(pane)?.map.grid())
    }
    pub fn view(&self, pane: usize) -> Result<&MapView> {
        Ok(self.pane(pane)?.map.view())
    }
    /// Seconds of driving that `scans` scans take at the scene's scan rate:
    /// the readout's time and the charts' x axis, both from here.
    pub fn seconds_after(&self, scans: usize) -> f64 {
        scans as f64 / self.settings.scene.scan_rate
    }

    /// The x axis of the curves: the time of each point, seconds (point 0
    /// is the empty map, point `i` the map after `i` scans).
    pub fn curve_times(&self) -> Vec<f64> {
        (0..=self.history.len())
            .map(|i| self.seconds_after(i))
            .collect()
    }

    /// Entropy (bits) after each scan, from the empty map on.
    pub fn entropy_curve(&self, pane: usize) -> Result<&[f64]> {
        Ok(&self.pane(pane)?.entropy_curve)
    }
    /// Brier score (surveyed rooms) after each scan, from the empty map on.
    pub fn brier_curve(&self, pane: usize) -> Result<&[f64]> {
        Ok(&self.pane(pane)?.brier_curve)
    }
    /// The tracked cells' log odds after each scan, from the empty map on.
    pub fn tracked_history(&self, pane: usize) -> Result<&[[f32; 3]]> {
        Ok(&self.pane(pane)?.tracked)
    }
    /// Scans each of pane `pane`'s completed ghost fades took, in the order
    /// they completed (exercise 5).
    pub fn ghost_fades(&self, pane: usize) -> Result<&[usize]> {
        Ok(self.pane(pane)?.ghost.fades())
    }

    fn pane(&self, pane: usize) -> Result<&Pane> {
        self.panes
            .get(pane)
            .ok_or_else(|| invalid("pane", pane, "0 (left) or 1 (right)"))
    }

    /// Simulates and integrates up to `n` scans (fewer when the run ends);
    /// returns how many were taken. A rebuild under way is finished first.
    /// [`Weaver::work`] with no budget.
    pub fn advance(&mut self, n: usize) -> Result<usize> {
        Ok(self.work(n, u64::MAX)?.scans)
    }

    /// The most cells one scan visits, both panes together: for a pane by
    /// ray traversal, its beams x the cells along a beam at the LiDAR's
    /// range (one per the pane's resolution); for a pane by the sweep,
    /// every cell of its map. The unit of [`MAX_FAST_FORWARD_WORK`]: an
    /// estimate, but one that grows as the real work does with finer
    /// grids, more beams and the sweep.
    pub fn work_per_scan(&self) -> u64 {
        let lidar = &self.settings.scene.lidar;
        self.panes
            .iter()
            .map(|p| match p.settings.mapper {
                MapperKind::Sweep => p.geometry.len() as u64,
                MapperKind::Traversal => {
                    let cells = (lidar.z_max / p.geometry.resolution()).ceil().max(1.0);
                    let beams = p.settings.beams.unwrap_or(lidar.beams);
                    // Finite and at most z_max / resolution: `as` cannot
                    // wrap here.
                    beams as u64 * cells as u64
                }
            })
            .sum()
    }

    /// How many scans [`Weaver::advance`] will take for a request of `scans`
    /// (fewer when the run's laps end first), or an error naming `scans`
    /// when that is more than [`MAX_FAST_FORWARD_WORK`]. Checked before a
    /// page starts the work, so that a link asking for a minute of mapping
    /// is refused with its reason instead of started.
    pub fn check_fast_forward(&self, scans: usize) -> Result<usize> {
        let taken = scans.min(self.total_scans().saturating_sub(self.history.len()));
        let per_scan = self.work_per_scan();
        let work = (taken as u64).saturating_mul(per_scan);
        if work > MAX_FAST_FORWARD_WORK {
            return Err(invalid(
                "scans",
                format!("{scans} ({taken} scans x {per_scan} cell visits = {work})"),
                format!(
                    "at most {MAX_FAST_FORWARD_WORK} cell visits before the first frame: fewer scans or laps, or a coarser resolution"
                ),
            ));
        }
        Ok(taken)
    }

    /// Changes every knob of pane `pane` at once and rebuilds the pane over
    /// the scans so far, now ([`Weaver::stage_pane`] leaves the rebuild to
    /// [`Weaver::work`]'s budgeted calls). Nothing changes when `settings`
    /// is refused.
    pub fn set_pane(&mut self, pane: usize, settings: PaneSettings) -> Result<()> {
        let Some(before) = self.swap_pane(pane, settings)? else {
            return Ok(());
        };
        if let Err(e) = self.catch_up(pane) {
            self.settings.panes[pane] = before.settings;
            self.panes[pane] = before;
            return Err(e);
        }
        Ok(())
    }

    /// Pane `pane`'s knobs now (a patch of them is what a page sends).
    pub fn pane_settings(&self, pane: usize) -> Result<PaneSettings> {
        Ok(self.pane(pane)?.settings)
    }

    /// Changes one knob of pane `pane` (`change` of its settings now) and
    /// rebuilds it over the scans so far ([`Weaver::set_pane`]).
    fn set_knob(&mut self, pane: usize, change: impl FnOnce(&mut PaneSettings)) -> Result<()> {
        let mut settings = self.pane_settings(pane)?;
        change(&mut settings);
        self.set_pane(pane, settings)
    }

    /// Switches a pane's inverse model and rebuilds it over the scans so
    /// far.
    pub fn set_model(&mut self, pane: usize, model: ModelKind) -> Result<()> {
        self.set_knob(pane, |s| s.model = model)
    }

    /// Switches a pane between the pose oracle and dead reckoning and
    /// rebuilds it over the scans so far.
    pub fn set_pose_source(&mut self, pane: usize, pose: PoseSource) -> Result<()> {
        self.set_knob(pane, |s| s.pose = pose)
    }

    /// Changes a pane's clamp and rebuilds it over the scans so far.
    pub fn set_clamp(&mut self, pane: usize, clamp: f64) -> Result<()> {
        self.set_knob(pane, |s| s.clamp = clamp)
    }

    /// Changes a pane's evidence strength and rebuilds it over the scans so
    /// far.
    pub fn set_strength(&mut self, pane: usize, strength: f64) -> Result<()> {
        self.set_knob(pane, |s| s.strength = strength)
    }

    /// Puts the person into the corridor or takes them out, from the next
    /// scan on.
    pub fn set_person(&mut self, on: bool) {
        self.sim.set_person(on);
        self.settings.person = on;
    }

    /// Records how long the page took for one frame (milliseconds, measured
    /// around the core's calls), for the "ms per frame" readout; a time that
    /// is no finite number of at least 0 is ignored.
    pub fn record_frame_ms(&mut self, ms: f64) {
        self.frame_ms.record(ms);
    }

    /// Pane `pane`'s map as a ROS `map_server` pair, the YAML naming the
    /// image `apartment-left.pgm` or `apartment-right.pgm`.
    pub fn export_map(&self, pane: usize) -> Result<MapServerPair> {
        let side = if pane == 0 { "left" } else { "right" };
        let name = format!("apartment-{side}.pgm");
        Ok(export::map_server_pair(self.grid(pane)?, &name))
    }

    /// Median of the recent frame times, milliseconds.
    pub fn frame_ms(&self) -> Option<f64> {
        self.frame_ms.median()
    }
}

#[cfg(test)]
mod tests;
