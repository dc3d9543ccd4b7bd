//! Submaps (Hess et al. 2016, section IV): a small log-odds grid of a few
//! consecutive scans in the local frame, which scans are matched against
//! while it grows; once it holds its scans it is finished, never changes
//! again, and is kept only as bytes for loop search ([`LoopGrid`]).
//! Two submaps grow at once, the second started halfway through the
//! first, so that a scan is always matched against a submap of at least
//! half its scans.

use super::loop_search::LoopGrid;
use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{FilterSettings, TiledGrid};
use crate::sensors::Scan;

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
    /// When its last loop search ended, in searches of any submap: the
    /// least recent drops its grids of maxima first.
    pub searched: u64,
    /// The box its scans' poses and beam ends span (world, metres): the
    /// only cells a finished grid is read over.
    bounds: [f64; 4],
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
            searched: 0,
            bounds: [pose.x, pose.y, pose.x, pose.y],
        })
    }

    /// Widens the box to `scan` at its pose, each beam cut at `reach`
    /// metres (the insertion's cap; a no-return clears no further).
    pub fn cover(&mut self, scan: &Scan, reach: f64) {
        let p = scan.pose();
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

    /// The grid kept as bytes over the box of its known cells; the grid
    /// dropped.
    pub fn finish(&mut self) {
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
        let (cx0, cy0) = (
            cell(self.bounds[0] - pad, ox, w),
            cell(self.bounds[1] - pad, oy, h),
        );
        let (cx1, cy1) = (
            cell(self.bounds[2] + pad, ox, w),
            cell(self.bounds[3] + pad, oy, h),
        );
        let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
        let mut known = Vec::new();
        for iy in cy0..=cy1 {
            for ix in cx0..=cx1 {
                if grid.updates_at(ix, iy).is_some_and(|u| u > 0) {
                    x0 = x0.min(ix);
                    y0 = y0.min(iy);
                    x1 = x1.max(ix);
                    y1 = y1.max(iy);
                }
            }
        }
        if x0 > x1 || y0 > y1 {
            self.finished = Some(LoopGrid::new(g.origin(), g.resolution(), 0, 0, known));
            return;
        }
        let (bw, bh) = (x1 - x0 + 1, y1 - y0 + 1);
        known.reserve(bw * bh);
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                let byte = match (grid.updates_at(ix, iy), grid.log_odds_at(ix, iy)) {
                    (Some(u), Some(l)) if u > 0 => {
                        let p = 1.0 / (1.0 + (-(l as f64)).exp());
                        (p * 255.0).round() as u8
                    }
                    _ => 0,
                };
                known.push(byte);
            }
        }
        self.finished = Some(LoopGrid::new(
            [ox + x0 as f64 * res, oy + y0 as f64 * res],
            res,
            bw,
            bh,
            known,
        ));
    }
}
