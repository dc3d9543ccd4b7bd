//! One line of a log, read: a `FLASER` or `ROBOTLASER1` line becomes a
//! [`LaserRecord`], any other message is skipped, and a malformed laser
//! line is a reason in words naming the message and the field (the module
//! doc of [`super`] lists what counts as malformed).

use super::{MAX_BEAMS, MAX_HEADING, MAX_POSE_COORDINATE};
use crate::error::Result;
use crate::geometry::Pose;
use crate::sensors::Scan;

/// Angle between consecutive FLASER beams for a scan of `n` beams.
pub fn flaser_angle_increment(n: usize) -> f64 {
    use std::f64::consts::PI;
    match n {
        181 | 361 | 721 => PI / (n - 1) as f64,
        _ => PI / n as f64,
    }
}

/// Which laser message a record came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum LaserMessage {
    Flaser,
    RobotLaser1,
}

/// One laser line of a log.
#[derive(Debug, Clone, PartialEq)]
pub struct LaserRecord {
    /// Line number in the file, from 1.
    pub line: usize,
    pub message: LaserMessage,
    /// The laser's corrected pose.
    pub pose: Pose,
    /// Ranges, metres: finite, not negative, each within `f32` (what
    /// [`crate::sensors::ScanLog`] keeps). Beam `i` lies at bearing
    /// `first_bearing + i * bearing_step` from the pose's heading.
    pub ranges: Vec<f64>,
    /// Bearing of the first beam, radians.
    pub first_bearing: f64,
    /// Angle between consecutive beams, radians.
    pub bearing_step: f64,
    /// The laser's own maximum range, metres (`ROBOTLASER1` only): a
    /// reading at or beyond it is a no-return.
    pub max_range: Option<f64>,
    /// Raw odometry pose (`FLASER` only).
    pub odometry: Option<Pose>,
    /// Corrected robot pose (`ROBOTLASER1` only).
    pub robot_pose: Option<Pose>,
    /// `ipc_timestamp`, seconds, when the line has one.
    pub timestamp: Option<f64>,
}

impl LaserRecord {
    /// The record as the mappers take it, at the text's own precision
    /// (the map is built from [`crate::sensors::ScanLog::scan`], which holds the
    /// ranges in `f32`).
    pub fn to_scan(&self) -> Result<Scan> {
        Scan::uniform(
            self.pose,
            self.ranges.clone(),
            self.first_bearing,
            self.bearing_step,
        )
    }
}

/// The laser messages CARMEN writes that are not read: front and rear
/// lasers of old logs (`RLASER`, `LASER3`, `LASER4` beside `FLASER`), the
/// raw scans without a pose (`RAWLASER1` to `RAWLASER4`) and the second
/// robot laser (`ROBOTLASER2`). A log holding them is still read; how many
/// were passed over is said once the read ends.
pub(super) const SKIPPED_LASER_MESSAGES: [&str; 8] = [
    "RLASER",
    "LASER3",
    "LASER4",
    "RAWLASER1",
    "RAWLASER2",
    "RAWLASER3",
    "RAWLASER4",
    "ROBOTLASER2",
];

/// What one line of a log is.
#[derive(Debug)]
pub(super) enum LogLine {
    /// A blank line, a comment or a message that is not a laser one.
    Other,
    /// A laser line that is read.
    Laser(LaserRecord),
    /// A laser line that is not read: its message's index in
    /// [`SKIPPED_LASER_MESSAGES`].
    SkippedLaser(usize),
}

/// Reads one complete line (newline included, if any): what the line is,
/// and the reason when a laser line is malformed.
pub(super) fn laser_line(number: usize, line: &[u8]) -> std::result::Result<LogLine, String> {
    let mut text = line;
    if number == 1 {
        text = text.strip_prefix(b"\xef\xbb\xbf").unwrap_or(text);
    }
    let mut fields = text
        .split(|b: &u8| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty());
    let Some(name) = fields.next() else {
        return Ok(LogLine::Other); // blank line
    };
    match name {
        b"FLASER" => parse_flaser(number, fields).map(LogLine::Laser),
        b"ROBOTLASER1" => parse_robot_laser(number, fields).map(LogLine::Laser),
        _ if name[0] == b'#' => Ok(LogLine::Other),
        _ if is_message_name(name) => Ok(SKIPPED_LASER_MESSAGES
            .iter()
            .position(|m| m.as_bytes() == name)
            .map_or(LogLine::Other, LogLine::SkippedLaser)),
        _ => Err(format!(
            "not a CARMEN log line: it starts with {}, not a message name such as FLASER or ODOM",
            show(token_text(name))
        )),
    }
}

/// A message name: a capital letter, then capitals, digits or `_`.
fn is_message_name(token: &[u8]) -> bool {
    token[0].is_ascii_uppercase()
        && token
            .iter()
            .all(|&b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
}

/// A token as text, at most 24 characters (and "…" when cut).
fn token_text(token: &[u8]) -> (String, bool) {
    let text = String::from_utf8_lossy(token);
    let cut: String = text.chars().take(24).collect();
    let was_cut = cut.len() < text.len();
    (cut, was_cut)
}

/// A token for an error message: quoted, at most 24 characters.
fn show((cut, was_cut): (String, bool)) -> String {
    format!("{cut:?}{}", if was_cut { "…" } else { "" })
}

/// A number as the log wrote it, for an error message (unquoted: it parsed
/// as a number, so it holds no byte a reader cannot see).
fn as_written(token: &[u8]) -> String {
    let (cut, was_cut) = token_text(token);
    format!("{cut}{}", if was_cut { "…" } else { "" })
}

/// A number as `str::parse::<f64>` reads it ([`super::number`]).
fn parse_f64(token: &[u8]) -> Option<f64> {
    super::number::parse_f64(token)
}

/// The fields of one laser line, parsed left to right; errors are messages
/// that name the message and the field.
struct Fields<'a, I: Iterator<Item = &'a [u8]>> {
    tokens: I,
    message: &'static str,
    /// The token the last number came from.
    last: &'a [u8],
}

impl<'a, I: Iterator<Item = &'a [u8]>> Fields<'a, I> {
    fn new(tokens: I, message: &'static str) -> Self {
        Self {
            tokens,
            message,
            last: b"",
        }
    }

    /// The next field as a finite number; `name` is only built on error.
    fn number(&mut self, name: impl FnOnce() -> String) -> std::result::Result<f64, String> {
        let message = self.message;
        let Some(token) = self.tokens.next() else {
            return Err(format!("{message} line ends before {}", name()));
        };
        self.last = token;
        match parse_f64(token) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(format!(
                "{message} {} is not finite: {}",
                name(),
                show(token_text(token))
            )),
            None => Err(format!(
                "{message} {} is not a number: {}",
                name(),
                show(token_text(token))
            )),
        }
    }

    fn named(&mut self, name: &str) -> std::result::Result<f64, String> {
        self.number(|| name.to_string())
    }

    /// A whole number from `min` to [`MAX_BEAMS`].
    fn count(&mut self, name: &str, min: usize) -> std::result::Result<usize, String> {
        let n = self.named(name)?;
        if n.fract() == 0.0 && n >= min as f64 && n <= MAX_BEAMS as f64 {
            Ok(n as usize)
        } else {
            Err(format!(
                "{} {name} must be a whole number from {min} to {MAX_BEAMS}, found {n}",
                self.message
            ))
        }
    }

    /// A distance that [`crate::sensors::ScanLog`] keeps in `f32`: one past
    /// `f32::MAX` would become infinite there, and a scan with an infinite
    /// reading cannot be mapped, so it is refused here by name rather than
    /// dropped later without a word.
    /// `name` is only built on error.
    fn stored_distance(
        &self,
        name: impl FnOnce() -> String,
        v: f64,
    ) -> std::result::Result<f64, String> {
        if (v as f32).is_finite() {
            Ok(v)
        } else {
            Err(format!(
                "{} {} = {} is beyond {:.1e} m, what a stored reading can hold",
                self.message,
                name(),
                as_written(self.last),
                f32::MAX
            ))
        }
    }

    /// `n` ranges, each finite, not negative and within `f32`.
    fn ranges(&mut self, n: usize) -> std::result::Result<Vec<f64>, String> {
        let mut ranges = Vec::with_capacity(n);
        for i in 0..n {
            let r = self.number(|| format!("range {}", i + 1))?;
            if r < 0.0 {
                return Err(format!("{} range {} is negative: {r}", self.message, i + 1));
            }
            ranges.push(self.stored_distance(|| format!("range {}", i + 1), r)?);
        }
        Ok(ranges)
    }

    /// A coordinate of a pose, within [`MAX_POSE_COORDINATE`] of the origin.
    fn coordinate(&mut self, name: &str) -> std::result::Result<f64, String> {
        let v = self.named(name)?;
        if v.abs() <= MAX_POSE_COORDINATE {
            Ok(v)
        } else {
            Err(format!(
                "{} {name} = {} m is beyond {MAX_POSE_COORDINATE:e} m from the log's origin \
                 (a log spans a few kilometres at most)",
                self.message,
                as_written(self.last)
            ))
        }
    }

    /// A pose's heading, radians, within [`MAX_HEADING`] of 0.
    fn heading(&mut self, name: &str) -> std::result::Result<f64, String> {
        let v = self.named(name)?;
        if v.abs() <= MAX_HEADING {
            Ok(v)
        } else {
            Err(format!(
                "{} {name} = {} is not a heading: beyond {MAX_HEADING:.0} radians \
                 (1,000 pi; a heading lies within pi)",
                self.message,
                as_written(self.last)
            ))
        }
    }

    fn pose(&mut self, x: &str, y: &str, theta: &str) -> std::result::Result<Pose, String> {
        Ok(Pose {
            x: self.coordinate(x)?,
            y: self.coordinate(y)?,
            theta: self.heading(theta)?,
        })
    }

    /// `ipc_timestamp`: the third field from the end, when the optional
    /// tail `... ipc_timestamp ipc_hostname logger_timestamp` is there.
    fn timestamp(self) -> Option<f64> {
        let rest: Vec<&[u8]> = self.tokens.collect();
        rest.len()
            .checked_sub(3)
            .and_then(|k| parse_f64(rest[k]))
            .filter(|t| t.is_finite())
    }
}

fn parse_flaser<'a>(
    line: usize,
    tokens: impl Iterator<Item = &'a [u8]>,
) -> std::result::Result<LaserRecord, String> {
    let mut f = Fields::new(tokens, "FLASER");
    let n = f.count("beam count", 1)?;
    let ranges = f.ranges(n)?;
    let pose = f.pose("x", "y", "theta")?;
    let odometry = f.pose("odom_x", "odom_y", "odom_theta")?;
    Ok(LaserRecord {
        line,
        message: LaserMessage::Flaser,
        pose,
        ranges,
        first_bearing: -std::f64::consts::FRAC_PI_2,
        bearing_step: flaser_angle_increment(n),
        max_range: None,
        odometry: Some(odometry),
        robot_pose: None,
        timestamp: f.timestamp(),
    })
}

fn parse_robot_laser<'a>(
    line: usize,
    tokens: impl Iterator<Item = &'a [u8]>,
) -> std::result::Result<LaserRecord, String> {
    let mut f = Fields::new(tokens, "ROBOTLASER1");
    f.named("laser_type")?;
    let start_angle = f.named("start_angle")?;
    let fov = f.named("field_of_view")?;
    if !(fov > 0.0 && fov <= std::f64::consts::TAU + 1e-6) {
        return Err(format!(
            "ROBOTLASER1 field_of_view must be above 0 and at most 2 pi radians, found {fov}"
        ));
    }
    let step = f.named("angular_resolution")?;
    if step <= 0.0 {
        return Err(format!(
            "ROBOTLASER1 angular_resolution must be above 0 radians, found {step}"
        ));
    }
    let max_range = f.named("maximum_range")?;
    if max_range <= 0.0 {
        return Err(format!(
            "ROBOTLASER1 maximum_range must be above 0 metres, found {max_range}"
        ));
    }
    let max_range = f.stored_distance(|| "maximum_range".into(), max_range)?;
    f.named("accuracy")?;
    f.named("remission_mode")?;
    let n = f.count("beam count", 1)?;
    let last = start_angle + (n - 1) as f64 * step;
    if !last.is_finite() {
        return Err(format!(
            "ROBOTLASER1 angular_resolution {step} puts the last beam at {last} radians"
        ));
    }
    let ranges = f.ranges(n)?;
    let m = f.count("remission count", 0)?;
    for i in 0..m {
        f.number(|| format!("remission {}", i + 1))?;
    }
    let pose = f.pose("laser_x", "laser_y", "laser_theta")?;
    let robot_pose = f.pose("robot_x", "robot_y", "robot_theta")?;
    Ok(LaserRecord {
        line,
        message: LaserMessage::RobotLaser1,
        pose,
        ranges,
        first_bearing: start_angle,
        bearing_step: step,
        max_range: Some(max_range),
        odometry: None,
        robot_pose: Some(robot_pose),
        timestamp: f.timestamp(),
    })
}

#[cfg(test)]
mod tests {
    use super::super::{read_scans, LogLoader, LogReader};
    use crate::error::OccError;
    use crate::geometry::Pose;

    const FLASER3: &str = "FLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

    fn parse_error(text: &[u8]) -> OccError {
        read_scans(text).unwrap_err()
    }

    #[test]
    fn reads_flaser_and_skips_other_messages() {
        let text = format!("# comment\nODOM 1 2 3\n{FLASER3}");
        let (scans, progress) = LogLoader::new(text.as_bytes()).read_to_end().unwrap();
        assert_eq!((scans.len(), progress.records), (1, 3));
        let s = scans.scan(0).unwrap();
        assert_eq!(s.ranges(), &[1.0, 2.0, 3.0]);
        assert_eq!(
            s.pose(),
            Pose {
                x: 0.5,
                y: -1.5,
                theta: 0.1
            }
        );
        let third_of_pi = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI / 3.0;
        assert!((s.bearings()[1] - third_of_pi).abs() < 1e-12);
    }

    #[test]
    fn malformed_lines_are_reported_with_their_number() {
        assert_eq!(
            parse_error(b"ODOM\nFLASER 3 1.0 2.0\n"),
            OccError::Parse {
                line: 2,
                reason: "FLASER line ends before range 3".into()
            }
        );
        let e = parse_error(b"FLASER 2 1.0 nan 0 0 0 0 0 0\n").to_string();
        assert!(e.starts_with("line 1:") && e.contains("range 2"), "{e}");
        let e = parse_error(b"FLASER 2 1.0 -3 0 0 0 0 0 0\n").to_string();
        assert!(e.contains("negative"), "{e}");
        let e = parse_error(&[0x46, 0xff, 0xfe, b'\n']).to_string();
        assert!(
            e.starts_with("line 1:") && e.contains("not a CARMEN log"),
            "{e}"
        );
        let e = parse_error(&[0x1f, 0x8b, 1, 2, 3]).to_string();
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn a_byte_order_mark_and_crlf_line_ends_are_accepted() {
        let text = format!("\u{feff}# log\r\n{}", FLASER3.replace('\n', "\r\n"));
        let (scans, progress) = LogLoader::new(text.as_bytes()).read_to_end().unwrap();
        assert_eq!((scans.len(), progress.records), (1, 2));
    }

    #[test]
    fn timestamps_are_read_from_the_optional_tail() {
        let r = LogReader::new(FLASER3.as_bytes()).next().unwrap().unwrap();
        assert_eq!(r.timestamp, Some(1.0));
        assert_eq!(r.odometry, Some(Pose::default()));
        let r = LogReader::new(&b"FLASER 1 1.0 0 0 0 0 0 0\n"[..])
            .next()
            .unwrap()
            .unwrap();
        assert_eq!(r.timestamp, None);
    }
}
