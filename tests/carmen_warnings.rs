#![cfg(not(target_arch = "wasm32"))]
//! What the CARMEN reader refuses or says about a log it still maps:
//! headings that are no angle, laser lines it passes over, stamps that run
//! backwards, and the six public logs, which read without a warning.

use occgrid::io::carmen::{read_scans, LogLoader, MAX_HEADING};
use occgrid::io::LoadProgress;
use occgrid::sensors::ScanLog;
use occgrid::OccError;
use std::path::PathBuf;

fn datasets() -> PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

fn read(text: &str) -> (ScanLog, LoadProgress) {
    LogLoader::new(text.as_bytes()).read_to_end().unwrap()
}

/// A FLASER line at stamp `t`.
fn flaser(t: f64) -> String {
    format!("FLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0.5 -1.5 0.1 {t} host {t}\n")
}

const ROBOTLASER: &str = "ROBOTLASER1 0 -2.0943951 4.1887902 1.0471976 5.6 0.01 0 \
     5 1.0 2.0 5.6 3.5 0.5 2 100 200 \
     1.5 -2.0 0.3 1.4 -2.1 0.3 0.1 0.0 0.5 0.3 0.0 1234.5 host 1234.6\n";

#[test]
fn a_heading_that_is_no_angle_is_refused_by_line_and_field() {
    // (the line, the field its reason names)
    let cases = [
        (
            "FLASER 2 1 1 0 0 1e300 0 0 0 1 host 1\n".to_string(),
            "FLASER theta = 1e300 is not a heading",
        ),
        (
            "FLASER 2 1 1 0 0 0 0 0 -4000 1 host 1\n".to_string(),
            "FLASER odom_theta = -4000 is not a heading",
        ),
        (
            ROBOTLASER.replace("1.5 -2.0 0.3", "1.5 -2.0 1e300"),
            "ROBOTLASER1 laser_theta = 1e300 is not a heading",
        ),
        (
            ROBOTLASER.replace("1.4 -2.1 0.3", "1.4 -2.1 -1e300"),
            "ROBOTLASER1 robot_theta = -1e300 is not a heading",
        ),
    ];
    for (bad, why) in cases {
        let text = format!("# log\n{}{bad}{}", flaser(1.0), flaser(2.0));
        match read_scans(text.as_bytes()) {
            Err(OccError::Parse { line, reason }) => {
                assert_eq!(line, 3, "{reason}");
                assert!(reason.contains(why), "expected {why:?} in {reason:?}");
            }
            other => panic!("{why}: {other:?}"),
        }
    }
    // A wrapped heading, a little past pi, and one unwrapped through many
    // turns are headings; the bound itself is one too.
    for theta in [3.25, -3.25, 100.0, MAX_HEADING] {
        let text = format!("FLASER 2 1 1 0 0 {theta} 0 0 {theta} 1 host 1\n");
        let scans = read_scans(text.as_bytes()).unwrap();
        assert_eq!(scans.scan(0).unwrap().pose().theta, theta);
    }
}

#[test]
fn laser_lines_passed_over_are_counted_by_message_once_the_read_ends() {
    let mut text = flaser(1.0);
    for _ in 0..66 {
        text.push_str("RLASER 3 1.0 2.0 3.0 0.5 -1.5 0.1 0.5 -1.5 0.1 1.0 host 1.0\n");
    }
    text.push_str(&flaser(2.0));
    let (scans, p) = read(&text);
    assert_eq!((scans.len(), p.records), (2, 68));
    assert_eq!(
        p.warning.as_deref(),
        Some(
            "66 RLASER lines were not read (the first on line 2): \
             only FLASER and ROBOTLASER1 lines are mapped"
        )
    );
    // Not said before the read has ended.
    let mut loader = LogLoader::new(text.as_bytes());
    let early = loader.read(1).unwrap();
    assert!(!early.finished);
    assert_eq!(early.warning, None);

    // Every kind is named with its count; the sentence stays one line
    // whatever the log's length.
    let mixed = format!(
        "{}RAWLASER1 0 -1.57 3.14 0.0175 8.1 0.01 0 2 1.0 1.0 0 2.0 host 2.0\n\
         LASER3 1 1.0\nROBOTLASER2 x\nLASER4 1 1.0\nRLASER 1 1.0\n{}",
        flaser(1.0),
        flaser(2.0)
    );
    assert_eq!(
        read(&mixed).1.warning.as_deref(),
        Some(
            "1 RLASER, 1 LASER3, 1 LASER4, 1 RAWLASER1 and 1 ROBOTLASER2 lines were not read \
             (the first on line 2): only FLASER and ROBOTLASER1 lines are mapped"
        )
    );
    let one = format!("{}RLASER 1 1.0\n", flaser(1.0));
    assert_eq!(
        read(&one).1.warning.as_deref(),
        Some(
            "1 RLASER line was not read (the first on line 2): \
             only FLASER and ROBOTLASER1 lines are mapped"
        )
    );
    // Other messages are passed over without a word.
    let quiet = format!("ODOM 0 0 0 0 0 0 1 host 1\nNEFF 3\n{}", flaser(1.0));
    assert_eq!(read(&quiet).1.warning, None);
}

#[test]
fn stamps_running_backwards_are_counted_from_their_first_line_and_mapped_in_file_order() {
    let stamps = [5.0, 4.0, 3.0, 3.5, 1.0];
    let text: String = stamps.iter().map(|&t| flaser(t)).collect();
    let (scans, p) = read(&text);
    assert_eq!(
        p.warning.as_deref(),
        Some(
            "The scans' stamps run backwards 3 times (the first on line 2): \
             the scans are mapped in file order"
        )
    );
    let kept: Vec<_> = (0..scans.len()).map(|i| scans.stamp(i)).collect();
    assert_eq!(kept, stamps.map(Some));
    // A single step back, however small, among few scans.
    let once: String = [1.0, 2.0, 1.9].iter().map(|&t| flaser(t)).collect();
    assert!(read(&once)
        .1
        .warning
        .unwrap()
        .contains("run backwards 1 time (the first on line 3)"));
    // A logger's jitter (one step back of under 2 s among 100 steps) and
    // lines without stamps say nothing.
    let mut jitter: String = (0..101).map(|k| flaser(k as f64)).collect();
    jitter.push_str(&flaser(99.5));
    jitter.push_str("FLASER 1 1.0 0 0 0 0 0 0\n");
    assert_eq!(read(&jitter).1.warning, None);
    // A splice back in time is no jitter, however long the log.
    let mut splice: String = (0..1000).map(|k| flaser(k as f64)).collect();
    splice.push_str(&flaser(10.0));
    assert!(read(&splice)
        .1
        .warning
        .unwrap()
        .contains("backwards 1 time (the first on line 1001)"));
}

#[test]
fn warnings_of_a_cut_short_log_are_joined_in_one_string() {
    let text = format!(
        "{}RLASER 1 1.0\n{}{}FLASER 3 1.0 2.0",
        flaser(2.0),
        flaser(1.0),
        flaser(3.0)
    );
    let (scans, p) = read(&text);
    assert_eq!(scans.len(), 3);
    assert_eq!(
        p.warning.as_deref(),
        Some(
            "line 5: the file ends inside this line, which is cut short \
             (FLASER line ends before range 3); the 3 complete scans before it are kept. \
             1 RLASER line was not read (the first on line 2): \
             only FLASER and ROBOTLASER1 lines are mapped. \
             The scans' stamps run backwards 1 time (the first on line 3): \
             the scans are mapped in file order"
        )
    );
}

#[test]
fn the_six_public_logs_read_without_a_warning() {
    let dir = datasets();
    if !dir.is_dir() {
        eprintln!("skipped: no datasets at {}", dir.display());
        return;
    }
    let names = [
        "aces-corrected.log.gz",
        "fhw-corrected.log.gz",
        "freiburg-101-corrected.log.gz",
        "freiburg-campus-corrected.log.gz",
        "infinite-corridor-corrected.log.gz",
        "intel-corrected.log.gz",
    ];
    for name in names {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        let (scans, p) = LogLoader::new(&bytes[..]).read_to_end().unwrap();
        assert!(p.finished && scans.len() > 200, "{name}");
        assert_eq!(p.warning, None, "{name}");
    }
}
