//! The one way a CARMEN log is read into scans: [`LogLoader`] runs the
//! [`LogReader`] a bounded step at a time and keeps what it finds in a
//! [`ScanLog`], so that the page can show progress and stay responsive
//! whatever the file holds; it is the CARMEN format's [`LogSource`].
//! [`super::read_scans`] and [`LogLoader::read_to_end`] run it to the end
//! in the same steps.

use super::lines::{LogReader, Step, StepLimits};
use super::parse::LaserRecord;
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::io::log_source::{LoadProgress, LogBudget, LogFormat, LogSource};
use crate::sensors::{LogPoseKinds, ScanLog, ScanRecord};
use std::io::Read;

/// What a CARMEN file calls the records [`ScanRecord::origin`] counts.
const UNIT: &str = "line";

/// Reads a CARMEN log into a [`ScanLog`] a few records at a time, so that
/// a page can show progress and stay responsive on a long log.
pub struct LogLoader<R: Read> {
    reader: LogReader<R>,
    scans: ScanLog,
    budget: LogBudget,
}

/// A laser line as the format-neutral store takes it. A FLASER line's
/// laser pose is its robot's (CARMEN's convention: the mount is the
/// identity), and its odometry fields give the laser's odometry pose; a
/// ROBOTLASER1 line gives the laser pose itself, and no odometry.
fn scan_record(record: &LaserRecord) -> ScanRecord<'_> {
    ScanRecord {
        origin: record.line,
        stamp: record.timestamp,
        pose: record.pose,
        odometry: record.odometry,
        ranges: &record.ranges,
        first_bearing: record.first_bearing,
        bearing_step: record.bearing_step,
        max_range: record.max_range,
    }
}

/// What a read CARMEN log's poses are: its laser poses are reference
/// poses (the public logs' corrected paths); its odometry is its own when
/// the odometry fields differ from them (a corrected log's copy its
/// corrected poses, and ROBOTLASER1 lines carry none).
fn pose_kinds(scans: &ScanLog) -> LogPoseKinds {
    LogPoseKinds {
        reference: true,
        odometry: scans.kept_odometry() != scans.poses(),
    }
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
            scans: ScanLog::new(UNIT),
            budget: budget.at_least_one(),
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
            .saturating_add(self.budget.compressed_bytes_per_read);
        for _ in 0..max_scans.max(1) {
            let limits = StepLimits {
                lines: self
                    .budget
                    .records_per_read
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
                Ok(Step::Record(record)) => self
                    .scans
                    .push(&scan_record(&record), self.budget.kept_bytes)
                    .map_err(|reason| OccError::Parse {
                        line: record.line,
                        reason,
                    }),
                Ok(Step::Paused | Step::End) => break,
                Err(e) => Err(e),
            };
            if let Err(e) = pushed {
                if self.reader.failure.is_none() {
                    self.reader.close();
                    self.reader.failure = Some(e.clone());
                }
                self.scans = ScanLog::new(UNIT);
                return Err(e);
            }
        }
        if self.reader.is_finished() {
            let kinds = pose_kinds(&self.scans);
            self.scans.set_pose_kinds(kinds);
            self.scans.set_mount(Pose::default());
        }
        Ok(self.progress())
    }

    /// Reads to the end, in the same bounded calls as [`Self::read`]: the
    /// scans and the last progress (lines read, a cut short's warning).
    pub fn read_to_end(mut self) -> Result<(ScanLog, LoadProgress)> {
        loop {
            let progress = self.read(usize::MAX)?;
            if progress.finished {
                return Ok((self.scans, progress));
            }
        }
    }

    pub fn progress(&self) -> LoadProgress {
        LoadProgress {
            records: self.reader.lines_read(),
            record_name: "lines",
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
    pub fn scans(&self) -> &ScanLog {
        &self.scans
    }

    /// The scans read so far.
    pub fn into_scans(self) -> ScanLog {
        self.scans
    }
}

impl<R: Read> LogSource for LogLoader<R> {
    fn format(&self) -> LogFormat {
        LogFormat::Carmen
    }

    fn read(&mut self, max_scans: usize) -> Result<LoadProgress> {
        LogLoader::read(self, max_scans)
    }

    fn progress(&self) -> LoadProgress {
        LogLoader::progress(self)
    }

    fn scans(&self) -> &ScanLog {
        &self.scans
    }

    fn into_scans(self: Box<Self>) -> ScanLog {
        self.scans
    }

    fn no_scans(&self) -> OccError {
        let lines = match self.reader.lines_read() {
            1 => "1 line read".to_string(),
            n => format!("{n} lines read"),
        };
        OccError::State(format!(
            "the file has no FLASER or ROBOTLASER1 lines ({lines}): no laser scans to map"
        ))
    }
}
