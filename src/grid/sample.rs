//! A map read at any point of the world, not only at cell centres: the
//! occupancy probability interpolated bilinearly between the four nearest
//! cell centres, and its gradient. This is how a scan matcher sees a map
//! (Hector SLAM's map access: a smooth occupancy it can climb with
//! Gauss–Newton), and it reads any grid, whatever its storage or cell
//! model; an unknown cell counts as its model's unknown probability.

use super::{CellModel, Grid, Store};

/// The interpolated occupancy at a point and its gradient (per metre).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Occupancy probability, 0 to 1.
    pub p: f64,
    /// `dp/dx` and `dp/dy`, per metre.
    pub gradient: [f64; 2],
}

/// The occupancy of `grid` at world point `(x, y)` (metres), interpolated
/// between the four cell centres around it; `None` where the four do not
/// all lie inside the map.
pub fn bilinear<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    x: f64,
    y: f64,
) -> Option<Sample> {
    let g = grid.geometry();
    let (u, v) = g.world_to_grid(x, y);
    // Cell centres sit at half-integers of grid coordinates.
    let (u, v) = (u - 0.5, v - 0.5);
    if !(u >= 0.0 && v >= 0.0) {
        return None;
    }
    let (ix, iy) = (u.floor() as usize, v.floor() as usize);
    let (fx, fy) = (u - ix as f64, v - iy as f64);
    let m = grid.model();
    let p = |cx: usize, cy: usize| -> Option<f64> { Some(m.probability(grid.cell_at(cx, cy)?)) };
    let (p00, p10) = (p(ix, iy)?, p(ix + 1, iy)?);
    let (p01, p11) = (p(ix, iy + 1)?, p(ix + 1, iy + 1)?);
    let bottom = p00 + fx * (p10 - p00);
    let top = p01 + fx * (p11 - p01);
    let per_metre = 1.0 / g.resolution();
    Some(Sample {
        p: bottom + fy * (top - bottom),
        gradient: [
            ((1.0 - fy) * (p10 - p00) + fy * (p11 - p01)) * per_metre,
            (top - bottom) * per_metre,
        ],
    })
}

/// A smooth reading of cell values at grid coordinates `(u, v)` (cells
/// from the grid's lower-left corner, cell `(i, j)` centred at `(i + 0.5,
/// j + 0.5)`): the quadratic B-spline of the values, `value(i, j)` read for
/// the 3 x 3 cells around the nearest centre. It returns the value and its
/// gradient per cell.
///
/// Bilinear interpolation peaks only at cell centres and is flat along a
/// run of equal cells, so a scan fitted to it snaps to the centres of the
/// cells its wall fills (up to half a cell off, a different half cell for
/// each scan) and slides freely along a wall two cells thick. The
/// quadratic B-spline is smooth (continuous slope), peaks in the middle of
/// such a run, and reaches half a cell further on each side, a wider
/// basin for Gauss–Newton to climb (Cartographer's scan matcher reads its
/// grid through a smooth cubic for the same reasons). It does not pass
/// through the values: a lone wall cell reads 0.56 of its value at its
/// centre, a straight wall of one cell's thickness 0.75.
pub fn quadratic_bspline(
    u: f64,
    v: f64,
    mut value: impl FnMut(i64, i64) -> f64,
) -> (f64, [f64; 2]) {
    quadratic_bspline_of_patch(u, v, |i, j| {
        // (Saturating: a point absurdly far away reads the cells at the
        // end of the index range, outside any map.)
        let mut patch = [[0.0; 3]; 3];
        for (b, row) in patch.iter_mut().enumerate() {
            for (a, c) in row.iter_mut().enumerate() {
                *c = value(
                    i.saturating_add(a as i64 - 1),
                    j.saturating_add(b as i64 - 1),
                );
            }
        }
        patch
    })
}

/// [`quadratic_bspline`] with the 3 x 3 values read at once: `patch(i,
/// j)` gives the values of the cells around cell `(i, j)`, `[b][a]` that
/// of cell `(i + a - 1, j + b - 1)`, so that a reader finds their storage
/// once rather than once a cell. The same arithmetic in the same order.
pub fn quadratic_bspline_of_patch(
    u: f64,
    v: f64,
    patch: impl FnOnce(i64, i64) -> [[f64; 3]; 3],
) -> (f64, [f64; 2]) {
    let (tu, tv) = (u - 0.5, v - 0.5);
    let (i, j) = (tu.round(), tv.round());
    let (wu, du) = bspline_weights(tu - i);
    let (wv, dv) = bspline_weights(tv - j);
    let values = patch(i as i64, j as i64);
    let (mut f, mut gx, mut gy) = (0.0, 0.0, 0.0);
    for (b, cells) in values.iter().enumerate() {
        let (mut row, mut row_dx) = (0.0, 0.0);
        for (a, &c) in cells.iter().enumerate() {
            row += wu[a] * c;
            row_dx += du[a] * c;
        }
        f += wv[b] * row;
        gx += wv[b] * row_dx;
        gy += dv[b] * row;
    }
    (f, [gx, gy])
}

/// The quadratic B-spline's weights of the cells at offsets -1, 0 and 1
/// from a point `d` cells from the nearest centre (`|d| <= 0.5`), and
/// their derivatives in `d`.
#[inline]
fn bspline_weights(d: f64) -> ([f64; 3], [f64; 3]) {
    let (l, r) = (0.5 - d, 0.5 + d);
    ([0.5 * l * l, 0.75 - d * d, 0.5 * r * r], [-l, -2.0 * d, r])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::grid::{FilterSettings, LogOddsGrid, TiledGrid};

    /// A map whose cells rise in probability from west to east is read as
    /// the same slope between cell centres, exactly at a centre, and alike
    /// from a dense and a tiled store.
    #[test]
    fn bilinear_reads_cell_centres_exactly_and_slopes_between_them() {
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 12.0,
        };
        let g = GridGeometry::new(8, 4, 0.5, -2.0, 0.0).unwrap();
        let mut dense = LogOddsGrid::new(g, settings).unwrap();
        let mut tiled = TiledGrid::new(
            GridGeometry::sparse(8, 4, 0.5, -2.0, 0.0).unwrap(),
            settings,
            1 << 20,
        )
        .unwrap();
        for iy in 0..4 {
            for ix in 0..8 {
                let l = (ix as f32 - 3.5) * 0.4;
                dense.apply_at(ix, iy, l);
                tiled.apply_at(ix, iy, l);
            }
        }
        let (cx, cy) = g.cell_center(2, 1);
        let at_centre = bilinear(&dense, cx, cy).unwrap();
        assert!((at_centre.p - dense.probability_at(g.index(2, 1))).abs() < 1e-12);
        let mid = bilinear(&dense, cx + 0.25, cy).unwrap();
        let (a, b) = (
            dense.probability_at(g.index(2, 1)),
            dense.probability_at(g.index(3, 1)),
        );
        assert!((mid.p - (a + b) / 2.0).abs() < 1e-12);
        assert!((mid.gradient[0] - (b - a) / 0.5).abs() < 1e-9);
        assert!(mid.gradient[1].abs() < 1e-12);
        assert_eq!(bilinear(&tiled, cx + 0.25, cy), Some(mid));
        assert_eq!(
            bilinear(&dense, -1.9, 0.1),
            None,
            "west of the first centre"
        );
        assert_eq!(bilinear(&dense, 1.9, 1.0), None, "east of the last centre");
    }

    /// The smooth reading of a wall two cells thick peaks between the two
    /// cells, where bilinear interpolation is flat; its weights sum to one
    /// and its slope is the value's derivative.
    #[test]
    fn the_quadratic_bspline_peaks_in_the_middle_of_a_thick_wall() {
        let wall = |i: i64, _j: i64| if i == 3 || i == 4 { 1.0 } else { 0.0 };
        let at = |u: f64| quadratic_bspline(u, 7.3, wall);
        // Cells 3 and 4 are centred at 3.5 and 4.5: the middle is 4.0.
        let (peak, g) = at(4.0);
        assert!((peak - 1.0).abs() < 1e-12 && g[0].abs() < 1e-12 && g[1].abs() < 1e-12);
        for u in [3.5, 3.7, 4.3, 4.5] {
            assert!(at(u).0 < peak, "{u}");
        }
        assert!(
            at(3.7).1[0] > 0.0 && at(4.3).1[0] < 0.0,
            "it climbs to the middle"
        );
        let h = 1e-6;
        for u in [2.2, 3.1, 3.6, 4.05, 4.9, 5.4] {
            let slope = (at(u + h).0 - at(u - h).0) / (2.0 * h);
            assert!((slope - at(u).1[0]).abs() < 1e-5, "{u}");
        }
        let (one, flat) = quadratic_bspline(2.9, -4.4, |_, _| 1.0);
        assert!((one - 1.0).abs() < 1e-12 && flat[0].abs() < 1e-12 && flat[1].abs() < 1e-12);
        // Absurdly far away: read, not a panic.
        let (far, _) = quadratic_bspline(1e300, -1e300, |i, j| (i > 0 && j < 0) as u8 as f64);
        assert!((far - 1.0).abs() < 1e-12);
    }
}
