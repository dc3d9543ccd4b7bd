//! [`McapReader`]: an MCAP file's records in file order, a bounded step at
//! a time, the records of each chunk inflated and read in place.

use super::chunk::{crc_mismatch, Inflating, CRC32};
use super::records::{
    self, channel_message_counts, malformed, record_name, Channel, Fields, MessageHead, Place,
    Schema, RECORD_HEAD,
};
use crate::error::{OccError, Result};
use crc::Digest;
use std::sync::Arc;

/// The magic bytes an MCAP file (major version 0) starts and ends with.
pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Bytes of a Footer record: its head and three fields.
const FOOTER_BYTES: usize = RECORD_HEAD + 8 + 8 + 4;

/// The largest summary section read: 16 MiB. A summary lists schemas,
/// channels, statistics and one index entry per chunk, some kilobytes for
/// an hour of recording; a larger one is passed over (it is never needed).
const MAX_SUMMARY_BYTES: usize = 16 << 20;

/// What the next step of a read found.
#[derive(Debug)]
pub enum Event<'a> {
    Schema(Schema),
    Channel(Channel),
    Message {
        head: MessageHead,
        data: &'a [u8],
        place: Place,
    },
    /// The step's bytes are spent: call again.
    Paused,
    /// The end of the data (or of what a file cut short holds).
    End,
}

/// What the summary section says, when the file has one.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Summary {
    pub schemas: Vec<Schema>,
    pub channels: Vec<Channel>,
    /// Messages per channel id (the Statistics record's), when stated.
    pub counts: Option<Vec<(u16, u64)>>,
}

/// A chunk's records: being inflated, or read one by one.
enum ChunkState {
    Inflating(Inflating),
    Records {
        chunk: u64,
        out: Vec<u8>,
        at: usize,
        cut: bool,
    },
}

/// An MCAP file read record by record.
pub struct McapReader {
    bytes: Arc<Vec<u8>>,
    /// The next top-level record.
    at: usize,
    /// Where the data section's records end at the latest: the summary or
    /// the footer of a whole file, the file's end for one cut short.
    data_end: usize,
    /// True when the file ends with a footer and the magic bytes.
    whole: bool,
    chunk: Option<ChunkState>,
    data_crc: Digest<'static, u32>,
    summary: Option<Summary>,
    started: bool,
    finished: bool,
    records: usize,
    warning: Option<String>,
}

fn le_u64(b: &[u8]) -> u64 {
    u64::from_le_bytes(b[..8].try_into().unwrap_or([0; 8]))
}

impl McapReader {
    /// A reader of `bytes` (checked on the first [`Self::next`]).
    pub fn new(bytes: Vec<u8>) -> Self {
        let len = bytes.len();
        Self {
            bytes: Arc::new(bytes),
            at: 0,
            data_end: len,
            whole: false,
            chunk: None,
            data_crc: CRC32.digest(),
            summary: None,
            started: false,
            finished: false,
            records: 0,
            warning: None,
        }
    }

    /// Bytes of the file read so far (a chunk counts once it is started).
    pub fn bytes_read(&self) -> u64 {
        if self.finished {
            self.bytes.len() as u64
        } else {
            self.at as u64
        }
    }

    /// Records read so far, in chunks and out of them.
    pub fn records(&self) -> usize {
        self.records
    }

    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// How a file cut short ends, once read to the cut.
    pub fn warning(&self) -> Option<&str> {
        self.warning.as_deref()
    }

    /// The summary section, once the first step has read it (`None` when
    /// the file has none, or is cut short).
    pub fn summary(&self) -> Option<&Summary> {
        self.summary.as_ref()
    }

    /// Checks the magic bytes and reads the footer and summary of a whole
    /// file, once (the first [`Self::next`] does it too).
    pub fn open(&mut self) -> Result<()> {
        if !self.started {
            self.started = true;
            self.start()?;
        }
        Ok(())
    }

    /// Checks the magic bytes and the header, and reads the footer and the
    /// summary of a whole file.
    fn start(&mut self) -> Result<()> {
        let b = &self.bytes;
        let len = b.len();
        if len < MAGIC.len() || &b[..MAGIC.len()] != MAGIC {
            let n = len.min(8);
            let hex: Vec<String> = b[..n].iter().map(|x| format!("{x:02x}")).collect();
            return Err(OccError::State(format!(
                "the file does not start with MCAP's magic bytes (0x89 \"MCAP0\" CR LF): its first {n} bytes are {}",
                hex.join(" ")
            )));
        }
        self.at = MAGIC.len();
        // The data section's CRC covers the leading magic bytes too.
        self.data_crc.update(MAGIC);
        self.whole = len >= 2 * MAGIC.len() + FOOTER_BYTES && &b[len - MAGIC.len()..] == MAGIC;
        if self.whole {
            self.read_footer()?;
        }
        Ok(())
    }

    fn read_footer(&mut self) -> Result<()> {
        let b = Arc::clone(&self.bytes);
        let footer = b.len() - MAGIC.len() - FOOTER_BYTES;
        let place = Place::File(footer as u64);
        if b[footer] != records::FOOTER || le_u64(&b[footer + 1..]) != 20 {
            return Err(malformed(
                records::FOOTER,
                place,
                "the file ends with MCAP's magic bytes, but no 20-byte Footer record before them",
            ));
        }
        let summary_start = le_u64(&b[footer + 9..]);
        let offsets_start = le_u64(&b[footer + 17..]);
        let crc = u32::from_le_bytes(b[footer + 25..footer + 29].try_into().unwrap_or([0; 4]));
        self.data_end = footer;
        if summary_start == 0 {
            return Ok(());
        }
        let in_file = |v: u64| v >= MAGIC.len() as u64 && v <= footer as u64;
        if !in_file(summary_start) || (offsets_start != 0 && !in_file(offsets_start)) {
            return Err(malformed(
                records::FOOTER,
                place,
                format_args!(
                    "summary_start {summary_start} or summary_offset_start {offsets_start} lies outside the file's {} bytes before the footer",
                    footer
                ),
            ));
        }
        let start = summary_start as usize;
        if footer - start > MAX_SUMMARY_BYTES {
            // Never needed, and too large to check in one step: the data
            // are read up to the footer instead.
            return Ok(());
        }
        if crc != 0 {
            let found = CRC32.checksum(&b[start..footer + 25]);
            if found != crc {
                return Err(crc_mismatch("Footer", place, crc, found));
            }
        }
        self.data_end = start;
        let end = if offsets_start != 0 && offsets_start >= summary_start {
            offsets_start as usize
        } else {
            footer
        };
        self.summary = Some(Self::read_summary(&b[start..end], start)?);
        Ok(())
    }

    fn read_summary(b: &[u8], base: usize) -> Result<Summary> {
        let mut summary = Summary::default();
        let mut at = 0;
        while at < b.len() {
            let place = Place::File((base + at) as u64);
            let (op, body) = Self::record(b, at).ok_or_else(|| {
                malformed(
                    b[at],
                    place,
                    "its length runs past the summary section's end",
                )
            })?;
            let mut f = Fields::new(op, place, body);
            match op {
                records::SCHEMA => summary.schemas.push(Schema::parse(&mut f)?),
                records::CHANNEL => summary.channels.push(Channel::parse(&mut f)?),
                records::STATISTICS => summary.counts = Some(channel_message_counts(&mut f)?),
                // A summary holds schemas, channels, statistics and
                // indexes: a footer whose summary_start points at data lies.
                records::HEADER
                | records::MESSAGE
                | records::CHUNK
                | records::DATA_END
                | records::FOOTER => {
                    return Err(malformed(
                        op,
                        place,
                        "the footer's summary_start points at it, but no summary section holds one",
                    ))
                }
                _ => {}
            }
            at += RECORD_HEAD + body.len();
        }
        Ok(summary)
    }

    /// The record at `b[at..]`: its opcode and body, `None` when its head
    /// or its body runs past `b`'s end.
    fn record(b: &[u8], at: usize) -> Option<(u8, &[u8])> {
        if b.len() - at < RECORD_HEAD {
            return None;
        }
        let len = le_u64(&b[at + 1..]);
        if len > (b.len() - at - RECORD_HEAD) as u64 {
            return None;
        }
        Some((b[at], &b[at + RECORD_HEAD..at + RECORD_HEAD + len as usize]))
    }

    /// Ends the read at a cut: the file's last bytes are inside `what`.
    fn cut(&mut self, what: String) -> Event<'static> {
        self.finished = true;
        self.warning = Some(format!(
            "the bag is cut short: it ends at byte {} inside {what}; the messages before it are read",
            self.bytes.len()
        ));
        Event::End
    }

    /// The next schema, channel or message, having inflated or passed over
    /// at most `bytes` more bytes (a record that crosses it is finished,
    /// and a chunk is inflated a step of `bytes` at a time); `most_chunk`
    /// the largest chunk the caller's budget allows.
    pub fn next(&mut self, bytes: &mut u64, most_chunk: u64) -> Result<Event<'_>> {
        if self.finished {
            return Ok(Event::End);
        }
        self.open()?;
        loop {
            if *bytes == 0 {
                return Ok(Event::Paused);
            }
            match self.chunk.take() {
                Some(ChunkState::Inflating(mut inflating)) => {
                    let before = inflating.out.len();
                    let done = inflating.step(usize::try_from(*bytes).unwrap_or(usize::MAX))?;
                    *bytes = bytes.saturating_sub((inflating.out.len() - before).max(1) as u64);
                    self.chunk = Some(if done {
                        ChunkState::Records {
                            chunk: inflating.chunk,
                            cut: inflating.cut,
                            out: std::mem::take(&mut inflating.out),
                            at: 0,
                        }
                    } else {
                        ChunkState::Inflating(inflating)
                    });
                }
                Some(ChunkState::Records {
                    chunk,
                    out,
                    at,
                    cut,
                }) => {
                    if at >= out.len() {
                        if cut {
                            return Ok(self.cut(format!("the Chunk at byte {chunk}")));
                        }
                        continue;
                    }
                    let place = Place::InChunk {
                        chunk,
                        at: at as u64,
                    };
                    let Some((op, body)) = Self::record(&out, at) else {
                        if cut {
                            return Ok(self.cut(format!("the Chunk at byte {chunk}")));
                        }
                        return Err(malformed(
                            out[at],
                            place,
                            format_args!(
                                "its length runs past the end of the chunk's {} bytes of records",
                                out.len()
                            ),
                        ));
                    };
                    let next = at + RECORD_HEAD + body.len();
                    *bytes = bytes.saturating_sub((next - at) as u64);
                    self.records += 1;
                    self.chunk = Some(ChunkState::Records {
                        chunk,
                        out,
                        at: next,
                        cut,
                    });
                    if matches!(op, records::SCHEMA | records::CHANNEL | records::MESSAGE) {
                        let Some(ChunkState::Records { out, .. }) = &self.chunk else {
                            unreachable!("the chunk was just put back")
                        };
                        let body = &out[at + RECORD_HEAD..next];
                        return Self::event(op, place, body);
                    }
                }
                None => {
                    if let Some(event) = self.top_level(bytes, most_chunk)? {
                        return Ok(match event {
                            TopLevel::End => Event::End,
                            TopLevel::Record(op, at, next) => {
                                let place = Place::File(at as u64);
                                let body = &self.bytes[at + RECORD_HEAD..next];
                                return Self::event(op, place, body);
                            }
                        });
                    }
                }
            }
        }
    }

    /// A schema, channel or message record as an event.
    fn event(op: u8, place: Place, body: &[u8]) -> Result<Event<'_>> {
        let mut f = Fields::new(op, place, body);
        Ok(match op {
            records::SCHEMA => Event::Schema(Schema::parse(&mut f)?),
            records::CHANNEL => Event::Channel(Channel::parse(&mut f)?),
            _ => {
                let (head, data) = MessageHead::parse(&mut f)?;
                Event::Message { head, data, place }
            }
        })
    }

    /// Reads the next top-level record: an event to hand over, the end,
    /// or `None` when it was passed over or started a chunk.
    fn top_level(&mut self, bytes: &mut u64, most_chunk: u64) -> Result<Option<TopLevel>> {
        let at = self.at;
        let b = Arc::clone(&self.bytes);
        let place = Place::File(at as u64);
        if at >= self.data_end && (self.whole || at > MAGIC.len()) {
            // The data read to its end (a file of the magic bytes alone
            // is cut short, below).
            self.finished = true;
            return Ok(Some(TopLevel::End));
        }
        let end = self.data_end;
        if end - at < RECORD_HEAD {
            if self.whole {
                return Err(malformed(
                    b[at],
                    place,
                    format_args!("its head runs past the data section's end at byte {end}"),
                ));
            }
            self.at = end;
            return Ok(self.cut_top(at, b.get(at).copied()));
        }
        let op = b[at];
        let len = le_u64(&b[at + 1..]);
        let room = (end - at - RECORD_HEAD) as u64;
        if len > room {
            if self.whole {
                return Err(malformed(
                    op,
                    place,
                    format_args!(
                        "its length {len} runs past the data section's end at byte {end} ({room} bytes left)"
                    ),
                ));
            }
            if op == records::CHUNK {
                return self
                    .start_chunk(at, &b[at + RECORD_HEAD..end], most_chunk, true)
                    .map(|_| None);
            }
            self.at = end;
            return Ok(self.cut_top(at, Some(op)));
        }
        let next = at + RECORD_HEAD + len as usize;
        if at == MAGIC.len() && op != records::HEADER {
            return Err(malformed(
                op,
                place,
                "the first record of an MCAP file must be its Header",
            ));
        }
        self.records += 1;
        *bytes = bytes.saturating_sub(next as u64 - at as u64);
        match op {
            records::DATA_END => {
                let mut f = Fields::new(op, place, &b[at + RECORD_HEAD..next]);
                let stated = f.u32("data_section_crc")?;
                let digest = std::mem::replace(&mut self.data_crc, CRC32.digest());
                let found = digest.finalize();
                if stated != 0 && found != stated {
                    return Err(crc_mismatch("Data End", place, stated, found));
                }
                self.at = next;
                self.finished = true;
                Ok(Some(TopLevel::End))
            }
            records::FOOTER => {
                self.at = next;
                self.finished = true;
                Ok(Some(TopLevel::End))
            }
            records::CHUNK => {
                self.start_chunk(at, &b[at + RECORD_HEAD..next], most_chunk, false)?;
                self.hash_to(next);
                self.at = next;
                Ok(None)
            }
            records::SCHEMA | records::CHANNEL | records::MESSAGE => {
                self.hash_to(next);
                self.at = next;
                Ok(Some(TopLevel::Record(op, at, next)))
            }
            _ => {
                self.hash_to(next);
                self.at = next;
                Ok(None)
            }
        }
    }

    fn hash_to(&mut self, next: usize) {
        let b = Arc::clone(&self.bytes);
        self.data_crc.update(&b[self.at..next]);
    }

    fn cut_top(&mut self, at: usize, op: Option<u8>) -> Option<TopLevel> {
        let name = op.map_or("a record", record_name);
        self.cut(format!("the {name} record at byte {at}"));
        Some(TopLevel::End)
    }

    /// Starts inflating the Chunk record at `at` whose body is `body` (all
    /// of it, or what a file cut short holds of it).
    fn start_chunk(&mut self, at: usize, body: &[u8], most_chunk: u64, cut: bool) -> Result<()> {
        let place = Place::File(at as u64);
        let mut f = Fields::new(records::CHUNK, place, body);
        let head = (|| -> Result<_> {
            f.u64("message_start_time")?;
            f.u64("message_end_time")?;
            let size = f.u64("uncompressed_size")?;
            let crc = f.u32("uncompressed_crc")?;
            let compression = f.string("compression")?.to_string();
            let len = f.u64("records")?;
            Ok((size, crc, compression, len))
        })();
        let (size, crc, compression, len) = match head {
            Ok(h) => h,
            Err(_) if cut => {
                self.at = self.bytes.len();
                self.cut_top(at, Some(records::CHUNK));
                return Ok(());
            }
            Err(e) => return Err(e),
        };
        let from = at + RECORD_HEAD + (body.len() - f.rest().len());
        let left = (at + RECORD_HEAD + body.len() - from) as u64;
        if len > left && !cut {
            return Err(malformed(
                records::CHUNK,
                place,
                format_args!(
                    "records: a length of {len} bytes, past the record's end ({left} bytes left)"
                ),
            ));
        }
        let to = from + len.min(left) as usize;
        let inflating = Inflating::start(
            at as u64,
            Arc::clone(&self.bytes),
            (from, to),
            &compression,
            size,
            crc,
            most_chunk,
            cut,
        )?;
        if cut {
            self.at = self.bytes.len();
        }
        self.chunk = Some(ChunkState::Inflating(inflating));
        Ok(())
    }
}

enum TopLevel {
    End,
    /// A schema, channel or message record: opcode, start, end.
    Record(u8, usize, usize),
}
