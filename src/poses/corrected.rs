//! The log's own reference poses: the corrected path another estimator
//! computed, which the chapter's maps assume as the pose oracle.

use super::{PoseSource, PoseSourceKind, SourceInfo, SourceSettings};
use crate::geometry::Pose;
use crate::sensors::ScanLog;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::Corrected,
    name: "corrected",
    caption: |_| "Corrected poses (the log\u{2019}s own)".into(),
    described: |_| None,
    export_suffix: None,
    beside: &[],
    start: |log, settings| Ok(Box::new(Corrected::new(log, settings))),
};

/// The log's poses, as it gives them.
#[derive(Debug, Clone)]
pub struct Corrected {
    poses: Vec<Pose>,
}

impl Corrected {
    fn new(log: &ScanLog, _: &SourceSettings) -> Self {
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
