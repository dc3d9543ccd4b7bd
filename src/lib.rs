//! occgrid — occupancy grid mapping after Thrun, Burgard & Fox,
//! *Probabilistic Robotics*, chapter 9.
//!
//! The crate is a pure Rust core, one module per idea, and a thin bindings
//! layer for the chapter's widgets:
//!
//! * [`grid`] — the log-odds map (Table 9.1's state), entropy, Brier score.
//! * [`cell_filter`] — one cell's filter, the chapter's worked example.
//! * [`scan`] — poses and range scans.
//! * [`raster`] — the supercover ray raster.
//! * [`inverse`] — inverse sensor models (Table 9.2) behind one trait.
//! * [`mapper`] — Table 9.1 by ray traversal and as a literal sweep.
//! * [`forward`] — the forward beam model `p(z | x, m)` (Table 6.1).
//! * [`joint`] — exact joint posteriors over a few cells (the independence trap).
//! * [`map_search`] — MAP occupancy mapping by hill climbing (Table 9.3).
//! * [`fusion`] — one grid per sensor, fused by eq. 9.9.
//! * [`sim`] — simulated scenes, robots and sensors.
//! * [`carmen`] — reading CARMEN laser logs.
//! * [`export`] — ROS `map_server` PGM + YAML.
//! * [`workloads`] — the benchmark workloads, shared by native and wasm runs.
//!
//! `bindings` (wasm only) wraps these for JavaScript and holds no algorithm.

pub mod carmen;
pub mod cell_filter;
pub mod error;
pub mod export;
pub mod forward;
pub mod fusion;
pub mod grid;
pub mod inverse;
pub mod joint;
pub mod map_search;
pub mod mapper;
pub mod raster;
pub mod scan;
pub mod sim;
pub mod workloads;

#[cfg(target_arch = "wasm32")]
pub mod bindings;

pub use error::{OccError, Result};
