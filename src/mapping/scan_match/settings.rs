//! What a scan matcher is told: its search window, its coarse level, its
//! Gauss–Newton budget and the weight of the predicted pose. Each default
//! is chosen for the corpus of real logs at 5 cm cells, mapped from dead
//! reckoning with the wheels of [`crate::sensors::odometry::OdometryParams::WHEELS`]
//! (the logs keep one scan per metre or per half radian turned, so a
//! scan's predicted pose is off by a few centimetres and a few degrees,
//! now and then by 20° or more after a sideways step).

use crate::error::{self, invalid, Result};
use crate::mapping::traversal::MAX_REACH_CELLS;

/// The most points a scan is matched with: a scan with more returns is
/// thinned evenly (a bound on the work of one match).
pub const MAX_POINTS: usize = 4096;

/// The coarsest level a search may use, in cells of the map.
pub const MAX_COARSE_FACTOR: usize = 16;

/// The most candidate poses a search may score: its bound on one match's
/// work (times the points).
pub const MAX_CANDIDATES: usize = 50_000;

/// The most hypotheses a search hands on.
pub const MAX_HYPOTHESES: usize = 16;

/// The most Gauss–Newton iterations per level.
pub const MAX_ITERATIONS: usize = 100;

/// A scan matcher's parameters (the names as a page spells them are the
/// serde names, and errors use them).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase", deny_unknown_fields)]
pub struct MatchSettings {
    /// The least half-width of the search window in x and in y around the
    /// predicted position, metres. 0.3 m: seeded dead reckoning between
    /// two scans of a log is off by 2 cm typically and at most 17 cm on
    /// the corpus.
    pub linear_window: f64,
    /// The least half-width of the search window in heading, radians.
    /// 30°: the heading of one step is off by about 1° typically, 10° in
    /// one step out of twenty and up to 29° (a sideways or backward step,
    /// whose direction of travel the wheel model turns by its rotation
    /// noise).
    pub angular_window: f64,
    /// How many spreads of the prediction ([`super::Prediction`]) the
    /// window reaches either side, where that is wider than the least
    /// window: 4. An in-place turn is predicted to 13° or so (Table 5.6's
    /// rotation noise on a turn whose direction of travel is unknown), and
    /// the truth may lie 45° from it; a drive ahead stays within the least
    /// window.
    pub window_spreads: f64,
    /// The most half-width of the search window in x and in y, metres:
    /// 1 m, a bound on one match's work.
    pub max_linear_window: f64,
    /// The most half-width of the search window in heading, radians: 90°.
    pub max_angular_window: f64,
    /// Heading step of the search, radians. 1°: on the coarse level
    /// (20 cm cells at 5 cm), a point 11 m away moves one coarse cell per
    /// step; Gauss–Newton then takes the pose the rest of the way.
    pub angular_step: f64,
    /// How many of the search's best headings (at least three steps
    /// apart) are refined down to the map, the best fit there winning
    /// (1 to 16). 3: in a cluttered place (foliage outdoors) the coarse
    /// level can rank a wrong heading a little above the right one, and
    /// three refinements cost less than a tenth of the search.
    pub hypotheses: usize,
    /// Cells of the map per cell of the coarse level the search scores on
    /// (2, 4, 8 or 16). 4: a 20 cm coarse cell at 5 cm,
    /// which is the search's position step; Gauss–Newton then runs on
    /// every level from it down to the map (factors 4, 2, 1), as Hector
    /// SLAM's three levels.
    pub coarse_factor: usize,
    /// Most Gauss–Newton iterations per level. 10: from the search's
    /// coarse pose a level converges in three to five.
    pub max_iterations: usize,
    /// Returns closer than this are not matched, metres: 0.1 m keeps the
    /// robot's own body out of the match.
    pub min_range: f64,
    /// Returns farther than this are not matched, metres. 30 m, the
    /// real-log range cap: far returns pin the heading best, and a range
    /// past the cap would match points the map never marks.
    pub max_range: f64,
    /// The most points matched per scan (at most 4096); a scan with more
    /// returns is thinned evenly. 720: every beam of the corpus's
    /// scanners (at most 361 beams).
    pub max_points: usize,
    /// The least spread of a predicted position, metres (one standard
    /// deviation; [`super::Prediction`]). 0.05 m: the pose a prediction
    /// starts from was itself matched, to a few centimetres.
    pub min_position_spread: f64,
    /// The least spread of a predicted heading, radians. 1°: a matched
    /// heading is good to a few tenths of a degree, and the odometry of a
    /// drive straight ahead adds less.
    pub min_heading_spread: f64,
    /// The spread of a fit's position against the truth, metres: how much
    /// the pose kept follows the fit rather than the prediction
    /// ([`super::Prediction::update`]). 0.05 m: on the office logs one
    /// scan's best fit to the map of all the others lies 2 to 4 cm from
    /// its corrected pose, about as far as a step of dead reckoning
    /// strays, and weighing the two alike brings the error between
    /// consecutive poses to 2 cm (3 to 5 cm following the fit alone).
    pub fit_position_spread: f64,
    /// The spread of a fit's heading, radians. 0.3°: a fit's heading is
    /// good to a few tenths of a degree, ten times better than the
    /// odometry's after a turn: the heading kept is the fit's.
    pub fit_heading_spread: f64,
    /// Weight of a refinement's start in Gauss–Newton, per metre: the
    /// refinement minimises `mean (1 - M(p_i))^2 + (wt |Δt|)^2 +
    /// (wr Δθ)^2` (Cartographer's Ceres matcher's `translation_weight`).
    /// 1: along a featureless corridor, where the map says little about
    /// one direction (a young map's walls, seen at a grazing angle, are
    /// dotted, and their faint slopes would pull the fit along), the pose
    /// stays where it started instead of sliding; anywhere else the map's
    /// slopes decide (the fit's curvature is about a hundred per square
    /// metre, the weight's 1), so the pose found does not lean towards
    /// the search's 20 cm steps.
    pub refine_translation_weight: f64,
    /// The same per radian of heading (Cartographer's `rotation_weight`).
    /// 1: the heading of a fit is pinned by every wall in view, and
    /// holding it harder only keeps the search's one-degree steps.
    pub refine_rotation_weight: f64,
    /// The fraction of points that must land on measured (not unknown)
    /// cells of the map for a match to be trusted; otherwise the scan is
    /// put at its predicted pose. 0.3: the first scans, and a scan that
    /// looks mostly into space the map has not seen yet, have too little
    /// map to match against.
    pub min_overlap: f64,
    /// The least mean match value (how sure the map is, on average, that a
    /// wall lies under each point) a match must reach to be trusted;
    /// below it the scan is put at its predicted pose. 0.05: a fit that
    /// weak lines up a handful of points with anything at all (a hedge
    /// outdoors), and a heading that wrong costs more than the
    /// odometry's error; trusted matches on the office logs score 0.15
    /// and more.
    pub min_score: f64,
}

impl Default for MatchSettings {
    fn default() -> Self {
        Self {
            linear_window: 0.3,
            angular_window: 30f64.to_radians(),
            window_spreads: 4.0,
            max_linear_window: 1.0,
            max_angular_window: 90f64.to_radians(),
            angular_step: 1f64.to_radians(),
            hypotheses: 3,
            coarse_factor: 4,
            max_iterations: 10,
            min_range: 0.1,
            max_range: 30.0,
            max_points: 720,
            min_position_spread: 0.05,
            min_heading_spread: 1f64.to_radians(),
            fit_position_spread: 0.05,
            fit_heading_spread: 0.3f64.to_radians(),
            refine_translation_weight: 1.0,
            refine_rotation_weight: 1.0,
            min_overlap: 0.3,
            min_score: 0.05,
        }
    }
}

impl MatchSettings {
    /// The field names as a page spells them (the serde names).
    pub const FIELDS: [&'static str; 20] = [
        "linearWindow",
        "angularWindow",
        "windowSpreads",
        "maxLinearWindow",
        "maxAngularWindow",
        "angularStep",
        "hypotheses",
        "coarseFactor",
        "maxIterations",
        "minRange",
        "maxRange",
        "maxPoints",
        "minPositionSpread",
        "minHeadingSpread",
        "fitPositionSpread",
        "fitHeadingSpread",
        "refineTranslationWeight",
        "refineRotationWeight",
        "minOverlap",
        "minScore",
    ];

    /// Checks every field, naming the first bad one as a page spells it.
    pub fn validate(&self) -> Result<()> {
        error::non_negative("linearWindow", self.linear_window)?;
        error::non_negative("angularWindow", self.angular_window)?;
        if self.angular_window > std::f64::consts::PI {
            return Err(invalid(
                "angularWindow",
                error::show(self.angular_window),
                "at most pi radians (half a turn either way)",
            ));
        }
        error::non_negative("windowSpreads", self.window_spreads)?;
        error::non_negative("maxLinearWindow", self.max_linear_window)?;
        if self.max_linear_window < self.linear_window {
            return Err(invalid(
                "maxLinearWindow",
                error::show(self.max_linear_window),
                format!(
                    "at least linearWindow ({})",
                    error::show(self.linear_window)
                ),
            ));
        }
        error::non_negative("maxAngularWindow", self.max_angular_window)?;
        if !(self.max_angular_window >= self.angular_window
            && self.max_angular_window <= std::f64::consts::PI)
        {
            return Err(invalid(
                "maxAngularWindow",
                error::show(self.max_angular_window),
                format!(
                    "at least angularWindow ({}) and at most pi radians",
                    error::show(self.angular_window)
                ),
            ));
        }
        error::positive("angularStep", self.angular_step)?;
        if !(1..=MAX_HYPOTHESES).contains(&self.hypotheses) {
            return Err(invalid(
                "hypotheses",
                self.hypotheses,
                "a whole number from 1 to 16",
            ));
        }
        let f = self.coarse_factor;
        if !(f.is_power_of_two() && (2..=MAX_COARSE_FACTOR).contains(&f)) {
            return Err(invalid(
                "coarseFactor",
                f,
                "2, 4, 8 or 16 (cells of the map per coarse cell)",
            ));
        }
        if self.max_iterations > MAX_ITERATIONS {
            return Err(invalid(
                "maxIterations",
                self.max_iterations,
                "a whole number from 0 to 100",
            ));
        }
        error::non_negative("minRange", self.min_range)?;
        error::positive("maxRange", self.max_range)?;
        if self.max_range <= self.min_range {
            return Err(invalid(
                "maxRange",
                error::show(self.max_range),
                format!("more than minRange ({})", error::show(self.min_range)),
            ));
        }
        if !(1..=MAX_POINTS).contains(&self.max_points) {
            return Err(invalid(
                "maxPoints",
                self.max_points,
                "a whole number from 1 to 4096",
            ));
        }
        error::positive("minPositionSpread", self.min_position_spread)?;
        error::positive("minHeadingSpread", self.min_heading_spread)?;
        error::positive("fitPositionSpread", self.fit_position_spread)?;
        error::positive("fitHeadingSpread", self.fit_heading_spread)?;
        error::non_negative("refineTranslationWeight", self.refine_translation_weight)?;
        error::non_negative("refineRotationWeight", self.refine_rotation_weight)?;
        for (field, v) in [
            ("minOverlap", self.min_overlap),
            ("minScore", self.min_score),
        ] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(invalid(field, error::show(v), "a fraction from 0 to 1"));
            }
        }
        Ok(())
    }

    /// [`Self::validate`], and the search's size on a map of `resolution`
    /// metres per cell: the window is walked candidate by candidate, so it
    /// is bounded before any work (a step of 1e-9 radians over half a turn
    /// would never end).
    pub fn validate_for(&self, resolution: f64) -> Result<()> {
        self.validate()?;
        self.check_resolution(resolution)
    }

    /// The part of [`Self::validate_for`] that depends on the map's
    /// resolution, for settings already validated.
    pub fn check_resolution(&self, resolution: f64) -> Result<()> {
        let resolution = error::positive("resolution", resolution)?;
        // The coarse copy of the map covers the scan's points: as wide as
        // the traversal's window for a beam of the same reach.
        let reach = (self.max_range + self.max_linear_window) / resolution;
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(reach <= MAX_REACH_CELLS) {
            return Err(invalid(
                "maxRange",
                error::show(self.max_range),
                format!(
                    "at most {} m at {} m per cell (2045 cells with the linear window)",
                    error::show(MAX_REACH_CELLS * resolution - self.max_linear_window),
                    error::show(resolution)
                ),
            ));
        }
        let widest = Self {
            linear_window: self.max_linear_window,
            angular_window: self.max_angular_window,
            ..*self
        };
        let candidates = widest.candidates_at(resolution * self.coarse_factor as f64);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(candidates <= MAX_CANDIDATES as f64) {
            return Err(invalid(
                "angularStep",
                error::show(self.angular_step),
                format!(
                    "a step that keeps the search within {MAX_CANDIDATES} candidate poses \
                     (these windows at {} m per cell need {}: widen the step, narrow the \
                     windows or raise coarseFactor)",
                    error::show(resolution),
                    candidates.min(1e18) as u64
                ),
            ));
        }
        Ok(())
    }

    /// These settings with the search window widened for `prediction`:
    /// `windowSpreads` of its spreads either side, at least the least
    /// window and at most the most.
    pub fn window_for(&self, prediction: &super::Prediction) -> Self {
        let linear = self.window_spreads * prediction.position_spread;
        let angular = self.window_spreads * prediction.heading_spread;
        Self {
            linear_window: linear.min(self.max_linear_window).max(self.linear_window),
            angular_window: angular
                .min(self.max_angular_window)
                .max(self.angular_window),
            ..*self
        }
    }

    /// Headings the search tries: the prediction and `n` steps either side.
    pub fn heading_steps(&self) -> usize {
        (self.angular_window / self.angular_step).floor() as usize
    }

    /// Positions either side of the prediction along x (and y) for a
    /// coarse cell of `step` metres.
    pub fn position_steps(&self, step: f64) -> usize {
        (self.linear_window / step).ceil() as usize
    }

    /// Candidate poses of a search with coarse cells of `step` metres.
    pub fn candidates_at(&self, step: f64) -> f64 {
        let headings = 2.0 * (self.angular_window / self.angular_step).floor() + 1.0;
        let side = 2.0 * (self.linear_window / step).ceil() + 1.0;
        headings * side * side
    }
}
