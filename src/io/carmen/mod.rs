//! Reading CARMEN laser logs.
//!
//! One of the log formats behind [`super::LogSource`]: a log file, read as
//! a stream, becomes [`LaserRecord`]s (one per laser line, with its
//! corrected pose), and the records are kept compactly in the
//! format-neutral [`ScanLog`]. Every map of a log is built from that store,
//! read by one [`LogLoader`]: the real-log session
//! ([`crate::apps::real_log`]) and the command-line export read it a
//! budgeted step at a time (through [`super::open_log`]), workload W1 and
//! the tests through [`read_scans`], which runs the same loader to the
//! end. The map then leaves through [`super::map_server`].
//!
//! One file per job, in the order the bytes flow:
//!
//! * `source`: the bytes, plain or gzip ([`super::gzip`]), counted and
//!   handed over up to a limit;
//! * `lines`: [`LogReader`], one bounded line at a time, to records;
//! * `parse`: one line to a [`LaserRecord`], or the reason it is malformed;
//! * `loader`: [`LogLoader`], within a [`super::LogBudget`], keeping each
//!   laser line as a scan of a [`ScanLog`].
//!
//! # The format
//!
//! A CARMEN log is text, one message per line, the message name first
//! (`ODOM`, `PARAM`, `NEFF`, ...; `#` starts a comment). Two laser messages
//! are read, every other message is skipped:
//!
//! * `FLASER n r_1 … r_n x y theta odom_x odom_y odom_theta ipc_timestamp
//!   ipc_hostname logger_timestamp` — `x y theta` is the (corrected) laser
//!   pose. The scan covers 180 degrees from `-pi/2`; CARMEN's convention is
//!   that 181, 361 or 721 beams include both ends and any other count does
//!   not (180 beams are 1 degree apart).
//! * `ROBOTLASER1 laser_type start_angle field_of_view angular_resolution
//!   maximum_range accuracy remission_mode n r_1 … r_n m e_1 … e_m
//!   laser_x laser_y laser_theta robot_x robot_y robot_theta laser_tv
//!   laser_rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp
//!   ipc_hostname logger_timestamp` — the scan carries its own angles: beam
//!   `i` lies at `start_angle + i * angular_resolution` from `laser_theta`,
//!   and a reading at or beyond `maximum_range` is a no-return. The map is
//!   built at the laser pose; the robot pose is kept for the record.
//!
//! Ranges are metres, angles radians.
//!
//! # What counts as malformed
//!
//! Every line must be blank, a comment, or start with a message name
//! (capital letters, digits and `_`, beginning with a letter); anything else
//! means the file is not a CARMEN log (a picture dropped by mistake fails on
//! line 1). A laser line must hold every field up to and including the
//! odometry (`FLASER`) or the robot pose (`ROBOTLASER1`), each a finite
//! number, counts whole, and:
//!
//! * ranges (and `maximum_range`) not negative and within `f32`, the type
//!   [`ScanLog`] keeps them in (up to 3.4e38 m: a reading of 1e39 would
//!   become infinite there and its scan could not be mapped);
//! * every `x` and `y` of the line's poses within [`MAX_POSE_COORDINATE`]
//!   (1,000 km) of the log's origin: the logs of buildings and campuses
//!   span a few kilometres, and a pose at 1e300 m would leave no grid to
//!   build (its cells could not be counted);
//! * every heading (`theta`, `odom_theta`, `laser_theta`, `robot_theta`)
//!   within [`MAX_HEADING`] (1,000 pi) of 0: a heading lies within pi, or
//!   a few hundred turns from it when a logger does not wrap it, and one of
//!   1e300 radians is no angle (its sine and cosine are rounding noise).
//!
//! The trailing timestamps and host name are optional. The first malformed
//! line ends the read with an [`OccError::Parse`](crate::error::OccError)
//! naming the line, the field and the value; nothing after it is trusted.
//!
//! A **log cut short** keeps the complete scans before the cut: a last
//! laser line that ends without a newline and cannot be read (a file cut
//! inside the ranges or the pose), or a gzip stream that ends early, ends
//! the read cleanly with a [`LogReader::warning`] naming the line, not an
//! error. (A cut among the trailing timestamps, which the map does not use,
//! loses nothing: that line is read as usual.)
//!
//! **What is read without a word lost**: a finished read's
//! [`LogReader::warning`] also names, in one short sentence each (counts
//! and a first line, never a list that grows with the log), the laser
//! lines it passes over (`RLASER`, `LASER3`, `LASER4`, `RAWLASER1` to
//! `RAWLASER4`, `ROBOTLASER2`: only `FLASER` and `ROBOTLASER1` are mapped)
//! and scans whose `ipc_timestamp` runs backwards (mapped in file order
//! all the same). Loggers write a few messages slightly out of order (the
//! Intel log's stamps step back four times, by under a second), so stamps
//! count as running backwards when one steps back by more than 2 s or more
//! than one step in 100 does. Sentences are joined by ". ", after a cut
//! short's.
//!
//! **Foreign bytes** (a picture, an archive, random data) are refused on
//! the first line holding bytes no text log has (NUL and other control
//! characters, invalid UTF-8), in words: "the file is neither gzip nor a
//! text log"; no byte of it is copied into the message.
//!
//! # Memory and budgets
//!
//! [`LogReader`] holds one line at a time (at most [`MAX_LINE_BYTES`]; a
//! longer "line" is an error, so a binary file without newlines cannot fill
//! memory). [`ScanLog`] keeps ranges as `f32` (CARMEN writes centimetres;
//! `f32` rounds an 80 m reading by at most 4 µm) and one pose and angle pair
//! per scan: about 0.8 kB per 180-beam scan, less than the line's text.
//! What it keeps has a budget ([`super::LogBudget::kept_bytes`], 256 MiB by
//! default: some 300,000 scans of 180 beams, sixty times the longest log of
//! the public corpus), checked before anything is allocated
//! (`try_reserve`): a log past it (a gzip bomb of valid lines) is refused
//! with the budget and what it would need, and what was kept is freed.
//! Each [`LogLoader::read`] call is bounded by scans, lines, bytes of text
//! and, for gzip, bytes of the compressed file ([`super::LogBudget`]), the last
//! even inside a line or a member's header: a file of blank lines, a gzip
//! file of millions of empty members, with a 40 MB header name or with
//! zero padding, is read in bounded steps like any other.

mod lines;
mod loader;
mod number;
mod parse;
mod source;

pub use lines::LogReader;
pub use loader::LogLoader;
pub use parse::{flaser_angle_increment, LaserMessage, LaserRecord};

use crate::error::Result;
use crate::sensors::ScanLog;
use std::io::Read;

/// Reads every laser record of a CARMEN log (gzip or plain) through
/// [`LogLoader`], within the default budget.
pub fn read_scans<R: Read>(reader: R) -> Result<ScanLog> {
    LogLoader::new(reader).read_to_end().map(|(scans, _)| scans)
}

/// The longest line the reader accepts, in bytes (a 10,000-beam
/// `ROBOTLASER1` line with remissions is about 200 kB).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most beams (and remission values) a laser line may declare.
pub const MAX_BEAMS: usize = 10_000;

/// How far from the log's origin, in metres along `x` or `y`, a pose may
/// lie: 1,000 km, hundreds of times the span of any building or campus
/// log, and far inside what a grid over the log can count in cells.
pub const MAX_POSE_COORDINATE: f64 = 1e6;

/// How far from 0 a pose's heading may lie, in radians: 1,000 pi. A
/// wrapped heading lies within pi (a log's rounding takes it a little past:
/// the public corpus's headings stay within 3.25 rad); a heading counted on
/// through whole turns without wrapping still fits for 500 of them, and at
/// this size an `f64` holds it to 1e-12 rad, so its sine and cosine are
/// still the heading's. A heading of 1e300 has no angle left in it.
pub const MAX_HEADING: f64 = 1000.0 * std::f64::consts::PI;
