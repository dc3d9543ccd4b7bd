#![cfg(not(target_arch = "wasm32"))]
//! The real-log session (`apps::real_log`): no-return reach, walls that
//! last, the chapter's model kept as a choice.

use occgrid::apps::real_log::{LogMapBuild, LogMapSettings, RealLogSession};
use occgrid::io::carmen::LaserScans;
use std::path::PathBuf;

fn datasets() -> PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

fn dataset(name: &str) -> Vec<u8> {
    std::fs::read(datasets().join(name)).unwrap()
}

use occgrid::inverse::{HandCrafted, HandCraftedParams};
use occgrid::io::map_server::map_server_pair;
use occgrid::mapping::traversal::RayMapper;
use occgrid::mapping::walls::WallModel;

/// A log as text: one FLASER line per `(x, y, theta, ranges)`.
fn flaser_log(scans: &[(f64, f64, f64, Vec<f64>)]) -> Vec<u8> {
    let mut text = String::new();
    for (k, (x, y, th, rs)) in scans.iter().enumerate() {
        let r: Vec<String> = rs.iter().map(|r| format!("{r:.3}")).collect();
        text.push_str(&format!(
            "FLASER {} {} {x} {y} {th} {x} {y} {th} {k} host {k}\n",
            rs.len(),
            r.join(" ")
        ));
    }
    text.into_bytes()
}

fn build(bytes: &[u8], settings: LogMapSettings) -> LogMapBuild {
    let scans = LaserScans::read(bytes).unwrap();
    let mut b = LogMapBuild::new(scans, settings).unwrap();
    b.advance(usize::MAX);
    b
}

#[test]
fn the_chapter_settings_are_table_9_2_bit_for_bit() {
    let bytes = dataset("intel-corrected.log.gz");
    let b = build(&bytes, LogMapSettings::chapter());
    let mut grid = b.grid().to_dense().unwrap().clone();
    grid.reset();
    let model = HandCrafted::new(HandCraftedParams::laser(30.0)).unwrap();
    let mut mapper = RayMapper::new();
    let mut updates = 0;
    for k in 0..b.scans().len() {
        updates += mapper
            .integrate(&mut grid, &model, &b.scans().scan(k).unwrap())
            .cells_updated as u64;
    }
    assert_eq!(grid, b.grid().to_dense().unwrap());
    assert_eq!(updates, b.progress().cell_updates);
}

#[test]
fn a_no_return_clears_at_most_the_no_return_reach_and_returns_still_carve() {
    // 180 beams from the origin facing east: within 45 degrees of east no
    // return (81.83 m, as in the Intel log), elsewhere a wall 20 m away;
    // and scans from (30, 0) so that the map reaches that far.
    let mut scans = Vec::new();
    for k in 0..20 {
        let rs = (0..180)
            .map(|i| if (45..135).contains(&i) { 81.83 } else { 20.0 })
            .collect();
        scans.push((0.0, 0.0, k as f64 * 0.001, rs));
    }
    scans.push((30.0, 0.0, std::f64::consts::PI, vec![1.0; 180]));
    let bytes = flaser_log(&scans);
    let free_at = |b: &LogMapBuild, x: f64, y: f64| {
        let g = *b.grid().to_dense().unwrap().geometry();
        let (ix, iy) = g.world_to_cell(x, y).unwrap();
        b.grid().to_dense().unwrap().probability_at(g.index(ix, iy)) < 0.196
    };
    let defaults = LogMapSettings::default();
    assert_eq!(defaults.no_return_reach, 5.0);
    let b = build(&bytes, defaults);
    assert!(free_at(&b, 4.0, 0.0), "cleared within the reach");
    for d in [6.0, 12.0, 20.0, 28.0] {
        assert!(!free_at(&b, d, 0.0), "a no-return cleared {d} m out");
        let dense = b.grid().to_dense().unwrap();
        let g = *dense.geometry();
        let (ix, iy) = g.world_to_cell(d, 1.0).unwrap();
        assert!(dense.is_unknown(g.index(ix, iy)));
    }
    // Returns still carve out to their reading (bearing -70 degrees, 15 m).
    let a = -70f64.to_radians();
    assert!(free_at(&b, 15.0 * a.cos(), 15.0 * a.sin()));
    // The setting moves the reach; the chapter's no-returns reach z_max.
    let b = build(
        &bytes,
        LogMapSettings {
            no_return_reach: 15.0,
            ..defaults
        },
    );
    assert!(free_at(&b, 12.0, 0.0) && !free_at(&b, 20.0, 0.0));
    let b = build(&bytes, LogMapSettings::chapter());
    assert!(free_at(&b, 28.0, 0.0));
    // Checked by name.
    let mut s = RealLogSession::new(bytes);
    let e = s
        .configure(LogMapSettings {
            no_return_reach: -1.0,
            ..defaults
        })
        .unwrap_err()
        .to_string();
    assert!(e.contains("noReturnReach") && e.contains("-1"), "{e}");
}

/// check_map_quality.py's wall recall, computed the same way on the
/// exported PGM: of every fifth endpoint closer than 30 m, the share whose
/// cell or one of its 8 neighbours is black.
fn wall_recall(b: &LogMapBuild) -> f64 {
    let pair = map_server_pair(&b.grid().to_dense().unwrap(), "m.pgm");
    let pgm = occgrid::io::map_server::read_pgm(&pair.pgm).unwrap();
    let g = *b.grid().to_dense().unwrap().geometry();
    let (mut ends, mut hits) = (0, 0);
    for k in 0..b.scans().len() {
        let scan = b.scans().scan(k).unwrap();
        let pose = scan.pose();
        for (i, (&z, &bearing)) in scan.ranges().iter().zip(scan.bearings()).enumerate() {
            if i % 5 != 0 || z >= 30.0 || z <= 0.0 {
                continue;
            }
            let (x, y) = pose.point_at(z, bearing);
            let Some((ix, iy)) = g.world_to_cell(x, y) else {
                continue;
            };
            let (c, r) = (ix as i64, (g.height() - 1 - iy) as i64);
            ends += 1;
            let black = (-1..=1).any(|dc| {
                (-1..=1).any(|dr| {
                    let (cc, rr) = (
                        (c + dc).clamp(0, pgm.width as i64 - 1),
                        (r + dr).clamp(0, pgm.height as i64 - 1),
                    );
                    pgm.at(cc as usize, rr as usize) == Some(0)
                })
            });
            hits += black as usize;
        }
    }
    hits as f64 / ends as f64
}

#[test]
fn walls_last_on_a_real_log_under_the_defaults_and_wear_under_the_chapter_model() {
    let bytes = dataset("freiburg-101-corrected.log.gz");
    let defaults = wall_recall(&build(&bytes, LogMapSettings::default()));
    let chapter = wall_recall(&build(&bytes, LogMapSettings::chapter()));
    assert!(defaults >= 0.955, "recall {defaults}");
    assert!(chapter < 0.95, "the chapter's lesson: {chapter}");
}

#[test]
fn a_person_s_ghost_still_fades_under_the_defaults() {
    // A person 3 m ahead for 10 scans, then gone: the beams reach the wall
    // 6 m away through the place where the person stood.
    let mut scans = Vec::new();
    for k in 0..60 {
        let rs = (0..180)
            .map(|i| {
                if k < 10 && (88..92).contains(&i) {
                    3.0
                } else {
                    6.0
                }
            })
            .collect();
        scans.push((0.0, 0.0, 0.0, rs));
    }
    let bytes = flaser_log(&scans);
    let at = |b: &LogMapBuild| {
        let g = *b.grid().to_dense().unwrap().geometry();
        let (ix, iy) = g.world_to_cell(3.0, 0.0).unwrap();
        b.grid().to_dense().unwrap().probability_at(g.index(ix, iy))
    };
    let mut b = LogMapBuild::new(
        LaserScans::read(&bytes[..]).unwrap(),
        LogMapSettings::default(),
    )
    .unwrap();
    b.seek(10).unwrap();
    b.advance(usize::MAX);
    assert!(at(&b) > 0.65, "the person is on the map");
    b.seek(60).unwrap();
    b.advance(usize::MAX);
    assert!(at(&b) < 0.196, "the ghost faded: p = {}", at(&b));
    assert_eq!(LogMapSettings::default().walls, WallModel::Incidence);
}

/// The Infinite Corridor spans about 250 m x 245 m: at 5 cm its bounding box
/// is 24.6 million cells, past the dense grid's 16.8 million, and it was
/// refused. Its tiles hold the cells the beams reached, far fewer, and its
/// export covers the whole box.
#[test]
fn a_campus_sized_log_maps_at_5_cm_in_tiles_and_exports_its_whole_extent() {
    let mut s = RealLogSession::new(dataset("infinite-corridor-corrected.log.gz"));
    while !s.read(usize::MAX).unwrap().progress.finished {}
    let g = s.geometry().unwrap();
    assert_eq!(g.resolution, 0.05);
    assert!(
        g.width * g.height > occgrid::geometry::MAX_CELLS,
        "{} x {}",
        g.width,
        g.height
    );
    let p = loop {
        let p = s.build_chunk(500).unwrap();
        if p.finished {
            break p;
        }
    };
    assert_eq!(p.cells, g.width * g.height);
    assert!(
        p.cells_allocated * 2 < p.cells,
        "{} of {} cells allocated",
        p.cells_allocated,
        p.cells
    );
    let c = s.build().unwrap().counts();
    assert_eq!(c.cells, p.cells);
    assert!(c.occupied > 10_000 && c.free > 100_000, "{c:?}");
    let pair = s.export_map(Some("ic")).unwrap();
    let pgm = occgrid::io::map_server::read_pgm(&pair.pgm).unwrap();
    assert_eq!((pgm.width, pgm.height), (g.width, g.height));
    // The image counts what the counts say.
    let black = pgm.pixels.iter().filter(|&&v| v == 0).count();
    let white = pgm.pixels.iter().filter(|&&v| v == 254).count();
    assert_eq!((black, white), (c.occupied, c.free));
}

/// A budget too small for a log refuses it, saying how many tiles, cells
/// and bytes the whole log would need; the same log fits the default.
#[test]
fn a_tile_budget_refuses_only_what_does_not_fit_and_says_what_it_would_need() {
    let scans = LaserScans::read(&dataset("aces-corrected.log.gz")[..]).unwrap();
    let mut whole = LogMapBuild::new(scans.clone(), LogMapSettings::default()).unwrap();
    let p = whole.advance(usize::MAX);
    assert!(p.finished && whole.failure().is_none());
    let budget = p.cells_allocated / 2;
    let mut s = LogMapBuild::with_tile_budget(scans, LogMapSettings::default(), budget).unwrap();
    let p2 = s.advance(usize::MAX);
    assert!(!p2.finished && p2.cells_allocated <= budget);
    let e = s.failure().unwrap().to_string();
    let tiles: usize = e
        .split("reach ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // The estimate walks the grid of tiles: at least what the map allocated.
    assert!(tiles * 4096 >= p.cells_allocated, "{e}");
    assert!(tiles * 4096 <= p.cells_allocated * 3 / 2, "{e}");
    assert!(
        e.contains(&format!("budget of {budget} cells")) && e.contains("MiB"),
        "{e}"
    );
}
