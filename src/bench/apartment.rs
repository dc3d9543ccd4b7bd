//! Benchmark workloads W2 `apartment-frame` and W3 `all-cells-vs-traversal`
//! of docs/BENCHMARKS.md, defined once so that the native benchmark
//! (benches/native.rs) and the wasm run under Node (scripts/bench/) do
//! exactly the same work. The callers hold the clock; these types only do
//! the work of one call.
//!
//! Both replay one lap of the apartment simulated in advance (seed 1, the
//! person walking, oracle poses), so that simulation is not timed.

use crate::apps::map_weaver::{Scaled, WeaverSettings};
use crate::error::{invalid, Result};
use crate::geometry::GridGeometry;
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, LearnedInverse};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::{RayMapper, ScanStats};
use crate::render::map_view::MapView;
use crate::scenes::apartment::{ApartmentScene, ApartmentSim};
use crate::sensors::Scan;

/// The seed of the lap both workloads replay.
pub const LAP_SEED: u64 = 1;

/// One lap of the default apartment as scans at the true poses.
pub fn lap_scans() -> Result<Vec<Scan>> {
    let scene = ApartmentScene::default();
    let mut sim = ApartmentSim::new(scene.clone(), LAP_SEED, true)?;
    let bearings = sim.bearings().to_vec();
    (0..scene.scans_per_lap())
        .map(|_| {
            let s = sim.next_scan();
            Scan::new(s.truth, s.ranges, bearings.clone())
        })
        .collect()
}

/// W2: one Map Weaver frame = one scan integrated into two maps (the
/// hand-crafted model and the learned model, as the widget's two panes by
/// default) and both maps' views brought up to date (pixels, entropy,
/// Brier score).
#[derive(Debug, Clone)]
pub struct ApartmentFrame {
    scans: Vec<Scan>,
    next: usize,
    hand: HandCrafted,
    learned: Scaled<LearnedInverse>,
    grids: [LogOddsGrid; 2],
    mappers: [RayMapper; 2],
    views: [MapView; 2],
}

impl ApartmentFrame {
    /// The workload with the learned model `learned` (train it with the
    /// default [`crate::inverse::TrainingConfig`]).
    pub fn new(learned: LearnedInverse) -> Result<Self> {
        let settings = WeaverSettings::default();
        let scene = &settings.scene;
        let truth = scene.ground_truth()?;
        let g = *truth.geometry();
        let region = scene.cells_in(&g, &[scene.surveyed]);
        let grid = LogOddsGrid::new(g, FilterSettings::default())?;
        let mut view = MapView::new(&g, truth.occupied(), &region)?;
        view.sync(&grid);
        Ok(Self {
            scans: lap_scans()?,
            next: 0,
            hand: HandCrafted::new(settings.hand_crafted)?,
            learned: Scaled {
                model: learned,
                factor: 1.0,
            },
            grids: [grid.clone(), grid],
            mappers: [RayMapper::new(), RayMapper::new()],
            views: [view.clone(), view],
        })
    }

    /// Scans in the lap.
    pub fn scans(&self) -> usize {
        self.scans.len()
    }

    /// Empties both maps and starts the lap again.
    pub fn restart(&mut self) {
        for (grid, view) in self.grids.iter_mut().zip(&mut self.views) {
            grid.reset();
            view.sync(grid);
        }
        self.next = 0;
    }

    fn next_scan(&mut self) -> usize {
        let k = self.next % self.scans.len().max(1);
        self.next += 1;
        k
    }

    /// One frame with the next scan of the lap (the lap wraps around).
    /// Returns the work done: cells visited by the two traversals.
    pub fn frame(&mut self) -> [ScanStats; 2] {
        let k = self.next_scan();
        let Some(scan) = self.scans.get(k) else {
            return [ScanStats::default(); 2];
        };
        let [g0, g1] = &mut self.grids;
        let [m0, m1] = &mut self.mappers;
        let stats = [
            m0.integrate(g0, &self.hand, scan),
            m1.integrate(g1, &self.learned, scan),
        ];
        self.views[0].sync(&self.grids[0]);
        self.views[1].sync(&self.grids[1]);
        stats
    }

    /// Only the `integrate_scan` call of one map (0: hand-crafted,
    /// 1: learned) with the next scan, without updating its view.
    pub fn integrate(&mut self, map: usize) -> Result<ScanStats> {
        if map > 1 {
            return Err(invalid("map", map, "0 (hand-crafted) or 1 (learned)"));
        }
        let k = self.next_scan();
        let Some(scan) = self.scans.get(k) else {
            return Ok(ScanStats::default());
        };
        let [g0, g1] = &mut self.grids;
        let [m0, m1] = &mut self.mappers;
        Ok(if map == 0 {
            m0.integrate(g0, &self.hand, scan)
        } else {
            m1.integrate(g1, &self.learned, scan)
        })
    }

    /// The RGBA pixels of one map's view (0 or 1).
    pub fn pixels(&self, map: usize) -> Option<&[u8]> {
        self.views.get(map).map(MapView::rgba)
    }
}

/// W3: the same lap, each scan integrated by the ray traversal into one
/// map and by the literal Table 9.1 sweep into another, at a chosen
/// resolution (the apartment's 12 m x 9 m at 0.10 m or 0.05 m).
#[derive(Debug, Clone)]
pub struct AllCellsVsTraversal {
    scans: Vec<Scan>,
    model: HandCrafted,
    traversal: LogOddsGrid,
    sweep: LogOddsGrid,
    mapper: RayMapper,
}

impl AllCellsVsTraversal {
    pub fn new(resolution: f64) -> Result<Self> {
        let settings = WeaverSettings::default();
        let scene = &settings.scene;
        let g = GridGeometry::covering(
            0.0,
            0.0,
            scene.width as f64 * scene.resolution,
            scene.height as f64 * scene.resolution,
            resolution,
        )?;
        let grid = LogOddsGrid::new(g, FilterSettings::default())?;
        Ok(Self {
            scans: lap_scans()?,
            model: HandCrafted::new(settings.hand_crafted)?,
            traversal: grid.clone(),
            sweep: grid,
            mapper: RayMapper::new(),
        })
    }

    pub fn scans(&self) -> usize {
        self.scans.len()
    }
    pub fn cells(&self) -> usize {
        self.traversal.geometry().len()
    }

    /// Scan `k` by ray traversal.
    pub fn traverse(&mut self, k: usize) -> Result<ScanStats> {
        let scan = lap_scan(&self.scans, k)?;
        Ok(self
            .mapper
            .integrate(&mut self.traversal, &self.model, scan))
    }

    /// Scan `k` by the sweep over every cell.
    pub fn sweep(&mut self, k: usize) -> Result<ScanStats> {
        let scan = lap_scan(&self.scans, k)?;
        Ok(sweep_scan(&mut self.sweep, &self.model, scan))
    }
}

fn lap_scan(scans: &[Scan], k: usize) -> Result<&Scan> {
    scans
        .get(k)
        .ok_or_else(|| invalid("scan", k, "an index below the lap's scan count"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::training::{train, TrainingConfig};

    #[test]
    fn frame_workload_fills_both_maps_and_wraps_around() {
        let (learned, _, _) = train(&TrainingConfig::default()).unwrap();
        let mut w = ApartmentFrame::new(learned).unwrap();
        let n = w.scans();
        assert!(n > 500);
        let mut visited = 0;
        for _ in 0..n + 3 {
            let [a, b] = w.frame();
            assert!(a.cells_visited > 0 && b.cells_visited > 0);
            visited += a.cells_visited;
        }
        assert!(visited / (n + 3) > 500, "a 60-beam scan crosses many cells");
        assert!(
            w.pixels(0).unwrap().iter().any(|&g| g < 10),
            "walls drawn black"
        );
        assert!(w.integrate(2).is_err());
    }

    #[test]
    fn sweep_visits_every_cell_traversal_only_the_beams() {
        let mut w = AllCellsVsTraversal::new(0.1).unwrap();
        let t = w.traverse(10).unwrap();
        let s = w.sweep(10).unwrap();
        assert_eq!(s.cells_visited, 10_800);
        assert!(t.cells_visited < 3_000, "{t:?}");
        assert!(w.sweep(100_000).is_err());
        assert_eq!(AllCellsVsTraversal::new(0.05).unwrap().cells(), 43_200);
    }
}
