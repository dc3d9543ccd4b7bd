//! A log-odds map whose memory follows the area the beams saw (SPEC §11,
//! "any extent"): the map's extent is cut into square tiles of
//! [`TILE_SIDE`] cells, and a tile is allocated the first time a beam gives
//! one of its cells evidence. A tile never touched holds the prior
//! everywhere, and reads (and exports) as unknown.
//!
//! A campus-sized log at 5 cm spans tens of millions of cells of bounding
//! box, while its corridors cover a fraction of them; the dense
//! [`super::LogOddsGrid`] (the chapter's widgets and workload W1) keeps its
//! single array and its speed.
//!
//! Two budgets, both stated in the errors that refuse a map: the extent
//! (its cell count bounds the exported image, one byte per cell) and the
//! cells allocated in tiles (eight bytes each: log odds and update count).

use crate::error::Result;

use crate::geometry::GridGeometry;

use super::readout::CellReadout;
use super::{logit, probability, FilterSettings, LogOddsGrid};

/// Cells along a tile's side (a power of two: a cell's tile and its place
/// in it are shifts and masks).
pub const TILE_SIDE: usize = 64;
const TILE_SHIFT: u32 = TILE_SIDE.trailing_zeros();
const TILE_MASK: usize = TILE_SIDE - 1;
/// Cells per tile.
pub const TILE_CELLS: usize = TILE_SIDE * TILE_SIDE;
/// Bytes a tile holds: an `f32` of log odds and a `u32` update count per cell.
pub const TILE_BYTES: usize = TILE_CELLS * 8;

/// The default budget of allocated cells (4,096 tiles, 128 MiB): what a
/// browser tab holds comfortably beside the rest of the page.
pub const DEFAULT_TILE_BUDGET_CELLS: usize = 1 << 24;

const NO_TILE: u32 = u32::MAX;

/// Tiles along x and y of a map's extent.
pub fn tiles_of(extent: &GridGeometry) -> (usize, usize) {
    (
        extent.width().div_ceil(TILE_SIDE),
        extent.height().div_ceil(TILE_SIDE),
    )
}

/// `n` bytes in MiB, one decimal.
pub fn mebibytes(n: u128) -> String {
    format!("{:.1} MiB", n as f64 / (1u64 << 20) as f64)
}

/// One tile's cells, row-major from its bottom row.
#[derive(Debug, Clone, PartialEq)]
struct Tile {
    log_odds: Box<[f32]>,
    updates: Box<[u32]>,
}

/// The tiled log-odds map: Table 9.1's filter per cell, as in
/// [`super::LogOddsGrid`], with tiles allocated on first touch.
#[derive(Debug, Clone, PartialEq)]
pub struct TiledGrid {
    extent: GridGeometry,
    tiles_x: usize,
    /// Per tile of the extent, its place in `tiles`, or [`NO_TILE`].
    index: Vec<u32>,
    tiles: Vec<Tile>,
    /// Most tiles that may be allocated.
    max_tiles: usize,
    /// Set when a cell could not get a tile: its evidence was dropped.
    refused: bool,
    l0: f32,
    clamp: f32,
}

impl TiledGrid {
    /// A fresh map, every cell at the prior, no tile allocated; at most
    /// `budget_cells` cells (rounded down to whole tiles, at least one) will
    /// ever be allocated.
    pub fn new(
        extent: GridGeometry,
        settings: FilterSettings,
        budget_cells: usize,
    ) -> Result<Self> {
        settings.validate()?;
        let (tx, ty) = tiles_of(&extent);
        Ok(Self {
            extent,
            tiles_x: tx,
            index: vec![NO_TILE; tx * ty],
            tiles: Vec::new(),
            max_tiles: (budget_cells / TILE_CELLS).clamp(1, NO_TILE as usize - 1),
            refused: false,
            l0: logit(settings.prior) as f32,
            clamp: settings.clamp as f32,
        })
    }

    pub fn extent(&self) -> &GridGeometry {
        &self.extent
    }
    pub fn l0(&self) -> f32 {
        self.l0
    }
    pub fn clamp(&self) -> f32 {
        self.clamp
    }
    /// Tiles allocated so far.
    pub fn tiles_allocated(&self) -> usize {
        self.tiles.len()
    }
    /// Cells allocated so far (whole tiles).
    pub fn cells_allocated(&self) -> usize {
        self.tiles.len() * TILE_CELLS
    }
    /// Bytes the allocated tiles hold.
    pub fn bytes_allocated(&self) -> usize {
        self.tiles.len() * TILE_BYTES
    }
    /// Most tiles the budget allows.
    pub fn max_tiles(&self) -> usize {
        self.max_tiles
    }
    /// True once a cell's evidence was dropped for want of a tile.
    pub fn refused(&self) -> bool {
        self.refused
    }

    /// Puts every cell back to the prior and frees every tile.
    pub fn reset(&mut self) {
        self.index.fill(NO_TILE);
        self.tiles = Vec::new();
        self.refused = false;
    }

    #[inline(always)]
    fn tile_of(&self, ix: usize, iy: usize) -> usize {
        (iy >> TILE_SHIFT) * self.tiles_x + (ix >> TILE_SHIFT)
    }

    #[inline(always)]
    fn offset(ix: usize, iy: usize) -> usize {
        ((iy & TILE_MASK) << TILE_SHIFT) | (ix & TILE_MASK)
    }

    /// Log odds of cell `(ix, iy)` (the prior where no tile is), `None`
    /// outside the extent.
    #[inline]
    pub fn log_odds_at(&self, ix: usize, iy: usize) -> Option<f32> {
        if ix >= self.extent.width() || iy >= self.extent.height() {
            return None;
        }
        Some(match self.index[self.tile_of(ix, iy)] {
            NO_TILE => self.l0,
            t => self.tiles[t as usize].log_odds[Self::offset(ix, iy)],
        })
    }

    /// Updates cell `(ix, iy)` received, `None` outside the extent.
    pub fn updates_at(&self, ix: usize, iy: usize) -> Option<u32> {
        if ix >= self.extent.width() || iy >= self.extent.height() {
            return None;
        }
        Some(match self.index[self.tile_of(ix, iy)] {
            NO_TILE => 0,
            t => self.tiles[t as usize].updates[Self::offset(ix, iy)],
        })
    }

    /// The cells of tile `(tx, ty)` (its log odds, row-major from the
    /// tile's bottom row, [`TILE_SIDE`] to a row), or `None` where no tile
    /// was allocated (every cell at the prior).
    #[inline]
    pub fn tile_log_odds(&self, tx: usize, ty: usize) -> Option<&[f32]> {
        match self.index.get(ty * self.tiles_x + tx) {
            Some(&t) if t != NO_TILE => Some(&self.tiles[t as usize].log_odds),
            _ => None,
        }
    }

    /// The log odds of every allocated tile (cells of edge tiles beyond the
    /// extent stay at the prior: no beam reaches them).
    pub fn allocated_log_odds(&self) -> impl Iterator<Item = &[f32]> {
        self.tiles.iter().map(|t| &t.log_odds[..])
    }

    /// The tile slot of cell `(ix, iy)` (inside the extent), allocated on
    /// first touch; `None` (and [`Self::refused`] set) past the budget.
    #[inline(always)]
    fn slot(&mut self, ix: usize, iy: usize) -> Option<(&mut f32, &mut u32)> {
        let k = self.tile_of(ix, iy);
        let mut t = self.index[k];
        if t == NO_TILE {
            if self.tiles.len() >= self.max_tiles {
                self.refused = true;
                return None;
            }
            t = self.tiles.len() as u32;
            self.tiles.push(Tile {
                log_odds: vec![self.l0; TILE_CELLS].into_boxed_slice(),
                updates: vec![0; TILE_CELLS].into_boxed_slice(),
            });
            self.index[k] = t;
        }
        let o = Self::offset(ix, iy);
        let tile = &mut self.tiles[t as usize];
        Some((&mut tile.log_odds[o], &mut tile.updates[o]))
    }

    /// [`super::LogOddsGrid::apply`] for cell `(ix, iy)`, inside the extent.
    #[inline(always)]
    pub fn apply(&mut self, ix: usize, iy: usize, evidence: f32) {
        let c = self.clamp;
        if let Some((l, n)) = self.slot(ix, iy) {
            let v = *l + evidence;
            *l = if v > c {
                c
            } else if v < -c {
                -c
            } else {
                v
            };
            *n += 1;
        }
    }

    /// [`Self::apply`] for evidence `>= 0` (only the upper clamp binds).
    #[inline(always)]
    pub fn raise(&mut self, ix: usize, iy: usize, evidence: f32) {
        let c = self.clamp;
        if let Some((l, n)) = self.slot(ix, iy) {
            let v = *l + evidence;
            *l = if v > c { c } else { v };
            *n += 1;
        }
    }

    /// [`Self::apply`] for evidence `<= 0` (only the lower clamp binds).
    #[inline(always)]
    pub fn lower(&mut self, ix: usize, iy: usize, evidence: f32) {
        let c = -self.clamp;
        if let Some((l, n)) = self.slot(ix, iy) {
            let v = *l + evidence;
            *l = if v < c { c } else { v };
            *n += 1;
        }
    }

    /// Cells `p > occupied_above` and `p < free_below`, over the whole
    /// extent (a cell still at the prior is neither, whatever the
    /// thresholds; every cell of an unallocated tile is at the prior).
    pub fn count_between(&self, occupied_above: f64, free_below: f64) -> (usize, usize) {
        let (occ_l, free_l) = (logit(occupied_above) as f32, logit(free_below) as f32);
        let l0 = self.l0;
        let (mut occupied, mut free) = (0, 0);
        for t in &self.tiles {
            for &l in t.log_odds.iter() {
                let known = l != l0;
                occupied += (known & (l > occ_l)) as usize;
                free += (known & (l < free_l)) as usize;
            }
        }
        (occupied, free)
    }
}

impl TiledGrid {
    /// Cell `(ix, iy)` for a hover readout, `None` outside the extent.
    pub fn readout_at_cell(&self, ix: usize, iy: usize) -> Option<CellReadout> {
        let l = self.log_odds_at(ix, iy)?;
        let (x, y) = self.extent.cell_center(ix, iy);
        Some(CellReadout {
            ix,
            iy,
            x,
            y,
            l: l as f64,
            p: probability(l as f64),
            updates: self.updates_at(ix, iy)?,
            unknown: l == self.l0,
        })
    }

    /// The same map as a dense [`LogOddsGrid`] (for an extent the dense
    /// grid can hold: at most [`crate::geometry::MAX_CELLS`] cells).
    pub fn to_dense(&self) -> Result<LogOddsGrid> {
        let e = &self.extent;
        let geometry = GridGeometry::new(
            e.width(),
            e.height(),
            e.resolution(),
            e.origin()[0],
            e.origin()[1],
        )?;
        let mut log_odds = vec![self.l0; geometry.len()];
        let mut updates = vec![0; geometry.len()];
        for iy in 0..e.height() {
            for ix in 0..e.width() {
                if let Some(t) = self.tile_log_odds(ix >> TILE_SHIFT, iy >> TILE_SHIFT) {
                    let i = geometry.index(ix, iy);
                    log_odds[i] = t[Self::offset(ix, iy)];
                    updates[i] = self.updates_at(ix, iy).unwrap_or(0);
                }
            }
        }
        Ok(LogOddsGrid {
            geometry,
            log_odds,
            updates,
            l0: self.l0,
            clamp: self.clamp,
        })
    }
}

/// What a map of `extent` would need beyond `budget_cells`, in words: the
/// tiles the beams reach (`needed_tiles`), their cells and bytes.
pub fn budget_message(extent: &GridGeometry, needed_tiles: usize, budget_cells: usize) -> String {
    let need = needed_tiles as u128 * TILE_CELLS as u128;
    format!(
        "the beams of this log reach {needed_tiles} tiles of {TILE_SIDE} x {TILE_SIDE} cells: {need} cells ({}) \
         of a {} x {} bounding box, over the budget of {budget_cells} cells ({}); choose a coarser resolution",
        mebibytes(need * 8),
        extent.width(),
        extent.height(),
        mebibytes(budget_cells as u128 * 8),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(w: usize, h: usize, budget: usize) -> TiledGrid {
        TiledGrid::new(
            GridGeometry::sparse(w, h, 0.05, -1.0, 2.0).unwrap(),
            FilterSettings {
                prior: 0.5,
                clamp: 2.0,
            },
            budget,
        )
        .unwrap()
    }

    #[test]
    fn tiled_cells_read_the_prior_until_touched_and_allocate_one_tile_each() {
        let mut g = grid(200, 130, 1 << 20);
        assert_eq!(tiles_of(g.extent()), (4, 3));
        assert_eq!(g.log_odds_at(199, 129), Some(0.0));
        assert_eq!(g.log_odds_at(200, 0), None);
        assert_eq!(g.tiles_allocated(), 0);
        g.raise(150, 100, 0.85);
        g.lower(151, 100, -1.5);
        g.apply(0, 0, 5.0);
        assert_eq!(g.tiles_allocated(), 2);
        assert_eq!(g.log_odds_at(150, 100), Some(0.85));
        assert_eq!(g.log_odds_at(151, 100), Some(-1.5));
        assert_eq!(g.log_odds_at(0, 0), Some(2.0), "clamped");
        assert_eq!(g.updates_at(150, 100), Some(1));
        assert_eq!(g.updates_at(149, 100), Some(0));
        assert_eq!(g.count_between(0.65, 0.196), (2, 1));
        g.reset();
        assert_eq!((g.tiles_allocated(), g.log_odds_at(0, 0)), (0, Some(0.0)));
    }

    #[test]
    fn tiled_budget_drops_evidence_past_it_and_says_so() {
        let mut g = grid(200, 130, TILE_CELLS);
        g.raise(0, 0, 1.0);
        assert!(!g.refused());
        g.raise(100, 0, 1.0);
        assert!(g.refused());
        assert_eq!(g.tiles_allocated(), 1);
        assert_eq!(g.log_odds_at(100, 0), Some(0.0));
        let msg = budget_message(g.extent(), 5, TILE_CELLS);
        assert!(
            msg.contains("5 tiles") && msg.contains("20480 cells") && msg.contains("0.2 MiB"),
            "{msg}"
        );
    }

    #[test]
    fn tiled_extent_refuses_what_its_export_cannot_hold_naming_the_size() {
        let e = GridGeometry::sparse(20_000, 20_000, 0.05, 0.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("20000 x 20000 = 400000000 cells") && e.contains("381.5 MiB"),
            "{e}"
        );
        assert!(GridGeometry::sparse(5009, 4906, 0.05, 0.0, 0.0).is_ok());
        assert!(GridGeometry::sparse(0, 3, 0.05, 0.0, 0.0).is_err());
        assert!(GridGeometry::sparse(3, 3, f64::NAN, 0.0, 0.0).is_err());
    }
}
