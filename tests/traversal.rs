#![cfg(not(target_arch = "wasm32"))]
//! The ray-traversal mapper and the literal sweep of Table 9.1: the raster's
//! guarantees, clipping, and where the two mappers agree and differ.

use occgrid::geometry::raster::supercover;
use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::inverse::{HandCrafted, HandCraftedParams};
use occgrid::mapping::sweep::sweep_scan;
use occgrid::mapping::traversal::RayMapper;
use occgrid::sensors::Scan;
use occgrid::world::{Rect, World};
use rand::{Rng, SeedableRng};
use std::collections::HashSet;
use std::f64::consts::PI;

/// A staircase wall of cells (i, i) that touch only at their corners: no
/// segment from one side to the other may pass without visiting a wall cell.
#[test]
fn supercover_never_slips_diagonally_between_corner_touching_wall_cells() {
    let wall: HashSet<(usize, usize)> = (0..40).map(|i| (i, i)).collect();
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let mut checked = 0;
    for k in 0..2000 {
        // Every fourth ray runs exactly through lattice corners at 45 degrees,
        // perpendicular to the staircase: the case a plain DDA gets wrong.
        let (a, b) = if k % 4 == 0 {
            let c = rng.random_range(4..36) as f64;
            let d = rng.random_range(1..4) as f64;
            ((c + d, c - d), (c - d, c + d))
        } else {
            let below = (rng.random_range(5.0..39.0), 0.0);
            let below = (below.0, rng.random_range(0.0..below.0 - 1.0));
            let above = (rng.random_range(0.0..34.0), 0.0);
            let above = (above.0, rng.random_range(above.0 + 1.0..40.0));
            (below, above)
        };
        let mut crossed = false;
        supercover(40, 40, a, b, |x, y| crossed |= wall.contains(&(x, y)));
        assert!(crossed, "ray {a:?} -> {b:?} slipped through the wall");
        checked += 1;
    }
    assert_eq!(checked, 2000);
}

fn lidar(beta_deg: f64) -> HandCrafted {
    HandCrafted::new(HandCraftedParams {
        alpha: 0.2,
        beta: beta_deg.to_radians(),
        ..HandCraftedParams::laser(8.0)
    })
    .unwrap()
}

#[test]
fn a_beam_leaving_the_map_still_carves_the_cells_inside_it() {
    let g = GridGeometry::new(30, 10, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    // 5 m east from x = 1.0 m: the map ends at 3.0 m.
    let scan = Scan::new(Pose::new(1.05, 0.55, 0.0).unwrap(), vec![5.0], vec![0.0]).unwrap();
    let stats = RayMapper::new().integrate(&mut m, &lidar(1.0), &scan);
    assert_eq!(stats.cells_updated, 20, "cells 10..=29 of row 5");
    for ix in 10..30 {
        assert!(m.log_odds()[g.index(ix, 5)] < 0.0, "cell {ix} carved free");
    }
    assert!(
        m.log_odds().iter().all(|&l| l <= 0.0),
        "nothing occupied: the hit is off the map"
    );
    // A sensor outside the map, looking in, carves the cells it crosses.
    let mut m2 = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let scan = Scan::new(Pose::new(-2.0, 0.55, 0.0).unwrap(), vec![3.5], vec![0.0]).unwrap();
    RayMapper::new().integrate(&mut m2, &lidar(1.0), &scan);
    assert!(m2.log_odds()[g.index(0, 5)] < 0.0);
    assert!(
        m2.log_odds()[g.index(14, 5)] > 0.0,
        "hit at 1.5 m inside the map"
    );
}

/// A 6 m x 5 m room with a pillar, scanned from a few poses.
fn room() -> (World, Vec<Pose>) {
    let g = GridGeometry::new(60, 50, 0.1, 0.0, 0.0).unwrap();
    let w = World::from_boxes(
        g,
        &[
            Rect::new(0.0, 0.0, 6.0, 0.2),
            Rect::new(0.0, 4.8, 6.0, 5.0),
            Rect::new(0.0, 0.0, 0.2, 5.0),
            Rect::new(5.8, 0.0, 6.0, 5.0),
            Rect::new(3.0, 2.0, 3.4, 2.4),
        ],
    );
    let poses = [
        (1.5, 1.5, 0.3),
        (4.5, 1.2, 2.0),
        (2.2, 3.8, -0.7),
        (4.6, 3.9, 3.5),
    ]
    .iter()
    .map(|&(x, y, t)| Pose::new(x, y, t).unwrap())
    .collect();
    (w, poses)
}

fn scans(world: &World, poses: &[Pose], beams: usize) -> Vec<Scan> {
    let step = 2.0 * PI / beams as f64;
    poses
        .iter()
        .map(|p| {
            let ranges = (0..beams)
                .map(|i| world.cast(p.x, p.y, p.theta + i as f64 * step, 8.0))
                .collect();
            Scan::uniform(*p, ranges, 0.0, step).unwrap()
        })
        .collect()
}

/// Each cell as free (-1), unknown (0) or occupied (+1).
fn classes(m: &LogOddsGrid) -> Vec<i8> {
    m.log_odds()
        .iter()
        .map(|&l| {
            if l > 0.0 {
                1
            } else if l < 0.0 {
                -1
            } else {
                0
            }
        })
        .collect()
}

fn both_ways(beams: usize, beta_deg: f64) -> (Vec<i8>, Vec<i8>) {
    let (world, poses) = room();
    let model = lidar(beta_deg);
    let settings = FilterSettings::default();
    let mut traversed = LogOddsGrid::new(*world.geometry(), settings).unwrap();
    let mut swept = traversed.clone();
    let mut mapper = RayMapper::new();
    for s in scans(&world, &poses, beams) {
        mapper.integrate(&mut traversed, &model, &s);
        sweep_scan(&mut swept, &model, &s);
    }
    (classes(&traversed), classes(&swept))
}

fn disagreement(a: &[i8], b: &[i8]) -> f64 {
    let seen = a
        .iter()
        .zip(b)
        .filter(|(x, y)| **x != 0 || **y != 0)
        .count();
    let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
    differ as f64 / seen as f64
}

/// A thin LiDAR beam (1 degree, 360 beams): both mappers see the room alike.
/// Bound: at most 1% of the cells either mapper touched are classified
/// differently (free / unknown / occupied); the differences sit on wall
/// edges, where the sweep's Euclidean range and the traversal's along-axis
/// range straddle `z - alpha/2`.
#[test]
fn traversal_and_sweep_agree_for_a_thin_lidar_beam() {
    let (t, s) = both_ways(360, 1.0);
    let d = disagreement(&t, &s);
    println!("thin beam: {:.2}% of seen cells differ", 100.0 * d);
    assert!(d < 0.01, "{d}");
}

/// A 22 degree sonar cone with 16 beams: the sweep paints the whole cone,
/// the traversal only the rasters of the 16 axes, so the maps differ a lot
/// (here more than a third of the cells either touched, and the sweep
/// touches over 1.5 times as many cells).
#[test]
fn traversal_and_sweep_differ_for_a_22_degree_sonar_cone() {
    let (t, s) = both_ways(16, 22.0);
    let d = disagreement(&t, &s);
    println!("22 degree cone: {:.2}% of seen cells differ", 100.0 * d);
    assert!(d > 0.35, "{d}");
    let swept_cells = s.iter().filter(|&&c| c != 0).count();
    let traversed_cells = t.iter().filter(|&&c| c != 0).count();
    println!("cells touched: swept {swept_cells}, traversed {traversed_cells}");
    assert!(
        2 * swept_cells > 3 * traversed_cells,
        "{swept_cells} vs {traversed_cells}"
    );
}

#[test]
fn each_cell_is_updated_at_most_once_per_scan_and_beam_order_does_not_matter() {
    let (world, poses) = room();
    let model = lidar(1.0);
    let scan = &scans(&world, &poses, 360)[0];
    let mut a = LogOddsGrid::new(*world.geometry(), FilterSettings::default()).unwrap();
    let stats = RayMapper::new().integrate(&mut a, &model, scan);
    assert!(a.update_counts().iter().all(|&n| n <= 1));
    assert!(
        stats.cells_visited > stats.cells_updated,
        "cells near the sensor lie on many beams"
    );
    // Reverse the beams: the same map, bit for bit.
    let rev = Scan::new(
        scan.pose(),
        scan.ranges().iter().rev().copied().collect(),
        scan.bearings().iter().rev().copied().collect(),
    )
    .unwrap();
    let mut b = LogOddsGrid::new(*world.geometry(), FilterSettings::default()).unwrap();
    RayMapper::new().integrate(&mut b, &model, &rev);
    assert_eq!(a.log_odds(), b.log_odds());
}

#[test]
fn traversal_cost_follows_the_beams_not_the_map() {
    let model = lidar(1.0);
    let scan = Scan::uniform(
        Pose::new(5.0, 5.0, 0.0).unwrap(),
        vec![1.0; 90],
        0.0,
        2.0 * PI / 90.0,
    )
    .unwrap();
    let mut cost = Vec::new();
    for size in [100, 400] {
        let g = GridGeometry::new(size, size, 0.1, 0.0, 0.0).unwrap();
        let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        cost.push(
            RayMapper::new()
                .integrate(&mut m, &model, &scan)
                .cells_visited,
        );
    }
    assert_eq!(cost[0], cost[1], "16x the map, same work");
    let g = GridGeometry::new(100, 100, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    assert_eq!(
        sweep_scan(&mut m, &model, &scan).cells_visited,
        10_000,
        "the sweep visits every cell"
    );
}
