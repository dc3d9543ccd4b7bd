//! The fans of a scan against the walks and wedges they stand in for: the
//! same verdict on every cell, for far fewer visits.

use super::between::{beam_spans, plan_wedges, trace_between};
use super::tests::{no_return_band, reading_band};
use super::wedge_tests::{empty_map, settled};
use super::*;
use crate::geometry::Pose;
use crate::grid::{LogOdds, Tiled, TiledGrid};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// The scan's bands as the wedges alone gather them: each beam walked
/// whole, or only its near part and tail where the wedges on both sides
/// hold its middle, and every wedge filled from its own start.
fn integrate_without_fans(
    grid: &mut TiledGrid,
    scan: &Scan,
    bands: &[Option<BeamBand>],
) -> ScanStats {
    let mut mapper = RayMapper::new();
    let res = grid.geometry().resolution();
    let walkable = |r: f64| r > 0.0 && r / res <= MAX_REACH_CELLS;
    let reach = bands.iter().flatten().map(|b| b.reach).fold(0.0, f64::max);
    let frame = BeamFrame::new::<LogOdds, Tiled<f32>>(grid.geometry(), &scan.pose(), reach)
        .expect("the scan reaches the map");
    mapper.cache_bearing_trig(scan.bearings());
    let trig = mapper.bearing_trig.clone();
    let mut wedges = Vec::new();
    plan_wedges(bands, scan.bearings(), res, walkable, &mut wedges);
    let mut gathered = frame.codes(&mut mapper.codes, &mut mapper.touched);
    let mut visits = 0;
    for (i, (band, &t)) in bands.iter().zip(&trig).enumerate() {
        let Some(b) = *band else { continue };
        let spans = match beam_spans(&wedges, i, res) {
            Some((near, tail)) => vec![(0.0, near), (tail, b.reach)],
            None => vec![(0.0, b.reach)],
        };
        for (from, to) in spans {
            let walk = if from == 0.0 && to == b.reach {
                frame.beam(t, b.reach)
            } else {
                frame.segment(t, from, to)
            };
            let Some((walk, at)) = walk else { continue };
            let n;
            (n, gathered) = trace(walk, at, BandCodes(b), gathered);
            visits += n;
        }
    }
    let n;
    (n, gathered) = trace_between(
        &frame,
        bands,
        scan.bearings(),
        &trig,
        &wedges,
        |_, from| from,
        walkable,
        gathered,
    );
    visits += n;
    settled(gathered, grid, &frame, visits)
}

/// A scan `spacing` apart over the front, in stretches as a building and
/// the open air give them: no-returns side by side (which clear 5 m),
/// readings at one range (a round pillar seen from its centre, or equal
/// readings in a log's centimetres), smooth walls near and far, and depth
/// jumps; Table 9.2's bands `alpha` thick.
fn stretches_scan(rng: &mut StdRng, n: usize, spacing: f64) -> (Scan, Vec<Option<BeamBand>>) {
    let pose = Pose::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-3.1..3.1),
    )
    .unwrap();
    let alpha = rng.random_range(0.05..0.3);
    let (mut ranges, mut bands) = (Vec::with_capacity(n), Vec::with_capacity(n));
    while ranges.len() < n {
        let len = rng.random_range(1..60).min(n - ranges.len());
        let kind = rng.random_range(0..4);
        let mut z: f64 = rng.random_range(0.5..20.0);
        for _ in 0..len {
            let band = match kind {
                0 => {
                    ranges.push(30.0);
                    no_return_band(5.0)
                }
                k => {
                    if k == 2 {
                        z = (z + rng.random_range(-0.05..0.05)).clamp(0.3, 20.0);
                    } else if k == 3 && rng.random_range(0..8) == 0 {
                        z = rng.random_range(0.5..20.0);
                    }
                    ranges.push(z);
                    reading_band(z, alpha)
                }
            };
            bands.push(Some(band));
        }
    }
    let first = -spacing * (n - 1) as f64 / 2.0;
    let bearings = (0..n).map(|k| first + k as f64 * spacing).collect();
    (Scan::new(pose, ranges, bearings).unwrap(), bands)
}

/// Filling fans near the sensor (in place of walking each beam's near
/// part) and far out (in place of filling each wedge alone from where it
/// starts) gives every cell the same verdict as the walks and wedges do,
/// for fewer visits per cell updated (measured: 1.68 alone, 1.44 with
/// the fans; the far fans fill the near ones' cells again).
#[test]
fn fans_give_every_cell_the_verdict_the_walks_and_wedges_gave() {
    let mut rng = StdRng::seed_from_u64(17);
    let (mut alone, mut fanned) = (ScanStats::default(), ScanStats::default());
    for round in 0..12 {
        let spacing = [1f64, 0.5, 0.25][round % 3].to_radians();
        let n = (std::f64::consts::PI / spacing) as usize + 1;
        let (scan, bands) = stretches_scan(&mut rng, n, spacing);
        let (mut a, mut b) = (empty_map(), empty_map());
        let sa = integrate_without_fans(&mut a, &scan, &bands);
        let sb =
            RayMapper::new().integrate_bands_between(&mut b, &scan, &bands, (-0.4, 0.85), true);
        let g = *a.geometry();
        let mut differ = Vec::new();
        for iy in 0..g.height() {
            for ix in 0..g.width() {
                let (la, lb) = (a.log_odds_at(ix, iy), b.log_odds_at(ix, iy));
                if la != lb || a.updates_at(ix, iy) != b.updates_at(ix, iy) {
                    differ.push(((ix, iy), la, lb));
                }
            }
        }
        assert!(
            differ.is_empty(),
            "round {round}: {} cells differ, first {:?}",
            differ.len(),
            &differ[..differ.len().min(5)]
        );
        assert_eq!(sa.cells_updated, sb.cells_updated, "round {round}");
        alone.cells_visited += sa.cells_visited;
        alone.cells_updated += sa.cells_updated;
        fanned.cells_visited += sb.cells_visited;
        fanned.cells_updated += sb.cells_updated;
    }
    let per_update = |s: ScanStats| s.cells_visited as f64 / s.cells_updated as f64;
    assert!(
        per_update(fanned) < 0.9 * per_update(alone),
        "alone: {alone:?}, with fans: {fanned:?}"
    );
}
