//! The log's own reference poses: the corrected path another estimator
//! computed, which the chapter's maps assume as the pose oracle.

use super::{PoseSource, PoseSourceKind, SourceInfo};
use crate::geometry::Pose;
use crate::sensors::ScanLog;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::Corrected,
    name: "corrected",
    menu: "corrected (the log\u{2019}s)",
    caption: &["Corrected poses (the log\u{2019}s own)"],
    described: None,
    provenance: &["corrected (the log's own poses)"],
    export_suffix: None,
    beside: &[],
};

/// The log's poses, as it gives them.
#[derive(Debug, Clone)]
pub struct Corrected {
    poses: Vec<Pose>,
}

impl Corrected {
    /// The source over `poses`, a copy of the log's own.
    pub(super) fn of_path(poses: Vec<Pose>) -> Self {
        Self { poses }
    }
}

impl PoseSource for Corrected {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::Corrected
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// The log's own poses, which these are (so that a plan sees, without
    /// comparing them, that it walks the log's poses).
    fn plan_poses<'a>(&'a self, log: &'a ScanLog) -> (&'a [Pose], f64) {
        (log.poses(), 0.0)
    }
}
