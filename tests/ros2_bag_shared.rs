#![cfg(not(target_arch = "wasm32"))]
//! The shared bags (written from the Intel and ACES logs by an independent
//! writer), read in place from `../shared/datasets` (or
//! `OCCGRID_DATASETS`): each maps at its odometry, whose poses are the
//! corrected CARMEN log's laser poses for `intel-perfect.mcap`.

use occgrid::io::{open_log, read_log, LogBudget};
use std::io::Read;
use std::path::PathBuf;
use std::time::Instant;

fn datasets() -> PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

fn read(name: &str) -> Option<Vec<u8>> {
    let path = datasets().join(name);
    match std::fs::read(&path) {
        Ok(b) => Some(b),
        Err(e) => {
            eprintln!("skipped: cannot read {}: {e}", path.display());
            None
        }
    }
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .read_to_end(&mut out)
        .unwrap();
    out
}

#[test]
fn intel_perfect_bag_puts_each_scan_at_the_corrected_logs_laser_pose() {
    let (Some(bag), Some(log)) = (read("intel-perfect.mcap"), read("intel-corrected.log.gz"))
    else {
        return;
    };
    let t = Instant::now();
    let scans = read_log(bag).unwrap();
    eprintln!("intel-perfect.mcap read in {:?}", t.elapsed());
    let carmen = read_log(gunzip(&log)).unwrap();
    assert_eq!(scans.len(), carmen.len());
    assert_eq!(scans.beams(), carmen.beams());
    assert!(!scans.pose_kinds().reference && scans.pose_kinds().odometry);
    let mut worst = (0.0f64, 0.0f64);
    for (a, b) in scans.poses().iter().zip(carmen.poses()) {
        worst.0 = worst.0.max((a.x - b.x).hypot(a.y - b.y));
        worst.1 = worst
            .1
            .max(occgrid::geometry::wrap_angle(a.theta - b.theta).abs());
    }
    assert!(
        worst.0 < 1e-3 && worst.1 < 1e-3,
        "worst pose difference {worst:?}"
    );
    let m = scans.mount();
    assert!(
        (m.x - 0.20).abs() < 1e-9 && (m.y + 0.05).abs() < 1e-9,
        "mount {m:?}"
    );
}

#[test]
fn each_shared_bag_reads_in_bounded_calls_to_the_same_scans() {
    for name in ["intel-perfect.mcap", "intel-noisy.mcap", "aces-noisy.mcap"] {
        let Some(bag) = read(name) else { return };
        let t = Instant::now();
        let whole = read_log(bag.clone()).unwrap();
        eprintln!("{name}: {} scans read in {:?}", whole.len(), t.elapsed());
        let budget = LogBudget {
            bytes_per_read: 4096,
            records_per_read: 16,
            ..LogBudget::default()
        };
        let mut source = open_log(bag, budget).unwrap();
        let mut calls = 0;
        while !source.read(3).unwrap().finished {
            calls += 1;
            assert!(calls < 1_000_000, "{name}: no end");
        }
        assert!(calls > 100, "{name}: {calls} calls");
        assert_eq!(*source.scans(), whole, "{name}");
        assert_eq!(source.progress().warning, None, "{name}");
    }
}
