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
use super::refine::{gauss_newton, AnchorWeights, GridField, OccupancyField, Refined};
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
    /// The match under way, when one runs a stage at a time.
    under_way: Option<UnderWay>,
}

/// A match run a stage at a time ([`ScanMatcher::match_step`]).
#[derive(Debug, Clone)]
struct UnderWay {
    prediction: Prediction,
    /// The settings with the window the prediction asks for.
    window: MatchSettings,
    /// What it has found and done so far.
    report: MatchReport,
    stage: Stage,
}

/// The stage a match is at.
#[derive(Debug, Clone, Copy)]
enum Stage {
    Pool,
    Search,
    /// The search's best from `next` on to refine on the coarse levels,
    /// with the best so far.
    RefineCoarse {
        next: usize,
        best: Option<(f64, Pose)>,
    },
    /// Refinements on the map itself from the coarse best (`next` 0) and
    /// from the prediction (1), with the better so far.
    RefineFine {
        coarse_pose: Pose,
        next: usize,
        refined: Option<(f64, Refined)>,
    },
    Done,
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
            under_way: None,
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
        self.begin_points(grid, prediction);
        loop {
            if let Some(report) = self.match_step(grid) {
                return report;
            }
        }
    }

    /// Starts matching `scan` as [`Self::match_scan`] does, to be carried
    /// on a stage at a time by [`Self::match_step`] against the same,
    /// unchanged `grid`: the coarse copy, the search, each hypothesis's
    /// refinement on the coarse levels, and each refinement on the map
    /// itself. On the Freiburg campus a match reads a million cells and
    /// scores a million points, 14 ms natively at most: a stage is a
    /// quarter of that, so that a page's call can stop between them.
    /// Whatever match was under way is dropped.
    pub fn begin_match(
        &mut self,
        grid: &dyn MatchMap,
        scan: &Scan,
        laser_max: f64,
        prediction: &Prediction,
    ) -> Result<()> {
        self.under_way = None;
        self.check_resolution(grid.geometry().resolution())?;
        self.points.fill(scan, laser_max, &self.settings);
        self.begin_points(grid, prediction);
        Ok(())
    }

    /// What the match under way has done so far (its candidates scored,
    /// cells read and steps taken, the work a caller counts as it goes),
    /// `None` when none is.
    pub fn under_way(&self) -> Option<&MatchReport> {
        self.under_way.as_ref().map(|u| &u.report)
    }

    fn begin_points(&mut self, grid: &dyn MatchMap, prediction: &Prediction) {
        // The window as wide as the prediction's spread asks.
        let window = self.settings.window_for(prediction);
        let predicted = &prediction.pose;
        let points = self.points.points();
        let score = mean_occupancy(&GridField::new(grid), points, predicted);
        let report = MatchReport {
            pose: *predicted,
            predicted: *predicted,
            fit: *predicted,
            accepted: false,
            score,
            predicted_score: score,
            overlap: 0.0,
            points: points.len(),
            candidates: 0,
            iterations: 0,
            cells_read: 0,
        };
        let stage = if points.is_empty() {
            Stage::Done
        } else {
            Stage::Pool
        };
        self.under_way = Some(UnderWay {
            prediction: *prediction,
            window,
            report,
            stage,
        });
    }

    /// The next stage of the match under way against `grid` (the grid it
    /// began on): its report once it has ended, `None` while stages are
    /// left (and when no match is under way).
    pub fn match_step(&mut self, grid: &dyn MatchMap) -> Option<MatchReport> {
        let mut u = self.under_way.take()?;
        u.stage = match u.stage {
            Stage::Pool => self.pool(grid, &mut u),
            Stage::Search => self.search(&mut u),
            Stage::RefineCoarse { next, best } => self.refine_hypothesis(&mut u, next, best),
            Stage::RefineFine {
                coarse_pose,
                next,
                refined,
            } => self.refine_fine(grid, &mut u, coarse_pose, next, refined),
            Stage::Done => Stage::Done,
        };
        if matches!(u.stage, Stage::Done) {
            return Some(u.report);
        }
        self.under_way = Some(u);
        None
    }

    /// The coarse copy: every cell a candidate's point can fall on, plus
    /// the search's positions and one coarse cell for the interpolation.
    fn pool(&mut self, grid: &dyn MatchMap, u: &mut UnderWay) -> Stage {
        let (s, predicted) = (&u.window, &u.prediction.pose);
        let g = grid.geometry();
        let res = g.resolution();
        let coarse = s.coarse_factor;
        let margin = (s.position_steps(res * coarse as f64) + 2) as f64 * res * coarse as f64;
        let [x0, y0, x1, y1] = reach_box(self.points.points(), predicted, s);
        let [ox, oy] = g.origin();
        let (ex, ey) = (ox + g.width() as f64 * res, oy + g.height() as f64 * res);
        // A scan that cannot reach the map has nothing to match (and a
        // pose thousands of kilometres away no cell indices).
        if !(x1 + margin > ox && x0 - margin < ex && y1 + margin > oy && y0 - margin < ey) {
            return Stage::Done;
        }
        let cell = |v: f64, o: f64| ((v - o) / res).floor() as i64;
        let bounds = [
            cell(x0 - margin, ox),
            cell(y0 - margin, oy),
            cell(x1 + margin, ox) + 1,
            cell(y1 + margin, oy) + 1,
        ];
        self.pyramid.build(grid, bounds, coarse);
        u.report.cells_read = self.pyramid.cells_read();
        if self.pyramid.level(coarse).is_some() {
            Stage::Search
        } else {
            Stage::Done
        }
    }

    /// The correlative search on the coarsest level.
    fn search(&mut self, u: &mut UnderWay) -> Stage {
        let s = &u.window;
        let Some(top) = self.pyramid.level(s.coarse_factor) else {
            return Stage::Done;
        };
        self.points
            .thinned(THINNING * top.cell_size(), &mut self.thinned);
        correlative_search(
            top,
            &self.thinned,
            &u.prediction,
            s,
            s.hypotheses,
            &mut self.placed,
            &mut self.found,
        );
        u.report.candidates = self.found.candidates;
        Stage::RefineCoarse {
            next: 0,
            best: None,
        }
    }

    /// Hypothesis `next` of the search refined on the coarse levels; the
    /// best on the finest of them (its points' evidence against its
    /// prior) goes on to the map itself.
    fn refine_hypothesis(
        &mut self,
        u: &mut UnderWay,
        next: usize,
        mut best: Option<(f64, Pose)>,
    ) -> Stage {
        if let Some(candidate) = self.found.best.get(next) {
            let (pose, evidence, iterations) = self.refine_coarse(candidate.pose);
            u.report.iterations += iterations;
            let weighted = evidence + u.prediction.log_prior(&pose);
            if best.is_none_or(|b| weighted > b.0) {
                best = Some((weighted, pose));
            }
            if next + 1 < self.found.best.len() {
                return Stage::RefineCoarse {
                    next: next + 1,
                    best,
                };
            }
        }
        match best {
            Some((_, coarse_pose)) => Stage::RefineFine {
                coarse_pose,
                next: 0,
                refined: None,
            },
            None => Stage::Done,
        }
    }

    /// The search's best refined on the map itself (`next` 0), then the
    /// prediction refined there too (1): where the map is young or says
    /// little (down a corridor), the search's coarse cells can put the
    /// best start in another basin than the prediction's, and the better
    /// of the two fits wins, judged in the refinement's own terms: each
    /// point's evidence `1 - (1 - M)^2`, what Gauss–Newton raises (the
    /// mean match value alone can fall as a fit pulls the worst points
    /// onto the walls). The better kept if it beats the prediction.
    fn refine_fine(
        &mut self,
        grid: &dyn MatchMap,
        u: &mut UnderWay,
        coarse_pose: Pose,
        next: usize,
        mut refined: Option<(f64, Refined)>,
    ) -> Stage {
        let fine = GridField::new(grid);
        let points = self.points.points();
        let n = points.len() as f64;
        let evidence = |pose: &Pose| n * (1.0 - mean_residual(&fine, points, pose));
        let predicted = u.prediction.pose;
        let start = if next == 0 { coarse_pose } else { predicted };
        let r = gauss_newton(
            &fine,
            points,
            start,
            &start,
            self.anchor_weights(),
            u.window.max_iterations,
        );
        u.report.iterations += r.iterations;
        let weighted = evidence(&r.pose) + u.prediction.log_prior(&r.pose);
        if refined.is_none_or(|(w, _)| weighted > w) {
            refined = Some((weighted, r));
        }
        if next == 0 {
            return Stage::RefineFine {
                coarse_pose,
                next: 1,
                refined,
            };
        }
        let Some((weighted, refined)) = refined else {
            return Stage::Done;
        };
        let s = &u.window;
        let report = &mut u.report;
        let score = mean_occupancy(&fine, points, &refined.pose);
        let pose = refined.pose;
        // Judged where the scan ends up: a prediction that is off by many
        // degrees puts most points on cells the map has not seen, which
        // is no reason not to search.
        report.overlap = overlap(grid, points, &pose);
        if report.overlap >= s.min_overlap
            && score >= s.min_score
            && weighted >= evidence(&predicted)
        {
            report.fit = pose;
            report.pose = u.prediction.update(&pose, refined.curvature, s);
            report.score = score;
            report.accepted = true;
        }
        Stage::Done
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
