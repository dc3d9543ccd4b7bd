#![cfg(not(target_arch = "wasm32"))]
//! SLAM on the shared logs, natively: a measurement, not a check (run with
//! `cargo test --release --test slam_logs -- --ignored --nocapture`;
//! `SLAM_LOGS` a comma-separated list of log file names, `SLAM_SEED` the
//! seed, `SLAM_OUT` a folder the poses are written to as `NAME.poses.tsv`).

use occgrid::apps::real_log::LogMapSettings;
use occgrid::poses::{match_settings, PoseSourceKind, SourceSettings};
use occgrid::sensors::odometry::OdometryParams;

use occgrid::grid::{FilterSettings, TiledGrid};
use occgrid::io::carmen::read_scans;
use occgrid::sensors::ScanLog;

/// A log of ../shared/datasets (or `OCCGRID_DATASETS`), by file name.
fn scans(name: &str) -> ScanLog {
    let dir: std::path::PathBuf = std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    read_scans(std::fs::File::open(dir.join(name)).unwrap()).unwrap()
}

#[test]
#[ignore = "a measurement: every shared log mapped by SLAM"]
fn slam_on_the_shared_logs() {
    let names = std::env::var("SLAM_LOGS")
        .unwrap_or_else(|_| "intel,freiburg-101,fhw,aces,freiburg-campus,infinite-corridor".into());
    let seed: u64 = std::env::var("SLAM_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let out =
        std::env::var("SLAM_OUT").unwrap_or_else(|_| std::env::temp_dir().display().to_string());
    for name in names.split(',') {
        let log = scans(&format!("{name}-corrected.log.gz"));
        let s = LogMapSettings::default();
        let settings = SourceSettings {
            seed,
            noise: OdometryParams::WHEELS,
            matching: match_settings(s.range_cap),
            resolution: s.resolution,
        };
        let started = std::time::Instant::now();
        let mut source = PoseSourceKind::Slam.start(&log, &settings).unwrap();
        // The source keeps its own submaps: the map it is handed is not read.
        let geometry =
            occgrid::geometry::GridGeometry::new(64, 64, s.resolution, 0.0, 0.0).unwrap();
        let filter = FilterSettings {
            prior: 0.5,
            clamp: s.clamp,
        };
        let empty = TiledGrid::new(geometry, filter, 64 * 64).unwrap();
        for k in 0..log.len() {
            let scan = log.scan(k).unwrap();
            let laser_max = log.max_range(k).unwrap_or(f64::INFINITY);
            source.locate(k, &scan, laser_max, &empty).unwrap();
        }
        // The last scan's loop search and the graph's last optimisation.
        while source.settling() {
            source.settle_within(u64::MAX);
        }
        let seconds = started.elapsed().as_secs_f64();
        let mut tsv = String::from("# scan x y theta\n");
        for (k, p) in source.poses().iter().enumerate() {
            tsv.push_str(&format!("{k}\t{}\t{}\t{}\n", p.x, p.y, p.theta));
        }
        let path = format!("{out}/{name}.poses.tsv");
        std::fs::write(&path, tsv).unwrap();
        println!(
            "{name}: {} scans, revision {}, {seconds:.1} s, {path}",
            log.len(),
            source.revision()
        );
        assert_eq!(source.poses().len(), log.len());
    }
}

/// This thread's time on a CPU so far, in nanoseconds (Linux's
/// `/proc/thread-self/schedstat`), or `None` where there is none: what a
/// call costs whatever else the machine runs, where wall time counts the
/// other processes' turns too.
fn thread_cpu_ns() -> Option<u64> {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// A real-log pane at SLAM poses built in calls of a fixed budget, as the
/// page builds it: the longest call, in work, in wall time and in time on
/// the CPU (run with `cargo test --release --test slam_logs -- --ignored
/// --nocapture`; `SLAM_LOGS` as above, `SLAM_BUDGET` the units of work a
/// call, 2e6 unless given).
#[test]
#[ignore = "a measurement: the longest build call of a SLAM pane"]
fn slam_pane_build_calls_on_the_shared_logs() {
    use occgrid::apps::real_log::LogPane;
    let names = std::env::var("SLAM_LOGS").unwrap_or_else(|_| "intel".into());
    let budget: u64 = std::env::var("SLAM_BUDGET")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2_000_000);
    for name in names.split(',') {
        let log = scans(&format!("{name}-corrected.log.gz"));
        let settings = LogMapSettings {
            poses: PoseSourceKind::Slam,
            ..LogMapSettings::default()
        };
        let mut pane = LogPane::new(log, settings).unwrap();
        let (mut calls, mut longest_work, mut longest_ms, mut total_ms) = (0, 0u64, 0f64, 0f64);
        let mut longest_cpu_ms = 0f64;
        loop {
            let before = pane.progress().work;
            let cpu = thread_cpu_ns();
            let started = std::time::Instant::now();
            let p = pane.advance_within(usize::MAX, budget);
            let ms = started.elapsed().as_secs_f64() * 1e3;
            if let (Some(a), Some(b)) = (cpu, thread_cpu_ns()) {
                longest_cpu_ms = longest_cpu_ms.max((b - a) as f64 / 1e6);
            }
            calls += 1;
            longest_work = longest_work.max(p.work - before);
            longest_ms = longest_ms.max(ms);
            total_ms += ms;
            if p.finished || pane.failure().is_some() {
                break;
            }
        }
        println!(
            "{name}: {calls} calls of {budget} units, the longest {longest_work} units, {longest_ms:.1} ms ({longest_cpu_ms:.1} ms on the CPU at most); {:.1} s in all",
            total_ms / 1e3
        );
    }
}
