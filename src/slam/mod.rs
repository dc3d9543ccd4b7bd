//! SLAM with loop closure: what the `slam` pose source
//! ([`crate::poses`]) locates each scan with when the log's poses are not
//! trusted. After Hess et al. 2016 ("Real-time loop closure in 2D LIDAR
//! SLAM", Cartographer), one idea per file:
//!
//! - [`submap`]: small grids of a few consecutive scans, matched against
//!   while they grow, finished and kept as bytes after;
//! - [`loop_search`]: branch and bound over precomputed maximum grids, a
//!   scan against a finished submap over a wide window;
//! - [`packed_rows`]: a finished submap's bytes run-length coded at rest;
//! - [`facing`]: which way the surfaces of a scan's points and of a
//!   submap's cells face, so that a wall's two faces are never matched
//!   one on the other;
//! - [`pose_graph`]: the SE(2) graph of scans, local edges and robust loop
//!   edges, optimised by Gauss–Newton over an envelope Cholesky of its own;
//! - [`builder`]: the local trajectory and the graph, scan by scan.
//!
//! Everything is sequential `f64` arithmetic in a fixed order: the same
//! odometry and scans give the same poses bit for bit.

pub mod builder;
pub mod facing;
pub mod loop_search;
pub mod packed_rows;
pub mod pose_graph;
pub mod submap;

pub use builder::SlamBuilder;
pub use pose_graph::{Edge, Optimizer, PoseGraph, RobustSettings};
