//! The records of an MCAP file, as the specification lays them out: an
//! opcode byte, a little-endian `u64` length, then the fields, each read
//! through [`Fields`], which refuses a length that runs past its record
//! and names the record and the byte where it starts.

use crate::error::OccError;
use std::fmt;

/// Opcodes of the records this reader reads (the others are passed over).
pub const HEADER: u8 = 0x01;
pub const FOOTER: u8 = 0x02;
pub const SCHEMA: u8 = 0x03;
pub const CHANNEL: u8 = 0x04;
pub const MESSAGE: u8 = 0x05;
pub const CHUNK: u8 = 0x06;
pub const STATISTICS: u8 = 0x0b;
pub const DATA_END: u8 = 0x0f;

/// Bytes of a record's opcode and length.
pub const RECORD_HEAD: usize = 9;

/// A name read from a file, as a message quotes it: printable characters
/// only (any other becomes `?`), at most 80 of them.
pub fn quoted(name: &str) -> String {
    // One loop, no formatting: a smaller wasm than an iterator chain and
    // `format!`.
    let mut out = String::from("\"");
    for (i, c) in name.chars().enumerate() {
        if i == 80 {
            out.push('\u{2026}');
            break;
        }
        out.push(if c.is_control() { '?' } else { c });
    }
    out.push('"');
    out
}

/// A record's name, for messages.
pub fn record_name(op: u8) -> &'static str {
    match op {
        HEADER => "Header",
        FOOTER => "Footer",
        SCHEMA => "Schema",
        CHANNEL => "Channel",
        MESSAGE => "Message",
        CHUNK => "Chunk",
        0x07 => "Message Index",
        0x08 => "Chunk Index",
        0x09 => "Attachment",
        0x0a => "Attachment Index",
        STATISTICS => "Statistics",
        0x0c => "Metadata",
        0x0d => "Metadata Index",
        0x0e => "Summary Offset",
        DATA_END => "Data End",
        _ => "unknown",
    }
}

/// Where a record lies: a byte of the file, or a byte of a chunk's
/// decompressed records (the chunk named by its own byte in the file).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    File(u64),
    InChunk { chunk: u64, at: u64 },
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Place::File(at) => write!(f, "byte {at}"),
            Place::InChunk { chunk, at } => {
                write!(f, "byte {at} of the records of the Chunk at byte {chunk}")
            }
        }
    }
}

/// The refusal of a malformed record: its name, where it starts, why.
pub fn malformed(op: u8, place: Place, why: impl fmt::Display) -> OccError {
    OccError::State(format!(
        "the bag's {} record at {place} is malformed: {why}",
        record_name(op)
    ))
}

/// A record's fields, read in order; every read checks the record's
/// length first.
pub struct Fields<'a> {
    bytes: &'a [u8],
    at: usize,
    op: u8,
    place: Place,
}

impl<'a> Fields<'a> {
    pub fn new(op: u8, place: Place, bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            at: 0,
            op,
            place,
        }
    }

    fn error(&self, field: &str, why: impl fmt::Display) -> OccError {
        malformed(self.op, self.place, format_args!("{field}: {why}"))
    }

    /// The next `n` bytes, or an error naming `field`.
    pub fn take(&mut self, field: &str, n: u64) -> Result<&'a [u8], OccError> {
        let left = (self.bytes.len() - self.at) as u64;
        if n > left {
            return Err(self.error(
                field,
                format_args!(
                    "{n} bytes at byte {} of the record, past its end ({left} bytes left)",
                    self.at
                ),
            ));
        }
        let s = &self.bytes[self.at..self.at + n as usize];
        self.at += n as usize;
        Ok(s)
    }

    pub fn u16(&mut self, field: &str) -> Result<u16, OccError> {
        Ok(u16::from_le_bytes(
            self.take(field, 2)?.try_into().unwrap_or([0; 2]),
        ))
    }

    pub fn u32(&mut self, field: &str) -> Result<u32, OccError> {
        Ok(u32::from_le_bytes(
            self.take(field, 4)?.try_into().unwrap_or([0; 4]),
        ))
    }

    pub fn u64(&mut self, field: &str) -> Result<u64, OccError> {
        Ok(u64::from_le_bytes(
            self.take(field, 8)?.try_into().unwrap_or([0; 8]),
        ))
    }

    /// A string: a `u32` length, then UTF-8.
    pub fn string(&mut self, field: &str) -> Result<&'a str, OccError> {
        let n = self.u32(field)?;
        let bytes = self.take(field, n as u64)?;
        std::str::from_utf8(bytes).map_err(|_| self.error(field, "not UTF-8 text"))
    }

    /// Bytes behind a `u32` length.
    pub fn bytes32(&mut self, field: &str) -> Result<&'a [u8], OccError> {
        let n = self.u32(field)?;
        self.take(field, n as u64)
    }

    /// Bytes behind a `u64` length.
    pub fn bytes64(&mut self, field: &str) -> Result<&'a [u8], OccError> {
        let n = self.u64(field)?;
        self.take(field, n)
    }

    /// The rest of the record.
    pub fn rest(&mut self) -> &'a [u8] {
        let s = &self.bytes[self.at..];
        self.at = self.bytes.len();
        s
    }
}

/// A Schema record: a message type's definition.
#[derive(Debug, Clone, PartialEq)]
pub struct Schema {
    pub id: u16,
    pub name: String,
    pub encoding: String,
    pub data: Vec<u8>,
}

impl Schema {
    pub fn parse(f: &mut Fields<'_>) -> Result<Self, OccError> {
        Ok(Self {
            id: f.u16("id")?,
            name: f.string("name")?.to_string(),
            encoding: f.string("encoding")?.to_string(),
            data: f.bytes32("data")?.to_vec(),
        })
    }
}

/// A Channel record: a topic, its schema and its message encoding.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub id: u16,
    pub schema_id: u16,
    pub topic: String,
    pub message_encoding: String,
}

impl Channel {
    pub fn parse(f: &mut Fields<'_>) -> Result<Self, OccError> {
        let id = f.u16("id")?;
        let schema_id = f.u16("schema_id")?;
        let topic = f.string("topic")?.to_string();
        let message_encoding = f.string("message_encoding")?.to_string();
        // The metadata map's entries are not read, but its length must fit.
        f.bytes32("metadata")?;
        Ok(Self {
            id,
            schema_id,
            topic,
            message_encoding,
        })
    }
}

/// A Message record's head; its data is the rest of the record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MessageHead {
    pub channel_id: u16,
    pub log_time: u64,
}

impl MessageHead {
    pub fn parse<'a>(f: &mut Fields<'a>) -> Result<(Self, &'a [u8]), OccError> {
        let channel_id = f.u16("channel_id")?;
        f.u32("sequence")?;
        let log_time = f.u64("log_time")?;
        f.u64("publish_time")?;
        Ok((
            Self {
                channel_id,
                log_time,
            },
            f.rest(),
        ))
    }
}

/// A Statistics record's message count per channel.
pub fn channel_message_counts(f: &mut Fields<'_>) -> Result<Vec<(u16, u64)>, OccError> {
    f.u64("message_count")?;
    f.u16("schema_count")?;
    f.u32("channel_count")?;
    f.u32("attachment_count")?;
    f.u32("metadata_count")?;
    f.u32("chunk_count")?;
    f.u64("message_start_time")?;
    f.u64("message_end_time")?;
    let map = f.bytes32("channel_message_counts")?;
    let mut entries = Fields::new(f.op, f.place, map);
    let mut counts = Vec::new();
    while entries.at < map.len() {
        counts.push((
            entries.u16("channel_message_counts")?,
            entries.u64("channel_message_counts")?,
        ));
    }
    Ok(counts)
}
