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
}
