//! A log's read comes in calls of bounded work, the planning of its panes
//! included (docs/ARCHITECTURE.md, "Real logs"): the extent of the map is
//! grown as the scans are read, and the tiles its beams reach are counted
//! over the calls that follow the last line, so that no call of the page's
//! read walks every scan. The panes planned so are the ones a whole-log
//! plan makes, cell for cell.

mod log_support;
use log_support::flaser_log;
use occgrid::apps::real_log::{
    LogMapSettings, LogPane, RealLogSession, Stage, CONFIGURE_SCANS, START_UNITS_PER_PASS,
};
use occgrid::grid::storage::TILE_CELLS;
use occgrid::io::carmen::read_scans;
use occgrid::poses::{PoseSourceKind, COPIES_PER_UNIT};

/// A robot driving 60 m along the diagonal with a 180-beam laser of 3 m
/// readings (and a no-return in each scan): a map whose bounding box is
/// far larger than the band its beams sweep.
fn diagonal_log(scans: usize) -> Vec<u8> {
    let poses: Vec<_> = (0..scans)
        .map(|k| {
            let s = 60.0 * k as f64 / (scans - 1) as f64;
            let mut ranges = vec![3.0; 180];
            ranges[90] = 50.0;
            (s, s, 0.785, ranges)
        })
        .collect();
    flaser_log(&poses)
}

/// A tile budget of 200 tiles: less than the diagonal's bounding box
/// (about 441 tiles at 5 cm), more than its beams reach.
const BUDGET_CELLS: usize = 200 * TILE_CELLS;

/// The passes a source's start of `units` (poses dead-reckoned, or
/// `COPIES_PER_UNIT` copied) counts, made over at most `calls` calls (each
/// call's share rounded up): the least and the most.
fn start_passes(units: usize, calls: u64) -> std::ops::RangeInclusive<u64> {
    let least = units.div_ceil(START_UNITS_PER_PASS) as u64;
    least..=least + calls - 1
}

/// The work a read call reports, in scans (as the page receives it).
fn work(report: &impl serde::Serialize) -> u64 {
    serde_json::to_value(report).unwrap()["work"]
        .as_u64()
        .expect("a read call states its work")
}

/// Reads `session` to the end in calls of `n` scans; each call's work.
fn read_all(session: &mut RealLogSession, n: usize) -> Vec<u64> {
    let mut works = Vec::new();
    loop {
        let report = session.read(n).expect("the log reads");
        works.push(work(&report));
        if report.progress.finished {
            return works;
        }
        assert!(works.len() < 10_000, "the read ends");
    }
}

#[test]
fn every_read_call_stays_within_its_budget_and_the_tile_walk_comes_after_the_last_line() {
    let (scans, n) = (300, 7);
    let bytes = diagonal_log(scans);
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), BUDGET_CELLS);
    let works = read_all(&mut session, n);
    assert!(
        works.iter().all(|&w| w <= n as u64),
        "a call did more than {n} scans of work: {works:?}"
    );
    // Every scan read once (its share of the extent grown with it), its
    // pose copied for the pane's source, and walked once more on the grid
    // of tiles: the walk was done, and spread.
    let copied = scans.div_ceil(COPIES_PER_UNIT);
    let walked = works.iter().sum::<u64>() - 2 * scans as u64;
    assert!(start_passes(copied, 2).contains(&walked), "{works:?}");
    assert_eq!(session.stage(), Stage::Building);

    // The pane is the one a whole-log plan makes, and builds the same map.
    let log = read_scans(&bytes[..]).unwrap();
    let settings = LogMapSettings::default();
    let mut whole = LogPane::with_tile_budget(log, settings, BUDGET_CELLS).unwrap();
    assert_eq!(session.geometry(0).unwrap(), whole.geometry());
    while !session.build_chunk(50).unwrap().finished {}
    whole.advance(usize::MAX);
    let planned = session.pane(0).unwrap();
    assert_eq!(planned.progress(), whole.progress());
    assert_eq!(
        planned.grid().to_dense().unwrap(),
        whole.grid().to_dense().unwrap()
    );
}

#[test]
fn a_log_past_the_tile_budget_is_refused_by_the_last_planning_call_as_a_whole_plan_refuses_it() {
    let bytes = diagonal_log(200);
    let budget = 40 * TILE_CELLS;
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), budget);
    let n = 9;
    let e = loop {
        match session.read(n) {
            Ok(r) => {
                assert!(!r.progress.finished, "refused before the map is set up");
                assert!(work(&r) <= n as u64);
            }
            Err(e) => break e,
        }
    };
    let log = read_scans(&bytes[..]).unwrap();
    let whole = LogPane::with_tile_budget(log, LogMapSettings::default(), budget);
    assert_eq!(Some(e.to_string()), whole.err().map(|e| e.to_string()));
    assert!(e.to_string().contains("fits"), "{e}");
    assert_eq!(session.stage(), Stage::AwaitingSettings);
}

#[test]
fn settings_changed_while_reading_plan_the_panes_at_the_new_settings() {
    let bytes = diagonal_log(120);
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), BUDGET_CELLS);
    for _ in 0..3 {
        session.read(10).unwrap();
    }
    let settings = LogMapSettings {
        no_return_reach: 2.0,
        margin: 1.0,
        ..Default::default()
    };
    session.configure(settings).unwrap();
    let works = read_all(&mut session, 10);
    assert!(works.iter().all(|&w| w <= 10), "{works:?}");
    let log = read_scans(&bytes[..]).unwrap();
    let whole = LogPane::with_tile_budget(log, settings, BUDGET_CELLS).unwrap();
    assert_eq!(session.geometry(0).unwrap(), whole.geometry());
    // A no-return clearing 2 m instead of 5 m gives another extent.
    let log = read_scans(&bytes[..]).unwrap();
    let before = LogPane::with_tile_budget(log, LogMapSettings::default(), BUDGET_CELLS).unwrap();
    assert_ne!(before.geometry(), whole.geometry());
}

/// Plans `session`'s panes after new settings to the end in calls of `n`
/// scans; each call's work.
fn plan_all(session: &mut RealLogSession, n: usize) -> Vec<u64> {
    let mut works = Vec::new();
    while session.stage() == Stage::Planning {
        let report = session.plan(n).expect("the settings map the log");
        works.push(report.work as u64);
        assert!(works.len() < 10_000, "the planning ends");
    }
    works
}

#[test]
fn new_settings_plan_the_panes_in_bounded_calls_while_the_old_maps_stay() {
    let (scans, n) = (2 * CONFIGURE_SCANS, 25);
    let bytes = diagonal_log(scans);
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), BUDGET_CELLS);
    read_all(&mut session, n);
    while !session.build_chunk(100).unwrap().finished {}
    let (old_geometry, old_counts) = (
        session.geometry(0).unwrap(),
        session.pane(0).unwrap().counts(),
    );

    let settings = LogMapSettings {
        resolution: 0.04,
        ..Default::default()
    };
    session.configure(settings).unwrap();
    // The configure call walked its own share only: the rest is left to
    // the page's calls, and the maps on screen stay until then.
    assert_eq!(session.stage(), Stage::Planning);
    assert_eq!(session.geometry(0).unwrap(), old_geometry);
    assert_eq!(session.pane(0).unwrap().counts(), old_counts);
    let works = plan_all(&mut session, n);
    assert!(works.iter().all(|&w| w <= n as u64), "{works:?}");
    // The poses copied for the pane's source, the extent walk and the tile
    // walk, CONFIGURE_SCANS of them in configure itself.
    let total = works.iter().sum::<u64>() + CONFIGURE_SCANS as u64;
    let copied = scans.div_ceil(COPIES_PER_UNIT);
    assert!(
        start_passes(copied, 2).contains(&(total - 2 * scans as u64)),
        "{works:?}"
    );
    assert_eq!(session.stage(), Stage::Building);

    let log = read_scans(&bytes[..]).unwrap();
    let mut whole = LogPane::with_tile_budget(log, settings, BUDGET_CELLS).unwrap();
    assert_eq!(session.geometry(0).unwrap(), whole.geometry());
    while !session.build_chunk(100).unwrap().finished {}
    whole.advance(usize::MAX);
    let planned = session.pane(0).unwrap();
    assert_eq!(
        planned.progress().cell_updates,
        whole.progress().cell_updates
    );
    assert_eq!(planned.counts(), whole.counts());
    assert_eq!(
        planned.grid().to_dense().unwrap(),
        whole.grid().to_dense().unwrap()
    );
}

#[test]
fn settings_that_make_no_map_are_refused_by_a_planning_call_and_the_old_maps_stay() {
    let scans = 2 * CONFIGURE_SCANS;
    let mut session = RealLogSession::with_tile_budget(diagonal_log(scans), BUDGET_CELLS);
    read_all(&mut session, 50);
    while !session.build_chunk(100).unwrap().finished {}
    let before = session.state();
    session
        .configure(LogMapSettings {
            resolution: 0.02,
            ..Default::default()
        })
        .unwrap();
    let e = loop {
        match session.plan(40) {
            Ok(r) => assert!(!r.finished && r.work <= 40),
            Err(e) => break e.to_string(),
        }
    };
    assert!(e.contains("invalid resolution: 0.02 m"), "{e}");
    assert!(e.contains("m or coarser fits"), "{e}");
    // Nothing changed: the settings, the maps and their state.
    assert_eq!(session.state(), before);
}

#[test]
fn a_scan_matched_pane_is_planned_in_the_read_s_bounded_calls_too() {
    let (scans, n) = (150, 8);
    let bytes = diagonal_log(scans);
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), BUDGET_CELLS);
    let settings = LogMapSettings {
        poses: PoseSourceKind::ScanMatched,
        ..Default::default()
    };
    session.configure(settings).unwrap();
    let works = read_all(&mut session, n);
    assert!(works.iter().all(|&w| w <= n as u64), "{works:?}");
    // Read once; the scan-matched pane's odometry dead-reckoned and copied,
    // its tiles; the corrected pane's poses copied, its tiles (both boxes
    // grown as the lines were read); then the dead-reckoned pane's path,
    // box and tiles: every walk and every pose made counted in some call's
    // work.
    // The scan-matched pane's start: its odometry dead-reckoned, a pose a
    // unit, and copied once more for the matcher; the dead-reckoned
    // pane's, dead-reckoned; the corrected pane's, copied.
    let copied = scans.div_ceil(COPIES_PER_UNIT);
    let starts = start_passes(scans + copied, 2).start()
        + start_passes(scans, 2).start()
        + start_passes(copied, 2).start()
        ..=start_passes(scans + copied, 2).end()
            + start_passes(scans, 2).end()
            + start_passes(copied, 2).end();
    let walked = works.iter().sum::<u64>() - 5 * scans as u64;
    assert!(
        starts.contains(&walked),
        "{walked} of {starts:?}: {works:?}"
    );
    let log = read_scans(&bytes[..]).unwrap();
    let whole = LogPane::with_tile_budget(log, settings, BUDGET_CELLS).unwrap();
    assert_eq!(session.geometry(0).unwrap(), whole.geometry());
}

#[test]
fn the_search_for_a_resolution_that_fits_is_spread_over_the_read_s_calls() {
    let (scans, n) = (200, 9);
    let bytes = diagonal_log(scans);
    let budget = 40 * TILE_CELLS;
    let mut session = RealLogSession::with_tile_budget(bytes.clone(), budget);
    let mut works = Vec::new();
    let e = loop {
        match session.read(n) {
            Ok(r) => works.push(work(&r)),
            Err(e) => break e,
        }
    };
    assert!(works.iter().all(|&w| w <= n as u64), "{works:?}");
    // Read, its tiles counted, then at least one coarser candidate walked
    // (each a whole walk of the scans) before the refusal: the calls, the
    // refusing one included, hold three walks of the scans.
    let calls = works.len() as u64 + 1;
    assert!(calls * n as u64 >= 3 * scans as u64, "{works:?}");
    let log = read_scans(&bytes[..]).unwrap();
    let whole = LogPane::with_tile_budget(log, LogMapSettings::default(), budget);
    assert_eq!(Some(e.to_string()), whole.err().map(|e| e.to_string()));
    assert!(e.to_string().contains("m or coarser fits"), "{e}");
}
