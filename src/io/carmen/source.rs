//! The bytes of a log: plain text or gzip (told apart by the first two
//! bytes), counted as they are taken from the caller's reader, and handed
//! over only up to a limit, so that one budgeted read takes a bounded
//! amount of the file whatever it holds.

use crate::io::gzip::{GzipReader, MAGIC};
use std::io::{self, BufRead, BufReader, Chain, Cursor, Read};

/// Buffer size of the line reader and of the decompressor's output.
pub(super) const BUFFER: usize = 64 * 1024;

/// Takes bytes from the caller's reader, counting them, and no more than up
/// to `limit` in all: past it, a read answers "not now" (`WouldBlock`
/// carrying [`InputBudgetSpent`]), which every layer above passes on.
pub(super) struct Counting<R> {
    inner: R,
    count: u64,
    limit: u64,
}

/// The error a [`Counting`] reader answers once its limit is reached.
#[derive(Debug)]
struct InputBudgetSpent;

impl std::fmt::Display for InputBudgetSpent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("this read's budget of input bytes is spent")
    }
}

impl std::error::Error for InputBudgetSpent {}

/// True for the pause a [`Counting`] reader's limit causes (not an error of
/// the caller's reader).
pub(super) fn is_budget_pause(e: &io::Error) -> bool {
    e.kind() == io::ErrorKind::WouldBlock
        && e.get_ref()
            .is_some_and(|inner| inner.is::<InputBudgetSpent>())
}

impl<R: Read> Read for Counting<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let room = self.limit.saturating_sub(self.count);
        if room == 0 && !buf.is_empty() {
            return Err(io::Error::new(io::ErrorKind::WouldBlock, InputBudgetSpent));
        }
        let take = buf.len().min(usize::try_from(room).unwrap_or(usize::MAX));
        let n = self.inner.read(&mut buf[..take])?;
        self.count += n as u64;
        Ok(n)
    }
}

/// The first bytes (read to detect gzip) put back in front of the rest.
type Head<R> = Chain<Cursor<Vec<u8>>, Counting<R>>;

pub(super) enum Source<R: Read> {
    /// Not yet read from: gzip or plain is decided on the first read.
    Unopened(R),
    Plain(BufReader<Head<R>>),
    Gzip(BufReader<GzipReader<BufReader<Head<R>>>>),
    /// After the end of the file or an error.
    Closed,
}

impl<R: Read> Source<R> {
    /// Reads up to two bytes (gzip members start with 0x1f 0x8b) and picks
    /// the reader. These two bytes are taken whatever the limit.
    pub(super) fn open(reader: R) -> io::Result<Self> {
        let mut counting = Counting {
            inner: reader,
            count: 0,
            limit: u64::MAX,
        };
        let mut magic = [0u8; 2];
        let mut n = 0;
        while n < 2 {
            match counting.read(&mut magic[n..]) {
                Ok(0) => break,
                Ok(k) => n += k,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        let gzip = n == 2 && magic == MAGIC;
        let head = Cursor::new(magic[..n].to_vec()).chain(counting);
        Ok(if gzip {
            Source::Gzip(BufReader::with_capacity(
                BUFFER,
                GzipReader::new(BufReader::with_capacity(BUFFER, head)),
            ))
        } else {
            Source::Plain(BufReader::with_capacity(BUFFER, head))
        })
    }

    fn counting(&self) -> Option<&Counting<R>> {
        match self {
            Source::Plain(b) => Some(b.get_ref().get_ref().1),
            Source::Gzip(b) => Some(b.get_ref().get_ref().get_ref().get_ref().1),
            _ => None,
        }
    }

    /// Bytes taken from the caller's reader so far, once open.
    pub(super) fn bytes_read(&self) -> Option<u64> {
        self.counting().map(|c| c.count)
    }

    /// Lets the readers above take bytes from the caller's reader until
    /// `limit` have been taken in all (from the start of the file).
    pub(super) fn set_input_limit(&mut self, limit: u64) {
        let counting = match self {
            Source::Plain(b) => b.get_mut().get_mut().1,
            Source::Gzip(b) => b.get_mut().get_mut().get_mut().get_mut().1,
            _ => return,
        };
        counting.limit = limit;
    }

    pub(super) fn is_gzip(&self) -> bool {
        matches!(self, Source::Gzip(_))
    }

    /// The text, line by line, when open.
    pub(super) fn text(&mut self) -> Option<&mut dyn BufRead> {
        match self {
            Source::Plain(b) => Some(b),
            Source::Gzip(b) => Some(b),
            _ => None,
        }
    }
}
