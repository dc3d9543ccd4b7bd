//! A real log's map of whichever cell model the reader chose
//! ([`LogCellModel`]): one map pane type per model ([`LogMap`]) and its
//! grid ([`LogGrid`]), each consumer generic over the model
//! (docs/ARCHITECTURE.md, "Real logs").

use super::settings::LogCellModel;
use crate::apps::pane::{MapPane, PaneWork, ScreenView};
use crate::error::Result;
use crate::geometry::GridGeometry;
use crate::grid::{
    CellModel, FilterSettings, Grid, HitCount, HitCounting, HitMissOdds, LogOdds, LogOddsGrid,
    Store, Tiled, TiledGrid,
};
use crate::mapping::traversal::{BeamBand, RayMapper};
use crate::sensors::Scan;

/// A real log's map: tiled, seen through a screen-sized view, of one of
/// the cell models a reader chooses from. One map pane type per model; the
/// pane dispatches to it ([`each_map`]).
#[derive(Debug, Clone)]
pub(super) enum LogMap {
    LogOdds(MapPane<LogOdds, Tiled<f32>, ScreenView>),
    HitCounting(MapPane<HitCounting, Tiled<HitCount>, ScreenView>),
    HitMissOdds(MapPane<HitMissOdds, Tiled<u16>, ScreenView>),
}

/// Runs `$body` with `$m` bound to the map pane inside `$map`, whatever its
/// cell model: every consumer of a map is generic over the model.
macro_rules! each_map {
    ($map:expr, $m:ident => $body:expr) => {
        match $map {
            LogMap::LogOdds($m) => $body,
            LogMap::HitCounting($m) => $body,
            LogMap::HitMissOdds($m) => $body,
        }
    };
}
pub(super) use each_map;

impl LogMap {
    /// A fresh map of `model`'s cells over `extent`, seen through `view`.
    pub(super) fn new(
        model: LogCellModel,
        extent: GridGeometry,
        filter: FilterSettings,
        budget_cells: usize,
        view: ScreenView,
    ) -> Result<Self> {
        Ok(match model {
            LogCellModel::LogOdds => Self::LogOdds(MapPane::new(
                TiledGrid::new(extent, filter, budget_cells)?,
                view,
            )),
            LogCellModel::HitCounting => Self::HitCounting(MapPane::new(
                Grid::with_model(extent, LogCellModel::hit_counting(), budget_cells)?,
                view,
            )),
            LogCellModel::HitMissOdds => Self::HitMissOdds(MapPane::new(
                Grid::with_model(extent, LogCellModel::hit_miss_odds(), budget_cells)?,
                view,
            )),
        })
    }

    pub(super) fn grid(&self) -> LogGrid<'_> {
        match self {
            Self::LogOdds(m) => LogGrid::LogOdds(m.grid()),
            Self::HitCounting(m) => LogGrid::HitCounting(m.grid()),
            Self::HitMissOdds(m) => LogGrid::HitMissOdds(m.grid()),
        }
    }

    pub(super) fn view(&self) -> &ScreenView {
        each_map!(self, m => m.view())
    }

    pub(super) fn view_mut(&mut self) -> &mut ScreenView {
        each_map!(self, m => m.view_mut())
    }

    pub(super) fn work(&self) -> PaneWork {
        each_map!(self, m => m.work())
    }

    /// Integrates one scan whose beams state their evidence as `bands`
    /// (with the space between beams if `between`), and counts its work.
    /// In wasm, the allocator is first grown ahead of the map's tiles
    /// whenever they near `reserved` bytes (returned updated): it otherwise
    /// grows the module's memory a tile or two at a time, and on the
    /// Freiburg campus (3,273 tiles) those growths and the collections they
    /// set off were a quarter of the build under Node.
    pub(super) fn integrate(
        &mut self,
        mapper: &mut RayMapper,
        scan: &Scan,
        bands: &[Option<BeamBand>],
        evidence: (f32, f32),
        between: bool,
        reserved: usize,
    ) -> usize {
        let reserved = reserve_ahead(self.grid().bytes_allocated(), reserved);
        each_map!(self, m => {
            let stats = mapper.integrate_bands_between(m.grid_mut(), scan, bands, evidence, between);
            m.count(scan, stats);
        });
        reserved
    }
}

/// The least the allocator is grown by ahead of a map's tiles, bytes, and
/// the share of the map's bytes so far it is grown by when that is more
/// (at most a quarter of the memory is held ahead, in a dozen growths for
/// the campus's 107 MB).
const RESERVE_MIN_BYTES: usize = 8 << 20;
const RESERVE_SHARE: usize = 4;

/// Grows the allocator ahead of a map holding `allocated` bytes of tiles
/// when fewer than [`RESERVE_MIN_BYTES`] of the `reserved` are left: a
/// block of the larger of that and a [`RESERVE_SHARE`]th of `allocated`
/// is allocated and freed, so that the tiles that follow are carved from
/// it. Returns the bytes reserved for. (Native allocators map large blocks
/// of their own: there this does nothing.)
fn reserve_ahead(allocated: usize, reserved: usize) -> usize {
    if !cfg!(target_arch = "wasm32") || allocated + RESERVE_MIN_BYTES / 2 <= reserved {
        return reserved;
    }
    let block = RESERVE_MIN_BYTES.max(allocated / RESERVE_SHARE);
    // (Seen by the optimiser, so that the allocation is made.)
    drop(std::hint::black_box(Vec::<u8>::with_capacity(block)));
    allocated + block
}

/// A real log's grid, of whichever cell model its pane holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LogGrid<'a> {
    LogOdds(&'a TiledGrid),
    HitCounting(&'a Grid<HitCounting, Tiled<HitCount>>),
    HitMissOdds(&'a Grid<HitMissOdds, Tiled<u16>>),
}

impl<'a> LogGrid<'a> {
    /// The map's limits.
    pub fn geometry(self) -> &'a GridGeometry {
        each_grid(self, |g| g.geometry(), |g| g.geometry(), |g| g.geometry())
    }
    /// Cells with storage.
    pub fn cells_allocated(self) -> usize {
        each_grid(
            self,
            |g| g.cells_allocated(),
            |g| g.cells_allocated(),
            |g| g.cells_allocated(),
        )
    }
    /// Bytes a cell takes.
    pub fn bytes_per_cell(self) -> usize {
        each_grid(
            self,
            |g| g.bytes_per_cell(),
            |g| g.bytes_per_cell(),
            |g| g.bytes_per_cell(),
        )
    }
    /// Bytes the allocated cells hold.
    pub fn bytes_allocated(self) -> usize {
        each_grid(
            self,
            |g| g.bytes_allocated(),
            |g| g.bytes_allocated(),
            |g| g.bytes_allocated(),
        )
    }
    /// True once a cell's evidence was dropped for want of storage.
    pub fn refused(self) -> bool {
        each_grid(self, |g| g.refused(), |g| g.refused(), |g| g.refused())
    }
    /// The probability of occupancy of cell `(ix, iy)`, `None` outside.
    pub fn probability_at(self, ix: usize, iy: usize) -> Option<f64> {
        fn p<M: CellModel, S: Store<M::Cell>>(g: &Grid<M, S>, ix: usize, iy: usize) -> Option<f64> {
            Some(g.model().probability(g.cell_at(ix, iy)?))
        }
        each_grid(self, |g| p(g, ix, iy), |g| p(g, ix, iy), |g| p(g, ix, iy))
    }

    /// The map in one array as log odds, each cell's update count kept:
    /// the log-odds map itself, or another model's cells read as log odds
    /// (the clamp then the largest magnitude among them, at least 1).
    pub fn to_dense(self) -> Result<LogOddsGrid> {
        match self {
            LogGrid::LogOdds(g) => g.to_dense(),
            LogGrid::HitCounting(g) => as_log_odds(g),
            LogGrid::HitMissOdds(g) => as_log_odds(g),
        }
    }
}

/// One closure per model (closures rather than a macro: each is checked
/// against its own grid type).
fn each_grid<'a, T>(
    g: LogGrid<'a>,
    log_odds: impl FnOnce(&'a TiledGrid) -> T,
    counting: impl FnOnce(&'a Grid<HitCounting, Tiled<HitCount>>) -> T,
    odds: impl FnOnce(&'a Grid<HitMissOdds, Tiled<u16>>) -> T,
) -> T {
    match g {
        LogGrid::LogOdds(g) => log_odds(g),
        LogGrid::HitCounting(g) => counting(g),
        LogGrid::HitMissOdds(g) => odds(g),
    }
}

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
    for (i, (&c, &n)) in dense.cells().iter().zip(dense.update_counts()).enumerate() {
        let (ix, iy) = g.cell_of_index(i);
        if let Some((l, u)) = store.slot(ix, iy, 0.0) {
            *l = m.log_odds(c);
            *u = n;
        }
    }
    Ok(out)
}
