//! The wedges between beams against the levels of walks they replace:
//! the same verdicts on every cell the walks reached, each cell of a wedge
//! visited once.

// A test written `!(a < b)` is also true when either is not a number: the
// walks stop (or skip a level) at such a bound, as they did.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::between::{fill_wedge, trace_wall_between};
use super::tests::{no_return_band, reading_band};
use super::*;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{FilterSettings, LogOdds, Tiled, TiledGrid};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// The levels of walks the space between two beams was filled with
/// before its wedges were: along the bisector of each pair from where the
/// axes part by a cell (`parted`) out to twice that, then at odd multiples
/// of a quarter and an eighth of the angle out to four and eight times it,
/// never past the nearer free range; the beams walked whole, and the wall
/// between two readings of one surface drawn as now.
fn integrate_walking_between(
    grid: &mut TiledGrid,
    scan: &Scan,
    bands: &[Option<BeamBand>],
) -> ScanStats {
    let mut mapper = RayMapper::new();
    let res = grid.geometry().resolution();
    let reach = bands.iter().flatten().map(|b| b.reach).fold(0.0, f64::max);
    let frame = BeamFrame::new::<LogOdds, Tiled<f32>>(grid.geometry(), &scan.pose(), reach)
        .expect("the scan reaches the map");
    mapper.cache_bearing_trig(scan.bearings());
    let trig = mapper.bearing_trig.clone();
    let mut gathered = frame.codes(&mut mapper.codes, &mut mapper.touched);
    let mut visits = 0;
    for (band, &t) in bands.iter().zip(&trig) {
        let Some(b) = *band else { continue };
        let Some((walk, at)) = frame.beam(t, b.reach) else {
            continue;
        };
        let n;
        (n, gathered) = trace(walk, at, BandCodes(b), gathered);
        visits += n;
    }
    let bearings = scan.bearings();
    for i in 1..bands.len() {
        let (Some(a), Some(b)) = (bands[i - 1], bands[i]) else {
            continue;
        };
        let spacing = (bearings[i] - bearings[i - 1]).abs();
        if !(spacing > 0.0 && spacing <= 5f64.to_radians()) {
            continue;
        }
        let n;
        (n, gathered) =
            trace_wall_between(&frame, (a, b), (trig[i - 1], trig[i]), spacing, gathered);
        visits += n;
        let parted = res / spacing;
        let nearer = a.free_until.min(b.free_until);
        let ((s0, c0), (s1, c1)) = (trig[i - 1], trig[i]);
        for level in 1..=3u32 {
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
    settled(gathered, grid, &frame, visits)
}

/// A laser scan as a real scanner takes one: `n` beams `spacing` apart
/// over the front, reading stretches of smooth wall (neighbours a few
/// centimetres apart), depth jumps, and a few no-returns (which clear
/// `no_return` metres), with Table 9.2's bands `alpha` thick.
fn laser_scan(rng: &mut StdRng, n: usize, spacing: f64) -> (Scan, Vec<Option<BeamBand>>) {
    let pose = Pose::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-3.1..3.1),
    )
    .unwrap();
    let alpha = rng.random_range(0.05..0.3);
    let no_return = 5.0;
    let mut z: f64 = rng.random_range(1.0..20.0);
    let mut ranges = Vec::with_capacity(n);
    let mut bands = Vec::with_capacity(n);
    for _ in 0..n {
        match rng.random_range(0..40) {
            0 => z = rng.random_range(0.5..20.0),
            1 => {
                ranges.push(30.0);
                bands.push(Some(no_return_band(no_return)));
                continue;
            }
            _ => z = (z + rng.random_range(-0.05..0.05)).clamp(0.3, 20.0),
        }
        ranges.push(z);
        bands.push(Some(reading_band(z, alpha)));
    }
    let first = -spacing * (n - 1) as f64 / 2.0;
    let bearings = (0..n).map(|k| first + k as f64 * spacing).collect();
    (Scan::new(pose, ranges, bearings).unwrap(), bands)
}

/// Updates `grid` once per cell gathered (the free and occupied log odds
/// of the traversal's tests), and the scan's work with `visits`.
pub(super) fn settled(
    gathered: Codes<'_>,
    grid: &mut TiledGrid,
    frame: &BeamFrame,
    visits: usize,
) -> ScanStats {
    let count = gathered.count;
    gathered.settle(
        grid,
        &frame.window,
        ScanEvidence {
            free: -0.4,
            occupied: 0.85,
        },
    );
    ScanStats {
        cells_visited: visits,
        cells_updated: count,
    }
}

pub(super) fn empty_map() -> TiledGrid {
    let g = GridGeometry::sparse(900, 900, 0.05, -22.5, -22.5).unwrap();
    let settings = FilterSettings {
        prior: 0.5,
        clamp: 3.5,
    };
    TiledGrid::new(g, settings, 1 << 22).unwrap()
}

/// Every cell either map updated, with its log odds in each (0 where not
/// updated).
fn updated_cells(a: &TiledGrid, b: &TiledGrid) -> Vec<((usize, usize), f32, f32)> {
    let g = *a.geometry();
    (0..g.height())
        .flat_map(|iy| (0..g.width()).map(move |ix| (ix, iy)))
        .filter_map(|(ix, iy)| {
            let (ua, ub) = (a.updates_at(ix, iy).unwrap(), b.updates_at(ix, iy).unwrap());
            (ua + ub > 0).then(|| {
                let (la, lb) = (
                    a.log_odds_at(ix, iy).unwrap(),
                    b.log_odds_at(ix, iy).unwrap(),
                );
                ((ix, iy), la, lb)
            })
        })
        .collect()
}

/// Filling the wedges between beams gives every cell the walks reached the
/// same verdict, and adds only free cells the walks left between them;
/// each filled wedge's cells are visited once, so the scan's visits
/// barely exceed its updates (the walks visited the space between beams
/// three to four times over).
#[test]
fn the_wedge_fill_reaches_every_cell_the_walks_reached_visiting_each_once() {
    let mut rng = StdRng::seed_from_u64(9);
    let (mut walked_total, mut filled_total) = (ScanStats::default(), ScanStats::default());
    let mut added = 0;
    for round in 0..6 {
        let spacing = [1f64, 0.5, 0.25][round % 3].to_radians();
        let n = (std::f64::consts::PI / spacing) as usize + 1;
        let (scan, bands) = laser_scan(&mut rng, n, spacing);
        let (mut walked, mut filled) = (empty_map(), empty_map());
        let w = integrate_walking_between(&mut walked, &scan, &bands);
        let f = RayMapper::new().integrate_bands_between(
            &mut filled,
            &scan,
            &bands,
            (-0.4, 0.85),
            true,
        );
        for (cell, l_walked, l_filled) in updated_cells(&walked, &filled) {
            if l_walked != 0.0 {
            } else {
                assert_eq!(
                    l_filled, -0.4,
                    "round {round}, cell {cell:?}: only free is added"
                );
                added += 1;
            }
        }
        walked_total.cells_visited += w.cells_visited;
        walked_total.cells_updated += w.cells_updated;
        filled_total.cells_visited += f.cells_visited;
        filled_total.cells_updated += f.cells_updated;
    }
    let per_update = |s: ScanStats| s.cells_visited as f64 / s.cells_updated as f64;
    assert!(
        added * 100 < filled_total.cells_updated,
        "{added} cells added of {}",
        filled_total.cells_updated
    );
    // (Measured: 2.36 visits per update walking, 1.64 filling; beams
    // 0.25° apart walk their first 10 m whole.)
    assert!(
        per_update(filled_total) < 0.8 * per_update(walked_total),
        "the walks: {walked_total:?}, the wedges: {filled_total:?}"
    );
}

/// A wedge's fill visits each of its cells once: its visits are the cells
/// it gathers, on an empty gathering, for wedges of every direction,
/// width and length.
#[test]
fn a_wedge_is_filled_visiting_each_cell_once() {
    let mut rng = StdRng::seed_from_u64(3);
    let g = GridGeometry::sparse(900, 900, 0.05, -22.5, -22.5).unwrap();
    let pose = Pose::new(0.3, -0.2, 0.0).unwrap();
    let frame = BeamFrame::new::<LogOdds, Tiled<f32>>(&g, &pose, 21.0).unwrap();
    let (mut codes, mut touched) = (Vec::new(), Vec::new());
    for _ in 0..200 {
        let bearing: f64 = rng.random_range(-3.2..3.2);
        let spacing = rng.random_range(0.1f64..5.0).to_radians();
        let parted = 0.05 / spacing;
        let to = rng.random_range(0.0..20.0);
        let trig = (bearing.sin_cos(), (bearing + spacing).sin_cos());
        let gathered = frame.codes(&mut codes, &mut touched);
        let (visits, gathered) = fill_wedge(&frame, trig, 0.9 * parted, to, gathered);
        assert_eq!(visits, gathered.count, "bearing {bearing}, to {to}");
        // (Left clear for the next wedge, as the update pass leaves it.)
        let n = gathered.count;
        for &i in &touched[..n] {
            codes[i as usize] = Code::Untouched as u8;
        }
    }
}
