//! The ray-to-cell raster: which cells a beam passes through.
//!
//! A supercover line after Amanatides & Woo's traversal ("A Fast Voxel
//! Traversal Algorithm for Ray Tracing", 1987): the walk steps from cell to
//! cell at each grid-line crossing, so it visits every cell the segment
//! touches, and its cost is the number of cells crossed, not the map size.
//! Where the segment passes exactly through a cell corner, both cells beside
//! the corner are visited too: otherwise free space would leak diagonally
//! between two wall cells that touch only at that corner.
//!
//! [`Walk`] is the traversal itself, split as in the paper into an
//! initialization phase ([`Walk::new`]: clip, first crossings, how many
//! crossings lie ahead on each axis) and an incremental phase
//! ([`Walk::run`]: one comparison per step tells which axis is crossed
//! next). It only says *which way* to move; a [`Cursor`] owned by the caller
//! keeps whatever it needs per cell (the cell's coordinates for
//! [`supercover`], a linear index and a range along the beam for the
//! mapper), updated by one addition per step instead of being recomputed.
//!
//! Coordinates are continuous grid coordinates (cell `(i, j)` spans
//! `[i, i+1) x [j, j+1)`), see [`crate::grid::GridGeometry::world_to_grid`].

/// Crossings closer than this (in units of the segment's parameter) count
/// as one corner crossing.
const CORNER_EPS: f64 = 1e-9;

/// What a caller keeps while a [`Walk`] runs. The walk starts the cursor on
/// the first cell and then only tells it to move to an edge neighbour and
/// to visit the cell it stands on; every move stays inside the grid.
pub trait Cursor {
    /// The cursor's cell is on the segment.
    fn visit(&mut self);
    /// Move one cell along x, in the segment's x direction.
    fn step_x(&mut self);
    /// Move one cell along y, in the segment's y direction.
    fn step_y(&mut self);
    /// Move one cell along x *against* the segment's x direction (only at
    /// an exact corner, to go from the first side cell to the second).
    fn unstep_x(&mut self);
}

/// A segment clipped to the grid, ready to be walked (Amanatides & Woo's
/// initialization phase). All fields are in cells or in units of the
/// segment's parameter `t` (0 at `a`, 1 at `b`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Walk {
    /// The first cell: the one holding the clipped start.
    pub start: (usize, usize),
    /// Step direction per axis, +1 or -1.
    pub step: (i8, i8),
    /// Parameter of the first grid-line crossing on each axis (infinite
    /// when the axis has no crossing ahead).
    t_max: (f64, f64),
    /// Parameter distance between two crossings on each axis.
    t_delta: (f64, f64),
    /// Crossings ahead on each axis before the clipped end: the walk makes
    /// exactly this many steps per axis, so it cannot leave the grid.
    crossings: (usize, usize),
}

impl Walk {
    /// Clips `a -> b` to a `width x height` grid and prepares the walk, or
    /// `None` when the segment misses the grid (or is not finite).
    #[inline]
    pub fn new(width: usize, height: usize, a: (f64, f64), b: (f64, f64)) -> Option<Self> {
        let (w, h) = (width as f64, height as f64);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        if !(a.0.is_finite() && a.1.is_finite() && dx.is_finite() && dy.is_finite()) {
            return None;
        }

        // Liang–Barsky clip of a + t d, t in [0, 1], to [0, w] x [0, h].
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [(-dx, a.0), (dx, w - a.0), (-dy, a.1), (dy, h - a.1)] {
            if p == 0.0 {
                if q < 0.0 {
                    return None; // parallel to this border and outside it
                }
            } else {
                // (Comparisons rather than f64::max/min: `r` is never NaN,
                // and in wasm those are library calls.)
                let r = q / p;
                if p < 0.0 {
                    if r > t0 {
                        t0 = r;
                    }
                } else if r < t1 {
                    t1 = r;
                }
            }
        }
        if t0 > t1 {
            return None;
        }

        let x = Axis::new(a.0, dx, t0, t1, width);
        let y = Axis::new(a.1, dy, t0, t1, height);
        Some(Self {
            start: (x.first, y.first),
            step: (x.step, y.step),
            t_max: (x.t_max, y.t_max),
            t_delta: (x.t_delta, y.t_delta),
            crossings: (x.crossings, y.crossings),
        })
    }

    /// How many cells the walk will visit at least (one per crossing plus
    /// the first cell; each exact corner adds one more).
    pub fn min_visits(&self) -> usize {
        1 + self.crossings.0 + self.crossings.1
    }

    /// Amanatides & Woo's incremental phase: visits the first cell, then at
    /// each grid-line crossing, in order along the segment, moves the cursor
    /// into the next cell and visits it. Returns the number of visits.
    ///
    /// The paper keeps `tMaxX` and `tMaxY`; only their difference decides
    /// the next axis, so that difference is what is carried. While both
    /// axes have crossings ahead, its sign picks the axis; once one axis is
    /// used up, the rest is a straight run. The crossing counts end the
    /// walk inside the grid: no per-step range or border test.
    #[inline(always)]
    pub fn run<C: Cursor>(self, cursor: &mut C) -> usize {
        let (d_x, d_y) = self.t_delta;
        let (mut n_x, mut n_y) = self.crossings;
        let mut visits = 1 + n_x + n_y;
        // tMaxX - tMaxY: negative when the next crossing is on x.
        let mut gap = self.t_max.0 - self.t_max.1;
        let both = n_x != 0 && n_y != 0;
        // One step of the two-axis phase; false once an axis is used up.
        let mut step = |cursor: &mut C| -> bool {
            cursor.visit();
            if gap < -CORNER_EPS {
                cursor.step_x();
                gap += d_x;
                n_x -= 1;
                n_x != 0
            } else if gap > CORNER_EPS {
                cursor.step_y();
                gap -= d_y;
                n_y -= 1;
                n_y != 0
            } else {
                cursor.step_x();
                cursor.visit();
                cursor.unstep_x();
                cursor.step_y();
                cursor.visit();
                cursor.step_x();
                visits += 1;
                gap += d_x - d_y;
                n_x -= 1;
                n_y -= 1;
                n_x != 0 && n_y != 0
            }
        };
        if both {
            while step(cursor) && step(cursor) {}
        }
        for _ in 0..n_x {
            cursor.visit();
            cursor.step_x();
        }
        for _ in 0..n_y {
            cursor.visit();
            cursor.step_y();
        }
        cursor.visit();
        visits
    }
}

/// Initialization of one axis of a [`Walk`].
struct Axis {
    first: usize,
    step: i8,
    t_max: f64,
    t_delta: f64,
    crossings: usize,
}

impl Axis {
    /// Axis of `a + t d` clipped to `t in [t0, t1]`, on a grid `cells`
    /// wide.
    #[inline]
    fn new(a: f64, d: f64, t0: f64, t1: f64, cells: usize) -> Self {
        let last = cells as i64 - 1;
        let first = floor_cell(a + t0 * d, last);
        if d == 0.0 {
            return Self {
                first: first as usize,
                step: 1,
                t_max: f64::INFINITY,
                t_delta: f64::INFINITY,
                crossings: 0,
            };
        }
        let end = a + t1 * d;
        // The cell holding the clipped end. A segment that ends exactly on
        // a grid line touches the cell beyond it: moving up that is
        // `floor(end)`, moving down `ceil(end) - 1`.
        let (step, last_cell, boundary) = if d > 0.0 {
            (1i8, floor_cell(end, last), first + 1)
        } else {
            (-1i8, below_cell(end, last), first)
        };
        Self {
            first: first as usize,
            step,
            t_max: (boundary as f64 - a) / d,
            t_delta: 1.0 / d.abs(),
            crossings: ((last_cell - first) * step as i64).max(0) as usize,
        }
    }
}

/// `floor(x)` clamped to `[0, last]`. On `x >= 0` truncation is the floor,
/// so clamping first needs no rounding call (x86-64 has no floor
/// instruction without SSE4.1).
#[inline]
fn floor_cell(x: f64, last: i64) -> i64 {
    if x > 0.0 {
        (x as i64).min(last)
    } else {
        0
    }
}

/// `ceil(x) - 1` clamped to `[0, last]`: the cell a segment moving down
/// ends in when it stops at `x` (a grid line counts as the cell below it).
#[inline]
fn below_cell(x: f64, last: i64) -> i64 {
    if x > 0.0 {
        let t = x as i64;
        let c = if (t as f64) < x { t } else { t - 1 };
        c.clamp(0, last)
    } else {
        0
    }
}

/// Visits, in order from `a` to `b`, every cell of a `width x height` grid
/// that the segment touches. The segment is clipped to the grid first: a
/// beam that leaves the map (or starts outside it) still reaches the cells it
/// crosses inside it. Returns the number of visits.
#[inline]
pub fn supercover(
    width: usize,
    height: usize,
    a: (f64, f64),
    b: (f64, f64),
    visit: impl FnMut(usize, usize),
) -> usize {
    let Some(walk) = Walk::new(width, height, a, b) else {
        return 0;
    };
    let mut cursor = CellCursor {
        x: walk.start.0,
        y: walk.start.1,
        step_x: walk.step.0 as isize,
        step_y: walk.step.1 as isize,
        visit,
    };
    walk.run(&mut cursor)
}

/// The cursor of [`supercover`]: the cell's coordinates.
struct CellCursor<F> {
    x: usize,
    y: usize,
    step_x: isize,
    step_y: isize,
    visit: F,
}

impl<F: FnMut(usize, usize)> Cursor for CellCursor<F> {
    #[inline(always)]
    fn visit(&mut self) {
        (self.visit)(self.x, self.y);
    }
    #[inline(always)]
    fn step_x(&mut self) {
        self.x = self.x.wrapping_add_signed(self.step_x);
    }
    #[inline(always)]
    fn step_y(&mut self) {
        self.y = self.y.wrapping_add_signed(self.step_y);
    }
    #[inline(always)]
    fn unstep_x(&mut self) {
        self.x = self.x.wrapping_add_signed(-self.step_x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(w: usize, h: usize, a: (f64, f64), b: (f64, f64)) -> Vec<(usize, usize)> {
        let mut v = Vec::new();
        let n = supercover(w, h, a, b, |x, y| v.push((x, y)));
        assert_eq!(n, v.len());
        v
    }

    #[test]
    fn axis_aligned_ray_visits_each_cell_once() {
        assert_eq!(
            cells(10, 3, (0.5, 1.5), (4.5, 1.5)),
            vec![(0, 1), (1, 1), (2, 1), (3, 1), (4, 1)]
        );
        assert_eq!(
            cells(3, 10, (1.5, 6.5), (1.5, 4.2)),
            vec![(1, 6), (1, 5), (1, 4)]
        );
    }

    #[test]
    fn diagonal_through_corners_visits_both_side_cells() {
        let v = cells(5, 5, (0.5, 0.5), (2.5, 2.5));
        assert_eq!(
            v,
            vec![(0, 0), (1, 0), (0, 1), (1, 1), (2, 1), (1, 2), (2, 2)]
        );
    }

    #[test]
    fn every_step_moves_to_an_edge_neighbour_or_fills_the_corner() {
        // A shallow line: consecutive cells share an edge.
        let v = cells(50, 50, (0.3, 0.7), (40.1, 13.9));
        for pair in v.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let d = (a.0 as i64 - b.0 as i64).abs() + (a.1 as i64 - b.1 as i64).abs();
            assert_eq!(d, 1, "{a:?} -> {b:?}");
        }
        assert_eq!(*v.last().unwrap(), (40, 13));
    }

    #[test]
    fn clips_at_the_border_and_enters_from_outside() {
        // Leaves the map to the east: the cells inside are still visited.
        let v = cells(4, 2, (1.5, 0.5), (9.5, 0.5));
        assert_eq!(v, vec![(1, 0), (2, 0), (3, 0)]);
        // Starts outside, crosses the map.
        let v = cells(4, 2, (-3.0, 1.5), (2.5, 1.5));
        assert_eq!(v, vec![(0, 1), (1, 1), (2, 1)]);
        // Misses the map entirely.
        assert!(cells(4, 2, (-3.0, 5.0), (9.0, 5.0)).is_empty());
        // Ignores a non-finite segment instead of looping.
        assert!(cells(4, 2, (0.5, 0.5), (f64::NAN, 1.0)).is_empty());
    }
}
