//! A pose source started over a log in steps of bounded work
//! ([`SourceStart`]): its path (the log's own poses or odometry copied,
//! or dead reckoning integrated) is made a bounded number of poses per
//! step, so that a page's session, which starts every pane's source when
//! a log is read, never makes a million poses in one call
//! (docs/ARCHITECTURE.md, "Real logs"). [`PoseSourceKind::start`] is the
//! same start run to its end: one path, bit for bit, however it is cut.
//! A source that finds its poses (scan matching, SLAM) also has its
//! second copy of the path made here, so that its making costs no walk
//! of the poses.

use super::scan_matched::path_work_bound;
use super::{corrected, dead_reckoning, odometry, scan_matched, slam};
use super::{PoseSource, PoseSourceKind, SourceSettings};
use crate::error::Result;
use crate::geometry::Pose;
use crate::mapping::scan_match::ScanMatcher;
use crate::sensors::odometry::DeadReckoner;
use crate::sensors::ScanLog;

/// Poses copied for a unit of a step's work: a pose dead-reckoned (three
/// normal samples, a rotation) costs a unit, and copying one costs a small
/// share of that.
pub const COPIES_PER_UNIT: usize = 16;

/// How the path a source starts from is made.
#[derive(Debug, Clone)]
enum Path {
    /// A copy of the log's reference poses (`own` false) or of its own
    /// odometry (`own` true).
    Copy { own: bool, poses: Vec<Pose> },
    /// Seeded dead reckoning of the log's reference poses.
    DeadReckoned(Box<DeadReckoner>),
}

/// A pose source being started over a log, a bounded number of poses per
/// [`Self::step`]; [`Self::finish`] gives the source once
/// [`Self::is_done`].
#[derive(Debug, Clone)]
pub struct SourceStart {
    kind: PoseSourceKind,
    settings: SourceSettings,
    path: Path,
    /// A scan-matched or SLAM source's matcher (its settings checked when
    /// the start begins) and the second copy of its path it finds poses
    /// in.
    matcher: Option<(ScanMatcher, Vec<Pose>)>,
}

impl PoseSourceKind {
    /// This source over `log`, to be started in bounded steps
    /// ([`SourceStart`]): an error naming the source when it does not
    /// apply to the log, or naming the setting a matcher refuses.
    pub fn starting(self, log: &ScanLog, settings: &SourceSettings) -> Result<SourceStart> {
        self.check_applies(log)?;
        let copy = |own: bool| Path::Copy {
            own,
            poses: Vec::new(),
        };
        let dead_reckoned =
            || Path::DeadReckoned(Box::new(DeadReckoner::new(settings.noise, settings.seed)));
        // The odometry a matcher corrects: the log's own, or dead reckoning
        // ([`super::ScanMatching::odometry_of`]).
        let corrected_odometry = || match log.odometry() {
            Some(_) => copy(true),
            None => dead_reckoned(),
        };
        let (path, matcher) = match self {
            Self::Corrected => (copy(false), None),
            Self::DeadReckoning => (dead_reckoned(), None),
            Self::Odometry => {
                odometry::check_has_odometry(log)?;
                (copy(true), None)
            }
            Self::ScanMatched | Self::Slam => {
                let matcher = ScanMatcher::for_resolution(settings.matching, settings.resolution)?;
                (corrected_odometry(), Some((matcher, Vec::new())))
            }
        };
        Ok(SourceStart {
            kind: self,
            settings: *settings,
            path,
            matcher,
        })
    }
}

impl SourceStart {
    /// Which source is being started.
    pub fn kind(&self) -> PoseSourceKind {
        self.kind
    }

    /// The most work finding the poses of `log` may cost the source, where
    /// known before its path is (a scan matcher's or SLAM's,
    /// [`PoseSource::work_bound`]); `None` until the source is started.
    pub fn work_bound(&self, log: &ScanLog) -> Option<u64> {
        let (matcher, _) = self.matcher.as_ref()?;
        let (settings, resolution) = (matcher.settings(), self.settings.resolution);
        Some(match self.kind {
            PoseSourceKind::Slam => slam::work_bound(settings, resolution, log),
            _ => path_work_bound(settings, resolution, log),
        })
    }

    /// Makes up to `max_units` units of the path over `log` (the log the
    /// start began over, at every step): a pose dead-reckoned is a unit,
    /// [`COPIES_PER_UNIT`] poses copied another. Returns the units spent,
    /// at least one while any pose is left, whatever `max_units`.
    pub fn step(&mut self, log: &ScanLog, max_units: usize) -> usize {
        let max_units = max_units.max(1);
        let n = log.len();
        let mut spent = match &mut self.path {
            Path::DeadReckoned(path) => path.extend(log.poses(), max_units),
            Path::Copy { own, poses } => {
                let from = if *own {
                    log.odometry().unwrap_or_default()
                } else {
                    log.poses()
                };
                copy_some(from, poses, max_units)
            }
        };
        // A matcher's second copy follows once the path is made.
        let left = max_units.saturating_sub(spent);
        if self.path_len() == n && left > 0 {
            if let Some((_, copy)) = &mut self.matcher {
                let path = match &self.path {
                    Path::DeadReckoned(p) => p.path(),
                    Path::Copy { poses, .. } => poses,
                };
                spent += copy_some(path, copy, left);
            }
        }
        spent
    }

    /// Poses of the path made so far.
    fn path_len(&self) -> usize {
        match &self.path {
            Path::DeadReckoned(path) => path.len(),
            Path::Copy { poses, .. } => poses.len(),
        }
    }

    /// True once the path over `log` is made: [`Self::finish`] then costs
    /// no walk of the poses.
    pub fn is_done(&self, log: &ScanLog) -> bool {
        let n = log.len();
        self.path_len() == n && self.matcher.as_ref().is_none_or(|(_, c)| c.len() == n)
    }

    /// The source, its path made to the end first if it is not yet.
    pub fn finish(mut self, log: &ScanLog) -> Result<Box<dyn PoseSource>> {
        while !self.is_done(log) {
            self.step(log, usize::MAX);
        }
        let path = match self.path {
            Path::DeadReckoned(path) => path.into_path(),
            Path::Copy { poses, .. } => poses,
        };
        let s = &self.settings;
        Ok(match (self.kind, self.matcher) {
            (PoseSourceKind::Corrected, _) => Box::new(corrected::Corrected::of_path(path)),
            (PoseSourceKind::DeadReckoning, _) => {
                Box::new(dead_reckoning::DeadReckoning::of_path(path))
            }
            (PoseSourceKind::Odometry, _) => Box::new(odometry::OwnOdometry::of_path(path)),
            (PoseSourceKind::ScanMatched, Some((matcher, poses))) => Box::new(
                scan_matched::ScanMatching::of_path(matcher, (path, poses), s.noise, s.resolution),
            ),
            (PoseSourceKind::ScanMatched, None) => Box::new(scan_matched::ScanMatching::new(
                path,
                s.noise,
                s.matching,
                s.resolution,
            )?),
            (PoseSourceKind::Slam, Some((matcher, poses))) => {
                let bound = slam::work_bound(matcher.settings(), s.resolution, log);
                Box::new(slam::Slam::of_path((path, poses), s, bound)?)
            }
            // (Not reached: a SLAM start has its matcher.)
            (PoseSourceKind::Slam, None) => {
                let bound = slam::work_bound(&s.matching, s.resolution, log);
                Box::new(slam::Slam::of_path((path.clone(), path), s, bound)?)
            }
        })
    }
}

/// Copies up to `max_units` units' worth of `from` past the end of `to`
/// (room for all of `from` reserved at once, so that no step copies the
/// poses before); returns the units spent.
fn copy_some(from: &[Pose], to: &mut Vec<Pose>, max_units: usize) -> usize {
    let k0 = to.len();
    if k0 >= from.len() {
        return 0;
    }
    let end = from
        .len()
        .min(k0.saturating_add(max_units.saturating_mul(COPIES_PER_UNIT)));
    to.reserve_exact(from.len() - k0);
    to.extend_from_slice(&from[k0..end]);
    (end - k0).div_ceil(COPIES_PER_UNIT)
}
