//! The free space between neighbouring beams
//! ([`super::RayMapper::integrate_bands_between`]): a scanner's beams are as
//! wide as their spacing (Table 9.2's `β`), and the cells a supercover
//! walk leaves between two beams' axes, once they part by more than a
//! cell, are filled by walks along directions between them; where both
//! beams end on one surface, the wall between their readings is drawn
//! too.

use super::{trace, BandCodes, BeamBand, BeamFrame, BeamState, Codes};
use crate::geometry::raster::Walk;

/// The widest spacing of two neighbouring beams whose between is filled
/// ([`super::RayMapper::integrate_bands_between`]), radians: 5°, past any
/// scanner's spacing; wider is a gap in the scan.
const MAX_BEAM_SPACING: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Levels of walks between two beams: level `k` fills out to `2^k` times
/// the range at which the beams part by a cell.
const BETWEEN_LEVELS: u32 = 3;

/// Walks the space between each pair of neighbouring beams (`bands[i -
/// 1]`, `bands[i]`, bearings with `(sin, cos)` in `trig`) into `gathered`
/// as free verdicts, out to `2^BETWEEN_LEVELS` times the range where the
/// two axes part by a cell and never past the nearer free range, and the
/// wall between their readings as hits ([`trace_wall_between`]); returns
/// the cells visited and the gathering.
pub(super) fn trace_between<'a>(
    frame: &BeamFrame,
    bands: &[Option<BeamBand>],
    bearings: &[f64],
    trig: &[(f64, f64)],
    walkable: impl Fn(f64) -> bool,
    mut gathered: Codes<'a>,
) -> (usize, Codes<'a>) {
    let mut visits = 0;
    for i in 1..bands.len().min(bearings.len()) {
        let (Some(a), Some(b)) = (bands[i - 1], bands[i]) else {
            continue;
        };
        if !(walkable(a.reach) && walkable(b.reach)) {
            continue;
        }
        let spacing = (bearings[i] - bearings[i - 1]).abs();
        // Neighbours only: a gap in the scan's bearings is no beam.
        if !(spacing > 0.0 && spacing <= MAX_BEAM_SPACING) {
            continue;
        }
        let n;
        (n, gathered) =
            trace_wall_between(frame, (a, b), (trig[i - 1], trig[i]), spacing, gathered);
        visits += n;
        let parted = frame.res / spacing;
        let nearer = a.free_until.min(b.free_until);
        let ((s0, c0), (s1, c1)) = (trig[i - 1], trig[i]);
        // Level k's walks split the pair's angle in 2^k, from
        // where level k - 1's walks part by a cell (the new ones)
        // or where they ended (the earlier ones), out to 2^k times
        // the range where the two beams part by a cell.
        for level in 1..=BETWEEN_LEVELS {
            let parts = 1usize << level;
            let begun = parted * (parts / 2) as f64;
            let to = (parted * parts as f64).min(nearer);
            if !(to > 0.9 * begun) {
                break;
            }
            for j in 1..parts {
                let from = if j % 2 == 1 {
                    0.9 * begun
                } else {
                    0.99 * begun
                };
                if !(to > from) {
                    continue;
                }
                // The direction at fraction j / parts from the
                // first beam to the second (a chord's point,
                // normalised: within a hair of the angle's).
                let f = j as f64 / parts as f64;
                let (sv, cv) = (s0 + f * (s1 - s0), c0 + f * (c1 - c0));
                let norm = sv.hypot(cv);
                let Some((walk, at)) = frame.segment((sv / norm, cv / norm), from, to) else {
                    continue;
                };
                let band = BeamBand {
                    reach: to,
                    free_until: to,
                    occupied_from: to,
                    occupied_until: to,
                };
                let n;
                (n, gathered) = trace(walk, at, BandCodes(band), gathered);
                visits += n;
            }
        }
    }
    (visits, gathered)
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
fn trace_wall_between<'a>(
    frame: &BeamFrame,
    (a, b): (BeamBand, BeamBand),
    ((s0, c0), (s1, c1)): ((f64, f64), (f64, f64)),
    spacing: f64,
    mut gathered: Codes<'a>,
) -> (usize, Codes<'a>) {
    let mut visits = 0;
    // A no-return has no occupied band.
    if !(a.occupied_until > a.occupied_from && b.occupied_until > b.occupied_from) {
        return (visits, gathered);
    }
    let (za, zb) = (
        0.5 * (a.occupied_from + a.occupied_until),
        0.5 * (b.occupied_from + b.occupied_until),
    );
    let (ha, hb) = (
        0.5 * (a.occupied_until - a.occupied_from),
        0.5 * (b.occupied_until - b.occupied_from),
    );
    if !((za - zb).abs() <= ha + hb + WALL_SLOPE * za.min(zb) * spacing) {
        return (visits, gathered);
    }
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

impl BeamFrame {
    /// As [`Self::beam`], from range `from` (metres) on, out to `to`;
    /// `None` also when its first cell lies outside the window (a segment
    /// past the reach the window was made for). (A function of its own:
    /// the beam's walk is the hot one, and stays as it was.)
    fn segment(&self, (sin_b, cos_b): (f64, f64), from: f64, to: f64) -> Option<(Walk, BeamState)> {
        if !(from >= 0.0 && from < to) {
            return None;
        }
        let (su, sv) = (self.su, self.sv);
        let s = self.sin_t * cos_b + self.cos_t * sin_b;
        let c = self.cos_t * cos_b - self.sin_t * sin_b;
        let (near, far) = (from * self.per_metre, to * self.per_metre);
        let start = (su + near * c, sv + near * s);
        let end = (su + far * c, sv + far * s);
        let walk = Walk::new(self.width, self.height, start, end)?;
        let (ix, iy) = walk.start;
        let w = &self.window;
        if !(ix >= w.x0 && iy >= w.y0 && ix - w.x0 < w.stride && iy - w.y0 < w.rows) {
            return None;
        }
        let at = self.beam_state(&walk, (s, c));
        Some((walk, at))
    }
}
