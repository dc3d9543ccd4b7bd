//! The one way a log is read into scans: [`LogLoader`] runs the
//! [`LogReader`] a bounded step at a time and keeps what it finds in
//! [`LaserScans`], so that the page can show progress and stay responsive
//! whatever the file holds. [`LaserScans::read`] and
//! [`LogLoader::read_to_end`] run it to the end in the same steps.

use super::lines::{LogReader, Step, StepLimits};
use super::scans::LaserScans;
use crate::error::Result;
use std::io::Read;

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
    /// Bytes of a gzip file, as given, one [`LogLoader::read`] call takes
    /// at most, never past, even inside a line or a header: compressed
    /// data, member headers, names, comments, empty members and padding
    /// alike. The text alone does not bound a call's work: 40 MB of empty
    /// gzip members inflate to no text at all. (A plain file's bytes are
    /// its text, bounded by [`Self::bytes_per_read`].)
    pub gzip_bytes_per_read: u64,
}

/// The default [`LogBudget::kept_bytes`]: 256 MiB.
pub const MAX_KEPT_BYTES: usize = 256 << 20;

impl Default for LogBudget {
    fn default() -> Self {
        Self {
            kept_bytes: MAX_KEPT_BYTES,
            lines_per_read: 1 << 16,
            bytes_per_read: 1 << 20,
            // The costliest input per byte is a deflate stream of blocks
            // that hold nothing: each one rebuilds its Huffman tables, some
            // 13,000 of them in 16 kB, tens of milliseconds. A real log's
            // 16 kB inflate to some 80 kB of text: a few milliseconds.
            gzip_bytes_per_read: 16 << 10,
        }
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
    /// Bytes taken from the (possibly compressed) input.
    pub bytes_read: u64,
    pub finished: bool,
    /// How a log cut short ended ([`LogReader::warning`]), or `None`.
    pub warning: Option<String>,
}

impl<R: Read> LogLoader<R> {
    pub fn new(reader: R) -> Self {
        Self::with_budget(reader, LogBudget::default())
    }

    /// A loader with its own budget (a test's smaller one). A per-call
    /// bound of 0 reads as 1, so that every call moves on.
    pub fn with_budget(reader: R, budget: LogBudget) -> Self {
        Self {
            reader: LogReader::new(reader),
            scans: LaserScans::new(),
            budget: LogBudget {
                lines_per_read: budget.lines_per_read.max(1),
                bytes_per_read: budget.bytes_per_read.max(1),
                gzip_bytes_per_read: budget.gzip_bytes_per_read.max(1),
                ..budget
            },
        }
    }

    /// Reads up to `max_scans` more laser records (at least one call's worth
    /// of progress even when `max_scans` is 0), and at most the budget's
    /// lines, bytes of text and compressed bytes per call ([`LogBudget`]).
    /// On an error (a malformed line, a log past the budget) the scans kept
    /// so far are freed: the log is refused whole, and the reader keeps
    /// returning the error.
    pub fn read(&mut self, max_scans: usize) -> Result<LoadProgress> {
        let lines0 = self.reader.lines_read();
        let text0 = self.reader.text_bytes();
        let gzip_up_to = self
            .reader
            .bytes_read()
            .saturating_add(self.budget.gzip_bytes_per_read);
        for _ in 0..max_scans.max(1) {
            let limits = StepLimits {
                lines: self
                    .budget
                    .lines_per_read
                    .saturating_sub(self.reader.lines_read() - lines0),
                text_bytes: self
                    .budget
                    .bytes_per_read
                    .saturating_sub(self.reader.text_bytes() - text0),
                gzip_up_to,
            };
            let gzip_spent = self.reader.is_gzip() && self.reader.bytes_read() >= gzip_up_to;
            if limits.lines == 0 || limits.text_bytes == 0 || gzip_spent {
                break;
            }
            let pushed = match self.reader.step(limits) {
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

    /// Reads to the end, in the same bounded calls as [`Self::read`]: the
    /// scans and the last progress (lines read, a cut short's warning).
    pub fn read_to_end(mut self) -> Result<(LaserScans, LoadProgress)> {
        loop {
            let progress = self.read(usize::MAX)?;
            if progress.finished {
                return Ok((self.scans, progress));
            }
        }
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

    /// The scans read so far, kept by the loader.
    pub fn scans(&self) -> &LaserScans {
        &self.scans
    }

    /// The scans read so far.
    pub fn into_scans(self) -> LaserScans {
        self.scans
    }
}
