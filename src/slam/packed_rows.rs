//! A finished submap's bytes at rest: each row run-length coded on its
//! own, so that the grid is restored a slice of rows at a time when a
//! loop search needs it ([`super::loop_search::LoopGrid`]).
//!
//! Most of a submap's box is unknown (0) or free space far from any wall,
//! where neighbouring cells hold the same byte: on the Freiburg campus its
//! 199 finished submaps hold 155.7 M bytes in 23.8 M runs, and this code
//! keeps them in 40.8 M (docs/ARCHITECTURE.md, "SLAM's memory").
//!
//! The code of a row is a sequence of runs, each a control byte `c` and
//! its bytes: `c < 128` is `c + 1` bytes as they are; `c >= 128` is one
//! byte repeated `c - 125` times (3 to 130).

/// Longest run of bytes copied as they are.
const MOST_LITERAL: usize = 128;
/// Shortest and longest repeat.
const LEAST_REPEAT: usize = 3;
const MOST_REPEAT: usize = 130;

/// Rows of bytes, each coded on its own.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PackedRows {
    code: Vec<u8>,
    /// Where each row's code starts in `code`, and one past the last.
    starts: Vec<u32>,
}

impl PackedRows {
    /// `cells` (rows of `width` bytes, at least one byte a row unless
    /// empty) coded row by row.
    pub fn pack(cells: &[u8], width: usize) -> Self {
        let rows = cells.len().checked_div(width).unwrap_or(0);
        let mut code = Vec::new();
        let mut starts = Vec::with_capacity(rows + 1);
        starts.push(0);
        for row in cells.chunks_exact(width.max(1)).take(rows) {
            pack_row(row, &mut code);
            starts.push(code.len() as u32);
        }
        code.shrink_to_fit();
        Self { code, starts }
    }

    /// Rows held.
    pub fn rows(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// Bytes the code takes.
    pub fn bytes(&self) -> usize {
        self.code.len() + 4 * self.starts.len()
    }

    /// Row `y` decoded into `out` (`width` bytes; nothing for a row not
    /// held).
    pub fn unpack_row(&self, y: usize, out: &mut [u8]) {
        let (Some(&a), Some(&b)) = (self.starts.get(y), self.starts.get(y + 1)) else {
            return;
        };
        let Some(mut code) = self.code.get(a as usize..b as usize) else {
            return;
        };
        let mut at = 0;
        while let Some((&c, rest)) = code.split_first() {
            let c = c as usize;
            if c < MOST_LITERAL {
                let n = c + 1;
                let (Some(bytes), Some(to)) = (rest.get(..n), out.get_mut(at..at + n)) else {
                    return;
                };
                to.copy_from_slice(bytes);
                code = &rest[n..];
                at += n;
            } else {
                let n = c - MOST_LITERAL + LEAST_REPEAT;
                let (Some(&byte), Some(to)) = (rest.first(), out.get_mut(at..at + n)) else {
                    return;
                };
                to.fill(byte);
                code = &rest[1..];
                at += n;
            }
        }
    }
}

/// Appends the code of `row` to `code`.
fn pack_row(row: &[u8], code: &mut Vec<u8>) {
    let mut literal_from = 0;
    let mut i = 0;
    let flush_literal = |code: &mut Vec<u8>, bytes: &[u8]| {
        for chunk in bytes.chunks(MOST_LITERAL) {
            code.push((chunk.len() - 1) as u8);
            code.extend_from_slice(chunk);
        }
    };
    while i < row.len() {
        let byte = row[i];
        let run = row[i..]
            .iter()
            .take(MOST_REPEAT)
            .take_while(|&&b| b == byte)
            .count();
        if run >= LEAST_REPEAT {
            flush_literal(code, &row[literal_from..i]);
            code.push((MOST_LITERAL + run - LEAST_REPEAT) as u8);
            code.push(byte);
            i += run;
            literal_from = i;
        } else {
            i += run;
        }
    }
    flush_literal(code, &row[literal_from..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn restored(p: &PackedRows, width: usize) -> Vec<u8> {
        let mut out = vec![0xAA; width * p.rows()];
        for (y, row) in out.chunks_exact_mut(width).enumerate() {
            p.unpack_row(y, row);
        }
        out
    }

    #[test]
    fn rows_of_runs_and_noise_come_back_byte_for_byte() {
        let (w, h) = (517, 9);
        let mut state = 0x2545_f491u32;
        let mut noise = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        let cells: Vec<u8> = (0..w * h)
            .map(|i| match (i / w, i % w) {
                (0, _) => 0,
                (1, x) => (x / 140) as u8,
                (2, x) => (x % 3 == 0) as u8,
                (3, x) if x < 300 => 7,
                _ => (noise() % 4) as u8 * 60,
            })
            .collect();
        let p = PackedRows::pack(&cells, w);
        assert_eq!(p.rows(), h);
        assert_eq!(restored(&p, w), cells);
        // A row of one byte takes two bytes a 130.
        let one = PackedRows::pack(&vec![0; w], w);
        assert_eq!(one.code.len(), 2 * w.div_ceil(MOST_REPEAT));
    }

    #[test]
    fn an_empty_grid_packs_to_no_rows() {
        let p = PackedRows::pack(&[], 0);
        assert_eq!(p.rows(), 0);
        p.unpack_row(0, &mut []);
    }
}
