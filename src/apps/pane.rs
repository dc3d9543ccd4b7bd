//! One map a widget shows: its grid, the mapper that writes it, the view it
//! is seen through, the readout under the reader's pointer, its export,
//! and the work it has cost. Map Weaver's two panes and each pose source of
//! a real log are panes; a session holds them and feeds them scans.
//!
//! A pane answers in image units (docs/ARCHITECTURE.md, "Sessions and
//! panes"): a view position in output pixels becomes a cell here, and the
//! pixels it hands out are the view's, so the page never flips, scales or
//! looks a cell up itself.

use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::readout::{readout_at_cell, readout_at_pixel, CellReadout};
use crate::grid::storage::DEFAULT_TILE_BUDGET_CELLS;
use crate::grid::{CellModel, Grid, Store};
use crate::inverse::InverseModel;
use crate::io::map_server::{export_counts, map_server_pair, ExportCounts, MapServerPair};
use crate::mapping::traversal::{BeamBand, RayMapper, ScanStats, MAX_REACH_CELLS};
use crate::render::map_view::MapView;
use crate::render::overlay::RobotMark;
use crate::render::viewport::{
    render_view, render_view_rows, samples_per_pixel, MapViewport, MAX_PIXELS_PER_CELL,
    MAX_SAMPLES, MAX_VIEW_PIXELS, MAX_VIEW_SIDE,
};
use crate::sensors::Scan;

/// The limits every pane keeps, as a page states them beside its controls
/// (and as the refusals that enforce them name them).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PaneLimits {
    /// The longest side of a view, pixels.
    pub max_view_side: usize,
    /// The most pixels a view may have.
    pub max_view_pixels: usize,
    /// The closest zoom, pixels per cell.
    pub max_pixels_per_cell: f64,
    /// The most cells a beam of a tiled map may reach from its sensor.
    pub max_reach_cells: f64,
    /// The most cells a tiled map may allocate.
    pub max_cells_allocated: usize,
}

/// The limits of [`MapPane`].
pub const PANE_LIMITS: PaneLimits = PaneLimits {
    max_view_side: MAX_VIEW_SIDE,
    max_view_pixels: MAX_VIEW_PIXELS,
    max_pixels_per_cell: MAX_PIXELS_PER_CELL,
    max_reach_cells: MAX_REACH_CELLS,
    max_cells_allocated: DEFAULT_TILE_BUDGET_CELLS,
};

/// The work a pane has done since it was last reset.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PaneWork {
    /// Scans integrated.
    pub scans: usize,
    /// Beams of those scans.
    pub beams: u64,
    /// Cells the mapper looked at.
    pub cells_visited: u64,
    /// Cell updates (at most one per cell per scan).
    pub cell_updates: u64,
}

/// How a pane is seen: through a screen-sized view that zooms and pans
/// ([`ScreenView`], a real log's map), or as the whole map at one pixel per
/// cell kept up to date cell by cell with its scores ([`MapView`], the
/// chapter's small maps).
pub trait PaneView<M: CellModel, S: Store<M::Cell>> {
    /// Brings the pixels up to date with `grid` and returns them (RGBA,
    /// north up).
    fn refresh(&mut self, grid: &Grid<M, S>) -> &[u8];
    /// The map image cell (column, row from the top) under view position
    /// `(x, y)` (output pixels), `None` off the map.
    fn image_cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)>;
    /// Forgets what was drawn: the next refresh draws everything.
    fn clear(&mut self);
}

/// A screen-sized view of a map of any size, and its pixel buffer.
#[derive(Debug, Clone)]
pub struct ScreenView {
    pub viewport: MapViewport,
    /// The last picture drawn whole.
    pixels: Vec<u8>,
    /// A picture being drawn in bands ([`ScreenView::refresh_within`]).
    drawing: Drawing,
}

/// A picture drawn a band of rows per call: the viewport it is drawn at,
/// its buffer and the rows done. A picture of another viewport starts
/// over.
#[derive(Debug, Clone, Default)]
struct Drawing {
    /// The viewport, and the samples per pixel side at most.
    viewport: Option<(MapViewport, usize)>,
    pixels: Vec<u8>,
    rows_done: usize,
}

impl ScreenView {
    /// The whole map of `geometry`, fitted into `width x height` pixels.
    pub fn new(geometry: &GridGeometry, width: usize, height: usize) -> Result<Self> {
        Ok(Self {
            viewport: MapViewport::new(geometry.width(), geometry.height(), width, height)?,
            pixels: Vec::new(),
            drawing: Drawing::default(),
        })
    }

    /// Draws at most `max_samples` map cells' worth of the view (whole
    /// rows, at least one) into a picture of its own, and returns true once
    /// that picture is whole: it then becomes [`Self::pixels`]. Until then
    /// the last whole picture stays. A zoomed-out view of a 26 M-cell map
    /// samples 16 cells per pixel (about 45 ms for 1200 x 900 pixels in a
    /// browser): drawn in bands, no call holds the page for long. A
    /// `quick` picture (a map still being built) samples one cell per
    /// pixel.
    pub fn refresh_within<M: CellModel, S: Store<M::Cell>>(
        &mut self,
        grid: &Grid<M, S>,
        max_samples: usize,
        quick: bool,
    ) -> bool {
        let v = self.viewport;
        let side = if quick { 1 } else { MAX_SAMPLES };
        let d = &mut self.drawing;
        if d.viewport != Some((v, side)) {
            d.viewport = Some((v, side));
            d.pixels.clear();
            d.pixels.resize(v.width * v.height * 4, 0);
            d.rows_done = 0;
        }
        let per_row = (v.width * samples_per_pixel(&v, side)).max(1);
        let rows = (max_samples / per_row).max(1);
        let end = d.rows_done.saturating_add(rows).min(v.height);
        render_view_rows(grid, &v, &mut d.pixels, d.rows_done..end, side);
        d.rows_done = end;
        if end < v.height {
            return false;
        }
        std::mem::swap(&mut self.pixels, &mut d.pixels);
        d.viewport = None;
        true
    }

    /// The last picture drawn whole (RGBA, north up; empty before the
    /// first).
    pub fn pixels(&self) -> &[u8] {
        &self.pixels
    }
}

impl<M: CellModel, S: Store<M::Cell>> PaneView<M, S> for ScreenView {
    fn refresh(&mut self, grid: &Grid<M, S>) -> &[u8] {
        render_view(grid, &self.viewport, &mut self.pixels);
        // A picture under way is of an older map, or of this viewport.
        self.drawing.viewport = None;
        &self.pixels
    }
    fn image_cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        self.viewport.cell_at(x, y)
    }
    fn clear(&mut self) {}
}

/// The whole map at one pixel per cell: a view position is an image cell.
impl<M: CellModel, S: Store<M::Cell>> PaneView<M, S> for MapView<M::Cell> {
    fn refresh(&mut self, grid: &Grid<M, S>) -> &[u8] {
        self.sync(grid);
        self.rgba()
    }
    fn image_cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let (w, h) = self.size();
        let (c, r) = (x.floor(), y.floor());
        (c >= 0.0 && r >= 0.0 && (c as usize) < w && (r as usize) < h)
            .then_some((c as usize, r as usize))
    }
    fn clear(&mut self) {
        MapView::clear(self);
    }
}

/// One map a widget shows.
#[derive(Debug, Clone)]
pub struct MapPane<M: CellModel, S: Store<M::Cell>, V> {
    grid: Grid<M, S>,
    mapper: RayMapper,
    view: V,
    work: PaneWork,
}

impl<M: CellModel, S: Store<M::Cell>, V: PaneView<M, S>> MapPane<M, S, V> {
    /// A pane showing `grid` through `view`.
    pub fn new(grid: Grid<M, S>, view: V) -> Self {
        Self {
            grid,
            mapper: RayMapper::new(),
            view,
            work: PaneWork::default(),
        }
    }

    pub fn grid(&self) -> &Grid<M, S> {
        &self.grid
    }
    /// The grid, for a caller that changes it outside a scan (a new clamp).
    pub fn grid_mut(&mut self) -> &mut Grid<M, S> {
        &mut self.grid
    }
    pub fn view(&self) -> &V {
        &self.view
    }
    pub fn view_mut(&mut self) -> &mut V {
        &mut self.view
    }
    /// The work done since the last reset.
    pub fn work(&self) -> PaneWork {
        self.work
    }

    /// Table 9.1 for one scan along its beams, with an inverse model.
    pub fn integrate<I: InverseModel + ?Sized>(&mut self, model: &I, scan: &Scan) -> ScanStats {
        let stats = self.mapper.integrate(&mut self.grid, model, scan);
        self.count(scan, stats);
        stats
    }

    /// Table 9.1 for one scan whose beams state their evidence as bands.
    pub fn integrate_bands(
        &mut self,
        scan: &Scan,
        bands: &[Option<BeamBand>],
        free: f32,
        occupied: f32,
    ) -> ScanStats {
        let stats = self
            .mapper
            .integrate_bands(&mut self.grid, scan, bands, free, occupied);
        self.count(scan, stats);
        stats
    }

    /// Counts a scan some other mapper integrated into [`Self::grid_mut`]
    /// (the literal sweep).
    pub fn count(&mut self, scan: &Scan, stats: ScanStats) {
        self.work.scans += 1;
        self.work.beams += scan.len() as u64;
        self.work.cells_visited += stats.cells_visited as u64;
        self.work.cell_updates += stats.cells_updated as u64;
    }

    /// Every cell back to unknown, the work to zero, the view redrawn.
    pub fn reset(&mut self) {
        self.grid.reset();
        self.work = PaneWork::default();
        self.view.clear();
    }

    /// The pixels, up to date.
    pub fn pixels(&mut self) -> &[u8] {
        self.view.refresh(&self.grid)
    }

    /// The cell under view position `(x, y)` (output pixels), `None` off
    /// the map.
    pub fn readout_at_view(&self, x: f64, y: f64) -> Option<CellReadout> {
        let (col, row) = self.view.image_cell_at(x, y)?;
        readout_at_pixel(&self.grid, col, row)
    }

    /// Cell `(ix, iy)` (row 0 at the bottom), `None` outside the map.
    pub fn readout_at_cell(&self, ix: usize, iy: usize) -> Option<CellReadout> {
        readout_at_cell(&self.grid, ix, iy)
    }

    /// A robot at `pose`, in the map's image units.
    pub fn robot_at(&self, pose: &Pose) -> RobotMark {
        RobotMark::at(self.grid.geometry(), pose)
    }

    /// `poses` as a path in image units, `[u0, v0, u1, v1, …]`.
    pub fn path_pixels(&self, poses: &[Pose]) -> Vec<f32> {
        let g = self.grid.geometry();
        poses
            .iter()
            .flat_map(|p| g.world_to_image(p.x, p.y).map(|c| c as f32))
            .collect()
    }

    /// The cells as the export shows them.
    pub fn counts(&self) -> ExportCounts {
        export_counts(&self.grid)
    }

    /// The map as a `map_server` pair whose YAML names `image_name`.
    pub fn export(&self, image_name: &str) -> MapServerPair {
        map_server_pair(&self.grid, image_name)
    }
}

impl<M: CellModel, S: Store<M::Cell>> MapPane<M, S, ScreenView> {
    /// Draws the view in a band of rows of at most `max_samples` sampled
    /// cells ([`ScreenView::refresh_within`]); true once the picture is
    /// whole.
    pub fn pixels_within(&mut self, max_samples: usize, quick: bool) -> bool {
        self.view.refresh_within(&self.grid, max_samples, quick)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{FilterSettings, LogOddsGrid, TiledGrid};
    use crate::inverse::{HandCrafted, HandCraftedParams};

    fn scan() -> Scan {
        let bearings: Vec<f64> = (0..36).map(|k| k as f64 * 10f64.to_radians()).collect();
        Scan::new(Pose::new(0.0, 0.0, 0.3).unwrap(), vec![2.0; 36], bearings).unwrap()
    }

    /// A large view is drawn a band of rows per call, each call sampling
    /// at most its budget of cells (whole rows, at least one); the last
    /// whole picture stays on screen until the new one is whole, which is
    /// then the picture drawn at once.
    #[test]
    fn a_view_drawn_in_bands_samples_at_most_its_budget_per_call() {
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 3.5,
        };
        let g = GridGeometry::sparse(60, 50, 0.1, -3.0, -2.5).unwrap();
        let mut pane = MapPane::new(
            TiledGrid::new(g, settings, 1 << 20).unwrap(),
            ScreenView::new(&g, 20, 16).unwrap(),
        );
        let model = HandCrafted::new(HandCraftedParams::laser(8.0)).unwrap();
        pane.integrate(&model, &scan());
        let whole = pane.clone().pixels().to_vec();
        // 20 x 16 pixels of a 60 x 50 map: 4 x 4 samples per pixel, 320
        // samples a row.
        let per_row = 20 * samples_per_pixel(&pane.view().viewport, MAX_SAMPLES);
        assert_eq!(per_row, 320);
        for (budget, calls_needed) in [(3 * per_row, 6), (per_row + 1, 16), (0, 16)] {
            let shown = pane.view().pixels().to_vec();
            let mut calls = 1;
            while !pane.pixels_within(budget, false) {
                calls += 1;
                assert_eq!(pane.view().pixels(), &shown[..], "budget {budget}");
            }
            assert_eq!(calls, calls_needed, "budget {budget}");
            assert_eq!(pane.view().pixels(), &whole[..]);
        }
    }

    /// A dense pane seen whole and a tiled pane seen through a screen view
    /// hold the same map after the same scan, and read the same cell under
    /// the same image pixel.
    #[test]
    fn dense_and_tiled_panes_map_and_read_alike() {
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 3.5,
        };
        let g = GridGeometry::new(60, 50, 0.1, -3.0, -2.5).unwrap();
        let truth = vec![false; g.len()];
        let region: Vec<usize> = (0..g.len()).collect();
        let mut dense = MapPane::new(
            LogOddsGrid::new(g, settings).unwrap(),
            MapView::new(&g, &truth, &region).unwrap(),
        );
        let sparse = GridGeometry::sparse(60, 50, 0.1, -3.0, -2.5).unwrap();
        let mut tiled = MapPane::new(
            TiledGrid::new(sparse, settings, 1 << 20).unwrap(),
            ScreenView::new(&sparse, 60, 50).unwrap(),
        );
        let model = HandCrafted::new(HandCraftedParams::laser(8.0)).unwrap();
        let s = scan();
        let a = dense.integrate(&model, &s);
        let b = tiled.integrate(&model, &s);
        assert_eq!(a, b);
        assert!(a.cells_updated > 100);
        assert_eq!(dense.work(), tiled.work());
        assert_eq!(dense.counts(), tiled.counts());
        assert_eq!(dense.export("m.pgm"), tiled.export("m.pgm"));
        assert_eq!(dense.pixels(), tiled.pixels());
        for (x, y) in [(30.5, 25.5), (50.2, 3.9), (0.1, 49.9)] {
            assert_eq!(dense.readout_at_view(x, y), tiled.readout_at_view(x, y));
        }
        assert_eq!(dense.readout_at_view(60.5, 1.0), None);
        dense.reset();
        assert_eq!(dense.work(), PaneWork::default());
        assert_eq!(dense.counts().unknown, g.len());
    }
}
