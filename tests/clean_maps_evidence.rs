//! Free space that rests on beams that saw something
//! (`occgrid::mapping::neighbour_support`), on synthetic buildings of the
//! failure classes a real building shows: a glass wall that returns some
//! beams and passes others, a window onto open sky, and a doorway seen at
//! a grazing angle (sawtooth fans). Each scan is written into a map the
//! way a real log's map is, at the real-log defaults (hit counting: one
//! crossing beam makes a cell free), and the map read as its export draws
//! it.

use occgrid::apps::real_log::{LogCellModel, LogMapSettings};
use occgrid::geometry::{GridGeometry, Pose};
use occgrid::grid::{Dense, Grid, HitCount, HitCounting};
use occgrid::io::map_server::{trinary_gray, PGM_FREE, PGM_OCCUPIED};
use occgrid::mapping::insertion::{ScanInserter, ScanInsertion};
use occgrid::mapping::walls::MAX_MARGIN;
use occgrid::sensors::Scan;

type CountingGrid = Grid<HitCounting, Dense<HitCount>>;

/// A reading past the default range cap (30 m): a no-return.
const NO_RETURN: f64 = 81.9;

/// A 30 m x 30 m map of 5 cm cells centred on the origin.
fn map() -> CountingGrid {
    let g = GridGeometry::new(600, 600, 0.05, -15.0, -15.0).unwrap();
    Grid::with_model(g, LogCellModel::hit_counting(), g.len()).unwrap()
}

/// The robot at the origin, facing +x.
fn origin() -> Pose {
    Pose::new(0.0, 0.0, 0.0).unwrap()
}

/// The real-log defaults' recipe.
fn defaults() -> ScanInsertion {
    LogMapSettings::default().scan_insertion()
}

/// One scan of `n` beams from `from` to `to` radians at `pose`, its
/// readings `range(k, bearing)`, written into `grid` with `insertion`.
fn insert(
    grid: &mut CountingGrid,
    insertion: ScanInsertion,
    pose: Pose,
    (from, to, n): (f64, f64, usize),
    mut range: impl FnMut(usize, f64) -> f64,
) {
    let step = (to - from) / (n - 1) as f64;
    let ranges = (0..n).map(|k| range(k, from + k as f64 * step)).collect();
    let scan = Scan::uniform(pose, ranges, from, step).unwrap();
    ScanInserter::new(insertion)
        .unwrap()
        .insert(grid, &scan, f64::INFINITY);
}

/// The gray the export draws the cell holding world point `(x, y)` with.
fn gray_at(grid: &CountingGrid, x: f64, y: f64) -> u8 {
    let (u, v) = grid.geometry().world_to_grid(x, y);
    let cell = grid.cell_at(u as usize, v as usize).unwrap();
    trinary_gray(grid.model(), cell)
}

/// Free cells among `points`.
fn free_among(grid: &CountingGrid, points: impl Iterator<Item = (f64, f64)>) -> usize {
    points
        .filter(|&(x, y)| gray_at(grid, x, y) == PGM_FREE)
        .count()
}

/// Range from the origin along `bearing` to the line `x = d`.
fn to_line_x(d: f64, bearing: f64) -> f64 {
    d / bearing.cos()
}

/// Points along `bearing` from the origin, every 2 cm from `from` to `to`
/// metres.
fn along(bearing: f64, from: f64, to: f64) -> impl Iterator<Item = (f64, f64)> + Clone {
    let n = ((to - from) / 0.02) as usize;
    (0..=n).map(move |k| {
        let r = from + k as f64 * 0.02;
        (r * bearing.cos(), r * bearing.sin())
    })
}

/// A glass wall 3 m ahead returns two beams of three and passes the third
/// to a wall 8 m ahead: the passing beam's line beyond the glass is
/// contradicted by both its neighbours and is not free; the floor before
/// the glass is, and the glass and the far wall's readings are marked.
#[test]
fn a_beam_through_a_glass_wall_its_neighbours_see_draws_no_free_line() {
    let mut grid = map();
    let fov = (-0.6, 0.6, 241); // 0.3° spacing
    let passes = |k: usize| k % 3 == 1;
    let mut passing = Vec::new();
    insert(&mut grid, defaults(), origin(), fov, |k, b| {
        if passes(k) {
            passing.push(b);
            to_line_x(8.0, b)
        } else {
            to_line_x(3.0, b)
        }
    });
    assert!(!passing.is_empty());
    let beyond: usize = passing
        .iter()
        .map(|&b| free_among(&grid, along(b, to_line_x(3.3, b), to_line_x(7.6, b))))
        .sum();
    assert_eq!(beyond, 0, "free cells on lines through the glass");
    // The floor before the glass is free on every beam, the glass is a
    // wall, and what the passing beams hit is still marked.
    for &b in &passing {
        let before = along(b, 0.5, to_line_x(2.7, b));
        assert_eq!(free_among(&grid, before.clone()), before.count(), "{b}");
    }
    assert_eq!(gray_at(&grid, 3.0, 0.0), PGM_OCCUPIED);
    let b = passing[passing.len() / 2];
    let end = to_line_x(8.0, b);
    assert_eq!(gray_at(&grid, end * b.cos(), end * b.sin()), PGM_OCCUPIED);
}

/// Under Table 9.2's walls (the chapter's map, workload W1) every beam
/// clears its own line: the passing beams do draw free lines, so the test
/// above tells the two recipes apart.
#[test]
fn the_chapter_s_recipe_still_clears_every_beam_s_line() {
    let mut grid = map();
    let chapter = LogMapSettings::chapter().scan_insertion();
    let b = 0.0;
    insert(&mut grid, chapter, origin(), (-0.6, 0.6, 241), |k, b| {
        if k == 120 {
            to_line_x(8.0, b)
        } else {
            to_line_x(3.0, b)
        }
    });
    assert!(free_among(&grid, along(b, 3.3, 7.6)) > 0);
}

/// A window 2 m wide in a wall 3 m ahead looks onto open sky: its beams
/// are no-returns. Nothing outside the wall is free (no beam saw
/// anything there), and a single no-return in the wall (a dark patch)
/// clears only the floor its neighbours saw free.
#[test]
fn a_window_onto_open_sky_clears_nothing_outside() {
    let mut grid = map();
    let window = |b: f64| (3.0 * b.tan()).abs() < 1.0;
    let dark_patch = |k: usize| k == 30;
    insert(&mut grid, defaults(), origin(), (-0.9, 0.9, 361), |k, b| {
        if window(b) || dark_patch(k) {
            NO_RETURN
        } else {
            to_line_x(3.0, b)
        }
    });
    // Outside the wall, through and beside the window: no free cell.
    let outside = (0..200)
        .flat_map(|i| (0..200).map(move |j| (3.2 + i as f64 * 0.025, -2.5 + j as f64 * 0.025)));
    assert_eq!(free_among(&grid, outside), 0);
    // The dark patch's beam: free in front of the wall, as its
    // neighbours saw.
    let b = -0.9 + 30.0 * (1.8 / 360.0);
    let before = along(b, 0.5, to_line_x(2.7, b));
    assert_eq!(free_among(&grid, before.clone()), before.count());
}

/// A doorway in a corridor's side wall, seen at a grazing angle: the
/// beams across it alternately pass into the room behind and
/// meet the door's frame. Each passing beam is flanked by two readings of
/// the frame, and the sawtooth of single free lines into the room is not
/// drawn; the corridor before the frame is free.
#[test]
fn a_doorway_seen_at_a_grazing_angle_draws_no_sawtooth() {
    let mut grid = map();
    let fov = (0.1, 0.5, 161); // 0.14° spacing
    let frame = |b: f64| 1.0 / b.sin(); // the wall's line y = 1
    let room = |b: f64| 2.5 / b.sin(); // the room's back wall, y = 2.5
    let doorway = |b: f64| (1.0 / b.tan() - 4.5).abs() < 0.5;
    let mut passing = Vec::new();
    insert(&mut grid, defaults(), origin(), fov, |k, b| {
        if doorway(b) && k % 2 == 0 {
            passing.push(b);
            room(b)
        } else {
            frame(b)
        }
    });
    assert!(passing.len() >= 3, "{passing:?}");
    let into_room: usize = passing
        .iter()
        .map(|&b| free_among(&grid, along(b, frame(b) + 0.3, room(b) - 0.3)))
        .sum();
    assert_eq!(into_room, 0, "free cells on the sawtooth's lines");
    let b = passing[0];
    // (Short of the frame by the most free evidence a reading withholds
    // before a surface it cannot tell the incidence of, `walls::MAX_MARGIN`.)
    let corridor = along(b, 0.5, frame(b) - MAX_MARGIN - 0.1);
    assert_eq!(free_among(&grid, corridor.clone()), corridor.count());
}

/// Unknown cells whose four neighbours are all free, among the cells of
/// the map inside `x0..x1` by `y0..y1` metres: floor a reader sees as
/// observed but left gray.
fn pinholes(grid: &CountingGrid, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> usize {
    let g = *grid.geometry();
    let (u0, v0) = g.world_to_grid(x0, y0);
    let (u1, v1) = g.world_to_grid(x1, y1);
    let gray = |u: usize, v: usize| trinary_gray(grid.model(), grid.cell_at(u, v).unwrap());
    let (u0, v0, u1, v1) = (u0 as usize, v0 as usize, u1 as usize, v1 as usize);
    (v0.max(1)..v1)
        .flat_map(|v| (u0.max(1)..u1).map(move |u| (u, v)))
        .filter(|&(u, v)| {
            gray(u, v) != PGM_FREE
                && gray(u, v) != PGM_OCCUPIED
                && [(u - 1, v), (u + 1, v), (u, v - 1), (u, v + 1)]
                    .iter()
                    .all(|&(a, b)| gray(a, b) == PGM_FREE)
        })
        .count()
}

/// A courtyard seen from a doorway: open sky but for a far façade 12 m
/// ahead that returns one beam in twelve (0.5° spacing, so 6° between
/// returns: the no-returns between them clear nothing). Each lone return
/// is as wide as the beam spacing (Table 9.2's `β`): its whole footprint
/// out to its reading is free, not a line one cell wide. The robot
/// stands in the doorway for five scans a few centimetres apart, and the
/// lines of its scans, side by side, leave no pinholes between them.
#[test]
fn a_lone_return_among_no_returns_frees_its_footprint_not_a_line() {
    let mut grid = map();
    let spacing = 0.5_f64.to_radians();
    let n = 121;
    let fov = (-30.0 * spacing * 2.0, 30.0 * spacing * 2.0, n);
    let facade = |b: f64| to_line_x(12.0, b);
    let poses = [
        (0.0, 0.0, 0.0),
        (0.03, 0.02, 0.004),
        (-0.02, 0.04, -0.003),
        (0.01, -0.03, 0.006),
        (0.04, -0.01, -0.005),
    ];
    let mut lone = Vec::new();
    for (s, &(x, y, t)) in poses.iter().enumerate() {
        let pose = Pose::new(x, y, t).unwrap();
        insert(&mut grid, defaults(), pose, fov, |k, b| {
            if k % 12 == 6 {
                if s == 0 {
                    lone.push(b);
                }
                to_line_x(12.0 - x, b + t)
            } else {
                NO_RETURN
            }
        });
    }
    assert!(lone.len() >= 8, "{lone:?}");
    // The first scan's lone returns: every point within a quarter of the
    // spacing of the axis, from 3 m out to 0.5 m short of the façade.
    let mut footprint = Vec::new();
    for &b in &lone {
        for side in [-0.25, 0.25] {
            footprint.extend(along(b + side * spacing, 3.0, facade(b) - 0.5));
        }
    }
    let free = free_among(&grid, footprint.iter().copied());
    assert_eq!(free, footprint.len(), "footprint points left unknown");
    let holes = pinholes(&grid, (2.0, 11.5), (-6.0, 6.0));
    assert_eq!(holes, 0, "pinholes between the lone returns' lines");
}
