//! The update pass on a windowed (tiled) store: the window index turned
//! into a map cell without a hardware division.

use super::{ScanEvidence, Slot};
use crate::grid::storage::WindowCells;
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
