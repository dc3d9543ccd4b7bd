//! A real log's counts (occupied, free, unknown, as the export holds them)
//! are kept per tile as the build writes the tiles: a finished map's
//! counts walk no cell, and they are the counts of every cell, cell for
//! cell, through builds, scrubs back and new settings.

use occgrid::apps::real_log::{LogGrid, LogMapSettings, RealLogSession, Stage};
use occgrid::io::map_server::ExportCounts;
use std::path::PathBuf;

fn dataset(name: &str) -> Vec<u8> {
    let dir: PathBuf = std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    std::fs::read(dir.join(name)).unwrap()
}

/// The counts of every cell of `grid`, walked now.
fn walked(grid: &dyn LogGrid) -> ExportCounts {
    grid.export_counts()
}

fn read_all(s: &mut RealLogSession) {
    while s.stage() == Stage::Reading && !s.read(500).unwrap().progress.finished {}
    while s.stage() == Stage::Planning {
        s.plan(500).unwrap();
    }
}

/// Builds `s` in slices of `budget` cell updates; after each, every
/// pane's counts are up to date (nothing left to recount) and equal a
/// walk of every cell.
fn build_checking(s: &mut RealLogSession, budget: u64) -> usize {
    let mut slices = 0;
    loop {
        let state = s.build_slice(budget).unwrap();
        slices += 1;
        for pane in s.panes() {
            assert_eq!(pane.counts_pending(), 0, "slice {slices}");
            if slices % 7 == 0 || state.finished {
                assert_eq!(pane.counts(), walked(pane.grid()), "slice {slices}");
            }
        }
        if state.finished {
            return slices;
        }
    }
}

#[test]
fn counts_kept_per_tile_are_every_cell_s_through_builds_scrubs_and_new_settings() {
    let mut s = RealLogSession::new(dataset("intel-corrected.log.gz"));
    s.configure(LogMapSettings {
        compare_model: Some(occgrid::apps::real_log::LogCellModel::LogOdds),
        ..Default::default()
    })
    .unwrap();
    read_all(&mut s);
    assert!(build_checking(&mut s, 200_000) > 10);
    let done = s.pane(0).unwrap().counts();
    assert!(done.occupied > 1000 && done.free > 100_000, "{done:?}");
    // Back to the middle of the log (the map is reset and rebuilt), then
    // on to the end again: the same counts.
    s.seek(455).unwrap();
    build_checking(&mut s, 300_000);
    s.seek(910).unwrap();
    build_checking(&mut s, 300_000);
    assert_eq!(s.pane(0).unwrap().counts(), done);
    // New settings: new maps, counted afresh.
    s.configure(LogMapSettings::chapter()).unwrap();
    read_all(&mut s);
    build_checking(&mut s, 500_000);
}

/// The campus's long calls, measured natively (run with `--ignored
/// --nocapture` in release): the planning after new settings, the slices'
/// recounts and the finished map's counts, against a walk of every cell.
#[test]
#[ignore]
fn campus_calls_measured() {
    use occgrid::apps::real_log::{LogPane, CONFIGURE_SCANS};
    use std::time::Instant;
    let bytes = dataset("freiburg-campus-corrected.log.gz");
    let mut s = RealLogSession::new(bytes.clone());
    read_all(&mut s);
    let n = s.pane(0).unwrap().scans().len();
    let (t, mut slices) = (Instant::now(), 1);
    while !s.build_slice(1_000_000).unwrap().finished {
        slices += 1;
    }
    let build = t.elapsed();
    let pane = s.pane(0).unwrap();
    let p = pane.progress();
    let t = Instant::now();
    let kept = pane.counts();
    let kept_ms = t.elapsed();
    let t = Instant::now();
    let all = walked(pane.grid());
    let walk_ms = t.elapsed();
    assert_eq!(kept, all);
    println!(
        "campus: {n} scans, {} updates, {} cells allocated; build in {slices} slices {build:?}; \
         counts kept {kept_ms:?}, walked {walk_ms:?}; {kept:?}",
        p.cell_updates, p.cells_allocated
    );
    // New settings: the whole plan in one call (as configure was) against
    // configure's own share and the longest plan call.
    let settings = LogMapSettings {
        no_return_reach: 8.0,
        ..Default::default()
    };
    let log = occgrid::io::carmen::read_scans(&bytes[..]).unwrap();
    let mut one_call = LogPane::new(log.clone(), LogMapSettings::default()).unwrap();
    let t = Instant::now();
    one_call.advance(usize::MAX);
    println!(
        "the same map in one call (one recount at its end): {:?}",
        t.elapsed()
    );
    assert_eq!(one_call.counts(), kept);
    let t = Instant::now();
    let whole = LogPane::new(log, settings).unwrap();
    let whole_ms = t.elapsed();
    let t = Instant::now();
    s.configure(settings).unwrap();
    let configure_ms = t.elapsed();
    let (mut calls, mut longest, mut work) = (0, std::time::Duration::ZERO, 0);
    while s.stage() == Stage::Planning {
        let t = Instant::now();
        work += s.plan(500).unwrap().work;
        longest = longest.max(t.elapsed());
        calls += 1;
    }
    assert_eq!(s.geometry(0).unwrap(), whole.geometry());
    println!(
        "new settings: whole plan {whole_ms:?}; configure {configure_ms:?} ({CONFIGURE_SCANS} scans), \
         then {calls} plan calls of 500 scans ({work} scans), longest {longest:?}"
    );
}
