//! Simulated worlds: ground truth as a binary grid, and an exact ray caster.
//!
//! Every scene of the chapter (the apartment, the doorway, the table) is a
//! [`World`]: a binary occupancy grid built from axis-aligned boxes, with
//! the same limits as the maps built from it, so a Brier score compares cell
//! with cell. Scenes are data (serde), and everything random in them is
//! seeded.

use crate::error::{self, Result};
use crate::geometry::raster::{entry_parameter, first_cell};
use crate::geometry::GridGeometry;

/// An axis-aligned box in world coordinates, metres.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rect {
    pub min_x: f64,
    pub min_y: f64,
    pub max_x: f64,
    pub max_y: f64,
}

impl Rect {
    pub const fn new(min_x: f64, min_y: f64, max_x: f64, max_y: f64) -> Self {
        Self {
            min_x,
            min_y,
            max_x,
            max_y,
        }
    }
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.min_x && x < self.max_x && y >= self.min_y && y < self.max_y
    }

    /// The columns and rows of `g` whose cell centres may lie in the box:
    /// from the cell holding its lower bound to the one holding its upper
    /// bound, clipped to the map (a superset; [`Rect::contains`] decides).
    /// A NaN bound gives an empty span, an infinite one the whole map.
    pub fn cells_under(
        &self,
        g: &GridGeometry,
    ) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let [ox, oy] = g.origin();
        let res = g.resolution();
        let span = |lo: f64, hi: f64, origin: f64, n: usize| {
            let first = ((lo - origin) / res).floor().max(0.0) as usize;
            let end = (((hi - origin) / res).ceil().max(0.0) as usize).min(n);
            first..end
        };
        (
            span(self.min_x, self.max_x, ox, g.width()),
            span(self.min_y, self.max_y, oy, g.height()),
        )
    }
}

/// Ground truth: which cells are occupied.
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    geometry: GridGeometry,
    occupied: Vec<bool>,
}

impl World {
    /// An empty (all free) world.
    pub fn empty(geometry: GridGeometry) -> Self {
        Self {
            geometry,
            occupied: vec![false; geometry.len()],
        }
    }

    /// A world whose occupied cells are those whose centres lie in one of
    /// `boxes`.
    pub fn from_boxes(geometry: GridGeometry, boxes: &[Rect]) -> Self {
        let mut w = Self::empty(geometry);
        for b in boxes {
            w.fill(b, true);
        }
        w
    }

    /// Sets every cell whose centre lies in `rect` to `occupied`.
    pub fn fill(&mut self, rect: &Rect, occupied: bool) {
        self.fill_rows(rect, occupied, 0..self.geometry.height());
    }

    /// [`World::fill`] over the rows `rows` only (clipped to the map): a
    /// large world is drawn a band of rows at a time this way, and bands
    /// that cover the map leave it as one `fill` does. Only the cells under
    /// the box's bounds are looked at ([`Rect::cells_under`]; `contains`
    /// decides, as for every cell), so a box costs its own cells, not the
    /// map's.
    pub fn fill_rows(&mut self, rect: &Rect, occupied: bool, rows: std::ops::Range<usize>) {
        let g = self.geometry;
        let (xs, ys) = rect.cells_under(&g);
        let ys = ys.start.max(rows.start)..ys.end.min(rows.end);
        for iy in ys {
            for ix in xs.clone() {
                let (x, y) = g.cell_center(ix, iy);
                if rect.contains(x, y) {
                    self.occupied[g.index(ix, iy)] = occupied;
                }
            }
        }
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// Occupancy of every cell, row-major from the bottom row.
    pub fn occupied(&self) -> &[bool] {
        &self.occupied
    }
    pub fn occupied_mut(&mut self) -> &mut [bool] {
        &mut self.occupied
    }
    pub fn is_occupied(&self, ix: usize, iy: usize) -> bool {
        self.occupied[self.geometry.index(ix, iy)]
    }

    /// The range (metres) from `(x, y)` along world angle `angle` to the
    /// boundary of the first occupied cell, or `z_max` if there is none
    /// within `z_max` (leaving the map counts as no return). A start inside
    /// an occupied cell reads 0.
    pub fn cast(&self, x: f64, y: f64, angle: f64, z_max: f64) -> f64 {
        let (s, c) = angle.sin_cos();
        self.cast_along(x, y, (c, s), z_max)
    }

    /// [`Self::cast`] along the unit vector `dir` instead of an angle:
    /// callers that draw directions without angles (the training sampler)
    /// save the trigonometry, which is slow in wasm. The walk is the
    /// supercover raster's, corners included, and stops at the first
    /// occupied cell: in a cluttered room most rays end within a few metres.
    pub fn cast_along(&self, x: f64, y: f64, (c, s): (f64, f64), z_max: f64) -> f64 {
        let g = &self.geometry;
        let res = g.resolution();
        let (su, sv) = g.world_to_grid(x, y);
        let end = (su + z_max * c / res, sv + z_max * s / res);
        let width = g.width();
        let hit = first_cell(width, g.height(), (su, sv), end, |ix, iy| {
            self.occupied[iy * width + ix]
        });
        let Some((ix, iy)) = hit else { return z_max };
        let t_in = entry_parameter(ix, iy, (su, sv), (c, s));
        (t_in * res).min(z_max)
    }

    /// The range (metres) to the nearest occupied cell inside a cone of
    /// half-angle `half_width` around `angle`, from `sub_rays` rays spread
    /// evenly across it (Table 6.1: a cone's expected range).
    pub fn cast_cone(
        &self,
        x: f64,
        y: f64,
        angle: f64,
        half_width: f64,
        sub_rays: usize,
        z_max: f64,
    ) -> Result<f64> {
        error::non_negative("half_width", half_width)?;
        if sub_rays == 0 {
            return Err(error::invalid("sub_rays", 0, "at least 1 ray"));
        }
        let n = sub_rays.max(1);
        Ok((0..n)
            .map(|k| {
                let f = if n == 1 {
                    0.0
                } else {
                    -1.0 + 2.0 * k as f64 / (n - 1) as f64
                };
                self.cast(x, y, angle + f * half_width, z_max)
            })
            .fold(z_max, f64::min))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> World {
        let g = GridGeometry::new(40, 20, 0.1, 0.0, 0.0).unwrap();
        World::from_boxes(g, &[Rect::new(3.0, 0.0, 3.1, 2.0)])
    }

    #[test]
    fn cast_hits_the_near_face_of_a_wall() {
        let w = world();
        let z = w.cast(1.05, 1.05, 0.0, 8.0);
        assert!((z - 1.95).abs() < 1e-9, "{z}");
        let z = w.cast(1.05, 1.05, std::f64::consts::PI, 8.0);
        assert_eq!(z, 8.0, "no wall behind: max range");
        let slanted = w.cast(1.0, 1.0, 0.3, 8.0);
        assert!((slanted - 2.0 / 0.3f64.cos()).abs() < 0.11, "{slanted}");
    }

    #[test]
    fn cone_sees_the_nearest_obstacle_inside_it() {
        let mut w = world();
        w.fill(&Rect::new(2.0, 1.2, 2.1, 1.3), true); // a post off the axis
        let axis = w.cast(1.05, 1.05, 0.0, 8.0);
        let cone = w.cast_cone(1.05, 1.05, 0.0, 0.3, 9, 8.0).unwrap();
        assert!(cone < axis - 0.5, "{cone} vs {axis}");
        assert!(w.cast_cone(1.0, 1.0, 0.0, 0.2, 0, 8.0).is_err());
    }
}
