//! A real log's map of whichever cell model the reader chose
//! ([`LogCellModel`]): a map pane of that model behind one interface
//! ([`LogMap`]), and its grid behind another ([`LogGrid`]), each
//! implemented once for every cell model's tiled map (docs/ARCHITECTURE.md,
//! "Real logs").

use super::settings::LogCellModel;
use crate::apps::pane::{MapPane, PaneWork, ScreenView};
use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::readout::{readout_at_pixel, CellReadout};
use crate::grid::stats::{StateCounts, TileTally};
use crate::grid::{
    CellModel, FilterSettings, Grid, HitCount, HitCounting, HitMissOdds, LogOddsGrid, Store,
    StoredCell, Tiled, TiledGrid,
};
use crate::io::map_server::MapServerPair;
#[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
use crate::io::map_server::{export_counts, ExportCounts};
use crate::mapping::insertion::ScanInserter;
use crate::mapping::scan_match::MatchMap;
use crate::render::overlay::RobotMark;
use crate::sensors::Scan;

/// A real log's grid, of whichever cell model its pane holds: what a pane
/// and its tests read of it.
pub trait LogGrid {
    /// The map's limits.
    fn geometry(&self) -> &GridGeometry;
    /// Cells with storage.
    fn cells_allocated(&self) -> usize;
    /// Bytes a cell takes.
    fn bytes_per_cell(&self) -> usize;
    /// Bytes the allocated cells hold.
    fn bytes_allocated(&self) -> usize;
    /// True once a cell's evidence was dropped for want of storage.
    fn refused(&self) -> bool;
    /// The probability of occupancy of cell `(ix, iy)`, `None` outside.
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn probability_at(&self, ix: usize, iy: usize) -> Option<f64>;
    /// The map in one array as log odds, each cell's update count kept:
    /// the log-odds map itself, or another model's cells read as log odds
    /// (the clamp then the largest magnitude among them, at least 1).
    /// (For tests and the benchmarks: the page never needs it, and a
    /// method of an interface is shipped whether it is called or not.)
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn to_dense(&self) -> Result<LogOddsGrid>;
    /// Every cell counted with the export's thresholds (a walk of the
    /// whole map: what the counts kept per tile must equal).
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn export_counts(&self) -> ExportCounts;
    /// The grid as a scan matcher reads it.
    fn as_match_map(&self) -> &dyn MatchMap;
}

/// A grid read as a dense log-odds map ([`LogGrid::to_dense`]): the
/// log-odds map as it is, another model's cells through
/// [`CellModel::log_odds`].
pub trait DenseLogOdds {
    fn dense_log_odds(&self) -> Result<LogOddsGrid>;
}

impl DenseLogOdds for TiledGrid {
    fn dense_log_odds(&self) -> Result<LogOddsGrid> {
        self.to_dense()
    }
}

impl DenseLogOdds for Grid<HitCounting, Tiled<HitCount>> {
    fn dense_log_odds(&self) -> Result<LogOddsGrid> {
        as_log_odds(self)
    }
}

impl DenseLogOdds for Grid<HitMissOdds, Tiled<u16>> {
    fn dense_log_odds(&self) -> Result<LogOddsGrid> {
        as_log_odds(self)
    }
}

impl<M: CellModel> LogGrid for Grid<M, Tiled<M::Cell>>
where
    Self: DenseLogOdds,
{
    fn geometry(&self) -> &GridGeometry {
        Grid::geometry(self)
    }
    fn cells_allocated(&self) -> usize {
        Grid::cells_allocated(self)
    }
    fn bytes_per_cell(&self) -> usize {
        Grid::bytes_per_cell(self)
    }
    fn bytes_allocated(&self) -> usize {
        Grid::bytes_allocated(self)
    }
    fn refused(&self) -> bool {
        Grid::refused(self)
    }
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn probability_at(&self, ix: usize, iy: usize) -> Option<f64> {
        Some(self.model().probability(self.cell_at(ix, iy)?))
    }
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn to_dense(&self) -> Result<LogOddsGrid> {
        self.dense_log_odds()
    }
    #[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
    fn export_counts(&self) -> ExportCounts {
        export_counts(self)
    }
    fn as_match_map(&self) -> &dyn MatchMap {
        self
    }
}

/// A real log's map pane: tiled, seen through a screen-sized view, of one
/// of the cell models a reader chooses from ([`LogMap::new`]). Every
/// method is one generic implementation for every model.
pub(super) trait LogMap {
    fn grid(&self) -> &dyn LogGrid;
    fn view(&self) -> &ScreenView;
    fn view_mut(&mut self) -> &mut ScreenView;
    fn work(&self) -> PaneWork;
    /// Every cell back to unknown, the work to zero, the view redrawn.
    fn reset(&mut self);
    /// Inserts `scan` (at its pose) with `inserter`, and counts its work.
    fn insert(&mut self, inserter: &mut ScanInserter, scan: &Scan, laser_max: f64);
    /// The counts kept per tile in `tally`, with the tiles written since
    /// its last refresh counted afresh.
    fn counts(&self, tally: &TileTally) -> StateCounts;
    /// Brings `tally` up to date; returns the cells recounted.
    fn refresh(&mut self, tally: &mut TileTally) -> usize;
    /// Tiles written since the tally's last refresh.
    fn tiles_touched(&self) -> usize;
    fn path_pixels(&self, poses: &[Pose]) -> Vec<f32>;
    fn robot_at(&self, pose: &Pose) -> RobotMark;
    fn readout_at_pixel(&self, col: usize, row: usize) -> Option<CellReadout>;
    fn readout_at_view(&self, x: f64, y: f64) -> Option<CellReadout>;
    fn pixels(&mut self) -> &[u8];
    fn pixels_within(&mut self, max_samples: usize, quick: bool) -> bool;
    fn export(&self, image_name: &str) -> MapServerPair;
}

impl dyn LogMap {
    /// A fresh map of `model`'s cells over `extent`, seen through `view`.
    pub(super) fn new(
        model: LogCellModel,
        extent: GridGeometry,
        filter: FilterSettings,
        budget_cells: usize,
        view: ScreenView,
    ) -> Result<Box<dyn LogMap>> {
        Ok(match model {
            LogCellModel::LogOdds => Box::new(MapPane::new(
                TiledGrid::new(extent, filter, budget_cells)?,
                view,
            )),
            LogCellModel::HitCounting => Box::new(MapPane::new(
                Grid::with_model(extent, LogCellModel::hit_counting(), budget_cells)?,
                view,
            )),
            LogCellModel::HitMissOdds => Box::new(MapPane::new(
                Grid::with_model(extent, LogCellModel::hit_miss_odds(), budget_cells)?,
                view,
            )),
        })
    }
}

impl<M: CellModel + 'static> LogMap for MapPane<M, Tiled<M::Cell>, ScreenView>
where
    Grid<M, Tiled<M::Cell>>: DenseLogOdds,
    M::Cell: 'static,
{
    fn grid(&self) -> &dyn LogGrid {
        MapPane::grid(self)
    }
    fn view(&self) -> &ScreenView {
        MapPane::view(self)
    }
    fn view_mut(&mut self) -> &mut ScreenView {
        MapPane::view_mut(self)
    }
    fn work(&self) -> PaneWork {
        MapPane::work(self)
    }
    fn reset(&mut self) {
        MapPane::reset(self)
    }
    fn insert(&mut self, inserter: &mut ScanInserter, scan: &Scan, laser_max: f64) {
        let stats = inserter.insert(self.grid_mut(), scan, laser_max);
        self.count(scan, stats);
    }
    fn counts(&self, tally: &TileTally) -> StateCounts {
        tally.counts(MapPane::grid(self))
    }
    fn refresh(&mut self, tally: &mut TileTally) -> usize {
        tally.refresh(self.grid_mut())
    }
    fn tiles_touched(&self) -> usize {
        MapPane::grid(self).store().touched().len()
    }
    fn path_pixels(&self, poses: &[Pose]) -> Vec<f32> {
        MapPane::path_pixels(self, poses)
    }
    fn robot_at(&self, pose: &Pose) -> RobotMark {
        MapPane::robot_at(self, pose)
    }
    fn readout_at_pixel(&self, col: usize, row: usize) -> Option<CellReadout> {
        readout_at_pixel(MapPane::grid(self), col, row)
    }
    fn readout_at_view(&self, x: f64, y: f64) -> Option<CellReadout> {
        MapPane::readout_at_view(self, x, y)
    }
    fn pixels(&mut self) -> &[u8] {
        MapPane::pixels(self)
    }
    fn pixels_within(&mut self, max_samples: usize, quick: bool) -> bool {
        MapPane::pixels_within(self, max_samples, quick)
    }
    fn export(&self, image_name: &str) -> MapServerPair {
        MapPane::export(self, image_name)
    }
}

/// Grows the allocator ahead of a map holding `allocated` bytes of tiles
/// when fewer than [`RESERVE_MIN_BYTES`] of the `reserved` are left: a
/// block of the larger of that and a [`RESERVE_SHARE`]th of `allocated`
/// is allocated and freed, so that the tiles that follow are carved from
/// it. Returns the bytes reserved for. (Native allocators map large blocks
/// of their own: there this does nothing.) In wasm the allocator otherwise
/// grows the module's memory a tile or two at a time, and on the Freiburg
/// campus (3,273 tiles) those growths and the collections they set off
/// were a quarter of the build under Node.
pub(super) fn reserve_ahead(allocated: usize, reserved: usize) -> usize {
    if !cfg!(target_arch = "wasm32") || allocated + RESERVE_MIN_BYTES / 2 <= reserved {
        return reserved;
    }
    let block = RESERVE_MIN_BYTES.max(allocated / RESERVE_SHARE);
    // (Seen by the optimiser, so that the allocation is made.)
    drop(std::hint::black_box(Vec::<u8>::with_capacity(block)));
    allocated + block
}

/// The least the allocator is grown by ahead of a map's tiles, bytes, and
/// the share of the map's bytes so far it is grown by when that is more
/// (at most a quarter of the memory is held ahead, in a dozen growths for
/// the campus's 107 MB).
const RESERVE_MIN_BYTES: usize = 8 << 20;
const RESERVE_SHARE: usize = 4;

/// A grid of any model as a dense log-odds map (see [`LogGrid::to_dense`]).
fn as_log_odds<M: CellModel>(grid: &Grid<M, Tiled<M::Cell>>) -> Result<LogOddsGrid> {
    let dense = grid.to_dense()?;
    let m = grid.model();
    let clamp = dense
        .cells()
        .iter()
        .map(|&c| m.log_odds(c).abs())
        .fold(1.0f32, f32::max);
    let g = dense.geometry();
    let mut out = LogOddsGrid::new(
        *g,
        FilterSettings {
            prior: 0.5,
            clamp: clamp as f64,
        },
    )?;
    let (_, store) = out.model_and_store();
    let updates = dense.store().updates();
    for (i, (&c, &n)) in dense.cells().iter().zip(updates).enumerate() {
        let (ix, iy) = g.cell_of_index(i);
        if let Some((l, u)) = store.slot(ix, iy, 0.0) {
            *l = m.log_odds(c);
            *u = c.updates(n);
        }
    }
    Ok(out)
}
