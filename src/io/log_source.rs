//! Every log format behind one reader interface, [`LogSource`]: a reader
//! takes a file's bytes a bounded step at a time and keeps its scans in
//! the format-neutral [`ScanLog`], so that the sessions above never see a
//! file format. [`super::open_log`] picks the reader from the file's first
//! bytes ([`LogFormat::sniff`]); a second format is one more room beside
//! `carmen/`, one more variant of [`LogFormat`] and one more arm of the
//! sniffer and of `open_log`.

use crate::error::{OccError, Result};
use crate::poses::PoseSourceKind;
use crate::sensors::ScanLog;

/// What a log may cost, checked as it is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogBudget {
    /// Bytes the kept scans ([`ScanLog`]) may take.
    pub kept_bytes: usize,
    /// Records (a text log's lines) one read call reads at most.
    pub records_per_read: usize,
    /// Bytes of (decompressed) data one read call reads at most (the
    /// record that crosses it is finished).
    pub bytes_per_read: u64,
    /// Bytes of a compressed file, as given, one read call takes at most,
    /// never past, even inside a record or a header: compressed data,
    /// headers, names, comments, empty members and padding alike. The
    /// decompressed data alone does not bound a call's work: 40 MB of
    /// empty gzip members inflate to nothing at all. (A plain file's bytes
    /// are its data, bounded by [`Self::bytes_per_read`].)
    pub compressed_bytes_per_read: u64,
}

/// The default [`LogBudget::kept_bytes`]: 256 MiB.
pub const MAX_KEPT_BYTES: usize = 256 << 20;

impl Default for LogBudget {
    fn default() -> Self {
        Self {
            kept_bytes: MAX_KEPT_BYTES,
            records_per_read: 1 << 16,
            bytes_per_read: 1 << 20,
            // The costliest input per byte is a deflate stream of blocks
            // that hold nothing: each one rebuilds its Huffman tables, some
            // 13,000 of them in 16 kB, tens of milliseconds. A real log's
            // 16 kB inflate to some 80 kB of text: a few milliseconds.
            compressed_bytes_per_read: 16 << 10,
        }
    }
}

impl LogBudget {
    /// The budget with every per-call bound at least 1, so that every call
    /// moves on.
    pub fn at_least_one(self) -> Self {
        Self {
            records_per_read: self.records_per_read.max(1),
            bytes_per_read: self.bytes_per_read.max(1),
            compressed_bytes_per_read: self.compressed_bytes_per_read.max(1),
            ..self
        }
    }
}

/// How far a read has got.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct LoadProgress {
    /// Records of the file read (a text log's lines, including those that
    /// hold no scan).
    pub records: usize,
    /// What the format calls a record, plural (`"lines"`), for a page to
    /// say.
    pub record_name: &'static str,
    pub scans: usize,
    pub beams: usize,
    /// Bytes taken from the (possibly compressed) input.
    pub bytes_read: u64,
    pub finished: bool,
    /// What a finished read has to say about a log it still maps, in
    /// short sentences joined by ". " (without a final stop), or `None`:
    /// how a log cut short ended, naming where, and what the format's
    /// reader passed over or found out of order (for CARMEN, the module
    /// doc of [`super::carmen`]). Bounded whatever the log's length.
    pub warning: Option<String>,
}

/// The log formats the core reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum LogFormat {
    /// A CARMEN text log, plain or gzip ([`super::carmen`]).
    #[serde(rename = "carmen")]
    Carmen,
    /// A ROS 2 bag, MCAP with CDR messages ([`super::ros2`]).
    #[serde(rename = "mcap")]
    Mcap,
}

impl LogFormat {
    /// The format of a file that starts with `head` (its first bytes, at
    /// least 8 where the file has them). A file of no known format is
    /// handed to the text reader, whose refusal of foreign bytes names
    /// them in words.
    pub fn sniff(head: &[u8]) -> Result<Self> {
        if head.starts_with(MCAP_MAGIC) {
            return Ok(Self::Mcap);
        }
        Ok(Self::Carmen)
    }
}

impl LogFormat {
    /// The poses a log of this format is mapped at when the reader names
    /// none, before it is read: a CARMEN log's corrected poses, a bag's
    /// own odometry (a bag carries corrected poses only with a `map →
    /// odom` transform, which its read finds: then
    /// [`PoseSourceKind::own_of`] the read log; docs/ARCHITECTURE.md,
    /// "Pose sources and log formats").
    pub fn own_poses(self) -> PoseSourceKind {
        match self {
            Self::Carmen => PoseSourceKind::Corrected,
            Self::Mcap => PoseSourceKind::Odometry,
        }
    }
}

/// One topic of a log that has topics (a ROS 2 bag): its name, message
/// type and message count.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct LogTopic {
    pub topic: String,
    #[serde(rename = "type")]
    pub type_name: String,
    pub messages: u64,
}

/// The topics a read was refused for want of a choice between (a bag with
/// several LaserScan or Odometry topics and none named): every topic of
/// each kind, for a page to offer.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TopicChoices {
    /// The LaserScan topics, one of which is mapped.
    pub scan_topics: Vec<LogTopic>,
    /// The Odometry topics, one of which places the scans.
    pub odom_topics: Vec<LogTopic>,
}

/// The first bytes of an MCAP file (a ROS 2 bag); the rest of its magic
/// is checked by its reader, which names a mismatch.
const MCAP_MAGIC: &[u8] = b"\x89MCAP";

/// A log being read into a [`ScanLog`], a bounded step at a time, so that
/// a page can show progress and stay responsive whatever the file holds.
pub trait LogSource {
    /// The file's format.
    fn format(&self) -> LogFormat;
    /// Reads up to `max_scans` more scans (at least one call's worth of
    /// progress when `max_scans` is 0) within the budget's bounds per
    /// call. On an error (a malformed record, a log past the budget) the
    /// scans kept so far are freed: the log is refused whole, and every
    /// later call gives the same error.
    fn read(&mut self, max_scans: usize) -> Result<LoadProgress>;
    fn progress(&self) -> LoadProgress;
    /// The scans read so far.
    fn scans(&self) -> &ScanLog;
    /// Passes over scans so far: each scan counts once when it is decoded
    /// and once more for each later pass over it (a bag decodes its scans
    /// while it reads every message, and places them at the odometry once
    /// all are read), so that a read call's work is counted in scans while
    /// none is kept yet, and a page sizes the next call by it.
    fn scan_steps(&self) -> usize {
        self.scans().len()
    }
    /// The scans read, the reader dropped.
    fn into_scans(self: Box<Self>) -> ScanLog;
    /// Why a file read to its end without a scan cannot be mapped, in the
    /// format's words.
    fn no_scans(&self) -> OccError;
    /// Names the topics to map, before the first read, for a format that
    /// has topics (a ROS 2 bag: its LaserScan and its Odometry topic);
    /// `None` leaves the reader to take the only one. A format without
    /// topics refuses a name.
    fn choose_topics(
        &mut self,
        scan_topic: Option<String>,
        odom_topic: Option<String>,
    ) -> Result<()> {
        match scan_topic.or(odom_topic) {
            None => Ok(()),
            Some(t) => Err(OccError::State(format!(
                "topic {} chosen, but the file is not a ROS 2 bag: it has no topics",
                super::mcap::quoted(&t)
            ))),
        }
    }
    /// After a refused read, the topics it wanted a choice between (the
    /// read named no topic of a kind the file holds several of, or one it
    /// does not hold), or `None`: a format without topics never wants one.
    fn topic_choices(&self) -> Option<TopicChoices> {
        None
    }
}
