//! Files in and out: CARMEN laser logs, and ROS `map_server` PGM + YAML.

pub mod carmen;
pub mod gzip;
pub mod map_server;
