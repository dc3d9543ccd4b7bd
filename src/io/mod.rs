//! Files in and out: gzip, CARMEN laser logs, and ROS `map_server` PGM + YAML.

pub mod carmen;
pub mod gzip;
pub mod map_server;
