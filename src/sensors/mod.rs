//! Sensors and their noise: range scans, the LiDAR, the sonar ring,
//! odometry (Table 5.6), a log's scans in one format-neutral store, the one normal draw every noisy reading uses, and
//! the forward beam model `p(z | x, m)` of Table 6.1, which both scores and
//! samples readings. One type per sensor kind: every scene holds these, and
//! none defines its own.

pub mod beam_model;
pub mod lidar;
pub mod noise;
pub mod odometry;
pub mod scan;
pub mod scan_log;
pub mod sonar;

pub use scan::Scan;
pub use scan_log::{LogPoseKinds, ScanLog, ScanRecord};
