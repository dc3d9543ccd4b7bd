//! The occupancy grid: one belief per cell, the chapter's being a binary
//! Bayes filter in log odds.
//!
//! This is the state every mapper writes into and every widget draws
//! (Probabilistic Robotics, §9.2, Table 9.1). The chapter's cell holds
//! `l = ln(p / (1 - p))`; a measurement adds the inverse sensor model's
//! evidence *net of the prior* `l0`, because the inverse model returns a
//! posterior and the prior must be counted once, not once per scan. Other
//! cell models hold their belief otherwise ([`cell`]); every consumer asks
//! a cell for its probability or its verdict.
//!
//! One map type, [`Grid`], for every consumer: the map's limits
//! ([`GridGeometry`], geometry layer), where its cells live
//! ([`storage`]: one array, or tiles allocated on first touch) and what a
//! cell believes ([`cell`]: the cell model) are three separate ideas, and
//! the update pass, the renderers, the readout ([`readout`]), the counts
//! ([`stats`]), the entropy and the export read and write every map through
//! the same methods. [`LogOddsGrid`] is the dense log-odds map of the
//! chapter's widgets, [`TiledGrid`] the tiled one of real logs.

use crate::error::{self, invalid, Result};
use crate::geometry::GridGeometry;

pub mod cell;
pub mod readout;
pub mod sample;
pub mod stats;
pub mod storage;

pub use cell::{CellModel, HitCount, HitCounting, HitMissOdds, LogOdds};
pub use storage::{Dense, InCell, Store, StoredCell, Tally, Tiled, Window};

/// The larger of two log odds, neither a NaN. `f32::max` says the same,
/// but it must ignore a NaN, which wasm's own `f32.max` returns, so in
/// wasm it is a call to a function per use: pooling a scan's box for the
/// scan matcher spent 2.2 s in such calls on the Freiburg campus's SLAM
/// under Node. (Of a zero's two signs it may keep either: a log odds'
/// sign of zero changes nothing read from it.)
#[inline(always)]
pub fn larger(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// Log odds of a probability, `ln(p / (1 - p))`.
pub fn logit(p: f64) -> f64 {
    (p / (1.0 - p)).ln()
}

/// Probability of log odds, `1 - 1 / (1 + exp(l))`, written so that it is
/// exact to rounding for any finite `l` (no `inf / inf` for large `|l|`).
pub fn probability(l: f64) -> f64 {
    if l >= 0.0 {
        1.0 / (1.0 + (-l).exp())
    } else {
        let e = l.exp();
        e / (1.0 + e)
    }
}

/// Binary entropy of a probability, in bits. `H_b(0) = H_b(1) = 0`.
pub fn binary_entropy_bits(p: f64) -> f64 {
    let term = |q: f64| if q > 0.0 { -q * q.log2() } else { 0.0 };
    term(p) + term(1.0 - p)
}

/// Settings of a log-odds map: its prior and its saturation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FilterSettings {
    /// Prior probability of occupancy of every cell, `p0`.
    pub prior: f64,
    /// Saturation `|l| <= clamp`, in log odds. Keeps every cell revisable.
    pub clamp: f64,
}

impl Default for FilterSettings {
    fn default() -> Self {
        Self {
            prior: 0.5,
            clamp: 12.0,
        }
    }
}

impl FilterSettings {
    pub fn validate(&self) -> Result<()> {
        error::open_probability("prior", self.prior)?;
        error::positive("clamp", self.clamp)?;
        // Cells are stored as f32. A clamp past f32's range would be
        // infinite there (and an infinite cell turns into NaN at the next
        // update of the opposite sign); one below it rounds to a clamp of 0.
        let stored = self.clamp as f32;
        if !(stored.is_finite() && stored > 0.0) {
            return Err(invalid(
                "clamp",
                error::show(self.clamp),
                "a saturation that f32 cells can hold, from 1.5e-45 to 3.4e38 log odds",
            ));
        }
        let l0 = logit(self.prior);
        if l0.abs() > self.clamp {
            return Err(invalid(
                "clamp",
                error::show(self.clamp),
                "at least |l0|, the prior's log odds (or the prior itself would be clamped)",
            ));
        }
        Ok(())
    }
}

/// An occupancy grid map: its limits, its cells and their model. `M` says
/// what a cell believes ([`CellModel`]), `S` where cells live ([`Store`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid<M: CellModel, S: Store<M::Cell>> {
    geometry: GridGeometry,
    model: M,
    store: S,
}

/// The chapter's map: log odds in one array over the whole map.
pub type LogOddsGrid = Grid<LogOdds, Dense<f32>>;

/// A log-odds map whose memory follows the area the beams saw: tiles of
/// [`storage::TILE_SIDE`] cells allocated on first touch, within a budget
/// of allocated cells (a real log's map).
pub type TiledGrid = Grid<LogOdds, Tiled<f32>>;

impl<M: CellModel, S: Store<M::Cell>> Grid<M, S> {
    /// A fresh map of `model`'s cells, every one unknown; a store that
    /// allocates keeps within `budget_cells` cells.
    pub fn with_model(geometry: GridGeometry, model: M, budget_cells: usize) -> Result<Self> {
        let store = S::fresh(&geometry, model.unknown(), budget_cells)?;
        Ok(Self {
            geometry,
            model,
            store,
        })
    }

    /// The map's limits.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// What a cell believes.
    pub fn model(&self) -> &M {
        &self.model
    }
    /// Where the cells live.
    pub fn store(&self) -> &S {
        &self.store
    }
    /// The model and the cells at once, for the update pass.
    #[inline(always)]
    pub fn model_and_store(&mut self) -> (&M, &mut S) {
        (&self.model, &mut self.store)
    }

    /// Cell `(ix, iy)` (row 0 at the bottom), `None` outside the map.
    #[inline]
    pub fn cell_at(&self, ix: usize, iy: usize) -> Option<M::Cell> {
        self.cell_and_updates_at(ix, iy).map(|(c, _)| c)
    }

    /// Cell `(ix, iy)` and how often it was updated, `None` outside the map.
    #[inline]
    pub fn cell_and_updates_at(&self, ix: usize, iy: usize) -> Option<(M::Cell, u32)> {
        if ix >= self.geometry.width() || iy >= self.geometry.height() {
            return None;
        }
        Some(self.store.get(ix, iy).unwrap_or((self.model.unknown(), 0)))
    }

    /// Log odds of cell `(ix, iy)`, `None` outside the map.
    pub fn log_odds_at(&self, ix: usize, iy: usize) -> Option<f32> {
        Some(self.model.log_odds(self.cell_at(ix, iy)?))
    }

    /// Updates cell `(ix, iy)` received, `None` outside the map.
    pub fn updates_at(&self, ix: usize, iy: usize) -> Option<u32> {
        Some(self.cell_and_updates_at(ix, iy)?.1)
    }

    /// One step of Table 9.1 for cell `(ix, iy)` with evidence of either
    /// sign ([`CellModel::add`]); nothing outside the map or past the
    /// store's budget ([`Self::refused`] then says so).
    pub fn apply_at(&mut self, ix: usize, iy: usize, evidence: f32) {
        let unknown = self.model.unknown();
        if let Some((c, n)) = self.store.slot(ix, iy, unknown) {
            self.model.add(c, evidence);
            n.add_one();
        }
    }

    /// Every cell back to unknown (a tiled store frees its tiles).
    pub fn reset(&mut self) {
        self.store.reset(self.model.unknown());
    }

    /// Cells with storage (every cell of a dense map).
    pub fn cells_allocated(&self) -> usize {
        self.store.cells_allocated()
    }
    /// Bytes a cell takes: the cell model's value and its update count
    /// (none beside a cell that counts its updates itself).
    pub fn bytes_per_cell(&self) -> usize {
        std::mem::size_of::<M::Cell>() + std::mem::size_of::<<M::Cell as StoredCell>::Updates>()
    }
    /// Bytes the allocated cells hold.
    pub fn bytes_allocated(&self) -> usize {
        self.cells_allocated() * self.bytes_per_cell()
    }
    /// True once a cell's evidence was dropped for want of storage.
    pub fn refused(&self) -> bool {
        self.store.refused()
    }

    /// Entropy of the map, `sum_i H_b(p_i)`, in bits. A fresh map with
    /// `p0 = 0.5` holds exactly one bit per cell; a cell no storage holds
    /// counts as unknown. (One pass over the cells held: a view that keeps
    /// the sum up to date cell by cell keeps it in [`stats::MapScores`].)
    pub fn entropy_bits(&self) -> f64 {
        let m = &self.model;
        let mut bits = 0.0;
        let mut held = 0;
        self.store.allocated(|cells| {
            held += cells.len();
            bits += cells
                .iter()
                .map(|&c| binary_entropy_bits(m.probability(c)))
                .sum::<f64>();
        });
        // Cells of edge tiles beyond the map are unknown too: take them
        // back out.
        let unheld = self.geometry.len() as f64 - held as f64;
        bits + unheld * binary_entropy_bits(m.probability(m.unknown()))
    }

    /// Brier score `mean_i (p_i - m_i)^2` against a ground-truth binary map
    /// (`true` = occupied, row-major like the map), over every cell or over
    /// the cells listed in `region`: every cell scored once, in index
    /// order, by the scores a view keeps ([`stats::MapScores`]).
    pub fn brier_score(&self, truth: &[bool], region: Option<&[usize]>) -> Result<f64> {
        let n = self.geometry.len();
        let every: Vec<usize>;
        let region = match region {
            Some(cells) => cells,
            None => {
                every = (0..n).collect();
                &every
            }
        };
        let mut scores = stats::MapScores::new(n, truth, region)?;
        for i in 0..n {
            let (ix, iy) = self.geometry.cell_of_index(i);
            let p = self
                .cell_at(ix, iy)
                .map_or(0.5, |c| self.model.probability(c));
            scores.rescore(i, p, 0.0);
        }
        Ok(scores.brier_region())
    }

    /// The same map in one array (for a map the dense store can hold: at
    /// most [`crate::geometry::MAX_CELLS`] cells).
    pub fn to_dense(&self) -> Result<Grid<M, Dense<M::Cell>>> {
        let g = &self.geometry;
        let geometry = GridGeometry::new(
            g.width(),
            g.height(),
            g.resolution(),
            g.origin()[0],
            g.origin()[1],
        )?;
        let mut dense = Grid::<M, Dense<M::Cell>>::with_model(geometry, self.model.clone(), 0)?;
        let unknown = self.model.unknown();
        for iy in 0..g.height() {
            self.store.row_runs(iy, |run| {
                if let Some((cells, updates)) = run.cells {
                    for (k, (&c, &u)) in cells.iter().zip(updates).enumerate() {
                        if let Some((d, n)) = dense.store.slot(run.x0 + k, iy, unknown) {
                            *d = c;
                            *n = u;
                        }
                    }
                }
            });
        }
        Ok(dense)
    }
}

impl<S: Store<f32>> Grid<LogOdds, S> {
    /// A fresh log-odds map, every cell at the prior's log odds `l0`; a
    /// store that allocates keeps within `budget_cells` cells.
    pub fn with_budget(
        geometry: GridGeometry,
        settings: FilterSettings,
        budget_cells: usize,
    ) -> Result<Self> {
        settings.validate()?;
        Self::with_model(
            geometry,
            LogOdds::new(settings.prior, settings.clamp),
            budget_cells,
        )
    }

    /// The prior's log odds.
    pub fn l0(&self) -> f32 {
        self.model.l0
    }
    pub fn clamp(&self) -> f32 {
        self.model.clamp
    }

    /// Changes the saturation. Cells beyond the new clamp are pulled in, as
    /// the next update would do anyway.
    pub fn set_clamp(&mut self, clamp: f64) -> Result<()> {
        FilterSettings {
            prior: probability(self.model.l0 as f64),
            clamp,
        }
        .validate()?;
        self.model.clamp = clamp as f32;
        let c = self.model.clamp;
        let (w, h) = (self.geometry.width(), self.geometry.height());
        for iy in 0..h {
            for ix in 0..w {
                if let Some((l, _)) = self.store.get(ix, iy) {
                    if l.abs() > c {
                        if let Some((cell, _)) = self.store.slot(ix, iy, self.model.l0) {
                            *cell = l.clamp(-c, c);
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

impl LogOddsGrid {
    /// A fresh dense map: every cell at the prior's log odds `l0`.
    pub fn new(geometry: GridGeometry, settings: FilterSettings) -> Result<Self> {
        Self::with_budget(geometry, settings, geometry.len())
    }
}

impl TiledGrid {
    /// A fresh tiled map, every cell at the prior, no tile allocated; at
    /// most `budget_cells` cells (rounded down to whole tiles, at least
    /// one) will ever be allocated.
    pub fn new(
        geometry: GridGeometry,
        settings: FilterSettings,
        budget_cells: usize,
    ) -> Result<Self> {
        Self::with_budget(geometry, settings, budget_cells)
    }

    /// Tiles allocated so far.
    pub fn tiles_allocated(&self) -> usize {
        self.store.tiles_allocated()
    }
    /// Most tiles the budget allows.
    pub fn max_tiles(&self) -> usize {
        self.store.max_tiles()
    }
}

/// Index-based access to a dense map (its cells are one row-major array,
/// bottom row first): what the chapter's widgets use.
impl<M: CellModel> Grid<M, Dense<M::Cell>> {
    /// Every cell, row-major from the bottom row.
    pub fn cells(&self) -> &[M::Cell] {
        self.store.cells()
    }
    pub fn probability_at(&self, i: usize) -> f64 {
        self.model.probability(self.store.cells()[i])
    }
    /// True when cell `i` still holds the unknown value: the third state,
    /// neither free nor occupied.
    pub fn is_unknown(&self, i: usize) -> bool {
        self.model.is_unknown(self.store.cells()[i])
    }
    /// One step of the cell's filter (Table 9.1) for cell `i`:
    /// [`CellModel::add`]. The caller has validated `evidence`.
    #[inline(always)]
    pub fn apply(&mut self, i: usize, evidence: f32) {
        let (cells, updates) = self.store.cells_mut();
        self.model.add(&mut cells[i], evidence);
        updates[i].add_one();
    }
}

/// A dense map whose cells count their updates beside them.
impl<M: CellModel> Grid<M, Dense<M::Cell>>
where
    M::Cell: StoredCell<Updates = u32>,
{
    /// How many updates each cell has received.
    pub fn update_counts(&self) -> &[u32] {
        self.store.updates()
    }
}

impl LogOddsGrid {
    /// Log odds of every cell, row-major from the bottom row.
    pub fn log_odds(&self) -> &[f32] {
        self.store.cells()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn probability_is_stable_for_extreme_log_odds() {
        assert_eq!(probability(800.0), 1.0);
        assert_eq!(probability(-800.0), 0.0);
        assert_abs_diff_eq!(probability(logit(0.7)), 0.7, epsilon = 1e-12);
    }

    #[test]
    fn binary_entropy_is_one_bit_at_one_half_and_zero_at_certainty() {
        assert_eq!(binary_entropy_bits(0.5), 1.0);
        assert_eq!(binary_entropy_bits(0.0), 0.0);
        assert_eq!(binary_entropy_bits(1.0), 0.0);
    }
}
