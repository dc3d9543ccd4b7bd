//! What a whole map amounts to: how many cells are occupied, free and still
//! unknown, and how well it is scored against the world it maps.
//! [`count_states`] uses the thresholds of workload W1 (the benchmark's
//! figures); [`count_states_between`] any pair, which is how an exported
//! map counts its cells with the thresholds its YAML states
//! (`crate::io::map_server::export_counts`). A cell is counted by its
//! verdict ([`CellModel::beyond`], [`CellModel::is_unknown`]), so that any
//! cell model's map is counted alike. [`MapScores`] keeps a map's entropy
//! and Brier scores cell by cell.

use super::cell::Thresholds;
use super::storage::Tiled;
use super::{CellModel, Grid, Store};
use crate::error::{invalid, OccError, Result};

/// Cells above this probability count as occupied (W1).
pub const OCCUPIED_ABOVE: f64 = 0.65;
/// Cells below this probability count as free (W1).
pub const FREE_BELOW: f64 = 0.35;

/// The cells of a map in each state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct StateCounts {
    /// Cells above the occupied threshold (`p > 0.65` for W1).
    pub occupied: usize,
    /// Cells below the free threshold (`p < 0.35` for W1).
    pub free: usize,
    /// Cells still exactly at the prior.
    pub unknown: usize,
    pub cells: usize,
}

/// Counts the three states of a map. A cell still at the prior is unknown,
/// whatever the thresholds say of `l0`.
pub fn count_states<M: CellModel, S: Store<M::Cell>>(grid: &Grid<M, S>) -> StateCounts {
    count_states_between(grid, OCCUPIED_ABOVE, FREE_BELOW)
}

/// Counts the three states of a map with `p > occupied_above` occupied and
/// `p < free_below` free (a cell still unknown is unknown either way; one
/// between the thresholds is in none of the three). Cells no storage holds
/// are unknown.
pub fn count_states_between<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    occupied_above: f64,
    free_below: f64,
) -> StateCounts {
    let thresholds = Thresholds::new(occupied_above, free_below);
    let mut sums = [0; 3];
    let mut held = 0;
    grid.store().allocated(|cells| {
        held += cells.len();
        let t = tally(grid.model(), &thresholds, cells);
        sums = [sums[0] + t[0], sums[1] + t[1], sums[2] + t[2]];
    });
    state_counts(grid, &thresholds, held, sums)
}

/// The counts of `grid` from the tally `[above, below, at_prior]` of the
/// `held` cells its storage holds.
fn state_counts<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    thresholds: &Thresholds,
    held: usize,
    [above, below, at_prior]: [usize; 3],
) -> StateCounts {
    let model = grid.model();
    let (unknown_above, unknown_below) = model.beyond(model.unknown(), thresholds);
    // Take the cells still unknown back out of the band their belief
    // falls in.
    let cells = grid.geometry().len();
    StateCounts {
        occupied: above - if unknown_above { at_prior } else { 0 },
        free: below - if unknown_below { at_prior } else { 0 },
        // Every cell not held (and every held cell beyond the map, at the
        // edge of a tile) is unknown.
        unknown: cells - (held - at_prior),
        cells,
    }
}

/// `[above, below, at_prior]` of `cells`: above the occupied threshold,
/// below the free one, still at the prior.
fn tally<M: CellModel>(model: &M, thresholds: &Thresholds, cells: &[M::Cell]) -> [usize; 3] {
    let mut tally = Tally {
        model,
        thresholds,
        at_prior: 0,
        above: 0,
        below: 0,
    };
    // Eight cells per loop turn: under Node the loop's own bookkeeping is
    // otherwise most of this short body.
    let mut chunks = cells.chunks_exact(8);
    for c in &mut chunks {
        for &cell in c {
            tally.add(cell);
        }
    }
    for &cell in chunks.remainder() {
        tally.add(cell);
    }
    [tally.above, tally.below, tally.at_prior]
}

/// A tiled map's counts kept per tile: each tile written since the last
/// [`Self::refresh`] is recounted then (its [`TILE_CELLS`] cells, once
/// however many updates it took), and the map's counts are the sum of the
/// tiles', so that asking for them walks no cell a build has not just
/// written (docs/ARCHITECTURE.md, "Real logs"). The counts are the ones
/// [`count_states_between`] counts, cell for cell.
///
/// [`TILE_CELLS`]: super::storage::TILE_CELLS
#[derive(Debug, Clone, PartialEq)]
pub struct TileTally {
    thresholds: Thresholds,
    /// Per allocated tile, `[above, below, at_prior]`.
    tiles: Vec<[usize; 3]>,
    /// Their sum.
    sums: [usize; 3],
    /// The store's resets when the tiles above were counted.
    resets: u64,
}

impl TileTally {
    /// No tile counted yet, with `p > occupied_above` occupied and
    /// `p < free_below` free.
    pub fn new(occupied_above: f64, free_below: f64) -> Self {
        Self {
            thresholds: Thresholds::new(occupied_above, free_below),
            tiles: Vec::new(),
            sums: [0; 3],
            resets: 0,
        }
    }

    /// Recounts the tiles of `grid` written since the last refresh, and
    /// returns the cells recounted.
    pub fn refresh<M: CellModel>(&mut self, grid: &mut Grid<M, Tiled<M::Cell>>) -> usize {
        let (model, store) = grid.model_and_store();
        if store.resets() != self.resets {
            // Every tile counted is gone; the ones since are all written.
            (self.tiles, self.sums, self.resets) = (Vec::new(), [0; 3], store.resets());
        }
        let mut recounted = 0;
        let thresholds = &self.thresholds;
        store.take_touched(|t, cells| {
            recounted += cells.len();
            if self.tiles.len() <= t {
                self.tiles.resize(t + 1, [0; 3]);
            }
            let (old, new) = (self.tiles[t], tally(model, thresholds, cells));
            for i in 0..3 {
                self.sums[i] = self.sums[i] - old[i] + new[i];
            }
            self.tiles[t] = new;
        });
        recounted
    }

    /// The counts of `grid` now: the sum kept, with the tiles written
    /// since the last refresh counted afresh (not kept).
    pub fn counts<M: CellModel>(&self, grid: &Grid<M, Tiled<M::Cell>>) -> StateCounts {
        let store = grid.store();
        // (Since a reset, every tile held is one written.)
        let kept = store.resets() == self.resets;
        let mut sums = if kept { self.sums } else { [0; 3] };
        for &t in store.touched() {
            let t = t as usize;
            let old = match kept {
                true => self.tiles.get(t).copied().unwrap_or([0; 3]),
                false => [0; 3],
            };
            let new = store
                .tile(t)
                .map_or([0; 3], |cells| tally(grid.model(), &self.thresholds, cells));
            for i in 0..3 {
                sums[i] = sums[i] - old[i] + new[i];
            }
        }
        state_counts(grid, &self.thresholds, grid.cells_allocated(), sums)
    }
}

/// Three independent counts per cell, with no branch between them (a
/// branch on "still at the prior" is mispredicted all over a half-explored
/// map).
struct Tally<'m, M> {
    model: &'m M,
    thresholds: &'m Thresholds,
    at_prior: usize,
    above: usize,
    below: usize,
}

impl<M: CellModel> Tally<'_, M> {
    #[inline(always)]
    fn add(&mut self, cell: M::Cell) {
        let (above, below) = self.model.beyond(cell, self.thresholds);
        self.at_prior += self.model.is_unknown(cell) as usize;
        self.above += above as usize;
        self.below += below as usize;
    }
}

/// A map's entropy (bits) and Brier scores against a ground truth, kept
/// cell by cell: each cell's binary entropy and squared error, and their
/// sums, which rescoring a cell changes by the difference. A view that
/// rescores only the cells a scan changed keeps a whole map's scores
/// without a pass over it (`crate::render::map_view::MapView`); a map
/// scored once, cell by cell in index order, gives them too
/// ([`Grid::brier_score`]).
#[derive(Debug, Clone)]
pub struct MapScores {
    truth: Vec<bool>,
    in_region: Vec<bool>,
    region_cells: usize,
    entropy: Vec<f64>,
    sq_error: Vec<f64>,
    entropy_sum: f64,
    sq_sum_all: f64,
    sq_sum_region: f64,
}

impl MapScores {
    /// Scores of a map of `cells` cells, nothing scored yet, against
    /// `truth` (`true` = occupied, row-major like the map), with a Brier
    /// region of the cells listed in `region`.
    pub fn new(cells: usize, truth: &[bool], region: &[usize]) -> Result<Self> {
        if truth.len() != cells {
            return Err(OccError::LengthMismatch {
                field: "truth".into(),
                expected: cells,
                found: truth.len(),
            });
        }
        let mut in_region = vec![false; cells];
        for &i in region {
            match in_region.get_mut(i) {
                Some(slot) => *slot = true,
                None => return Err(invalid("region", i, "cell indices inside the map")),
            }
        }
        let region_cells = in_region.iter().filter(|&&b| b).count();
        if region_cells == 0 {
            return Err(invalid("region", "[]", "at least one cell"));
        }
        Ok(Self {
            truth: truth.to_vec(),
            in_region,
            region_cells,
            entropy: vec![0.0; cells],
            sq_error: vec![0.0; cells],
            entropy_sum: 0.0,
            sq_sum_all: 0.0,
            sq_sum_region: 0.0,
        })
    }

    /// Cell `i` now believes `p` with binary entropy `entropy_bits` (the
    /// caller's: exact, or interpolated in a table).
    #[inline]
    pub fn rescore(&mut self, i: usize, p: f64, entropy_bits: f64) {
        let m = if self.truth[i] { 1.0 } else { 0.0 };
        let sq = (p - m) * (p - m);
        self.entropy_sum += entropy_bits - self.entropy[i];
        self.entropy[i] = entropy_bits;
        let d = sq - self.sq_error[i];
        self.sq_sum_all += d;
        if self.in_region[i] {
            self.sq_sum_region += d;
        }
        self.sq_error[i] = sq;
    }

    /// Every cell unscored, every sum zero.
    pub fn clear(&mut self) {
        self.entropy.fill(0.0);
        self.sq_error.fill(0.0);
        self.entropy_sum = 0.0;
        self.sq_sum_all = 0.0;
        self.sq_sum_region = 0.0;
    }

    /// Map entropy, bits: the sum of the cells' binary entropies.
    pub fn entropy_bits(&self) -> f64 {
        self.entropy_sum
    }
    /// Brier score over the region: the mean squared error of its cells.
    pub fn brier_region(&self) -> f64 {
        self.sq_sum_region / self.region_cells as f64
    }
    /// Brier score over every cell.
    pub fn brier_all(&self) -> f64 {
        self.sq_sum_all / self.truth.len() as f64
    }
    /// Each cell's squared error `(p - truth)^2`, row-major like the map.
    pub fn squared_errors(&self) -> &[f64] {
        &self.sq_error
    }
    /// The ground truth each cell is scored against (`true` = occupied).
    pub fn truth(&self) -> &[bool] {
        &self.truth
    }
    /// Whether each cell counts in the Brier region.
    pub fn region(&self) -> &[bool] {
        &self.in_region
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::grid::{FilterSettings, LogOddsGrid};

    /// The state count, cell by cell as W1 defines it, against the
    /// branch-free tally: with the prior inside the band (W1's), above
    /// p = 0.65 and below p = 0.35, so that cells still at the prior would
    /// otherwise count as occupied or free.
    #[test]
    fn state_counts_match_a_cell_by_cell_count_whatever_the_prior() {
        let evidence = [0.0f32, 0.3, -0.3, 0.9, -0.9, 2.5, -2.5, 0.05, -0.05];
        for prior in [0.5, 0.2, 0.8, 0.66, 0.34] {
            let geometry = GridGeometry::new(37, 5, 0.1, 0.0, 0.0).unwrap();
            let mut grid =
                LogOddsGrid::new(geometry, FilterSettings { prior, clamp: 3.0 }).unwrap();
            for i in 0..geometry.len() {
                let e = evidence[(i * 7) % evidence.len()];
                if e != 0.0 {
                    grid.apply(i, e);
                }
            }
            let counts = count_states(&grid);
            let (mut occupied, mut free, mut unknown) = (0, 0, 0);
            for i in 0..geometry.len() {
                let p = grid.probability_at(i);
                if grid.is_unknown(i) {
                    unknown += 1;
                } else if p > 0.65 {
                    occupied += 1;
                } else if p < 0.35 {
                    free += 1;
                }
            }
            assert!(unknown > 0 && occupied > 0 && free > 0, "prior {prior}");
            assert_eq!(
                (counts.occupied, counts.free, counts.unknown),
                (occupied, free, unknown),
                "prior {prior}"
            );
        }
    }

    /// Sums kept by differences are the scores of the cells as they are
    /// now; the region counts a cell listed twice once.
    #[test]
    fn map_scores_kept_by_differences_are_the_scores_of_the_cells_now() {
        use crate::grid::binary_entropy_bits as h;
        let truth = [true, false, false, true, false];
        let mut s = MapScores::new(5, &truth, &[1, 3, 3]).unwrap();
        for (i, p) in [(0, 0.9), (1, 0.2), (3, 0.6), (1, 0.5), (4, 0.1), (0, 0.7)] {
            s.rescore(i, p, h(p));
        }
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(s.entropy_bits(), h(0.7) + h(0.5) + h(0.6) + h(0.1)));
        assert!(close(s.brier_all(), (0.09 + 0.25 + 0.16 + 0.01) / 5.0));
        assert!(close(s.brier_region(), (0.25 + 0.16) / 2.0));
        s.clear();
        assert_eq!((s.entropy_bits(), s.brier_all()), (0.0, 0.0));
        let err = |r: Result<MapScores>| r.unwrap_err().to_string();
        assert!(err(MapScores::new(4, &truth, &[0])).contains("truth"));
        assert!(err(MapScores::new(5, &truth, &[])).contains("at least one cell"));
        assert!(err(MapScores::new(5, &truth, &[0, 5])).contains("inside the map"));
    }
}
