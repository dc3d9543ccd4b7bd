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
//!
//! # Reading in bounded steps
//!
//! Every part of a member is read as a state that survives a pause: the
//! reader takes bytes only through `fill_buf` / `consume` of the stream
//! underneath, and when that stream answers "not now" (`WouldBlock` or
//! `Interrupted`, as the CARMEN reader's input budget does) the reader
//! passes the answer on and resumes where it was on the next call. So a
//! caller that bounds the compressed bytes it hands over bounds the work,
//! whatever the file holds: a name of 40 MB, millions of empty members, or
//! a deflate stream that inflates to nothing.
//!
//! # Zero padding
//!
//! Tape and block devices pad an archive with zero bytes; GNU gzip and
//! Python's `gzip` read such a file. Zero bytes after a complete member are
//! read as padding up to the end of the file; anything else after them (or
//! any other byte where a member should start) is damage.

use crc::{Crc, Digest, CRC_32_ISO_HDLC};
use miniz_oxide::inflate::stream::{inflate, InflateState, MinReset};
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

/// Where the reader is in a member's header (RFC 1952 §2.3), in file order.
#[derive(Clone, Copy, PartialEq, Eq)]
enum HeaderPart {
    /// ID1 ID2 CM FLG MTIME XFL OS: ten bytes.
    Fixed,
    /// XLEN, when FEXTRA is set.
    ExtraLength,
    /// The extra field: this many bytes left.
    Extra(usize),
    /// The zero-terminated file name, when FNAME is set.
    Name,
    /// The zero-terminated comment, when FCOMMENT is set.
    Comment,
    /// The header's CRC-16, when FHCRC is set.
    Crc,
}

enum Phase {
    /// Where a member may start: the first, or one after a trailer.
    Between,
    Header(HeaderPart),
    Body,
    Trailer,
    /// Zero bytes after the last member, up to the end of the file.
    Padding,
    /// After the end of the file, or after an error.
    Done,
}

/// The inflated bytes of every gzip member in `inner`, in order (a gzip
/// file may hold several members, as `cat a.gz b.gz` writes them).
///
/// Errors are `io::Error`s: `UnexpectedEof` when the file ends inside a
/// member (a download cut short), `InvalidData` when it is not gzip or
/// is damaged (a wrong CRC among them). After such an error every read
/// returns 0 bytes. `WouldBlock` and `Interrupted` from `inner` are passed
/// on and end nothing: the next read resumes.
pub struct GzipReader<R: BufRead> {
    inner: R,
    state: Box<InflateState>,
    phase: Phase,
    crc: Digest<'static, u32>,
    /// Bytes inflated in this member, modulo 2^32 (the trailer's ISIZE).
    size: u32,
    /// Members whose header has been read.
    members: u64,
    /// The header's flags and running CRC (for FHCRC).
    flags: u8,
    header_crc: Digest<'static, u32>,
    /// A fixed-size part (header, XLEN, CRC-16, trailer) gathered so far:
    /// a pause may fall inside one.
    held: [u8; 10],
    held_len: usize,
}

impl<R: BufRead> GzipReader<R> {
    pub fn new(inner: R) -> Self {
        Self {
            inner,
            state: InflateState::new_boxed(DataFormat::Raw),
            phase: Phase::Between,
            crc: CRC32.digest(),
            size: 0,
            members: 0,
            flags: 0,
            header_crc: CRC32.digest(),
            held: [0; 10],
            held_len: 0,
        }
    }

    /// The compressed stream underneath.
    pub fn get_ref(&self) -> &R {
        &self.inner
    }

    /// The compressed stream underneath, to change its limits (reading from
    /// it directly would lose the reader's place).
    pub fn get_mut(&mut self) -> &mut R {
        &mut self.inner
    }

    /// Gathers the next `n` (at most 10) bytes into `held`, across pauses:
    /// once this returns, `held[..n]` holds them.
    fn gather(&mut self, n: usize) -> io::Result<()> {
        while self.held_len < n {
            let input = self.inner.fill_buf()?;
            if input.is_empty() {
                return Err(cut_short());
            }
            let k = (n - self.held_len).min(input.len());
            self.held[self.held_len..self.held_len + k].copy_from_slice(&input[..k]);
            self.inner.consume(k);
            self.held_len += k;
        }
        self.held_len = 0;
        Ok(())
    }

    /// The header part after `part`, given the member's flags.
    fn after(&self, part: HeaderPart) -> Option<HeaderPart> {
        let order = [
            (HeaderPart::ExtraLength, FEXTRA),
            (HeaderPart::Name, FNAME),
            (HeaderPart::Comment, FCOMMENT),
            (HeaderPart::Crc, FHCRC),
        ];
        let rank = |p: HeaderPart| match p {
            HeaderPart::Fixed => 0,
            HeaderPart::ExtraLength | HeaderPart::Extra(_) => 1,
            HeaderPart::Name => 2,
            HeaderPart::Comment => 3,
            HeaderPart::Crc => 4,
        };
        order
            .into_iter()
            .skip(rank(part))
            .find(|&(_, flag)| self.flags & flag != 0)
            .map(|(p, _)| p)
    }

    /// Reads the header from `part` on; returns once the whole header is
    /// read (a pause returns the error with the place kept).
    fn header(&mut self, mut part: HeaderPart) -> io::Result<()> {
        loop {
            self.phase = Phase::Header(part);
            let next = match part {
                HeaderPart::Fixed => {
                    self.gather(10)?;
                    let fixed = self.held;
                    if fixed[..2] != MAGIC {
                        return Err(damaged("what follows a gzip member is not another one"));
                    }
                    if fixed[2] != DEFLATE {
                        return Err(damaged(
                            "a gzip member compressed with a method other than deflate",
                        ));
                    }
                    if fixed[3] & RESERVED != 0 {
                        return Err(damaged("a gzip header with reserved flags set"));
                    }
                    self.flags = fixed[3];
                    self.header_crc = CRC32.digest();
                    self.header_crc.update(&fixed);
                    self.after(part)
                }
                HeaderPart::ExtraLength => {
                    self.gather(2)?;
                    let len = [self.held[0], self.held[1]];
                    self.header_crc.update(&len);
                    Some(HeaderPart::Extra(u16::from_le_bytes(len) as usize))
                }
                HeaderPart::Extra(0) => self.after(part),
                HeaderPart::Extra(left) => {
                    let input = self.inner.fill_buf()?;
                    if input.is_empty() {
                        return Err(cut_short());
                    }
                    let k = left.min(input.len());
                    self.header_crc.update(&input[..k]);
                    self.inner.consume(k);
                    Some(HeaderPart::Extra(left - k))
                }
                HeaderPart::Name | HeaderPart::Comment => {
                    // Zero-terminated, of any length: skipped a buffer at a
                    // time, not a byte at a time.
                    let input = self.inner.fill_buf()?;
                    if input.is_empty() {
                        return Err(cut_short());
                    }
                    let end = input.iter().position(|&b| b == 0);
                    let k = end.map_or(input.len(), |i| i + 1);
                    self.header_crc.update(&input[..k]);
                    self.inner.consume(k);
                    if end.is_some() {
                        self.after(part)
                    } else {
                        Some(part)
                    }
                }
                HeaderPart::Crc => {
                    self.gather(2)?;
                    let crc16 = u16::from_le_bytes([self.held[0], self.held[1]]);
                    let crc = std::mem::replace(&mut self.header_crc, CRC32.digest());
                    if crc16 != crc.finalize() as u16 {
                        return Err(damaged("a gzip header whose CRC does not match it"));
                    }
                    None
                }
            };
            match next {
                Some(p) => part = p,
                None => return Ok(()),
            }
        }
    }

    /// Reads a member's trailer and checks it against what was inflated.
    fn trailer(&mut self) -> io::Result<()> {
        self.gather(8)?;
        let t = self.held;
        let crc = std::mem::replace(&mut self.crc, CRC32.digest()).finalize();
        let size = std::mem::take(&mut self.size);
        if u32::from_le_bytes([t[0], t[1], t[2], t[3]]) != crc {
            return Err(damaged(
                "the CRC of the inflated data does not match the file's",
            ));
        }
        if u32::from_le_bytes([t[4], t[5], t[6], t[7]]) != size {
            return Err(damaged("the inflated data is not as long as the file says"));
        }
        Ok(())
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

    /// Skips zero padding to the end of the file.
    fn padding(&mut self) -> io::Result<()> {
        loop {
            let input = self.inner.fill_buf()?;
            if input.is_empty() {
                return Ok(());
            }
            if input.iter().any(|&b| b != 0) {
                return Err(damaged(
                    "the zero bytes that pad a gzip file are followed by other bytes",
                ));
            }
            let n = input.len();
            self.inner.consume(n);
        }
    }

    fn step(&mut self, out: &mut [u8]) -> io::Result<usize> {
        loop {
            match self.phase {
                Phase::Between => {
                    if self.members > 0 {
                        match self.inner.fill_buf()?.first() {
                            None => {
                                self.phase = Phase::Done;
                                return Ok(0);
                            }
                            Some(0) => {
                                self.phase = Phase::Padding;
                                continue;
                            }
                            Some(_) => {}
                        }
                    }
                    // An empty file is not gzip: the first header is due.
                    self.header(HeaderPart::Fixed)?;
                    self.start_body();
                }
                Phase::Header(part) => {
                    self.header(part)?;
                    self.start_body();
                }
                Phase::Body => {
                    let n = self.body(out)?;
                    if n > 0 {
                        return Ok(n);
                    }
                }
                Phase::Trailer => {
                    self.trailer()?;
                    self.phase = Phase::Between;
                }
                Phase::Padding => {
                    self.padding()?;
                    self.phase = Phase::Done;
                }
                Phase::Done => return Ok(0),
            }
        }
    }

    fn start_body(&mut self) {
        self.members += 1;
        // The least reset: no 32 KB dictionary to clear per member, so a
        // file of empty members costs little more than reading it. A
        // member that refers back past its own start can reach only bytes
        // of the member before it, from the same file, and the trailer's
        // CRC still checks what it inflates to.
        self.state.reset_as(MinReset);
        self.phase = Phase::Body;
    }
}

/// "Not now" from the stream underneath: the read stops where it is and
/// the next one resumes.
fn is_pause(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
    )
}

impl<R: BufRead> Read for GzipReader<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        if out.is_empty() {
            return Ok(0);
        }
        self.step(out).inspect_err(|e| {
            if !is_pause(e) {
                self.phase = Phase::Done;
            }
        })
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
