//! The ray traversal: Table 9.1's recursion applied along each beam.
//!
//! * [`RayMapper`] — the production path. Each beam is rastered with a
//!   supercover line from the sensor out to the model's reach
//!   (`min(z_max, z + alpha/2)` for Table 9.2). Cells near the sensor lie on
//!   many beams, so the verdicts of one scan are gathered first and every
//!   touched cell is updated once, occupied evidence winning over free
//!   (Cartographer's range-data inserter does the same: hits, then misses,
//!   each cell once per scan). The result then does not depend on beam
//!   order, and the cost follows the cells the beams cross, not the map.
//!   The walk carries each cell's index and range along the beam from cell
//!   to cell; when the model states its evidence along the beam as a step
//!   function of range ([`crate::inverse::AxisProfile`], as Table 9.2 can),
//!   a cell's verdict is two comparisons of that range. When every beam of
//!   the scan shares the same two values (free below zero, occupied above),
//!   the verdicts are gathered as flags in a byte per cell; otherwise as a
//!   float per cell.
//! * [`super::sweep::sweep_scan`] — Table 9.1 as printed, every cell of the
//!   map (what a wide cone needs).

use crate::geometry::raster::{Cursor, Walk};
use crate::grid::storage::{StoredCell, Tally, WindowCells};
use crate::grid::{CellModel, Grid, Store, Window};
use crate::inverse::{AxisProfile, InverseModel};

use crate::sensors::Scan;

/// The work one scan cost.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct ScanStats {
    /// Cells the mapper looked at (raster visits for the traversal, every
    /// cell of the map for the sweep).
    pub cells_visited: usize,
    /// Cells whose log odds were updated.
    pub cells_updated: usize,
}

/// Scratch mark of a cell no beam of the current scan has given evidence.
/// Any real verdict is larger, so "keep the larger" needs no extra test,
/// and a cell is new to the scan exactly when it still holds the mark.
const UNTOUCHED: f32 = f32::NEG_INFINITY;

/// The ray-traversal mapper, with its per-scan scratch space (kept between
/// scans so that integrating a scan allocates nothing). Every per-cell
/// slot is clear again between scans: the update pass clears the slots it
/// applies.
#[derive(Debug, Default, Clone)]
pub struct RayMapper {
    /// Per cell, the verdict code of the current scan (step-profile path).
    codes: Vec<u8>,
    /// Per cell, the evidence the current scan has gathered for it (log
    /// odds net of `l0`), or [`UNTOUCHED`] (general path).
    pending: Vec<f32>,
    /// The cells touched in the current scan, in first-touch order.
    touched: Vec<u32>,
    /// A bit per segment of the window holding a verdict of the current
    /// scan (the bands' path on a windowed map, see [`Gathered`]).
    segments: Vec<u64>,
    /// The current scan's reach and axis profile per beam (step-profile
    /// path; `None` for a beam with nothing to walk).
    profiles: Vec<Option<(f64, AxisProfile)>>,
    /// `(sin, cos)` of each bearing of the last scan, and those bearings:
    /// a scanner's bearings rarely change from scan to scan, so a beam's
    /// direction costs four products instead of two library calls (which
    /// in wasm are software routines).
    bearings: Vec<f64>,
    bearing_trig: Vec<(f64, f64)>,
    /// The current scan's wedges between neighbouring beams (with the
    /// space between beams only).
    wedges: Vec<Option<between::Wedge>>,
    /// The current scan's fans of beams near the sensor.
    fans: fans::Fans,
}

impl RayMapper {
    pub fn new() -> Self {
        Self::default()
    }

    /// Integrates one scan into `grid` with the inverse model `model`.
    ///
    /// Each cell on a beam's raster gets the model's evidence for its range
    /// along the beam axis (the projection of its centre), at bearing offset
    /// zero: a thin beam's raster *is* its footprint. Every input was
    /// validated when the scan and model were built, so this cannot fail.
    pub fn integrate<M: InverseModel + ?Sized, C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        model: &M,
        scan: &Scan,
    ) -> ScanStats {
        self.cache_bearing_trig(scan.bearings());
        let reach = scan
            .ranges()
            .iter()
            .map(|&z| model.reach(z))
            .fold(0.0, f64::max);
        let Some(frame) = BeamFrame::new::<C, S>(grid.geometry(), &scan.pose(), reach) else {
            return ScanStats::default();
        };
        match self.step_profiles(model, scan.ranges()) {
            Some(evidence) => self.integrate_step_profiles(grid, &frame, evidence),
            None => self.integrate_general(grid, model, scan, &frame),
        }
    }

    /// Fills `profiles` with each beam's reach and axis profile, and
    /// returns the scan's free and occupied evidence when every beam states
    /// its evidence as a step function with those same two values, free
    /// negative and occupied positive (Table 9.2 and the like). `None` sends the scan down the
    /// general path.
    fn step_profiles<M: InverseModel + ?Sized>(
        &mut self,
        model: &M,
        ranges: &[f64],
    ) -> Option<ScanEvidence> {
        self.profiles.clear();
        let mut evidence: Option<ScanEvidence> = None;
        for &z in ranges {
            let reach = model.reach(z);
            #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN reach is no beam
            if !(reach > 0.0) {
                self.profiles.push(None);
                continue;
            }
            let p = model.axis_profile(z)?;
            let these = ScanEvidence {
                free: p.free,
                occupied: p.occupied,
            };
            // A band whose evidence is zero carries no information and must
            // not count as an update: the general path leaves such cells
            // out. Free lowers the log odds and occupied raises them, so
            // each needs only one side of the clamp.
            if !(these.free < 0.0 && these.occupied > 0.0) {
                return None;
            }
            match evidence {
                None => evidence = Some(these),
                Some(b) if b.same(these) => {}
                Some(_) => return None,
            }
            self.profiles.push(Some((reach, p)));
        }
        // A scan without a beam to walk has no evidence to apply.
        Some(evidence.unwrap_or(ScanEvidence {
            free: -1.0,
            occupied: 1.0,
        }))
    }

    /// A scan whose beams share one free and one occupied value
    /// ([`Self::step_profiles`]): a cell's verdicts are then two flags
    /// (free, occupied) in a byte per cell, and "occupied wins" is reading
    /// the occupied flag first. A map of bytes is a quarter of a map of
    /// floats, and stays in cache.
    fn integrate_step_profiles<C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        frame: &BeamFrame,
        evidence: ScanEvidence,
    ) -> ScanStats {
        let mut gathered = frame.codes(&mut self.codes, &mut self.touched);
        let mut visits = 0;
        for (profile, &trig) in self.profiles.iter().zip(&self.bearing_trig) {
            let Some((reach, p)) = *profile else { continue };
            let Some((walk, at)) = frame.beam(trig, reach) else {
                continue;
            };
            let n;
            (n, gathered) = trace(walk, at, StepCodes(p), gathered);
            visits += n;
        }

        let count = gathered.settle(grid, &frame.window, evidence);
        ScanStats {
            cells_visited: visits,
            cells_updated: count,
        }
    }

    /// The general path: each cell's evidence is gathered as a float (the
    /// larger wins per cell), then every touched cell is updated once.
    fn integrate_general<M: InverseModel + ?Sized, C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        model: &M,
        scan: &Scan,
        frame: &BeamFrame,
    ) -> ScanStats {
        let mut gathered = frame.pending(&mut self.pending, &mut self.touched);
        let mut visits = 0;
        for (&z, &trig) in scan.ranges().iter().zip(&self.bearing_trig) {
            let reach = model.reach(z);
            #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN reach is no beam
            if !(reach > 0.0) {
                continue;
            }
            let Some((walk, at)) = frame.beam(trig, reach) else {
                continue;
            };
            let n;
            (n, gathered) = match model.axis_profile(z) {
                // Two comparisons per cell. (A band whose evidence is zero
                // carries no information and must not count as an update:
                // such a profile takes the per-cell branch.)
                Some(p) if p.free != 0.0 && p.occupied != 0.0 => {
                    trace(walk, at, StepEvidence(p), gathered)
                }
                _ => trace(walk, at, ModelEvidence { model, z }, gathered),
            };
            visits += n;
        }

        // (The floats are the evidence itself: nothing to look up.)
        let count = gathered.settle(
            grid,
            &frame.window,
            ScanEvidence {
                free: 0.0,
                occupied: 0.0,
            },
        );
        ScanStats {
            cells_visited: visits,
            cells_updated: count,
        }
    }

    /// Makes `bearing_trig` hold `(sin, cos)` of `bearings`.
    fn cache_bearing_trig(&mut self, bearings: &[f64]) {
        // Every bearing compared, no early exit: a loop without branches
        // (the bearings almost always all match).
        let same = self.bearings.len() == bearings.len()
            && self
                .bearings
                .iter()
                .zip(bearings)
                .fold(true, |same, (a, b)| same & (a.to_bits() == b.to_bits()));
        if !same {
            self.bearings.clear();
            self.bearings.extend_from_slice(bearings);
            self.bearing_trig.clear();
            self.bearing_trig
                .extend(bearings.iter().map(|b| b.sin_cos()));
        }
    }
}

/// One beam's evidence along its axis for [`RayMapper::integrate_bands`]:
/// free for `r <= free_until`, nothing up to `occupied_from`, occupied for
/// `occupied_from < r <= occupied_until`, nothing beyond. The walk stops at
/// `reach`. (Table 9.2 is the case `occupied_from == free_until`; a gap
/// lets a mapper withhold free evidence near a reading without marking it
/// occupied.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamBand {
    pub reach: f64,
    pub free_until: f64,
    pub occupied_from: f64,
    pub occupied_until: f64,
}

/// The most cells a beam of a windowed (tiled) map may reach from its
/// sensor (range cap over resolution): the scan's window of `(2 n + 5)^2`
/// cells then stays within 2^24, its scratch within 80 MiB.
pub const MAX_REACH_CELLS: f64 = 2045.0;

/// A model's evidence is finite by contract. Should one return NaN, it is
/// read as "no information"; minus infinity as the most negative finite
/// verdict (the grid's clamp makes the two equivalent). Either way the
/// [`UNTOUCHED`] mark stays unambiguous.
#[inline(always)]
fn sanitize(e: f32) -> f32 {
    if e.is_nan() {
        0.0
    } else if e < f32::MIN {
        f32::MIN
    } else {
        e
    }
}

/// The free and occupied evidence (net of `l0`) shared by every beam of a
/// scan on the step-profile path.
#[derive(Debug, Clone, Copy)]
struct ScanEvidence {
    free: f32,
    occupied: f32,
}

impl ScanEvidence {
    fn same(self, other: ScanEvidence) -> bool {
        self.free.to_bits() == other.free.to_bits()
            && self.occupied.to_bits() == other.occupied.to_bits()
    }
}

/// A cell's verdicts on the step-profile path, as flags: a cell that any
/// beam found occupied has the occupied flag, and "occupied wins" is
/// reading that flag first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Code {
    Untouched = 0,
    Free = 1,
    Occupied = 2,
}

/// A cell's verdicts as gathered in one scan; `UNTOUCHED` until a beam
/// gives evidence.
trait Slot: Copy + PartialEq {
    const UNTOUCHED: Self;
    /// A cell's verdicts so far, `self`, merged with a beam's verdict `v`.
    fn merge(self, v: Self) -> Self;
    /// Applies the evidence this verdict stands for (given the scan's
    /// `evidence`) to a cell of the model `model`, and counts the update.
    fn apply<C: CellModel>(
        self,
        model: &C,
        cell: &mut C::Cell,
        updates: &mut <C::Cell as StoredCell>::Updates,
        evidence: ScanEvidence,
    );
    /// Merges `v` into every slot of `row`.
    #[inline(always)]
    fn merge_row(row: &mut [Self], v: Self) {
        for slot in row {
            *slot = slot.merge(v);
        }
    }
    /// True when each of eight slots holds the free verdict and nothing
    /// else (the update pass then misses all eight in one go: the bulk of
    /// a scan's cells lie in its free space).
    #[inline(always)]
    fn all_free(_: &[Self; 8]) -> bool {
        false
    }
    /// Of eight slots, which hold a verdict: bit `8 k + 7` set for slot
    /// `k` (the update pass visits only those, without a branch per slot).
    #[inline(always)]
    fn held(slots: &[Self; 8]) -> u64 {
        slots.iter().enumerate().fold(0, |m, (k, &s)| {
            m | ((s != Self::UNTOUCHED) as u64) << (8 * k + 7)
        })
    }
}

/// [`Code`] flags (step-profile path).
impl Slot for u8 {
    const UNTOUCHED: u8 = Code::Untouched as u8;
    #[inline(always)]
    fn merge(self, v: u8) -> u8 {
        self | v
    }
    #[inline(always)]
    fn all_free(slots: &[u8; 8]) -> bool {
        u64::from_le_bytes(*slots) == u64::from_le_bytes([Code::Free as u8; 8])
    }
    /// Eight codes at a time (a word's bytes or-ed at once).
    #[inline(always)]
    fn merge_row(row: &mut [u8], v: u8) {
        let word = u64::from_le_bytes([v; 8]);
        let mut eights = row.chunks_exact_mut(8);
        for eight in &mut eights {
            if let Ok(eight) = <&mut [u8; 8]>::try_from(eight) {
                *eight = (u64::from_le_bytes(*eight) | word).to_le_bytes();
            }
        }
        for slot in eights.into_remainder() {
            *slot |= v;
        }
    }
    /// Eight codes as one word: a lane's high bit is set when any of its
    /// bits is (codes are below 128, so the sum never carries between
    /// lanes).
    #[inline(always)]
    fn held(slots: &[u8; 8]) -> u64 {
        const LOW7: u64 = 0x7f7f_7f7f_7f7f_7f7f;
        let w = u64::from_le_bytes(*slots);
        (((w & LOW7) + LOW7) | w) & !LOW7
    }
    /// (The evidence's signs are known, see [`RayMapper::step_profiles`], so
    /// each update needs one side of the clamp only.)
    #[inline(always)]
    fn apply<C: CellModel>(
        self,
        model: &C,
        cell: &mut C::Cell,
        updates: &mut <C::Cell as StoredCell>::Updates,
        evidence: ScanEvidence,
    ) {
        if self & Code::Occupied as u8 != 0 {
            model.hit(cell, evidence.occupied)
        } else {
            model.miss(cell, evidence.free)
        }
        updates.add_one();
    }
}

/// Log odds net of `l0` (general path). Occupied (positive) wins over
/// free; between two free verdicts the weaker one stands.
impl Slot for f32 {
    const UNTOUCHED: f32 = UNTOUCHED;
    #[inline(always)]
    fn merge(self, v: f32) -> f32 {
        if v > self {
            v
        } else {
            self
        }
    }
    #[inline(always)]
    fn apply<C: CellModel>(
        self,
        model: &C,
        cell: &mut C::Cell,
        updates: &mut <C::Cell as StoredCell>::Updates,
        _: ScanEvidence,
    ) {
        model.add(cell, self);
        updates.add_one();
    }
}

/// Where a scan's verdicts are gathered, at most one per cell: a slot per
/// cell, and the list of cells touched so far, in first-touch order (a cell
/// enters at most once per scan, so a list longer than the map never
/// overflows). Merging verdicts (flags or-ed, the larger float kept) is
/// symmetric, so beam order does not matter.
///
/// Both buffers are `mask + 1` long, a power of two, and are indexed with
/// `& mask`: the compiler then sees every index in range and drops the
/// bounds checks from the per-cell loop. The mask never changes an index:
/// the walk stays inside the map, and the count below the number of cells.
///
/// `SEGMENTED` (a windowed map's bands): instead of the touched list, a
/// bit per segment of [`SEGMENT`] window cells marks the segments holding
/// a verdict, and the update pass walks those segments, each a row of one
/// tile of the map: a tile is looked up once a segment rather than once a
/// cell, and the cells are written in the order they lie in memory.
struct Gathered<'a, T, const SEGMENTED: bool = false> {
    slots: &'a mut [T],
    touched: &'a mut [u32],
    segments: &'a mut [u64],
    mask: usize,
    count: usize,
}

/// Window cells per segment: a tile's row ([`crate::grid::storage::TILE_SIDE`]).
const SEGMENT: usize = crate::grid::storage::TILE_SIDE;
const SEGMENT_SHIFT: u32 = SEGMENT.trailing_zeros();

impl<'a, T: Slot, const SEGMENTED: bool> Gathered<'a, T, SEGMENTED> {
    /// `slots` has a power-of-two length; `touched` the same length, or
    /// (segmented) `segments` a bit per segment of the slots.
    fn new(slots: &'a mut [T], touched: &'a mut [u32], segments: &'a mut [u64]) -> Self {
        debug_assert!(slots.len().is_power_of_two());
        debug_assert!(if SEGMENTED {
            segments.len() * 64 * SEGMENT >= slots.len()
        } else {
            touched.len() == slots.len()
        });
        let mask = slots.len() - 1;
        Self {
            slots,
            touched,
            segments,
            mask,
            count: 0,
        }
    }

    /// The same gathering with its buffers resliced to exactly `mask + 1`
    /// entries, done inside the function that loops, so that the compiler
    /// knows the length there.
    #[inline(always)]
    fn narrowed(self) -> Self {
        let mask = self.mask;
        Self {
            slots: &mut self.slots[..=mask],
            touched: if SEGMENTED {
                self.touched
            } else {
                &mut self.touched[..=mask]
            },
            ..self
        }
    }

    /// Records verdict `v` for cell `i`, without a branch on whether the
    /// cell is new to the scan: the cell is written past the end of the
    /// touched list, which only grows when the cell was untouched. Where
    /// beams start to fan apart, that follows no pattern a branch predictor
    /// can learn.
    #[inline(always)]
    fn record(&mut self, i: usize, v: T) {
        let slot = &mut self.slots[i & self.mask];
        let old = *slot;
        let new = old.merge(v);
        *slot = new;
        if SEGMENTED {
            let segment = (i & self.mask) >> SEGMENT_SHIFT;
            if let Some(word) = self.segments.get_mut(segment >> 6) {
                *word |= 1 << (segment & 63);
            }
        } else {
            self.touched[self.count & self.mask] = i as u32;
            self.count += (old == T::UNTOUCHED && new != T::UNTOUCHED) as usize;
        }
    }

    /// Table 9.1's update, once per touched cell, written through the
    /// map's store (window index `w` is a dense map's cell index); every
    /// slot is clear again afterwards, so no map-sized clearing is ever
    /// needed. Four cells per loop turn: under Node the loop's own
    /// bookkeeping (a stack check and a counter per turn) is a sizeable
    /// share of this short body. A cell its store cannot hold (past a
    /// tiled map's budget) is left out; the store says so.
    #[inline(always)]
    fn settle<C: CellModel, S: Store<C::Cell>>(
        self,
        grid: &mut Grid<C, S>,
        window: &Window,
        evidence: ScanEvidence,
    ) -> usize {
        let Self {
            slots,
            touched,
            segments,
            mask,
            count,
        } = self.narrowed();
        let (model, store) = grid.model_and_store();
        if SEGMENTED {
            return settle_segments(slots, segments, model, store, window, evidence);
        }
        if S::WINDOWED {
            settle_windowed(
                &touched[..count],
                slots,
                mask,
                model,
                store,
                window,
                evidence,
            );
            return count;
        }
        let cells = &mut store.window_cells(*window, model.unknown());
        // (A function rather than a closure: at opt-level "s" a closure
        // called from several places stays a call.)
        #[inline(always)]
        fn settle_one<T: Slot, C: CellModel, W: WindowCells<C::Cell>>(
            slots: &mut [T],
            mask: usize,
            model: &C,
            cells: &mut W,
            evidence: ScanEvidence,
            w: u32,
        ) {
            let w = w as usize;
            let slot = &mut slots[w & mask];
            if let Some((cell, updates)) = cells.slot(w) {
                slot.apply(model, cell, updates, evidence);
            }
            *slot = T::UNTOUCHED;
        }
        let mut fours = touched[..count].chunks_exact(4);
        for four in &mut fours {
            settle_one(slots, mask, model, cells, evidence, four[0]);
            settle_one(slots, mask, model, cells, evidence, four[1]);
            settle_one(slots, mask, model, cells, evidence, four[2]);
            settle_one(slots, mask, model, cells, evidence, four[3]);
        }
        for &w in fours.remainder() {
            settle_one(slots, mask, model, cells, evidence, w);
        }
        count
    }
}

impl<T, const SEGMENTED: bool> Gathered<'_, T, SEGMENTED> {
    /// The length of the buffers for a map of `cells` cells: a power of
    /// two, and more than `cells`, so that the touched list always has a
    /// spare entry past its end (see [`Gathered::record`]).
    fn len_for(cells: usize) -> usize {
        (cells + 1).next_power_of_two()
    }
}

/// Verdicts as codes, for a scan whose beams share one free and one
/// occupied value.
type Codes<'a> = Gathered<'a, u8>;

/// Verdicts as log odds (net of `l0`), for any model.
type Pending<'a> = Gathered<'a, f32>;

/// A beam's verdict on the cell under the cursor, from the range of the
/// cell's centre along the beam axis. (Methods rather than closures: they
/// must be inlined into the walk, which calls them from several places.)
trait Verdict<G> {
    fn visit(&self, r: f64, i: usize, gathered: &mut G);
}

/// A step profile, as codes: free up to `free_until`, then occupied.
struct StepCodes(AxisProfile);

impl Verdict<Codes<'_>> for StepCodes {
    #[inline(always)]
    fn visit(&self, r: f64, i: usize, gathered: &mut Codes) {
        if r <= self.0.free_until {
            gathered.record(i, Code::Free as u8);
        } else if r <= self.0.occupied_until {
            gathered.record(i, Code::Occupied as u8);
        }
    }
}

/// A [`BeamBand`], as codes.
struct BandCodes(BeamBand);

impl<const SEGMENTED: bool> Verdict<Gathered<'_, u8, SEGMENTED>> for BandCodes {
    #[inline(always)]
    fn visit(&self, r: f64, i: usize, gathered: &mut Gathered<'_, u8, SEGMENTED>) {
        let b = &self.0;
        if r <= b.free_until {
            gathered.record(i, Code::Free as u8);
        } else if r > b.occupied_from && r <= b.occupied_until {
            gathered.record(i, Code::Occupied as u8);
        }
    }
}

/// A step profile, as log odds.
struct StepEvidence(AxisProfile);

impl Verdict<Pending<'_>> for StepEvidence {
    #[inline(always)]
    fn visit(&self, r: f64, i: usize, gathered: &mut Pending) {
        if r <= self.0.free_until {
            gathered.record(i, self.0.free);
        } else if r <= self.0.occupied_until {
            gathered.record(i, self.0.occupied);
        }
    }
}

/// Any model, asked per cell.
struct ModelEvidence<'m, M: ?Sized> {
    model: &'m M,
    z: f64,
}

impl<M: InverseModel + ?Sized> Verdict<Pending<'_>> for ModelEvidence<'_, M> {
    #[inline(always)]
    fn visit(&self, r: f64, i: usize, gathered: &mut Pending) {
        let e = sanitize(self.model.evidence(r, 0.0, self.z));
        if e != 0.0 {
            gathered.record(i, e);
        }
    }
}

/// Walks one beam, handing each cell's verdict to `gathered`; returns the
/// number of visits and the gathering. (Inlined into the loop over the
/// beams: under Node a call per beam, its arguments passed through memory,
/// cost more than the registers the loop gives up.)
#[inline(always)]
fn trace<'a, T: Slot, V: Verdict<Gathered<'a, T, SEGMENTED>>, const SEGMENTED: bool>(
    walk: Walk,
    at: BeamState,
    verdict: V,
    gathered: Gathered<'a, T, SEGMENTED>,
) -> (usize, Gathered<'a, T, SEGMENTED>) {
    let mut cursor = BeamCursor {
        at,
        gathered: gathered.narrowed(),
        verdict,
    };
    let visits = walk.run(&mut cursor);
    (visits, cursor.gathered)
}

/// The mapper's [`Cursor`]: the verdict on the cell under it, gathered.
struct BeamCursor<G, V> {
    at: BeamState,
    gathered: G,
    verdict: V,
}

impl<G, V: Verdict<G>> Cursor for BeamCursor<G, V> {
    #[inline(always)]
    fn visit(&mut self) {
        self.verdict
            .visit(self.at.range, self.at.index, &mut self.gathered);
    }
    #[inline(always)]
    fn step_x(&mut self) {
        self.at.index = self.at.index.wrapping_add_signed(self.at.index_step.0);
        self.at.range += self.at.range_step.0;
    }
    #[inline(always)]
    fn step_y(&mut self) {
        self.at.index = self.at.index.wrapping_add_signed(self.at.index_step.1);
        self.at.range += self.at.range_step.1;
    }
    #[inline(always)]
    fn unstep_x(&mut self) {
        self.at.index = self.at.index.wrapping_add_signed(-self.at.index_step.0);
        self.at.range -= self.at.range_step.0;
    }
}

mod bands;
mod between;
mod fans;
mod frame;
use frame::{BeamFrame, BeamState};
mod windowed;
use windowed::{settle_segments, settle_windowed};

#[cfg(test)]
mod fan_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod wedge_tests;
