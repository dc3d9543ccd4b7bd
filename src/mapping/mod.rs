//! Mapping: from readings to a map. Table 9.1's recursion by ray traversal
//! and as the literal sweep, MAP occupancy mapping (Table 9.3), the exact
//! joint posterior of a few cells (the independence trap), max fusion of one
//! grid per sensor (eq. 9.9), a single cell's filter, and scan matching (the
//! pose source for when no oracle hands the poses over).

pub mod cell_filter;
pub mod drift;
pub mod fusion;
pub mod insertion;
pub mod joint;
pub mod map_search;
pub mod neighbour_support;
pub mod reach;
pub mod scan_match;
mod search_incidence;
pub mod sweep;
pub mod traversal;
pub mod walls;

pub use sweep::sweep_scan;
pub use traversal::{RayMapper, ScanStats};
