//! The log's own odometry as the laser's poses: a ROS 2 bag's odometry
//! interpolated at each scan's stamp and moved by the laser's mount
//! ([`crate::io::ros2`]), or a CARMEN log's raw odometry fields, where
//! they differ from its corrected poses. The map lies in the odometry
//! frame, where every source over the log starts.

use super::{PoseSource, PoseSourceKind, SourceInfo};
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::sensors::ScanLog;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::Odometry,
    name: "odometry",
    menu: "odometry (the log\u{2019}s own)",
    caption: &["Odometry (the log\u{2019}s own)"],
    described: Some(&["odometry: the log's own odometry, not corrected poses"]),
    provenance: &["odometry (the log's own odometry, as recorded)"],
    export_suffix: Some("odometry"),
    beside: &[],
};

/// The log's odometry, one laser pose per scan.
#[derive(Debug, Clone)]
pub struct OwnOdometry {
    poses: Vec<Pose>,
}

impl OwnOdometry {
    /// The source over `poses`, a copy of the log's own odometry.
    pub(super) fn of_path(poses: Vec<Pose>) -> Self {
        Self { poses }
    }
}

/// An error naming the source when `log` carries no odometry of its own.
pub(super) fn check_has_odometry(log: &ScanLog) -> Result<()> {
    match log.odometry() {
        Some(_) => Ok(()),
        None => Err(OccError::State(
            "the pose source odometry does not apply: the log carries no odometry of its own (its odometry fields repeat its corrected poses)".into(),
        )),
    }
}

impl PoseSource for OwnOdometry {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::Odometry
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }
}
