//! The one gray ramp every map is drawn with, and the one north-up raster
//! every renderer writes through.
//!
//! SPEC §1's drawing convention: white free, black occupied, a linear gray
//! ramp on `p` in between, and cells still exactly at the prior mid-gray
//! whatever the prior is, because "unknown" is a state of its own.

use crate::error::{OccError, Result};
use crate::geometry::GridGeometry;
use crate::grid::{probability, LogOddsGrid};

/// The gray level of a cell still exactly at the prior: "unknown".
pub const UNKNOWN_GRAY: u8 = 128;

/// The ramp's gray level for log odds `l`: `round(255 (1 - p))`, white free,
/// black occupied. (Cells exactly at the prior are [`UNKNOWN_GRAY`]; the
/// caller checks that.)
#[inline]
pub fn ramp_gray(l: f32) -> u8 {
    (255.0 * (1.0 - probability(l as f64)) + 0.5) as u8
}

/// The gray level of probability `p` on the same ramp, for maps that hold
/// probabilities (max fusion, eq. 9.9) rather than log odds.
#[inline]
pub fn probability_gray(p: f64) -> u8 {
    (255.0 * (1.0 - p) + 0.5) as u8
}

/// Draws a log-odds map into RGBA pixels, north up (the top pixel row is the
/// grid's last row), on the ramp with unknown cells mid-gray.
pub fn render_grid_rgba(grid: &LogOddsGrid, out: &mut [u8]) -> Result<()> {
    let l0 = grid.l0();
    render_gray_rgba(grid.geometry(), grid.log_odds(), out, |l| {
        if l == l0 {
            UNKNOWN_GRAY
        } else {
            ramp_gray(l)
        }
    })
}

/// Draws a binary map (the MAP search's, Table 9.3) into RGBA pixels, north
/// up: occupied black, free white, and [`UNKNOWN_GRAY`] for the free cells
/// no reading ever `reached` (the search decided nothing about them: they
/// are free only because it starts all-free, and its export marks them
/// unknown).
pub fn render_binary_rgba(
    geometry: &GridGeometry,
    occupied: &[bool],
    reached: &[bool],
    out: &mut [u8],
) -> Result<()> {
    if reached.len() != occupied.len() {
        return Err(OccError::LengthMismatch {
            field: "reached".into(),
            expected: occupied.len(),
            found: reached.len(),
        });
    }
    let cells: Vec<(bool, bool)> = occupied
        .iter()
        .copied()
        .zip(reached.iter().copied())
        .collect();
    render_gray_rgba(geometry, &cells, out, |(o, r)| match (o, r) {
        (true, _) => 0,
        (false, true) => 255,
        (false, false) => UNKNOWN_GRAY,
    })
}

/// Writes one gray level per cell (`gray(cell)`) into RGBA pixels, north up:
/// the top pixel row is the grid's last row. Every map drawn by the core
/// goes through here, so all of them share one orientation.
pub fn render_gray_rgba<T: Copy>(
    geometry: &GridGeometry,
    cells: &[T],
    out: &mut [u8],
    gray: impl Fn(T) -> u8,
) -> Result<()> {
    let (w, h) = (geometry.width(), geometry.height());
    if cells.len() != w * h {
        return Err(OccError::LengthMismatch {
            field: "cells".into(),
            expected: w * h,
            found: cells.len(),
        });
    }
    if out.len() != w * h * 4 {
        return Err(OccError::LengthMismatch {
            field: "pixel buffer".into(),
            expected: w * h * 4,
            found: out.len(),
        });
    }
    for (row_out, iy) in (0..h).rev().enumerate() {
        let src = &cells[iy * w..(iy + 1) * w];
        let dst = &mut out[row_out * w * 4..(row_out + 1) * w * 4];
        for (px, &c) in dst.chunks_exact_mut(4).zip(src) {
            let g = gray(c);
            px.copy_from_slice(&[g, g, g, 255]);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::FilterSettings;

    #[test]
    fn render_puts_north_up_and_unknown_mid_gray() {
        let geometry = GridGeometry::new(4, 3, 0.5, -1.0, 2.0).unwrap();
        let mut m = LogOddsGrid::new(
            geometry,
            FilterSettings {
                prior: 0.2,
                clamp: 5.0,
            },
        )
        .unwrap();
        m.apply(0, 10.0); // south-west cell: occupied, clamped at 5
        let mut px = vec![0u8; 4 * 3 * 4];
        render_grid_rgba(&m, &mut px).unwrap();
        let bottom_left = (2 * 4) * 4;
        assert!(px[bottom_left] <= 2, "occupied is black");
        assert_eq!(px[0], 128, "unknown is mid-gray even with prior 0.2");
        assert_eq!(m.update_counts()[0], 1);
        assert!(render_grid_rgba(&m, &mut [0u8; 3]).is_err());
    }

    #[test]
    fn a_binary_map_draws_cells_no_reading_reached_unknown() {
        let geometry = GridGeometry::new(3, 1, 1.0, 0.0, 0.0).unwrap();
        let mut px = vec![0u8; 3 * 4];
        let (occupied, reached) = ([true, false, false], [true, true, false]);
        render_binary_rgba(&geometry, &occupied, &reached, &mut px).unwrap();
        assert_eq!((px[0], px[4], px[8]), (0, 255, UNKNOWN_GRAY));
        assert!(render_binary_rgba(&geometry, &occupied, &reached[..2], &mut px).is_err());
    }
}
