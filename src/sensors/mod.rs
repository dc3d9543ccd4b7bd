//! Sensors and their noise: range scans, the LiDAR, odometry (Table 5.6), the
//! one normal draw every noisy reading uses, and the forward beam model
//! `p(z | x, m)` of Table 6.1, which both scores and samples readings.

pub mod beam_model;
pub mod lidar;
pub mod noise;
pub mod odometry;
pub mod scan;

pub use scan::Scan;
