//! What a whole map amounts to: how many cells are occupied, free and still
//! unknown. [`count_states`] uses the thresholds of BENCHMARKS.md W1 (the
//! benchmark's figures); [`count_states_between`] any pair, which is how an
//! exported map counts its cells with the thresholds its YAML states
//! (`crate::io::map_server::export_counts`).

use super::{logit, CellModel, Grid, Store};

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

/// The log-odds form of the thresholds `p > occupied_above` and
/// `p < free_below`, as every comparison against them is made (one place,
/// so that a map's image and its counts cannot disagree on a cell).
pub fn log_odds_thresholds(occupied_above: f64, free_below: f64) -> (f32, f32) {
    (logit(occupied_above) as f32, logit(free_below) as f32)
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
    // Compared in log odds: no exp per cell.
    let (occ_l, free_l) = log_odds_thresholds(occupied_above, free_below);
    let model = grid.model();
    let unknown_l = model.log_odds(model.unknown());
    let mut tally = Tally {
        model,
        occ_l,
        free_l,
        at_prior: 0,
        above: 0,
        below: 0,
    };
    let mut held = 0;
    grid.store().allocated(|cells| {
        held += cells.len();
        // Eight cells per loop turn: under Node the loop's own bookkeeping
        // is otherwise most of this short body.
        let mut chunks = cells.chunks_exact(8);
        for c in &mut chunks {
            for &cell in c {
                tally.add(cell);
            }
        }
        for &cell in chunks.remainder() {
            tally.add(cell);
        }
    });
    // Take the cells still unknown back out of the band their log odds
    // fall in.
    let at_prior = tally.at_prior;
    let cells = grid.geometry().len();
    StateCounts {
        occupied: tally.above - if unknown_l > occ_l { at_prior } else { 0 },
        free: tally.below - if unknown_l < free_l { at_prior } else { 0 },
        // Every cell not held (and every held cell beyond the map, at the
        // edge of a tile) is unknown.
        unknown: cells - (held - at_prior),
        cells,
    }
}

/// Three independent counts per cell, with no branch between them (a
/// branch on "still at the prior" is mispredicted all over a half-explored
/// map).
struct Tally<'m, M> {
    model: &'m M,
    occ_l: f32,
    free_l: f32,
    at_prior: usize,
    above: usize,
    below: usize,
}

impl<M: CellModel> Tally<'_, M> {
    #[inline(always)]
    fn add(&mut self, cell: M::Cell) {
        let l = self.model.log_odds(cell);
        self.at_prior += self.model.is_unknown(cell) as usize;
        self.above += (l > self.occ_l) as usize;
        self.below += (l < self.free_l) as usize;
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
}
