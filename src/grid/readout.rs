//! One cell as a hover readout shows it: where it is, its log odds and
//! probability, how often it was updated, and whether it is still unknown.
//! Every widget's hover line reads a [`CellReadout`].

use super::LogOddsGrid;

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
pub fn readout_at_pixel(grid: &LogOddsGrid, col: usize, row: usize) -> Option<CellReadout> {
    let (ix, iy) = grid.geometry().image_pixel_to_cell(col, row)?;
    readout_at_cell(grid, ix, iy)
}

/// Cell `(ix, iy)` (row 0 at the bottom), or `None` outside the map.
pub fn readout_at_cell(grid: &LogOddsGrid, ix: usize, iy: usize) -> Option<CellReadout> {
    let g = grid.geometry();
    if ix >= g.width() || iy >= g.height() {
        return None;
    }
    let i = g.index(ix, iy);
    let (x, y) = g.cell_center(ix, iy);
    Some(CellReadout {
        ix,
        iy,
        x,
        y,
        l: *grid.log_odds().get(i)? as f64,
        p: grid.probability_at(i),
        updates: *grid.update_counts().get(i)?,
        unknown: grid.is_unknown(i),
    })
}
