//! Reading MCAP files, the container `ros2 bag record` writes by default.
//!
//! A reader of its own over the published MCAP specification (major
//! version 0): the magic bytes, then records (an opcode, a little-endian
//! `u64` length, the fields); messages stand alone or inside Chunk
//! records, whose records are stored as they are, or compressed with zstd
//! or lz4 (frames). Decompression is `ruzstd` and `lz4_flex` (its block
//! decoder, the frames read in `lz4`), pure Rust as every dependency of
//! the wasm must be.
//!
//! * `records`: one record's fields, every length checked against its
//!   record, and every refusal naming the record and its byte;
//! * `chunk`: a chunk's records inflated in bounded steps, the size it
//!   states checked before inflating and the output cut at it, its CRC-32
//!   checked;
//! * `reader`: [`McapReader`], the file's records in order, a bounded
//!   step at a time.
//!
//! The **summary section**, when a whole file has one (its footer and
//! trailing magic bytes in place), is read first: it names the channels
//! and their message counts before the data is read, and its CRC is
//! checked. It is never needed: a file without one is read from its data
//! alone. A file **cut short** (no trailing magic bytes) is read up to
//! the last whole record before the cut (inside a chunk, the records that
//! inflate before it), and [`McapReader::warning`] names the byte where
//! the file ends and the record it ends in. In a whole file, a length
//! that runs past the data section is an error. The Data End record's
//! CRC of the data section is checked when it states one.
//!
//! # Bounded steps
//!
//! [`McapReader::next`] takes a budget of bytes per call
//! ([`crate::io::LogBudget::bytes_per_read`]): the records passed over
//! and the bytes a chunk inflates count against it, a chunk being
//! inflated a step at a time (a zstd or lz4 block at most past the
//! budget), so that one call's work is bounded whatever the file holds;
//! the record that crosses the budget is finished (a record outside
//! chunks is taken whole: its bytes are in memory already, and only its
//! CRC is computed).
//!
//! What the messages mean is the ROS 2 layer's (`crate::io::ros2`).

mod chunk;
mod lz4;
mod reader;
mod records;

pub use chunk::MAX_CHUNK_BYTES;
pub use reader::{Event, McapReader, Summary, MAGIC};
pub use records::{quoted, Channel, MessageHead, Place, Schema};
