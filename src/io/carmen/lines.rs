//! The log as lines: [`LogReader`] takes one line at a time from the
//! [`Source`] (never more than [`MAX_LINE_BYTES`]), refuses binary bytes,
//! hands laser lines to the parser and stops at the first malformed one.
//! A read may be bounded by lines, bytes of text and, for gzip, bytes of
//! the compressed file; it then pauses (for the compressed bytes, even
//! inside a line) and the next read resumes there.

use super::parse::{laser_line, LaserRecord, LogLine, SKIPPED_LASER_MESSAGES};
use super::source::{is_budget_pause, Source};
use super::MAX_LINE_BYTES;
use crate::error::{OccError, Result};
use std::io::{self, BufRead, Read};

/// How a call to [`read_line`] ended.
enum LineEnd {
    /// No more bytes: the previous line was the last.
    Eof,
    /// A line (with its newline, or the last line without one).
    Line,
    /// More than [`MAX_LINE_BYTES`] without a newline.
    TooLong,
    /// The step's budget of compressed bytes ran out; `buf` holds the line
    /// so far.
    Paused,
}

/// Appends to `buf` up to the end of the line (its newline included)
/// without ever holding more than `limit` bytes (`BufRead::read_until`
/// would buffer a newline-free file whole).
fn read_line(src: &mut dyn BufRead, buf: &mut Vec<u8>, limit: usize) -> io::Result<LineEnd> {
    loop {
        let avail = match src.fill_buf() {
            Ok(a) => a,
            Err(e) if is_budget_pause(&e) => return Ok(LineEnd::Paused),
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
pub(super) enum Step {
    Record(LaserRecord),
    /// The step's budget of lines or bytes ran out first.
    Paused,
    End,
}

/// What one step of [`LogReader`] may read at most.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepLimits {
    /// Lines, counted when complete.
    pub lines: usize,
    /// Bytes of text (after decompression); the line that crosses it is
    /// finished (unless the input runs out first).
    pub text_bytes: u64,
    /// For a gzip file, the compressed bytes taken from the caller's
    /// reader since the start of the file, in all: not a count for this
    /// step, the mark it may read up to. (A plain file's text is its input,
    /// bounded by `text_bytes`.)
    pub gzip_up_to: u64,
}

impl StepLimits {
    const NONE: Self = Self {
        lines: usize::MAX,
        text_bytes: u64::MAX,
        gzip_up_to: u64::MAX,
    };
}

/// A streaming reader of a CARMEN log (gzip or plain, detected from the
/// first bytes): an iterator over its laser records, which
/// [`super::LogLoader`] keeps in [`crate::sensors::ScanLog`]. It stops at the
/// first error, which names the line: the iterator yields it once and ends,
/// and [`LogReader::next_record`] keeps returning it (a reader that failed
/// never reports a clean end over a half-read log). A log cut short ends
/// cleanly with a [`Self::warning`].
pub struct LogReader<R: Read> {
    source: Source<R>,
    line: Vec<u8>,
    /// `line` holds the start of a line a pause cut: the next step goes on
    /// with it.
    resuming: bool,
    lines: usize,
    /// Bytes of text (after decompression) read so far.
    text_bytes: u64,
    /// Laser records returned so far.
    records: usize,
    bytes_at_close: u64,
    pub(super) failure: Option<OccError>,
    /// How a log cut short ended, when it was.
    cut: Option<String>,
    /// Laser lines not read, by message ([`SKIPPED_LASER_MESSAGES`]).
    skipped: [usize; SKIPPED_LASER_MESSAGES.len()],
    /// The first laser line not read.
    first_skipped: Option<usize>,
    stamps: StampOrder,
    /// Everything worth saying about the read, once it has ended.
    warning: Option<String>,
}

/// How often a read laser line's stamp lies before the previous one's.
#[derive(Debug, Default)]
struct StampOrder {
    previous: Option<f64>,
    steps: usize,
    backwards: usize,
    first_backwards: Option<usize>,
    /// The longest step back, seconds.
    longest_back: f64,
}

/// A step back of more than this, in seconds, is no logger's jitter: the
/// public corpus's stamps step back four times in the Intel log, by at most
/// 0.86 s (messages logged slightly out of order), never by more.
const STAMP_JITTER_SECONDS: f64 = 2.0;

/// Steps back in more than one step in this many are no jitter either
/// (the public corpus: at most 4 in 910).
const STAMP_JITTER_STEPS: usize = 100;

impl StampOrder {
    fn record(&mut self, line: usize, stamp: Option<f64>) {
        let Some(stamp) = stamp else { return };
        if let Some(previous) = self.previous {
            self.steps += 1;
            if stamp < previous {
                self.backwards += 1;
                self.first_backwards.get_or_insert(line);
                self.longest_back = self.longest_back.max(previous - stamp);
            }
        }
        self.previous = Some(stamp);
    }

    /// A sentence when the stamps run backwards beyond a logger's jitter.
    fn warning(&self) -> Option<String> {
        let line = self.first_backwards?;
        let jitter = self.longest_back <= STAMP_JITTER_SECONDS
            && self.backwards * STAMP_JITTER_STEPS <= self.steps;
        if jitter {
            return None;
        }
        let n = self.backwards;
        Some(format!(
            "The scans' stamps run backwards {n} time{} (the first on line {line}): \
             the scans are mapped in file order",
            if n == 1 { "" } else { "s" },
        ))
    }
}

impl<R: Read> LogReader<R> {
    /// A reader over `reader` (any `Read`, so any `BufRead` too). Nothing is
    /// read until the first record is asked for.
    pub fn new(reader: R) -> Self {
        Self {
            source: Source::Unopened(reader),
            line: Vec::new(),
            resuming: false,
            lines: 0,
            text_bytes: 0,
            records: 0,
            bytes_at_close: 0,
            failure: None,
            cut: None,
            skipped: [0; SKIPPED_LASER_MESSAGES.len()],
            first_skipped: None,
            stamps: StampOrder::default(),
            warning: None,
        }
    }

    /// What the reader has to say once the read has ended, in sentences
    /// joined by ". " (no final stop), each bounded whatever the log's
    /// length: how the read ended early when the log was cut short ("line
    /// 5103: the file ends inside this FLASER line (...); the 1519 complete
    /// scans before it are kept"), the laser lines not read, by message
    /// ("66 RLASER lines were not read (the first on line 4): only FLASER
    /// and ROBOTLASER1 lines are mapped"), and stamps that run backwards
    /// beyond a logger's jitter. `None` until the read ends.
    pub fn warning(&self) -> Option<&str> {
        self.warning.as_deref()
    }

    /// Bytes of text read so far (after decompression).
    pub fn text_bytes(&self) -> u64 {
        self.text_bytes
    }

    /// Lines read so far, laser or not.
    pub fn lines_read(&self) -> usize {
        self.lines
    }

    /// Bytes taken from the underlying reader so far (compressed bytes for
    /// a gzip file, never past a step's limit of compressed bytes; read
    /// ahead of the text by up to one buffer).
    pub fn bytes_read(&self) -> u64 {
        self.source.bytes_read().unwrap_or(self.bytes_at_close)
    }

    /// True once the file is known to be gzip (from its first read on).
    pub fn is_gzip(&self) -> bool {
        self.source.is_gzip()
    }

    /// True once the end of the file or an error has been reached.
    pub fn is_finished(&self) -> bool {
        matches!(self.source, Source::Closed)
    }

    /// Ends the read cleanly at a cut on line `line` (an error when there is
    /// no complete scan before it to keep).
    fn cut_short(&mut self, line: usize, what: String) -> Result<Step> {
        let n = self.records;
        if n == 0 {
            return self.fail(line, what);
        }
        self.cut = Some(format!(
            "line {line}: {what}; the {n} complete scan{} before it {} kept",
            if n == 1 { "" } else { "s" },
            if n == 1 { "is" } else { "are" },
        ));
        self.close();
        Ok(Step::End)
    }

    pub(super) fn close(&mut self) {
        self.bytes_at_close = self.bytes_read();
        self.source = Source::Closed;
        let sentences: Vec<String> = [
            self.cut.clone(),
            self.skipped_warning(),
            self.stamps.warning(),
        ]
        .into_iter()
        .flatten()
        .collect();
        self.warning = (!sentences.is_empty()).then(|| sentences.join(". "));
    }

    /// A sentence naming the laser lines not read, by message.
    fn skipped_warning(&self) -> Option<String> {
        let first = self.first_skipped?;
        let counts: Vec<String> = SKIPPED_LASER_MESSAGES
            .iter()
            .zip(self.skipped)
            .filter(|&(_, n)| n > 0)
            .map(|(name, n)| format!("{n} {name}"))
            .collect();
        let total: usize = self.skipped.iter().sum();
        let lines = if total == 1 { "line was" } else { "lines were" };
        let counts = match counts.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
            None => return None,
        };
        Some(format!(
            "{counts} {lines} not read (the first on line {first}): \
             only FLASER and ROBOTLASER1 lines are mapped"
        ))
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
        match self.step(StepLimits::NONE)? {
            Step::Record(r) => Ok(Some(r)),
            Step::End => Ok(None),
            Step::Paused => unreachable!("an unbounded step does not pause"),
        }
    }

    /// Reads lines until a laser record, the end, or a limit.
    pub(super) fn step(&mut self, limits: StepLimits) -> Result<Step> {
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
        if self.source.is_gzip() {
            self.source.set_input_limit(limits.gzip_up_to);
        }
        loop {
            if !self.resuming
                && (self.lines - lines0 >= limits.lines
                    || self.text_bytes - bytes0 >= limits.text_bytes)
            {
                return Ok(Step::Paused);
            }
            let gzip = self.source.is_gzip();
            let Some(src) = self.source.text() else {
                return Ok(Step::End);
            };
            if !self.resuming {
                self.line.clear();
            }
            self.resuming = false;
            match read_line(src, &mut self.line, MAX_LINE_BYTES) {
                Ok(LineEnd::Eof) => {
                    self.close();
                    return Ok(Step::End);
                }
                Ok(LineEnd::Paused) => {
                    self.resuming = true;
                    return Ok(Step::Paused);
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
            return match laser_line(number, &self.line) {
                Ok(LogLine::Other) => continue,
                Ok(LogLine::SkippedLaser(message)) => {
                    self.skipped[message] += 1;
                    self.first_skipped.get_or_insert(number);
                    continue;
                }
                Ok(LogLine::Laser(record)) => {
                    self.records += 1;
                    self.stamps.record(number, record.timestamp);
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

#[cfg(test)]
mod tests {
    use super::super::{read_scans, LogLoader};
    use super::*;

    const FLASER3: &str = "FLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

    #[test]
    fn a_line_longer_than_the_limit_is_an_error_not_a_buffer() {
        let mut text = b"ODOM 1 2 3\nCOMMENT ".to_vec();
        text.resize(text.len() + MAX_LINE_BYTES + 10, b'x');
        let e = read_scans(&text[..]).unwrap_err();
        assert!(
            matches!(&e, OccError::Parse { line: 2, reason } if reason.contains("longer")),
            "{e}"
        );
        // Exactly at the limit (newline included) is still a line.
        let mut ok = b"C".to_vec();
        ok.resize(MAX_LINE_BYTES - 1, b'X');
        ok.push(b'\n');
        let (_, progress) = LogLoader::new(&ok[..]).read_to_end().unwrap();
        assert_eq!(progress.records, 1);
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
}
