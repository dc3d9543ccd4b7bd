//! Fans: consecutive wedges between beams filled together, in long
//! lines of cells ([`super::RayMapper::integrate_bands_between`],
//! docs/ARCHITECTURE.md, "Real logs").
//!
//! * Near the sensor, neighbouring beams' axes are less than a cell apart
//!   and the wedges between them start only further out (see `between`);
//!   a beam walked from the sensor shares most of its cells there with
//!   its neighbours (out to 5.2 m for 0.5° at 5 cm, some 45,000 visits a
//!   scan for 17,000 cells). Where consecutive wedges are free out to one
//!   radius, their near triangles make a fan with the sensor at its
//!   corner: it is filled, each cell once, and a beam inside it is walked
//!   only where its cells may lie outside it.
//! * Far out, a wedge alone is filled in lines across it, as many as it is
//!   long (five cells each on the campus); wedges side by side whose free
//!   ends lie close together are filled as one fan out to the nearest end,
//!   sharing their lines, and each wedge alone only beyond it.
//!
//! Each fan holds only cells whose centres the walks and wedges it stands
//! for held, and they hold every cell it leaves out (`fan_tests`).

// A test written `!(a < b)` is also true when either is not a number: a
// fan with such a bound fills nothing.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::between::{ceil_at_least, Lines, Wedge};
use super::{BeamFrame, Gathered, Slot, SEGMENT_SHIFT};

/// The widest convex piece a fan is filled in, radians: a polygon with the
/// sensor as a corner and its other corners on an arc is convex while the
/// arc is at most half a turn.
const MAX_PIECE: f64 = std::f64::consts::FRAC_PI_2;

/// How far a supercover walk's cells lie from its axis, at most, in cells
/// (half a cell's diagonal), with a margin.
const WALK_SPREAD: f64 = 0.75;

/// `cos(2.5°)`: the chords of a fan's corners lie at least this part of
/// its radius from the sensor, for beams at most 5° apart (the widest the
/// wedges pair, `between::MAX_BEAM_SPACING`).
const MAX_HALF_SPACING_COS: f64 = 0.999_048_2;

/// The wedges of a far fan end within this part of each other.
const FAR_RATIO: f64 = 0.75;
/// The fewest wedges a far fan holds.
const FAR_MIN_WEDGES: usize = 3;
/// A far fan reaches at least this many times the wedges' start.
const FAR_MIN_GAIN: f64 = 1.5;

/// A fan's planning and scratch space, kept between scans.
#[derive(Debug, Default, Clone)]
pub(super) struct Fans {
    /// Per beam, the part of its walk a fan holds ([`Self::held`]).
    held: Vec<(f64, f64)>,
    /// Per wedge, where a far fan ends (the wedge's own fill starts
    /// there), or minus infinity.
    wedge_from: Vec<f64>,
    /// Per row of the piece being filled, the lowest and highest column
    /// coordinate of the polygon's edges there.
    lo: Vec<f64>,
    hi: Vec<f64>,
    corners: Vec<(f64, f64)>,
}

impl Fans {
    /// The part of beam `i`'s walk a fan holds, `(from, to)` metres along
    /// it: the beam is walked out to `from`, and on from `to` (or from
    /// where its wedges' fills end, if later). Empty (`from >= to`) when no
    /// fan holds the beam.
    #[inline(always)]
    pub(super) fn held(&self, i: usize) -> (f64, f64) {
        self.held
            .get(i)
            .copied()
            .unwrap_or((f64::INFINITY, f64::INFINITY))
    }

    /// Plans and fills the fans of a scan (wedges from
    /// [`super::between::plan_wedges`], bearings `bearings` with
    /// `(sin, cos)` in `trig`) into `gathered` as free verdicts, and notes
    /// the part of each beam inside a fan that a walk no longer needs.
    /// Returns the cells filled and the gathering.
    pub(super) fn fill<'a, const SEGMENTED: bool>(
        &mut self,
        frame: &BeamFrame,
        wedges: &[Option<Wedge>],
        bearings: &[f64],
        trig: &[(f64, f64)],
        mut gathered: Gathered<'a, u8, SEGMENTED>,
    ) -> (usize, Gathered<'a, u8, SEGMENTED>) {
        let n = wedges.len().min(bearings.len()).min(trig.len());
        self.held.clear();
        self.held.resize(n, (f64::INFINITY, f64::INFINITY));
        let res = frame.res;
        // How far a wedge's near triangle is free: out to where its fill
        // starts (nearer, its beams' walks held every cell of it), or to
        // the nearer of its beams' free ranges (a no-return's reach, or a
        // reading closer than that start).
        let near = |k: usize| {
            wedges[k]
                .map(|w| w.from().min(w.to()))
                .filter(|&r| r > 2.0 * res)
        };
        let turn = |k: usize| bearings[k] - bearings[k - 1];
        let mut filled = 0;
        let mut k = 1;
        while k < n {
            let Some(r0) = near(k) else {
                k += 1;
                continue;
            };
            // The fan runs from beam `k - 1` over the wedges `k ..= last`
            // (beams `k - 1` and `last` its edges, walked as planned); a
            // wedge joins while its triangle is free as far and it turns
            // the same way.
            let joins = |j: usize| {
                near(j).is_some_and(|r| (r - r0).abs() <= 1e-9 * r0)
                    && (turn(j) > 0.0) == (turn(k) > 0.0)
            };
            let mut last = k;
            while last + 1 < n && joins(last + 1) {
                last += 1;
            }
            let first = k - 1;
            k = last + 1;
            if last - first < 2 {
                // No beam inside.
                continue;
            }
            // Every corner on the arc at the fan's largest radius (they
            // differ by rounding at most).
            let radius = (first + 1..=last).filter_map(near).fold(r0, f64::max);
            let n_filled;
            (n_filled, gathered) =
                self.fill_fan(frame, (first, last), radius, bearings, trig, gathered);
            let Some(n_filled) = n_filled else {
                continue;
            };
            filled += n_filled;
            // A cell a walk reaches at `t` cells along its beam has its
            // centre within `WALK_SPREAD` of the point at `t`: less than
            // `delta` off the beam's bearing once
            // `t >= WALK_SPREAD + WALK_SPREAD / tan(delta)`, and nearer the
            // sensor than `t + WALK_SPREAD`. Inside the fan's bearings, a
            // centre nearer than its chords (`radius cos(spacing / 2)`)
            // lies in it.
            let chord = radius * frame.per_metre * MAX_HALF_SPACING_COS;
            for b in first + 1..last {
                let delta = (bearings[b] - bearings[first])
                    .abs()
                    .min((bearings[last] - bearings[b]).abs())
                    .min(std::f64::consts::FRAC_PI_4);
                let from = WALK_SPREAD + 0.25 + WALK_SPREAD / delta.tan();
                let to = chord - WALK_SPREAD - 0.25;
                if from < to {
                    self.held[b] = (from * res, to * res);
                }
            }
        }
        let n_far;
        (n_far, gathered) = self.fill_far(frame, wedges, bearings, trig, gathered);
        (filled + n_far, gathered)
    }

    /// Where the fill of wedge `k` starts, metres, if a far fan holds its
    /// nearer part (else its own start).
    pub(super) fn wedge_from(&self, k: usize, from: f64) -> f64 {
        match self.wedge_from.get(k) {
            Some(&f) if f > from => f,
            _ => from,
        }
    }

    /// The far fans of a scan: consecutive wedges that are free beyond
    /// where their fill starts, and whose free ends lie within
    /// [`FAR_RATIO`] of each other, are filled together out to the nearest
    /// of those ends (from the sensor, as a convex fan), and each wedge
    /// then only beyond it. A wedge alone is filled in lines across it, as
    /// many as it is long; side by side, wedges share their lines.
    fn fill_far<'a, const SEGMENTED: bool>(
        &mut self,
        frame: &BeamFrame,
        wedges: &[Option<Wedge>],
        bearings: &[f64],
        trig: &[(f64, f64)],
        mut gathered: Gathered<'a, u8, SEGMENTED>,
    ) -> (usize, Gathered<'a, u8, SEGMENTED>) {
        let n = wedges.len().min(bearings.len()).min(trig.len());
        self.wedge_from.clear();
        self.wedge_from.resize(n, f64::NEG_INFINITY);
        let open = |k: usize| wedges[k].filter(|w| w.to() > w.from() && w.from() > 0.0);
        let turn = |k: usize| bearings[k] - bearings[k - 1];
        let mut filled = 0;
        let mut k = 1;
        while k < n {
            let Some(w0) = open(k) else {
                k += 1;
                continue;
            };
            let (mut lo, mut hi) = (w0.to(), w0.to());
            let mut last = k;
            while last + 1 < n {
                let Some(w) = open(last + 1) else { break };
                let (l, h) = (lo.min(w.to()), hi.max(w.to()));
                if !((w.from() - w0.from()).abs() <= 1e-9 * w0.from()
                    && (turn(last + 1) > 0.0) == (turn(k) > 0.0)
                    && l >= FAR_RATIO * h)
                {
                    break;
                }
                (lo, hi) = (l, h);
                last += 1;
            }
            let first = k - 1;
            k = last + 1;
            // A fan of fewer wedges saves too few lines, and one ending
            // near the wedges' start saves none.
            if last - first < FAR_MIN_WEDGES || !(lo > FAR_MIN_GAIN * w0.from()) {
                continue;
            }
            // Two cells short of the nearest end: each wedge's own fill
            // still reaches past its end's arc (see `between::fill_wedge`).
            let radius = lo - 2.0 * frame.res;
            let n_filled;
            (n_filled, gathered) =
                self.fill_fan(frame, (first, last), radius, bearings, trig, gathered);
            if let Some(n_filled) = n_filled {
                filled += n_filled;
                for j in first + 1..=last {
                    self.wedge_from[j] = radius;
                }
            }
        }
        (filled, gathered)
    }

    /// Fills the fan of beams `first ..= last` out to `radius` metres, in
    /// convex pieces of at most [`MAX_PIECE`]; `None` (nothing filled) when
    /// a corner is not a number.
    fn fill_fan<'a, const SEGMENTED: bool>(
        &mut self,
        frame: &BeamFrame,
        (first, last): (usize, usize),
        radius: f64,
        bearings: &[f64],
        trig: &[(f64, f64)],
        mut gathered: Gathered<'a, u8, SEGMENTED>,
    ) -> (Option<usize>, Gathered<'a, u8, SEGMENTED>) {
        let cells = radius * frame.per_metre;
        // The same corners, by the same operations, as the wedges' near
        // edges (`between::fill_wedge`).
        let corner = |(sin_b, cos_b): (f64, f64)| {
            let s = frame.sin_t * cos_b + frame.cos_t * sin_b;
            let c = frame.cos_t * cos_b - frame.sin_t * sin_b;
            (frame.su + cells * c, frame.sv + cells * s)
        };
        let sensor = (frame.su, frame.sv);
        let all_finite = (first..=last)
            .map(|k| corner(trig[k]))
            .chain([sensor])
            .all(|p| p.0.is_finite() && p.1.is_finite());
        if !all_finite {
            return (None, gathered);
        }
        let mut filled = 0;
        let mut start = first;
        while start < last {
            let mut end = start + 1;
            while end < last && (bearings[end + 1] - bearings[start]).abs() <= MAX_PIECE {
                end += 1;
            }
            self.corners.clear();
            self.corners.push(sensor);
            self.corners.extend((start..=end).map(|k| corner(trig[k])));
            let n;
            (n, gathered) = self.fill_convex(frame, gathered);
            filled += n;
            start = end;
        }
        (Some(filled), gathered)
    }

    /// Fills every cell whose centre lies in the convex polygon `corners`
    /// (map cell coordinates, in order round its edge, edges included) and
    /// in the frame's window, a line of cells at a time: rows, or columns
    /// for a polygon much taller than wide (as many lines as it is wide).
    fn fill_convex<'a, const SEGMENTED: bool>(
        &mut self,
        frame: &BeamFrame,
        gathered: Gathered<'a, u8, SEGMENTED>,
    ) -> (usize, Gathered<'a, u8, SEGMENTED>) {
        let extent = |f: fn(&(f64, f64)) -> f64| {
            self.corners
                .iter()
                .map(f)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        };
        let (x_range, y_range) = (extent(|p| p.0), extent(|p| p.1));
        let lines = Lines::of(frame, y_range.1 - y_range.0 > 3.0 * (x_range.1 - x_range.0));
        lines.orient(&mut self.corners);
        let (line_min, line_max) = if lines.columns() { x_range } else { y_range };
        let Some((first, last)) = lines.within(line_min, line_max) else {
            return (0, gathered);
        };
        let count = last - first + 1;
        self.lo.clear();
        self.lo.resize(count, f64::INFINITY);
        self.hi.clear();
        self.hi.resize(count, f64::NEG_INFINITY);
        // A convex polygon meets a line's centre in one span: from the
        // lowest to the highest crossing of its edges.
        let m = self.corners.len();
        for k in 0..m {
            let (p, q) = (self.corners[k], self.corners[(k + 1) % m]);
            if p.1 == q.1 {
                // A level edge's ends are other edges' ends.
                continue;
            }
            let (a, b) = if p.1 < q.1 { (p, q) } else { (q, p) };
            let slope = (b.0 - a.0) / (b.1 - a.1);
            let from = ceil_at_least((a.1 - 0.5).max(first as f64));
            let to = (b.1 - 0.5).min(last as f64);
            if !(to >= from as f64) {
                continue;
            }
            for line in from..=to as usize {
                let x = a.0 + (line as f64 + 0.5 - a.1) * slope;
                let r = line - first;
                if x < self.lo[r] {
                    self.lo[r] = x;
                }
                if x > self.hi[r] {
                    self.hi[r] = x;
                }
            }
        }
        let mut gathered = gathered.narrowed();
        let mut filled = 0;
        for r in 0..count {
            filled += lines.fill(&mut gathered, first + r, self.lo[r], self.hi[r]);
        }
        (filled, gathered)
    }
}

impl<T: Slot, const SEGMENTED: bool> Gathered<'_, T, SEGMENTED> {
    /// Records verdict `v` for the `len >= 1` cells from window index `i`
    /// along a row: on a gathering by segment, the row's slots at once and
    /// a bit per segment it spans, instead of a bit per cell.
    #[inline(always)]
    pub(super) fn record_row(&mut self, i: usize, len: usize, v: T) {
        let start = i & self.mask;
        if SEGMENTED {
            if let Some(row) = self.slots.get_mut(start..start + len) {
                T::merge_row(row, v);
                let (a, b) = (start >> SEGMENT_SHIFT, (start + len - 1) >> SEGMENT_SHIFT);
                for segment in a..=b {
                    if let Some(word) = self.segments.get_mut(segment >> 6) {
                        *word |= 1 << (segment & 63);
                    }
                }
                return;
            }
        }
        for k in 0..len {
            self.record(i + k, v);
        }
    }
}
