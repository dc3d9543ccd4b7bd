//! A log's read comes in calls of bounded work, the planning of its panes
//! included (docs/ARCHITECTURE.md, "Real logs"): the extent of the map is
//! grown as the scans are read, and the tiles its beams reach are counted
//! over the calls that follow the last line, so that no call of the page's
//! read walks every scan. The panes planned so are the ones a whole-log
//! plan makes, cell for cell.

mod log_support;
use log_support::flaser_log;
use occgrid::apps::real_log::{LogMapSettings, LogPane, RealLogSession, Stage};
use occgrid::grid::storage::TILE_CELLS;
use occgrid::io::carmen::LaserScans;

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
    // Every scan read once (its share of the extent grown with it), and
    // walked once more on the grid of tiles: the walk was done, and spread.
    assert_eq!(works.iter().sum::<u64>(), 2 * scans as u64, "{works:?}");
    assert_eq!(session.stage(), Stage::Building);

    // The pane is the one a whole-log plan makes, and builds the same map.
    let log = LaserScans::read(&bytes[..]).unwrap();
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
    let log = LaserScans::read(&bytes[..]).unwrap();
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
    let log = LaserScans::read(&bytes[..]).unwrap();
    let whole = LogPane::with_tile_budget(log, settings, BUDGET_CELLS).unwrap();
    assert_eq!(session.geometry(0).unwrap(), whole.geometry());
    // A no-return clearing 2 m instead of 5 m gives another extent.
    let log = LaserScans::read(&bytes[..]).unwrap();
    let before = LogPane::with_tile_budget(log, LogMapSettings::default(), BUDGET_CELLS).unwrap();
    assert_ne!(before.geometry(), whole.geometry());
}
