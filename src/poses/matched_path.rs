//! A scan-matched path with a map of its own ([`MatchedPath`]): the
//! scan-matched pose source ([`ScanMatching`]) and a log-odds map it
//! inserts each scan into at the pose found, one scan per step, for a
//! caller that holds no map of its own. One step is one scan: its work is
//! the match's bound ([`crate::mapping::scan_match::ScanMatcher`]) plus one
//! scan's insertion, whatever the log's length.

use super::{PoseSource, ScanMatching};
use crate::error::{self, invalid, OccError, Result};
use crate::geometry::Pose;
use crate::grid::storage::TILE_CELLS;
use crate::grid::TiledGrid;
use crate::mapping::insertion::{ScanInserter, ScanInsertion};
use crate::mapping::scan_match::{MatchReport, MatchSettings, Prediction};
use crate::mapping::traversal::MAX_REACH_CELLS;
use crate::sensors::odometry::OdometryParams;
use crate::sensors::Scan;

/// What one step did.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct StepReport {
    /// The scan's index in the log.
    pub scan: usize,
    #[serde(flatten)]
    pub matched: MatchReport,
    /// Cells the scan's integration updated.
    pub cell_updates: usize,
}

/// Scan-matched poses and the map built at them, one scan per step.
#[derive(Debug, Clone)]
pub struct MatchedPath {
    source: ScanMatching,
    /// Scans located and inserted so far.
    done: usize,
    inserter: ScanInserter,
    grid: TiledGrid,
    /// Why the path stopped short (the map's tile budget), once it has.
    failure: Option<OccError>,
}

impl MatchedPath {
    /// A path over a log of `odometry.len()` scans, building its map in
    /// `grid` (which should be fresh, and wide enough for the path: the
    /// odometry's extent plus the range cap and a few metres of drift;
    /// beams past its edge are clipped). `noise` is the odometry's
    /// (Table 5.6; [`OdometryParams::WHEELS`] for seeded dead reckoning):
    /// it says how far each prediction may be off. Errors name the bad
    /// field.
    pub fn new(
        grid: TiledGrid,
        odometry: Vec<Pose>,
        noise: OdometryParams,
        settings: MatchSettings,
        insertion: ScanInsertion,
    ) -> Result<Self> {
        let res = grid.geometry().resolution();
        let source = ScanMatching::new(odometry, noise, settings, res)?;
        noise.validate()?;
        let inserter = ScanInserter::new(insertion)?;
        let z_max = insertion.model.z_max;
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(z_max / res <= MAX_REACH_CELLS) {
            return Err(invalid(
                "z_max",
                error::show(z_max),
                format!(
                    "at most 2045 cells of the resolution ({} m at {} m per cell)",
                    error::show(MAX_REACH_CELLS * res),
                    error::show(res)
                ),
            ));
        }
        for (k, p) in source.odometry().iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite()) {
                return Err(invalid(
                    &format!("odometry[{k}]"),
                    format!("({}, {}, {})", p.x, p.y, p.theta),
                    "a pose of finite numbers",
                ));
            }
        }
        Ok(Self {
            source,
            done: 0,
            inserter,
            grid,
            failure: None,
        })
    }

    /// The index of the scan [`Self::step`] takes next.
    pub fn next_scan(&self) -> usize {
        self.done
    }

    /// Scans in the log (one per odometry pose).
    pub fn len(&self) -> usize {
        self.source.odometry().len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// True once every scan has been matched and integrated.
    pub fn is_finished(&self) -> bool {
        self.done == self.len()
    }

    /// Where scan `next_scan()` is predicted: the last pose found, moved
    /// by the odometry's increment, with that increment's spread.
    pub fn prediction(&self) -> Option<Prediction> {
        self.source.prediction(self.done)
    }

    /// Matches and integrates the next scan of the log (`scan`, its own
    /// pose ignored; `laser_max` the laser's own maximum range, infinite
    /// when the log does not say). An error, and nothing changed, past the
    /// last scan; an error once the map's tile budget is spent (said in
    /// words, and repeated by every later call).
    pub fn step(&mut self, scan: &Scan, laser_max: f64) -> Result<StepReport> {
        if let Some(e) = &self.failure {
            return Err(e.clone());
        }
        let k = self.done;
        if self.prediction().is_none() {
            return Err(OccError::State(format!(
                "all {} scans of the path are matched",
                self.len()
            )));
        }
        if laser_max.is_nan() || laser_max <= 0.0 {
            return Err(invalid(
                "laser_max",
                error::show(laser_max),
                "a range above 0 (infinite when the log does not say)",
            ));
        }
        let pose = self.source.locate(k, scan, laser_max, &self.grid)?;
        let matched = match self.source.last() {
            Some((at, report)) if at == k => *report,
            _ => MatchReport::unmatched(pose),
        };
        let placed = scan.with_pose(pose)?;
        let cell_updates = self
            .inserter
            .insert(&mut self.grid, &placed, laser_max)
            .cells_updated;
        if self.grid.refused() {
            let e = OccError::State(format!(
                "the map's tile budget ({} cells) is spent at scan {k}: the matched path \
                 reaches more of the map than it can hold; choose a coarser resolution",
                self.grid.max_tiles() * TILE_CELLS
            ));
            self.failure = Some(e.clone());
            return Err(e);
        }
        self.done += 1;
        Ok(StepReport {
            scan: k,
            matched,
            cell_updates,
        })
    }

    /// The poses found so far, one per scan integrated.
    pub fn poses(&self) -> &[Pose] {
        &self.source.poses()[..self.done]
    }

    /// The odometry the path corrects.
    pub fn odometry(&self) -> &[Pose] {
        self.source.odometry()
    }

    /// The map built at the poses found.
    pub fn grid(&self) -> &TiledGrid {
        &self.grid
    }

    pub fn into_grid(self) -> TiledGrid {
        self.grid
    }

    pub fn settings(&self) -> &MatchSettings {
        self.source.matcher().settings()
    }

    /// Why the path stopped short, if it did.
    pub fn failure(&self) -> Option<&OccError> {
        self.failure.as_ref()
    }

    /// Back to before the first scan: the map emptied, no pose found.
    pub fn reset(&mut self) {
        self.grid.reset();
        self.source.reset();
        self.done = 0;
        self.failure = None;
    }
}
