//! Gzip files (RFC 1952), read as a stream: one member after another, each
//! a header, a deflate stream and a trailer holding the CRC-32 and length
//! of what it inflates to.
//!
//! The inflating is `miniz_oxide`'s and the CRC-32 the `crc` crate's; this
//! module reads the framing around them. It exists instead of a gzip
//! wrapper crate for the size of the page's core: the wrappers check the
//! CRC with a slice-by-16 table, 16 KB of data that does not compress,
//! where one 1 KB table checks a log at the speed the inflating runs
//! anyway.

use crc::{Crc, Digest, CRC_32_ISO_HDLC};
use miniz_oxide::inflate::stream::{inflate, InflateState};
use miniz_oxide::{DataFormat, MZError, MZFlush, MZStatus};
use std::io::{self, BufRead, Read};

/// The CRC-32 of gzip (and zip, and PNG).
static CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// The CRC-32 of `bytes` (the checksum a zip entry carries).
pub fn crc32(bytes: &[u8]) -> u32 {
    CRC32.checksum(bytes)
}

/// The first two bytes of every gzip member.
pub const MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Header flags (RFC 1952 §2.3.1).
const FHCRC: u8 = 1 << 1;
const FEXTRA: u8 = 1 << 2;
const FNAME: u8 = 1 << 3;
const FCOMMENT: u8 = 1 << 4;
const RESERVED: u8 = 0b1110_0000;
/// The only compression method gzip defines: deflate.
const DEFLATE: u8 = 8;

enum Phase {
    /// Before a member's header (the first, or one after a trailer).
    Header,
    Body,
    Trailer,
    /// After the last member, or after an error.
    Done,
}

/// The inflated bytes of every gzip member in `inner`, in order (a gzip
/// file may hold several members, as `cat a.gz b.gz` writes them).
///
/// Errors are `io::Error`s: `UnexpectedEof` when the file ends inside a
/// member (a download cut short), `InvalidData` when it is not gzip or
/// is damaged (a wrong CRC among them). After an error every read returns
/// 0 bytes.
pub struct GzipReader<R: BufRead> {
    inner: R,
    state: Box<InflateState>,
    phase: Phase,
    crc: Digest<'static, u32>,
    /// Bytes inflated in this member, modulo 2^32 (the trailer's ISIZE).
    size: u32,
    /// Members whose header has been read.
    members: u64,
}

impl<R: BufRead> GzipReader<R> {
    pub fn new(inner: R) -> Self {
        Self {
            inner,
            state: InflateState::new_boxed(DataFormat::Raw),
            phase: Phase::Header,
            crc: CRC32.digest(),
            size: 0,
            members: 0,
        }
    }

    /// The compressed stream underneath.
    pub fn get_ref(&self) -> &R {
        &self.inner
    }

    /// Reads a member's header, or finds that the file has ended; `first`
    /// says whether this is the first member (an empty file is not gzip).
    fn header(&mut self, first: bool) -> io::Result<bool> {
        if !first && self.inner.fill_buf()?.is_empty() {
            return Ok(false);
        }
        let mut fixed = [0u8; 10];
        self.exact(&mut fixed)?;
        if fixed[..2] != MAGIC {
            return Err(damaged("what follows a gzip member is not another one"));
        }
        if fixed[2] != DEFLATE {
            return Err(damaged(
                "a gzip member compressed with a method other than deflate",
            ));
        }
        let flags = fixed[3];
        if flags & RESERVED != 0 {
            return Err(damaged("a gzip header with reserved flags set"));
        }
        let mut header = CRC32.digest();
        header.update(&fixed);
        if flags & FEXTRA != 0 {
            let mut len = [0u8; 2];
            self.exact(&mut len)?;
            header.update(&len);
            let mut left = u16::from_le_bytes(len) as usize;
            while left > 0 {
                let mut chunk = [0u8; 256];
                let n = left.min(chunk.len());
                self.exact(&mut chunk[..n])?;
                header.update(&chunk[..n]);
                left -= n;
            }
        }
        for flag in [FNAME, FCOMMENT] {
            if flags & flag != 0 {
                // A zero-terminated name or comment, of any length.
                loop {
                    let mut byte = [0u8; 1];
                    self.exact(&mut byte)?;
                    header.update(&byte);
                    if byte[0] == 0 {
                        break;
                    }
                }
            }
        }
        if flags & FHCRC != 0 {
            let mut crc16 = [0u8; 2];
            self.exact(&mut crc16)?;
            if u16::from_le_bytes(crc16) != header.finalize() as u16 {
                return Err(damaged("a gzip header whose CRC does not match it"));
            }
        }
        Ok(true)
    }

    /// Reads a member's trailer and checks it against what was inflated.
    fn trailer(&mut self) -> io::Result<()> {
        let mut trailer = [0u8; 8];
        self.exact(&mut trailer)?;
        let crc = std::mem::replace(&mut self.crc, CRC32.digest()).finalize();
        let size = std::mem::take(&mut self.size);
        if u32::from_le_bytes([trailer[0], trailer[1], trailer[2], trailer[3]]) != crc {
            return Err(damaged(
                "the CRC of the inflated data does not match the file's",
            ));
        }
        if u32::from_le_bytes([trailer[4], trailer[5], trailer[6], trailer[7]]) != size {
            return Err(damaged("the inflated data is not as long as the file says"));
        }
        Ok(())
    }

    /// Fills `buf` from the compressed stream; running out is
    /// `UnexpectedEof`.
    fn exact(&mut self, buf: &mut [u8]) -> io::Result<()> {
        self.inner.read_exact(buf).map_err(|e| {
            if e.kind() == io::ErrorKind::UnexpectedEof {
                cut_short()
            } else {
                e
            }
        })
    }

    /// Inflates into `out` until it holds something or the member ends.
    fn body(&mut self, out: &mut [u8]) -> io::Result<usize> {
        loop {
            let input = self.inner.fill_buf()?;
            let ended = input.is_empty();
            let result = inflate(&mut self.state, input, out, MZFlush::None);
            self.inner.consume(result.bytes_consumed);
            let written = &out[..result.bytes_written];
            self.crc.update(written);
            self.size = self.size.wrapping_add(written.len() as u32);
            match result.status {
                Ok(MZStatus::StreamEnd) => {
                    self.phase = Phase::Trailer;
                    return Ok(written.len());
                }
                Ok(_) if !written.is_empty() => return Ok(written.len()),
                Ok(_) | Err(MZError::Buf) if ended => return Err(cut_short()),
                Ok(_) | Err(MZError::Buf) if result.bytes_consumed > 0 => {}
                // Input left and room to write, yet no progress: the
                // decompressor has stopped for good.
                _ => return Err(damaged("the compressed data is corrupt")),
            }
        }
    }

    fn step(&mut self, out: &mut [u8]) -> io::Result<usize> {
        loop {
            match self.phase {
                Phase::Header => {
                    if !self.header(self.members == 0)? {
                        self.phase = Phase::Done;
                        return Ok(0);
                    }
                    self.members += 1;
                    self.state.reset(DataFormat::Raw);
                    self.phase = Phase::Body;
                }
                Phase::Body => {
                    let n = self.body(out)?;
                    if n > 0 {
                        return Ok(n);
                    }
                }
                Phase::Trailer => {
                    self.trailer()?;
                    self.phase = Phase::Header;
                }
                Phase::Done => return Ok(0),
            }
        }
    }
}

impl<R: BufRead> Read for GzipReader<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        if out.is_empty() {
            return Ok(0);
        }
        self.step(out).inspect_err(|_| self.phase = Phase::Done)
    }
}

fn damaged(what: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, what)
}

fn cut_short() -> io::Error {
    io::Error::new(
        io::ErrorKind::UnexpectedEof,
        "the gzip file ends inside a member",
    )
}
