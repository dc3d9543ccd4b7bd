//! The one gray ramp every map is drawn with, and the one look of a cell
//! on screen ([`cell_gray`]) that every renderer uses.
//!
//! The drawing convention (docs/ARCHITECTURE.md, "Drawing"): white free,
//! black occupied, a linear gray ramp on `p` in between, and cells still
//! unknown mid-gray whatever the prior is, because "unknown" is a state of
//! its own. A whole map is drawn by the view renderer (`render_view`, and
//! `render_grid_rgba` at one pixel per cell, beside the viewport), which
//! takes its grays from here.

use crate::error::{OccError, Result};
use crate::geometry::GridGeometry;
use crate::grid::{probability, CellModel};
use std::sync::OnceLock;

/// The gray level of a cell still exactly at the prior: "unknown".
pub const UNKNOWN_GRAY: u8 = 128;

/// The ramp's gray level for log odds `l`: `round(255 (1 - p))`, white free,
/// black occupied. (Cells exactly at the prior are [`UNKNOWN_GRAY`]; the
/// caller checks that.)
#[inline]
pub fn ramp_gray(l: f32) -> u8 {
    (255.0 * (1.0 - probability(l as f64)) + 0.5) as u8
}

/// Orders finite `f32`s as integers, so that a bisection can walk them.
pub(crate) fn key(f: f32) -> i32 {
    let b = f.to_bits() as i32;
    b ^ (((b >> 31) as u32) >> 1) as i32
}
pub(crate) fn unkey(k: i32) -> f32 {
    f32::from_bits((k ^ (((k >> 31) as u32) >> 1) as i32) as u32)
}

/// `THRESHOLDS[k - 1]` is the smallest `f32` log odds whose gray level is
/// below `k` (k = 1..=255). The ramp falls as `l` grows, so the thresholds
/// fall too, and the gray level of `l` is the number of thresholds above
/// `l`.
pub(crate) fn thresholds() -> &'static [f32; 255] {
    static T: OnceLock<[f32; 255]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [0.0f32; 255];
        // Beyond +-100 the ramp is flat at 0 and 255.
        let (lo, hi) = (key(-100.0) as i64, key(100.0) as i64);
        for (j, slot) in t.iter_mut().enumerate() {
            let k = (j + 1) as u8;
            // Smallest key in [lo, hi] with ramp < k (ramp(hi) = 0 < k).
            let (mut a, mut b) = (lo, hi);
            while a < b {
                let m = a + (b - a) / 2;
                if ramp_gray(unkey(m as i32)) < k {
                    b = m;
                } else {
                    a = m + 1;
                }
            }
            *slot = unkey(a as i32);
        }
        t
    })
}

/// [`ramp_gray`] of log odds `l`, bit for bit, found without an
/// exponential (a binary search over the ramp's 255 thresholds).
#[inline]
pub fn gray_level(l: f32) -> u8 {
    // Thresholds are decreasing: those above `l` come first.
    thresholds().partition_point(|&t| l < t) as u8
}

/// A cell's gray level on screen: [`UNKNOWN_GRAY`] while it is unknown,
/// the ramp of its belief otherwise ([`known_cell_gray`]).
#[inline(always)]
pub fn cell_gray<M: CellModel>(model: &M, cell: M::Cell) -> u8 {
    if model.is_unknown(cell) {
        UNKNOWN_GRAY
    } else {
        known_cell_gray(model, cell)
    }
}

/// The ramp's gray level of a cell's belief: found from the log odds the
/// model holds without an exponential ([`gray_level`]), else from its
/// probability ([`probability_gray`]); the two agree bit for bit.
#[inline(always)]
pub fn known_cell_gray<M: CellModel>(model: &M, cell: M::Cell) -> u8 {
    match model.held_log_odds(cell) {
        Some(l) => gray_level(l),
        None => probability_gray(model.probability(cell)),
    }
}

/// The gray level of probability `p` on the same ramp, for maps that hold
/// probabilities (max fusion, eq. 9.9) rather than log odds.
#[inline]
pub fn probability_gray(p: f64) -> u8 {
    (255.0 * (1.0 - p) + 0.5) as u8
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
