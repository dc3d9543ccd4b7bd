//! One cell as a hover readout shows it: where it is, its log odds and
//! probability, how often it was updated, and whether it is still unknown.
//! Every widget's hover line reads a [`CellReadout`], of any map.

use super::{CellModel, Grid, Store};

/// One cell, for a hover readout.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellReadout {
    pub ix: usize,
    pub iy: usize,
    /// The cell centre, metres.
    pub x: f64,
    pub y: f64,
    /// Log odds.
    pub l: f64,
    /// Probability of occupancy.
    pub p: f64,
    /// Updates the cell received.
    pub updates: u32,
    /// Still exactly at the prior.
    pub unknown: bool,
}

/// The cell under image pixel `(col, row)` of the north-up image (row 0 at
/// the top), or `None` outside the map.
pub fn readout_at_pixel<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    col: usize,
    row: usize,
) -> Option<CellReadout> {
    let (ix, iy) = grid.geometry().image_pixel_to_cell(col, row)?;
    readout_at_cell(grid, ix, iy)
}

/// Cell `(ix, iy)` (row 0 at the bottom), or `None` outside the map.
pub fn readout_at_cell<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    ix: usize,
    iy: usize,
) -> Option<CellReadout> {
    let (cell, updates) = grid.cell_and_updates_at(ix, iy)?;
    let (x, y) = grid.geometry().cell_center(ix, iy);
    let m = grid.model();
    Some(CellReadout {
        ix,
        iy,
        x,
        y,
        l: m.log_odds(cell) as f64,
        p: m.probability(cell),
        updates,
        unknown: m.is_unknown(cell),
    })
}
