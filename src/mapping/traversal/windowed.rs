//! The update pass on a windowed (tiled) store: the window index turned
//! into a map cell without a hardware division.

use super::{ScanEvidence, Slot, SEGMENT};
use crate::grid::storage::{Tally, WindowCells};
use crate::grid::{CellModel, Store, Window};

/// `w / d` by one multiplication and a shift, exact for `w < 2^25` and
/// `d < 2^12` (Granlund & Montgomery's division by invariant integers with
/// `m = ceil(2^37 / d)`: the error `m d - 2^37 < 2^12` times `w` stays under
/// `2^37`). A windowed map's window index is `row * stride + column`, and
/// a hardware division per updated cell was a tenth of a real log's build.
#[derive(Clone, Copy)]
pub(super) struct DivideBy {
    magic: u64,
    d: usize,
}

impl DivideBy {
    const SHIFT: u32 = 37;
    const MAX_DIVISOR: usize = 1 << 12;
    const MAX_DIVIDEND: usize = 1 << 25;

    /// `None` for a divisor past the range the multiplication is exact for.
    pub(super) fn new(d: usize) -> Option<Self> {
        (d > 0 && d < Self::MAX_DIVISOR).then(|| Self {
            magic: (1u64 << Self::SHIFT).div_ceil(d as u64),
            d,
        })
    }

    /// `(w / d, w % d)` for `w < 2^25`.
    #[inline(always)]
    pub(super) fn div_rem(self, w: usize) -> (usize, usize) {
        debug_assert!(w < Self::MAX_DIVIDEND);
        let q = ((w as u64 * self.magic) >> Self::SHIFT) as usize;
        (q, w - q * self.d)
    }
}

/// [`Gathered::settle`] on a windowed (tiled) store: each touched window
/// index turned into its map cell by [`DivideBy`], then the update through
/// the store. Clears the slots as it goes.
#[inline(always)]
pub(super) fn settle_windowed<T: Slot, C: CellModel, S: Store<C::Cell>>(
    touched: &[u32],
    slots: &mut [T],
    mask: usize,
    model: &C,
    store: &mut S,
    window: &Window,
    evidence: ScanEvidence,
) {
    let unknown = model.unknown();
    let (x0, y0) = (window.x0, window.y0);
    let Some(rows) = DivideBy::new(window.stride).filter(|_| window.len() < DivideBy::MAX_DIVIDEND)
    else {
        // (Windows are at most 4,095 cells wide, MAX_REACH_CELLS: this is
        // for a store that would gather in wider ones.)
        let cells = &mut store.window_cells(*window, unknown);
        for &w in touched {
            let w = w as usize;
            let slot = &mut slots[w & mask];
            if let Some((cell, updates)) = cells.slot(w) {
                slot.apply(model, cell, updates, evidence);
            }
            *slot = T::UNTOUCHED;
        }
        return;
    };
    // Each touched window index as its map cell, in first-touch order
    // (along the beams: a run of cells shares a tile).
    let cells = touched.iter().map(|&w| {
        let (row, col) = rows.div_rem(w as usize);
        (x0 + col, y0 + row, w as usize)
    });
    store.update_each(cells, unknown, |w, slot| {
        let slot_code = &mut slots[w & mask];
        if let Some((cell, updates)) = slot {
            slot_code.apply(model, cell, updates, evidence);
        }
        *slot_code = T::UNTOUCHED;
    });
}

/// [`Gathered::settle`](super::Gathered) for a gathering by segment: each
/// segment marked in `segments` is a row of one tile of the map (the
/// window starts on a tile's edge and its stride is whole segments), so
/// its tile is found once, and its cells are updated in the order they lie
/// in memory. Clears the slots and the marks; returns the cells updated
/// (the cells holding a verdict, as a touched list would have counted
/// them).
#[inline(never)]
pub(super) fn settle_segments<T: Slot, C: CellModel, S: Store<C::Cell>>(
    slots: &mut [T],
    segments: &mut [u64],
    model: &C,
    store: &mut S,
    window: &Window,
    evidence: ScanEvidence,
) -> usize {
    let unknown = model.unknown();
    let per_row = window.stride / SEGMENT;
    let mut count = 0;
    for (k, word) in segments.iter_mut().enumerate() {
        let mut bits = std::mem::take(word);
        while bits != 0 {
            let segment = k * 64 + bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let Some(codes) = slots.get_mut(segment * SEGMENT..(segment + 1) * SEGMENT) else {
                continue;
            };
            let (row, column) = (segment / per_row, segment % per_row * SEGMENT);
            let (ix, iy) = (window.x0 + column, window.y0 + row);
            match store.tile_row(ix, iy, unknown) {
                Some((cells, updates)) => {
                    let n = cells.len().min(updates.len()).min(SEGMENT);
                    let (cells, updates) = (&mut cells[..n], &mut updates[..n]);
                    for (eight, k0) in codes.chunks_exact_mut(8).zip((0..n).step_by(8)) {
                        let Ok(lanes) = <&mut [T; 8]>::try_from(eight) else {
                            continue;
                        };
                        if T::all_free(lanes) {
                            if let (Some(cells), Some(updates)) =
                                (cells.get_mut(k0..k0 + 8), updates.get_mut(k0..k0 + 8))
                            {
                                for (cell, u) in cells.iter_mut().zip(updates) {
                                    model.miss(cell, evidence.free);
                                    u.add_one();
                                }
                                *lanes = [T::UNTOUCHED; 8];
                                count += 8;
                                continue;
                            }
                        }
                        let mut held = T::held(lanes);
                        // (Cells past the map's east edge hold no verdict:
                        // the walks and fills stay inside the map.)
                        while held != 0 {
                            let k = held.trailing_zeros() as usize / 8;
                            held &= held - 1;
                            let i = k0 + k;
                            if let (Some(cell), Some(u)) = (cells.get_mut(i), updates.get_mut(i)) {
                                lanes[k].apply(model, cell, u, evidence);
                            }
                            lanes[k] = T::UNTOUCHED;
                            count += 1;
                        }
                    }
                }
                None => {
                    count += codes.iter().filter(|&&c| c != T::UNTOUCHED).count();
                    codes.fill(T::UNTOUCHED);
                }
            }
        }
    }
    count
}
