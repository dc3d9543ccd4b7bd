//! Geometry, the bottom layer: poses, the grid's limits (world ↔ cell ↔
//! image), and the supercover raster that walks a ray through cells.

pub mod grid_geometry;
pub mod order;
pub mod pose;
pub mod raster;

pub use grid_geometry::{GridGeometry, MAX_CELLS};
pub use pose::{wrap_angle, Pose};
