//! A Chunk record's records, inflated a bounded step at a time: none,
//! zstd (`ruzstd`'s frame decoder) or lz4 frames (`lz4`: the framing read
//! here, the blocks by `lz4_flex`), all pure Rust. A chunk
//! states how large its records are once inflated; that size is checked
//! against [`MAX_CHUNK_BYTES`] and the log's budget before anything is
//! inflated, and the output is cut at it, so that a bomb (a small chunk
//! that claims little and inflates to gigabytes) costs no more than the
//! size it claims. The CRC-32 it states (0: none) is checked once it is
//! inflated.

use super::lz4::Lz4Frames;
use super::records::{malformed, quoted, Place, CHUNK};
use crate::error::{OccError, Result};
use crc::{Crc, Digest, CRC_32_ISO_HDLC};
use ruzstd::decoding::{BlockDecodingStrategy, FrameDecoder};
use std::io::Read;
use std::sync::Arc;

/// The CRC-32 MCAP uses (that of zlib and gzip).
pub static CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// The largest chunk inflated: 64 MiB. Writers cut chunks at a few
/// hundred kilobytes to a few megabytes (the ROS 2 recorder's default is
/// under one); a chunk has to be held whole while its records are read.
pub const MAX_CHUNK_BYTES: u64 = 64 << 20;

/// A slice of the file's bytes, read as a stream by the zstd decoder.
pub struct SharedSlice {
    bytes: Arc<Vec<u8>>,
    at: usize,
    end: usize,
}

impl Read for SharedSlice {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.end - self.at);
        buf[..n].copy_from_slice(&self.bytes[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

/// How a chunk's records are stored.
enum Codec {
    Stored,
    Zstd(Box<FrameDecoder>),
    Lz4(Lz4Frames),
}

/// A chunk being inflated.
pub struct Inflating {
    /// Where the Chunk record starts in the file.
    pub chunk: u64,
    input: SharedSlice,
    codec: Codec,
    /// The records inflated so far.
    pub out: Vec<u8>,
    declared: u64,
    crc: u32,
    digest: Digest<'static, u32>,
    /// True when the file ends inside this chunk: what inflates before the
    /// cut is kept, and neither the size nor the CRC can be checked.
    pub cut: bool,
}

impl Inflating {
    /// Starts inflating `bytes[at..end]`, compressed by `compression`, to
    /// `declared` bytes (the limit `most`, the log's budget).
    #[allow(clippy::too_many_arguments)] // the chunk's own fields, in order
    pub fn start(
        chunk: u64,
        bytes: Arc<Vec<u8>>,
        (at, end): (usize, usize),
        compression: &str,
        declared: u64,
        crc: u32,
        most: u64,
        cut: bool,
    ) -> Result<Self> {
        let place = Place::File(chunk);
        let limit = MAX_CHUNK_BYTES.min(most);
        if declared > limit {
            return Err(malformed(
                CHUNK,
                place,
                format_args!(
                    "uncompressed_size {declared} is over the {limit} bytes a chunk may inflate to"
                ),
            ));
        }
        let mut input = SharedSlice { bytes, at, end };
        let codec = match compression {
            "" => Codec::Stored,
            "zstd" => {
                let mut frame = FrameDecoder::new();
                // A frame whose window is past what any chunk may hold is
                // refused before its window is allocated.
                frame.set_max_window_size(MAX_CHUNK_BYTES);
                match frame.init(&mut input) {
                    Ok(()) => Codec::Zstd(Box::new(frame)),
                    Err(_) if cut => {
                        // Cut inside the frame's header: nothing inflates.
                        input.at = input.end;
                        Codec::Stored
                    }
                    Err(_) => return Err(malformed(CHUNK, place, "its records are no zstd frame")),
                }
            }
            "lz4" => Codec::Lz4(Lz4Frames::default()),
            other => {
                return Err(malformed(
                    CHUNK,
                    place,
                    format_args!("compression {} is not none, zstd or lz4", quoted(other)),
                ))
            }
        };
        Ok(Self {
            chunk,
            input,
            codec,
            out: Vec::new(),
            declared,
            crc,
            digest: CRC32.digest(),
            cut,
        })
    }

    /// Inflates some `step` more bytes (a block's worth past it at most):
    /// `Ok(true)` once the chunk is whole (its size and CRC checked) or,
    /// for a chunk cut short, once nothing more inflates.
    pub fn step(&mut self, step: usize) -> Result<bool> {
        let place = Place::File(self.chunk);
        let from = self.out.len();
        let broken = |why: &str| {
            malformed(
                CHUNK,
                place,
                format_args!("its records do not inflate: {why}"),
            )
        };
        // One byte past the declared size is let through, to see a chunk
        // that inflates to more than it says.
        let room = (self.declared + 1).saturating_sub(from as u64);
        let step = (step.max(1) as u64).min(room) as usize;
        let finished = match &mut self.codec {
            Codec::Stored => {
                let input = &mut self.input;
                let n = step.min(input.end - input.at);
                self.out
                    .extend_from_slice(&input.bytes[input.at..input.at + n]);
                input.at += n;
                input.at == input.end
            }
            Codec::Zstd(frame) => {
                let decoded =
                    frame.decode_blocks(&mut self.input, BlockDecodingStrategy::UptoBytes(step));
                if let Some(bytes) = frame.collect() {
                    self.out.extend_from_slice(&bytes);
                }
                match decoded {
                    Ok(done) => {
                        if done || frame.is_finished() {
                            if let Some(bytes) = frame.collect() {
                                self.out.extend_from_slice(&bytes);
                            }
                            true
                        } else {
                            false
                        }
                    }
                    Err(_) if self.cut => true,
                    Err(_) => return Err(broken("a zstd block is malformed")),
                }
            }
            Codec::Lz4(frames) => {
                let input = &mut self.input;
                match frames.step(
                    &input.bytes[..input.end],
                    &mut input.at,
                    &mut self.out,
                    from + step,
                ) {
                    Ok(done) => done,
                    Err(_) if self.cut => true,
                    Err(why) => return Err(broken(why)),
                }
            }
        };
        let len = self.out.len() as u64;
        if len > self.declared && !self.cut {
            return Err(malformed(
                CHUNK,
                place,
                format_args!(
                    "its records inflate past the uncompressed_size of {} bytes",
                    self.declared
                ),
            ));
        }
        self.digest.update(&self.out[from..]);
        if !finished {
            return Ok(false);
        }
        if self.cut {
            self.out.truncate(self.declared.min(len) as usize);
            return Ok(true);
        }
        if len != self.declared {
            return Err(malformed(
                CHUNK,
                place,
                format_args!(
                    "its records inflate to {len} bytes, not the uncompressed_size of {}",
                    self.declared
                ),
            ));
        }
        let digest = std::mem::replace(&mut self.digest, CRC32.digest());
        let found = digest.finalize();
        if self.crc != 0 && found != self.crc {
            return Err(crc_mismatch("Chunk", place, self.crc, found));
        }
        Ok(true)
    }
}

/// The refusal of a CRC that does not match.
pub fn crc_mismatch(record: &str, place: Place, stated: u32, found: u32) -> OccError {
    OccError::State(format!(
        "the bag's {record} record at {place} fails its CRC: it states {stated:#010x}, the bytes give {found:#010x}"
    ))
}
