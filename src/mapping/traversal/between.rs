//! The free space between neighbouring beams
//! ([`super::RayMapper::integrate_bands_between`]): a scanner's beams are as
//! wide as their spacing (Table 9.2's `β`), so the wedge between two
//! neighbouring beams' axes is free out to the nearer one's free range
//! (within a bound); it is filled a line of cells at a time, each cell
//! once, and the beams themselves are walked only where the wedges beside
//! them do not already hold their cells. Where both beams end on one
//! surface, the wall between their readings is drawn too.

// A test written `!(a < b)` is also true when either is not a number: a
// wedge or a wall with such a bound fills nothing.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{trace, BandCodes, BeamBand, BeamFrame, Code, Gathered};

/// The widest spacing of two neighbouring beams whose between is filled
/// ([`super::RayMapper::integrate_bands_between`]), radians: 5°, past any
/// scanner's spacing; wider is a gap in the scan.
const MAX_BEAM_SPACING: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// How far the wedge between two beams is filled, in units of the range
/// at which their axes part by a cell (`res / δφ`, 2.9 m for 1° at 5 cm):
/// 23 m for 1° and 46 m for 0.5° at 5 cm. (Out to 4 times, the Infinite
/// Corridor kept 1.21 pinholes per 1,000 free cells and the campus 1.48,
/// against 0.82 and 0.92 at 8; docs/ARCHITECTURE.md, "Real logs".)
const FILL_PARTED: f64 = 8.0;

/// Where a wedge's fill starts, in the same units: nearer, the two axes
/// are less than 0.9 of a cell apart, so every centre between them lies
/// within 0.45 of a cell of an axis and the beams' own walks hold it.
const FILL_FROM_PARTED: f64 = 0.9;

/// The wedge between beams `i - 1` and `i` of a scan, in metres along
/// their axes: filled from `from` out to `to` (the nearer of the two free
/// ranges, at most [`FILL_PARTED`] times where the axes part by a cell).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Wedge {
    from: f64,
    to: f64,
}

impl Wedge {
    /// Where the wedge's fill starts, metres.
    pub(super) fn from(&self) -> f64 {
        self.from
    }
    /// Where it ends, metres: the nearer of its beams' free ranges (at
    /// most [`FILL_PARTED`] times where the axes part by a cell).
    pub(super) fn to(&self) -> f64 {
        self.to
    }
}

/// Plans the wedges of a scan: `wedges[i]` between beams `i - 1` and `i`
/// (bands `bands`, bearings `bearings`), `None` where the two are no
/// neighbours (a gap in the bearings, a beam with nothing to walk or past
/// the window); `wedges[0]` is `None`.
pub(super) fn plan_wedges(
    bands: &[Option<BeamBand>],
    bearings: &[f64],
    res: f64,
    walkable: impl Fn(f64) -> bool,
    wedges: &mut Vec<Option<Wedge>>,
) {
    wedges.clear();
    let n = bands.len().min(bearings.len());
    wedges.extend((0..n).map(|i| {
        let (Some(a), Some(b)) = (*bands.get(i.checked_sub(1)?)?, bands[i]) else {
            return None;
        };
        if !(walkable(a.reach) && walkable(b.reach)) {
            return None;
        }
        let spacing = (bearings[i] - bearings[i - 1]).abs();
        // Neighbours only: a gap in the scan's bearings is no beam.
        if !(spacing > 0.0 && spacing <= MAX_BEAM_SPACING) {
            return None;
        }
        let parted = res / spacing;
        let from = FILL_FROM_PARTED * parted;
        let to = (FILL_PARTED * parted).min(a.free_until.min(b.free_until));
        // (An empty fill, `to <= from`, still pairs the two beams: the
        // wall between their readings is drawn.)
        Some(Wedge { from, to })
    }));
}

/// The part of beam `i`'s walk the wedges beside it leave to it: its
/// near part, out to `near` metres, and its tail, from `tail` on; `None`
/// when the beam must be walked whole (a side without a wedge, or wedges
/// too short to hold anything). Past where both wedges start (plus a cell)
/// and short of where either ends (less a cell), every cell the beam's
/// supercover walk touches has its centre in one of the two wedges, each
/// at least 0.9 of a cell wide there: the fills hold it.
pub(super) fn beam_spans(wedges: &[Option<Wedge>], i: usize, res: f64) -> Option<(f64, f64)> {
    let (Some(left), Some(right)) = (*wedges.get(i)?, *wedges.get(i + 1)?) else {
        return None;
    };
    let near = left.from.max(right.from) + res;
    let tail = left.to.min(right.to) - res;
    (tail > near).then_some((near, tail))
}

/// Fills the wedges of a scan (planned by [`plan_wedges`], bearings with
/// `(sin, cos)` in `trig`; wedge `i` from `starts(i, from)` on, where a
/// fan holds its nearer part) into `gathered` as free verdicts, draws the
/// wall between two neighbouring readings as hits
/// ([`trace_wall_between`]), and fills the footprint of a return beside
/// a beam that clears nothing ([`fill_footprint_beside_the_unseen`];
/// `walkable` tells a reach the scan's frame holds); returns the cells
/// visited and the gathering.
#[allow(clippy::too_many_arguments)]
pub(super) fn trace_between<'a, const SEGMENTED: bool>(
    frame: &BeamFrame,
    bands: &[Option<BeamBand>],
    bearings: &[f64],
    trig: &[(f64, f64)],
    wedges: &[Option<Wedge>],
    starts: impl Fn(usize, f64) -> f64,
    walkable: impl Fn(f64) -> bool,
    mut gathered: Gathered<'a, u8, SEGMENTED>,
) -> (usize, Gathered<'a, u8, SEGMENTED>) {
    let mut visits = 0;
    let n;
    (n, gathered) =
        fill_footprint_beside_the_unseen(frame, bands, bearings, trig, walkable, gathered);
    visits += n;
    for (i, wedge) in wedges.iter().enumerate() {
        let Some(wedge) = *wedge else { continue };
        let (Some(a), Some(b)) = (bands[i - 1], bands[i]) else {
            continue;
        };
        let spacing = (bearings[i] - bearings[i - 1]).abs();
        let n;
        (n, gathered) =
            trace_wall_between(frame, (a, b), (trig[i - 1], trig[i]), spacing, gathered);
        visits += n;
        let n;
        (n, gathered) = fill_wedge(
            frame,
            (trig[i - 1], trig[i]),
            starts(i, wedge.from),
            wedge.to,
            gathered,
        );
        visits += n;
        // The nearer beam, the farther, and the nearer one's other
        // neighbour.
        let (near, far, near_trig, far_trig, other) = if a.free_until > b.free_until {
            (
                b,
                a,
                trig[i],
                trig[i - 1],
                bands.get(i + 1).copied().flatten(),
            )
        } else {
            (
                a,
                b,
                trig[i - 1],
                trig[i],
                i.checked_sub(2).and_then(|k| bands[k]),
            )
        };
        let n;
        (n, gathered) = fill_beside_a_post(
            frame,
            (near, far),
            (near_trig, far_trig),
            other,
            wedge,
            spacing,
            gathered,
        );
        visits += n;
    }
    (visits, gathered)
}

/// Beside a beam that clears nothing (a no-return without a return on
/// each side near enough, [`crate::mapping::neighbour_support`]), the
/// half of the space between the two beams on a return's side lies within
/// half the spacing of the return's bearing: inside its footprint (Table
/// 9.2's `β/2`, a scanner's beams as wide as their spacing), and free out
/// to its free range (at most [`FILL_PARTED`] times where the axes part
/// by a cell, and [`BESIDE_POST_SHORT`] cells short of the free range).
/// Without it, a lone return among no-returns (a far wall
/// seen through a window, a tree across a square) drew a free line one
/// cell wide, and the lines of a few scans from nearly one place lay side
/// by side with single gray cells between them: pinholes no reader takes
/// for unobserved floor (docs/ARCHITECTURE.md, "Real logs"). Every cell
/// filled lies in the wedge of a beam that returned.
fn fill_footprint_beside_the_unseen<'a, const SEGMENTED: bool>(
    frame: &BeamFrame,
    bands: &[Option<BeamBand>],
    bearings: &[f64],
    trig: &[(f64, f64)],
    walkable: impl Fn(f64) -> bool,
    mut gathered: Gathered<'a, u8, SEGMENTED>,
) -> (usize, Gathered<'a, u8, SEGMENTED>) {
    let n = bands.len().min(bearings.len()).min(trig.len());
    let mut visits = 0;
    for i in 0..n {
        let Some(beam) = bands[i] else { continue };
        // A return (an occupied band), its reach inside the frame.
        if !(beam.occupied_until > beam.occupied_from && walkable(beam.reach)) {
            continue;
        }
        for j in [i.checked_sub(1), Some(i + 1)].into_iter().flatten() {
            if j >= n || bands[j].is_some() {
                continue;
            }
            let spacing = (bearings[j] - bearings[i]).abs();
            if !(spacing > 0.0 && spacing <= MAX_BEAM_SPACING) {
                continue;
            }
            let parted = frame.res / spacing;
            let from = FILL_FROM_PARTED * parted;
            let to = (FILL_PARTED * parted).min(beam.free_until - BESIDE_POST_SHORT * frame.res);
            let Some(half) = bisector(trig[i], trig[j]) else {
                continue;
            };
            let filled;
            (filled, gathered) = fill_wedge(frame, (trig[i], half), from, to, gathered);
            visits += filled;
        }
    }
    (visits, gathered)
}

/// How far past a nearer reading's occupied band the space behind it
/// starts to be filled beside it ([`fill_beside_a_post`]), metres: a door
/// frame or a wall's end seen edge-on runs back from its edge, and filling
/// nearer than this wore such walls away.
const BESIDE_POST_FROM: f64 = 0.5;

/// How many cells short of the farther beam's free range the space beside
/// a post stops ([`fill_beside_a_post`]), and a return's footprint beside
/// a beam that clears nothing ([`fill_footprint_beside_the_unseen`]): a
/// wall the beam meets at a slant lies nearer on one side of its axis.
const BESIDE_POST_SHORT: f64 = 4.0;

/// Past a reading nearer than both its neighbours' (a door frame's edge, a
/// post, a leg: the beams on both sides pass it), the wedge between it and
/// a farther neighbour is filled only out to its own free range
/// ([`plan_wedges`]); beyond, the half of the wedge on the farther beam's
/// side of the bisector lies within half the spacing of that beam's
/// bearing, inside its footprint (Table 9.2's `β/2`), and is free out to
/// its free range. In a room seen through a doorway, beams alternately
/// pass the door and meet its frame, and the floor between the passing
/// ones stayed gray in pinholes (docs/ARCHITECTURE.md, "Real logs").
/// `near` and `far` are the wedge's two beams (bearings' `(sin, cos)` in
/// `trig`), `other` the near beam's other neighbour.
fn fill_beside_a_post<'a, const SEGMENTED: bool>(
    frame: &BeamFrame,
    (near, far): (BeamBand, BeamBand),
    (near_trig, far_trig): ((f64, f64), (f64, f64)),
    other: Option<BeamBand>,
    wedge: Wedge,
    spacing: f64,
    gathered: Gathered<'a, u8, SEGMENTED>,
) -> (usize, Gathered<'a, u8, SEGMENTED>) {
    // A post: both neighbours pass it (depth jumps on both sides).
    let Some(other) = other else {
        return (0, gathered);
    };
    let passed =
        |b: BeamBand| b.free_until > near.free_until && one_surface(near, b, spacing).is_none();
    if !(passed(far) && passed(other)) {
        return (0, gathered);
    }
    let bound = FILL_PARTED * frame.res / spacing;
    let to = bound.min(far.free_until - BESIDE_POST_SHORT * frame.res);
    let from = wedge
        .to
        .max(wedge.from)
        .max(near.occupied_until + BESIDE_POST_FROM);
    if !(to > from) {
        return (0, gathered);
    }
    let Some(half) = bisector(near_trig, far_trig) else {
        return (0, gathered);
    };
    fill_wedge(frame, (half, far_trig), from, to, gathered)
}

/// The `(sin, cos)` of the direction halfway between two bearings given
/// as `(sin, cos)`: the sum of the two unit vectors, scaled back to unit
/// length; `None` for opposite bearings.
fn bisector(a: (f64, f64), b: (f64, f64)) -> Option<(f64, f64)> {
    let (s, c) = (a.0 + b.0, a.1 + b.1);
    let norm = s.hypot(c);
    (norm > 0.0).then(|| (s / norm, c / norm))
}

/// Two neighbouring readings as their bands give them: the middles `z`
/// and half-widths `h` of the two occupied bands.
struct Surface {
    z: (f64, f64),
    h: (f64, f64),
}

/// Where two neighbouring beams `spacing` apart both end on one surface,
/// their readings: both return, and the readings lie no further apart
/// than their bands' overlap and [`WALL_SLOPE`] allow (a larger difference
/// is a depth jump); `None` otherwise.
fn one_surface(a: BeamBand, b: BeamBand, spacing: f64) -> Option<Surface> {
    // A no-return has no occupied band.
    if !(a.occupied_until > a.occupied_from && b.occupied_until > b.occupied_from) {
        return None;
    }
    let (za, zb) = (
        0.5 * (a.occupied_from + a.occupied_until),
        0.5 * (b.occupied_from + b.occupied_until),
    );
    let (ha, hb) = (
        0.5 * (a.occupied_until - a.occupied_from),
        0.5 * (b.occupied_until - b.occupied_from),
    );
    ((za - zb).abs() <= ha + hb + WALL_SLOPE * za.min(zb) * spacing).then_some(Surface {
        z: (za, zb),
        h: (ha, hb),
    })
}

/// How far apart the readings of two neighbouring beams may be, beyond
/// their bands' overlap, for both to count as ending on one surface, in
/// units of the arc `z δφ` between them: a straight wall at incidence `θ`
/// gives readings `z δφ / tan θ` apart, so this admits walls down to
/// `θ = atan(1 / WALL_SLOPE)` (34°); a larger difference is a depth jump
/// (an object's edge, a doorway), and nothing is drawn across it. Chosen
/// by measuring the datasets' logs (docs/ARCHITECTURE.md, "Real logs"):
/// 1 left grazing walls dotted; 2 and 3 joined more foliage returns on
/// the Freiburg campus into lines no endpoint lies next to (its precision
/// 0.952 and 0.932, against 0.963 here).
const WALL_SLOPE: f64 = 1.5;

/// Where two neighbouring beams `a` and `b` (bearings' `(sin, cos)` in
/// `trig`, `spacing` apart) both end on one surface, the wall between
/// their endpoints: Table 9.2 gives a cell within `β/2` of a beam's
/// bearing and `α/2` of its reading occupied, and a scanner's beams are
/// as wide as their spacing, so the arc between two readings of one wall
/// is the wall. Walks through the occupied band along directions to
/// points of the chord between the two readings, at most a cell apart,
/// each as wide in range as the bands (interpolated); the cells join the
/// scan's verdicts as hits. Without them a wall seen from afar (one
/// reading every 26 cm at 15 m for 1°) prints as a dotted line.
pub(super) fn trace_wall_between<'a, const SEGMENTED: bool>(
    frame: &BeamFrame,
    (a, b): (BeamBand, BeamBand),
    ((s0, c0), (s1, c1)): ((f64, f64), (f64, f64)),
    spacing: f64,
    mut gathered: Gathered<'a, u8, SEGMENTED>,
) -> (usize, Gathered<'a, u8, SEGMENTED>) {
    let mut visits = 0;
    let Some(Surface {
        z: (za, zb),
        h: (ha, hb),
    }) = one_surface(a, b, spacing)
    else {
        return (visits, gathered);
    };
    let (ea, eb) = ((za * c0, za * s0), (zb * c1, zb * s1));
    let chord_cells = (eb.0 - ea.0).hypot(eb.1 - ea.1) * frame.per_metre;
    // Endpoints within a cell of each other leave no gap to draw.
    if !(chord_cells > 1.0) {
        return (visits, gathered);
    }
    let parts = chord_cells.ceil() as usize;
    // The budget: no more cells than the two beams' own walks (a wall's
    // band is a few cells, so a real scanner's settings stay far below
    // it; a band as wide as the range would not).
    let band_cells = (ha + hb) * frame.per_metre + 4.0;
    if !(parts as f64 * band_cells <= (za + zb) * frame.per_metre) {
        return (visits, gathered);
    }
    for j in 1..parts {
        let f = j as f64 / parts as f64;
        let p = (ea.0 + f * (eb.0 - ea.0), ea.1 + f * (eb.1 - ea.1));
        let r = p.0.hypot(p.1);
        let h = ha + f * (hb - ha);
        let (from, to) = (r - h, r + h);
        let Some((walk, at)) = frame.segment((p.1 / r, p.0 / r), from, to) else {
            continue;
        };
        let band = BeamBand {
            reach: to,
            free_until: f64::NEG_INFINITY,
            occupied_from: from,
            occupied_until: to,
        };
        let n;
        (n, gathered) = trace(walk, at, BandCodes(band), gathered);
        visits += n;
    }
    (visits, gathered)
}

/// Fills the wedge between two neighbouring beams' axes (bearings'
/// `(sin, cos)` in `trig`) from range `from` out to range `to` (metres)
/// as free verdicts: every cell whose centre lies in the quadrilateral of
/// the two axes' points at `from` and (about) at `to`, each cell once, a
/// line of cells at a time. Inside `from` (where the axes are less than a cell
/// apart) every centre between them lies within half a cell of an axis,
/// so the beams' own walks hold it; a cell a beam's walk touches beside
/// the wedge is that walk's. (Levels of supercover walks along directions
/// between the two beams, each level twice the walks and twice the range,
/// reached the same floor visiting its cells several times each.)
/// Returns the cells filled and the gathering.
pub(super) fn fill_wedge<'a, const SEGMENTED: bool>(
    frame: &BeamFrame,
    (a, b): ((f64, f64), (f64, f64)),
    from: f64,
    to: f64,
    gathered: Gathered<'a, u8, SEGMENTED>,
) -> (usize, Gathered<'a, u8, SEGMENTED>) {
    if !(from >= 0.0 && from < to) {
        return (0, gathered);
    }
    // The quadrilateral's corners in the map's cell coordinates, in order
    // round its edge: beam `a` near and far, beam `b` far and near.
    let direction = |(sin_b, cos_b): (f64, f64)| {
        let s = frame.sin_t * cos_b + frame.cos_t * sin_b;
        let c = frame.cos_t * cos_b - frame.sin_t * sin_b;
        (c, s)
    };
    let (da, db) = (direction(a), direction(b));
    let at = |(c, s): (f64, f64), r: f64| {
        let cells = r * frame.per_metre;
        (frame.su + cells * c, frame.sv + cells * s)
    };
    // The far edge is the chord whose middle lies at range `to`, so that
    // the wedge holds the arc of radius `to` between the axes (a cell whose
    // centre lies within `to` of the sensor, between the two beams, is
    // within both beams' free ranges); a hundredth of a cell more keeps the
    // cells whose centres lie on the arc.
    let cos_half = (0.5 * (1.0 + da.0 * db.0 + da.1 * db.1)).max(0.0).sqrt();
    let far = to / cos_half + 0.01 * frame.res;
    let mut corners = [at(da, from), at(da, far), at(db, far), at(db, from)];
    // Lines of cells along the wedge's longer extent: rows when it points
    // along x, columns when along y.
    let lines = Lines::of(frame, (da.1 + db.1).abs() > (da.0 + db.0).abs());
    lines.orient(&mut corners);
    if corners
        .iter()
        .any(|p| !(p.0.is_finite() && p.1.is_finite()))
    {
        return (0, gathered);
    }
    let Some(bounds) = LineBounds::of(&corners) else {
        return (0, gathered);
    };
    let mut gathered = gathered.narrowed();
    // Lines whose centres `k + 0.5` lie within the wedge, inside the
    // window (which holds every cell within the scan's reach).
    let Some((first, last)) = lines.within(bounds.min, bounds.max) else {
        return (0, gathered);
    };
    let mut filled = 0;
    for k in first..=last {
        let (lo, hi) = bounds.span(k as f64 + 0.5);
        filled += lines.fill(&mut gathered, k, lo, hi);
    }
    (filled, gathered)
}

/// `ceil(v)` for a finite `v >= 0`, without a library call (native code
/// without SSE4.1 has no rounding instruction).
#[inline(always)]
pub(super) fn ceil_at_least(v: f64) -> usize {
    let t = v as usize;
    t + ((t as f64) < v) as usize
}

/// The lines of cells of a scan's window a convex polygon is filled in
/// (`fill_wedge`, and the fans of `fans`): rows, or columns (the polygon's
/// coordinates then swapped, `(y, x)`, and a step along a line a step of
/// a row). A line `k` and a cell `j` along it are map coordinates.
pub(super) struct Lines {
    /// The first line of the window and how many.
    lines: (usize, usize),
    /// The first cell along a line and how many.
    along: (usize, usize),
    line_step: usize,
    cell_step: usize,
    columns: bool,
}

impl Lines {
    /// Rows of `frame`'s window, or its columns.
    pub(super) fn of(frame: &BeamFrame, columns: bool) -> Self {
        let w = &frame.window;
        if columns {
            Self {
                lines: (w.x0, frame.cols),
                along: (w.y0, w.rows),
                line_step: 1,
                cell_step: w.stride,
                columns,
            }
        } else {
            Self {
                lines: (w.y0, w.rows),
                along: (w.x0, frame.cols),
                line_step: w.stride,
                cell_step: 1,
                columns,
            }
        }
    }

    /// True for columns.
    pub(super) fn columns(&self) -> bool {
        self.columns
    }

    /// Map coordinates `(x, y)` as `(along a line, across the lines)`.
    pub(super) fn orient(&self, points: &mut [(f64, f64)]) {
        if self.columns {
            points.iter_mut().for_each(|p| *p = (p.1, p.0));
        }
    }

    /// The first and last line whose centres `k + 0.5` lie within
    /// `[min, max]`, inside the window; `None` for none.
    pub(super) fn within(&self, min: f64, max: f64) -> Option<(usize, usize)> {
        let first = ceil_at_least((min - 0.5).max(self.lines.0 as f64));
        let last = (max - 0.5).min((self.lines.0 + self.lines.1) as f64 - 1.0);
        (last >= first as f64).then_some((first, last as usize))
    }

    /// Records as free the cells of line `k` whose centres `j + 0.5` lie
    /// within `[lo, hi]`, inside the window: a row's at once, a column's
    /// one by one. Returns the cells recorded.
    #[inline(always)]
    pub(super) fn fill<const SEGMENTED: bool>(
        &self,
        gathered: &mut Gathered<'_, u8, SEGMENTED>,
        k: usize,
        lo: f64,
        hi: f64,
    ) -> usize {
        let (lo_limit, hi_limit) = (
            self.along.0 as f64,
            (self.along.0 + self.along.1) as f64 - 1.0,
        );
        // (Comparisons: in wasm `f64::max` is a library call.)
        let lo = if lo - 0.5 > lo_limit {
            lo - 0.5
        } else {
            lo_limit
        };
        let hi = if hi - 0.5 < hi_limit {
            hi - 0.5
        } else {
            hi_limit
        };
        if !(hi >= lo) {
            return 0;
        }
        let (lo, hi) = (ceil_at_least(lo), hi as usize);
        if lo > hi {
            return 0;
        }
        let mut i = (k - self.lines.0) * self.line_step + (lo - self.along.0) * self.cell_step;
        if self.columns {
            for _ in lo..=hi {
                gathered.record(i, Code::Free as u8);
                i += self.cell_step;
            }
        } else {
            gathered.record_row(i, hi - lo + 1, Code::Free as u8);
        }
        hi - lo + 1
    }
}

/// A convex quadrilateral as the lines that bound each scanline of it:
/// the span at line coordinate `y` is `x` from the largest of its lower
/// bounds to the smallest of its upper bounds (`x = x0 + y slope` each,
/// unused ones infinite), for `y` within `[min, max]`.
struct LineBounds {
    lower: [(f64, f64); 3],
    upper: [(f64, f64); 3],
    min: f64,
    max: f64,
}

impl LineBounds {
    /// The bounds of the convex quadrilateral with `corners` in order round
    /// its edge (either way round); `None` when it has no area.
    fn of(corners: &[(f64, f64); 4]) -> Option<Self> {
        let twice_area: f64 = (0..4)
            .map(|k| {
                let (p, q) = (corners[k], corners[(k + 1) % 4]);
                p.0 * q.1 - q.0 * p.1
            })
            .sum();
        if !(twice_area != 0.0) {
            return None;
        }
        let counter_clockwise = twice_area > 0.0;
        let mut lower = [(f64::NEG_INFINITY, 0.0); 3];
        let mut upper = [(f64::INFINITY, 0.0); 3];
        let (mut n_lower, mut n_upper) = (0, 0);
        for k in 0..4 {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            let dy = q.1 - p.1;
            if dy == 0.0 {
                // A level edge bounds the lines only at `min` or `max`.
                continue;
            }
            let slope = (q.0 - p.0) / dy;
            let line = (p.0 - p.1 * slope, slope);
            // Round a counter-clockwise polygon the inside lies left of
            // each edge: an edge going up bounds it from above in x.
            if (dy > 0.0) == counter_clockwise {
                *upper.get_mut(n_upper)? = line;
                n_upper += 1;
            } else {
                *lower.get_mut(n_lower)? = line;
                n_lower += 1;
            }
        }
        let (min, max) = corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.1), hi.max(p.1))
            });
        Some(Self {
            lower,
            upper,
            min,
            max,
        })
    }

    /// The span `(lo, hi)` of line coordinate `y`.
    #[inline(always)]
    fn span(&self, y: f64) -> (f64, f64) {
        let at = |(x0, slope): (f64, f64)| x0 + y * slope;
        let lo = max3(at(self.lower[0]), at(self.lower[1]), at(self.lower[2]));
        let hi = min3(at(self.upper[0]), at(self.upper[1]), at(self.upper[2]));
        (lo, hi)
    }
}

/// The largest of three numbers, none NaN (comparisons: `f64::max` keeps
/// NaN handling the spans never need).
#[inline(always)]
fn max3(a: f64, b: f64, c: f64) -> f64 {
    let m = if a > b { a } else { b };
    if m > c {
        m
    } else {
        c
    }
}

/// The smallest of three numbers, none NaN.
#[inline(always)]
fn min3(a: f64, b: f64, c: f64) -> f64 {
    let m = if a < b { a } else { b };
    if m < c {
        m
    } else {
        c
    }
}
