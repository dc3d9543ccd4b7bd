//! Submaps (Hess et al. 2016, section IV): a small log-odds grid of a few
//! consecutive scans in the local frame, which scans are matched against
//! while it grows; once it holds its scans it is finished, never changes
//! again, and is kept only as bytes for loop search ([`LoopGrid`]).
//! Two submaps grow at once, the second started halfway through the
//! first, so that a scan is always matched against a submap of at least
//! half its scans.

use super::facing::{normal_code, pack_log_odds, surface_normals};
use super::loop_search::LoopGrid;
use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{CellModel, FilterSettings, Store, TiledGrid};
use crate::sensors::Scan;

/// How closely a cell's returns' normals must agree (the length of their
/// mean unit vector) for the cell to keep their mean.
const NORMAL_CONSENSUS: f64 = 0.7;

/// Most cells across a submap's grid (its tiles are allocated only where
/// beams reach).
const MAX_SIDE_CELLS: usize = 4000;

/// One submap: the scans it holds, and its grid while it grows or its
/// bytes once finished.
#[derive(Debug, Clone)]
pub struct Submap {
    /// The first scan inserted: the node its loop edges attach to.
    pub anchor: usize,
    /// Scans inserted so far.
    pub scans: usize,
    /// The last scan inserted.
    pub last: usize,
    pub grid: Option<TiledGrid>,
    pub finished: Option<LoopGrid>,
    /// Its grid while it is made into bytes, once full.
    closing: Option<Closing>,
    /// When its last loop search ended, in searches of any submap: the
    /// least recent drops its grids of maxima first.
    pub searched: u64,
    /// The box its scans' poses and beam ends span (world, metres): the
    /// only cells a finished grid is read over.
    bounds: [f64; 4],
    /// Each return's cell (index in the growing grid) and its surface's
    /// normal (radians, [`surface_normals`]): which side of a wall the
    /// submap saw.
    facing: Vec<(u32, f64)>,
}

impl Submap {
    /// A fresh submap around `pose` (local frame), reaching `reach` metres
    /// from it, of `resolution`.
    pub fn start(anchor: usize, pose: &Pose, reach: f64, resolution: f64) -> Result<Self> {
        let side = ((2.0 * reach / resolution).ceil() as usize).clamp(64, MAX_SIDE_CELLS);
        let half = side as f64 * resolution / 2.0;
        let geometry = GridGeometry::new(side, side, resolution, pose.x - half, pose.y - half)?;
        let filter = FilterSettings {
            prior: 0.5,
            clamp: 3.5,
        };
        Ok(Self {
            anchor,
            scans: 0,
            last: anchor,
            grid: Some(TiledGrid::new(geometry, filter, side * side)?),
            finished: None,
            closing: None,
            searched: 0,
            bounds: [pose.x, pose.y, pose.x, pose.y],
            facing: Vec::new(),
        })
    }

    /// Widens the box to `scan` at its pose, each beam cut at `reach`
    /// metres (the insertion's cap; a no-return clears no further), and
    /// notes the normal of the surface each return lay on, by its cell
    /// ([`surface_normals`]).
    pub fn cover(&mut self, scan: &Scan, reach: f64) {
        let p = scan.pose();
        if let Some(grid) = &self.grid {
            let g = grid.geometry();
            let (s, c) = p.theta.sin_cos();
            let returns: Vec<[f64; 2]> = scan
                .ranges()
                .iter()
                .zip(scan.bearings())
                .filter(|(r, _)| r.is_finite() && **r < reach)
                .map(|(r, a)| [r * a.cos(), r * a.sin()])
                .collect();
            for (q, normal) in returns.iter().zip(surface_normals(&returns)) {
                let Some(normal) = normal else { continue };
                let (x, y) = (p.x + c * q[0] - s * q[1], p.y + s * q[0] + c * q[1]);
                if let Some((ix, iy)) = g.world_to_cell(x, y) {
                    self.facing
                        .push(((iy * g.width() + ix) as u32, p.theta + normal));
                }
            }
        }
        let b = &mut self.bounds;
        let mut widen = |x: f64, y: f64| {
            b[0] = b[0].min(x);
            b[1] = b[1].min(y);
            b[2] = b[2].max(x);
            b[3] = b[3].max(y);
        };
        widen(p.x, p.y);
        for (r, a) in scan.ranges().iter().zip(scan.bearings()) {
            let r = if r.is_finite() { r.min(reach) } else { reach };
            let (s, c) = (p.theta + a).sin_cos();
            widen(p.x + c * r, p.y + s * r);
        }
    }

    /// Stops the submap growing: its grid is set aside to be made into
    /// bytes by [`Self::finish_within`], a slice of rows at a time.
    pub fn close(&mut self) {
        let Some(grid) = self.grid.take() else {
            return;
        };
        let g = *grid.geometry();
        let (w, h) = (g.width(), g.height());
        // The box's cells, a cell and the wall's thickness wider.
        let res = g.resolution();
        let [ox, oy] = g.origin();
        let cell =
            |v: f64, o: f64, n: usize| (((v - o) / res).floor().max(0.0) as usize).min(n - 1);
        let pad = 0.5;
        let scan = [
            cell(self.bounds[0] - pad, ox, w),
            cell(self.bounds[1] - pad, oy, h),
            cell(self.bounds[2] + pad, ox, w),
            cell(self.bounds[3] + pad, oy, h),
        ];
        // Each return's normal, on its cell and the cells round it (a wall
        // a cell or two thick), in the order the cells are read; a cell
        // whose normals disagree (a corner, a thin wall seen from both
        // sides) keeps none, and any point scores it.
        let mut spread = Vec::with_capacity(9 * self.facing.len());
        for &(i, normal) in &self.facing {
            let (ix, iy) = (i as usize % w, i as usize / w);
            for ny in iy.saturating_sub(1)..=(iy + 1).min(h - 1) {
                for nx in ix.saturating_sub(1)..=(ix + 1).min(w - 1) {
                    spread.push(((ny * w + nx) as u32, normal));
                }
            }
        }
        self.facing = Vec::new();
        spread.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut facing: Vec<(u32, u8)> = Vec::new();
        for run in spread.chunk_by(|a, b| a.0 == b.0) {
            let (sx, sy) = run
                .iter()
                .fold((0.0, 0.0), |(x, y), (_, a)| (x + a.cos(), y + a.sin()));
            let agreement = sx.hypot(sy) / run.len() as f64;
            let code = if agreement >= NORMAL_CONSENSUS {
                normal_code(sy.atan2(sx))
            } else {
                0
            };
            facing.push((run[0].0, code));
        }
        self.closing = Some(Closing {
            grid,
            scan,
            known: [usize::MAX, usize::MAX, 0, 0],
            row: scan[1],
            bytes: None,
            facing,
            next_facing: 0,
        });
    }

    /// Whether the submap is closed but not yet finished.
    pub fn is_closing(&self) -> bool {
        self.closing.is_some()
    }

    /// Goes on making the closed grid into bytes, whole rows at a time,
    /// until the cells read reach `max_cells` (at least one row): first
    /// the box of its scans, for the box of its known cells, then that box
    /// as bytes. The cells read, and true once finished (the grid then
    /// dropped). Cut anywhere, the bytes are those of one call. A cell
    /// made into a byte counts as two reads (its updates and its log odds,
    /// then the probability's exponential): natively on the Freiburg
    /// campus a cell of the first pass took 7 ns, one of the second 23,
    /// and counted alike, a page's calls that met the second pass after
    /// the first ran three times their slice.
    pub fn finish_within(&mut self, max_cells: u64) -> (u64, bool) {
        let Some(c) = self.closing.as_mut() else {
            return (0, true);
        };
        let mut read = 0u64;
        let [cx0, _, cx1, cy1] = c.scan;
        while c.bytes.is_none() && c.row <= cy1 {
            let iy = c.row;
            // The row's first and last updated cells within the scans' box,
            // a tile's run at a time (a tile never touched has none).
            let mut first_last: Option<(usize, usize)> = None;
            runs_between(&c.grid, iy, cx0, cx1, |a, _, cells| {
                let Some((_, updates)) = cells else {
                    return;
                };
                let first = updates.iter().position(|&u| u > 0);
                let last = updates.iter().rposition(|&u| u > 0);
                if let (Some(f), Some(l)) = (first, last) {
                    let (f, l) = (a + f, a + l);
                    first_last = Some(first_last.map_or((f, l), |(f0, l0)| (f0.min(f), l0.max(l))));
                }
            });
            if let Some((f, l)) = first_last {
                c.known[0] = c.known[0].min(f);
                c.known[1] = c.known[1].min(iy);
                c.known[2] = c.known[2].max(l);
                c.known[3] = c.known[3].max(iy);
            }
            c.row += 1;
            read += (cx1 - cx0 + 1) as u64;
            if c.row > cy1 {
                let [x0, y0, x1, y1] = c.known;
                let cells = if x0 > x1 || y0 > y1 {
                    0
                } else {
                    (x1 - x0 + 1) * (y1 - y0 + 1)
                };
                c.bytes = Some(Vec::with_capacity(cells));
                c.row = y0;
            }
            if read >= max_cells {
                return (read, false);
            }
        }
        let g = *c.grid.geometry();
        let [x0, y0, x1, y1] = c.known;
        if x0 <= x1 && y0 <= y1 {
            let bytes = c.bytes.as_mut().expect("the box of known cells is found");
            let model = *c.grid.model();
            while c.row <= y1 {
                let iy = c.row;
                let (facing, next_facing) = (&c.facing, &mut c.next_facing);
                // The row's cells a tile's run at a time: a cell never
                // updated (or in a tile never touched) is 0.
                runs_between(&c.grid, iy, x0, x1, |a, n, cells| {
                    let Some((cells, updates)) = cells else {
                        bytes.resize(bytes.len() + n, 0);
                        return;
                    };
                    for (k, (&cell, &u)) in cells.iter().zip(updates).enumerate() {
                        if u == 0 {
                            bytes.push(0);
                            continue;
                        }
                        let at = (iy * g.width() + a + k) as u32;
                        while facing.get(*next_facing).is_some_and(|f| f.0 < at) {
                            *next_facing += 1;
                        }
                        let normal = match facing.get(*next_facing) {
                            Some(&(i, bits)) if i == at => bits,
                            _ => 0,
                        };
                        bytes.push(pack_log_odds(model.log_odds(cell), normal));
                    }
                });
                c.row += 1;
                read += 2 * (x1 - x0 + 1) as u64;
                if c.row <= y1 && read >= max_cells {
                    return (read, false);
                }
            }
        }
        let c = self.closing.take().expect("a closed submap");
        let res = g.resolution();
        let [ox, oy] = g.origin();
        let known = c.bytes.unwrap_or_default();
        self.finished = Some(if x0 > x1 || y0 > y1 {
            LoopGrid::from_packed(g.origin(), res, 0, 0, known)
        } else {
            LoopGrid::from_packed(
                [ox + x0 as f64 * res, oy + y0 as f64 * res],
                res,
                x1 - x0 + 1,
                y1 - y0 + 1,
                known,
            )
        });
        (read, true)
    }
}

/// Row `iy` of `grid` from column `x0` to `x1` (inclusive), a tile's run
/// at a time: `f(first column, cells in the run, its cells and updates)`,
/// the cells `None` for a tile never touched.
fn runs_between(
    grid: &TiledGrid,
    iy: usize,
    x0: usize,
    x1: usize,
    mut f: impl FnMut(usize, usize, Option<(&[f32], &[u32])>),
) {
    grid.store().row_runs(iy, |run| {
        let (a, b) = (run.x0.max(x0), (run.x0 + run.len).min(x1 + 1));
        if a >= b {
            return;
        }
        let span = a - run.x0..b - run.x0;
        let cells = run
            .cells
            .and_then(|(c, u)| Some((c.get(span.clone())?, u.get(span)?)));
        f(a, b - a, cells)
    });
}

/// A closed submap's grid being made into bytes ([`Submap::finish_within`]).
#[derive(Debug, Clone)]
struct Closing {
    grid: TiledGrid,
    /// The box of the submap's scans, cells `[x0, y0, x1, y1]`.
    scan: [usize; 4],
    /// The box of its known cells found so far (empty while `x0 > x1`).
    known: [usize; 4],
    /// The next row read: of the scans' box, then of the known box.
    row: usize,
    /// The known box's bytes, once that box is found.
    bytes: Option<Vec<u8>>,
    /// The normal codes of the submap's returns' cells, in cell order, and
    /// the first not yet passed by the rows made into bytes.
    facing: Vec<(u32, u8)>,
    next_facing: usize,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::HandCraftedParams;
    use crate::mapping::insertion::{ScanInserter, ScanInsertion};
    use crate::mapping::walls::WallModel;

    /// A submap of three scans in a room, closed.
    fn closed() -> Submap {
        let pose = Pose::new(1.0, 2.0, 0.3).unwrap();
        let mut s = Submap::start(0, &pose, 9.0, 0.05).unwrap();
        let mut inserter = ScanInserter::new(ScanInsertion {
            model: HandCraftedParams::laser(8.0),
            no_return_reach: 5.0,
            walls: WallModel::Incidence,
            between_beams: false,
        })
        .unwrap();
        let bearings: Vec<f64> = (0..181).map(|i| (i as f64 - 90.0).to_radians()).collect();
        for k in 0..3 {
            let ranges = bearings
                .iter()
                .map(|b: &f64| 2.0 + 0.5 * (3.0 * b + k as f64).sin().abs())
                .collect();
            let at = Pose::new(1.0 + 0.1 * k as f64, 2.0, 0.3).unwrap();
            let scan = Scan::new(at, ranges, bearings.clone()).unwrap();
            s.cover(&scan, 8.0);
            inserter.insert(s.grid.as_mut().unwrap(), &scan, 8.0);
        }
        s.close();
        s
    }

    /// Made into bytes a few rows a call or in one call: the same grid,
    /// and every cell read counted once whatever the slices.
    #[test]
    fn a_closed_submap_finished_in_slices_is_the_one_finished_at_once() {
        let mut whole = closed();
        let (whole_read, done) = whole.finish_within(u64::MAX);
        assert!(done && !whole.is_closing() && whole.grid.is_none());
        let mut sliced = closed();
        let (mut read, mut calls) = (0, 0);
        loop {
            let (r, done) = sliced.finish_within(100);
            read += r;
            calls += 1;
            if done {
                break;
            }
        }
        assert!(calls > 10, "{calls} calls");
        assert_eq!(read, whole_read);
        let (a, b) = (whole.finished.unwrap(), sliced.finished.unwrap());
        let bytes = a.unpacked();
        assert!(
            a.width > 10 && bytes.iter().any(|&v| v > 200),
            "a room's walls"
        );
        // The walls keep the normals of the surfaces their returns lay on.
        assert!(
            bytes.iter().any(|&v| v >> 4 >= 12 && v & 0b1111 != 0),
            "walls with normals"
        );
        assert_eq!(a, b);
    }
}
