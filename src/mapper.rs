//! Applying the occupancy grid recursion of Table 9.1 to a scan, two ways.
//!
//! * [`RayMapper`] — the production path. Each beam is rastered with a
//!   supercover line from the sensor out to the model's reach
//!   (`min(z_max, z + alpha/2)` for Table 9.2). Cells near the sensor lie on
//!   many beams, so the verdicts of one scan are gathered first and every
//!   touched cell is updated once, occupied evidence winning over free
//!   (Cartographer's range-data inserter does the same: hits, then misses,
//!   each cell once per scan). The result then does not depend on beam
//!   order, and the cost follows the cells the beams cross, not the map.
//! * [`sweep_scan`] — Table 9.1 as printed: every cell of the map is visited,
//!   the beam nearest in bearing is found, and the inverse model decides.
//!   This is what a wide cone (a sonar) needs: its cone covers cells that no
//!   beam's raster passes through.

use crate::grid::LogOddsGrid;
use crate::inverse::InverseModel;
use crate::raster::supercover;
use crate::scan::{wrap_angle, Scan};

/// The work one scan cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct ScanStats {
    /// Cells the mapper looked at (raster visits for the traversal, every
    /// cell of the map for the sweep).
    pub cells_visited: usize,
    /// Cells whose log odds were updated.
    pub cells_updated: usize,
}

/// The ray-traversal mapper, with its per-scan scratch space (kept between
/// scans so that integrating a scan allocates nothing).
#[derive(Debug, Default, Clone)]
pub struct RayMapper {
    /// Which scan last touched each cell (`epoch`), so that a cell is
    /// recorded once per scan without clearing a map-sized buffer.
    stamp: Vec<u32>,
    /// The evidence gathered for each touched cell in the current scan.
    pending: Vec<f32>,
    /// The cells touched in the current scan, in first-touch order.
    touched: Vec<u32>,
    epoch: u32,
}

impl RayMapper {
    pub fn new() -> Self {
        Self::default()
    }

    /// Integrates one scan into `grid` with the inverse model `model`.
    ///
    /// Each cell on a beam's raster gets the model's evidence for its range
    /// along the beam axis (the projection of its centre), at bearing offset
    /// zero: a thin beam's raster *is* its footprint. Every input was
    /// validated when the scan and model were built, so this cannot fail.
    pub fn integrate<M: InverseModel + ?Sized>(
        &mut self,
        grid: &mut LogOddsGrid,
        model: &M,
        scan: &Scan,
    ) -> ScanStats {
        let geometry = *grid.geometry();
        let n = geometry.len();
        if self.stamp.len() != n {
            self.stamp = vec![0; n];
            self.pending = vec![0.0; n];
            self.epoch = 0;
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        self.touched.clear();

        let pose = scan.pose();
        let (su, sv) = geometry.world_to_grid(pose.x, pose.y);
        let res = geometry.resolution();
        let (w, h) = (geometry.width(), geometry.height());
        let mut visits = 0;
        for (&z, &bearing) in scan.ranges().iter().zip(scan.bearings()) {
            let reach = model.reach(z);
            if !(reach > 0.0) {
                continue;
            }
            let (s, c) = (pose.theta + bearing).sin_cos();
            let end = (su + reach * c / res, sv + reach * s / res);
            let (stamp, pending, touched, epoch) = (
                &mut self.stamp,
                &mut self.pending,
                &mut self.touched,
                self.epoch,
            );
            visits += supercover(w, h, (su, sv), end, |ix, iy| {
                // Range of the cell centre along the beam axis, metres.
                let r = res * ((ix as f64 + 0.5 - su) * c + (iy as f64 + 0.5 - sv) * s);
                let e = model.evidence(r, 0.0, z);
                if e == 0.0 {
                    return;
                }
                let i = iy * w + ix;
                if stamp[i] != epoch {
                    stamp[i] = epoch;
                    pending[i] = e;
                    touched.push(i as u32);
                } else if e > pending[i] {
                    // Occupied (positive) wins over free; between two free
                    // verdicts the weaker one stands. Either way the rule is
                    // symmetric, so beam order does not matter.
                    pending[i] = e;
                }
            });
        }
        for &i in &self.touched {
            grid.apply(i as usize, self.pending[i as usize]);
        }
        ScanStats {
            cells_visited: visits,
            cells_updated: self.touched.len(),
        }
    }
}

/// Table 9.1 literally: every cell of the map, the nearest beam by bearing,
/// the inverse model. Each cell is updated at most once by construction.
pub fn sweep_scan<M: InverseModel + ?Sized>(
    grid: &mut LogOddsGrid,
    model: &M,
    scan: &Scan,
) -> ScanStats {
    let pose = scan.pose();
    // Beams sorted by bearing in (-pi, pi], for a binary search per cell.
    let mut beams: Vec<(f64, f64)> = scan
        .bearings()
        .iter()
        .zip(scan.ranges())
        .map(|(&b, &z)| (wrap_angle(b), z))
        .collect();
    beams.sort_by(|a, b| a.0.total_cmp(&b.0));
    let max_reach = beams
        .iter()
        .map(|&(_, z)| model.reach(z))
        .fold(0.0, f64::max);

    let geometry = *grid.geometry();
    let mut updated = 0;
    for iy in 0..geometry.height() {
        for ix in 0..geometry.width() {
            let (cx, cy) = geometry.cell_center(ix, iy);
            let (dx, dy) = (cx - pose.x, cy - pose.y);
            let r = dx.hypot(dy);
            if r > max_reach {
                continue;
            }
            let bearing = wrap_angle(dy.atan2(dx) - pose.theta);
            let (phi, z) = nearest_beam(&beams, bearing);
            let e = model.evidence(r, phi, z);
            if e != 0.0 {
                grid.apply(geometry.index(ix, iy), e);
                updated += 1;
            }
        }
    }
    ScanStats {
        cells_visited: geometry.len(),
        cells_updated: updated,
    }
}

/// The beam nearest in bearing to `bearing` among `beams` (sorted by
/// bearing, wrapped): returns the cell's offset from that beam's axis and
/// the beam's reading.
fn nearest_beam(beams: &[(f64, f64)], bearing: f64) -> (f64, f64) {
    let k = beams.partition_point(|&(b, _)| b < bearing);
    // The candidates are the neighbours of the insertion point, wrapping
    // around at +-pi.
    let below = beams[(k + beams.len() - 1) % beams.len()];
    let above = beams[k % beams.len()];
    let (d_below, d_above) = (wrap_angle(bearing - below.0), wrap_angle(bearing - above.0));
    if d_below.abs() <= d_above.abs() {
        (d_below, below.1)
    } else {
        (d_above, above.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{FilterSettings, GridGeometry};
    use crate::inverse::{HandCrafted, HandCraftedParams};
    use crate::scan::Pose;

    fn lidar() -> HandCrafted {
        HandCrafted::new(HandCraftedParams {
            alpha: 0.15,
            beta: 0.02,
            z_max: 8.0,
            l_occ: 0.85,
            l_free: -0.4,
            l0: 0.0,
        })
        .unwrap()
    }

    #[test]
    fn nearest_beam_wraps_around_pi() {
        let beams = [(-3.1, 1.0), (0.0, 2.0), (3.1, 3.0)];
        assert_eq!(nearest_beam(&beams, 3.14).1, 3.0);
        assert_eq!(nearest_beam(&beams, -3.14).1, 1.0);
        let (phi, z) = nearest_beam(&beams, 0.1);
        assert!((phi - 0.1).abs() < 1e-12 && z == 2.0);
    }

    #[test]
    fn one_beam_marks_free_then_occupied() {
        let g = GridGeometry::new(20, 5, 0.1, 0.0, 0.0).unwrap();
        let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        let scan = Scan::new(Pose::new(0.05, 0.25, 0.0).unwrap(), vec![1.0], vec![0.0]).unwrap();
        let stats = RayMapper::new().integrate(&mut m, &lidar(), &scan);
        let l = |ix| m.log_odds()[g.index(ix, 2)];
        assert!(l(3) < 0.0 && l(9) < 0.0, "free in front");
        assert!(l(10) > 0.0, "occupied at 1.0 m");
        assert_eq!(l(12), 0.0, "unknown behind");
        assert_eq!(stats.cells_updated, 11);
    }
}
