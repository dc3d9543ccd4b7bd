//! What a scan matcher reads of a map, whatever its cell model or storage:
//! log odds cell by cell and row by row, and whether a cell was measured.
//!
//! The matcher itself (the pooling, the search, the refinement) reads the
//! map only through this trait object, so it is compiled once, not once
//! per cell model and storage; the per-cell conversion stays generic
//! inside [`MatchMap::row_log_odds`], one call per row of a scan's box.

use crate::geometry::GridGeometry;
use crate::grid::{CellModel, Grid, Store};

/// A map a scan can be matched against: what a pose source reads of the
/// map built so far.
pub trait MatchMap {
    /// The map's limits.
    fn geometry(&self) -> &GridGeometry;
    /// The log odds an unknown cell holds.
    fn unknown_log_odds(&self) -> f32;
    /// Cell `(ix, iy)`'s log odds, `None` outside the map (a cell no tile
    /// holds reads as unknown).
    fn log_odds_at(&self, ix: usize, iy: usize) -> Option<f32>;
    /// Whether cell `(ix, iy)` was measured (`false` outside the map).
    fn is_measured(&self, ix: usize, iy: usize) -> bool;
    /// The log odds of cells `x0..x1` of row `y` (all inside the map)
    /// into `out`, cleared first.
    fn row_log_odds(&self, y: usize, x0: usize, x1: usize, out: &mut Vec<f32>);
}

impl<M: CellModel, S: Store<M::Cell>> MatchMap for Grid<M, S> {
    fn geometry(&self) -> &GridGeometry {
        Grid::geometry(self)
    }

    fn unknown_log_odds(&self) -> f32 {
        let m = self.model();
        m.log_odds(m.unknown())
    }

    fn log_odds_at(&self, ix: usize, iy: usize) -> Option<f32> {
        let m = self.model();
        self.cell_at(ix, iy).map(|c| m.log_odds(c))
    }

    fn is_measured(&self, ix: usize, iy: usize) -> bool {
        let m = self.model();
        self.cell_at(ix, iy).is_some_and(|c| !m.is_unknown(c))
    }

    fn row_log_odds(&self, y: usize, x0: usize, x1: usize, out: &mut Vec<f32>) {
        out.clear();
        let m = self.model();
        let unknown = m.log_odds(m.unknown());
        // One storage block (tile) at a time.
        let mut x = x0;
        while x < x1 {
            let b = self.store().block(x, y);
            let bx1 = (b.x0 + b.width).min(x1);
            match b.cells {
                Some(cells) => {
                    let start = (y - b.y0) * b.stride + (x - b.x0);
                    out.extend(
                        cells[start..start + (bx1 - x)]
                            .iter()
                            .map(|&c| m.log_odds(c)),
                    );
                }
                None => out.extend(std::iter::repeat_n(unknown, bx1 - x)),
            }
            x = bx1;
        }
    }
}
