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
//! Coordinates are continuous grid coordinates (cell `(i, j)` spans
//! `[i, i+1) x [j, j+1)`), see [`crate::grid::GridGeometry::world_to_grid`].

/// Crossings closer than this (in units of the segment's parameter) count
/// as one corner crossing.
const CORNER_EPS: f64 = 1e-9;

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
    mut visit: impl FnMut(usize, usize),
) -> usize {
    let (w, h) = (width as f64, height as f64);
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    if !(a.0.is_finite() && a.1.is_finite() && dx.is_finite() && dy.is_finite()) {
        return 0;
    }

    // Liang–Barsky clip of a + t d, t in [0, 1], to [0, w] x [0, h].
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0), (dx, w - a.0), (-dy, a.1), (dy, h - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return 0; // parallel to this border and outside it
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return 0;
    }

    // Initialization: the cell holding the clipped start, the step
    // direction, and the parameter of the first crossing on each axis.
    let start = (a.0 + t0 * dx, a.1 + t0 * dy);
    let mut ix = (start.0.floor() as i64).clamp(0, width as i64 - 1);
    let mut iy = (start.1.floor() as i64).clamp(0, height as i64 - 1);
    let (step_x, step_y) = (if dx > 0.0 { 1 } else { -1 }, if dy > 0.0 { 1 } else { -1 });
    let first_crossing = |i: i64, step: i64, a: f64, d: f64| -> (f64, f64) {
        if d == 0.0 {
            return (f64::INFINITY, f64::INFINITY);
        }
        let boundary = if step > 0 { i + 1 } else { i } as f64;
        ((boundary - a) / d, 1.0 / d.abs())
    };
    let (mut t_max_x, t_delta_x) = first_crossing(ix, step_x, a.0, dx);
    let (mut t_max_y, t_delta_y) = first_crossing(iy, step_y, a.1, dy);

    let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < width as i64 && y < height as i64;
    let mut visits = 0;
    // Incremental phase: one step per grid-line crossing until the end.
    loop {
        visit(ix as usize, iy as usize);
        visits += 1;
        let t_next = t_max_x.min(t_max_y);
        if t_next > t1 {
            break;
        }
        if (t_max_x - t_max_y).abs() <= CORNER_EPS {
            // Through a corner: both side cells, then the diagonal one.
            for (cx, cy) in [(ix + step_x, iy), (ix, iy + step_y)] {
                if inside(cx, cy) {
                    visit(cx as usize, cy as usize);
                    visits += 1;
                }
            }
            ix += step_x;
            iy += step_y;
            t_max_x += t_delta_x;
            t_max_y += t_delta_y;
        } else if t_max_x < t_max_y {
            ix += step_x;
            t_max_x += t_delta_x;
        } else {
            iy += step_y;
            t_max_y += t_delta_y;
        }
        if !inside(ix, iy) {
            break;
        }
    }
    visits
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
