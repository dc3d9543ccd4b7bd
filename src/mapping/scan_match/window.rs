//! The coarse levels a match runs on: the part of the map around a scan,
//! copied into small dense arrays in which each cell holds the most
//! occupied of the `factor x factor` map cells it covers (Olson 2009's
//! low-resolution table: a wall anywhere in a coarse cell makes the whole
//! coarse cell a wall, so a search that steps one coarse cell at a time
//! cannot step over it). Level `factor 2^k` is pooled from level
//! `2^(k-1)`, the first from the map itself, so the whole pyramid costs
//! one read of the map cells under the scan.
//!
//! A level is read like the map ([`crate::grid::sample`]): interpolated
//! bilinearly between cell centres, with its gradient. What is
//! interpolated is each cell's [`match_value`], not its probability.

use super::match_map::MatchMap;
use crate::grid::larger;

/// What a cell of log odds `l` is worth to a match: how sure the map is
/// that a wall is there, `max(0, 2 p - 1) = max(0, tanh((l - l_u) / 2))`
/// with `l_u` the unknown cell's log odds — 0 for free and unknown cells
/// alike, 0.4 for a cell one hit of the real-log model has marked, 0.94 at
/// its clamp. Reading the probability itself (Hector SLAM's choice) would
/// score a point in unknown space at 0.5, above a point on a cell seen
/// free once (0.4 under the real-log weights): a young map would then pull
/// a scan off the walls it shares with the map and into space the map has
/// not seen (Cartographer scores unknown cells at its lowest probability
/// for the same reason).
///
/// (Computed as tanh's [3/2] Padé approximant `x (15 + x^2) / (15 +
/// 6 x^2)`, `x = d / 2`, capped at 1: increasing like tanh, within 0.006
/// of it up to the real-log clamp, and free of a library call on each of
/// the hundreds of thousands of cells a match reads per scan.)
#[inline]
pub fn match_value(l: f32, l_unknown: f32) -> f64 {
    let x = 0.5 * (l - l_unknown) as f64;
    if x > 0.0 {
        let x2 = x * x;
        // (Not `f64::min`: a call in wasm, see [`larger`]; a NaN, from an
        // infinite `l`, reads 1 either way.)
        let v = x * (15.0 + x2) / (15.0 + 6.0 * x2);
        if v < 1.0 {
            v
        } else {
            1.0
        }
    } else {
        0.0
    }
}

/// One coarse level over a window of the map.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PooledLevel {
    /// Map cells per coarse cell along x and y.
    factor: usize,
    /// Metres per coarse cell.
    cell: f64,
    /// World position of the window's lower-left corner, metres.
    origin: [f64; 2],
    nx: usize,
    ny: usize,
    /// The most occupied log odds of each coarse cell, row-major from the
    /// bottom row.
    log_odds: Vec<f32>,
    /// The [`match_value`] of each coarse cell, filled only for the level
    /// a search scores on (it reads every cell hundreds of times; the
    /// other levels read a few thousand and convert as they go).
    values: Vec<f32>,
    /// The unknown cell's log odds.
    l_unknown: f32,
}

/// The interpolated match value at a point and its gradient (per metre).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSample {
    /// [`match_value`], 0 to 1.
    pub value: f64,
    /// `d value / dx` and `d value / dy`, per metre.
    pub gradient: [f64; 2],
}

impl PooledLevel {
    pub fn factor(&self) -> usize {
        self.factor
    }
    /// Metres per coarse cell.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }
    /// Coarse cells along x and y.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    /// World position of the window's lower-left corner, metres.
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    /// The match value of every cell, row-major from the bottom row
    /// (filled by [`Pyramid::build`] for the coarsest level only).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The pooled log odds of coarse cell `(i, j)`, `None` outside.
    pub fn log_odds_at(&self, i: usize, j: usize) -> Option<f32> {
        (i < self.nx && j < self.ny).then(|| self.log_odds[j * self.nx + i])
    }

    /// The match value at world point `(x, y)`, bilinear between the
    /// centres of the four coarse cells around it; 0, with no slope, where
    /// they do not all lie in the window.
    pub fn sample(&self, x: f64, y: f64) -> FieldSample {
        let u = (x - self.origin[0]) / self.cell - 0.5;
        let v = (y - self.origin[1]) / self.cell - 0.5;
        let flat = FieldSample {
            value: 0.0,
            gradient: [0.0; 2],
        };
        if !(u >= 0.0 && v >= 0.0) {
            return flat;
        }
        let (i, j) = (u as usize, v as usize);
        if i + 1 >= self.nx || j + 1 >= self.ny {
            return flat;
        }
        let (fx, fy) = (u - i as f64, v - j as f64);
        let k = j * self.nx + i;
        let v = |k: usize| match_value(self.log_odds[k], self.l_unknown);
        let (p00, p10, p01, p11) = (v(k), v(k + 1), v(k + self.nx), v(k + self.nx + 1));
        let bottom = p00 + fx * (p10 - p00);
        let top = p01 + fx * (p11 - p01);
        let per_metre = 1.0 / self.cell;
        FieldSample {
            value: bottom + fy * (top - bottom),
            gradient: [
                ((1.0 - fy) * (p10 - p00) + fy * (p11 - p01)) * per_metre,
                (top - bottom) * per_metre,
            ],
        }
    }
}

/// The coarse levels of one match: factors 2, 4, … up to the search's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pyramid {
    levels: Vec<PooledLevel>,
}

impl Pyramid {
    /// The level of `factor` map cells per cell, once built.
    pub fn level(&self, factor: usize) -> Option<&PooledLevel> {
        self.levels.iter().find(|l| l.factor == factor)
    }

    /// Map cells read by the last build (its work).
    pub fn cells_read(&self) -> usize {
        self.levels
            .first()
            .map_or(0, |l| l.nx * l.ny * l.factor * l.factor)
    }

    /// Copies the map cells `[ix0, ix1) x [iy0, iy1)` (cell indices, which
    /// may reach past the map: those cells are unknown) into levels of
    /// factor 2, 4, … up to `coarsest` (a power of two; nothing for 1),
    /// the box widened to whole cells of the coarsest level, aligned on
    /// the map's own cell 0 so that a coarse cell always covers the same
    /// map cells. The coarsest level's match values are filled.
    pub fn build(&mut self, grid: &dyn MatchMap, [ix0, iy0, ix1, iy1]: [i64; 4], coarsest: usize) {
        let kept = coarsest.max(1).trailing_zeros() as usize;
        self.levels.resize_with(kept, PooledLevel::default);
        if kept == 0 {
            return;
        }
        let f = coarsest as i64;
        let (ix0, iy0) = (ix0.div_euclid(f) * f, iy0.div_euclid(f) * f);
        let (ix1, iy1) = (
            (ix1.max(ix0 + 1) + f - 1).div_euclid(f) * f,
            (iy1.max(iy0 + 1) + f - 1).div_euclid(f) * f,
        );
        let g = grid.geometry();
        let res = g.resolution();
        let origin = [
            g.origin()[0] + ix0 as f64 * res,
            g.origin()[1] + iy0 as f64 * res,
        ];
        let unknown_l = grid.unknown_log_odds();
        for (k, level) in self.levels.iter_mut().enumerate() {
            let factor = 2usize << k;
            level.factor = factor;
            level.cell = res * factor as f64;
            level.origin = origin;
            level.nx = ((ix1 - ix0) / factor as i64) as usize;
            level.ny = ((iy1 - iy0) / factor as i64) as usize;
            level.l_unknown = unknown_l;
            level.values.clear();
        }
        Self::pool_map(&mut self.levels[0], grid, [ix0, iy0, ix1, iy1], unknown_l);
        for k in 1..kept {
            let (finer, coarser) = self.levels.split_at_mut(k);
            Self::pool_level(&finer[k - 1], &mut coarser[0]);
        }
        if let Some(top) = self.levels.last_mut() {
            let lu = top.l_unknown;
            top.values.clear();
            top.values
                .extend(top.log_odds.iter().map(|&l| match_value(l, lu) as f32));
        }
    }

    /// The first level, pooled 2 x 2 from the map's cells.
    fn pool_map(
        level: &mut PooledLevel,
        grid: &dyn MatchMap,
        [ix0, iy0, ix1, iy1]: [i64; 4],
        unknown_l: f32,
    ) {
        let g = grid.geometry();
        let (w, h) = (g.width() as i64, g.height() as i64);
        let nx = level.nx;
        level.log_odds.clear();
        // A coarse cell that reaches past the map holds an unknown cell.
        for j in 0..level.ny as i64 {
            let fy = iy0 + 2 * j;
            for i in 0..nx as i64 {
                let fx = ix0 + 2 * i;
                let inside = fx >= 0 && fy >= 0 && fx + 2 <= w && fy + 2 <= h;
                level
                    .log_odds
                    .push(if inside { f32::NEG_INFINITY } else { unknown_l });
            }
        }
        let (cx0, cy0) = (ix0.max(0), iy0.max(0));
        let (cx1, cy1) = (ix1.min(w), iy1.min(h));
        if cx0 < cx1 && cy0 < cy1 {
            grid.pool_pairs(
                [cx0 as usize, cy0 as usize, cx1 as usize, cy1 as usize],
                [ix0, iy0],
                nx,
                &mut level.log_odds,
            );
        }
    }

    /// `coarser` pooled 2 x 2 from `finer` (same window).
    fn pool_level(finer: &PooledLevel, coarser: &mut PooledLevel) {
        let fx = finer.nx;
        coarser.log_odds.clear();
        for j in 0..coarser.ny {
            let (r0, r1) = (2 * j * fx, (2 * j + 1) * fx);
            for i in 0..coarser.nx {
                let c = 2 * i;
                let l = larger(
                    larger(finer.log_odds[r0 + c], finer.log_odds[r0 + c + 1]),
                    larger(finer.log_odds[r1 + c], finer.log_odds[r1 + c + 1]),
                );
                coarser.log_odds.push(l);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;

    /// The match value is `2 p - 1` above the prior to within 0.006 over
    /// the real-log range of log odds, rises with them, and is 0 at
    /// and below the prior.
    #[test]
    fn the_match_value_is_twice_the_probability_less_one_above_the_prior() {
        let mut last = 0.0;
        for k in 1..=400 {
            let l = k as f32 * 0.01;
            let v = match_value(l, 0.0);
            let exact = 2.0 * crate::grid::probability(l as f64) - 1.0;
            if l <= 3.5 {
                assert!((v - exact).abs() < 0.006, "{l}: {v} against {exact}");
            }
            assert!(v >= last && v <= 1.0);
            last = v;
        }
        assert_eq!(match_value(-2.0, 0.0), 0.0);
        assert_eq!(match_value(0.3, 0.3), 0.0);
        assert_eq!(match_value(1.25, 0.25), match_value(1.0, 0.0));
    }
    use crate::grid::{FilterSettings, LogOddsGrid, TiledGrid};

    /// One occupied cell makes its whole coarse cell occupied at every
    /// level, and cells past the map's edge read as unknown, alike from a
    /// dense and a tiled store.
    #[test]
    fn a_wall_cell_fills_its_coarse_cell_and_the_map_edge_is_unknown() {
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 3.5,
        };
        // An odd width: the last column pairs with a cell past the map.
        let g = GridGeometry::new(69, 40, 0.05, -1.0, -1.0).unwrap();
        let mut dense = LogOddsGrid::new(g, settings).unwrap();
        let mut tiled = TiledGrid::new(
            GridGeometry::sparse(69, 40, 0.05, -1.0, -1.0).unwrap(),
            settings,
            1 << 20,
        )
        .unwrap();
        for iy in 0..40 {
            for ix in 0..69 {
                let l = if (ix, iy) == (65, 9) { 3.0 } else { -2.0 };
                dense.apply_at(ix, iy, l);
                tiled.apply_at(ix, iy, l);
            }
        }
        let (mut a, mut b) = (Pyramid::default(), Pyramid::default());
        a.build(&dense, [-3, 2, 75, 30], 4);
        b.build(&tiled, [-3, 2, 75, 30], 4);
        assert_eq!(a, b);
        let four = a.level(4).unwrap();
        // The box widened to multiples of 4: x from -4, y from 0.
        assert_eq!(four.size(), (20, 8));
        assert_eq!(four.log_odds_at((65 + 4) / 4, 9 / 4), Some(3.0));
        assert_eq!(four.log_odds_at(10, 4), Some(-2.0));
        assert_eq!(four.log_odds_at(0, 0), Some(0.0), "west of the map");
        let two = a.level(2).unwrap();
        assert_eq!(two.log_odds_at((65 + 4) / 2, 9 / 2), Some(3.0));
        assert_eq!(two.log_odds_at((66 + 4) / 2, 20 / 2), Some(-2.0));
        assert_eq!(
            two.log_odds_at((68 + 4) / 2, 20 / 2),
            Some(0.0),
            "the last column beside the edge"
        );
        let v = four.values()[2 * 20 + (65 + 4) / 4];
        assert!((v as f64 - (2.0 * crate::grid::probability(3.0) - 1.0)).abs() < 0.01);
        assert_eq!(four.values()[4 * 20 + 10], 0.0, "free");
        assert_eq!(four.values()[0], 0.0, "unknown");
        assert!(a.level(8).is_none());
    }
}
