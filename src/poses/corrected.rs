//! The log's own reference poses: the corrected path another estimator
//! computed, which the chapter's maps assume as the pose oracle.

use super::{PoseSource, PoseSourceKind, SourceInfo, SourceSettings};
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
    pub(super) fn new(log: &ScanLog, _: &SourceSettings) -> Self {
        Self {
            poses: log.poses().to_vec(),
        }
    }
}

impl PoseSource for Corrected {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::Corrected
    }

    fn poses(&self) -> &[Pose] {
        &self.poses
    }
}
