//! Files in and out: every log format behind one reader interface
//! (`log_source`: the trait, the budgets, the sniffer that picks the
//! reader; `open`: the reader a file's first bytes name), the CARMEN reader (`carmen/`), gzip, and ROS `map_server` PGM +
//! YAML.

pub mod carmen;
pub mod gzip;
pub mod log_source;
pub mod map_server;
pub mod mcap;
mod open;
pub mod ros2;

pub use log_source::{
    LoadProgress, LogBudget, LogFormat, LogSource, LogTopic, TopicChoices, MAX_KEPT_BYTES,
};
pub use open::{open_log, read_log};
