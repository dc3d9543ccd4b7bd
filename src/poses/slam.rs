//! The SLAM pose source ([`Slam`]): seeded dead reckoning (or the log's
//! own odometry where it has some, as the scan-matched source) corrected
//! by matching each scan against a submap of the scans before it, loops
//! closed against finished submaps, the pose graph optimised
//! ([`crate::slam`]). It keeps its own submaps: the map it is handed is
//! not read. After an optimisation the poses of earlier scans change, and
//! the revision ([`PoseSource::revision`]) rises: a map built at the old
//! poses is built again. An optimisation runs in slices of bounded work
//! ([`PoseSource::settle_within`]), its poses handed out only once it has
//! converged.

use super::{PoseSource, PoseSourceKind, SourceInfo, SourceSettings, MATCH_DRIFT_MARGIN};
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::mapping::scan_match::MatchMap;
use crate::sensors::{Scan, ScanLog};
use crate::slam::SlamBuilder;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::Slam,
    name: "slam",
    menu: "SLAM (scan matching with loop closure)",
    caption: &["SLAM (from dead reckoning, seed ", ")"],
    described: Some(&[
        "slam (seed ",
        "): dead reckoning (or the log's own odometry) matched against submaps, loops closed and the pose graph optimised, not the log's corrected poses",
    ]),
    provenance: &[
        "slam (from odometry simulated with Table 5.6's noise, seed ",
        ", or the log's own odometry where it differs from its corrected poses; submaps matched, loops closed, the pose graph optimised)",
    ],
    export_suffix: Some("slam"),
    beside: &[PoseSourceKind::Corrected, PoseSourceKind::DeadReckoning],
};

/// SLAM as a pose source.
#[derive(Debug, Clone)]
pub struct Slam {
    start: SlamBuilder,
    builder: SlamBuilder,
    /// The graph's poses for the scans located, the odometry's after.
    poses: Vec<Pose>,
    /// The local matches' work ([`super::match_work`]).
    match_work: u64,
}

impl Slam {
    /// SLAM from `odometry` (one pose per scan: the log's own, or dead
    /// reckoning, [`super::ScanMatching::odometry_of`], made by the caller).
    pub(super) fn from_odometry(odometry: Vec<Pose>, settings: &SourceSettings) -> Result<Self> {
        let builder = SlamBuilder::new(
            odometry.clone(),
            settings.noise,
            settings.matching,
            settings.resolution,
        )?;
        Ok(Self {
            start: builder.clone(),
            builder,
            poses: odometry,
            match_work: 0,
        })
    }

    /// The graph's poses handed out (once an optimisation has converged).
    fn take_poses(&mut self) {
        let found = self.builder.poses();
        self.poses[..found.len()].copy_from_slice(found);
    }

    /// The SLAM state: its graph, closures, revision.
    pub fn builder(&self) -> &SlamBuilder {
        &self.builder
    }
}

impl PoseSource for Slam {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::Slam
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Scan `k` located by SLAM. Scans come in order from the first: a
    /// scan out of order is an error, and nothing changes.
    fn locate(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Pose> {
        let _ = map;
        if k != self.builder.located() {
            return Err(OccError::State(format!(
                "SLAM locates scans in order: scan {k} asked, scan {} next",
                self.builder.located()
            )));
        }
        let revision = self.builder.revision();
        let pose = self.builder.locate_scan(scan, laser_max)?;
        self.match_work += super::match_work(self.builder.last_match());
        if self.builder.revision() != revision {
            self.take_poses();
        } else if let Some(p) = self.poses.get_mut(k) {
            *p = pose;
        }
        Ok(pose)
    }

    fn loop_closures(&self) -> Option<usize> {
        Some(self.builder.closures())
    }

    fn pose_graph(&self) -> Option<&crate::slam::PoseGraph> {
        Some(&self.builder.graph)
    }

    fn settling(&self) -> bool {
        self.builder.is_settling()
    }

    fn settle_within(&mut self, budget: u64) -> bool {
        let revision = self.builder.revision();
        let done = self.builder.settle_within(budget);
        if self.builder.revision() != revision {
            self.take_poses();
        }
        done
    }

    fn plan_poses<'a>(&'a self, log: &'a ScanLog) -> (&'a [Pose], f64) {
        (log.poses(), MATCH_DRIFT_MARGIN)
    }

    fn work(&self) -> u64 {
        self.builder.work() + self.match_work
    }

    fn reset(&mut self) {
        self.builder = self.start.clone();
        self.match_work = 0;
        self.poses.copy_from_slice(self.start.odometry());
    }

    fn revision(&self) -> u64 {
        self.builder.revision()
    }
}
