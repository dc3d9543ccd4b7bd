//! LZ4 frames (the LZ4 frame format, version 01), the framing read here
//! and each block inflated by `lz4_flex`'s block decoder: a magic number,
//! a descriptor (flags, the largest block, optional content size and
//! dictionary id, a header checksum), then blocks, each a little-endian
//! `u32` size whose top bit marks a block stored as it is, an end mark of
//! 0 and optional checksums. A block of a linked frame may refer to the
//! 64 KiB before it. (The checksums are not verified: the chunk's CRC-32
//! covers what the frames inflate to.) A skippable frame (a magic number
//! `0x184D2A50` to `0x184D2A5F`, a little-endian `u32` size, that many
//! bytes of the writer's own) is passed over, as the format says.

/// The magic number of an LZ4 frame.
const MAGIC: u32 = 0x184d_2204;
/// The magic numbers of a skippable frame, less their last four bits.
const SKIPPABLE: u32 = 0x184d_2a50;
/// How far back a linked block may refer.
const WINDOW: usize = 64 << 10;

/// Where the reader is in a chunk's frames.
#[derive(Debug, Default)]
pub struct Lz4Frames {
    /// The frame being read: its largest block and flags, once its header
    /// is read.
    frame: Option<Frame>,
    scratch: Vec<u8>,
}

#[derive(Debug, Clone, Copy)]
struct Frame {
    block_max: usize,
    block_checksum: bool,
    content_checksum: bool,
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}

impl Lz4Frames {
    /// Reads blocks of `input` from `*at` into `out` until `out` holds
    /// `until` bytes or the input ends: `Ok(true)` at its end.
    pub fn step(
        &mut self,
        input: &[u8],
        at: &mut usize,
        out: &mut Vec<u8>,
        until: usize,
    ) -> Result<bool, &'static str> {
        while out.len() < until {
            let Some(frame) = self.frame else {
                if *at == input.len() {
                    return Ok(true);
                }
                self.frame = Self::header(input, at)?;
                continue;
            };
            let size = u32_at(input, *at).ok_or("a block size past the end")?;
            *at += 4;
            if size == 0 {
                if frame.content_checksum {
                    *at = at
                        .checked_add(4)
                        .filter(|&e| e <= input.len())
                        .ok_or("the content checksum is cut")?;
                }
                self.frame = None;
                continue;
            }
            let stored = size & 0x8000_0000 != 0;
            let len = (size & 0x7fff_ffff) as usize;
            if len > frame.block_max {
                return Err("a block larger than its frame allows");
            }
            let block = input.get(*at..*at + len).ok_or("a block past the end")?;
            *at += len;
            if frame.block_checksum {
                *at = at
                    .checked_add(4)
                    .filter(|&e| e <= input.len())
                    .ok_or("a block checksum is cut")?;
            }
            if stored {
                out.extend_from_slice(block);
                continue;
            }
            self.scratch.resize(frame.block_max, 0);
            let dict = &out[out.len().saturating_sub(WINDOW)..];
            let n = lz4_flex::block::decompress_into_with_dict(block, &mut self.scratch, dict)
                .map_err(|_| "a block is malformed")?;
            out.extend_from_slice(&self.scratch[..n]);
        }
        Ok(false)
    }

    /// The header of the frame at `*at`, read past; `None` for a
    /// skippable frame, passed over whole.
    fn header(input: &[u8], at: &mut usize) -> Result<Option<Frame>, &'static str> {
        let magic = u32_at(input, *at).ok_or("a frame header past the end")?;
        if magic & !0xf == SKIPPABLE {
            let past = "a skippable frame past the end";
            let size = u32_at(input, *at + 4).ok_or(past)?;
            *at = (*at + 8)
                .checked_add(size as usize)
                .filter(|&e| e <= input.len())
                .ok_or(past)?;
            return Ok(None);
        }
        if magic != MAGIC {
            return Err("no LZ4 frame magic number");
        }
        let (flags, bd) = match input.get(*at + 4..*at + 6) {
            Some(&[f, b]) => (f, b),
            _ => return Err("a frame header past the end"),
        };
        if flags >> 6 != 1 {
            return Err("an LZ4 frame of another version");
        }
        let block_max = match (bd >> 4) & 7 {
            4 => 64 << 10,
            5 => 256 << 10,
            6 => 1 << 20,
            7 => 4 << 20,
            _ => return Err("an LZ4 frame's block size is none of 64 KiB, 256 KiB, 1 MiB, 4 MiB"),
        };
        let mut len = 4 + 2 + 1;
        if flags & 0x08 != 0 {
            len += 8;
        }
        if flags & 0x01 != 0 {
            len += 4;
        }
        if *at + len > input.len() {
            return Err("a frame header past the end");
        }
        *at += len;
        Ok(Some(Frame {
            block_max,
            block_checksum: flags & 0x10 != 0,
            content_checksum: flags & 0x04 != 0,
        }))
    }
}
