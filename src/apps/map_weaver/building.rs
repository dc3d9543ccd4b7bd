//! Making a Map Weaver run in calls of bounded work.
//!
//! A run at the scene's largest size holds three maps of a million cells:
//! the simulation's ground truth and each pane's own (its truth, grid and
//! view). Drawn in one call, they cost a page a long task (docs/
//! ARCHITECTURE.md, "Sessions and panes": a page never blocks). A
//! [`WeaverBuild`] starts from settings checked once
//! ([`super::CheckedWeaverSettings`]), makes the panes' grids, then draws the ground truths and first draws the panes' views a band of rows
//! per piece, so that a call stops within one piece of its budget of cells.
//! The pieces compute what one call computes in the same order, so the run
//! is the one-call run bit for bit ([`super::Weaver::with_learned`] is a
//! build with no budget).

use super::pane::{Pane, PaneModel};
use super::settings::{renamed, CheckedWeaverSettings, PaneSettings, WeaverSettings};
use super::timing::RecentTimes;
use super::{Clock, Weaver};
use crate::apps::pane::MapPane;
use crate::error::Result;
use crate::geometry::GridGeometry;
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::LearnedInverse;
use crate::mapping::traversal::ScanStats;
use crate::render::map_view::MapView;
use crate::scenes::apartment::{ApartmentScene, ApartmentSim};
use crate::world::{Rect, World};

/// The build's unit of work is a cell of a view synced (its gray, entropy
/// and squared error computed and written, about 25 ns natively). A cell
/// of a truth drawn costs an eighth of that (only the cells under a box
/// are written), a cell of a view made a quarter (its arrays allocated,
/// the surveyed region's flags set): counted so, a page's budget learned
/// from one piece's time fits the next piece whatever its kind.
const TRUTH_CELLS_PER_UNIT: u64 = 8;
const VIEW_CELLS_PER_UNIT: u64 = 4;

/// What one [`WeaverBuild::work`] call did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BuildReport {
    /// The work the call did, in cells of a view synced (the unit of its
    /// budget: a cell of the truth map counts a fraction of one).
    pub cells: u64,
    /// True once every map is drawn: [`WeaverBuild::finish`] is then a
    /// matter of moving the parts into place.
    pub done: bool,
}

/// The rows a piece of at most about `budget` units takes next, at least
/// one: from `done` on, in a map `width` x `height` whose cells cost a
/// unit per `per_unit` cells.
fn band(
    done: usize,
    (width, height): (usize, usize),
    per_unit: u64,
    budget: u64,
) -> std::ops::Range<usize> {
    let cells = budget.saturating_mul(per_unit);
    let rows = (cells / width.max(1) as u64).clamp(1, height as u64) as usize;
    done..(done + rows).min(height)
}

/// A ground truth drawn a band of rows per piece: every box over the band
/// ([`World::fill_rows`]), the bands covering the map giving the world
/// [`World::from_boxes`] gives.
#[derive(Debug, Clone)]
struct TruthDrawing {
    world: World,
    boxes: Vec<Rect>,
    rows: usize,
}

impl TruthDrawing {
    fn new(geometry: GridGeometry, boxes: &[Rect]) -> Self {
        Self {
            world: World::empty(geometry),
            boxes: boxes.to_vec(),
            rows: 0,
        }
    }

    fn done(&self) -> bool {
        self.rows >= self.world.geometry().height()
    }

    /// Draws one band of about `budget` units; returns its units.
    fn piece(&mut self, budget: u64) -> u64 {
        let g = *self.world.geometry();
        let size = (g.width(), g.height());
        let rows = band(self.rows, size, TRUTH_CELLS_PER_UNIT, budget);
        for b in &self.boxes {
            self.world.fill_rows(b, true, rows.clone());
        }
        self.rows = rows.end;
        ((rows.len() * g.width()) as u64).div_ceil(TRUTH_CELLS_PER_UNIT)
    }
}

/// A pane's view once its truth is drawn, synced with its empty grid a
/// band of rows per piece.
#[derive(Debug, Clone)]
struct PaneMaps {
    truth: Vec<bool>,
    view: MapView,
    rows: usize,
}

/// One pane being made: everything [`Pane`] checks is checked and its
/// grid made when the build starts; its truth and view follow in pieces.
#[derive(Debug, Clone)]
struct PaneBuild {
    settings: PaneSettings,
    model: PaneModel,
    scene: ApartmentScene,
    tracked_cells: [usize; 3],
    grid: LogOddsGrid,
    truth: TruthDrawing,
    maps: Option<PaneMaps>,
}

impl PaneBuild {
    /// Pane `k` of `settings` with pane settings `p`, already checked
    /// ([`PaneSettings::validate`]): a resolution the scene cannot be drawn
    /// at is refused here, naming the pane's field.
    fn new(
        settings: &WeaverSettings,
        learned: &LearnedInverse,
        k: usize,
        p: &PaneSettings,
    ) -> Result<Self> {
        // A resolution the scene cannot be drawn at is the pane's field.
        let field = format!("panes[{k}].resolution (the scene's width x height at it)");
        let scene = match p.resolution {
            Some(r) => settings
                .scene
                .at_resolution(r)
                .map_err(|e| renamed(&field, e))?,
            None => settings.scene.clone(),
        };
        let geometry = scene.validate().map_err(|e| renamed(&field, e))?;
        let tracked_cells = scene.tracked_cells()?;
        let grid = LogOddsGrid::new(
            geometry,
            FilterSettings {
                prior: 0.5,
                clamp: p.clamp,
            },
        )?;
        let model = PaneModel::build(p, &settings.hand_crafted, learned)?;
        Ok(Self {
            settings: *p,
            model,
            truth: TruthDrawing::new(geometry, &scene.obstacles),
            scene,
            tracked_cells,
            grid,
            maps: None,
        })
    }

    fn done(&self) -> bool {
        self.maps
            .as_ref()
            .is_some_and(|m| m.rows >= self.grid.geometry().height())
    }

    /// One piece: a band of the truth, the view made, or a band of the
    /// view synced. Returns its units.
    fn piece(&mut self, budget: u64) -> Result<u64> {
        if !self.truth.done() {
            return Ok(self.truth.piece(budget));
        }
        let g = *self.grid.geometry();
        let Some(maps) = &mut self.maps else {
            let truth = self.truth.world.occupied().to_vec();
            let region = self.scene.cells_in(&g, &[self.scene.surveyed]);
            let view = MapView::new(&g, &truth, &region)?;
            self.maps = Some(PaneMaps {
                truth,
                view,
                rows: 0,
            });
            return Ok((g.len() as u64).div_ceil(VIEW_CELLS_PER_UNIT));
        };
        let rows = band(maps.rows, (g.width(), g.height()), 1, budget);
        maps.rows = rows.end;
        Ok(maps.view.sync_rows(&self.grid, rows) as u64)
    }

    /// The pane, its pieces worked to the end first.
    fn finish(mut self, settings: &WeaverSettings) -> Result<Pane> {
        let height = self.grid.geometry().height();
        let PaneMaps { truth, view, .. } = loop {
            match self.maps.take() {
                Some(m) if m.rows >= height => break m,
                maps => {
                    self.maps = maps;
                    self.piece(u64::MAX)?;
                }
            }
        };
        let first = self.tracked_cells.map(|i| self.grid.log_odds()[i]);
        Ok(Pane {
            settings: self.settings,
            model: self.model,
            geometry: *self.grid.geometry(),
            truth,
            tracked_cells: self.tracked_cells,
            entropy_curve: vec![view.entropy_bits()],
            brier_curve: vec![view.brier_region()],
            tracked: vec![first],
            map: MapPane::new(self.grid, view),
            last: ScanStats::default(),
            pose: settings.scene.path.pose_at(0.0),
            ghost: Default::default(),
            scan_ms: RecentTimes::default(),
            sweep: Default::default(),
            scene: self.scene,
        })
    }
}

impl Pane {
    /// An empty pane `k` of `settings` with pane settings `p` (checked by
    /// [`PaneSettings::validate`] first), made in one call.
    pub fn new(
        settings: &WeaverSettings,
        learned: &LearnedInverse,
        k: usize,
        p: &PaneSettings,
    ) -> Result<Self> {
        PaneBuild::new(settings, learned, k, p)?.finish(settings)
    }
}

/// A Map Weaver run being made: the simulation's ground truth, then each
/// pane's truth and view, in pieces of a band of rows.
#[derive(Debug, Clone)]
pub struct WeaverBuild {
    settings: WeaverSettings,
    /// Boxed as the panes' copies are ([`PaneModel`]).
    learned: Box<LearnedInverse>,
    sim_truth: TruthDrawing,
    panes: [PaneBuild; 2],
}

impl WeaverBuild {
    /// Checks `settings` ([`WeaverSettings::check`], a refusal names the
    /// field) and makes the panes' grids; no map is drawn yet.
    pub fn new(settings: WeaverSettings, learned: LearnedInverse) -> Result<Self> {
        Self::checked(settings.check()?, learned)
    }

    /// [`WeaverBuild::new`] with settings checked already.
    pub fn checked(settings: CheckedWeaverSettings, learned: LearnedInverse) -> Result<Self> {
        let (settings, geometry) = settings.into_parts();
        let panes = [
            PaneBuild::new(&settings, &learned, 0, &settings.panes[0])?,
            PaneBuild::new(&settings, &learned, 1, &settings.panes[1])?,
        ];
        Ok(Self {
            sim_truth: TruthDrawing::new(geometry, &settings.scene.obstacles),
            settings,
            learned: Box::new(learned),
            panes,
        })
    }

    /// True once every map is drawn.
    pub fn done(&self) -> bool {
        self.sim_truth.done() && self.panes.iter().all(PaneBuild::done)
    }

    /// Works pieces while the call has spent less than `budget` units (a
    /// budget of 0 counts as 1): at least one piece while there is one, and
    /// past the budget by at most one piece (a band of rows, at most a row
    /// past the budget, or a pane's view made).
    pub fn work(&mut self, budget: u64) -> Result<BuildReport> {
        let budget = budget.max(1);
        let mut spent = 0u64;
        while spent < budget && !self.done() {
            let left = budget - spent;
            let cells = if !self.sim_truth.done() {
                self.sim_truth.piece(left)
            } else if let Some(p) = self.panes.iter_mut().find(|p| !p.done()) {
                p.piece(left)?
            } else {
                break;
            };
            spent = spent.saturating_add(cells);
        }
        Ok(BuildReport {
            cells: spent,
            done: self.done(),
        })
    }

    /// The run at scan 0, what is left of the maps drawn first.
    pub fn finish(mut self) -> Result<Weaver> {
        self.work(u64::MAX)?;
        let Self {
            settings,
            learned,
            sim_truth,
            panes: [left, right],
        } = self;
        let sim = ApartmentSim::with_truth(
            settings.scene.clone(),
            sim_truth.world,
            settings.seed,
            settings.person,
        )?;
        let geometry = *sim.ground_truth().geometry();
        let tracked_cells = settings.scene.tracked_cells()?;
        let panes = [left.finish(&settings)?, right.finish(&settings)?];
        #[cfg(not(target_arch = "wasm32"))]
        let clock: Option<Clock> = Some(super::timing::native_clock);
        #[cfg(target_arch = "wasm32")]
        let clock: Option<Clock> = None;
        Ok(Weaver {
            scans_per_lap: settings.scene.scans_per_lap(),
            learned,
            geometry,
            sim,
            tracked_cells,
            history: Vec::new(),
            panes,
            frame_ms: RecentTimes::default(),
            clock,
            brier_pixels: Vec::new(),
            settings,
        })
    }
}
