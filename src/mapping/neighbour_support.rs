//! Free space that rests on beams that saw something: what a beam's
//! neighbours say of the space it alone claims free (docs/ARCHITECTURE.md,
//! "Real logs").
//!
//! Under a counting cell model one crossing beam makes a cell free, so a
//! beam the rest of the scan contradicts draws a line of free cells on its
//! own. Two kinds of beams claim space that their neighbours saw as
//! closed, or did not see at all:
//!
//! * **A beam that passes where its neighbours stop.** A glass pane returns
//!   some beams and passes others; a doorway seen at a grazing angle passes
//!   one beam in two between returns off its frame (sawtooth fans). When
//!   the nearest returns on both sides, within [`MAX_PASSING_RUN`] beams,
//!   lie on one surface (their readings no further apart than a wall at the
//!   steepest slope [`SURFACE_SLOPE`] allows) and the beam reads beyond
//!   that surface, its free evidence stops where theirs stops. Its own
//!   reading still marks what it hit: the return is real, only the free
//!   line to it has no second witness.
//! * **A no-return** (a reading at or beyond `z_max`: open sky, a window,
//!   a surface too dark or too oblique) measured nothing. It clears only
//!   what the nearest returns on both sides, at most
//!   [`MAX_NO_RETURN_GAP`] apart, saw free (the nearer of their free
//!   ranges, at most the no-return reach); without a return on each side
//!   it clears nothing. A wider gap of no-returns (a window onto open sky,
//!   the outside of a building past its last wall) leaves gray what
//!   nobody saw.
//!
//! Both rules look at a few neighbouring readings per beam and shorten
//! bands: no cell is visited twice, and what the beams between them fill
//! ([`super::traversal::RayMapper::integrate_bands_between`]) ends with the
//! shortened bands.

use super::traversal::BeamBand;

/// The longest run of neighbouring beams that may pass a surface their
/// two flanking neighbours see and still count as contradicted: a pane
/// of glass passes one beam or two between returns; a wider run is an
/// opening (a doorway seen squarely is several beams wide at any range
/// a laser sees a room's far wall).
pub const MAX_PASSING_RUN: usize = 2;

/// The widest gap between two returns, radians, across which the
/// no-returns between them clear what both saw free: 5°, a dark patch, a
/// pane or a person's legs a few beams wide at any spacing (4 beams at
/// 1°, 9 at 0.5°). A wider gap is an opening (a window 2 m wide seen from
/// 3 m spans 37°) and clears nothing.
pub const MAX_NO_RETURN_GAP: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// How far apart two flanking readings may lie, beyond their occupied
/// bands, for both to count as one surface, in units of the arc
/// `z δφ` between them: readings of a plane at incidence `θ` lie
/// `z δφ / tan θ` apart, so this admits surfaces down to 18°
/// (`atan(1 / 3)`); a doorway's frame seen at a grazing angle is such a
/// surface, and its two edges a depth jump only past that.
pub const SURFACE_SLOPE: f64 = 3.0;

/// The widest spacing of beams whose readings are compared, radians: 5°
/// (past any scanner's spacing; wider is a gap in the scan).
const MAX_SPACING: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Shortens `bands` (one per beam of a scan with `ranges` and `bearings`;
/// `is_return` tells a return from a no-return) by the two rules of the
/// module: a beam contradicted by its flanking returns keeps free evidence
/// only as far as theirs, and a no-return clears only what its flanking
/// returns saw free, or nothing. `None` bands (no beam to walk) stay.
pub fn rest_on_neighbours(
    ranges: &[f64],
    bearings: &[f64],
    is_return: impl Fn(f64) -> bool,
    bands: &mut [Option<BeamBand>],
) {
    let n = bands.len().min(ranges.len()).min(bearings.len());
    let returned = |j: usize| is_return(ranges[j]) && bands[j].is_some();
    // Decided on the bands as `beam_bands` made them, applied after: a
    // shortened band is no witness for its neighbour.
    let mut cuts: Vec<(usize, Option<f64>)> = Vec::new();
    // No-returns: the nearest return on each side, the two at most
    // `MAX_NO_RETURN_GAP` apart.
    let span = |l: usize, r: usize| (bearings[r] - bearings[l]).abs();
    let flank = |i: usize, left: bool| -> Option<usize> {
        (1..)
            .map_while(|d| if left { i.checked_sub(d) } else { Some(i + d) })
            .take_while(|&j| j < n && span(i.min(j), i.max(j)) <= MAX_NO_RETURN_GAP)
            .find(|&j| returned(j))
    };
    for i in 0..n {
        let Some(band) = bands[i] else { continue };
        if is_return(ranges[i]) {
            continue;
        }
        let to = match (flank(i, true), flank(i, false)) {
            (Some(l), Some(r))
                if span(l, r) <= MAX_NO_RETURN_GAP && within_spacing(bearings, l, r) =>
            {
                let (a, b) = (bands[l], bands[r]);
                let to = band
                    .reach
                    .min(a.map_or(0.0, |a| a.free_until))
                    .min(b.map_or(0.0, |b| b.free_until));
                (to > 0.0).then_some(to)
            }
            _ => None,
        };
        cuts.push((i, to));
    }
    // Returns beyond a surface both flanking returns see: every pair of
    // returns at most a run apart on one surface, and the beams between
    // them that read past it.
    let half = |b: BeamBand| 0.5 * (b.occupied_until - b.occupied_from).max(0.0);
    for l in 0..n {
        let Some(a) = bands[l].filter(|_| returned(l)) else {
            continue;
        };
        for r in (l + 2..=l + MAX_PASSING_RUN + 1).take_while(|&r| r < n) {
            let Some(b) = bands[r].filter(|_| returned(r)) else {
                continue;
            };
            let (zl, zr) = (ranges[l], ranges[r]);
            let arc = zl.min(zr) * (bearings[r] - bearings[l]).abs();
            let one_surface = (zl - zr).abs() <= half(a) + half(b) + SURFACE_SLOPE * arc;
            if !(one_surface && within_spacing(bearings, l, r)) {
                continue;
            }
            let surface = a.occupied_until.max(b.occupied_until);
            let beyond = |k: usize| match bands[k] {
                None => true,
                Some(c) => !is_return(ranges[k]) || ranges[k] - half(c) > surface,
            };
            if !(l + 1..r).all(beyond) {
                continue;
            }
            let to = a.free_until.min(b.free_until);
            cuts.extend((l + 1..r).filter(|&k| returned(k)).map(|k| (k, Some(to))));
        }
    }
    for (i, to) in cuts {
        let Some(band) = bands[i].as_mut() else {
            continue;
        };
        match to {
            None => bands[i] = None,
            Some(to) if band.occupied_until > band.occupied_from => {
                // A return keeps its reading; only its free line shortens.
                band.free_until = band.free_until.min(to);
            }
            Some(to) => {
                *band = BeamBand {
                    reach: to,
                    free_until: to,
                    occupied_from: to,
                    occupied_until: to,
                };
            }
        }
    }
}

/// Whether beams `l` and `r` are neighbours of one sweep: every step
/// between them within [`MAX_SPACING`].
fn within_spacing(bearings: &[f64], l: usize, r: usize) -> bool {
    (l..r).all(|k| {
        let s = (bearings[k + 1] - bearings[k]).abs();
        s > 0.0 && s <= MAX_SPACING
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(z: f64) -> Option<BeamBand> {
        Some(BeamBand {
            reach: z + 0.1,
            free_until: z - 0.1,
            occupied_from: z - 0.1,
            occupied_until: z + 0.1,
        })
    }

    fn no_return(reach: f64) -> Option<BeamBand> {
        Some(BeamBand {
            reach,
            free_until: reach,
            occupied_from: reach,
            occupied_until: reach,
        })
    }

    fn bearings(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 * 0.01).collect()
    }

    const MAX: f64 = 30.0;

    fn run(ranges: &[f64], bands: &mut [Option<BeamBand>]) {
        rest_on_neighbours(ranges, &bearings(ranges.len()), |z| z < MAX, bands);
    }

    /// A beam through a pane whose neighbours return from it keeps its
    /// reading and loses its free line past the pane.
    #[test]
    fn a_beam_its_neighbours_contradict_stops_at_their_surface() {
        let ranges = [3.0, 3.0, 8.0, 3.0, 3.0];
        let mut bands: Vec<_> = ranges.iter().map(|&z| band(z)).collect();
        run(&ranges, &mut bands);
        let b = bands[2].unwrap();
        assert_eq!(b.free_until, 2.9);
        assert_eq!((b.occupied_from, b.occupied_until), (7.9, 8.1));
        assert_eq!(bands[1], band(3.0));
    }

    /// Two beams through one pane between returns off it are contradicted
    /// too.
    #[test]
    fn two_passing_beams_are_contradicted() {
        let ranges = [3.0, 3.0, 8.0, 9.0, 3.0, 3.0];
        let mut bands: Vec<_> = ranges.iter().map(|&z| band(z)).collect();
        run(&ranges, &mut bands);
        assert_eq!(bands[2].unwrap().free_until, 2.9);
        assert_eq!(bands[3].unwrap().free_until, 2.9);
    }

    /// A run of passing beams wider than [`MAX_PASSING_RUN`] is an opening.
    #[test]
    fn a_wide_run_of_passing_beams_is_an_opening() {
        let ranges = [3.0, 3.0, 8.0, 8.0, 8.0, 3.0, 3.0];
        let mut bands: Vec<_> = ranges.iter().map(|&z| band(z)).collect();
        let before = bands.clone();
        run(&ranges, &mut bands);
        assert_eq!(bands, before);
    }

    /// Flanking readings at a depth jump are two surfaces, not one.
    #[test]
    fn flanks_at_a_depth_jump_contradict_nothing() {
        let ranges = [2.0, 2.0, 9.0, 5.0, 5.0];
        let mut bands: Vec<_> = ranges.iter().map(|&z| band(z)).collect();
        let before = bands.clone();
        run(&ranges, &mut bands);
        assert_eq!(bands, before);
    }

    /// A no-return clears what its flanking returns saw free; a run of
    /// them too wide to be flanked clears nothing.
    #[test]
    fn a_no_return_clears_only_what_its_flanks_saw() {
        // Beams 0.01 rad apart: 9 of them span 0.08 rad, 4.6°; 10, 5.2°.
        let mut ranges = vec![4.0, MAX, 3.0, MAX, MAX, MAX, 6.0];
        ranges.extend([MAX; 9]);
        ranges.push(5.0);
        let mut bands: Vec<_> = ranges
            .iter()
            .map(|&z| if z < MAX { band(z) } else { no_return(5.0) })
            .collect();
        run(&ranges, &mut bands);
        assert_eq!(bands[1].unwrap().reach, 2.9);
        assert_eq!(bands[1].unwrap().free_until, 2.9);
        assert!(
            bands[3..6].iter().all(|b| b.unwrap().reach == 2.9),
            "{bands:?}"
        );
        assert!(bands[7..16].iter().all(Option::is_none), "{bands:?}");
    }
}
