//! Reading CARMEN laser logs.
//!
//! This is where real data enters the project (SPEC §11): a log file, read
//! as a stream, becomes [`LaserRecord`]s (one per laser line, with its
//! corrected pose), and the records are kept compactly in [`LaserScans`].
//! The real-log session ([`crate::apps::real_log`]) maps them; the map then
//! leaves through [`super::map_server`].
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
//! number, ranges not negative, counts whole. The trailing timestamps and
//! host name are optional. The first malformed line ends the read with an
//! [`OccError::Parse`] naming the line and the reason; nothing after it is
//! trusted.
//!
//! A **log cut short** keeps the complete scans before the cut: a last
//! laser line that ends without a newline and cannot be read (a file cut
//! inside the ranges or the pose), or a gzip stream that ends early, ends
//! the read cleanly with a [`LogReader::warning`] naming the line, not an
//! error. (A cut among the trailing timestamps, which the map does not use,
//! loses nothing: that line is read as usual.)
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
//! memory). [`LaserScans`] keeps ranges as `f32` (CARMEN writes centimetres;
//! `f32` rounds an 80 m reading by at most 4 µm) and one pose and angle pair
//! per scan: about 0.8 kB per 180-beam scan, less than the line's text.
//! What it keeps has a budget ([`LogBudget::kept_bytes`], 256 MiB by
//! default: some 300,000 scans of 180 beams, sixty times the longest log of
//! the public corpus), checked before anything is allocated
//! (`try_reserve`): a log past it (a gzip bomb of valid lines) is refused
//! with the budget and what it would need, and what was kept is freed.
//! Each [`LogLoader::read`] call is bounded by scans, lines and bytes of
//! text ([`LogBudget`]), so a file of blank lines is read in bounded steps
//! like any other.

use super::gzip::GzipReader;
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::sensors::Scan;
use std::io::{self, BufRead, BufReader, Chain, Cursor, Read};

/// The longest line the reader accepts, in bytes (a 10,000-beam
/// `ROBOTLASER1` line with remissions is about 200 kB).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most beams (and remission values) a laser line may declare.
pub const MAX_BEAMS: usize = 10_000;

/// What a log may cost, checked as it is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogBudget {
    /// Bytes the kept scans ([`LaserScans`]) may take.
    pub kept_bytes: usize,
    /// Lines one [`LogLoader::read`] call reads at most.
    pub lines_per_read: usize,
    /// Bytes of (decompressed) text one [`LogLoader::read`] call reads at
    /// most (the line that crosses it is finished).
    pub bytes_per_read: u64,
}

/// The default [`LogBudget::kept_bytes`]: 256 MiB.
pub const MAX_KEPT_BYTES: usize = 256 << 20;

impl Default for LogBudget {
    fn default() -> Self {
        Self {
            kept_bytes: MAX_KEPT_BYTES,
            lines_per_read: 1 << 16,
            bytes_per_read: 1 << 20,
        }
    }
}

/// Mebibytes, for messages.
fn mib(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
}

/// A parsed log: its laser scans in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct CarmenLog {
    pub scans: Vec<Scan>,
    /// Lines read, laser or not.
    pub lines: usize,
    /// How a log cut short ended ([`LogReader::warning`]), if it was.
    pub warning: Option<String>,
}

/// Angle between consecutive FLASER beams for a scan of `n` beams.
pub fn flaser_angle_increment(n: usize) -> f64 {
    use std::f64::consts::PI;
    match n {
        181 | 361 | 721 => PI / (n - 1) as f64,
        _ => PI / n as f64,
    }
}

/// Reads a whole log from bytes, gzip-compressed or plain.
pub fn parse_bytes(bytes: &[u8]) -> Result<CarmenLog> {
    read_log(bytes)
}

/// Reads a whole log from a stream, gzip-compressed or plain: only the
/// current line is held besides the scans.
pub fn read_log<R: Read>(reader: R) -> Result<CarmenLog> {
    let mut log = LogReader::new(reader);
    let mut scans = Vec::new();
    for record in &mut log {
        scans.push(record?.to_scan()?);
    }
    Ok(CarmenLog {
        scans,
        lines: log.lines_read(),
        warning: log.warning().map(str::to_string),
    })
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
    /// Ranges, metres: finite, not negative. Beam `i` lies at bearing
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
    /// The record as the mappers take it. (The reader has checked every
    /// field already; the scan checks again, so this cannot fail on a
    /// record the reader produced.)
    pub fn to_scan(&self) -> Result<Scan> {
        Scan::uniform(
            self.pose,
            self.ranges.clone(),
            self.first_bearing,
            self.bearing_step,
        )
    }
}

/// Counts the bytes taken from the caller's reader, for a progress bar over
/// the raw (possibly compressed) input.
struct Counting<R> {
    inner: R,
    count: u64,
}

impl<R: Read> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.count += n as u64;
        Ok(n)
    }
}

/// The first bytes (read to detect gzip) put back in front of the rest.
type Head<R> = Chain<Cursor<Vec<u8>>, Counting<R>>;

/// Buffer size of the line reader and of the decompressor's output.
const BUFFER: usize = 64 * 1024;

enum Source<R: Read> {
    /// Not yet read from: gzip or plain is decided on the first read.
    Unopened(R),
    Plain(BufReader<Head<R>>),
    Gzip(BufReader<GzipReader<BufReader<Head<R>>>>),
    /// After the end of the file or an error.
    Closed,
}

impl<R: Read> Source<R> {
    fn open(reader: R) -> io::Result<Self> {
        // Read up to two bytes: gzip members start with 0x1f 0x8b.
        let mut counting = Counting {
            inner: reader,
            count: 0,
        };
        let mut magic = [0u8; 2];
        let mut n = 0;
        while n < 2 {
            match counting.read(&mut magic[n..]) {
                Ok(0) => break,
                Ok(k) => n += k,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        let gzip = n == 2 && magic == super::gzip::MAGIC;
        let head = Cursor::new(magic[..n].to_vec()).chain(counting);
        Ok(if gzip {
            Source::Gzip(BufReader::with_capacity(
                BUFFER,
                GzipReader::new(BufReader::with_capacity(BUFFER, head)),
            ))
        } else {
            Source::Plain(BufReader::with_capacity(BUFFER, head))
        })
    }

    fn bytes_read(&self) -> Option<u64> {
        match self {
            Source::Plain(b) => Some(b.get_ref().get_ref().1.count),
            Source::Gzip(b) => Some(b.get_ref().get_ref().get_ref().get_ref().1.count),
            _ => None,
        }
    }

    fn is_gzip(&self) -> bool {
        matches!(self, Source::Gzip(_))
    }
}

/// How a call to [`read_line`] ended.
enum LineEnd {
    /// No more bytes: the previous line was the last.
    Eof,
    /// A line (with its newline, or the last line without one).
    Line,
    /// More than [`MAX_LINE_BYTES`] without a newline.
    TooLong,
}

/// Appends one line to `buf` (its newline included) without ever holding
/// more than `limit` bytes (`BufRead::read_until` would buffer a
/// newline-free file whole).
fn read_line(src: &mut dyn BufRead, buf: &mut Vec<u8>, limit: usize) -> io::Result<LineEnd> {
    loop {
        let avail = match src.fill_buf() {
            Ok(a) => a,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if avail.is_empty() {
            return Ok(if buf.is_empty() {
                LineEnd::Eof
            } else {
                LineEnd::Line
            });
        }
        let (take, complete) = match avail.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (avail.len(), false),
        };
        if buf.len() + take > limit {
            return Ok(LineEnd::TooLong);
        }
        buf.extend_from_slice(&avail[..take]);
        src.consume(take);
        if complete {
            return Ok(LineEnd::Line);
        }
    }
}

/// True when `line` holds bytes no text log has: NUL and the other control
/// characters (tab, line and form feeds, carriage return and escape
/// excepted), or invalid UTF-8.
fn is_binary(line: &[u8]) -> bool {
    line.iter()
        .any(|&b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0b | 0x0c | 0x1b) || b == 0x7f)
        // A character cut at the end (a line cut at the length limit) is
        // not a sign of binary.
        || std::str::from_utf8(line).is_err_and(|e| e.error_len().is_some())
}

/// The error for a line of binary bytes, in words.
fn binary_reason(line: usize, gzip: bool) -> String {
    if gzip {
        "the file is gzip, but what it holds is not text: not a CARMEN log".into()
    } else if line == 1 {
        "the file is neither gzip nor a text log (its first line holds binary bytes): not a CARMEN log".into()
    } else {
        "the line holds binary bytes, not text: the file is not a CARMEN log".into()
    }
}

/// What one step of [`LogReader::step`] found.
enum Step {
    Record(LaserRecord),
    /// The step's budget of lines or bytes ran out first.
    Paused,
    End,
}

/// A streaming reader of a CARMEN log (gzip or plain, detected from the
/// first bytes): an iterator over its laser records. It stops at the first
/// error, which names the line: the iterator yields it once and ends, and
/// [`LogReader::next_record`] keeps returning it (a reader that failed
/// never reports a clean end over a half-read log). A log cut short ends
/// cleanly with a [`Self::warning`].
pub struct LogReader<R: Read> {
    source: Source<R>,
    line: Vec<u8>,
    lines: usize,
    /// Bytes of text (after decompression) read so far.
    text_bytes: u64,
    /// Laser records returned so far.
    records: usize,
    bytes_at_close: u64,
    failure: Option<OccError>,
    warning: Option<String>,
}

impl<R: Read> LogReader<R> {
    /// A reader over `reader` (any `Read`, so any `BufRead` too). Nothing is
    /// read until the first record is asked for.
    pub fn new(reader: R) -> Self {
        Self {
            source: Source::Unopened(reader),
            line: Vec::new(),
            lines: 0,
            text_bytes: 0,
            records: 0,
            bytes_at_close: 0,
            failure: None,
            warning: None,
        }
    }

    /// How the read ended early, when the log was cut short: the line and
    /// what was kept ("line 5103: the file ends inside this FLASER line
    /// (...); the 1519 complete scans before it are kept").
    pub fn warning(&self) -> Option<&str> {
        self.warning.as_deref()
    }

    /// Bytes of text read so far (after decompression).
    pub fn text_bytes(&self) -> u64 {
        self.text_bytes
    }

    /// Ends the read cleanly at a cut on line `line` (an error when there is
    /// no complete scan before it to keep).
    fn cut_short(&mut self, line: usize, what: String) -> Result<Step> {
        let n = self.records;
        if n == 0 {
            return self.fail(line, what);
        }
        self.close();
        self.warning = Some(format!(
            "line {line}: {what}; the {n} complete scan{} before it {} kept",
            if n == 1 { "" } else { "s" },
            if n == 1 { "is" } else { "are" },
        ));
        Ok(Step::End)
    }

    /// Lines read so far, laser or not.
    pub fn lines_read(&self) -> usize {
        self.lines
    }

    /// Bytes taken from the underlying reader so far (compressed bytes for
    /// a gzip file; read ahead by up to one buffer).
    pub fn bytes_read(&self) -> u64 {
        self.source.bytes_read().unwrap_or(self.bytes_at_close)
    }

    /// True once the end of the file or an error has been reached.
    pub fn is_finished(&self) -> bool {
        matches!(self.source, Source::Closed)
    }

    fn close(&mut self) {
        self.bytes_at_close = self.bytes_read();
        self.source = Source::Closed;
    }

    fn fail<T>(&mut self, line: usize, reason: String) -> Result<T> {
        self.close();
        let e = OccError::Parse { line, reason };
        self.failure = Some(e.clone());
        Err(e)
    }

    /// The next laser record, `Ok(None)` at the end of the file (or at a
    /// cut: see [`Self::warning`]).
    pub fn next_record(&mut self) -> Result<Option<LaserRecord>> {
        match self.step(usize::MAX, u64::MAX)? {
            Step::Record(r) => Ok(Some(r)),
            Step::End => Ok(None),
            Step::Paused => unreachable!("an unbounded step does not pause"),
        }
    }

    /// Reads lines until a laser record, the end, or `max_lines` lines /
    /// `max_bytes` bytes of text (the line that crosses it is finished).
    fn step(&mut self, max_lines: usize, max_bytes: u64) -> Result<Step> {
        if let Some(e) = &self.failure {
            return Err(e.clone());
        }
        let (lines0, bytes0) = (self.lines, self.text_bytes);
        if matches!(self.source, Source::Unopened(_)) {
            if let Source::Unopened(reader) = std::mem::replace(&mut self.source, Source::Closed) {
                match Source::open(reader) {
                    Ok(s) => self.source = s,
                    Err(e) => return self.fail(1, format!("cannot read the file: {e}")),
                }
            }
        }
        loop {
            if self.lines - lines0 >= max_lines || self.text_bytes - bytes0 >= max_bytes {
                return Ok(Step::Paused);
            }
            let gzip = self.source.is_gzip();
            let src: &mut dyn BufRead = match &mut self.source {
                Source::Plain(b) => b,
                Source::Gzip(b) => b,
                _ => return Ok(Step::End),
            };
            self.line.clear();
            match read_line(src, &mut self.line, MAX_LINE_BYTES) {
                Ok(LineEnd::Eof) => {
                    self.close();
                    return Ok(Step::End);
                }
                Ok(LineEnd::Line) => {
                    self.lines += 1;
                    self.text_bytes += self.line.len() as u64;
                }
                Ok(LineEnd::TooLong) => {
                    let line = self.lines + 1;
                    let reason = if is_binary(&self.line) {
                        binary_reason(line, gzip)
                    } else {
                        format!("line is longer than {MAX_LINE_BYTES} bytes: not a CARMEN log")
                    };
                    return self.fail(line, reason);
                }
                Err(e) => {
                    if gzip && e.kind() == io::ErrorKind::UnexpectedEof {
                        // The partial line (if any) is dropped with the cut.
                        return self.cut_short(
                            self.lines + 1,
                            "the compressed file ends early (cut short?)".into(),
                        );
                    }
                    let reason = if gzip {
                        format!("the compressed file is damaged: {e}")
                    } else {
                        format!("cannot read the file: {e}")
                    };
                    return self.fail(self.lines + 1, reason);
                }
            }
            let number = self.lines;
            if is_binary(&self.line) {
                return self.fail(number, binary_reason(number, gzip));
            }
            // The last line of a file cut short has no newline.
            let unterminated = self.line.last() != Some(&b'\n');
            let mut text: &[u8] = &self.line;
            if number == 1 {
                text = text.strip_prefix(b"\xef\xbb\xbf").unwrap_or(text);
            }
            let mut fields = text
                .split(|b: &u8| b.is_ascii_whitespace())
                .filter(|t| !t.is_empty());
            let Some(name) = fields.next() else {
                continue; // blank line
            };
            let parsed = match name {
                b"FLASER" => parse_flaser(number, fields),
                b"ROBOTLASER1" => parse_robot_laser(number, fields),
                _ if name[0] == b'#' || is_message_name(name) => continue,
                _ => Err(format!(
                    "not a CARMEN log line: it starts with {}, not a message name such as FLASER or ODOM",
                    show(name)
                )),
            };
            return match parsed {
                Ok(record) => {
                    self.records += 1;
                    Ok(Step::Record(record))
                }
                Err(reason) if unterminated => self.cut_short(
                    number,
                    format!("the file ends inside this line, which is cut short ({reason})"),
                ),
                Err(reason) => self.fail(number, reason),
            };
        }
    }
}

impl<R: Read> Iterator for LogReader<R> {
    type Item = Result<LaserRecord>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failure.is_some() {
            return None; // already yielded
        }
        self.next_record().transpose()
    }
}

/// A message name: a capital letter, then capitals, digits or `_`.
fn is_message_name(token: &[u8]) -> bool {
    token[0].is_ascii_uppercase()
        && token
            .iter()
            .all(|&b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
}

/// A token for an error message: quoted, at most 24 characters.
fn show(token: &[u8]) -> String {
    let text = String::from_utf8_lossy(token);
    let cut: String = text.chars().take(24).collect();
    if cut.len() < text.len() {
        format!("{cut:?}…")
    } else {
        format!("{cut:?}")
    }
}

fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// The fields of one laser line, parsed left to right; errors are messages
/// that name the message and the field.
struct Fields<'a, I: Iterator<Item = &'a [u8]>> {
    tokens: I,
    message: &'static str,
}

impl<'a, I: Iterator<Item = &'a [u8]>> Fields<'a, I> {
    /// The next field as a finite number; `name` is only built on error.
    fn number(&mut self, name: impl FnOnce() -> String) -> std::result::Result<f64, String> {
        let message = self.message;
        let Some(token) = self.tokens.next() else {
            return Err(format!("{message} line ends before {}", name()));
        };
        match parse_f64(token) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(format!(
                "{message} {} is not finite: {}",
                name(),
                show(token)
            )),
            None => Err(format!(
                "{message} {} is not a number: {}",
                name(),
                show(token)
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

    /// `n` ranges, each finite and not negative.
    fn ranges(&mut self, n: usize) -> std::result::Result<Vec<f64>, String> {
        let mut ranges = Vec::with_capacity(n);
        for i in 0..n {
            let r = self.number(|| format!("range {}", i + 1))?;
            if r < 0.0 {
                return Err(format!("{} range {} is negative: {r}", self.message, i + 1));
            }
            ranges.push(r);
        }
        Ok(ranges)
    }

    fn pose(&mut self, x: &str, y: &str, theta: &str) -> std::result::Result<Pose, String> {
        Ok(Pose {
            x: self.named(x)?,
            y: self.named(y)?,
            theta: self.named(theta)?,
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
    let mut f = Fields {
        tokens,
        message: "FLASER",
    };
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
    let mut f = Fields {
        tokens,
        message: "ROBOTLASER1",
    };
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

/// The laser scans of a log, kept compactly for a map build: all ranges in
/// one `f32` buffer, one pose, angle pair and maximum range per scan.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LaserScans {
    poses: Vec<Pose>,
    /// `[first_bearing, bearing_step]`, radians.
    angles: Vec<[f64; 2]>,
    /// The laser's own maximum range, metres; infinite when the log does
    /// not say (FLASER). Kept in `f32` like the ranges, so that "at or
    /// beyond the maximum" is decided the same way after rounding.
    max_range: Vec<f32>,
    /// Scan `k`'s ranges are `ranges[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    ranges: Vec<f32>,
    lines: Vec<usize>,
}

impl LaserScans {
    pub fn new() -> Self {
        Self::default()
    }

    /// Reads every laser record of a log (gzip or plain), within the
    /// default budget.
    pub fn read<R: Read>(reader: R) -> Result<Self> {
        let mut scans = Self::new();
        for record in LogReader::new(reader) {
            scans.push(&record?, MAX_KEPT_BYTES)?;
        }
        Ok(scans)
    }

    /// Bytes kept per scan besides its ranges: pose, angles, maximum range,
    /// offset and line number.
    pub const SCAN_BYTES: usize = std::mem::size_of::<Pose>()
        + std::mem::size_of::<[f64; 2]>()
        + std::mem::size_of::<f32>()
        + 2 * std::mem::size_of::<usize>();

    /// Bytes the scans take (by the same reckoning as the budget).
    pub fn kept_bytes(&self) -> usize {
        self.ranges.len() * std::mem::size_of::<f32>() + self.len() * Self::SCAN_BYTES
    }

    /// Grows `v` to hold `more` more items: doubling, but never past
    /// `most` items (the budget), and without aborting when memory is short.
    fn grow<T>(v: &mut Vec<T>, more: usize, most: usize) -> std::result::Result<(), ()> {
        let need = v.len() + more;
        if need <= v.capacity() {
            return Ok(());
        }
        let target = need.max(v.capacity().saturating_mul(2)).min(most.max(need));
        v.try_reserve_exact(target - v.len()).map_err(|_| ())
    }

    /// Keeps `record`, unless the scans would then take more than `budget`
    /// bytes: then an error naming the line, the budget and what keeping
    /// the log so far would need, and nothing is added. Room is reserved
    /// before anything is written (`try_reserve`), so an allocation that
    /// fails is the same clear error, not an abort.
    pub fn push(&mut self, record: &LaserRecord, budget: usize) -> Result<()> {
        let beams = record.ranges.len();
        let need = self.kept_bytes() + beams * std::mem::size_of::<f32>() + Self::SCAN_BYTES;
        let refuse = |what: String| OccError::Parse {
            line: record.line,
            reason: what,
        };
        if need > budget {
            return Err(refuse(format!(
                "the log is too large to keep: its scans up to this line need {} ({} scans, {} beams), \
                 over the budget of {} for a log's scans",
                mib(need),
                self.len() + 1,
                self.beams() + beams,
                mib(budget)
            )));
        }
        let scans_most = budget / Self::SCAN_BYTES + 1;
        let beams_most = budget / std::mem::size_of::<f32>();
        let n = self.len();
        let ok = Self::grow(&mut self.poses, 1, scans_most).is_ok()
            && Self::grow(&mut self.angles, 1, scans_most).is_ok()
            && Self::grow(&mut self.max_range, 1, scans_most).is_ok()
            && Self::grow(
                &mut self.offsets,
                if n == 0 { 2 } else { 1 },
                scans_most + 1,
            )
            .is_ok()
            && Self::grow(&mut self.lines, 1, scans_most).is_ok()
            && Self::grow(&mut self.ranges, beams, beams_most).is_ok();
        if !ok {
            return Err(refuse(format!(
                "out of memory keeping the log's scans: {} needed ({} scans so far)",
                mib(need),
                n + 1
            )));
        }
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.poses.push(record.pose);
        self.angles
            .push([record.first_bearing, record.bearing_step]);
        self.max_range
            .push(record.max_range.map_or(f32::INFINITY, |m| m as f32));
        self.ranges.extend(record.ranges.iter().map(|&r| r as f32));
        self.offsets.push(self.ranges.len());
        self.lines.push(record.line);
        Ok(())
    }

    /// Number of scans.
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// Number of beams over all scans.
    pub fn beams(&self) -> usize {
        self.ranges.len()
    }

    /// The laser pose of scan `k`.
    pub fn pose(&self, k: usize) -> Option<Pose> {
        self.poses.get(k).copied()
    }

    /// Every scan's laser pose, in order.
    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Puts the scans at other poses (a dead-reckoned path), one per scan:
    /// an error, and nothing changed, when the count differs.
    pub fn set_poses(&mut self, poses: &[Pose]) -> Result<()> {
        if poses.len() != self.poses.len() {
            let given = format!("{} poses for {} scans", poses.len(), self.poses.len());
            return Err(crate::error::invalid("poses", given, "one pose per scan"));
        }
        self.poses.copy_from_slice(poses);
        Ok(())
    }

    /// The line of the file scan `k` came from.
    pub fn line(&self, k: usize) -> Option<usize> {
        self.lines.get(k).copied()
    }

    /// The laser's own maximum range for scan `k` (infinite when unknown).
    pub fn max_range(&self, k: usize) -> Option<f64> {
        self.max_range.get(k).map(|&m| m as f64)
    }

    fn raw(&self, k: usize) -> Option<(&[f32], [f64; 2], Pose)> {
        let (&a, &b) = (self.offsets.get(k)?, self.offsets.get(k + 1)?);
        Some((
            self.ranges.get(a..b)?,
            *self.angles.get(k)?,
            *self.poses.get(k)?,
        ))
    }

    /// Scan `k` as the mappers take it.
    pub fn scan(&self, k: usize) -> Option<Scan> {
        let (ranges, [first, step], pose) = self.raw(k)?;
        let ranges = ranges.iter().map(|&r| r as f64).collect();
        Scan::uniform(pose, ranges, first, step).ok()
    }

    /// The box `[min_x, min_y, max_x, max_y]` (metres) holding every laser
    /// pose and every beam endpoint closer than `range_cap` (and than the
    /// laser's own maximum range: a no-return has no endpoint), or `None`
    /// when there are no scans.
    pub fn extent(&self, range_cap: f64) -> Option<[f64; 4]> {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut grow = |x: f64, y: f64| {
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        };
        for k in 0..self.len() {
            let Some((ranges, [first, step], pose)) = self.raw(k) else {
                continue;
            };
            grow(pose.x, pose.y);
            let max = self.max_range[k];
            for (i, &r) in ranges.iter().enumerate() {
                if r < max && (r as f64) < range_cap {
                    let (x, y) = pose.point_at(r as f64, first + i as f64 * step);
                    grow(x, y);
                }
            }
        }
        (!self.is_empty()).then_some(b)
    }
}

/// Reads a log into [`LaserScans`] a few records at a time, so that a page
/// can show progress and stay responsive on a long log.
pub struct LogLoader<R: Read> {
    reader: LogReader<R>,
    scans: LaserScans,
    budget: LogBudget,
}

/// How far a [`LogLoader`] has got.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct LoadProgress {
    pub lines: usize,
    pub scans: usize,
    pub beams: usize,
    /// Bytes of the (possibly compressed) input consumed.
    pub bytes_read: u64,
    pub finished: bool,
    /// How a log cut short ended ([`LogReader::warning`]), or `None`.
    pub warning: Option<String>,
}

impl<R: Read> LogLoader<R> {
    pub fn new(reader: R) -> Self {
        Self::with_budget(reader, LogBudget::default())
    }

    /// A loader with its own budget (a test's smaller one).
    pub fn with_budget(reader: R, budget: LogBudget) -> Self {
        Self {
            reader: LogReader::new(reader),
            scans: LaserScans::new(),
            budget,
        }
    }

    /// Reads up to `max_scans` more laser records (at least one call's worth
    /// of progress even when `max_scans` is 0), and at most the budget's
    /// lines and bytes of text per call. On an error (a malformed line, a
    /// log past the budget) the scans kept so far are freed: the log is
    /// refused whole, and the reader keeps returning the error.
    pub fn read(&mut self, max_scans: usize) -> Result<LoadProgress> {
        let (lines0, bytes0) = (self.reader.lines_read(), self.reader.text_bytes());
        for _ in 0..max_scans.max(1) {
            let lines = self
                .budget
                .lines_per_read
                .saturating_sub(self.reader.lines_read() - lines0);
            let bytes = self
                .budget
                .bytes_per_read
                .saturating_sub(self.reader.text_bytes() - bytes0);
            if lines == 0 || bytes == 0 {
                break;
            }
            let pushed = match self.reader.step(lines, bytes) {
                Ok(Step::Record(record)) => self.scans.push(&record, self.budget.kept_bytes),
                Ok(Step::Paused | Step::End) => break,
                Err(e) => Err(e),
            };
            if let Err(e) = pushed {
                if self.reader.failure.is_none() {
                    self.reader.close();
                    self.reader.failure = Some(e.clone());
                }
                self.scans = LaserScans::new();
                return Err(e);
            }
        }
        Ok(self.progress())
    }

    pub fn progress(&self) -> LoadProgress {
        LoadProgress {
            lines: self.reader.lines_read(),
            scans: self.scans.len(),
            beams: self.scans.beams(),
            bytes_read: self.reader.bytes_read(),
            finished: self.reader.is_finished(),
            warning: self.reader.warning().map(str::to_string),
        }
    }

    pub fn is_finished(&self) -> bool {
        self.reader.is_finished()
    }

    /// The scans read so far.
    pub fn into_scans(self) -> LaserScans {
        self.scans
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLASER3: &str = "FLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

    #[test]
    fn reads_flaser_and_skips_other_messages() {
        let text = format!("# comment\nODOM 1 2 3\n{FLASER3}");
        let log = parse_bytes(text.as_bytes()).unwrap();
        assert_eq!(log.scans.len(), 1);
        assert_eq!(log.lines, 3);
        let s = &log.scans[0];
        assert_eq!(s.ranges(), &[1.0, 2.0, 3.0]);
        assert_eq!(
            s.pose(),
            Pose {
                x: 0.5,
                y: -1.5,
                theta: 0.1
            }
        );
        assert!(
            (s.bearings()[1] - (-std::f64::consts::FRAC_PI_2 + std::f64::consts::PI / 3.0)).abs()
                < 1e-12
        );
    }

    #[test]
    fn malformed_lines_are_reported_with_their_number() {
        let e = parse_bytes(b"ODOM\nFLASER 3 1.0 2.0\n").unwrap_err();
        assert_eq!(
            e,
            OccError::Parse {
                line: 2,
                reason: "FLASER line ends before range 3".into()
            }
        );
        let e = parse_bytes(b"FLASER 2 1.0 nan 0 0 0 0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("line 1:") && e.contains("range 2"), "{e}");
        let e = parse_bytes(b"FLASER 2 1.0 -3 0 0 0 0 0 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("negative"), "{e}");
        let e = parse_bytes(&[0x46, 0xff, 0xfe, b'\n'])
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 1:") && e.contains("not a CARMEN log"),
            "{e}"
        );
        let e = parse_bytes(&[0x1f, 0x8b, 1, 2, 3]).unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn a_line_longer_than_the_limit_is_an_error_not_a_buffer() {
        let mut text = b"ODOM 1 2 3\nCOMMENT ".to_vec();
        text.resize(text.len() + MAX_LINE_BYTES + 10, b'x');
        let e = parse_bytes(&text).unwrap_err();
        assert!(
            matches!(&e, OccError::Parse { line: 2, reason } if reason.contains("longer")),
            "{e}"
        );
        // Exactly at the limit (newline included) is still a line.
        let mut ok = b"C".to_vec();
        ok.resize(MAX_LINE_BYTES - 1, b'X');
        ok.push(b'\n');
        assert_eq!(parse_bytes(&ok).unwrap().lines, 1);
    }

    #[test]
    fn a_byte_order_mark_and_crlf_line_ends_are_accepted() {
        let text = format!("\u{feff}# log\r\n{}", FLASER3.replace('\n', "\r\n"));
        let log = parse_bytes(text.as_bytes()).unwrap();
        assert_eq!((log.scans.len(), log.lines), (1, 2));
    }

    #[test]
    fn a_reader_that_failed_keeps_failing_and_the_iterator_ends() {
        let text = format!("{FLASER3}FLASER 2 1.0\n{FLASER3}");
        let mut loader = LogLoader::new(text.as_bytes());
        let e = loader.read(10).unwrap_err();
        assert!(matches!(e, OccError::Parse { line: 2, .. }), "{e}");
        assert_eq!(
            loader.read(10).unwrap_err(),
            e,
            "no clean end after a failure"
        );
        let mut it = LogReader::new(text.as_bytes());
        assert!(it.next().unwrap().is_ok());
        assert!(it.next().unwrap().is_err());
        assert!(it.next().is_none());
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
