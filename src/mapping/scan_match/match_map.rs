//! What a scan matcher reads of a map, whatever its cell model or storage:
//! log odds cell by cell and row by row, and whether a cell was measured.
//!
//! The matcher itself (the search, the refinement) reads the map only
//! through this trait object, so it is compiled once, not once per cell
//! model and storage; what reads every cell of a scan's box stays generic
//! inside [`MatchMap::pool_pairs`], one call per scan.

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
    /// Pools the cells `[x0, x1) x [y0, y1)` (`cells`, all inside the map) two by
    /// two into `out`, a row-major array `nx` wide whose cell `(0, 0)`
    /// covers map cells `origin` and one past it in x and y: each of `out`'s
    /// cells becomes the most occupied of its own value and its map
    /// cells' log odds. `x0 - origin[0]` is even.
    fn pool_pairs(&self, cells: [usize; 4], origin: [i64; 2], nx: usize, out: &mut [f32]);
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

    fn pool_pairs(
        &self,
        [x0, y0, x1, y1]: [usize; 4],
        [ox, oy]: [i64; 2],
        nx: usize,
        out: &mut [f32],
    ) {
        let m = self.model();
        let unknown = m.log_odds(m.unknown());
        // One storage block (tile) at a time, a whole band of rows per
        // block looked up.
        let mut y = y0;
        while y < y1 {
            let mut x = x0;
            let mut next_y = y1;
            while x < x1 {
                let b = self.store().block(x, y);
                let bx1 = (b.x0 + b.width).min(x1);
                let by1 = (b.y0 + b.height).min(y1);
                next_y = next_y.min(by1);
                // Columns `x..bx1` of the block, two map cells to a
                // pooled cell (`x - ox` is even: the box and the blocks
                // start on even columns).
                let c0 = ((x as i64 - ox) >> 1) as usize;
                let c1 = ((bx1 as i64 - ox + 1) >> 1) as usize;
                for yy in y..by1 {
                    let row = ((yy as i64 - oy) >> 1) as usize * nx;
                    let pooled = &mut out[row + c0..row + c1];
                    match b.cells {
                        Some(cells) => {
                            let start = (yy - b.y0) * b.stride + (x - b.x0);
                            let run = &cells[start..start + (bx1 - x)];
                            let pairs = run.chunks_exact(2);
                            let odd = pairs.remainder().first().copied();
                            for (o, pair) in pooled.iter_mut().zip(pairs) {
                                *o = o.max(m.log_odds(pair[0]).max(m.log_odds(pair[1])));
                            }
                            if let (Some(c), Some(o)) = (odd, pooled.last_mut()) {
                                *o = o.max(m.log_odds(c));
                            }
                        }
                        None => {
                            for o in pooled.iter_mut() {
                                *o = o.max(unknown);
                            }
                        }
                    }
                }
                // (A block's rows past `next_y` are read again with the
                // next row of blocks: the maximum does not mind.)
                x = bx1;
            }
            y = next_y;
        }
    }
}
