//! The scan-matched pose source ([`ScanMatching`]): each scan's pose is
//! predicted from the pose found for the scan before and the odometry's
//! increment between them (the log's own odometry, or seeded dead
//! reckoning where it has none), corrected by matching the scan against
//! the map of the scans before it ([`crate::mapping::scan_match`]), and
//! only then integrated there. The first scan is put at the first
//! odometry pose: the path starts where the log does.

use super::{PoseSource, PoseSourceKind, SourceInfo};
use crate::error::Result;
use crate::geometry::Pose;
use crate::mapping::scan_match::{MatchMap, MatchReport, MatchSettings, Prediction, ScanMatcher};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::{Scan, ScanLog};

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::ScanMatched,
    name: "scan-matched",
    menu: "scan-matched (dead reckoning corrected by matching each scan)",
    caption: &["Scan-matched (from dead reckoning, seed ", ")"],
    described: Some(&[
        "scan-matched (seed ",
        "): dead reckoning (or the log's own odometry) corrected by matching each scan against the map built so far, not the log's corrected poses",
    ]),
    // The corrected map for comparison, and the dead-reckoned one it
    // started from (the same seed).
    provenance: &[
        "scan-matched (from odometry simulated with Table 5.6's noise, seed ",
        ", or the log's own odometry where it differs from its corrected poses)",
    ],
    export_suffix: Some("scan-matched"),
    beside: &[PoseSourceKind::Corrected, PoseSourceKind::DeadReckoning],
};

/// Metres of drift the map holds beyond the extent of the scans at the
/// log's own poses: a matched path that strays further has its beams
/// clipped at the map's edge (and its pane shows the path leaving it). Not
/// the odometry's extent: the map of a matched path should look like the
/// building, at the scale of the maps beside it, not like the space dead
/// reckoning wandered through.
pub const MATCH_DRIFT_MARGIN: f64 = 5.0;

/// The matching work one step costs, in the units of a cell update: so
/// that a page's time slice, a budget of cell updates, holds the matching
/// too. Fitted to each scan's time on the Intel and Freiburg 101 logs at
/// 5 cm (a cell update taken as 12 ns): a search candidate's point costs
/// about 1.5 ns (an eighth of an update), a Gauss–Newton iteration's point
/// 48 ns (four: each reads the 3 x 3 cells of the smooth field) and a map
/// cell pooled into the coarse levels 2.5 ns (a fifth); a scan's time is
/// within 8 to 16 ns per unit of its estimate for eight scans in ten. A
/// candidate also costs `CANDIDATE_POINTS` points of its own, whatever
/// its points: a log of one-beam scans, counted by its points alone, ran
/// at twice the time per unit of the office logs.
pub fn match_work(report: &MatchReport) -> u64 {
    let points = report.points as u64;
    let search = report.candidates as u64 * (points + CANDIDATE_POINTS) / 8;
    let refine = report.iterations as u64 * points * 4;
    search + refine + pooled_work(report)
}

/// The part of [`match_work`] that is the coarse copy's: a map cell
/// pooled a fifth of a unit.
pub fn pooled_work(report: &MatchReport) -> u64 {
    report.cells_read as u64 / 5
}

/// What a search candidate costs besides its points (its heading's
/// rotation, its place among the best), in points: a one-beam scan's
/// match (some 4,300 candidates) took 66 us natively, 10 ns per unit
/// counted so, 33 counted by its one point (the office logs: 13 to 15).
pub const CANDIDATE_POINTS: u64 = 8;

/// The most [`match_work`] one scan's match may cost under `settings` on a
/// map of `resolution` metres per cell: `(per scan, per point matched)`.
/// A scan's points lie within `max_range` of its pose and the window
/// reaches at most `max_linear_window` and `max_angular_window` either
/// side, so the coarse copy reads at most a square of `2 (maxRange +
/// maxLinearWindow) / resolution` cells a side (and a few coarse cells of
/// rounding), the search scores at most the widest window's candidates, and
/// each hypothesis runs at most `maxIterations` steps on each coarse level,
/// and the best two more on the map itself.
pub fn match_work_bound(settings: &MatchSettings, resolution: f64) -> (u64, u64) {
    let s = settings;
    let coarse = s.coarse_factor as f64;
    let side = 2.0 * (s.max_range + s.max_linear_window) / resolution + 8.0 * coarse + 2.0;
    let widest = MatchSettings {
        linear_window: s.max_linear_window,
        angular_window: s.max_angular_window,
        ..*s
    };
    let candidates = widest.candidates_at(resolution * coarse);
    let coarse_levels = s.coarse_factor.max(1).ilog2() as u64;
    let iterations = (s.hypotheses as u64 * coarse_levels + 2) * s.max_iterations as u64;
    // (Saturating: settings that pass `check_resolution` give a few
    // million at most.)
    let per_scan = (side * side / 5.0 + candidates * CANDIDATE_POINTS as f64 / 8.0).ceil() as u64;
    let per_point = (candidates / 8.0).ceil() as u64 + iterations * 4;
    (per_scan, per_point)
}

/// The most [`match_work`] matching every scan of `log` but the first may
/// cost under `settings` on a map of `resolution` metres per cell, each
/// at the most [`match_work_bound`] allows with as many points as it has
/// beams (at most `maxPoints`): known before the path it corrects is.
pub(super) fn path_work_bound(settings: &MatchSettings, resolution: f64, log: &ScanLog) -> u64 {
    let (per_scan, per_point) = match_work_bound(settings, resolution);
    let matched = log.len().saturating_sub(1) as u64;
    let points = (log.beams() as u64).min(matched.saturating_mul(settings.max_points as u64));
    matched
        .saturating_mul(per_scan)
        .saturating_add(points.saturating_mul(per_point))
}

/// The matcher's settings for a map whose range cap is `range_cap`
/// metres: the defaults, with points matched out to the cap at most (a
/// return past it marks nothing on the map, so it has nothing to fit).
pub fn match_settings(range_cap: f64) -> MatchSettings {
    let defaults = MatchSettings::default();
    MatchSettings {
        max_range: defaults.max_range.min(range_cap),
        ..defaults
    }
}

/// Scan matching as a pose source: the odometry it corrects, the poses
/// found, the matcher and its last report.
#[derive(Debug, Clone)]
pub struct ScanMatching {
    /// One odometry pose per scan: only their increments are used, and
    /// the first pose, where the path starts.
    odometry: Vec<Pose>,
    /// The poses found for the scans located so far; the odometry's for
    /// the others.
    poses: Vec<Pose>,
    /// The odometry's noise (Table 5.6): how far each prediction may be off.
    noise: OdometryParams,
    matcher: ScanMatcher,
    last: Option<(usize, MatchReport)>,
    /// The matching work since the last reset ([`match_work`]).
    work: u64,
    /// The map's resolution, metres per cell (what a match's work is
    /// bounded at: [`match_work_bound`]).
    resolution: f64,
}

impl ScanMatching {
    /// Matching from `odometry` (one pose per scan) with `noise`, on maps
    /// of `resolution` metres per cell: `settings` are checked once, here.
    pub fn new(
        odometry: Vec<Pose>,
        noise: OdometryParams,
        settings: MatchSettings,
        resolution: f64,
    ) -> Result<Self> {
        let matcher = ScanMatcher::for_resolution(settings, resolution)?;
        let poses = odometry.clone();
        Ok(Self::of_path(matcher, (odometry, poses), noise, resolution))
    }

    /// Matching with `matcher` (checked at `resolution`) from `odometry`,
    /// `poses` a copy of it (the poses found so far: none yet).
    pub(super) fn of_path(
        matcher: ScanMatcher,
        (odometry, poses): (Vec<Pose>, Vec<Pose>),
        noise: OdometryParams,
        resolution: f64,
    ) -> Self {
        Self {
            matcher,
            poses,
            odometry,
            noise,
            last: None,
            work: 0,
            resolution,
        }
    }

    /// The odometry a path over `log` corrects: the log's own when it has
    /// some, else seeded dead reckoning of its poses.
    pub fn odometry_of(log: &ScanLog, seed: u64, noise: &OdometryParams) -> Vec<Pose> {
        match log.odometry() {
            Some(own) => own.to_vec(),
            None => noise.dead_reckon_path(log.poses(), seed),
        }
    }

    /// The odometry this path corrects.
    pub fn odometry(&self) -> &[Pose] {
        &self.odometry
    }

    /// The matcher (its settings, the points of the last scan matched).
    pub fn matcher(&self) -> &ScanMatcher {
        &self.matcher
    }

    /// The last scan matched and what the match found.
    pub fn last(&self) -> Option<(usize, &MatchReport)> {
        self.last.as_ref().map(|(k, r)| (*k, r))
    }

    /// Where scan `k` is predicted: the pose found for scan `k - 1`, moved
    /// by the odometry's increment, with that increment's spread; the
    /// first scan where the odometry starts.
    pub fn prediction(&self, k: usize) -> Option<Prediction> {
        let s = self.matcher.settings();
        match k {
            0 => Some(Prediction::at(*self.odometry.first()?, s)),
            _ => Some(Prediction::from_odometry(
                self.poses.get(k - 1)?,
                self.odometry.get(k - 1)?,
                self.odometry.get(k)?,
                &self.noise,
                s,
            )),
        }
    }
}

impl PoseSource for ScanMatching {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::ScanMatched
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Scan `k` (its own pose ignored) matched against `map`, the map of
    /// scans `0..k` at the poses found for them. The first scan is put
    /// where the odometry starts: nothing to match against yet.
    fn locate(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Pose> {
        let Some(prediction) = self.prediction(k) else {
            return Ok(scan.pose());
        };
        let report = if k == 0 {
            MatchReport::unmatched(prediction.pose)
        } else {
            map.match_scan_with(&mut self.matcher, scan, laser_max, &prediction)?
        };
        self.work += match_work(&report);
        self.last = Some((k, report));
        self.poses[k] = report.pose;
        Ok(report.pose)
    }

    /// The log's own poses, and room for drift around them: the matched
    /// path stays near them, where the odometry it starts from wanders
    /// off.
    fn plan_poses<'a>(&'a self, log: &'a ScanLog) -> (&'a [Pose], f64) {
        (log.poses(), MATCH_DRIFT_MARGIN)
    }

    fn work(&self) -> u64 {
        self.work
    }

    /// Every scan but the first matched at the most [`match_work_bound`]
    /// allows, with as many points as it has beams (at most `maxPoints`).
    fn work_bound(&self, log: &ScanLog) -> u64 {
        path_work_bound(self.matcher.settings(), self.resolution, log)
    }

    fn reset(&mut self) {
        self.last = None;
        self.work = 0;
    }

    fn matching(&self) -> Option<&ScanMatching> {
        Some(self)
    }
}
