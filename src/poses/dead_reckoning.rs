//! Dead reckoning on a real log: the log's motion between consecutive
//! laser poses, each increment split into rotate, translate, rotate and
//! given the odometry noise of Table 5.6 drawn from a seed, the noisy
//! motions added up from the first pose
//! ([`crate::sensors::odometry::OdometryParams::dead_reckon_path`]). The
//! chapter's "pose oracle off" on a real building.

use super::{PoseSource, PoseSourceKind, SourceInfo};
use crate::geometry::Pose;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::DeadReckoning,
    name: "dead-reckoning",
    menu: "dead reckoning (Table 5.6 noise)",
    caption: &["Dead reckoning (seed ", ")"],
    described: Some(&[
        "dead-reckoning (seed ",
        "): the log's motion with the odometry noise of Table 5.6, not its corrected poses",
    ]),
    provenance: &[
        "dead-reckoning (odometry simulated: the log's motion with Table 5.6's noise, seed ",
        ")",
    ],
    export_suffix: Some("dead-reckoning"),
    beside: &[PoseSourceKind::Corrected],
};

/// The dead-reckoned path of one seed.
#[derive(Debug, Clone)]
pub struct DeadReckoning {
    poses: Vec<Pose>,
}

impl DeadReckoning {
    /// The source over `poses`, dead-reckoned by the caller
    /// ([`crate::sensors::odometry::DeadReckoner`]).
    pub(super) fn of_path(poses: Vec<Pose>) -> Self {
        Self { poses }
    }
}

impl PoseSource for DeadReckoning {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::DeadReckoning
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }
}
