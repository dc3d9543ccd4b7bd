//! One pose source's map of a log ([`LogPane`]): the log's scans (shared
//! with the session's other panes), the pose source that puts them on the
//! map ([`crate::poses`]), a tiled grid of the chosen cell model
//! ([`LogCellModel`]), the one scan insertion of a log
//! ([`crate::mapping::insertion`]: the ray traversal of Table 9.1 with the
//! bands of Table 9.2), and the build's progress towards a target scan
//! count. What it shows (its view, cursor, readouts and export) is in
//! `view.rs`.

use super::budget::{
    at_pose, check_pose_work, check_tile_budget, grid_of_extent, placed_at, scan_model,
    tiles_needed, MAX_POSE_WORK, UNITS_PER_NEW_CELL, VISITS_PER_UNIT,
};
use super::map::{reserve_ahead, LogGrid, LogMap};
use super::settings::{CheckedSettings, LogCellModel, LogMapSettings};
use crate::apps::pane::ScreenView;
use crate::error::{invalid, OccError, Result};
use crate::geometry::{GridGeometry, Pose};
use crate::grid::stats::TileTally;
use crate::grid::storage::{budget_message, DEFAULT_TILE_BUDGET_CELLS};
use crate::io::map_server;
use crate::mapping::insertion::ScanInserter;
use crate::mapping::reach::scan_extent;
use crate::poses::{match_settings, PoseSource, PoseSourceKind, SourceSettings};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::{Scan, ScanLog};
use std::sync::Arc;

/// How far a revision may move a scan of a pane's map, in cells, before
/// the map is built again at once (see `LogPane::follow_revision`), and
/// the reach at which a scan's turn is measured: a wall 10 m off moves by
/// its turn times 10 m.
const SHOWN_SHIFT_CELLS: f64 = 1.0;
const SHIFT_REACH: f64 = 10.0;
/// A revision rebuilds the map only once one scan in this many of those
/// in it was located since the last rebuild (`LogPane::follow_revision`).
const REBUILD_SHARE: usize = 4;

/// The output size a pane's view starts at, pixels, until a page sets its
/// own.
pub const DEFAULT_VIEW_SIZE: (usize, usize) = (480, 360);

/// How far a pane's build has got.
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
    /// Cells the mapper looked at since then.
    pub cells_visited: u64,
    /// The build's work in cell updates: the updates, visits ([`VISITS_PER_UNIT`]), tiles' cells
    /// (two units each), finding poses ([`crate::poses::PoseSource::work`], for scan matching
    /// [`crate::poses::match_work`]): what a budget counts.
    pub work: u64,
    /// Beams traced since the map was last reset.
    pub beams: u64,
    pub finished: bool,
    /// Cells allocated in tiles (what the beams have reached, in whole
    /// tiles), of the `cells` of the bounding box.
    pub cells_allocated: usize,
    pub bytes_allocated: usize,
    pub cells: usize,
    /// Loop closures the pose source has found (SLAM), `None` for a
    /// source that closes no loops.
    pub loop_closures: Option<usize>,
}

/// A map of a log at one pose source, built a few scans at a time towards
/// a target scan count (all scans, or a scrub position); going back resets
/// the map and rebuilds from the first scan (snapshots of a large map
/// would cost more memory than the whole log).
pub struct LogPane {
    /// The log's scans at its own poses, shared by the panes.
    scans: Arc<ScanLog>,
    /// Where this pane puts each scan.
    pub(super) source: Box<dyn PoseSource>,
    /// What this pane's cells believe.
    model: LogCellModel,
    /// The odometry noise dead reckoning adds (and a scan matcher's
    /// predictions allow for).
    noise: OdometryParams,
    settings: CheckedSettings,
    /// The grid, its view and the work done.
    pub(super) map: Box<dyn LogMap>,
    /// Most cells the map's tiles may hold.
    budget_cells: usize,
    /// Why the build stopped short (the tile budget), once it has.
    failure: Option<OccError>,
    /// How each scan is written into the map (and its scratch).
    inserter: ScanInserter,
    /// The bytes of tiles the allocator was grown for ([`reserve_ahead`]).
    reserved: usize,
    /// Scans located by the source.
    done: usize,
    /// Scans in the map (`0..inserted`): fewer than `done` while the map
    /// is built again at revised poses, a scan a step.
    inserted: usize,
    target: usize,
    /// The keyboard cursor's image cell `(col, row)`, if any.
    pub(super) cursor: Option<(usize, usize)>,
    /// The map's counts as exported, kept per tile (`view.rs`).
    pub(super) tally: TileTally,
    /// The source's revision the map is built at ([`PoseSource::revision`]).
    revision: u64,
    /// Where each scan of the map was inserted, for a source that revises
    /// its poses (empty for the others).
    built_at: Vec<Pose>,
    /// The map was kept through a revision (see [`Self::follow_revision`]):
    /// it is built again once the source has its last word, so that the
    /// finished map is the one of its poses.
    stale: bool,
    /// Scans located when the map was last emptied to be built again.
    rebuilt_at: usize,
    /// The work of maps built at poses since revised, so that a build's
    /// work only grows.
    earlier_work: u64,
    /// The pose error's sums so far (`slam_view.rs`).
    pub(super) pose_error: crate::poses::GrowingAlignment,
    /// The work a step of each kind ([`Self::next_step_kind`]) may take,
    /// from the steps of that kind before: the largest of them, a
    /// sixteenth of it forgotten a step ([`Self::advance_within`]).
    step_estimate: [u64; 3],
}

/// What a pose source of a pane is started with under `settings`.
pub(super) fn source_settings(settings: &CheckedSettings, noise: OdometryParams) -> SourceSettings {
    let s = settings.settings();
    SourceSettings {
        seed: s.seed,
        noise,
        matching: match_settings(s.range_cap),
        resolution: s.resolution,
    }
}

impl LogPane {
    /// A fresh map of `scans` at the poses `settings` choose, heading for
    /// all scans.
    pub fn new(scans: ScanLog, settings: LogMapSettings) -> Result<Self> {
        Self::with_tile_budget(scans, settings, DEFAULT_TILE_BUDGET_CELLS)
    }

    /// [`Self::new`] with at most `budget_cells` cells allocated in tiles
    /// (the default is [`DEFAULT_TILE_BUDGET_CELLS`]).
    pub fn with_tile_budget(
        scans: ScanLog,
        settings: LogMapSettings,
        budget_cells: usize,
    ) -> Result<Self> {
        let checked = settings.validate()?;
        Self::plan(
            Arc::new(scans),
            (settings.poses, settings.model),
            &checked,
            OdometryParams::WHEELS,
            budget_cells,
        )
    }

    /// [`Self::new`] with dead reckoning's noise chosen by the caller
    /// ([`OdometryParams::EXACT`] maps the corrected poses again, through
    /// the integration).
    pub fn with_odometry(
        scans: ScanLog,
        settings: LogMapSettings,
        odometry: OdometryParams,
    ) -> Result<Self> {
        let checked = settings.validate()?;
        odometry.validate()?;
        Self::plan(
            Arc::new(scans),
            (settings.poses, settings.model),
            &checked,
            odometry,
            DEFAULT_TILE_BUDGET_CELLS,
        )
    }

    /// A pane of pose source `kind` with cells of `model` over shared
    /// scans, heading for all of them, its view fitted at
    /// [`DEFAULT_VIEW_SIZE`].
    pub(super) fn plan(
        scans: Arc<ScanLog>,
        (kind, model): (PoseSourceKind, LogCellModel),
        settings: &CheckedSettings,
        noise: OdometryParams,
        budget_cells: usize,
    ) -> Result<Self> {
        let source = kind.start(&scans, &source_settings(settings, noise))?;
        check_pose_work(&scans, source.as_ref(), MAX_POSE_WORK)?;
        let extent = plan_grid(&scans, source.as_ref(), settings)?;
        let pane = Self::planned(
            Arc::clone(&scans),
            (source, model),
            settings,
            noise,
            budget_cells,
            extent,
        )?;
        // Refused now, with the resolution that fits, rather than part way
        // through the build (the map above has allocated no tile yet).
        let (poses, _) = pane.source.plan_poses(&scans);
        check_tile_budget(
            &scans,
            poses,
            pane.grid().geometry(),
            settings,
            budget_cells,
            pane.grid().bytes_per_cell(),
            |c| plan_grid(&scans, pane.source.as_ref(), c),
        )?;
        Ok(pane)
    }

    /// A pane of `source` with cells of `model` over shared scans, on the
    /// grid `extent` its plan found (the tile budget checked by the
    /// caller), heading for all of them, its view fitted at
    /// [`DEFAULT_VIEW_SIZE`].
    pub(super) fn planned(
        scans: Arc<ScanLog>,
        (source, model): (Box<dyn PoseSource>, LogCellModel),
        settings: &CheckedSettings,
        noise: OdometryParams,
        budget_cells: usize,
        extent: GridGeometry,
    ) -> Result<Self> {
        let (w, h) = DEFAULT_VIEW_SIZE;
        let view = ScreenView::new(&extent, w, h)?;
        let map = <dyn LogMap>::new(model, extent, settings.filter(), budget_cells, view)?;
        let inserter =
            ScanInserter::with_model(settings.settings().scan_insertion(), *settings.model());
        let target = scans.len();
        Ok(Self {
            scans,
            source,
            model,
            noise,
            settings: *settings,
            map,
            budget_cells,
            failure: None,
            inserter,
            reserved: 0,
            done: 0,
            inserted: 0,
            target,
            cursor: None,
            tally: {
                let t = map_server::cut_thresholds(model.trinary_cut());
                TileTally::new(t.occupied_above(), t.free_below())
            },
            revision: 0,
            built_at: Vec::new(),
            stale: false,
            rebuilt_at: 0,
            earlier_work: 0,
            pose_error: Default::default(),
            step_estimate: [0; 3],
        })
    }

    /// This pane's map under new checked settings (and pose source and cell
    /// model), heading for the same target, built from the first scan. The
    /// view and cursor stay when the map's limits do (a change of the model
    /// keeps the reader's zoom); otherwise the view shows the whole new map
    /// at the same output size.
    pub(super) fn replanned(
        &self,
        settings: &CheckedSettings,
        plan: (PoseSourceKind, LogCellModel),
    ) -> Result<Self> {
        let mut pane = Self::plan(
            Arc::clone(&self.scans),
            plan,
            settings,
            self.noise,
            self.budget_cells,
        )?;
        pane.target = self.target;
        pane.keep_view(self)?;
        Ok(pane)
    }

    /// Takes the view and cursor of `old`, this pane's map before new
    /// settings, when the map's limits stay; otherwise shows the whole map
    /// at `old`'s output size.
    pub(super) fn keep_view(&mut self, old: &LogPane) -> Result<()> {
        let v = old.map.view().viewport;
        if self.grid().geometry() == old.grid().geometry() {
            self.map.view_mut().viewport = v;
            self.cursor = old.cursor;
        } else {
            let view = &mut self.map.view_mut().viewport;
            view.resize(v.width, v.height)?;
            view.fit();
        }
        Ok(())
    }

    /// The grid `settings` would give `scans`, without allocating it: an
    /// error if the settings are invalid, the log has no laser scans, or
    /// the grid would be too large. A caller can check before handing its
    /// scans over to [`Self::new`].
    pub fn check(scans: &ScanLog, settings: &LogMapSettings) -> Result<GridGeometry> {
        let checked = settings.validate()?;
        let source = settings
            .poses
            .start(scans, &source_settings(&checked, OdometryParams::WHEELS))?;
        plan_grid(scans, source.as_ref(), &checked)
    }

    /// New settings: a new grid (the extent depends on the range cap, the
    /// margin and the poses) and a rebuild from the first scan towards the
    /// same target, at the pose source the settings name. On error nothing
    /// changes.
    pub fn configure(&mut self, settings: LogMapSettings) -> Result<()> {
        let checked = settings.validate()?;
        *self = self.replanned(&checked, (settings.poses, settings.model))?;
        Ok(())
    }

    fn restart(&mut self) {
        self.map.reset();
        self.source.reset();
        self.failure = None;
        self.done = 0;
        self.inserted = 0;
        self.revision = self.source.revision();
        self.earlier_work = 0;
        self.built_at.clear();
        self.stale = false;
        self.rebuilt_at = 0;
    }

    /// The source's poses revised: the map is emptied, to be built again
    /// from the first scan at them a scan a step ([`Self::integrate_next`]),
    /// so that no step holds the whole rebuild.
    ///
    /// While the source goes on, a revision keeps the map, marked stale,
    /// when it moves no scan of the map by more than [`SHOWN_SHIFT_CELLS`]
    /// (a reader would see no wall move), or when fewer than one scan in
    /// [`REBUILD_SHARE`] of those in the map was located since it was last
    /// built again: each rebuild integrates every scan so far again, and a
    /// rebuild at every revision cost Intel's SLAM pane 34 rebuilds, a
    /// third of its build; spaced so, the rebuilds together integrate at
    /// most about `REBUILD_SHARE` times the log's scans. Once the source
    /// has its last word, a stale map is built again.
    fn follow_revision(&mut self) {
        self.revision = self.source.revision();
        let recent = self.done - self.rebuilt_at;
        if self.done < self.target
            && (recent * REBUILD_SHARE < self.inserted || !self.moved_visibly())
        {
            self.stale = true;
            return;
        }
        self.rebuild();
    }

    /// The map emptied, to be built again at the source's poses.
    fn rebuild(&mut self) {
        self.earlier_work = self.progress().work - self.source.work();
        self.map.reset();
        self.inserted = 0;
        self.built_at.clear();
        self.stale = false;
        self.rebuilt_at = self.done;
    }

    /// Whether some scan of the map now lies more than
    /// [`SHOWN_SHIFT_CELLS`] from where it was inserted: its position's
    /// move plus its heading's turn at [`SHIFT_REACH`] metres.
    fn moved_visibly(&self) -> bool {
        let limit = SHOWN_SHIFT_CELLS * self.settings.settings().resolution;
        self.built_at.iter().zip(self.poses()).any(|(a, b)| {
            (a.x - b.x).hypot(a.y - b.y)
                + SHIFT_REACH * crate::geometry::wrap_angle(a.theta - b.theta).abs()
                > limit
        })
    }

    /// Whether the map shows the target's scans at the source's final
    /// word on their poses: nothing left to locate, settle or rebuild.
    fn caught_up(&self) -> bool {
        self.done >= self.target
            && self.inserted == self.done
            && !self.source.settling()
            && !self.stale
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
    /// stops after the scan whose work ([`BuildProgress::work`]) brings
    /// this call's to `max_cells` or more, or before one that would likely
    /// bring it past (by the largest of the last steps): a call is bounded
    /// by what it does (a scan down a long corridor updates ten times the cells of one
    /// in an office), so a page sizing the next call from the last one's
    /// duration keeps every call near its time slice. At least one scan is
    /// integrated when any is left (and `max_scans` is not 0).
    ///
    /// A step of a source that revises its poses (SLAM) may instead be a
    /// slice of its loop search or of an optimiser iteration, or a scan of
    /// the map built again at the revised poses: `max_scans` counts steps.
    pub fn advance_within(&mut self, max_scans: usize, max_cells: u64) -> BuildProgress {
        let start = self.progress().work;
        let mut steps = 0;
        while steps < max_scans && !self.caught_up() && self.failure.is_none() {
            // A step that would likely take the call past its budget waits
            // for the next call: SLAM's steps are up to 1.5 million units
            // on the Freiburg campus (a scan matched against a submap 70 m
            // across, a grid of maxima made), as large as a page's budget,
            // and taken after the budget was nearly spent they made calls
            // of twice their slice.
            let spent = self.progress().work - start;
            let kind = self.next_step_kind();
            let estimate = &mut self.step_estimate[kind];
            if steps > 0 && spent.saturating_add(*estimate) > max_cells {
                break;
            }
            // The estimate forgets the largest step slowly: a sixteenth a
            // step, and for a scan located over several steps (SLAM's
            // match, a stage a step) a sixteenth a scan, so that its
            // largest stage is still remembered at the next scan's.
            let located_before = self.done;
            if kind != 2 {
                *estimate -= *estimate / 16;
            }
            self.integrate_next();
            let step = self.progress().work - start - spent;
            let estimate = &mut self.step_estimate[kind];
            if kind == 2 && self.done != located_before {
                *estimate -= *estimate / 16;
            }
            *estimate = step.max(*estimate);
            steps += 1;
            if self.progress().work - start >= max_cells {
                break;
            }
        }
        self.refresh_counts();
        self.progress()
    }

    /// The kind of [`Self::integrate_next`]'s next step: 0 a scan inserted
    /// again at revised poses, 1 a slice of the source's settling, 2 a
    /// scan located (and inserted), or the map emptied to be built again.
    /// Their work differs a hundredfold (the Freiburg campus at SLAM: a
    /// scan located up to 1.6 million units, 200 settling slices and
    /// scans inserted again between two of them).
    fn next_step_kind(&self) -> usize {
        if self.inserted < self.done {
            0
        } else if self.source.settling() {
            1
        } else {
            2
        }
    }

    /// One step of bounded work: while the map is built again at revised
    /// poses, its next scan; while the source settles its poses, a bounded
    /// slice of that (a grid or heading of a loop search, a few rows of an
    /// optimiser iteration); otherwise scan `done` located by its
    /// source and inserted where the source put it.
    pub(super) fn integrate_next(&mut self) {
        if self.inserted < self.done {
            let k = self.inserted;
            if let Some(scan) = self.scan_at_pose(k) {
                if !self.insert(k, &scan) {
                    return;
                }
            }
            self.inserted += 1;
            return;
        }
        if self.source.settling() {
            self.source.settle_within(0);
            if let Some(e) = self.source.refusal() {
                // Past what finding the poses may cost: said, not built on.
                self.failure = Some(e.clone());
                return;
            }
            if self.source.revision() != self.revision {
                self.follow_revision();
            }
            return;
        }
        if self.done >= self.target {
            if self.stale {
                self.rebuild();
            }
            return;
        }
        let k = self.done;
        let laser_max = self.scans.max_range(k).unwrap_or(f64::INFINITY);
        // The scan is read from the log once: its source locates it, and
        // it is inserted where the source put it.
        // A source may locate a scan over several steps (SLAM's match
        // against its submap, a stage a step).
        let placed = match self.scans.scan(k) {
            Some(scan) => {
                let located =
                    self.source
                        .locate_step(k, &scan, laser_max, self.map.grid().as_match_map());
                match located {
                    Ok(Some(pose)) => placed_at(scan, pose),
                    Ok(None) => return,
                    Err(e) => {
                        self.failure = Some(e);
                        return;
                    }
                }
            }
            None => None,
        };
        if self.source.revision() != self.revision {
            // Every scan so far, this one too, is inserted again at the
            // revised poses in the steps that follow.
            self.done += 1;
            self.follow_revision();
            return;
        }
        if placed.is_some() && self.source.revises() {
            // Inserted by the next step, at the pose just found: a SLAM
            // step counts steps, not scans, and a campus scan's insertion
            // is a fifth of its match.
            self.done += 1;
            return;
        }
        if let Some(scan) = placed {
            if !self.insert(k, &scan) {
                return;
            }
        }
        self.done += 1;
        self.inserted = self.done;
    }

    /// Inserts scan `k`, `scan` where it is placed: false (and the build's
    /// failure said) when its beams reach past the tile budget.
    fn insert(&mut self, k: usize, scan: &Scan) -> bool {
        let laser_max = self.scans.max_range(k).unwrap_or(f64::INFINITY);
        if self.source.revises() {
            self.built_at.truncate(k);
            self.built_at.push(scan.pose());
        }
        self.reserved = reserve_ahead(self.grid().bytes_allocated(), self.reserved);
        self.map.insert(&mut self.inserter, scan, laser_max);
        if self.grid().refused() {
            let needed = self.tiles_reached();
            let grid = self.grid();
            self.failure = Some(OccError::State(budget_message(
                grid.geometry(),
                needed,
                self.budget_cells,
                grid.bytes_per_cell(),
            )));
            return false;
        }
        true
    }

    /// Scan `k` at this pane's pose for it.
    pub fn scan_at_pose(&self, k: usize) -> Option<Scan> {
        at_pose(&self.scans, k, *self.poses().get(k)?)
    }

    /// The tiles the beams of every scan reach: what the whole log would
    /// allocate, said when the budget refuses it.
    fn tiles_reached(&self) -> usize {
        tiles_needed(
            &self.scans,
            self.poses(),
            self.grid().geometry(),
            &self.settings,
        )
    }

    pub fn progress(&self) -> BuildProgress {
        let work = self.map.work();
        BuildProgress {
            scans_done: self.inserted,
            scans_target: self.target,
            scans_total: self.scans.len(),
            cell_updates: work.cell_updates,
            cells_visited: work.cells_visited,
            work: work.cell_updates
                + work.cells_visited / VISITS_PER_UNIT
                + self.grid().cells_allocated() as u64 * UNITS_PER_NEW_CELL
                + self.source.work()
                + self.earlier_work,
            beams: work.beams,
            finished: self.caught_up(),
            cells_allocated: self.grid().cells_allocated(),
            bytes_allocated: self.grid().bytes_allocated(),
            cells: self.grid().geometry().len(),
            loop_closures: self.source.loop_closures(),
        }
    }

    /// Why the build stopped short of its target (the tile budget), if it did.
    pub fn failure(&self) -> Option<&OccError> {
        self.failure.as_ref()
    }

    /// The map's grid, of this pane's cell model.
    pub fn grid(&self) -> &dyn LogGrid {
        self.map.grid()
    }

    /// What this pane's cells believe.
    pub fn model(&self) -> LogCellModel {
        self.model
    }

    /// The log's scans at its own poses.
    pub fn scans(&self) -> &ScanLog {
        &self.scans
    }

    /// Where this pane puts each scan.
    pub fn poses(&self) -> &[Pose] {
        self.source.poses()
    }

    /// The scans as the session's panes share them.
    pub(super) fn shared_scans(&self) -> &Arc<ScanLog> {
        &self.scans
    }

    /// This pane's pose source.
    pub fn source(&self) -> PoseSourceKind {
        self.source.kind()
    }

    /// The settings the map is built with (their `poses` field is the
    /// session's choice; [`Self::source`] is this pane's).
    pub fn settings(&self) -> &LogMapSettings {
        self.settings.settings()
    }
}

/// The grid for `scans` placed by `source` under valid settings: the
/// extent of the poses its plan walks ([`PoseSource::plan_poses`]) and of
/// every cell their beams carve or mark, the room it leaves for drift
/// around them, covered on whole cells, and a range cap whose reach fits
/// the traversal.
pub(super) fn plan_grid(
    scans: &ScanLog,
    source: &dyn PoseSource,
    c: &CheckedSettings,
) -> Result<GridGeometry> {
    let (poses, margin) = source.plan_poses(scans);
    let placed = (0..scans.len()).filter_map(|k| {
        let scan = at_pose(scans, k, *poses.get(k)?)?;
        Some((scan, scan_model(c, scans, k)))
    });
    grid_of_extent(scan_extent(placed, c.settings().no_return_reach), margin, c)
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
        let scans = crate::io::carmen::read_scans(text.as_bytes()).unwrap();
        let settings = LogMapSettings {
            resolution: 0.1,
            ..Default::default()
        };
        let mut a = LogPane::new(scans.clone(), settings).unwrap();
        a.seek(3).unwrap();
        let p = a.advance(100);
        assert_eq!((p.scans_done, p.finished), (3, true));
        let at3 = a.grid().to_dense().unwrap();
        a.seek(6).unwrap();
        a.advance(2);
        a.advance(2);
        assert!(a.progress().finished && a.progress().scans_done == 6);
        a.seek(3).unwrap();
        assert_eq!(a.progress().scans_done, 0, "going back resets");
        a.advance(10);
        assert_eq!(a.grid().to_dense().unwrap(), at3);
        assert!(a.seek(7).is_err());
    }

    #[test]
    fn the_default_settings_check_and_carry_table_9_2_s_model() {
        let checked = CheckedSettings::default();
        let model =
            crate::inverse::HandCrafted::new(crate::inverse::HandCraftedParams::laser(30.0))
                .unwrap();
        assert_eq!(checked.model(), &model);
        assert!(checked.model_for_laser(40.0).is_none());
        assert_eq!(checked.model_for_laser(8.0).unwrap().params().z_max, 8.0);
    }
}
