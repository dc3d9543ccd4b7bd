//! One plain-Rust session per widget: every number a reader sees, answered
//! in image units (pixels of the drawn map, x right, y down), so that the
//! JavaScript only draws. The bindings wrap each session in one newtype.

pub mod doorway_trap;
pub mod inverse_workbench;
pub mod map_weaver;
pub mod real_log;
pub mod sensor_fusion;
pub mod two_cell_table;
