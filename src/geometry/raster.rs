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
//! `[i, i+1) x [j, j+1)`), see [`crate::geometry::GridGeometry::world_to_grid`].

/// Crossings closer than this (in units of the segment's parameter) count
/// as one corner crossing.
const CORNER_EPS: f64 = 1e-9;

/// What a caller keeps while a [`Walk`] runs. The walk starts the cursor on
/// the first cell and then only tells it to move to an edge neighbour and
/// to visit the cell it stands on; every move stays inside the grid.
pub trait Cursor {
    /// Whether the walk may end early: a cursor that sets it is asked
    /// [`Cursor::done`] after every visit (the mapper's cursors leave it
    /// false, so their walk has no such test at all).
    const STOPS: bool = false;
    /// The cursor's cell is on the segment.
    fn visit(&mut self);
    /// With [`Cursor::STOPS`]: the walk ends here.
    fn done(&self) -> bool {
        false
    }
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
    /// for a segment parallel to that axis's grid lines).
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
        if width == 0 || height == 0 {
            return None; // a grid without cells has nothing to visit
        }
        let (w, h) = (width as f64, height as f64);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        if !(a.0.is_finite() && a.1.is_finite() && dx.is_finite() && dy.is_finite()) {
            return None;
        }

        // One division per axis: the clip's ratios and the walk's crossings
        // are all multiples of 1/d (a division costs several products).
        let (inv_x, inv_y) = (1.0 / dx, 1.0 / dy);

        // Liang–Barsky clip of a + t d, t in [0, 1], to [0, w] x [0, h]:
        // each border `p t <= q`, with `1/p` alongside.
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q, inv_p) in [
            (-dx, a.0, -inv_x),
            (dx, w - a.0, inv_x),
            (-dy, a.1, -inv_y),
            (dy, h - a.1, inv_y),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return None; // parallel to this border and outside it
                }
            } else if p < 0.0 {
                // Entering through this border. From a start on its inner
                // side (q >= 0, the usual case) the ratio is <= 0 and
                // cannot move t0: skip it.
                if q < 0.0 {
                    let r = q * inv_p;
                    if r > t0 {
                        t0 = r;
                    }
                }
            } else {
                // Leaving through this border. (Comparisons rather than
                // f64::min: `r` is never NaN, and in wasm that is a call.)
                let r = q * inv_p;
                if r < t1 {
                    t1 = r;
                }
            }
        }
        if t0 > t1 {
            return None;
        }

        let x = Axis::new(a.0, dx, inv_x, t0, t1, width);
        let y = Axis::new(a.1, dy, inv_y, t0, t1, height);
        Some(Self {
            start: (x.first, y.first),
            step: (x.step, y.step),
            t_max: (x.t_max, y.t_max),
            t_delta: (x.t_delta, y.t_delta),
            crossings: (x.crossings, y.crossings),
        })
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
        if n_x != 0 && n_y != 0 {
            loop {
                cursor.visit();
                if C::STOPS && cursor.done() {
                    return visits;
                }
                if gap < -CORNER_EPS {
                    cursor.step_x();
                    gap += d_x;
                    n_x -= 1;
                    if n_x == 0 {
                        break;
                    }
                } else if gap > CORNER_EPS {
                    cursor.step_y();
                    gap -= d_y;
                    n_y -= 1;
                    if n_y == 0 {
                        break;
                    }
                } else {
                    // Through a corner: both side cells, then the diagonal
                    // one at the top of the loop.
                    cursor.step_x();
                    cursor.visit();
                    if C::STOPS && cursor.done() {
                        return visits;
                    }
                    cursor.unstep_x();
                    cursor.step_y();
                    cursor.visit();
                    if C::STOPS && cursor.done() {
                        return visits;
                    }
                    cursor.step_x();
                    visits += 1;
                    gap += d_x - d_y;
                    n_x -= 1;
                    n_y -= 1;
                    if n_x == 0 || n_y == 0 {
                        break;
                    }
                }
            }
        }
        for _ in 0..n_x {
            cursor.visit();
            if C::STOPS && cursor.done() {
                return visits;
            }
            cursor.step_x();
        }
        for _ in 0..n_y {
            cursor.visit();
            if C::STOPS && cursor.done() {
                return visits;
            }
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
    /// wide; `inv` is `1 / d`.
    #[inline(always)]
    fn new(a: f64, d: f64, inv: f64, t0: f64, t1: f64, cells: usize) -> Self {
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
            t_max: (boundary as f64 - a) * inv,
            t_delta: inv.abs(),
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
    let mut visit = visit;
    let mut cursor = CellCursor::<_, false>::new(&walk, |x, y| {
        visit(x, y);
        false
    });
    walk.run(&mut cursor)
}

/// The first cell, in order from `a` to `b`, for which `hit(ix, iy)` holds
/// among the cells [`supercover`] would visit; the walk stops there.
#[inline]
pub fn first_cell(
    width: usize,
    height: usize,
    a: (f64, f64),
    b: (f64, f64),
    hit: impl FnMut(usize, usize) -> bool,
) -> Option<(usize, usize)> {
    let walk = Walk::new(width, height, a, b)?;
    let mut cursor = CellCursor::<_, true>::new(&walk, hit);
    walk.run(&mut cursor);
    cursor.found
}

/// The parameter at which the ray `start + t (c, s)` (grid coordinates,
/// `t >= 0`) enters cell `(ix, iy)`: the slab test's entry, 0 when it
/// starts inside. Only the entry is needed for a cell [`supercover`]
/// reports, since the ray touches it; an axis the ray is parallel to sets
/// no bound.
pub fn entry_parameter(ix: usize, iy: usize, start: (f64, f64), (c, s): (f64, f64)) -> f64 {
    // (A function rather than a closure: at opt-level "s" a closure
    // called twice stays a call.)
    #[inline(always)]
    fn slab_entry(lo: f64, start: f64, d: f64) -> f64 {
        if d == 0.0 {
            f64::NEG_INFINITY
        } else {
            ((lo - start) / d).min((lo + 1.0 - start) / d)
        }
    }
    slab_entry(ix as f64, start.0, c)
        .max(slab_entry(iy as f64, start.1, s))
        .max(0.0)
}

/// The cursor of [`supercover`] and [`first_cell`]: the cell's coordinates,
/// and with `STOP` the first cell `visit` says yes to, where the walk ends.
struct CellCursor<F, const STOP: bool> {
    x: usize,
    y: usize,
    step_x: isize,
    step_y: isize,
    visit: F,
    found: Option<(usize, usize)>,
}

impl<F, const STOP: bool> CellCursor<F, STOP> {
    fn new(walk: &Walk, visit: F) -> Self {
        Self {
            x: walk.start.0,
            y: walk.start.1,
            step_x: walk.step.0 as isize,
            step_y: walk.step.1 as isize,
            visit,
            found: None,
        }
    }
}

impl<F: FnMut(usize, usize) -> bool, const STOP: bool> Cursor for CellCursor<F, STOP> {
    const STOPS: bool = STOP;
    #[inline(always)]
    fn visit(&mut self) {
        if (self.visit)(self.x, self.y) {
            self.found = Some((self.x, self.y));
        }
    }
    #[inline(always)]
    fn done(&self) -> bool {
        self.found.is_some()
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

/// The most raster steps a scene's cone readings may cost the MAP search's
/// incidence cache (beams x sub-rays x cells per sub-ray): bounds memory and time for any input. At the limit
/// the cache takes about half a second and 30 MB natively; the doorway
/// scene needs about 1/1000 of it.
pub const MAX_RASTER_WORK: f64 = 5e7;

/// The raster steps the incidence cache takes for `beams` cones of
/// `sub_rays` sub-rays each reaching `z_max` metres over cells of
/// `resolution` metres: a sub-ray crosses at most about
/// `2 z_max / resolution + 4` cells. A scene checks this before it casts
/// its readings, so that too large a request is refused before any work.
pub fn raster_work(beams: usize, sub_rays: usize, z_max: f64, resolution: f64) -> f64 {
    let steps_per_ray = 2.0 * z_max / resolution + 4.0;
    beams as f64 * sub_rays as f64 * steps_per_ray
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    /// The textbook form of the traversal, kept as the reference: `tMaxX`
    /// and `tMaxY` carried separately, a range test against the clipped end
    /// and a border test at every step.
    fn reference(w: usize, h: usize, a: (f64, f64), b: (f64, f64)) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        let (wf, hf) = (w as f64, h as f64);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [(-dx, a.0), (dx, wf - a.0), (-dy, a.1), (dy, hf - a.1)] {
            if p == 0.0 {
                if q < 0.0 {
                    return out;
                }
            } else if p < 0.0 {
                t0 = t0.max(q / p);
            } else {
                t1 = t1.min(q / p);
            }
        }
        if t0 > t1 {
            return out;
        }
        let start = (a.0 + t0 * dx, a.1 + t0 * dy);
        let mut ix = (start.0.floor() as i64).clamp(0, w as i64 - 1);
        let mut iy = (start.1.floor() as i64).clamp(0, h as i64 - 1);
        let (sx, sy) = (if dx > 0.0 { 1 } else { -1 }, if dy > 0.0 { 1 } else { -1 });
        let first = |i: i64, s: i64, a: f64, d: f64| {
            if d == 0.0 {
                (f64::INFINITY, f64::INFINITY)
            } else {
                let boundary = if s > 0 { i + 1 } else { i };
                ((boundary as f64 - a) / d, 1.0 / d.abs())
            }
        };
        let (mut tx, ddx) = first(ix, sx, a.0, dx);
        let (mut ty, ddy) = first(iy, sy, a.1, dy);
        let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < w as i64 && y < h as i64;
        loop {
            out.push((ix as usize, iy as usize));
            if tx.min(ty) > t1 {
                break;
            }
            if (tx - ty).abs() <= CORNER_EPS {
                for (cx, cy) in [(ix + sx, iy), (ix, iy + sy)] {
                    if inside(cx, cy) {
                        out.push((cx as usize, cy as usize));
                    }
                }
                ix += sx;
                iy += sy;
                tx += ddx;
                ty += ddy;
            } else if tx < ty {
                ix += sx;
                tx += ddx;
            } else {
                iy += sy;
                ty += ddy;
            }
            if !inside(ix, iy) {
                break;
            }
        }
        out
    }

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

    #[test]
    fn walk_matches_the_reference_traversal_on_random_segments() {
        let mut rng = StdRng::seed_from_u64(7);
        let (w, h) = (37, 23);
        for k in 0..20_000 {
            // Starts inside and outside the grid, short and long segments,
            // every direction. (Ends exactly on a grid line are left to the
            // test below: there the reference's accumulated `tMax` decides
            // by rounding whether the touched cell is reached.)
            let mut point = |spread: f64| {
                (
                    rng.random_range(-spread..w as f64 + spread),
                    rng.random_range(-spread..h as f64 + spread),
                )
            };
            let a = point(if k % 3 == 0 { 20.0 } else { 0.0 });
            let b = point(30.0);
            let got = cells(w, h, a, b);
            assert_eq!(got, reference(w, h, a, b), "{a:?} -> {b:?}");
        }
    }

    #[test]
    fn walk_matches_the_reference_through_exact_corners() {
        // Centre to centre along slopes of +-1 and +-1/2 or 2 (through
        // corners every one or two cells). Both ends inside: a clipped end
        // on a corner is the case below.
        let mut rng = StdRng::seed_from_u64(11);
        let (w, h) = (16, 12);
        let inside = |p: (f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0 < w as f64 && p.1 < h as f64;
        for _ in 0..5_000 {
            let a = (
                rng.random_range(0..w) as f64 + 0.5,
                rng.random_range(0..h) as f64 + 0.5,
            );
            let n = rng.random_range(1..20) as f64;
            let (kx, ky) = [(1.0, 1.0), (1.0, 2.0), (2.0, 1.0)][rng.random_range(0..3)];
            let sx = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let sy = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let b = (a.0 + sx * kx * n, a.1 + sy * ky * n);
            if inside(b) {
                assert_eq!(cells(w, h, a, b), reference(w, h, a, b), "{a:?} -> {b:?}");
            }
        }
    }

    #[test]
    fn a_segment_ending_on_a_grid_line_reaches_the_cell_beyond_it() {
        // The end point touches the next cell's edge, in either direction.
        assert_eq!(cells(6, 1, (0.5, 0.5), (3.0, 0.5)).last(), Some(&(3, 0)));
        assert_eq!(cells(6, 1, (4.5, 0.5), (2.0, 0.5)).last(), Some(&(1, 0)));
        assert_eq!(cells(1, 6, (0.5, 4.5), (0.5, 2.0)).last(), Some(&(0, 1)));
        // At the border there is no cell beyond.
        assert_eq!(cells(6, 1, (0.5, 0.5), (6.0, 0.5)).last(), Some(&(5, 0)));
        assert_eq!(cells(6, 1, (4.5, 0.5), (0.0, 0.5)).last(), Some(&(0, 0)));
        // Clipped exactly at a corner on the border: the cell beside that
        // corner inside the map is touched, so it is visited. (Carrying
        // `tMax` and testing it against the clipped end would decide this by
        // rounding: 0.1 + 0.2 > 0.3.)
        assert_eq!(
            cells(4, 12, (1.5, 5.5), (-3.5, 10.5)),
            vec![(1, 5), (0, 5), (1, 6), (0, 6), (0, 7)]
        );
    }

    #[test]
    fn a_corner_on_the_border_visits_only_the_side_cell_inside() {
        // Leaves through the top-right corner of a 3 x 3 grid.
        assert_eq!(
            cells(3, 3, (1.5, 1.5), (3.5, 3.5)),
            vec![(1, 1), (2, 1), (1, 2), (2, 2)]
        );
        // Leaves through the right border exactly at a row line: of the
        // corner's side cells only the upper one is inside.
        assert_eq!(cells(3, 3, (2.5, 0.5), (3.5, 1.5)), vec![(2, 0), (2, 1)]);
    }

    #[test]
    fn a_point_or_a_grazing_touch_visits_one_cell() {
        assert_eq!(cells(4, 4, (2.5, 1.5), (2.5, 1.5)), vec![(2, 1)]);
        // Touches the grid only at its corner (0, 0).
        assert_eq!(cells(4, 4, (-1.0, 1.0), (1.0, -1.0)), vec![(0, 0)]);
    }
}
