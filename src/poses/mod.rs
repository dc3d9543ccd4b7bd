//! Pose sources: where each scan of a log is put on the map. The chapter
//! maps with known poses (an oracle hands them over); a real robot has its
//! odometry, and what an estimator makes of it. Every source is one
//! [`PoseSource`] (the pose of scan `k`, the work found poses cost, a
//! reset), each in a file of its own:
//!
//! - `corrected`: the log's reference poses (a corrected path: the oracle);
//! - `dead_reckoning`: the log's motion with the odometry noise of Table
//!   5.6, drawn from a seed, integrated from the first pose;
//! - `scan_matched`: the log's odometry (or dead reckoning) corrected scan
//!   by scan by matching each scan against the map of the scans before it
//!   ([`crate::mapping::scan_match`]);
//! - `odometry`: the log's own odometry (a ROS 2 bag's), where it has
//!   some;
//! - `slam`: scan matching against submaps with loops closed and a pose
//!   graph optimised ([`crate::slam`]);
//! - `matched_path`: that source with a map of its own, for a caller
//!   without one.
//!
//! [`PoseSourceKind`] names them as the settings and the page do; the
//! registry ([`PoseSourceKind::info`]) is the one place that knows every
//! source: a new source is one more file here, one more variant, one more
//! entry of the registry and one more arm of [`PoseSourceKind::start`]. A map holder (a real-log pane) holds a
//! `Box<dyn PoseSource>` and asks it for each scan's pose before inserting
//! the scan with the one insertion recipe ([`crate::mapping::insertion`]).

mod corrected;
mod dead_reckoning;
mod matched_path;
mod odometry;
mod pose_error;
mod scan_matched;
mod slam;
mod start;

pub use matched_path::{MatchedPath, StepReport};
pub use pose_error::{Alignment, AlignmentSums, GrowingAlignment};
pub use scan_matched::{
    match_settings, match_work, match_work_bound, pooled_work, ScanMatching, MATCH_DRIFT_MARGIN,
};
pub use slam::{local_match_work, Slam, LOCAL_MATCH_UNITS, LOOP_SEARCH_ALLOWANCE};
pub use start::{SourceStart, COPIES_PER_UNIT};

use crate::error::{invalid, Result};
use crate::geometry::Pose;
use crate::mapping::scan_match::{MatchMap, MatchSettings};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::{Scan, ScanLog};

/// A source of one laser pose per scan of a log.
pub trait PoseSource {
    /// Which source this is.
    fn kind(&self) -> PoseSourceKind;

    /// One laser pose per scan: the poses found for the scans located so
    /// far, and the source's first guess for the others (a scan-matched
    /// path's odometry).
    fn poses(&self) -> &[Pose];

    /// The pose of scan `k` (`scan` at its pose in the log, `laser_max`
    /// the laser's own maximum range, infinite when unknown), found before
    /// the scan is inserted into `map`, the map of scans `0..k` at the
    /// poses found for them. Sources that know every pose in advance read
    /// nothing.
    fn locate(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Pose> {
        let _ = (scan, laser_max, map);
        Ok(self.poses().get(k).copied().unwrap_or_else(|| scan.pose()))
    }

    /// A bounded step towards locating scan `k` as [`Self::locate`]
    /// does: the pose once found, `None` while steps are left (the call
    /// is then made again with the same scan and map, the map unchanged).
    /// A source whose locating is one bounded step locates at once.
    fn locate_step(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Option<Pose>> {
        self.locate(k, scan, laser_max, map).map(Some)
    }

    /// The poses a plan of the map walks (its extent, the tiles its beams
    /// reach) and the metres of drift it leaves room for around them: the
    /// source's own poses, known in advance, by default.
    fn plan_poses<'a>(&'a self, log: &'a ScanLog) -> (&'a [Pose], f64) {
        let _ = log;
        (self.poses(), 0.0)
    }

    /// Work spent finding poses since the last reset, in the units of a
    /// cell update (so that one budget bounds a build's call).
    fn work(&self) -> u64 {
        0
    }

    /// The most [`Self::work`] finding the pose of every scan of `log` may
    /// cost, known before the first scan is located, so that a plan can
    /// refuse a log past its budget: 0 for a source that knows its poses
    /// in advance.
    fn work_bound(&self, log: &ScanLog) -> u64 {
        let _ = log;
        0
    }

    /// Back to before the first scan.
    fn reset(&mut self) {}

    /// The scan matching of a source that matches scans (its last match,
    /// the odometry it corrects).
    fn matching(&self) -> Option<&ScanMatching> {
        None
    }

    /// Raised each time the poses of scans already located change (a
    /// SLAM source's optimisation): a map built at the old poses must be
    /// built again. Sources whose poses never change once found stay at 0.
    fn revision(&self) -> u64 {
        0
    }

    /// Whether the poses of scans already located may change later (a
    /// SLAM source): a map built at them keeps where it put each scan.
    fn revises(&self) -> bool {
        false
    }

    /// The loop closures a source that closes loops (SLAM) has found so
    /// far; `None` for one that closes none.
    fn loop_closures(&self) -> Option<usize> {
        None
    }

    /// The pose graph of a source that keeps one (SLAM: its nodes, local
    /// edges and loop closures), for a page to draw; `None` for the others.
    fn pose_graph(&self) -> Option<&crate::slam::PoseGraph> {
        None
    }

    /// Why the source locates no more scans, once it has refused to (a
    /// SLAM source past its bound of work, [`PoseSource::work_bound`]):
    /// a build then stops there and says so.
    fn refusal(&self) -> Option<&crate::error::OccError> {
        None
    }

    /// Whether work on the poses already located is under way (a SLAM
    /// source's optimisation): the next scan waits until it is done.
    fn settling(&self) -> bool {
        false
    }

    /// That work for at most about `budget` units (at least one bounded
    /// step of it); the revision rises once it has changed the poses.
    /// True when none is left.
    fn settle_within(&mut self, budget: u64) -> bool {
        let _ = budget;
        true
    }
}

/// What a source is started with besides the log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceSettings {
    /// The seed of dead reckoning's noise (one seed, one path).
    pub seed: u64,
    /// The odometry's noise (Table 5.6): what dead reckoning adds, and how
    /// far a scan matcher's predictions may be off.
    pub noise: OdometryParams,
    /// The scan matcher's settings, for the sources that match.
    pub matching: MatchSettings,
    /// The map's resolution, metres per cell.
    pub resolution: f64,
}

/// The pose sources, as settings, pages and the command line name them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum PoseSourceKind {
    /// The log's own reference (corrected) laser poses: the pose oracle.
    #[default]
    #[serde(rename = "corrected")]
    Corrected,
    /// Dead reckoning: the log's motion increments between consecutive
    /// laser poses, each corrupted with the odometry noise of Table 5.6
    /// (drawn from the seed) and integrated from the first pose. The
    /// corrected logs carry no raw odometry (their odometry fields repeat
    /// the corrected poses), so the noise is made here: the chapter's
    /// "pose oracle off" on a real building.
    #[serde(rename = "dead-reckoning")]
    DeadReckoning,
    /// Scan matching: dead reckoning (or the log's own odometry) corrected
    /// scan by scan by matching each scan against the map built so far,
    /// before integrating it ([`crate::mapping::scan_match`]).
    #[serde(rename = "scan-matched")]
    ScanMatched,
    /// The log's own odometry (a ROS 2 bag's, interpolated at each scan's
    /// stamp), where it has odometry of its own.
    #[serde(rename = "odometry")]
    Odometry,
    /// SLAM: dead reckoning (or the log's own odometry) matched against
    /// submaps of recent scans, loops closed and the pose graph optimised
    /// ([`crate::slam`]).
    #[serde(rename = "slam")]
    Slam,
}

/// What the registry knows of one pose source.
pub struct SourceInfo {
    pub kind: PoseSourceKind,
    /// The name a page and the CLI use.
    pub name: &'static str,
    /// How a page's menu of pose sources words this one.
    pub menu: &'static str,
    /// The caption of a pane mapped at these poses: its pieces, the seed
    /// written between them.
    pub caption: &'static [&'static str],
    /// What a map exported at these poses says of them (a comment line of
    /// its YAML; the seed written between the pieces), or `None` for the
    /// log's own.
    pub described: Option<&'static [&'static str]>,
    /// How the poses were found, for the provenance lines of an exported
    /// map's YAML (the seed written between the pieces): a simulated
    /// odometry says so, with its seed.
    pub provenance: &'static [&'static str],
    /// What an exported map's file name adds for these poses
    /// (`intel-dead-reckoning-map`), or `None` for the log's own.
    pub export_suffix: Option<&'static str>,
    /// The sources whose maps a session shows beside this one's, for
    /// comparison.
    pub beside: &'static [PoseSourceKind],
}

impl PoseSourceKind {
    /// Every source, in the order a page lists them.
    pub const ALL: [PoseSourceKind; 5] = [
        Self::Corrected,
        Self::DeadReckoning,
        Self::ScanMatched,
        Self::Odometry,
        Self::Slam,
    ];
    /// The names a page and the CLI use, in the order of [`Self::ALL`].
    pub const NAMES: [&'static str; 5] = [
        "corrected",
        "dead-reckoning",
        "scan-matched",
        "odometry",
        "slam",
    ];

    /// The registry entry of this source.
    pub fn info(self) -> &'static SourceInfo {
        match self {
            Self::Corrected => &corrected::INFO,
            Self::DeadReckoning => &dead_reckoning::INFO,
            Self::ScanMatched => &scan_matched::INFO,
            Self::Odometry => &odometry::INFO,
            Self::Slam => &slam::INFO,
        }
    }

    /// The name a page uses (one of [`Self::NAMES`]).
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The source named `name`, or an error naming `field` and the text.
    pub fn from_name(field: &str, name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| invalid(field, format!("\"{name}\""), Self::NAMES.join(", ")))
    }

    /// The caption of a pane mapped at these poses.
    pub fn caption(self, seed: u64) -> String {
        with_seed(self.info().caption, seed)
    }

    /// What a map exported at these poses says of them, or `None` for the
    /// log's own.
    pub fn described(self, seed: u64) -> Option<String> {
        Some(with_seed(self.info().described?, seed))
    }

    /// How these poses were found, with `seed` where the source draws
    /// from one ([`SourceInfo::provenance`]).
    pub fn provenance(self, seed: u64) -> String {
        with_seed(self.info().provenance, seed)
    }

    /// The panes a session shows when the reader maps at `chosen`: that
    /// source's map first (the one operated: hover, zoom, export), then
    /// the maps of the sources it is compared with.
    pub fn panes(chosen: PoseSourceKind) -> Vec<PoseSourceKind> {
        std::iter::once(chosen)
            .chain(chosen.info().beside.iter().copied())
            .collect()
    }

    /// This source over `log` (one pose per scan). (Apart from the
    /// registry's words, which pages read without the code of a source.)
    /// Started at once: [`Self::starting`] run to its end.
    pub fn start(self, log: &ScanLog, settings: &SourceSettings) -> Result<Box<dyn PoseSource>> {
        self.starting(log, settings)?.finish(log)
    }

    /// The poses a read log is mapped at when the reader names none: its
    /// corrected poses where it carries reference poses (a CARMEN log, and
    /// a ROS 2 bag with a `map → odom` transform, as a localiser or SLAM
    /// recorded it: the best poses the log has, as a CARMEN log's corrected
    /// path is), else its own odometry.
    pub fn own_of(log: &ScanLog) -> Self {
        let kinds = log.pose_kinds();
        if kinds.odometry && !kinds.reference {
            Self::Odometry
        } else {
            Self::Corrected
        }
    }

    /// Whether this source can place `log`'s scans: the log's reference
    /// poses for `corrected`, and for `dead-reckoning`, which adds its
    /// noise to their motion (a log with odometry of its own and no
    /// reference poses, a ROS 2 bag, has real odometry instead); the
    /// log's own odometry for `odometry`.
    pub fn applies(self, log: &ScanLog) -> bool {
        self.check_applies(log).is_ok()
    }

    fn check_applies(self, log: &ScanLog) -> Result<()> {
        let kinds = log.pose_kinds();
        let why = match self {
            Self::Corrected if !kinds.reference => {
                "the log carries no reference (corrected) poses, only its own odometry (a ROS 2 bag has them only with a map \u{2192} odom transform): map it at odometry or scan-matched"
            }
            Self::DeadReckoning if !kinds.reference => {
                "the log carries real odometry and no reference poses to add noise to; map it at odometry"
            }
            Self::Odometry if !kinds.odometry => {
                "the log carries no odometry of its own (its odometry fields repeat its corrected poses)"
            }
            _ => return Ok(()),
        };
        Err(crate::error::OccError::State(format!(
            "the pose source {} does not apply: {why}",
            self.name()
        )))
    }
}

/// The pieces of a text with `seed` written between them.
fn with_seed(pieces: &[&str], seed: u64) -> String {
    pieces.join(&seed.to_string())
}
