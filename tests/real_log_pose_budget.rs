//! What a log may cost in each pose source (docs/ARCHITECTURE.md, "Real
//! logs"): a log of a million scans of one beam each was scan-matched for
//! minutes. Finding a pane's poses is bounded before the first scan is
//! located ([`MAX_POSE_WORK`], refused by name with the figure and the
//! budget), and a build call's budget counts every candidate a match
//! scores, so that a call of one-beam scans is as long as any other.

use occgrid::apps::real_log::{
    LogMapSettings, LogPane, RealLogSession, Stage, MAX_POSE_WORK, START_UNITS_PER_PASS,
};
use occgrid::poses::{
    local_match_work, match_settings, match_work, PoseSourceKind, SourceSettings, COPIES_PER_UNIT,
};
use occgrid::sensors::odometry::OdometryParams;
use std::time::Instant;

/// The hostile log's length: a million scans.
const MILLION: usize = 1_000_000;

/// A log of `scans` FLASER lines of `beams` readings of `range` metres: a
/// robot creeping round a circle of 2 m, a millimetre and a milliradian a
/// scan.
fn creeping_log(scans: usize, beams: usize, range: f64) -> Vec<u8> {
    let ranges = vec![format!("{range}"); beams].join(" ");
    let mut text = String::with_capacity(scans * (48 + ranges.len()));
    for k in 0..scans {
        let a = k as f64 * 1e-3;
        let (x, y) = (2.0 * a.cos(), 2.0 * a.sin());
        let th = a + std::f64::consts::FRAC_PI_2;
        text.push_str(&format!(
            "FLASER {beams} {ranges} {x:.4} {y:.4} {th:.4} {x:.4} {y:.4} {th:.4} {k} h {k}\n"
        ));
    }
    text.into_bytes()
}

/// `scans` scans of one beam each, 1.5 m ahead.
fn one_beam_log(scans: usize) -> Vec<u8> {
    creeping_log(scans, 1, 1.5)
}

/// Reads `session` to its end: the error of its last call, if any.
fn read_all(session: &mut RealLogSession) -> Result<(), String> {
    loop {
        match session.read(1 << 16) {
            Ok(r) if r.progress.finished => return Ok(()),
            Ok(_) => {}
            Err(e) => return Err(e.to_string()),
        }
    }
}

fn settings(poses: PoseSourceKind) -> LogMapSettings {
    LogMapSettings {
        poses,
        ..Default::default()
    }
}

/// The figure a pose refusal names: what the log's poses could cost.
fn named_bound(message: &str) -> u64 {
    message
        .split("could cost up to ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("the figure is named: {message}"))
}

/// A 2,000-scan share of the million-scan log, against the same share of
/// the budget: scan matching it is refused when its panes are planned,
/// naming the source, what it could cost and the budget; the poses known in
/// advance (the log's own, dead reckoning) cost nothing to find and map it.
#[test]
fn a_log_whose_matching_passes_the_budget_is_refused_by_its_figure_and_the_budget() {
    let scans = 2000;
    let budget = MAX_POSE_WORK / (MILLION / scans) as u64;
    let bytes = one_beam_log(scans);
    let mut s = RealLogSession::with_pose_work_budget(bytes.clone(), budget);
    s.configure(settings(PoseSourceKind::ScanMatched)).unwrap();
    let message = read_all(&mut s).expect_err("scan matching is refused");
    assert!(
        message.contains("poses") && message.contains("\"scan-matched\" over 2000 scans"),
        "{message}"
    );
    assert!(
        message.contains(&format!("at most {budget} units")),
        "{message}"
    );
    let bound = named_bound(&message);
    assert!(bound > budget, "{message}");
    // The whole million-scan log passes the whole budget by as much.
    assert!(bound * (MILLION / scans) as u64 > MAX_POSE_WORK);
    assert_eq!(s.stage(), Stage::AwaitingSettings);
    assert_eq!(s.state().error.as_deref(), Some(message.as_str()));

    // The scans wait for settings that fit: poses known in advance.
    for poses in [PoseSourceKind::Corrected, PoseSourceKind::DeadReckoning] {
        s.configure(settings(poses)).unwrap();
        while s.stage() == Stage::Planning {
            s.plan(1 << 16).unwrap();
        }
        while !s.build_slice(1 << 22).unwrap().finished {}
        assert_eq!(s.state().scans_done, scans, "{poses:?}");
    }

    // Under the whole budget the same scans are matched.
    let mut s = RealLogSession::new(bytes);
    s.configure(settings(PoseSourceKind::ScanMatched)).unwrap();
    read_all(&mut s).unwrap();
    while !s.build_slice(1 << 22).unwrap().finished {}
    assert_eq!(s.state().scans_done, scans);
}

/// SLAM over the same 2,000-scan share against the same share of the
/// budget: its bound (the scan-matched source's matching, the insertion
/// into submaps, and an allowance for the loop search and the
/// optimisation) is refused when the panes are planned, before its path
/// is made, by name, with the figure and the budget; a log of a million
/// one-beam scans at SLAM was otherwise mapped for as long as it took.
#[test]
fn a_slam_log_whose_work_passes_the_budget_is_refused_by_its_figure_and_the_budget() {
    let scans = 2000;
    let budget = MAX_POSE_WORK / (MILLION / scans) as u64;
    let mut s = RealLogSession::with_pose_work_budget(one_beam_log(scans), budget);
    s.configure(settings(PoseSourceKind::Slam)).unwrap();
    let (_, total, error) = read_in_calls(&mut s, 1 << 16);
    let message = error.expect("SLAM is refused");
    assert!(
        message.contains("invalid poses: \"slam\" over 2000 scans"),
        "{message}"
    );
    assert!(
        message.contains(&format!("at most {budget} units")),
        "{message}"
    );
    let bound = named_bound(&message);
    assert!(bound > budget, "{message}");
    // The million-scan log passes the whole budget by as much.
    assert!(bound * (MILLION / scans) as u64 > MAX_POSE_WORK);
    // What fits is said: the scans that would, and poses known in advance.
    let fit = budget as u128 * scans as u128 / bound as u128;
    assert!(
        message.contains(&format!("or cut it to at most {fit} scans")),
        "{message}"
    );
    assert!(message.contains("the log's own poses"), "{message}");
    // Refused before its path was made: the lines read, little more.
    assert!(
        total < scans + scans / 10,
        "{total} units to read {scans} scans and refuse them"
    );
    assert_eq!(s.stage(), Stage::AwaitingSettings);
}

/// The sizes of the shared logs (scans, beams a scan: the Intel lab and
/// its bags, ACES and its bag, FHW, Freiburg 101, the campus, the Infinite
/// Corridor) at the real-log defaults: SLAM's bound and the scan matcher's
/// fit the budget, SLAM's with room for its loop search (the campus, the
/// largest, is bounded at under 1.9e10).
#[test]
fn the_shared_logs_sizes_fit_the_pose_budget_in_every_source() {
    let defaults = LogMapSettings::default();
    let source_settings = SourceSettings {
        seed: 1,
        noise: OdometryParams::WHEELS,
        matching: match_settings(defaults.range_cap),
        resolution: defaults.resolution,
    };
    let mut largest = (0, 0);
    for (scans, beams) in [
        (910, 180),
        (440, 180),
        (488, 180),
        (292, 360),
        (2008, 360),
        (1941, 180),
    ] {
        let log = occgrid::io::carmen::read_scans(&creeping_log(scans, beams, 5.0)[..]).unwrap();
        assert_eq!((log.len(), log.beams()), (scans, scans * beams));
        let bound = |kind: PoseSourceKind| {
            kind.starting(&log, &source_settings)
                .unwrap()
                .work_bound(&log)
                .unwrap()
        };
        let (slam, matched) = (
            bound(PoseSourceKind::Slam),
            bound(PoseSourceKind::ScanMatched),
        );
        assert!(
            slam <= MAX_POSE_WORK && matched <= MAX_POSE_WORK,
            "{scans} scans of {beams} beams: SLAM {slam}, scan matching {matched}"
        );
        // SLAM matches as the scan matcher does, and searches loops besides.
        assert!(slam > 2 * matched, "{slam} against {matched}");
        largest = largest.max((slam, scans));
    }
    assert_eq!(largest.1, 2008, "the campus is the largest");
}

/// Reads `session` to its end in calls of `max_scans`: the most work a
/// call reported, the work of all of them (a refused call's as the read's
/// report keeps it), and the error of the last.
fn read_in_calls(session: &mut RealLogSession, max_scans: usize) -> (usize, usize, Option<String>) {
    let (mut longest, mut total) = (0, 0);
    loop {
        match session.read(max_scans) {
            Ok(r) => {
                longest = longest.max(r.work);
                total += r.work;
                if r.progress.finished {
                    return (longest, total, None);
                }
            }
            // A refusal's call keeps its work in the read's report.
            Err(e) => {
                let last = session.state().read.map_or(0, |r| r.work);
                return (longest.max(last), total + last, Some(e.to_string()));
            }
        }
    }
}

/// When the last line is read, every pane's pose source is started: the
/// dead-reckoned paths integrated, the log's poses copied. That is work
/// of the read's calls too, within each call's budget, whatever the log's
/// length: the call that read the last line made every pose of every
/// pane at once (at a million one-beam scans, 194 ms natively, 548 ms in
/// the page). Every pose made is counted: the work reported covers the
/// lines read, the two dead-reckoned paths (the scan-matched pane's and
/// the dead-reckoned one's) and the dead-reckoned pane's walk of its
/// extent.
///
/// SLAM's pane makes two copies of its path too (the odometry its graph
/// starts from, the poses it hands out): in the steps of the read, counted,
/// never in the call that takes the started source (which copied both at
/// once). (Its bound is past the budget at this length: the test's budget
/// is unbounded.)
#[test]
fn no_read_call_starts_every_pose_of_a_long_log() {
    let scans = 10_000;
    let bytes = one_beam_log(scans);
    for poses in [PoseSourceKind::ScanMatched, PoseSourceKind::Slam] {
        for max_scans in [1, 97, 4096] {
            let mut s = RealLogSession::with_pose_work_budget(bytes.clone(), u64::MAX);
            s.configure(settings(poses)).unwrap();
            let (longest, total, error) = read_in_calls(&mut s, max_scans);
            assert_eq!(error, None);
            assert!(
                longest <= max_scans,
                "{poses:?}: a call of {max_scans} scans worked {longest}"
            );
            // A scan read and a scan walked are a unit each, the poses of
            // a source's start START_UNITS_PER_PASS to a unit.
            let paths = 2 * (scans / START_UNITS_PER_PASS);
            assert!(
                total >= 2 * scans + paths,
                "{total} units reported for {scans} scans read, two paths dead-reckoned and one walked"
            );
            if poses == PoseSourceKind::Slam {
                // The corrected pane's copy and SLAM's second copy.
                let copies = 2 * (scans / COPIES_PER_UNIT) / START_UNITS_PER_PASS;
                assert!(
                    total >= 2 * scans + paths + copies,
                    "{total} units reported: SLAM's copy of its path is not counted"
                );
            }
            assert_eq!(s.panes().len(), 3);
            assert_eq!(s.stage(), Stage::Building);
        }
    }
    // New settings plan in bounded calls too.
    let mut s = RealLogSession::new(bytes);
    read_in_calls(&mut s, 4096);
    s.configure(settings(PoseSourceKind::DeadReckoning))
        .unwrap();
    let mut calls = 0;
    while s.stage() == Stage::Planning {
        let r = s.plan(300).unwrap();
        assert!(r.work <= 300, "a plan call of 300 scans worked {}", r.work);
        calls += 1;
    }
    assert!(calls * 300 >= 2 * scans, "{calls} calls");
    assert_eq!(s.panes().len(), 2);
}

/// A pane refused for what finding its poses could cost is refused before
/// its path is made, and the panes after it are not planned: the read of
/// a refused log costs its lines and little more (the dead-reckoned pane
/// beside the refused scan-matched one walked every scan again).
#[test]
fn a_refused_pane_stops_the_plan() {
    let scans = 2000;
    let budget = MAX_POSE_WORK / (MILLION / scans) as u64;
    let mut s = RealLogSession::with_pose_work_budget(one_beam_log(scans), budget);
    s.configure(settings(PoseSourceKind::ScanMatched)).unwrap();
    let (_, total, error) = read_in_calls(&mut s, 1 << 16);
    let error = error.expect("scan matching is refused");
    assert!(
        error.contains("\"scan-matched\" over 2000 scans"),
        "{error}"
    );
    assert!(
        total < scans + scans / 10,
        "{total} units to read {scans} scans and refuse them"
    );
    assert_eq!(s.stage(), Stage::AwaitingSettings);
}

/// Seeking back restarts a SLAM pane from its first scan: its odometry
/// copied again for a fresh graph, and the poses it hands out set back.
/// Over a long log that is a long copy: it is done in the build's calls
/// that follow, a bounded step each and counted in their work, not in the
/// seek (which copied every pose at once, uncounted); and the poses found
/// again are the same, bit for bit.
#[test]
fn seeking_back_restarts_slam_in_bounded_calls() {
    let scans = 20_000;
    let built = 100;
    let mut s = RealLogSession::with_pose_work_budget(one_beam_log(scans), u64::MAX);
    s.configure(settings(PoseSourceKind::Slam)).unwrap();
    read_all(&mut s).unwrap();
    s.seek(built).unwrap();
    while !s.build_slice(1 << 22).unwrap().finished {}
    let first: Vec<_> = s.panes()[0].poses()[..built].to_vec();
    assert_eq!(s.panes()[0].progress().scans_done, built);

    s.seek(0).unwrap();
    let slam = |s: &RealLogSession| s.panes()[0].progress();
    assert!(!slam(&s).finished, "the restart is work left");
    let (mut calls, mut longest, mut before) = (0, 0, slam(&s).work);
    while !s.build_slice(1).unwrap().finished {
        let p = slam(&s);
        longest = longest.max(p.work - before);
        before = p.work;
        calls += 1;
    }
    let copies = (scans / COPIES_PER_UNIT) as u64;
    assert!(
        slam(&s).work >= copies,
        "{} units counted for copying {scans} poses",
        slam(&s).work
    );
    assert!(calls >= 4, "{calls} calls");
    assert!(longest < copies / 2, "a call worked {longest} units");

    s.seek(built).unwrap();
    while !s.build_slice(1 << 22).unwrap().finished {}
    assert_eq!(s.panes()[0].poses()[..built], first[..]);
}

/// A candidate of the search costs a unit at least, whatever its points:
/// a one-beam scan's match was counted at an eighth of a unit per
/// candidate, and a build call of such scans ran twice as long per unit
/// as the office logs' (see `time_per_unit_measured`).
#[test]
fn a_one_beam_match_counts_each_candidate_it_scores() {
    use occgrid::poses::{match_settings, PoseSource, ScanMatching};
    use occgrid::sensors::odometry::OdometryParams;
    let log = occgrid::io::carmen::read_scans(&one_beam_log(300)[..]).unwrap();
    // The map of the log at its own poses, to match each scan against.
    let mut map = LogPane::new(log.clone(), settings(PoseSourceKind::Corrected)).unwrap();
    map.advance(usize::MAX);
    let mut source = ScanMatching::new(
        log.poses().to_vec(),
        OdometryParams::WHEELS,
        match_settings(30.0),
        0.05,
    )
    .unwrap();
    let mut counted = 0;
    for k in 0..log.len() {
        let scan = log.scan(k).unwrap();
        source
            .locate(k, &scan, f64::INFINITY, map.grid().as_match_map())
            .unwrap();
        let (_, report) = source.last().unwrap();
        if report.candidates > 0 {
            assert_eq!(report.points, 1);
            assert!(
                match_work(report) >= report.candidates as u64,
                "{} candidates counted as {} units",
                report.candidates,
                match_work(report)
            );
            counted += 1;
        }
    }
    assert!(counted > 200, "most scans are searched: {counted}");
}

/// This thread's CPU time, ns (the machine may be shared: wall time is not
/// the code's).
fn cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

/// The million-scan log read and built natively in calls of the page's
/// first budget (run with `SCANS=1000000 cargo test --release --test
/// real_log_pose_budget -- --ignored --nocapture`; `WRITE=PATH` keeps the
/// log; `POSES=scan-matched,corrected` measures those sources only;
/// `POSE_BUDGET` the pose budget, unbounded at 18446744073709551615): the
/// longest read and build calls, in CPU time.
#[test]
#[ignore = "a measurement"]
fn one_beam_log_calls_measured() {
    let env = |k: &str, d: u64| {
        std::env::var(k)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let n = env("SCANS", 100_000) as usize;
    let budget = env("BUDGET", 250_000);
    // (`POSE_BUDGET` another pose budget: 18446744073709551615 for none.)
    let pose_budget = env("POSE_BUDGET", MAX_POSE_WORK);
    let bytes = one_beam_log(n);
    if let Ok(path) = std::env::var("WRITE") {
        std::fs::write(path, &bytes).unwrap();
    }
    let chosen = std::env::var("POSES").unwrap_or_default();
    for poses in PoseSourceKind::ALL {
        if !chosen.is_empty() && !chosen.split(',').any(|n| n == poses.name()) {
            continue;
        }
        let mut s = RealLogSession::with_pose_work_budget(bytes.clone(), pose_budget);
        s.configure(settings(poses)).unwrap();
        let t = Instant::now();
        let mut longest_read = 0;
        let read = loop {
            let c = cpu_ns();
            let r = s.read(4096);
            longest_read = longest_read.max(cpu_ns() - c);
            match r {
                Ok(r) if r.progress.finished => break Ok(()),
                Ok(_) => {}
                Err(e) => break Err(e),
            }
        };
        if let Err(e) = read {
            println!(
                "{poses:?}: {n} scans; refused after {:?} (longest read call {:.1} ms): {e}",
                t.elapsed(),
                longest_read as f64 / 1e6
            );
            continue;
        }
        println!(
            "{poses:?}: {n} scans read in {:?}, longest read call {:.1} ms",
            t.elapsed(),
            longest_read as f64 / 1e6
        );
        let t = Instant::now();
        let (mut longest, mut calls) = (0, 0);
        loop {
            let c = cpu_ns();
            let st = s.build_slice(budget).unwrap();
            longest = longest.max(cpu_ns() - c);
            calls += 1;
            if st.finished {
                break;
            }
        }
        println!(
            "{poses:?}: {n} scans; longest read call {:.1} ms; build {:?} in {calls} calls of {budget} units, longest {:.1} ms",
            longest_read as f64 / 1e6,
            t.elapsed(),
            longest as f64 / 1e6
        );
    }
}

/// Native time per unit of work, for insertion and for matching, on logs
/// of one and many beams and on the office logs (`OCCGRID_DATASETS` names
/// their folder): what [`match_work`] is fitted to.
#[test]
#[ignore = "a measurement"]
fn time_per_unit_measured() {
    use occgrid::poses::match_work_bound;
    let mut cases: Vec<(String, Vec<u8>)> = vec![];
    for (beams, range) in [(1, 1.5), (1, 10.0), (1, 29.0), (20, 5.0), (180, 5.0)] {
        cases.push((
            format!("{beams} beams at {range} m"),
            creeping_log(5000, beams, range),
        ));
    }
    if let Ok(dir) = std::env::var("OCCGRID_DATASETS") {
        for name in [
            "intel-corrected.log.gz",
            "freiburg-101-corrected.log.gz",
            "freiburg-campus-corrected.log.gz",
        ] {
            cases.push((name.into(), std::fs::read(format!("{dir}/{name}")).unwrap()));
        }
    }
    let (per_scan, per_point) = match_work_bound(&occgrid::poses::match_settings(30.0), 0.05);
    println!("bound at 5 cm: {per_scan} a scan, {per_point} a point");
    for (name, bytes) in cases {
        let mut s = RealLogSession::new(bytes);
        read_all(&mut s).unwrap();
        let log = s.pane(0).unwrap().scans().clone();
        let mut row = vec![];
        for poses in [PoseSourceKind::Corrected, PoseSourceKind::ScanMatched] {
            let mut pane = LogPane::new(log.clone(), settings(poses)).unwrap();
            let t = cpu_ns();
            pane.advance(usize::MAX);
            row.push((
                cpu_ns() - t,
                pane.progress().work,
                pane.progress().scans_done,
            ));
        }
        let (c, m) = (row[0], row[1]);
        let (ns, units) = (m.0 as f64 - c.0 as f64, m.1 as f64 - c.1 as f64);
        let bound = (log.len() as u64 - 1) * per_scan + log.beams() as u64 * per_point;
        println!(
            "{name}: {} scans, {} beams; insertion {:.1} ns/unit ({:.0} units/scan); matching {:.1} ns/unit ({:.0} units/scan, {:.1} us/scan); matching bound {bound:.2e}, used {:.1} %",
            c.2, log.beams(), c.0 as f64 / c.1 as f64, c.1 as f64 / c.2 as f64,
            ns / units, units / m.2 as f64, ns / m.2 as f64 / 1e3, 100.0 * units / bound as f64
        );
    }
}

/// SLAM's work on each shared log at 5 cm, seed 1, by part, beside its
/// bound (run with `cargo test --release --test real_log_pose_budget --
/// --ignored --nocapture slam_work_measured`; `OCCGRID_DATASETS` names the
/// folder of the logs, `LOGS` a comma-separated list of their file names):
/// the local matches, the insertion into submaps and their finishing, and
/// the loop search and optimisation together.
#[test]
#[ignore = "a measurement"]
fn slam_work_measured() {
    use occgrid::poses::ScanMatching;
    use occgrid::slam::SlamBuilder;
    let dir = std::env::var("OCCGRID_DATASETS")
        .unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    let names = std::env::var("LOGS").unwrap_or_else(|_| {
        "intel-corrected.log.gz,aces-corrected.log.gz,fhw-corrected.log.gz,\
         freiburg-101-corrected.log.gz,freiburg-campus-corrected.log.gz,\
         infinite-corridor-corrected.log.gz,intel-perfect.mcap,intel-noisy.mcap,aces-noisy.mcap"
            .into()
    });
    let defaults = LogMapSettings::default();
    let source_settings = SourceSettings {
        seed: 1,
        noise: OdometryParams::WHEELS,
        matching: match_settings(defaults.range_cap),
        resolution: defaults.resolution,
    };
    for name in names.split(',') {
        let bytes = std::fs::read(format!("{dir}/{name}")).unwrap();
        // A bag is read at its own odometry, a CARMEN log at its poses.
        let own = if name.ends_with(".mcap") {
            PoseSourceKind::Odometry
        } else {
            PoseSourceKind::Corrected
        };
        let mut s = RealLogSession::new(bytes);
        s.configure(settings(own)).unwrap();
        read_all(&mut s).unwrap();
        let log = s.pane(0).unwrap().scans().clone();
        let bound = PoseSourceKind::Slam
            .starting(&log, &source_settings)
            .unwrap()
            .work_bound(&log)
            .unwrap();
        let odometry = ScanMatching::odometry_of(&log, 1, &OdometryParams::WHEELS);
        let s = &source_settings;
        let mut b = SlamBuilder::new(odometry, s.noise, s.matching, s.resolution).unwrap();
        let (mut matched, mut inserted, mut settled) = (0u64, 0u64, 0u64);
        let t = Instant::now();
        for k in 0..log.len() {
            let w = b.work();
            let laser_max = log.max_range(k).unwrap_or(f64::INFINITY);
            b.locate_scan(&log.scan(k).unwrap(), laser_max).unwrap();
            inserted += b.work() - w;
            matched += local_match_work(b.last_match());
            let w = b.work();
            b.settle_within(u64::MAX);
            settled += b.work() - w;
        }
        let total = matched + inserted + settled;
        println!(
            "{name}: {} scans, {:.1} s; matched {matched:.2e}, inserted and finished {inserted:.2e}, \
             searched and optimised {settled:.2e}, {} closures: {total:.2e} of its bound {bound:.2e}",
            log.len(),
            t.elapsed().as_secs_f64(),
            b.closures(),
            total = total as f64,
            bound = bound as f64,
            matched = matched as f64,
            inserted = inserted as f64,
            settled = settled as f64,
        );
        assert!(total <= bound);
    }
}
