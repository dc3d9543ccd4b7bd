//! The traversal against a plain reference and its own promises: one
//! update per cell per scan, occupied winning, beam order irrelevant, the
//! tiled map cell for cell the dense one.

use super::*;
use crate::geometry::raster::supercover;
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::grid::FilterSettings;
use crate::grid::LogOddsGrid;
use crate::inverse::{HandCrafted, HandCraftedParams};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// Table 9.2 without its axis profile: the mapper then asks
/// `evidence` per cell.
struct PerCell(HandCrafted);

impl InverseModel for PerCell {
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        self.0.evidence(r, phi, z)
    }
    fn reach(&self, z: f64) -> f64 {
        self.0.reach(z)
    }
    fn half_width(&self) -> f64 {
        self.0.half_width()
    }
    fn z_max(&self) -> f64 {
        self.0.z_max()
    }
    fn l0(&self) -> f32 {
        self.0.l0()
    }
}

/// The traversal mapper written plainly on top of `supercover`: the
/// range of each cell computed afresh, the verdicts of a scan gathered
/// in a map, occupied (the larger) winning, then one update per cell.
fn reference_integrate<M: InverseModel>(
    grid: &mut LogOddsGrid,
    model: &M,
    scan: &Scan,
) -> ScanStats {
    let g = *grid.geometry();
    let pose = scan.pose();
    let (su, sv) = g.world_to_grid(pose.x, pose.y);
    let res = g.resolution();
    let mut best = std::collections::BTreeMap::<usize, f32>::new();
    let mut visits = 0;
    for (&z, &bearing) in scan.ranges().iter().zip(scan.bearings()) {
        let reach = model.reach(z);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN reach is no beam
        if !(reach > 0.0) {
            continue;
        }
        let (s, c) = (pose.theta + bearing).sin_cos();
        let end = (su + reach * c / res, sv + reach * s / res);
        visits += supercover(g.width(), g.height(), (su, sv), end, |ix, iy| {
            let r = res * ((ix as f64 + 0.5 - su) * c + (iy as f64 + 0.5 - sv) * s);
            let e = model.evidence(r, 0.0, z);
            if e != 0.0 {
                let slot = best.entry(g.index(ix, iy)).or_insert(e);
                *slot = slot.max(e);
            }
        });
    }
    for (&i, &e) in &best {
        grid.apply(i, e);
    }
    ScanStats {
        cells_visited: visits,
        cells_updated: best.len(),
    }
}

fn random_model(rng: &mut StdRng) -> HandCrafted {
    HandCrafted::new(HandCraftedParams {
        alpha: rng.random_range(0.05..0.4),
        beta: 0.02,
        z_max: 8.0,
        l_occ: rng.random_range(0.2..2.0),
        l_free: rng.random_range(-2.0..-0.2),
        l0: rng.random_range(-0.3..0.3),
    })
    .unwrap()
}

/// A scan from anywhere near (or outside) a 6 m x 4 m map, with
/// no-returns, zero readings and repeated bearings among its beams.
fn random_scan(rng: &mut StdRng) -> Scan {
    let pose = Pose::new(
        rng.random_range(-2.0..7.0),
        rng.random_range(-2.0..5.0),
        rng.random_range(-4.0..4.0),
    )
    .unwrap();
    let n = rng.random_range(1..120);
    let ranges = (0..n)
        .map(|k| match k % 11 {
            0 => 8.0 + rng.random_range(0.0..2.0),
            1 => 0.0,
            _ => rng.random_range(0.0..9.0),
        })
        .collect();
    let span = rng.random_range(0.0..7.0);
    let bearings = (0..n)
        .map(|k| {
            if k % 13 == 5 {
                0.25
            } else {
                rng.random_range(-span..=span)
            }
        })
        .collect();
    Scan::new(pose, ranges, bearings).unwrap()
}

fn map() -> LogOddsGrid {
    let g = GridGeometry::new(60, 40, 0.1, -1.0, -1.0).unwrap();
    LogOddsGrid::new(
        g,
        FilterSettings {
            prior: 0.5,
            clamp: 2.0,
        },
    )
    .unwrap()
}

#[test]
fn traversal_builds_the_same_map_as_the_plain_reference() {
    let mut rng = StdRng::seed_from_u64(5);
    for _ in 0..40 {
        let model = random_model(&mut rng);
        let (mut fast, mut plain, mut per_cell) = (map(), map(), map());
        let (mut mapper, mut per_cell_mapper) = (RayMapper::new(), RayMapper::new());
        for _ in 0..6 {
            let scan = random_scan(&mut rng);
            let stats = mapper.integrate(&mut fast, &model, &scan);
            assert_eq!(stats, reference_integrate(&mut plain, &model, &scan));
            let per_cell_stats = per_cell_mapper.integrate(&mut per_cell, &PerCell(model), &scan);
            assert_eq!(stats, per_cell_stats);
        }
        assert_eq!(fast, plain, "profile path vs reference");
        assert_eq!(fast, per_cell, "profile path vs per-cell evidence");
    }
}

/// Table 9.2 with its evidence scaled by a factor that depends on the
/// reading: every beam is a step profile, but their values differ, so
/// the mapper must gather floats (occupied still winning, and between
/// two verdicts the larger).
struct ScaledByReading(HandCrafted);

impl ScaledByReading {
    fn scale(z: f64) -> f32 {
        1.0 + (z * 4.0).floor().rem_euclid(3.0) as f32 * 0.5
    }
}

impl InverseModel for ScaledByReading {
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        self.0.evidence(r, phi, z) * Self::scale(z)
    }
    fn reach(&self, z: f64) -> f64 {
        self.0.reach(z)
    }
    fn half_width(&self) -> f64 {
        self.0.half_width()
    }
    fn z_max(&self) -> f64 {
        self.0.z_max()
    }
    fn l0(&self) -> f32 {
        self.0.l0()
    }
    fn axis_profile(&self, z: f64) -> Option<AxisProfile> {
        let p = self.0.axis_profile(z)?;
        Some(AxisProfile {
            free: p.free * Self::scale(z),
            occupied: p.occupied * Self::scale(z),
            ..p
        })
    }
}

#[test]
fn beams_with_different_step_values_build_the_reference_map() {
    let mut rng = StdRng::seed_from_u64(6);
    for _ in 0..40 {
        let model = ScaledByReading(random_model(&mut rng));
        let (mut fast, mut plain) = (map(), map());
        let mut mapper = RayMapper::new();
        for _ in 0..6 {
            let scan = random_scan(&mut rng);
            let stats = mapper.integrate(&mut fast, &model, &scan);
            assert_eq!(stats, reference_integrate(&mut plain, &model, &scan));
        }
        assert_eq!(fast, plain);
    }
}

#[test]
fn each_cell_is_updated_once_per_scan_whatever_the_beam_order() {
    let mut rng = StdRng::seed_from_u64(9);
    for _ in 0..30 {
        let model = random_model(&mut rng);
        let scan = random_scan(&mut rng);
        let mut order: Vec<usize> = (0..scan.len()).collect();
        order.reverse();
        order.rotate_left(rng.random_range(0..scan.len()));
        let shuffled = Scan::new(
            scan.pose(),
            order.iter().map(|&k| scan.ranges()[k]).collect(),
            order.iter().map(|&k| scan.bearings()[k]).collect(),
        )
        .unwrap();
        let (mut a, mut b) = (map(), map());
        let stats = RayMapper::new().integrate(&mut a, &model, &scan);
        RayMapper::new().integrate(&mut b, &model, &shuffled);
        assert_eq!(a.log_odds(), b.log_odds());
        assert!(a.update_counts().iter().all(|&n| n <= 1));
        let updated = a.update_counts().iter().filter(|&&n| n == 1).count();
        assert_eq!(stats.cells_updated, updated);
    }
}

#[test]
fn occupied_wins_where_a_wall_cell_lies_on_another_beams_free_path() {
    // Beam 0 ends at 1.0 m straight ahead; beam 1 passes through the
    // same cells at a shallow angle and goes on for another metre.
    let g = GridGeometry::new(40, 5, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let pose = Pose::new(0.05, 0.25, 0.0).unwrap();
    let scan = Scan::new(pose, vec![1.0, 2.0], vec![0.0, 0.001]).unwrap();
    RayMapper::new().integrate(&mut m, &lidar(), &scan);
    assert!(
        m.log_odds()[g.index(10, 2)] > 0.0,
        "the wall cell stays occupied"
    );
    assert!(
        m.log_odds()[g.index(15, 2)] < 0.0,
        "beyond it, beam 1 carves"
    );
}

/// The tiled map holds, cell for cell, what a dense grid of the same
/// extent holds after the same scans (beams leaving the map included),
/// with the same counts per scan, with and without the space between
/// beams: the tiled map gathers by segment (a map 150 cells wide ends in
/// a partial one), the dense map in a touched list.
#[test]
fn tiled_integration_builds_the_dense_map_cell_for_cell() {
    use crate::geometry::GridGeometry;
    use crate::grid::TiledGrid;
    let mut rng = StdRng::seed_from_u64(12);
    let (w, h, res, ox, oy) = (150, 97, 0.05, -1.0, -1.0);
    for round in 0..20 {
        let between = round % 2 == 1;
        let g = GridGeometry::new(w, h, res, ox, oy).unwrap();
        let settings = FilterSettings {
            prior: 0.5,
            clamp: 2.0,
        };
        let mut dense = LogOddsGrid::new(g, settings).unwrap();
        let mut tiled = TiledGrid::new(
            GridGeometry::sparse(w, h, res, ox, oy).unwrap(),
            settings,
            1 << 20,
        )
        .unwrap();
        let (mut a, mut b) = (RayMapper::new(), RayMapper::new());
        for _ in 0..5 {
            let scan = random_scan(&mut rng);
            let bands: Vec<Option<BeamBand>> = scan
                .ranges()
                .iter()
                .map(|&z| {
                    let z = z.min(3.0);
                    (z > 0.0).then_some(reading_band(z, 0.1))
                })
                .collect();
            let sd = a.integrate_bands_between(&mut dense, &scan, &bands, (-0.4, 0.85), between);
            let st = b.integrate_bands_between(&mut tiled, &scan, &bands, (-0.4, 0.85), between);
            assert_eq!(sd, st);
        }
        for iy in 0..h {
            for ix in 0..w {
                let i = g.index(ix, iy);
                assert_eq!(
                    tiled.log_odds_at(ix, iy),
                    Some(dense.log_odds()[i]),
                    "({ix}, {iy})"
                );
                assert_eq!(tiled.updates_at(ix, iy), Some(dense.update_counts()[i]));
            }
        }
        assert!(tiled.tiles_allocated() <= 6);
    }
}

#[test]
fn evidence_of_zero_strength_updates_nothing() {
    let model = HandCrafted::with_strength(*lidar().params(), 0.0).unwrap();
    let mut rng = StdRng::seed_from_u64(2);
    let mut m = map();
    let stats = RayMapper::new().integrate(&mut m, &model, &random_scan(&mut rng));
    assert_eq!(stats.cells_updated, 0);
    assert!(m.update_counts().iter().all(|&n| n == 0));
}

fn lidar() -> HandCrafted {
    HandCrafted::new(HandCraftedParams {
        alpha: 0.15,
        beta: 0.02,
        ..HandCraftedParams::laser(8.0)
    })
    .unwrap()
}

#[test]
fn one_beam_marks_free_then_occupied() {
    let g = GridGeometry::new(20, 5, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let scan = Scan::new(Pose::new(0.05, 0.25, 0.0).unwrap(), vec![1.0], vec![0.0]).unwrap();
    let stats = RayMapper::new().integrate(&mut m, &lidar(), &scan);
    let l = |ix| m.log_odds()[g.index(ix, 2)];
    assert!(l(3) < 0.0 && l(9) < 0.0, "free in front");
    assert!(l(10) > 0.0, "occupied at 1.0 m");
    assert_eq!(l(12), 0.0, "unknown behind");
    assert_eq!(stats.cells_updated, 11);
}

/// The window index's division by multiplication is exact over the whole
/// range a window can have (every width up to 4,095 cells, every index
/// below 2^25), and refuses widths past it.
#[test]
fn division_by_the_window_width_is_exact_over_every_window() {
    for d in 1..4096usize {
        let div = super::windowed::DivideBy::new(d).unwrap();
        let last = (1usize << 25) - 1;
        for w in [0, 1, d - 1, d, d + 1, 7 * d + 3, last - d, last - 1, last]
            .into_iter()
            .chain((0..64).map(|k| (k * 524_287 + d) % (last + 1)))
        {
            assert_eq!(div.div_rem(w), (w / d, w % d), "{w} / {d}");
        }
    }
    assert!(
        super::windowed::DivideBy::new(0).is_none()
            && super::windowed::DivideBy::new(4096).is_none()
    );
}

/// Two beams 1° apart reading 20 m: alone, their walks leave cells between
/// them unvisited once they part by more than a cell (2.9 m at 5 cm);
/// with the space between them filled, every cell whose centre lies
/// between the two axes is free out to eight times that range (23 m, so
/// here up to the readings), and each cell is still updated once.
#[test]
fn the_space_between_two_beams_is_free_out_to_eight_times_where_they_part() {
    use crate::grid::TiledGrid;
    let spacing = 1f64.to_radians();
    let scan = Scan::new(
        Pose::new(0.0, 0.0, 0.0).unwrap(),
        vec![20.0, 20.0],
        vec![0.3, 0.3 + spacing],
    )
    .unwrap();
    let band = Some(BeamBand {
        reach: 20.05,
        free_until: 19.95,
        occupied_from: 19.95,
        occupied_until: 20.05,
    });
    let g = GridGeometry::sparse(900, 900, 0.05, -22.5, -22.5).unwrap();
    let settings = FilterSettings {
        prior: 0.5,
        clamp: 3.5,
    };
    let run = |between: bool| {
        let mut grid = TiledGrid::new(g, settings, 1 << 22).unwrap();
        let stats = RayMapper::new().integrate_bands_between(
            &mut grid,
            &scan,
            &[band, band],
            (-0.4, 0.85),
            between,
        );
        (grid, stats)
    };
    let (thin, thin_stats) = run(false);
    let (wide, wide_stats) = run(true);
    let parted = 0.05 / spacing;
    let between_axes = |r: f64, f: f64| {
        let a = 0.3 + f * spacing;
        g.world_to_cell(r * a.cos(), r * a.sin()).unwrap()
    };
    let (mut holes_thin, mut holes_wide) = (0, 0);
    for k in 0..400 {
        let r = 1.0 + k as f64 * ((8.0 * parted).min(19.5) - 1.0) / 400.0;
        for f in [0.2, 0.35, 0.5, 0.65, 0.8] {
            let (ix, iy) = between_axes(r, f);
            holes_thin += (thin.updates_at(ix, iy).unwrap() == 0) as usize;
            let l = wide.log_odds_at(ix, iy).unwrap();
            holes_wide += (l != -0.4) as usize;
            assert!(wide.updates_at(ix, iy).unwrap() <= 1, "once per scan");
        }
    }
    assert!(holes_thin > 500, "thin beams leave {holes_thin} holes");
    assert_eq!(holes_wide, 0);
    assert!(wide_stats.cells_updated > thin_stats.cells_updated);
    // Occupied only on the wall the two readings lie on, nothing nearer.
    for (ix, iy) in cells_where(&wide, |l| l > 0.0) {
        let (x, y) = g.cell_center(ix, iy);
        let r = x.hypot(y);
        assert!((19.9..=20.1).contains(&r), "occupied at {r} m");
    }
}

/// Every cell of `grid` (900 × 900) whose log odds pass `keep`.
fn cells_where(grid: &crate::grid::TiledGrid, keep: impl Fn(f32) -> bool) -> Vec<(usize, usize)> {
    (0..900)
        .flat_map(|iy| (0..900).map(move |ix| (ix, iy)))
        .filter(|&(ix, iy)| keep(grid.log_odds_at(ix, iy).unwrap()))
        .collect()
}

/// Two beams 1° apart with readings `ranges` (Table 9.2's bands, `alpha`
/// thick) at bearings 0.25 and 0.25 + 1° from the origin, integrated into
/// an empty 45 m map with and without the space between beams.
fn two_beams_of_width(ranges: [f64; 2], alpha: f64) -> [crate::grid::TiledGrid; 2] {
    use crate::grid::TiledGrid;
    let bearings = vec![0.25, 0.25 + 1f64.to_radians()];
    let scan = Scan::new(Pose::new(0.0, 0.0, 0.0).unwrap(), ranges.to_vec(), bearings).unwrap();
    let bands = ranges.map(|z| Some(reading_band(z, alpha)));
    let g = GridGeometry::sparse(900, 900, 0.05, -22.5, -22.5).unwrap();
    let settings = FilterSettings {
        prior: 0.5,
        clamp: 3.5,
    };
    [false, true].map(|between| {
        let mut grid = TiledGrid::new(g, settings, 1 << 22).unwrap();
        RayMapper::new().integrate_bands_between(&mut grid, &scan, &bands, (-0.4, 0.85), between);
        grid
    })
}

/// [`two_beams_of_width`] with a lidar's α, 0.1 m.
fn two_beams(ranges: [f64; 2]) -> [crate::grid::TiledGrid; 2] {
    two_beams_of_width(ranges, 0.1)
}

/// Two beams ending on a straight wall 15 m away (the plane x = 15 m)
/// read endpoints 27 cm apart; each beam is as wide as the spacing
/// (Table 9.2's β), so the wall between them is drawn whole, not as two
/// dots, and no free cell lies beyond it.
#[test]
fn the_wall_between_two_beams_far_away_is_drawn_whole() {
    let bearings = [0.25, 0.25 + 1f64.to_radians()];
    let [thin, wide] = two_beams(bearings.map(|b| 15.0 / b.cos()));
    let g = *wide.geometry();
    let (y0, y1) = (15.0 * bearings[0].tan(), 15.0 * bearings[1].tan());
    let wall: Vec<(usize, usize)> = (0..=100)
        .map(|k| y0 + (y1 - y0) * k as f64 / 100.0)
        .map(|y| g.world_to_cell(15.0, y).unwrap())
        .collect();
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN cell counts as a gap
    let gaps = |grid: &crate::grid::TiledGrid| {
        wall.iter()
            .filter(|&&(ix, iy)| !(grid.log_odds_at(ix, iy).unwrap() > 0.0))
            .count()
    };
    assert!(gaps(&thin) > 50, "thin beams leave {} gaps", gaps(&thin));
    assert_eq!(gaps(&wide), 0, "the wall between the readings is occupied");
    for (ix, iy) in cells_where(&wide, |l| l != 0.0) {
        let (x, _) = g.cell_center(ix, iy);
        assert!(
            x < 15.0 || wide.log_odds_at(ix, iy).unwrap() > 0.0,
            "free beyond the wall at x = {x}"
        );
        assert!(wide.updates_at(ix, iy).unwrap() <= 1, "once per scan");
    }
}

/// A depth jump between two beams (an object's edge 10 m away in front of
/// a wall at 14 m) is no surface: nothing is drawn across it.
#[test]
fn nothing_is_drawn_across_a_depth_jump_between_two_beams() {
    let [thin, wide] = two_beams([10.0, 14.0]);
    let occupied = |grid| cells_where(grid, |l| l > 0.0);
    assert!(!occupied(&thin).is_empty());
    assert_eq!(occupied(&thin), occupied(&wide));
}

/// The wall between two readings has a budget: no more cells than the two
/// beams' own walks. A band as thick as the range (a setting no scanner
/// has) draws no wall rather than a wide fan of long walks.
#[test]
fn a_band_as_thick_as_the_range_draws_no_wall_between_beams() {
    let [thin, wide] = two_beams_of_width([20.0, 20.0], 16.0);
    let occupied = |grid| cells_where(grid, |l| l > 0.0);
    assert!(!occupied(&thin).is_empty());
    assert_eq!(occupied(&thin), occupied(&wide));
}

/// Three beams 1° apart from the origin at bearings 0.25, 0.25 + 1° and
/// 0.25 + 2°, with readings `ranges` (a lidar's bands), integrated with the
/// space between beams into an empty 45 m map.
fn three_beams(ranges: [f64; 3]) -> crate::grid::TiledGrid {
    let bearings: Vec<f64> = (0..3).map(|k| 0.25 + (k as f64).to_radians()).collect();
    let scan = Scan::new(Pose::new(0.0, 0.0, 0.0).unwrap(), ranges.to_vec(), bearings).unwrap();
    let bands = ranges.map(|z| Some(reading_band(z, 0.1)));
    let g = GridGeometry::sparse(900, 900, 0.05, -22.5, -22.5).unwrap();
    let settings = FilterSettings {
        prior: 0.5,
        clamp: 3.5,
    };
    let mut grid = crate::grid::TiledGrid::new(g, settings, 1 << 22).unwrap();
    RayMapper::new().integrate_bands_between(&mut grid, &scan, &bands, (-0.4, 0.85), true);
    grid
}

/// The cells of `grid` whose centres lie between bearings `from` and `to`
/// (radians) and between 8 and 12 m from the origin: how many are free,
/// and how many unknown.
fn free_and_unknown_between(grid: &crate::grid::TiledGrid, from: f64, to: f64) -> (usize, usize) {
    let g = *grid.geometry();
    let (mut free, mut unknown) = (0, 0);
    for (ix, iy) in cells_where(grid, |_| true) {
        let (x, y) = g.cell_center(ix, iy);
        let (r, bearing) = (x.hypot(y), y.atan2(x));
        if (8.0..12.0).contains(&r) && bearing > from && bearing < to {
            match grid.log_odds_at(ix, iy).unwrap() {
                l if l < 0.0 => free += 1,
                0.0 => unknown += 1,
                _ => {}
            }
        }
    }
    (free, unknown)
}

/// A post 4 m away seen by one beam, with the beams on both sides passing
/// it to a wall 15 m away (a door frame's edge in a doorway): past the
/// post, the half of each wedge on the passing beam's side lies in that
/// beam's footprint and is free, not a strip of gray pinholes; behind the
/// post (within a quarter of the spacing of its bearing) nothing is
/// filled. Where the near reading is a wall's end (its other neighbour as
/// near), the wedge past it is left as before.
#[test]
fn the_floor_beside_a_post_both_neighbours_pass_is_free() {
    let b = |k: f64| 0.25 + k.to_radians();
    let eps = 0.02f64.to_radians();
    let post = three_beams([15.0, 4.0, 15.0]);
    for (from, to) in [(b(0.0) + eps, b(0.5) - eps), (b(1.5) + eps, b(2.0) - eps)] {
        let (free, unknown) = free_and_unknown_between(&post, from, to);
        assert!(free > 20, "{free} free cells beside the post");
        assert_eq!(unknown, 0, "no pinholes beside the post");
    }
    let (free, _) = free_and_unknown_between(&post, b(0.75), b(1.25));
    assert_eq!(free, 0, "nothing is filled behind the post");
    let wall_end = three_beams([15.0, 4.0, 4.0]);
    let (_, unknown) = free_and_unknown_between(&wall_end, b(0.0) + eps, b(0.5) - eps);
    assert!(
        unknown > 0,
        "beside a wall's end the wedge is left as it was"
    );
}

/// Table 9.2's band of a reading `z` with obstacle depth `alpha`: free in
/// front of it, occupied within `alpha / 2` of it.
pub(super) fn reading_band(z: f64, alpha: f64) -> BeamBand {
    BeamBand {
        reach: z + alpha / 2.0,
        free_until: z - alpha / 2.0,
        occupied_from: z - alpha / 2.0,
        occupied_until: z + alpha / 2.0,
    }
}

/// The band of a no-return that clears `reach` metres.
pub(super) fn no_return_band(reach: f64) -> BeamBand {
    BeamBand {
        reach,
        free_until: reach,
        occupied_from: reach,
        occupied_until: reach,
    }
}
