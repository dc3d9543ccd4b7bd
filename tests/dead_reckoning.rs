#![cfg(not(target_arch = "wasm32"))]
//! Dead reckoning on a real log: the log's own motion increments
//! with Table 5.6's noise, integrated from the first pose, seeded; and the
//! work budget that bounds each call of a map build.

use occgrid::apps::real_log::{
    BuildProgress, LogMapSettings, LogPane, RealLogSession, Stage, MAX_SEED,
};
use occgrid::io::carmen::read_scans;
use occgrid::poses::PoseSourceKind;
use occgrid::sensors::odometry::OdometryParams;
use occgrid::sensors::ScanLog;
use std::path::PathBuf;

fn dataset(name: &str) -> Vec<u8> {
    let dir: PathBuf = std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    std::fs::read(dir.join(name)).unwrap()
}

fn scans(name: &str) -> ScanLog {
    read_scans(&dataset(name)[..]).unwrap()
}

fn dead_reckoning(seed: u64) -> LogMapSettings {
    LogMapSettings {
        poses: PoseSourceKind::DeadReckoning,
        seed,
        ..LogMapSettings::default()
    }
}

fn built(scans: ScanLog, settings: LogMapSettings, odometry: OdometryParams) -> LogPane {
    let mut b = LogPane::with_odometry(scans, settings, odometry).unwrap();
    b.advance(usize::MAX);
    b
}

/// The grid's state, bit for bit: its geometry and every cell's log odds.
fn bits(b: &LogPane) -> (String, Vec<u32>) {
    let g = b.grid().to_dense().unwrap();
    let cells = g.log_odds().iter().map(|l| l.to_bits()).collect();
    (format!("{:?}", g.geometry()), cells)
}

#[test]
fn one_seed_one_map_bit_for_bit_another_seed_another_map() {
    let log = scans("aces-corrected.log.gz");
    let a = built(log.clone(), dead_reckoning(7), OdometryParams::WHEELS);
    let again = built(log.clone(), dead_reckoning(7), OdometryParams::WHEELS);
    assert!(bits(&a) == bits(&again), "the same seed gives the same map");
    assert_eq!(a.poses(), again.poses());

    let other = built(log.clone(), dead_reckoning(8), OdometryParams::WHEELS);
    assert_ne!(a.poses(), other.poses());
    assert!(bits(&a) != bits(&other), "another seed, another map");

    let corrected = built(
        log.clone(),
        LogMapSettings::default(),
        OdometryParams::WHEELS,
    );
    assert_eq!(
        corrected.poses(),
        log.poses(),
        "the corrected poses are the log's"
    );
    // The dead-reckoned path starts where the log does and drifts away.
    let (dr, truth) = (a.poses(), log.poses());
    assert_eq!(dr[0], truth[0]);
    let last = truth.len() - 1;
    let drift = (dr[last].x - truth[last].x).hypot(dr[last].y - truth[last].y);
    assert!(drift > 0.5, "the end of the path drifted {drift} m");
    assert_ne!(corrected.counts(), a.counts());
}

#[test]
fn zero_noise_dead_reckoning_reproduces_the_corrected_map_exactly() {
    let log = scans("intel-corrected.log.gz");
    let corrected = built(
        log.clone(),
        LogMapSettings::default(),
        OdometryParams::WHEELS,
    );
    let exact = built(log, dead_reckoning(3), OdometryParams::EXACT);
    // Integrating the increments again lands within rounding of each pose…
    for (p, q) in exact.poses().iter().zip(corrected.poses()) {
        assert!(
            (p.x - q.x).abs() < 1e-9 && (p.y - q.y).abs() < 1e-9,
            "{p:?} vs {q:?}"
        );
    }
    // …and the map is the corrected one, cell for cell. (The cells
    // visited, and the work that counts them, may differ by a few where
    // two poses differ by rounding.)
    assert!(bits(&exact) == bits(&corrected));
    let updates_only = |p: BuildProgress| BuildProgress {
        cells_visited: 0,
        work: 0,
        ..p
    };
    assert_eq!(
        updates_only(exact.progress()),
        updates_only(corrected.progress())
    );
}

#[test]
fn dead_reckoning_is_one_more_pane_beside_the_corrected_map_and_a_change_of_source_rebuilds() {
    let bytes = dataset("aces-corrected.log.gz");
    let mut s = RealLogSession::new(bytes.clone());
    s.configure(dead_reckoning(5)).unwrap();
    while !s.read(usize::MAX).unwrap().progress.finished {}
    while !s.build_chunk(usize::MAX).unwrap().finished {}
    // One session, two panes: the chosen source first, the corrected beside.
    let sources: Vec<_> = s.panes().iter().map(|p| p.source()).collect();
    assert_eq!(
        sources,
        [PoseSourceKind::DeadReckoning, PoseSourceKind::Corrected]
    );
    let dr = bits(&s.panes()[0]);
    let alone = built(
        scans("aces-corrected.log.gz"),
        dead_reckoning(5),
        OdometryParams::WHEELS,
    );
    assert!(dr == bits(&alone), "the pane is the dead-reckoned map");
    let corrected = built(
        scans("aces-corrected.log.gz"),
        LogMapSettings::default(),
        OdometryParams::WHEELS,
    );
    assert!(
        bits(&s.panes()[1]) == bits(&corrected),
        "the pane beside is the corrected map"
    );
    let state = s.state();
    assert_eq!(state.panes.len(), 2);
    assert_eq!(state.panes[0].caption, "Dead reckoning (seed 5)");
    assert_eq!(state.beams, 2 * state.panes[1].progress.beams);

    // Back to the corrected poses: one pane, the same corrected map (once
    // the new panes are planned)…
    s.configure(LogMapSettings::default()).unwrap();
    while s.stage() == Stage::Planning {
        s.plan(usize::MAX).unwrap();
    }
    assert_eq!(s.panes().len(), 1);
    while !s.build_chunk(usize::MAX).unwrap().finished {}
    assert!(bits(&s.panes()[0]) == bits(&corrected));
    // …and on to the same seed again: the same dead-reckoned map.
    s.configure(dead_reckoning(5)).unwrap();
    while s.stage() == Stage::Planning {
        s.plan(usize::MAX).unwrap();
    }
    while !s.build_chunk(usize::MAX).unwrap().finished {}
    assert!(bits(&s.panes()[0]) == dr);
}

#[test]
fn a_seed_past_what_a_page_can_send_is_refused_by_name() {
    assert!(dead_reckoning(MAX_SEED).validate().is_ok());
    let e = dead_reckoning(MAX_SEED + 1)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("seed") && e.contains("9007199254740992"), "{e}");
}

#[test]
fn a_slice_stops_at_its_cell_budget_or_before_a_scan_that_would_pass_it() {
    let log = scans("fhw-corrected.log.gz");
    // What each scan costs, one scan per call.
    let mut one = LogPane::new(log.clone(), LogMapSettings::default()).unwrap();
    let mut per_scan = Vec::new();
    while !one.progress().finished {
        let before = one.progress().work;
        per_scan.push(one.advance(1).work - before);
    }
    let budget = 40_000;
    let mut b = LogPane::new(log, LogMapSettings::default()).unwrap();
    let mut calls = 0;
    while !b.progress().finished {
        let (k0, u0) = (b.progress().scans_done, b.progress().work);
        let p = b.advance_within(usize::MAX, budget);
        calls += 1;
        let did = &per_scan[k0..p.scans_done];
        assert_eq!(p.work - u0, did.iter().sum::<u64>());
        // Every scan but the last started below the budget…
        assert!(
            did[..did.len() - 1].iter().sum::<u64>() < budget,
            "call {calls} went on past its budget"
        );
        // …and the call went on while it was below, but for a last scan
        // that a scan as large as one before would have taken past it.
        let largest = per_scan[..p.scans_done].iter().max().copied().unwrap_or(0);
        assert!(
            p.finished || did.iter().sum::<u64>() + largest > budget,
            "call {calls} stopped early"
        );
    }
    assert!(bits(&b) == bits(&one), "slicing does not change the map");
    assert!(calls > 10, "{calls} calls");
}
