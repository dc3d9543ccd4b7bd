//! The scan-matched pose source of a real-log pane ([`PoseMatching`]):
//! each scan's pose is predicted from the pose found for the scan before
//! and the odometry's increment between them, corrected by matching the
//! scan against the pane's own map of the scans before it
//! ([`crate::mapping::scan_match`]), and only then integrated there. The
//! pane's map is the matched path's map: no second copy is built.
//!
//! Also here, for every pose source: the poses a pane has mapped with, as
//! the text of a `poses.tsv` file, and what the page draws of the last
//! match (the scan's points where the match put them).

use super::pane::LogPane;
use super::settings::{CheckedSettings, LogMapSettings};
use crate::error::Result;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{CellModel, Grid, Store};
use crate::io::carmen::LaserScans;
use crate::mapping::reach::{covering_grid, scan_extent};
use crate::mapping::scan_match::{MatchReport, MatchSettings, Prediction, ScanMatcher};
use crate::render::overlay::RobotMark;
use crate::sensors::odometry::OdometryParams;
use crate::sensors::Scan;

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
/// within 8 to 16 ns per unit of its estimate for eight scans in ten.
pub fn match_work(report: &MatchReport) -> u64 {
    let points = report.points as u64;
    let search = report.candidates as u64 * points / 8;
    let refine = report.iterations as u64 * points * 4;
    let pooled = report.cells_read as u64 / 5;
    search + refine + pooled
}

/// The matcher's settings for a map of `settings`: the defaults, with
/// points matched out to the range cap at most (a return past it marks
/// nothing on the map, so it has nothing to fit).
pub fn match_settings(settings: &LogMapSettings) -> MatchSettings {
    let defaults = MatchSettings::default();
    MatchSettings {
        max_range: defaults.max_range.min(settings.range_cap),
        ..defaults
    }
}

/// What the last match of a pane did, as the page draws it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MatchView {
    /// The scan matched.
    pub scan: usize,
    pub accepted: bool,
    pub score: f64,
    pub predicted_score: f64,
    pub overlap: f64,
    /// The robot where the odometry predicted it, and where the scan was
    /// put, in image units.
    pub predicted: RobotMark,
    pub pose: RobotMark,
    /// How far the match moved the prediction, metres and degrees.
    pub correction_m: f64,
    pub correction_deg: f64,
    /// The matched points at the pose found, image units, `[u0, v0, ...]`.
    pub points: Vec<f32>,
}

/// Scan matching inside a pane: the odometry it corrects, the matcher and
/// its last report.
#[derive(Debug, Clone)]
pub(super) struct PoseMatching {
    /// One odometry pose per scan: only their increments are used, and
    /// the first pose, where the path starts.
    odometry: Vec<Pose>,
    /// The odometry's noise (Table 5.6): how far each prediction may be off.
    noise: OdometryParams,
    matcher: ScanMatcher,
    last: Option<(usize, MatchReport)>,
    /// The matching work since the last reset ([`match_work`]).
    work: u64,
}

impl PoseMatching {
    /// Matching from `odometry` (one pose per scan) with `noise`, under
    /// the map's `settings`.
    pub(super) fn new(
        odometry: Vec<Pose>,
        noise: OdometryParams,
        settings: &LogMapSettings,
    ) -> Result<Self> {
        let matcher = ScanMatcher::new(match_settings(settings))?;
        matcher.settings().validate_for(settings.resolution)?;
        Ok(Self {
            odometry,
            noise,
            matcher,
            last: None,
            work: 0,
        })
    }

    /// The odometry the path corrects: the log's own when it is raw, else
    /// seeded dead reckoning of its corrected poses.
    pub(super) fn odometry_of(scans: &LaserScans, seed: u64, noise: &OdometryParams) -> Vec<Pose> {
        match scans.raw_odometry() {
            Some(raw) => raw.to_vec(),
            None => noise.dead_reckon_path(scans.poses(), seed),
        }
    }

    pub(super) fn odometry(&self) -> &[Pose] {
        &self.odometry
    }

    /// The pose of scan `k`, found by matching `scan` (its own pose
    /// ignored) against `grid`, the map of scans `0..k` at `matched[..k]`.
    /// The first scan is put where the odometry starts.
    pub(super) fn pose_of<M: CellModel, S: Store<M::Cell>>(
        &mut self,
        k: usize,
        matched: &[Pose],
        grid: &Grid<M, S>,
        scan: &Scan,
        laser_max: f64,
    ) -> Result<Pose> {
        let s = *self.matcher.settings();
        let report = match (k, self.odometry.get(k)) {
            (_, None) => return Ok(scan.pose()),
            (0, Some(&first)) => MatchReport::unmatched(Prediction::at(first, &s).pose),
            (_, Some(to)) => {
                let prediction = Prediction::from_odometry(
                    &matched[k - 1],
                    &self.odometry[k - 1],
                    to,
                    &self.noise,
                    &s,
                );
                self.matcher
                    .match_scan(grid, scan, laser_max, &prediction)?
            }
        };
        self.work += match_work(&report);
        self.last = Some((k, report));
        Ok(report.pose)
    }

    /// The matching work since the last reset.
    pub(super) fn work(&self) -> u64 {
        self.work
    }

    /// Back to before the first scan.
    pub(super) fn reset(&mut self) {
        self.last = None;
        self.work = 0;
    }

    /// The last match, drawn on `geometry`'s image.
    fn view(&self, geometry: &GridGeometry) -> Option<MatchView> {
        let (scan, r) = self.last.as_ref()?;
        let trig = r.pose.theta.sin_cos();
        let points = self
            .matcher
            .points()
            .points()
            .iter()
            .flat_map(|&p| {
                let [x, y] = crate::mapping::scan_match::ScanPoints::to_world(&r.pose, trig, p);
                geometry.world_to_image(x, y).map(|c| c as f32)
            })
            .collect();
        Some(MatchView {
            scan: *scan,
            accepted: r.accepted,
            score: r.score,
            predicted_score: r.predicted_score,
            overlap: r.overlap,
            predicted: RobotMark::at(geometry, &r.predicted),
            pose: RobotMark::at(geometry, &r.pose),
            correction_m: (r.pose.x - r.predicted.x).hypot(r.pose.y - r.predicted.y),
            correction_deg: crate::geometry::wrap_angle(r.pose.theta - r.predicted.theta)
                .to_degrees(),
            points,
        })
    }
}

/// The grid a scan-matched pane builds in: the extent of the scans at the
/// log's own poses (for a raw log, its odometry's) and
/// [`MATCH_DRIFT_MARGIN`] more, covered on whole cells with the settings'
/// margin.
pub(super) fn matched_grid(
    scans: &LaserScans,
    c: &CheckedSettings,
) -> Option<Result<GridGeometry>> {
    let s = c.settings();
    let placed = (0..scans.len()).filter_map(|k| {
        let laser_max = scans.max_range(k).unwrap_or(f64::INFINITY);
        Some((
            scans.scan(k)?,
            c.model_for_laser(laser_max).unwrap_or(*c.model()),
        ))
    });
    let a = scan_extent(placed, s.no_return_reach)?;
    let m = MATCH_DRIFT_MARGIN;
    let extent = [a[0] - m, a[1] - m, a[2] + m, a[3] + m];
    Some(covering_grid(extent, s.resolution, s.margin))
}

impl LogPane {
    /// The last scan matched and where it went (`None` for a pane that
    /// does not match, or before its first scan).
    pub fn match_view(&self) -> Option<MatchView> {
        self.matching.as_ref()?.view(self.grid().geometry())
    }

    /// The odometry a scan-matched pane corrects (`None` for the others).
    pub fn matched_odometry(&self) -> Option<&[Pose]> {
        Some(self.matching.as_ref()?.odometry())
    }

    /// The poses the map so far was built with, one line per scan
    /// integrated: `scan x y theta` (metres, radians, each number as the
    /// shortest text that reads back as the same `f64`).
    pub fn poses_tsv(&self) -> String {
        let done = self.progress().scans_done;
        let mut out = String::with_capacity(done * 64);
        for (k, p) in self.poses().iter().take(done).enumerate() {
            out.push_str(&format!("{k} {} {} {}\n", p.x, p.y, p.theta));
        }
        out
    }
}
