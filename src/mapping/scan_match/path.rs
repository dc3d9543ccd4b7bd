//! The scan-matched pose source: a path that advances one scan at a time.
//!
//! Scan `k` is predicted from the pose found for scan `k - 1` and the
//! motion the odometry reports between them (the increment from odometry
//! pose `k - 1` to `k`: seeded dead reckoning, or a log's own odometry),
//! matched against the map of scans `0..k` at their matched poses, and
//! then integrated at the pose found (the same per-scan recipe as the
//! real-log map: [`crate::mapping::walls::beam_bands`] and
//! [`RayMapper::integrate_bands`], with the shorter model of a laser whose
//! maximum range is below the cap). The first scan is put at the first
//! odometry pose: the path starts where the log does.
//!
//! One [`MatchedPath::step`] is one scan: its work is the match's bound
//! ([`super::ScanMatcher`]) plus one scan's integration, whatever the log's
//! length, so a page calls it as often as its time slice allows.

use super::{MatchReport, MatchSettings, Prediction, ScanMatcher};
use crate::error::{self, invalid, OccError, Result};
use crate::geometry::Pose;
use crate::grid::storage::TILE_CELLS;
use crate::grid::{CellModel, Grid, Store, TiledGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::traversal::{BeamBand, RayMapper, MAX_REACH_CELLS};
use crate::mapping::walls::{beam_bands, WallModel};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::Scan;

/// How a scan is written into the map: Table 9.2's model (its `z_max` the
/// range cap), how far a no-return clears, and how free evidence ends
/// before a wall ([`WallModel`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanInsertion {
    pub model: HandCraftedParams,
    /// Metres a no-return clears (at most the model's `z_max` is used).
    pub no_return_reach: f64,
    pub walls: WallModel,
}

impl ScanInsertion {
    /// Checks the model (its own field names) and the reach.
    pub fn validate(&self) -> Result<HandCrafted> {
        let model = HandCrafted::new(self.model)?;
        error::positive("no_return_reach", self.no_return_reach)?;
        let p = &self.model;
        if !((p.l_occ - p.l0) as f32 > 0.0 && ((p.l_free - p.l0) as f32) < 0.0) {
            return Err(invalid(
                "l_occ, l_free",
                format!("{}, {}", error::show(p.l_occ), error::show(p.l_free)),
                "occupied evidence above l0 and free evidence below it",
            ));
        }
        Ok(model)
    }
}

/// Writes scans into a map, one at a time, the real-log way
/// ([`ScanInsertion`]), keeping the traversal's scratch between scans.
#[derive(Debug, Clone)]
pub struct ScanInserter {
    insertion: ScanInsertion,
    model: HandCrafted,
    mapper: RayMapper,
    bands: Vec<Option<BeamBand>>,
}

impl ScanInserter {
    pub fn new(insertion: ScanInsertion) -> Result<Self> {
        Ok(Self {
            model: insertion.validate()?,
            insertion,
            mapper: RayMapper::new(),
            bands: Vec::new(),
        })
    }

    pub fn insertion(&self) -> &ScanInsertion {
        &self.insertion
    }

    /// Integrates `scan` at its own pose into `grid` (`laser_max` the
    /// laser's own maximum range, infinite when the log does not say):
    /// the cells updated. Beams past the map's edge are clipped; past the
    /// store's budget nothing more is written ([`Grid::refused`] says so).
    pub fn insert<C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        scan: &Scan,
        laser_max: f64,
    ) -> usize {
        let ins = &self.insertion;
        // A laser that says its own maximum range is shorter than the cap
        // reports no-returns at that maximum: the model must treat them as
        // no-returns, not as walls at the maximum.
        let short = (laser_max < ins.model.z_max)
            .then(|| {
                HandCrafted::new(HandCraftedParams {
                    z_max: laser_max,
                    ..ins.model
                })
                .ok()
            })
            .flatten();
        let model = short.as_ref().unwrap_or(&self.model);
        let res = grid.geometry().resolution();
        beam_bands(
            scan,
            model,
            ins.no_return_reach,
            ins.walls,
            res,
            &mut self.bands,
        );
        let p = model.params();
        let (free, occupied) = ((p.l_free - p.l0) as f32, (p.l_occ - p.l0) as f32);
        self.mapper
            .integrate_bands(grid, scan, &self.bands, free, occupied)
            .cells_updated
    }
}

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
    /// One odometry pose per scan of the log: only their increments are
    /// used (and the first pose, where the path starts).
    odometry: Vec<Pose>,
    /// The odometry's noise: how far each increment may be off.
    noise: OdometryParams,
    /// The poses found so far, one per scan integrated.
    matched: Vec<Pose>,
    matcher: ScanMatcher,
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
        settings.validate_for(res)?;
        noise.validate()?;
        let inserter = ScanInserter::new(insertion)?;
        let z_max = insertion.model.z_max;
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
        for (k, p) in odometry.iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite()) {
                return Err(invalid(
                    &format!("odometry[{k}]"),
                    format!("({}, {}, {})", p.x, p.y, p.theta),
                    "a pose of finite numbers",
                ));
            }
        }
        Ok(Self {
            matched: Vec::with_capacity(odometry.len()),
            odometry,
            noise,
            matcher: ScanMatcher::new(settings)?,
            inserter,
            grid,
            failure: None,
        })
    }

    /// The index of the scan [`Self::step`] takes next.
    pub fn next_scan(&self) -> usize {
        self.matched.len()
    }

    /// Scans in the log (one per odometry pose).
    pub fn len(&self) -> usize {
        self.odometry.len()
    }

    pub fn is_empty(&self) -> bool {
        self.odometry.is_empty()
    }

    /// True once every scan has been matched and integrated.
    pub fn is_finished(&self) -> bool {
        self.matched.len() == self.odometry.len()
    }

    /// Where scan `next_scan()` is predicted: the last pose found, moved
    /// by the odometry's increment, with that increment's spread.
    pub fn prediction(&self) -> Option<Prediction> {
        let k = self.matched.len();
        let s = self.matcher.settings();
        match k {
            0 => Some(Prediction::at(*self.odometry.first()?, s)),
            _ => {
                let (a, b) = (self.odometry.get(k - 1)?, self.odometry.get(k)?);
                Some(Prediction::from_odometry(
                    &self.matched[k - 1],
                    a,
                    b,
                    &self.noise,
                    s,
                ))
            }
        }
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
        let k = self.matched.len();
        let Some(prediction) = self.prediction() else {
            return Err(OccError::State(format!(
                "all {} scans of the path are matched",
                self.odometry.len()
            )));
        };
        if laser_max.is_nan() || laser_max <= 0.0 {
            return Err(invalid(
                "laser_max",
                error::show(laser_max),
                "a range above 0 (infinite when the log does not say)",
            ));
        }
        let matched = if k == 0 {
            // Nothing to match against yet: the path starts where the
            // odometry does.
            MatchReport::unmatched(prediction.pose)
        } else {
            self.matcher
                .match_scan(&self.grid, scan, laser_max, &prediction)?
        };
        let placed = scan.with_pose(matched.pose)?;
        let cell_updates = self.inserter.insert(&mut self.grid, &placed, laser_max);
        if self.grid.refused() {
            let e = OccError::State(format!(
                "the map's tile budget ({} cells) is spent at scan {k}: the matched path \
                 reaches more of the map than it can hold; choose a coarser resolution",
                self.grid.max_tiles() * TILE_CELLS
            ));
            self.failure = Some(e.clone());
            return Err(e);
        }
        self.matched.push(matched.pose);
        Ok(StepReport {
            scan: k,
            matched,
            cell_updates,
        })
    }

    /// The poses found so far, one per scan integrated.
    pub fn poses(&self) -> &[Pose] {
        &self.matched
    }

    /// The odometry the path corrects.
    pub fn odometry(&self) -> &[Pose] {
        &self.odometry
    }

    /// The map built at the poses found.
    pub fn grid(&self) -> &TiledGrid {
        &self.grid
    }

    pub fn into_grid(self) -> TiledGrid {
        self.grid
    }

    pub fn settings(&self) -> &MatchSettings {
        self.matcher.settings()
    }

    /// Why the path stopped short, if it did.
    pub fn failure(&self) -> Option<&OccError> {
        self.failure.as_ref()
    }

    /// Back to before the first scan: the map emptied, no pose found.
    pub fn reset(&mut self) {
        self.grid.reset();
        self.matched.clear();
        self.failure = None;
    }
}
