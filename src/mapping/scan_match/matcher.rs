//! One scan matched against a map: the correlative search on the coarse
//! level, then Gauss–Newton on every level down to the map itself for
//! each of the search's best headings, the best fit against the
//! prediction's prior winning ([`Prediction`]).
//!
//! # Work per scan
//!
//! With `n` points (at most `maxPoints`), `c` candidates
//! ([`MatchSettings::candidates_at`]: headings times positions squared),
//! `h` hypotheses, `L` levels below the coarse one and `I` iterations per
//! level:
//!
//! * the coarse copy reads every map cell of the box the rotated scan can
//!   reach: at most `(2 (maxRange + linearWindow) / resolution + 4
//!   coarseFactor)^2` cells (about 1.5 million at 30 m and 5 cm; around a
//!   hundred thousand indoors, where returns are short);
//! * the search costs `c n` bilinear reads at most (61 x 25 x 180 =
//!   274,500 with the defaults on a 180-beam scan; thinned points make it
//!   a third of that indoors);
//! * the refinement `3 h I (L + 1) n` bilinear reads at most.
//!
//! Nothing else depends on the log's length or the map's size.

use super::match_map::MatchMap;
use super::points::ScanPoints;
use super::refine::{gauss_newton, AnchorWeights, GridField, OccupancyField};
use super::search::{correlative_search, reach_box, PlacedPoint, SearchOutcome};
use super::window::Pyramid;
use super::{MatchSettings, Prediction};
use crate::error::Result;
use crate::geometry::Pose;
use crate::sensors::Scan;

/// Points closer together than this many cells of a level are thinned
/// for that level ([`ScanPoints::thinned`]): about two points per cell
/// along a wall, and one search costs a third of what every point would
/// on an office log (most returns there are a few metres away, 2 to 5 cm
/// apart).
const THINNING: f64 = 0.5;

/// What matching one scan found.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MatchReport {
    /// The pose the scan is put at: the fit combined with the prediction
    /// ([`Prediction::update`]) when the match is trusted, the prediction
    /// otherwise.
    pub pose: Pose,
    pub predicted: Pose,
    /// The pose that fits the map best (the prediction when nothing was
    /// matched).
    pub fit: Pose,
    /// True when the match was trusted (enough of the scan on measured
    /// cells at the pose found, a fit good enough, and more evidence than
    /// the prediction's once its prior is counted).
    pub accepted: bool,
    /// Mean match value ([`super::window::match_value`]) of the points on
    /// the map at `pose`.
    pub score: f64,
    /// The same at the predicted pose.
    pub predicted_score: f64,
    /// Fraction of the points on measured cells at the pose found (0 when
    /// the scan had no points to match).
    pub overlap: f64,
    /// Points matched.
    pub points: usize,
    /// Candidate poses the search scored.
    pub candidates: usize,
    /// Gauss–Newton steps kept, over all levels.
    pub iterations: usize,
    /// Map cells read into the coarse levels.
    pub cells_read: usize,
}

impl MatchReport {
    /// A scan put at `predicted` without matching (nothing to match
    /// against).
    pub fn unmatched(predicted: Pose) -> Self {
        Self {
            pose: predicted,
            predicted,
            fit: predicted,
            accepted: false,
            score: 0.0,
            predicted_score: 0.0,
            overlap: 0.0,
            points: 0,
            candidates: 0,
            iterations: 0,
            cells_read: 0,
        }
    }
}

/// A scan matcher: its settings and the scratch it reuses from scan to
/// scan (so that matching allocates only when a scan needs more room
/// than any before).
#[derive(Debug, Clone)]
pub struct ScanMatcher {
    settings: MatchSettings,
    /// The resolution the search's size was last checked at
    /// ([`MatchSettings::check_resolution`]): each map's resolution is
    /// checked once, not on every scan.
    checked_resolution: Option<f64>,
    points: ScanPoints,
    pyramid: Pyramid,
    placed: Vec<PlacedPoint>,
    found: SearchOutcome,
    /// The points thinned for the level at hand.
    thinned: Vec<[f64; 2]>,
}

impl ScanMatcher {
    /// A matcher with `settings`, checked field by field.
    pub fn new(settings: MatchSettings) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            settings,
            checked_resolution: None,
            points: ScanPoints::default(),
            pyramid: Pyramid::default(),
            placed: Vec::new(),
            found: SearchOutcome::default(),
            thinned: Vec::new(),
        })
    }

    /// A matcher with `settings`, checked field by field and for maps of
    /// `resolution` metres per cell ([`MatchSettings::validate_for`]).
    pub fn for_resolution(settings: MatchSettings, resolution: f64) -> Result<Self> {
        let mut matcher = Self::new(settings)?;
        matcher.check_resolution(resolution)?;
        Ok(matcher)
    }

    /// Checks the search's size on a map of `resolution`, once per
    /// resolution.
    fn check_resolution(&mut self, resolution: f64) -> Result<()> {
        if self.checked_resolution != Some(resolution) {
            self.settings.check_resolution(resolution)?;
            self.checked_resolution = Some(resolution);
        }
        Ok(())
    }

    pub fn settings(&self) -> &MatchSettings {
        &self.settings
    }

    /// Matches `scan` (its own pose ignored) against `grid`, around
    /// `prediction`; `laser_max` is the laser's own maximum range (infinite
    /// when the log does not say). An error, and no work, when the search
    /// on this grid's cells would exceed its bound
    /// ([`MatchSettings::validate_for`]).
    pub fn match_scan(
        &mut self,
        grid: &dyn MatchMap,
        scan: &Scan,
        laser_max: f64,
        prediction: &Prediction,
    ) -> Result<MatchReport> {
        self.check_resolution(grid.geometry().resolution())?;
        self.points.fill(scan, laser_max, &self.settings);
        Ok(self.match_points(grid, prediction))
    }

    /// The points of the last scan matched.
    pub fn points(&self) -> &ScanPoints {
        &self.points
    }

    fn match_points(&mut self, grid: &dyn MatchMap, prediction: &Prediction) -> MatchReport {
        // The window as wide as the prediction's spread asks.
        let s = self.settings.window_for(prediction);
        let predicted = &prediction.pose;
        let fine = GridField::new(grid);
        let points = self.points.points();
        let mut report = MatchReport {
            pose: *predicted,
            predicted: *predicted,
            fit: *predicted,
            accepted: false,
            score: mean_occupancy(&fine, points, predicted),
            predicted_score: 0.0,
            overlap: 0.0,
            points: points.len(),
            candidates: 0,
            iterations: 0,
            cells_read: 0,
        };
        report.predicted_score = report.score;
        if points.is_empty() {
            return report;
        }
        // The coarse copy: every cell a candidate's point can fall on,
        // plus the search's positions and one coarse cell for the
        // interpolation.
        let g = grid.geometry();
        let res = g.resolution();
        let coarse = s.coarse_factor;
        let margin = (s.position_steps(res * coarse as f64) + 2) as f64 * res * coarse as f64;
        let [x0, y0, x1, y1] = reach_box(self.points.points(), predicted, &s);
        let [ox, oy] = g.origin();
        let (ex, ey) = (ox + g.width() as f64 * res, oy + g.height() as f64 * res);
        // A scan that cannot reach the map has nothing to match (and a
        // pose thousands of kilometres away no cell indices).
        if !(x1 + margin > ox && x0 - margin < ex && y1 + margin > oy && y0 - margin < ey) {
            return report;
        }
        let cell = |v: f64, o: f64| ((v - o) / res).floor() as i64;
        let bounds = [
            cell(x0 - margin, ox),
            cell(y0 - margin, oy),
            cell(x1 + margin, ox) + 1,
            cell(y1 + margin, oy) + 1,
        ];
        self.pyramid.build(grid, bounds, coarse);
        report.cells_read = self.pyramid.cells_read();
        let Some(top) = self.pyramid.level(coarse) else {
            return report;
        };
        self.points
            .thinned(THINNING * top.cell_size(), &mut self.thinned);
        correlative_search(
            top,
            &self.thinned,
            prediction,
            &s,
            s.hypotheses,
            &mut self.placed,
            &mut self.found,
        );
        report.candidates = self.found.candidates;
        // Each hypothesis refined on the coarse levels; the best on the
        // finest of them (its points' evidence against its prior) is
        // refined on the map itself, and kept if it beats the prediction
        // there.
        let mut best: Option<(f64, Pose)> = None;
        for i in 0..self.found.best.len() {
            let start = self.found.best[i].pose;
            let (pose, evidence, iterations) = self.refine_coarse(start);
            report.iterations += iterations;
            let weighted = evidence + prediction.log_prior(&pose);
            if best.is_none_or(|b| weighted > b.0) {
                best = Some((weighted, pose));
            }
        }
        let Some((_, coarse_pose)) = best else {
            return report;
        };
        // The search's best refined on the map itself, and the prediction
        // refined there too: where the map is young or says little (down a
        // corridor), the search's coarse cells can put the best start in
        // another basin than the prediction's, and the better of the two
        // fits wins, judged in the refinement's own terms: each point's
        // evidence `1 - (1 - M)^2`, what Gauss–Newton raises (the mean
        // match value alone can fall as a fit pulls the worst points onto
        // the walls).
        let n = self.points.len() as f64;
        let evidence = |pose: &Pose| n * (1.0 - mean_residual(&fine, self.points.points(), pose));
        let mut refined = None;
        for start in [coarse_pose, *predicted] {
            let r = gauss_newton(
                &fine,
                self.points.points(),
                start,
                &start,
                self.anchor_weights(),
                s.max_iterations,
            );
            report.iterations += r.iterations;
            let weighted = evidence(&r.pose) + prediction.log_prior(&r.pose);
            if refined.is_none_or(|(w, _)| weighted > w) {
                refined = Some((weighted, r));
            }
        }
        let Some((weighted, refined)) = refined else {
            return report;
        };
        let score = mean_occupancy(&fine, self.points.points(), &refined.pose);
        let pose = refined.pose;
        // Judged where the scan ends up: a prediction that is off by many
        // degrees puts most points on cells the map has not seen, which
        // is no reason not to search.
        report.overlap = overlap(grid, self.points.points(), &pose);
        if report.overlap >= s.min_overlap
            && score >= s.min_score
            && weighted >= evidence(predicted)
        {
            report.fit = pose;
            report.pose = prediction.update(&pose, refined.curvature, &s);
            report.score = score;
            report.accepted = true;
        }
        report
    }

    fn anchor_weights(&self) -> AnchorWeights {
        AnchorWeights {
            translation: self.settings.refine_translation_weight,
            rotation: self.settings.refine_rotation_weight,
        }
    }

    /// Gauss–Newton from `start` on every coarse level, the coarsest
    /// first, held near `start`: the pose found, its points' evidence on
    /// the finest coarse level (their match values summed, nats), and the
    /// steps taken.
    fn refine_coarse(&mut self, start: Pose) -> (Pose, f64, usize) {
        let weights = self.anchor_weights();
        let s = &self.settings;
        let (mut pose, mut evidence, mut iterations) = (start, 0.0, 0);
        let mut factor = s.coarse_factor;
        while factor > 1 {
            if let Some(level) = self.pyramid.level(factor) {
                self.points
                    .thinned(THINNING * level.cell_size(), &mut self.thinned);
                let r = gauss_newton(
                    level,
                    &self.thinned,
                    pose,
                    &start,
                    weights,
                    s.max_iterations,
                );
                pose = r.pose;
                iterations += r.iterations;
                evidence = self.thinned.len() as f64 * mean_occupancy(level, &self.thinned, &pose);
            }
            factor /= 2;
        }
        (pose, evidence, iterations)
    }
}

/// Mean match value of `points` on `field` with the sensor at `pose`.
fn mean_occupancy(field: &dyn OccupancyField, points: &[[f64; 2]], pose: &Pose) -> f64 {
    let trig = pose.theta.sin_cos();
    let sum: f64 = points
        .iter()
        .map(|&p| {
            let [x, y] = ScanPoints::to_world(pose, trig, p);
            field.sample(x, y).value
        })
        .sum();
    sum / points.len().max(1) as f64
}

/// Mean squared residual `(1 - M)^2` of `points` on `field` with the
/// sensor at `pose` (Gauss–Newton's cost without its anchor).
fn mean_residual(field: &dyn OccupancyField, points: &[[f64; 2]], pose: &Pose) -> f64 {
    let trig = pose.theta.sin_cos();
    let sum: f64 = points
        .iter()
        .map(|&p| {
            let [x, y] = ScanPoints::to_world(pose, trig, p);
            let r = 1.0 - field.sample(x, y).value;
            r * r
        })
        .sum();
    sum / points.len().max(1) as f64
}

/// Fraction of `points` that land on measured cells of `grid` with the
/// sensor at `pose`.
fn overlap(grid: &dyn MatchMap, points: &[[f64; 2]], pose: &Pose) -> f64 {
    let g = grid.geometry();
    let trig = pose.theta.sin_cos();
    let known = points
        .iter()
        .filter(|&&p| {
            let [x, y] = ScanPoints::to_world(pose, trig, p);
            g.world_to_cell(x, y)
                .is_some_and(|(ix, iy)| grid.is_measured(ix, iy))
        })
        .count();
    known as f64 / points.len().max(1) as f64
}

/// [`ScanMatcher::match_scan`] through the map a pose source is given.
impl dyn MatchMap + '_ {
    pub fn match_scan_with(
        &self,
        matcher: &mut ScanMatcher,
        scan: &Scan,
        laser_max: f64,
        prediction: &Prediction,
    ) -> Result<MatchReport> {
        matcher.match_scan(self, scan, laser_max, prediction)
    }
}
