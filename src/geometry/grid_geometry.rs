//! The map's limits: size, resolution, and where cell (0, 0) lies in the
//! world. World ↔ cell conversion lives here, below every layer that needs
//! it (the ground truth, the mappers, the renderers, the log reader).

use crate::error::{self, invalid, Result};

/// The largest dense map the core accepts, in cells (4096 x 4096). Larger
/// dense grids would not fit a browser tab's memory with their render
/// buffers.
pub const MAX_CELLS: usize = 1 << 24;

/// The largest extent of a sparse (tiled) map, in cells: its export is one
/// byte per cell (a 256 MiB PGM), and every reader of the map can still
/// index it with 32 bits.
pub const MAX_SPARSE_CELLS: usize = 1 << 28;

/// Where the map lies in the world: `width x height` square cells of
/// `resolution` metres, cell (0, 0)'s lower-left corner at `origin`.
/// Rows are stored bottom to top (y grows north), each row west to east.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GridGeometry {
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 2],
}

impl GridGeometry {
    /// The limits of a dense map: at most [`MAX_CELLS`] cells.
    pub fn new(
        width: usize,
        height: usize,
        resolution: f64,
        origin_x: f64,
        origin_y: f64,
    ) -> Result<Self> {
        Self::check_size(width, height)?;
        match width.checked_mul(height) {
            Some(n) if n <= MAX_CELLS => {}
            _ => {
                return Err(invalid(
                    "width x height",
                    format!("{width} x {height}"),
                    "at most 16777216 cells",
                ))
            }
        }
        Self::finish(width, height, resolution, origin_x, origin_y)
    }

    /// The limits of a sparse map, whose cells exist only where they are
    /// touched: at most [`MAX_SPARSE_CELLS`] cells, refused saying how many
    /// it would be and what its export would weigh.
    pub fn sparse(
        width: usize,
        height: usize,
        resolution: f64,
        origin_x: f64,
        origin_y: f64,
    ) -> Result<Self> {
        Self::check_size(width, height)?;
        let cells = width as u128 * height as u128;
        if cells > MAX_SPARSE_CELLS as u128 {
            return Err(invalid(
                "width x height",
                format!(
                    "{width} x {height} = {cells} cells ({:.1} MiB of exported image)",
                    cells as f64 / (1u64 << 20) as f64
                ),
                "at most 268435456 cells (a 256 MiB image): a coarser resolution",
            ));
        }
        Self::finish(width, height, resolution, origin_x, origin_y)
    }

    fn check_size(width: usize, height: usize) -> Result<()> {
        if width == 0 {
            return Err(invalid("width", width, "at least 1 cell"));
        }
        if height == 0 {
            return Err(invalid("height", height, "at least 1 cell"));
        }
        Ok(())
    }

    fn finish(
        width: usize,
        height: usize,
        resolution: f64,
        origin_x: f64,
        origin_y: f64,
    ) -> Result<Self> {
        error::positive("resolution", resolution)?;
        error::finite("origin_x", origin_x)?;
        error::finite("origin_y", origin_y)?;
        // The far corner must be finite too, or world<->cell arithmetic
        // produces infinities.
        error::finite(
            "origin_x + width * resolution",
            origin_x + width as f64 * resolution,
        )?;
        error::finite(
            "origin_y + height * resolution",
            origin_y + height as f64 * resolution,
        )?;
        Ok(Self {
            width,
            height,
            resolution,
            origin: [origin_x, origin_y],
        })
    }

    /// A grid covering the box `[min_x, max_x) x [min_y, max_y)` in metres.
    pub fn covering(
        min_x: f64,
        min_y: f64,
        max_x: f64,
        max_y: f64,
        resolution: f64,
    ) -> Result<Self> {
        error::positive("resolution", resolution)?;
        for (field, v) in [
            ("min_x", min_x),
            ("min_y", min_y),
            ("max_x", max_x),
            ("max_y", max_y),
        ] {
            error::finite(field, v)?;
        }
        if max_x <= min_x {
            return Err(invalid("max_x", max_x, "greater than min_x"));
        }
        if max_y <= min_y {
            return Err(invalid("max_y", max_y, "greater than min_y"));
        }
        let w = ((max_x - min_x) / resolution).ceil();
        let h = ((max_y - min_y) / resolution).ceil();
        if w * h > MAX_CELLS as f64 {
            return Err(invalid(
                "width x height",
                format!("{w} x {h}"),
                "at most 16777216 cells",
            ));
        }
        Self::new(w as usize, h as usize, resolution, min_x, min_y)
    }

    pub fn width(&self) -> usize {
        self.width
    }
    pub fn height(&self) -> usize {
        self.height
    }
    pub fn len(&self) -> usize {
        self.width * self.height
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Metres per cell.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }
    /// World position (metres) of cell (0, 0)'s lower-left corner.
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }

    /// Row-major index of cell `(ix, iy)`; the caller guarantees it is inside.
    #[inline]
    pub fn index(&self, ix: usize, iy: usize) -> usize {
        iy * self.width + ix
    }

    /// The cell of index `i` as `(ix, iy)`.
    #[inline]
    pub fn cell_of_index(&self, i: usize) -> (usize, usize) {
        (i % self.width, i / self.width)
    }

    /// The cell containing world point `(x, y)`, or `None` when the point is
    /// outside the map (never clamped to the border: a beam endpoint outside
    /// the map is not evidence about the border cell).
    pub fn world_to_cell(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let u = (x - self.origin[0]) / self.resolution;
        let v = (y - self.origin[1]) / self.resolution;
        if !(u >= 0.0 && v >= 0.0) {
            return None; // also rejects NaN
        }
        let (ix, iy) = (u.floor() as usize, v.floor() as usize);
        (ix < self.width && iy < self.height).then_some((ix, iy))
    }

    /// World point to image units: `u` columns from the left edge, `v` rows
    /// from the top edge of the north-up image the renderers draw (row 0 is
    /// the grid's last row), one unit per cell. Every overlay a widget draws
    /// over a map comes through here, so JavaScript never flips an axis.
    pub fn world_to_image(&self, x: f64, y: f64) -> [f64; 2] {
        let (u, v) = self.world_to_grid(x, y);
        [u, self.height as f64 - v]
    }

    /// A world box `[min_x, min_y, max_x, max_y]` in image units,
    /// `[u0, v0, u1, v1]` with `u0 <= u1` and `v0 <= v1`.
    pub fn box_to_image(&self, min_x: f64, min_y: f64, max_x: f64, max_y: f64) -> [f64; 4] {
        let [u0, v1] = self.world_to_image(min_x, min_y);
        let [u1, v0] = self.world_to_image(max_x, max_y);
        [u0, v0, u1, v1]
    }

    /// The cell `(ix, iy)` under image pixel `(col, row)` of the north-up
    /// image, or `None` outside the map.
    pub fn image_pixel_to_cell(&self, col: usize, row: usize) -> Option<(usize, usize)> {
        (col < self.width && row < self.height).then(|| (col, self.height - 1 - row))
    }

    /// World position of the centre of cell `(ix, iy)`, in metres.
    #[inline]
    pub fn cell_center(&self, ix: usize, iy: usize) -> (f64, f64) {
        (
            self.origin[0] + (ix as f64 + 0.5) * self.resolution,
            self.origin[1] + (iy as f64 + 0.5) * self.resolution,
        )
    }

    /// World point to continuous grid coordinates (cell units, cell (i, j)
    /// spans `[i, i+1) x [j, j+1)`).
    #[inline]
    pub fn world_to_grid(&self, x: f64, y: f64) -> (f64, f64) {
        (
            (x - self.origin[0]) / self.resolution,
            (y - self.origin[1]) / self.resolution,
        )
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> GridGeometry {
        GridGeometry::new(4, 3, 0.5, -1.0, 2.0).unwrap()
    }

    #[test]
    fn world_to_cell_says_outside_instead_of_clamping() {
        let g = geometry();
        assert_eq!(g.world_to_cell(-1.0, 2.0), Some((0, 0)));
        assert_eq!(g.world_to_cell(0.99, 3.49), Some((3, 2)));
        assert_eq!(g.world_to_cell(1.0, 2.2), None, "east border is outside");
        assert_eq!(g.world_to_cell(-1.01, 2.2), None);
        assert_eq!(g.world_to_cell(0.0, 3.5), None, "north border is outside");
        assert_eq!(g.world_to_cell(f64::NAN, 2.2), None);
        let (x, y) = g.cell_center(3, 2);
        assert_eq!(g.world_to_cell(x, y), Some((3, 2)));
    }
}
