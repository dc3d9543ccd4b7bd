//! occgrid — occupancy grid mapping after Thrun, Burgard & Fox,
//! *Probabilistic Robotics*, chapter 9.
//!
//! The folders follow a scan from the sensor to the pixel; each layer uses
//! only the layers above it in this list (`tests/layers.rs` checks it):
//!
//! * [`error`] — `OccError`, the validators, strict settings objects.
//! * [`geometry`] — poses, the grid's limits (world ↔ cell), the supercover raster.
//! * [`world`] — ground truth as a binary grid, and the one ray caster.
//! * [`sensors`] — scans, a log's scans in one format-neutral store, the LiDAR, the sonar ring, odometry (Table 5.6), noise, the beam model (Table 6.1).
//! * [`scenes`] — the apartment, the doorway, the table, training floor plans.
//! * [`grid`] — the log-odds map (Table 9.1's state), entropy, Brier score, counts.
//! * [`inverse`] — inverse sensor models: Table 9.2 and the learned one (§9.3).
//! * [`mapping`] — traversal, the one scan insertion of a log, the literal sweep, MAP search (Table 9.3), joint, fusion (eq. 9.9), scan matching.
//! * [`slam`] — submaps, loop search by branch and bound, the pose graph and its optimiser.
//! * [`poses`] — pose sources: where each scan of a log is put (the log's own poses, dead reckoning, scan matching).
//! * [`render`] — the gray ramp and the incremental map view.
//! * [`io`] — logs in (one reader per format behind one interface, CARMEN's first), ROS `map_server` maps out.
//! * [`apps`] — one session per widget: what each widget shows, in image units.
//! * [`mod@bench`] — the workloads of docs/BENCHMARKS.md.
//!
//! `bindings` (wasm only) wraps the sessions for JavaScript and holds no algorithm.

pub mod apps;
// The workloads are compiled natively always, and into the wasm only for
// the benchmark (`--features bench`): the page does not ship them.
#[cfg(any(not(target_arch = "wasm32"), feature = "bench"))]
pub mod bench;
pub mod error;
pub mod geometry;
pub mod grid;
pub mod inverse;
pub mod io;
pub mod mapping;
pub mod poses;
pub mod render;
pub mod scenes;
pub mod sensors;
pub mod slam;
pub mod world;

#[cfg(target_arch = "wasm32")]
pub mod bindings;

pub use error::{OccError, Result};
