//! Where a map's cells live: one array over the whole extent ([`Dense`],
//! the chapter's widgets and workload W1), or square tiles allocated the
//! first time a beam gives one of their cells evidence ([`Tiled`], real logs
//! of any extent: memory follows the area the beams saw, not the bounding
//! box).
//!
//! Storage knows nothing of what a cell believes: it holds one value of the
//! cell model's type per cell ([`super::cell::CellModel::Cell`]) and how
//! many updates each cell received, and every consumer of a map (the
//! traversal's update pass, the renderers, the readout, the counts, the
//! export) reads and writes through the one [`Store`] interface. A cell no
//! storage holds (a tile never touched) reads as the model's unknown cell
//! with no update.
//!
//! The update count is kept beside the cell ([`StoredCell::Updates`]: a
//! `u32`) unless the cell counts its updates itself, as hit counting's
//! visits do ([`InCell`], no bytes at all): a real log's map then takes
//! half the memory.
//!
//! Cells are addressed by `(ix, iy)`, row 0 at the bottom. The traversal
//! gathers a scan's verdicts in a *window* of the map (the whole map for a
//! dense store; a square around the sensor for a tiled one, see
//! [`Window`]) and hands the store window indices, which a dense store
//! uses as they are.

use crate::error::{OccError, Result};
use crate::geometry::GridGeometry;

/// Cells along a tile's side (a power of two: a cell's tile and its place
/// in it are shifts and masks).
pub const TILE_SIDE: usize = 64;
const TILE_SHIFT: u32 = TILE_SIDE.trailing_zeros();
const TILE_MASK: usize = TILE_SIDE - 1;
/// Cells per tile.
pub const TILE_CELLS: usize = TILE_SIDE * TILE_SIDE;

/// The default budget of allocated cells of a tiled map (4,096 tiles):
/// what a browser tab holds comfortably beside the rest of the page.
pub const DEFAULT_TILE_BUDGET_CELLS: usize = 1 << 24;

const NO_TILE: u32 = u32::MAX;

/// How a cell's updates are counted beside it: one more per verdict.
pub trait Tally: Copy + Default + PartialEq + std::fmt::Debug {
    /// One more update.
    fn add_one(&mut self);
}

/// An update count of its own beside the cell.
impl Tally for u32 {
    #[inline(always)]
    fn add_one(&mut self) {
        *self += 1;
    }
}

/// Nothing beside the cell: the cell counts its updates itself. Takes no
/// memory (a tile's counts of it allocate nothing) and counting it is no
/// instruction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InCell;

impl Tally for InCell {
    #[inline(always)]
    fn add_one(&mut self) {}
}

/// What a store holds per cell: the cell model's value, and how its
/// updates are counted.
pub trait StoredCell: Copy + PartialEq + std::fmt::Debug {
    /// What is kept beside each cell to count its updates.
    type Updates: Tally;
    /// The updates the cell received, from the cell and what was kept
    /// beside it.
    fn updates(self, beside: Self::Updates) -> u32;
}

/// A plain number (log odds, an index into a table of odds) counts its
/// updates beside it.
macro_rules! counted_beside {
    ($($t:ty),*) => {$(
        impl StoredCell for $t {
            type Updates = u32;
            #[inline(always)]
            fn updates(self, beside: u32) -> u32 {
                beside
            }
        }
    )*};
}
counted_beside!(f32, u8, u16);

/// Part of the map in which a scan's verdicts are gathered: `stride`
/// cells per row, its first cell at `(x0, y0)`. Window index `w` is cell
/// `(x0 + w % stride, y0 + w / stride)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub x0: usize,
    pub y0: usize,
    pub stride: usize,
    pub rows: usize,
}

impl Window {
    /// Cells in the window.
    pub fn len(&self) -> usize {
        self.stride * self.rows
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The window covering a whole map.
    pub fn whole(geometry: &GridGeometry) -> Self {
        Self {
            x0: 0,
            y0: 0,
            stride: geometry.width(),
            rows: geometry.height(),
        }
    }
}

/// A run of cells along one row of the map: the cells from column `x0`
/// on, or `None` where no storage holds them (every cell unknown, no
/// update). Every reader that walks a whole map walks it in such runs, so
/// that a tile never touched costs one test, not one per cell.
pub struct RowRun<'a, C: StoredCell> {
    pub x0: usize,
    pub len: usize,
    pub cells: Option<(&'a [C], &'a [C::Updates])>,
}

/// The cells holding `(ix, iy)` as one contiguous block: the block's
/// cells and update counts, row-major from its bottom row, `stride` to a
/// row, its first cell at `(x0, y0)`, `width x height` of them inside the
/// map. A reader that needs many neighbouring cells (a renderer sampling
/// several cells per pixel) looks them up in the block.
pub struct Block<'a, C> {
    pub x0: usize,
    pub y0: usize,
    pub width: usize,
    pub height: usize,
    pub stride: usize,
    pub cells: Option<&'a [C]>,
}

impl<C: Copy> Block<'_, C> {
    /// True when `(ix, iy)` lies in the block.
    #[inline]
    pub fn holds(&self, ix: usize, iy: usize) -> bool {
        ix.wrapping_sub(self.x0) < self.width && iy.wrapping_sub(self.y0) < self.height
    }
    /// The cell `(ix, iy)` of the block (`None` for an unallocated block).
    #[inline]
    pub fn cell(&self, ix: usize, iy: usize) -> Option<C> {
        self.cells
            .map(|c| c[(iy - self.y0) * self.stride + (ix - self.x0)])
    }
}

/// The cells of a window, borrowed for one scan's update pass.
pub trait WindowCells<C: StoredCell> {
    /// Cell `w` of the window for an update, allocating its storage on
    /// first touch; `None` (and the store's `refused` set) past the budget.
    fn slot(&mut self, w: usize) -> Option<(&mut C, &mut C::Updates)>;
}

/// A dense map's cells for an update pass: its window is the whole map,
/// and a window index is the cell's index. Both arrays have the same
/// length, and the compiler sees it: an index is checked once for both.
pub struct DenseCells<'a, C: StoredCell> {
    cells: &'a mut [C],
    updates: &'a mut [C::Updates],
}

impl<C: StoredCell> WindowCells<C> for DenseCells<'_, C> {
    #[inline(always)]
    fn slot(&mut self, w: usize) -> Option<(&mut C, &mut C::Updates)> {
        Some((&mut self.cells[w], &mut self.updates[w]))
    }
}

/// A tiled map's cells for an update pass: window indices become cells,
/// and cells their tiles.
pub struct TiledCells<'a, C: StoredCell> {
    store: &'a mut Tiled<C>,
    window: Window,
    unknown: C,
}

impl<C: StoredCell> WindowCells<C> for TiledCells<'_, C> {
    #[inline(always)]
    fn slot(&mut self, w: usize) -> Option<(&mut C, &mut C::Updates)> {
        let win = &self.window;
        let (ix, iy) = (win.x0 + w % win.stride, win.y0 + w / win.stride);
        self.store.slot(ix, iy, self.unknown)
    }
}

/// Where cells live. `C` is the cell model's cell; every cell also counts
/// its updates (the hover readout's "updated n times"), beside it or in it
/// ([`StoredCell`]).
pub trait Store<C: StoredCell>: Clone + std::fmt::Debug + PartialEq {
    /// True when the traversal should gather a scan in a window around the
    /// sensor rather than over the whole map (a map too large to keep a
    /// scratch slot per cell).
    const WINDOWED: bool;

    /// Every cell unknown (`unknown`), within `budget_cells` allocated
    /// cells where the store allocates.
    fn fresh(geometry: &GridGeometry, unknown: C, budget_cells: usize) -> Result<Self>;

    /// Cell `(ix, iy)` (inside the map) and its updates; `None` where no
    /// storage holds it (unknown, never updated).
    fn get(&self, ix: usize, iy: usize) -> Option<(C, u32)>;

    /// The cells of `window`, borrowed for a scan's update pass.
    type Writer<'a>: WindowCells<C>
    where
        Self: 'a;

    /// Borrows the cells of `window` for an update pass; `unknown` is what
    /// a newly allocated cell holds.
    fn window_cells(&mut self, window: Window, unknown: C) -> Self::Writer<'_>;

    /// Cell `(ix, iy)` for an update, allocating its storage on first
    /// touch; `None` outside the map, or (and [`Self::refused`] set) past
    /// the budget.
    fn slot(&mut self, ix: usize, iy: usize, unknown: C) -> Option<(&mut C, &mut C::Updates)>;

    /// The cells of row `iy` from column `ix` (a multiple of
    /// [`TILE_SIDE`]) to the east edge of its tile (or of the map), and
    /// their updates, for an update pass, allocating their storage on
    /// first touch; `None` outside the map, or (and [`Self::refused`] set)
    /// past the budget.
    fn tile_row(
        &mut self,
        ix: usize,
        iy: usize,
        unknown: C,
    ) -> Option<(&mut [C], &mut [C::Updates])>;

    /// Row `iy` of the map in runs, west to east.
    fn row_runs(&self, iy: usize, f: impl FnMut(RowRun<'_, C>));

    /// The block holding `(ix, iy)` (inside the map).
    fn block(&self, ix: usize, iy: usize) -> Block<'_, C>;

    /// Every allocated cell, in no particular order (the counts and the
    /// entropy); cells outside it are unknown.
    fn allocated(&self, f: impl FnMut(&[C]));

    /// Cells with storage.
    fn cells_allocated(&self) -> usize;

    /// True once a cell's evidence was dropped for want of storage.
    fn refused(&self) -> bool;

    /// Every cell back to `unknown`, every tile freed.
    fn reset(&mut self, unknown: C);

    /// Hands each of `cells` (`(ix, iy, item)`, in order) to `f` with its
    /// slot for an update, as [`Self::slot`] gives it (`None` outside the
    /// map or past the budget): one scan's update pass. A store may find a
    /// run of cells in one block of storage once for the run.
    #[inline(always)]
    fn update_each<I>(
        &mut self,
        cells: impl Iterator<Item = (usize, usize, I)>,
        unknown: C,
        mut f: impl FnMut(I, Option<(&mut C, &mut C::Updates)>),
    ) {
        for (ix, iy, item) in cells {
            f(item, self.slot(ix, iy, unknown));
        }
    }
}

/// One array over the whole map.
#[derive(Debug, Clone, PartialEq)]
pub struct Dense<C: StoredCell> {
    width: usize,
    height: usize,
    cells: Vec<C>,
    updates: Vec<C::Updates>,
}

impl<C: StoredCell> Dense<C> {
    /// Every cell, row-major from the bottom row.
    pub fn cells(&self) -> &[C] {
        &self.cells
    }
    /// What is kept beside every cell to count its updates.
    pub fn updates(&self) -> &[C::Updates] {
        &self.updates
    }
    /// Both arrays, for a caller that updates many cells by index; the
    /// update counts are cut to the cells' length so that the compiler
    /// checks one index for both.
    #[inline(always)]
    pub fn cells_mut(&mut self) -> (&mut [C], &mut [C::Updates]) {
        let n = self.cells.len();
        (&mut self.cells, &mut self.updates[..n])
    }
}

impl<C: StoredCell> Store<C> for Dense<C> {
    const WINDOWED: bool = false;

    fn fresh(geometry: &GridGeometry, unknown: C, _budget_cells: usize) -> Result<Self> {
        if geometry.len() > crate::geometry::MAX_CELLS {
            return Err(OccError::State(format!(
                "a dense map holds at most {} cells, not {} x {}",
                crate::geometry::MAX_CELLS,
                geometry.width(),
                geometry.height()
            )));
        }
        Ok(Self {
            width: geometry.width(),
            height: geometry.height(),
            cells: vec![unknown; geometry.len()],
            updates: vec![C::Updates::default(); geometry.len()],
        })
    }

    #[inline]
    fn get(&self, ix: usize, iy: usize) -> Option<(C, u32)> {
        let i = iy * self.width + ix;
        let c = *self.cells.get(i)?;
        Some((c, c.updates(*self.updates.get(i)?)))
    }

    type Writer<'a>
        = DenseCells<'a, C>
    where
        Self: 'a;

    /// (A dense map's window is the whole map: `w` is the cell's index.)
    #[inline(always)]
    fn window_cells(&mut self, _: Window, _: C) -> DenseCells<'_, C> {
        let (cells, updates) = self.cells_mut();
        DenseCells { cells, updates }
    }

    #[inline]
    fn tile_row(&mut self, ix: usize, iy: usize, _: C) -> Option<(&mut [C], &mut [C::Updates])> {
        if ix >= self.width || iy >= self.height {
            return None;
        }
        let len = TILE_SIDE.min(self.width - ix);
        let at = iy * self.width + ix;
        Some((
            &mut self.cells[at..at + len],
            &mut self.updates[at..at + len],
        ))
    }

    fn slot(&mut self, ix: usize, iy: usize, _: C) -> Option<(&mut C, &mut C::Updates)> {
        let i = iy * self.width + ix;
        let (cells, updates) = self.cells_mut();
        Some((cells.get_mut(i)?, updates.get_mut(i)?))
    }

    fn row_runs(&self, iy: usize, mut f: impl FnMut(RowRun<'_, C>)) {
        let w = self.width;
        if iy < self.height {
            let r = iy * w..(iy + 1) * w;
            f(RowRun {
                x0: 0,
                len: w,
                cells: Some((&self.cells[r.clone()], &self.updates[r])),
            });
        }
    }

    fn block(&self, _: usize, _: usize) -> Block<'_, C> {
        Block {
            x0: 0,
            y0: 0,
            width: self.width,
            height: self.height,
            stride: self.width,
            cells: Some(&self.cells),
        }
    }

    fn allocated(&self, mut f: impl FnMut(&[C])) {
        f(&self.cells)
    }

    fn cells_allocated(&self) -> usize {
        self.cells.len()
    }

    fn refused(&self) -> bool {
        false
    }

    fn reset(&mut self, unknown: C) {
        self.cells.fill(unknown);
        self.updates.fill(C::Updates::default());
    }
}

/// One tile's cells, row-major from its bottom row.
#[derive(Debug, Clone)]
struct Tile<C: StoredCell> {
    cells: Box<[C]>,
    updates: Box<[C::Updates]>,
    /// True once written since the last [`Tiled::take_touched`].
    touched: bool,
}

/// Square tiles of [`TILE_SIDE`] cells, allocated on first touch, at most
/// a budget of them.
#[derive(Debug, Clone)]
pub struct Tiled<C: StoredCell> {
    width: usize,
    height: usize,
    tiles_x: usize,
    /// Per tile of the map, its place in `tiles`, or [`NO_TILE`].
    index: Vec<u32>,
    tiles: Vec<Tile<C>>,
    /// Most tiles that may be allocated.
    max_tiles: usize,
    refused: bool,
    /// The tiles written since the last [`Self::take_touched`], by their
    /// place in `tiles`: what a count kept per tile recounts
    /// ([`super::stats::TileTally`]).
    touched: Vec<u32>,
    /// Resets so far: a count kept per tile starts again after one.
    resets: u64,
}

/// Two stores are equal when they hold the same cells in the same tiles
/// (which tiles were written since a count was kept is no part of a map).
impl<C: StoredCell> PartialEq for Tiled<C> {
    fn eq(&self, other: &Self) -> bool {
        let same_tile = |(a, b): (&Tile<C>, &Tile<C>)| a.cells == b.cells && a.updates == b.updates;
        (
            self.width,
            self.height,
            &self.index,
            self.max_tiles,
            self.refused,
        ) == (
            other.width,
            other.height,
            &other.index,
            other.max_tiles,
            other.refused,
        ) && self.tiles.len() == other.tiles.len()
            && self.tiles.iter().zip(&other.tiles).all(same_tile)
    }
}

/// Tiles along x and y of a map.
pub fn tiles_of(geometry: &GridGeometry) -> (usize, usize) {
    (
        geometry.width().div_ceil(TILE_SIDE),
        geometry.height().div_ceil(TILE_SIDE),
    )
}

impl<C: StoredCell> Tiled<C> {
    #[inline(always)]
    fn tile_of(&self, ix: usize, iy: usize) -> usize {
        (iy >> TILE_SHIFT) * self.tiles_x + (ix >> TILE_SHIFT)
    }

    #[inline(always)]
    fn offset(ix: usize, iy: usize) -> usize {
        ((iy & TILE_MASK) << TILE_SHIFT) | (ix & TILE_MASK)
    }

    /// The cells and update counts of tile `k` (row-major on the grid of
    /// tiles), allocated on first touch; `None` (and `refused` set) past
    /// the budget.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn tile_cells(
        &mut self,
        k: usize,
        unknown: C,
    ) -> Option<(&mut [C; TILE_CELLS], &mut [C::Updates; TILE_CELLS])> {
        let tile = self.written_tile(k, unknown)?;
        Some((
            (&mut tile.cells[..]).try_into().ok()?,
            (&mut tile.updates[..]).try_into().ok()?,
        ))
    }

    /// Tile `k` about to be written: allocated on first touch (`None`, and
    /// `refused` set, past the budget) and marked touched, so that the
    /// counts kept per tile recount it.
    #[inline(always)]
    fn written_tile(&mut self, k: usize, unknown: C) -> Option<&mut Tile<C>> {
        let mut t = *self.index.get(k)?;
        if t == NO_TILE {
            if self.tiles.len() >= self.max_tiles {
                self.refused = true;
                return None;
            }
            t = self.tiles.len() as u32;
            self.tiles.push(Tile {
                cells: vec![unknown; TILE_CELLS].into_boxed_slice(),
                updates: vec![C::Updates::default(); TILE_CELLS].into_boxed_slice(),
                touched: false,
            });
            self.index[k] = t;
        }
        let tile = self.tiles.get_mut(t as usize)?;
        if !tile.touched {
            tile.touched = true;
            self.touched.push(t);
        }
        Some(tile)
    }

    /// Tiles allocated so far.
    pub fn tiles_allocated(&self) -> usize {
        self.tiles.len()
    }
    /// Most tiles the budget allows.
    pub fn max_tiles(&self) -> usize {
        self.max_tiles
    }

    /// The tiles written since the last [`Self::take_touched`], by their
    /// place among the allocated tiles ([`Self::tile`]).
    pub fn touched(&self) -> &[u32] {
        &self.touched
    }

    /// The cells of allocated tile `t` (row-major from its bottom row,
    /// [`TILE_CELLS`] of them, the ones beyond the map's edge unknown).
    pub fn tile(&self, t: usize) -> Option<&[C]> {
        Some(&self.tiles.get(t)?.cells)
    }

    /// Hands each tile written since the last call to `f` (its place
    /// among the allocated tiles, and its cells), and forgets they were.
    pub fn take_touched(&mut self, mut f: impl FnMut(usize, &[C])) {
        for &t in &self.touched {
            let tile = &mut self.tiles[t as usize];
            tile.touched = false;
            f(t as usize, &tile.cells);
        }
        self.touched.clear();
    }

    /// Resets so far: the tiles of a count kept per tile since then are gone.
    pub fn resets(&self) -> u64 {
        self.resets
    }
}

impl<C: StoredCell> Store<C> for Tiled<C> {
    const WINDOWED: bool = true;

    fn fresh(geometry: &GridGeometry, _: C, budget_cells: usize) -> Result<Self> {
        let (tx, ty) = tiles_of(geometry);
        Ok(Self {
            width: geometry.width(),
            height: geometry.height(),
            tiles_x: tx,
            index: vec![NO_TILE; tx * ty],
            tiles: Vec::new(),
            max_tiles: (budget_cells / TILE_CELLS).clamp(1, NO_TILE as usize - 1),
            refused: false,
            touched: Vec::new(),
            resets: 0,
        })
    }

    #[inline]
    fn get(&self, ix: usize, iy: usize) -> Option<(C, u32)> {
        if ix >= self.width || iy >= self.height {
            return None;
        }
        match self.index[self.tile_of(ix, iy)] {
            NO_TILE => None,
            t => {
                let (tile, o) = (&self.tiles[t as usize], Self::offset(ix, iy));
                let c = tile.cells[o];
                Some((c, c.updates(tile.updates[o])))
            }
        }
    }

    type Writer<'a>
        = TiledCells<'a, C>
    where
        Self: 'a;

    #[inline(always)]
    fn window_cells(&mut self, window: Window, unknown: C) -> TiledCells<'_, C> {
        TiledCells {
            store: self,
            window,
            unknown,
        }
    }

    #[inline(always)]
    fn tile_row(
        &mut self,
        ix: usize,
        iy: usize,
        unknown: C,
    ) -> Option<(&mut [C], &mut [C::Updates])> {
        if ix >= self.width || iy >= self.height {
            return None;
        }
        debug_assert_eq!(ix & TILE_MASK, 0);
        let len = TILE_SIDE.min(self.width - ix);
        let k = self.tile_of(ix, iy);
        let tile = self.written_tile(k, unknown)?;
        let o = Self::offset(ix, iy);
        Some((&mut tile.cells[o..o + len], &mut tile.updates[o..o + len]))
    }

    #[inline(always)]
    fn slot(&mut self, ix: usize, iy: usize, unknown: C) -> Option<(&mut C, &mut C::Updates)> {
        if ix >= self.width || iy >= self.height {
            return None;
        }
        let k = self.tile_of(ix, iy);
        let tile = self.written_tile(k, unknown)?;
        let o = Self::offset(ix, iy);
        Some((&mut tile.cells[o], &mut tile.updates[o]))
    }

    /// The tile of the last cell is kept while the cells stay in it (a
    /// scan's cells come along its beams, dozens to a tile): its lookup,
    /// the map's bounds and the tile's own length are then checked once a
    /// run rather than once a cell, a third of an update's instructions on
    /// the campus.
    #[inline(always)]
    fn update_each<I>(
        &mut self,
        cells: impl Iterator<Item = (usize, usize, I)>,
        unknown: C,
        mut f: impl FnMut(I, Option<(&mut C, &mut C::Updates)>),
    ) {
        type TileCells<'t, C, U> = (&'t mut [C; TILE_CELLS], &'t mut [U; TILE_CELLS]);
        let (width, height, tiles_x) = (self.width, self.height, self.tiles_x);
        let mut key = usize::MAX;
        let mut tile: Option<TileCells<'_, C, C::Updates>> = None;
        for (ix, iy, item) in cells {
            if ix >= width || iy >= height {
                f(item, None);
                continue;
            }
            let k = (iy >> TILE_SHIFT) * tiles_x + (ix >> TILE_SHIFT);
            if k != key {
                key = k;
                tile = self.tile_cells(k, unknown);
            }
            match &mut tile {
                Some((cells, updates)) => {
                    let o = Self::offset(ix, iy);
                    f(item, Some((&mut cells[o], &mut updates[o])))
                }
                None => f(item, None),
            }
        }
    }

    fn row_runs(&self, iy: usize, mut f: impl FnMut(RowRun<'_, C>)) {
        if iy >= self.height {
            return;
        }
        let row = (iy & TILE_MASK) << TILE_SHIFT;
        for tx in 0..self.tiles_x {
            let x0 = tx * TILE_SIDE;
            let len = TILE_SIDE.min(self.width - x0);
            let cells = match self.index[(iy >> TILE_SHIFT) * self.tiles_x + tx] {
                NO_TILE => None,
                t => {
                    let tile = &self.tiles[t as usize];
                    Some((&tile.cells[row..row + len], &tile.updates[row..row + len]))
                }
            };
            f(RowRun { x0, len, cells });
        }
    }

    fn block(&self, ix: usize, iy: usize) -> Block<'_, C> {
        let (x0, y0) = (ix & !TILE_MASK, iy & !TILE_MASK);
        let cells = match self.index.get(self.tile_of(ix, iy)) {
            Some(&t) if t != NO_TILE => Some(&self.tiles[t as usize].cells[..]),
            _ => None,
        };
        Block {
            x0,
            y0,
            width: TILE_SIDE.min(self.width.saturating_sub(x0)),
            height: TILE_SIDE.min(self.height.saturating_sub(y0)),
            stride: TILE_SIDE,
            cells,
        }
    }

    /// (Cells of edge tiles beyond the map stay unknown: no beam reaches
    /// them.)
    fn allocated(&self, mut f: impl FnMut(&[C])) {
        for t in &self.tiles {
            f(&t.cells)
        }
    }

    fn cells_allocated(&self) -> usize {
        self.tiles.len() * TILE_CELLS
    }

    fn refused(&self) -> bool {
        self.refused
    }

    fn reset(&mut self, _: C) {
        self.index.fill(NO_TILE);
        self.tiles = Vec::new();
        self.refused = false;
        self.touched.clear();
        self.resets += 1;
    }
}

/// `n` bytes in MiB, one decimal.
pub fn mebibytes(n: u128) -> String {
    format!("{:.1} MiB", n as f64 / (1u64 << 20) as f64)
}

/// What a tiled map of `geometry` would need beyond `budget_cells`, in
/// words: the tiles the beams reach (`needed_tiles`), their cells and
/// bytes (`bytes_per_cell` each: the cell model's cell and its update
/// count).
pub fn budget_message(
    geometry: &GridGeometry,
    needed_tiles: usize,
    budget_cells: usize,
    bytes_per_cell: usize,
) -> String {
    let need = needed_tiles as u128 * TILE_CELLS as u128;
    let b = bytes_per_cell as u128;
    format!(
        "the beams of this log reach {needed_tiles} tiles of {TILE_SIDE} x {TILE_SIDE} cells: {need} cells ({}) \
         of a {} x {} bounding box, over the budget of {budget_cells} cells ({}); choose a coarser resolution",
        mebibytes(need * b),
        geometry.width(),
        geometry.height(),
        mebibytes(budget_cells as u128 * b),
    )
}
