#![cfg(not(target_arch = "wasm32"))]
//! The real-log session (`apps::real_log`): no-return reach, walls that
//! last, the chapter's model kept as a choice.

use occgrid::apps::real_log::{LogMapSettings, LogPane, RealLogSession, SettingLimits, Stage};
use occgrid::io::carmen::read_scans;
use occgrid::poses::PoseSourceKind;
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

mod log_support;
use log_support::flaser_log;

fn build(bytes: &[u8], settings: LogMapSettings) -> LogPane {
    let scans = read_scans(bytes).unwrap();
    let mut b = LogPane::new(scans, settings).unwrap();
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
    let free_at = |b: &LogPane, x: f64, y: f64| {
        let g = *b.grid().to_dense().unwrap().geometry();
        let (ix, iy) = g.world_to_cell(x, y).unwrap();
        b.grid().to_dense().unwrap().probability_at(g.index(ix, iy)) < 0.196
    };
    let defaults = LogMapSettings::default();
    assert_eq!(defaults.no_return_reach, 5.0);
    // By default a no-return clears only what returns on both its sides
    // saw free (`mapping::neighbour_support`): a run of 90 no-returns
    // clears nothing, within the reach or beyond it.
    let b = build(&bytes, defaults);
    assert!(!free_at(&b, 4.0, 0.0), "a wide run of no-returns cleared");
    for d in [6.0, 12.0, 20.0, 28.0] {
        assert!(!free_at(&b, d, 0.0), "a no-return cleared {d} m out");
    }
    // The reach alone bounds the clearing under Table 9.2's walls.
    let table_9_2 = LogMapSettings {
        walls: WallModel::Table92,
        ..defaults
    };
    let b = build(&bytes, table_9_2);
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
            ..table_9_2
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
fn wall_recall(b: &LogPane) -> f64 {
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
    let at = |b: &LogPane| {
        let g = *b.grid().to_dense().unwrap().geometry();
        let (ix, iy) = g.world_to_cell(3.0, 0.0).unwrap();
        b.grid().to_dense().unwrap().probability_at(g.index(ix, iy))
    };
    let mut b = LogPane::new(read_scans(&bytes[..]).unwrap(), LogMapSettings::default()).unwrap();
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
    let g = s.geometry(0).unwrap();
    assert_eq!(g.resolution, 0.05);
    assert!(
        g.width * g.height > occgrid::geometry::MAX_CELLS,
        "{} x {}",
        g.width,
        g.height
    );
    while !s.build_chunk(500).unwrap().finished {}
    let p = s.pane(0).unwrap().progress();
    assert_eq!(p.cells, g.width * g.height);
    assert!(
        p.cells_allocated * 2 < p.cells,
        "{} of {} cells allocated",
        p.cells_allocated,
        p.cells
    );
    let c = s.pane(0).unwrap().counts();
    assert_eq!(c.cells, p.cells);
    assert!(c.occupied > 10_000 && c.free > 100_000, "{c:?}");
    let pair = s.pane(0).unwrap().export_map(Some("ic"));
    let pgm = occgrid::io::map_server::read_pgm(&pair.pgm).unwrap();
    assert_eq!((pgm.width, pgm.height), (g.width, g.height));
    // The image counts what the counts say.
    let black = pgm.pixels.iter().filter(|&&v| v == 0).count();
    let white = pgm.pixels.iter().filter(|&&v| v == 254).count();
    assert_eq!((black, white), (c.occupied, c.free));
}

/// A budget too small for a log refuses its resolution before a cell is
/// allocated, saying how many tiles, cells and bytes the whole log would
/// need and the finest resolution that fits; that resolution then maps the
/// whole log within the budget.
#[test]
fn a_tile_budget_refuses_a_resolution_it_cannot_hold_before_building_and_names_one_that_fits() {
    let scans = read_scans(&dataset("aces-corrected.log.gz")[..]).unwrap();
    let mut whole = LogPane::new(scans.clone(), LogMapSettings::default()).unwrap();
    let p = whole.advance(usize::MAX);
    assert!(p.finished && whole.failure().is_none());
    let budget = p.cells_allocated / 2;
    let Err(e) = LogPane::with_tile_budget(scans.clone(), LogMapSettings::default(), budget) else {
        panic!("a budget of half the map was accepted");
    };
    let e = e.to_string();
    assert!(e.starts_with("invalid resolution: 0.05 m"), "{e}");
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
        e.contains(&format!("the {budget} cells")) && e.contains("MiB"),
        "{e}"
    );
    let fits: f64 = e
        .split("; ")
        .last()
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|_| panic!("no resolution named: {e}"));
    assert!(fits > 0.05 && fits <= 0.1, "{e}");
    let coarser = LogMapSettings {
        resolution: fits,
        ..LogMapSettings::default()
    };
    let mut pane = LogPane::with_tile_budget(scans, coarser, budget).unwrap();
    let done = pane.advance(usize::MAX);
    assert!(done.finished && pane.failure().is_none());
    assert!(done.cells_allocated <= budget);
}

/// A small log: `n` scans of 90 beams along a corridor, 4 m to either wall.
fn corridor(n: usize) -> Vec<u8> {
    let scans: Vec<_> = (0..n)
        .map(|k| {
            let rs = (0..90).map(|i| 2.0 + (i % 7) as f64 * 0.3).collect();
            (k as f64 * 0.1, 0.0, 0.0, rs)
        })
        .collect();
    flaser_log(&scans)
}

fn read_all(s: &mut RealLogSession) {
    loop {
        match s.read(usize::MAX) {
            Ok(r) if r.progress.finished => break,
            Ok(_) => {}
            Err(e) => panic!("{e}"),
        }
    }
}

/// A session of `corridor(n)`, read, at
/// dead-reckoned poses (seed 4) beside the corrected ones.
fn dead_reckoned_corridor(n: usize) -> RealLogSession {
    let mut s = RealLogSession::new(corridor(n));
    s.configure(LogMapSettings {
        poses: PoseSourceKind::DeadReckoning,
        seed: 4,
        ..LogMapSettings::default()
    })
    .unwrap();
    read_all(&mut s);
    s
}

/// A caller that slices with a budget of 0 cells still gets somewhere: each
/// call integrates at least one scan, so looping until finished ends.
#[test]
fn a_slice_of_no_cells_still_integrates_a_scan_and_a_loop_until_finished_ends() {
    let mut s = RealLogSession::new(corridor(12));
    read_all(&mut s);
    let mut calls = 0;
    let mut last = 0;
    loop {
        let state = s.build_slice(0).unwrap();
        calls += 1;
        assert!(
            state.scans_done > last || state.finished,
            "call {calls} made no progress"
        );
        last = state.scans_done;
        if state.finished {
            break;
        }
        assert!(calls <= 12, "the build never finished");
    }
    assert_eq!(calls, 12, "one scan per call");
    assert_eq!(s.stage(), Stage::Done);
}

/// The session's one state, from no log to a finished map, with the pane
/// beside added and dropped by the pose source, and a scrub back.
#[test]
fn the_session_state_runs_from_idle_through_reading_and_building_to_done() {
    let mut s = RealLogSession::idle();
    assert_eq!(s.stage(), Stage::Idle);
    assert!(s.read(1).is_err() && s.build_slice(1).is_err() && s.seek(0).is_err());
    s.open(corridor(40), "corridor.log");
    assert_eq!(s.state().log.as_deref(), Some("corridor.log"));
    assert_eq!(s.stage(), Stage::Reading);
    let mut progress = vec![s.state().progress];
    while !s.read(5).unwrap().progress.finished {
        assert_eq!(s.stage(), Stage::Reading);
        progress.push(s.state().progress);
    }
    assert_eq!(s.stage(), Stage::Building);
    assert_eq!(s.state().panes.len(), 1);
    assert_eq!(s.state().panes[0].poses, PoseSourceKind::Corrected);
    s.configure(LogMapSettings {
        poses: PoseSourceKind::DeadReckoning,
        seed: 9,
        ..LogMapSettings::default()
    })
    .unwrap();
    // A rebuild counts from 0; every slice moves both panes forward.
    loop {
        let state = s.build_slice(5_000).unwrap();
        progress.push(state.progress);
        let done: Vec<_> = state.panes.iter().map(|p| p.progress.scans_done).collect();
        assert_eq!(done.len(), 2);
        assert!(
            done[0].abs_diff(done[1]) <= 1,
            "the panes keep in step: {done:?}"
        );
        if state.finished {
            assert_eq!(state.state, Stage::Done);
            break;
        }
        assert_eq!(state.state, Stage::Building);
    }
    assert_eq!(*progress.last().unwrap(), 1.0);
    assert!(progress[..progress.len() - 1].iter().all(|&p| p < 1.0));
    // A scrub back: building again, then done at the scrub position.
    s.seek(10).unwrap();
    assert_eq!(s.stage(), Stage::Building);
    while !s.build_slice(u64::MAX).unwrap().finished {}
    let state = s.state();
    assert_eq!(
        (state.state, state.scans_done, state.scans_target),
        (Stage::Done, 10, 10)
    );
    assert!(state.panes.iter().all(|p| p.progress.scans_done == 10));
    // New settings head for the same scan count, and drop the pane beside.
    s.configure(LogMapSettings::default()).unwrap();
    assert_eq!(s.state().panes.len(), 1);
    assert_eq!(s.state().scans_target, 10);
    // A bad setting changes nothing, and says which field.
    let before = s.state();
    let e = s
        .configure(LogMapSettings {
            clamp: -1.0,
            ..LogMapSettings::default()
        })
        .unwrap_err();
    assert!(e.to_string().contains("clamp"), "{e}");
    assert_eq!(s.state(), before);
}

/// Settings too large for the log: the scans wait, the state says why,
/// and settings that fit map them.
#[test]
fn a_log_read_under_settings_too_large_awaits_settings_then_maps() {
    let mut s = RealLogSession::new(corridor(5));
    s.configure(LogMapSettings {
        resolution: 0.025,
        range_cap: 80.0,
        ..LogMapSettings::default()
    })
    .unwrap();
    let e = loop {
        match s.read(usize::MAX) {
            Ok(r) if r.progress.finished => panic!("mapped under a range cap of 3,200 cells"),
            Ok(_) => {}
            Err(e) => break e,
        }
    };
    assert!(e.to_string().contains("rangeCap"), "{e}");
    let state = s.state();
    assert_eq!(state.state, Stage::AwaitingSettings);
    assert!(state.error.unwrap().contains("rangeCap"));
    assert_eq!(state.read.unwrap().progress.scans, 5);
    assert!(s.build_slice(1).is_err());
    s.configure(LogMapSettings {
        resolution: 0.1,
        range_cap: 80.0,
        ..LogMapSettings::default()
    })
    .unwrap();
    assert_eq!(s.stage(), Stage::Building);
    while !s.build_slice(u64::MAX).unwrap().finished {}
    assert_eq!(s.state().scans_done, 5);
}

/// A refused read fails the session with the line named; the maps of the
/// log read before stay, and operating them is the news again.
#[test]
fn a_refused_read_fails_by_line_and_keeps_the_map_read_before() {
    let mut s = RealLogSession::new(corridor(6));
    read_all(&mut s);
    while !s.build_slice(u64::MAX).unwrap().finished {}
    let counts = s.pane(0).unwrap().counts();
    s.open(
        b"FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1 h 1\nShopping list\n".to_vec(),
        "list.log",
    );
    assert_eq!(s.stage(), Stage::Reading);
    let e = s.read(usize::MAX).unwrap_err().to_string();
    assert!(e.contains("line 2"), "{e}");
    let state = s.state();
    assert_eq!(state.state, Stage::Failed);
    assert!(state.error.unwrap().contains("line 2"));
    assert_eq!(
        s.read(1).unwrap_err().to_string(),
        e,
        "the same error again"
    );
    assert_eq!(
        s.pane(0).unwrap().counts(),
        counts,
        "the map read before stays"
    );
    s.seek(3).unwrap();
    assert_eq!(s.stage(), Stage::Building);
}

/// A log read under a resolution its tile budget cannot hold waits for
/// settings that fit, saying which resolution does; that one maps it.
#[test]
fn a_log_past_its_tile_budget_waits_for_the_resolution_that_fits() {
    let mut s = RealLogSession::with_tile_budget(dataset("aces-corrected.log.gz"), 40 * 4096);
    let e = loop {
        match s.read(usize::MAX) {
            Ok(r) => assert!(!r.progress.finished, "the budget held the whole log"),
            Err(e) => break e.to_string(),
        }
    };
    assert!(e.contains("invalid resolution: 0.05 m"), "{e}");
    assert!(e.contains("the 163840 cells"), "{e}");
    assert!(s.awaiting_settings(), "{:?}", s.stage());
    let fits: f64 = e
        .rsplit("; ")
        .next()
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no resolution named: {e}"));
    s.configure(LogMapSettings {
        resolution: fits,
        ..LogMapSettings::default()
    })
    .unwrap();
    while s.stage() == Stage::Planning {
        s.plan(200).unwrap();
    }
    let state = loop {
        let state = s.build_slice(100_000).unwrap();
        if state.finished {
            break state;
        }
    };
    assert_eq!(state.state, Stage::Done);
    assert_eq!(state.scans_done, 440);
}

/// One budget bounds a whole slice, both panes together: the call stops at
/// the scan that reaches it.
#[test]
fn one_cell_budget_bounds_a_slice_across_the_panes() {
    let mut s = RealLogSession::new(dataset("aces-corrected.log.gz"));
    s.configure(LogMapSettings {
        poses: PoseSourceKind::DeadReckoning,
        ..LogMapSettings::default()
    })
    .unwrap();
    read_all(&mut s);
    // The most one scan of the log costs (180 beams of at most 30 m at
    // 5 cm, each cell of a beam once, its band twice at most, visits at
    // half a unit, and as much again between the beams).
    let one_scan = 180 * 600 * 2 * 2;
    let budget = 50_000;
    let mut last = 0;
    let mut calls = 0;
    loop {
        let state = s.build_slice(budget).unwrap();
        calls += 1;
        let did = state.work - last;
        last = state.work;
        assert!(did < budget + one_scan, "call {calls} did {did}");
        assert!(
            state.finished || did >= budget,
            "call {calls} stopped early: {did}"
        );
        if state.finished {
            break;
        }
    }
    assert!(calls > 20, "{calls} calls");
}

/// A call the page's clock ends (`build_slice_until`, asked after each
/// step) stops after the step at which its time is due, whatever is left
/// of its budget of work; and however the build is cut, it ends with the
/// maps a call of the whole build gives, byte for byte.
#[test]
fn a_call_ends_after_the_step_its_time_is_due_and_the_maps_do_not_change() {
    let open = || dead_reckoned_corridor(40);
    let mut whole = open();
    while !whole.build_slice(u64::MAX).unwrap().finished {}
    let mut timed = open();
    let (mut calls, mut last) = (0, 0);
    loop {
        // The clock is due at the call's `k`th step: 1, 2 or 3 steps.
        let k = 1 + calls % 3;
        let mut asked = 0;
        let state = timed
            .build_slice_until(u64::MAX, || {
                asked += 1;
                asked >= k
            })
            .unwrap();
        calls += 1;
        let steps: usize = state.panes.iter().map(|p| p.progress.scans_done).sum();
        if state.finished {
            assert!(
                steps - last <= k,
                "call {calls}: {} steps, {k} due",
                steps - last
            );
            break;
        }
        assert_eq!(
            steps - last,
            k,
            "call {calls}: the steps before the clock was due"
        );
        assert_eq!(asked, k);
        last = steps;
    }
    assert!(calls > 20, "{calls} calls");
    for pane in 0..2 {
        let (a, b) = (
            whole.pane(pane).unwrap().export_map(Some("m")),
            timed.pane(pane).unwrap().export_map(Some("m")),
        );
        assert!(a.pgm == b.pgm && a.yaml == b.yaml, "pane {pane}");
    }
}

/// What a scan costs, in units of a cell update: its updates, and its
/// visits (along the beams and in the wedges between them) at
/// `VISITS_PER_UNIT` to the unit, over every pane.
fn cost(state: &occgrid::apps::real_log::SessionState) -> u64 {
    use occgrid::apps::real_log::VISITS_PER_UNIT;
    let p = state.panes.iter().map(|p| p.progress);
    p.map(|p| p.cell_updates + p.cells_visited / VISITS_PER_UNIT)
        .sum()
}

/// A build call never runs past its budget by more than one scan's
/// cost, counting the cells it visits and not only those it updates: the
/// space between beams is mostly visits (cells another beam already
/// updated), so on a log of long beams a budget of updates alone let a
/// call cost half again its budget.
#[test]
fn a_build_call_costs_its_budget_and_at_most_one_scan_more() {
    let open = || {
        let mut s = RealLogSession::new(dataset("freiburg-101-corrected.log.gz"));
        read_all(&mut s);
        s
    };
    let mut one_by_one = open();
    let (mut last, mut one_scan) = (0, 0);
    loop {
        let state = one_by_one.build_chunk(1).unwrap();
        one_scan = one_scan.max(cost(&state) - last);
        last = cost(&state);
        if state.finished {
            break;
        }
    }
    let budget = 40 * one_scan;
    let mut s = open();
    let (mut last, mut calls) = (0, 0);
    loop {
        let state = s.build_slice(budget).unwrap();
        calls += 1;
        let did = cost(&state) - last;
        last = cost(&state);
        assert!(
            did <= budget + one_scan,
            "call {calls} cost {did}, budget {budget}, one scan at most {one_scan}"
        );
        if state.finished {
            break;
        }
    }
    assert!(calls > 3, "{calls} calls");
}

/// The panel's numbers come from here: the range cap's limit at each
/// resolution, the view's scale in words, the cursor's cell and the
/// export's name and pose source.
#[test]
fn the_panel_s_limits_legend_cursor_and_export_come_from_the_pane() {
    let limits = SettingLimits::at(0.025).unwrap();
    assert_eq!(limits.range_cap_max, 51.125);
    assert_eq!(SettingLimits::at(0.05).unwrap().range_cap_max, 102.25);
    assert!(SettingLimits::at(0.0).is_err());
    let fits = LogMapSettings {
        resolution: 0.025,
        range_cap: limits.range_cap_max,
        ..LogMapSettings::default()
    };
    let scans = read_scans(&corridor(5)[..]).unwrap();
    assert!(LogPane::check(&scans, &fits).is_ok());
    let past = LogMapSettings {
        range_cap: limits.range_cap_max + 0.01,
        ..fits
    };
    let e = LogPane::check(&scans, &past).unwrap_err().to_string();
    assert!(e.contains("rangeCap") && e.contains("2045 cells"), "{e}");

    let mut s = dead_reckoned_corridor(5);
    while !s.build_slice(u64::MAX).unwrap().finished {}
    let pane = s.pane_mut(1).unwrap();
    pane.set_view_size(200, 100).unwrap();
    let v = *pane.view();
    let res = 0.05;
    let legend = pane.legend(2.0).unwrap();
    let per_cell = v.scale / 2.0;
    assert_eq!(legend.screen_pixels_per_cell, per_cell);
    let text = if per_cell >= 1.0 {
        format!("{per_cell:.1} screen pixels per cell")
    } else {
        format!("{:.1} cells per screen pixel", 1.0 / per_cell)
    };
    assert!(legend.text.starts_with(&text), "{}", legend.text);
    assert!(legend.text.ends_with(&format!(
        "{:.1} m \u{d7} {:.1} m shown",
        200.0 / v.scale * res,
        100.0 / v.scale * res
    )));
    assert!(pane.legend(0.0).is_err());
    // The cursor starts at the view's centre and steps 16 pixels (at least
    // a cell), ten steps with the long modifier, never off the map.
    assert_eq!(pane.cursor(), None);
    let step = ((16.0 / v.scale).round() as usize).max(1);
    let centre = (
        (v.u0 + 100.0 / v.scale).floor() as usize,
        (v.v0 + 50.0 / v.scale).floor() as usize,
    );
    let cell = pane.move_cursor(1, 0, false).unwrap().unwrap();
    let at = pane.cursor().unwrap();
    assert_eq!((at.col, at.row), (centre.0 + step, centre.1));
    assert_eq!(
        (cell.ix, cell.iy),
        (at.col, pane.geometry().height - 1 - at.row)
    );
    pane.move_cursor(-1, 0, true).unwrap();
    assert_eq!(
        pane.cursor().unwrap().col,
        (centre.0 + step).saturating_sub(10 * step)
    );
    for _ in 0..100 {
        pane.move_cursor(0, 1, true).unwrap();
    }
    assert_eq!(pane.cursor().unwrap().row, pane.geometry().height - 1);
    assert!(pane.move_cursor(2, 0, false).is_err());
    // Exports: the stem and the YAML say the pose source.
    let dr = &s.panes()[0];
    assert_eq!(
        dr.export_stem("intel-corrected.log.gz"),
        "intel-corrected-dead-reckoning-map"
    );
    assert_eq!(s.panes()[1].export_stem("Lab.CLF"), "Lab-map");
    let yaml = dr.export_map(Some("x")).yaml;
    assert!(yaml.starts_with("image: x.pgm\n"), "{yaml}");
    assert!(
        yaml.contains("\n# poses: dead-reckoning (seed 4)"),
        "{yaml}"
    );
    assert!(!s.panes()[1].export_map(Some("x")).yaml.contains("# poses"));
}
