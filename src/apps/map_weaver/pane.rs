//! One of Map Weaver's two maps: its grid, mapper and view, the model its
//! settings ask for, and everything the widget shows about it over time.
//!
//! Per scan ([`Pane::integrate`]): the scan at the pose the pane's settings
//! ask for (the oracle's or dead reckoning's), thinned to its beams, goes
//! through its inverse model and mapper into its grid (Table 9.1, by ray
//! traversal or by the literal sweep); its [`MapView`] brings pixels,
//! entropy and Brier score up to date from the cells that changed; the
//! curves, the tracked cells and the ghost watch take one more point.

use super::ghosts::GhostTracker;
use super::settings::{MapperKind, ModelKind, PaneSettings, PoseSource, SensorKind};
use super::timing::{Clock, RecentTimes};
use crate::apps::pane::MapPane;
use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{Dense, LogOdds};
use crate::inverse::{HandCrafted, HandCraftedParams, InverseModel, LearnedInverse, Scaled};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::ScanStats;
use crate::render::map_view::MapView;
use crate::scenes::apartment::{ApartmentScene, SimScan};
use crate::sensors::Scan;
use std::borrow::Cow;
use std::cell::OnceCell;

/// A Map Weaver map: the whole apartment at one pixel per cell, its view
/// kept up to date cell by cell with its entropy and Brier score.
pub(super) type WeaverMap = MapPane<LogOdds, Dense<f32>, MapView>;

/// A pane's inverse model, with the strength applied. An enum rather than
/// a trait object so that the traversal's inner loop is monomorphic. The
/// learned model is boxed: its tables are inline (about 12 KB), and a run
/// holding them by value would be tens of kilobytes in every stack frame
/// that moves it (a debug wasm build has a 1 MB stack).
#[derive(Debug, Clone)]
pub(super) enum PaneModel {
    HandCrafted(HandCrafted),
    Learned(Box<Scaled<LearnedInverse>>),
}

impl PaneModel {
    /// The model pane settings `p` ask for: the kind, its strength, the
    /// cone's opening for Table 9.2, and `l0` forgotten or not.
    pub fn build(
        p: &PaneSettings,
        base: &HandCraftedParams,
        learned: &LearnedInverse,
    ) -> Result<Self> {
        Ok(match p.model {
            ModelKind::HandCrafted => {
                let mut params = *base;
                if p.sensor == SensorKind::Cone {
                    params.beta = p.beta_deg.to_radians();
                }
                if p.forget_l0 {
                    // Evidence l - 0 instead of l - l0.
                    let l0 = params.l0;
                    params.l_occ -= l0;
                    params.l_free -= l0;
                }
                Self::HandCrafted(HandCrafted::with_strength(params, p.strength)?)
            }
            ModelKind::Learned => {
                let model = if p.forget_l0 {
                    learned.with_l0(0.0)
                } else {
                    learned.clone()
                };
                Self::Learned(Box::new(Scaled::new(model, p.strength)?))
            }
        })
    }

    pub(super) fn integrate(
        &self,
        kind: MapperKind,
        map: &mut WeaverMap,
        scan: &Scan,
    ) -> ScanStats {
        match (self, kind) {
            (Self::HandCrafted(m), MapperKind::Traversal) => map.integrate(m, scan),
            (Self::Learned(m), MapperKind::Traversal) => map.integrate(&**m, scan),
            (Self::HandCrafted(m), MapperKind::Sweep) => {
                let stats = sweep_scan(map.grid_mut(), m, scan);
                map.count(scan, stats);
                stats
            }
            (Self::Learned(m), MapperKind::Sweep) => {
                let stats = sweep_scan(map.grid_mut(), &**m, scan);
                map.count(scan, stats);
                stats
            }
        }
    }

    /// The log odds one free reading adds (Table 9.2's `l_free - l0` at
    /// the pane's strength); `None` for the learned model, whose free
    /// evidence depends on the range.
    pub fn free_evidence(&self) -> Option<f32> {
        match self {
            Self::HandCrafted(m) => Some((m.params().l_free - m.params().l0) as f32),
            Self::Learned(_) => None,
        }
    }

    /// The prior the model removes from its scores (0 when `l0` is
    /// forgotten).
    pub fn l0(&self) -> f32 {
        match self {
            Self::HandCrafted(m) => m.l0(),
            Self::Learned(m) => m.l0(),
        }
    }
}

/// One simulated scan as a mapper's [`Scan`], at the true pose, and at the
/// dead-reckoned pose when a pane asks for it (validated once, whichever
/// panes use it).
pub(super) struct PoseScans {
    oracle: Scan,
    odometry: Pose,
    dead_reckoning: OnceCell<Scan>,
}

impl PoseScans {
    pub fn new(scan: &SimScan, bearings: &[f64]) -> Result<Self> {
        Ok(Self {
            oracle: Scan::new(scan.truth, scan.ranges.clone(), bearings.to_vec())?,
            odometry: scan.odometry,
            dead_reckoning: OnceCell::new(),
        })
    }

    fn at(&self, pose: PoseSource) -> Result<&Scan> {
        match pose {
            PoseSource::Oracle => Ok(&self.oracle),
            PoseSource::DeadReckoning => {
                if let Some(s) = self.dead_reckoning.get() {
                    return Ok(s);
                }
                let s = self.oracle.with_pose(self.odometry)?;
                Ok(self.dead_reckoning.get_or_init(|| s))
            }
        }
    }
}

/// One map and everything the widget shows about it.
#[derive(Debug, Clone)]
pub(super) struct Pane {
    pub settings: PaneSettings,
    pub model: PaneModel,
    /// The pane's own scene: the run's, at the pane's resolution (its grid
    /// limits may differ from the other pane's).
    pub scene: ApartmentScene,
    pub geometry: GridGeometry,
    /// The ground truth at the pane's resolution.
    pub truth: Vec<bool>,
    pub tracked_cells: [usize; 3],
    /// The grid, its mapper and its view.
    pub map: WeaverMap,
    /// Entropy (bits) after each scan; entry 0 is the empty map.
    pub entropy_curve: Vec<f64>,
    /// Brier score over the surveyed region after each scan; entry 0 is
    /// the empty map.
    pub brier_curve: Vec<f64>,
    /// The tracked cells' log odds after each scan; entry 0 is the empty
    /// map.
    pub tracked: Vec<[f32; 3]>,
    pub last: ScanStats,
    /// The pose the last scan was integrated at.
    pub pose: Pose,
    pub ghost: GhostTracker,
    /// Core milliseconds of the pane's recent scans (mapping and view).
    pub scan_ms: RecentTimes,
    /// How far the sweep of the pane's next scan has gone, when it is
    /// spread over several calls ([`super::stepping`]).
    pub sweep: SweepProgress,
}

/// A scan's sweep under way: the rows swept so far (from row 0), and the
/// work and time they took. The view and the curves wait for the last row.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct SweepProgress {
    pub rows: usize,
    pub stats: ScanStats,
    pub ms: f64,
}

impl Pane {
    /// The scan this pane maps: at the pose its settings ask for, thinned
    /// to its beams.
    pub fn scan<'a>(&self, scans: &'a PoseScans) -> Result<Cow<'a, Scan>> {
        let full = scans.at(self.settings.pose)?;
        full.thinned(self.beam_stride(full.len()))
    }

    /// What follows a scan's mapping (`stats`, the work it took): the view,
    /// the curves and the ghost watch take one more point. `started`: the
    /// clock when the last part of the mapping began, and the milliseconds
    /// its earlier parts took.
    pub fn finish_scan(
        &mut self,
        s: &Scan,
        stats: ScanStats,
        sim: &SimScan,
        count: usize,
        clock: Option<Clock>,
        started: Option<(f64, f64)>,
    ) {
        self.last = stats;
        self.pose = s.pose();
        self.map.pixels();
        if let (Some(c), Some((t0, before))) = (clock, started) {
            self.scan_ms.record(before + (c() - t0).max(0.0));
        }
        let (grid, view) = (self.map.grid(), self.map.view());
        self.entropy_curve.push(view.entropy_bits());
        self.brier_curve.push(view.brier_region());
        self.tracked
            .push(self.tracked_cells.map(|i| grid.log_odds()[i]));
        let near = sim.person.map(|r| self.near_person(r)).unwrap_or_default();
        self.ghost.observe(count, &near, self.map.grid().log_odds());
    }

    /// Scans integrated so far (a scan whose sweep is under way is not).
    pub fn scans_done(&self) -> usize {
        self.entropy_curve.len() - 1
    }

    /// The cells a person standing on `footprint` may have marked: the
    /// beams end on their outline, and Table 9.2 puts the occupied band on
    /// the cell whose centre lies within `alpha / 2` of the reading, which
    /// may lie just outside the footprint. So the footprint grown by one
    /// cell, less the cells the ground truth holds occupied (a wall next to
    /// the person is no ghost).
    fn near_person(&self, footprint: crate::world::Rect) -> Vec<usize> {
        let m = self.geometry.resolution();
        let grown = crate::world::Rect::new(
            footprint.min_x - m,
            footprint.min_y - m,
            footprint.max_x + m,
            footprint.max_y + m,
        );
        let mut cells = self.scene.cells_in(&self.geometry, &[grown]);
        cells.retain(|&c| !self.truth[c]);
        cells
    }

    /// Back to the empty map, with the settings it has: the sums start
    /// from zero, as a new pane's do, so that a pane rebuilt over the same
    /// scans is bit for bit the pane that had these settings all along.
    pub fn clear(&mut self) {
        self.map.reset();
        self.map.pixels();
        self.entropy_curve.truncate(1);
        self.brier_curve.truncate(1);
        self.tracked.truncate(1);
        self.last = ScanStats::default();
        self.ghost.clear();
        self.scan_ms.clear();
        self.sweep = SweepProgress::default();
    }

    /// The pane uses every `stride`-th beam of a `lidar_beams`-beam scan:
    /// its beam count divides the LiDAR's (checked with the settings), so
    /// the beams kept stay evenly spaced.
    pub fn beam_stride(&self, lidar_beams: usize) -> usize {
        self.settings
            .beams
            .map_or(1, |b| lidar_beams / b.max(1))
            .max(1)
    }
}
