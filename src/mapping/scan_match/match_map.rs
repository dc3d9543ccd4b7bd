//! What a scan matcher reads of a map, whatever its cell model or storage:
//! log odds cell by cell and row by row, and whether a cell was measured.
//!
//! The matcher itself (the search, the refinement) reads the map only
//! through this trait object, so it is compiled once, not once per cell
//! model and storage; what reads every cell of a scan's box stays generic
//! inside [`MatchMap::pool_pairs`], one call per scan.

use crate::geometry::GridGeometry;
use crate::grid::{larger, CellModel, Grid, Store};

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
    /// The log odds of the 3 x 3 cells around `(ix, iy)`, `[b][a]` those
    /// of cell `(ix + a - 1, iy + b - 1)`, `None` for a cell outside the
    /// map: a refinement's smooth reading of the map
    /// ([`crate::grid::sample::quadratic_bspline_of_patch`]), its storage
    /// found once for the nine cells where one block holds them all.
    fn log_odds_around(&self, ix: i64, iy: i64) -> [[Option<f32>; 3]; 3];
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

    fn log_odds_around(&self, ix: i64, iy: i64) -> [[Option<f32>; 3]; 3] {
        let m = self.model();
        let mut out = [[None; 3]; 3];
        let (w, h) = (self.geometry().width(), self.geometry().height());
        let (x0, y0) = (ix.wrapping_sub(1), iy.wrapping_sub(1));
        let whole = x0 >= 0 && y0 >= 0 && x0 < ix && y0 < iy;
        if whole && ((x0 + 2) as usize) < w && ((y0 + 2) as usize) < h {
            let (x0, y0) = (x0 as usize, y0 as usize);
            let block = self.store().block(x0, y0);
            if block.holds(x0 + 2, y0 + 2) {
                let unknown = m.log_odds(m.unknown());
                for (b, row) in out.iter_mut().enumerate() {
                    for (a, l) in row.iter_mut().enumerate() {
                        *l = Some(
                            block
                                .cell(x0 + a, y0 + b)
                                .map_or(unknown, |c| m.log_odds(c)),
                        );
                    }
                }
                return out;
            }
        }
        // Near a block's edge or the map's: cell by cell.
        for (b, row) in out.iter_mut().enumerate() {
            for (a, l) in row.iter_mut().enumerate() {
                let (x, y) = (
                    ix.saturating_add(a as i64 - 1),
                    iy.saturating_add(b as i64 - 1),
                );
                if x >= 0 && y >= 0 {
                    *l = self.log_odds_at(x as usize, y as usize);
                }
            }
        }
        out
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
                                *o = larger(*o, larger(m.log_odds(pair[0]), m.log_odds(pair[1])));
                            }
                            if let (Some(c), Some(o)) = (odd, pooled.last_mut()) {
                                *o = larger(*o, m.log_odds(c));
                            }
                        }
                        None => {
                            for o in pooled.iter_mut() {
                                *o = larger(*o, unknown);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::grid::{FilterSettings, LogOddsGrid, TiledGrid};

    /// The nine cells around any cell read at once are the nine read one
    /// by one: inside a tile, across tiles' edges, beside a tile never
    /// touched, at the map's edges and past them, dense or tiled.
    #[test]
    fn the_cells_around_a_cell_are_read_as_each_alone() {
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 9.0,
        };
        let (w, h) = (150, 70);
        let mut dense =
            LogOddsGrid::new(GridGeometry::new(w, h, 0.1, 0.0, 0.0).unwrap(), settings).unwrap();
        let sparse = GridGeometry::sparse(w, h, 0.1, 0.0, 0.0).unwrap();
        let mut tiled = TiledGrid::new(sparse, settings, 1 << 20).unwrap();
        // Cells written everywhere but in the tile from column 64, row 0.
        for iy in 0..h {
            for ix in (0..w).filter(|&ix| !(64..128).contains(&ix) || iy >= 64) {
                let e = ((ix * 7 + iy * 13) % 11) as f32 * 0.3 - 1.5;
                dense.apply_at(ix, iy, e);
                tiled.apply_at(ix, iy, e);
            }
        }
        let grids: [&dyn MatchMap; 2] = [&dense, &tiled];
        for grid in grids {
            for iy in -2..h as i64 + 2 {
                for ix in -2..w as i64 + 2 {
                    let around = grid.log_odds_around(ix, iy);
                    for (b, row) in around.iter().enumerate() {
                        for (a, &l) in row.iter().enumerate() {
                            let (x, y) = (ix + a as i64 - 1, iy + b as i64 - 1);
                            let alone = if x < 0 || y < 0 {
                                None
                            } else {
                                grid.log_odds_at(x as usize, y as usize)
                            };
                            assert_eq!(l, alone, "({x}, {y}) around ({ix}, {iy})");
                        }
                    }
                }
            }
            assert_eq!(grid.log_odds_around(i64::MIN, i64::MAX), [[None; 3]; 3]);
        }
    }
}
