#![cfg(not(target_arch = "wasm32"))]
//! The CARMEN reader on the two real logs, on damaged and mixed files, on
//! `ROBOTLASER1` lines, and the chunked map build it feeds. (What a read
//! may cost is in `tests/carmen_budgets.rs`.)

use occgrid::apps::real_log::{LogMapSettings, LogPane};
use occgrid::io::carmen::{read_scans, LaserMessage, LogLoader, LogReader};
use occgrid::io::LoadProgress;
use occgrid::mapping::walls::WallModel;
use occgrid::sensors::ScanLog;
use occgrid::OccError;
use rand::{Rng, SeedableRng};
use std::f64::consts::{FRAC_PI_2, PI};
use std::io::{BufReader, Read};
use std::path::PathBuf;

fn datasets() -> PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

fn dataset(name: &str) -> Vec<u8> {
    let path = datasets().join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

fn gunzip(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .read_to_end(&mut out)
        .unwrap();
    out
}

/// A message for a reader: printable ASCII and the typographic characters
/// the project writes, no byte of a binary file (no control characters, no
/// replacement characters, no escapes such as `\u{..}`).
fn assert_words_only(message: &str) {
    assert!(
        message
            .chars()
            .all(|c| (' '..='~').contains(&c) || "…–—’".contains(c)),
        "{message:?}"
    );
    assert!(
        !message.contains("\\u{") && !message.contains("\\x"),
        "{message:?}"
    );
}

/// The whole log through the one reader the page uses: its scans and the
/// last progress (lines read, a cut short's warning).
fn read_all(bytes: &[u8]) -> occgrid::Result<(ScanLog, LoadProgress)> {
    LogLoader::new(bytes).read_to_end()
}

/// True when `a` holds the first scans of `b`, each exactly as in `b`.
fn is_prefix(a: &ScanLog, b: &ScanLog) -> bool {
    a.len() <= b.len() && (0..a.len()).all(|k| a.scan(k) == b.scan(k) && a.origin(k) == b.origin(k))
}

fn parse_error(bytes: &[u8]) -> (usize, String) {
    match read_all(bytes) {
        Err(OccError::Parse { line, reason }) => (line, reason),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// What the README and docs/BENCHMARKS.md say about each log.
struct Expected {
    name: &'static str,
    scans: usize,
    lines: usize,
    first_line: usize,
    last_line: usize,
    /// Readings at or beyond 30 m (W1's z_max): no-returns for the mapper.
    beyond_30m: usize,
    max_range: f64,
}

const INTEL: Expected = Expected {
    name: "intel-corrected.log.gz",
    scans: 910,
    lines: 16365,
    first_line: 175,
    last_line: 16316,
    beyond_30m: 4172,
    max_range: 81.83,
};

const ACES: Expected = Expected {
    name: "aces-corrected.log.gz",
    scans: 440,
    lines: 8700,
    first_line: 144,
    last_line: 8510,
    beyond_30m: 1156,
    max_range: 50.0,
};

/// Streams the log from its file and checks every record.
fn check_real_log(e: &Expected) {
    let path = datasets().join(e.name);
    let file = std::fs::File::open(&path).unwrap();
    let size = file.metadata().unwrap().len();
    let mut reader = LogReader::new(BufReader::new(file));
    let records: Vec<_> = (&mut reader).map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), e.scans, "{}: FLASER lines", e.name);
    assert_eq!(reader.lines_read(), e.lines, "{}: lines", e.name);
    assert_eq!(reader.bytes_read(), size, "every compressed byte consumed");
    assert!(reader.is_finished());
    assert_eq!(records[0].line, e.first_line);
    assert_eq!(records[e.scans - 1].line, e.last_line);
    let (mut beyond, mut max) = (0, 0.0f64);
    let mut last_line = 0;
    let (mut first_time, mut last_time) = (None, 0.0);
    for r in &records {
        assert_eq!(r.message, LaserMessage::Flaser);
        assert!(r.line > last_line, "records come in file order");
        last_line = r.line;
        let s = r.to_scan().unwrap();
        assert_eq!(s.len(), 180, "{}: line {}", e.name, r.line);
        for (i, (&z, &b)) in s.ranges().iter().zip(s.bearings()).enumerate() {
            assert!(z.is_finite() && z >= 0.0, "line {}: range {z}", r.line);
            assert!((b - (-FRAC_PI_2 + i as f64 * PI / 180.0)).abs() < 1e-12);
            beyond += (z >= 30.0) as usize;
            max = max.max(z);
        }
        let p = s.pose();
        assert!(p.x.abs() < 60.0 && p.y.abs() < 60.0 && p.theta.abs() <= 2.0 * PI);
        assert!(r.odometry.is_some() && r.robot_pose.is_none() && r.max_range.is_none());
        let t = r.timestamp.expect("each FLASER line has its ipc_timestamp");
        first_time.get_or_insert(t);
        last_time = t;
    }
    assert_eq!(beyond, e.beyond_30m, "{}: no-returns", e.name);
    // Minutes of driving (the logger's clock may step back by a fraction of
    // a second between lines, so only the span is checked).
    assert!(
        last_time - first_time.unwrap() > 600.0,
        "{}: seconds",
        e.name
    );
    assert_eq!(max, e.max_range);
    // The robot moves: the poses span metres, not a point.
    let xs: Vec<f64> = records.iter().map(|r| r.pose.x).collect();
    let span =
        xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    assert!(span > 10.0, "{}: poses span {span} m in x", e.name);
}

#[test]
fn intel_log_streams_910_flaser_scans_with_valid_ranges_and_poses() {
    check_real_log(&INTEL);
}

#[test]
fn aces_log_streams_440_flaser_scans_with_valid_ranges_and_poses() {
    check_real_log(&ACES);
}

#[test]
fn the_store_keeps_every_record_of_the_stream_at_f32_precision_gzip_or_plain() {
    let bytes = dataset(INTEL.name);
    let (scans, p) = read_all(&bytes).unwrap();
    assert_eq!((scans.len(), p.records), (INTEL.scans, INTEL.lines));
    let (plain, _) = read_all(&gunzip(&bytes)).unwrap();
    assert_eq!(plain, scans, "gzip and plain text read alike");
    let records: Vec<_> = LogReader::new(&bytes[..]).map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), scans.len());
    for (k, r) in records.iter().enumerate() {
        let kept = scans.scan(k).unwrap();
        let text = r.to_scan().unwrap();
        assert_eq!(scans.origin(k), Some(r.line));
        assert_eq!(
            (kept.pose(), kept.bearings()),
            (text.pose(), text.bearings())
        );
        let rounded: Vec<f64> = r.ranges.iter().map(|&z| z as f32 as f64).collect();
        assert_eq!(kept.ranges(), &rounded[..], "line {}", r.line);
    }
}

/// W1 (`bench::intel`) through the store the page maps: the counts pinned
/// for the Intel log, and the same cells as a build from the text's own
/// `f64` readings (the store's `f32` rounding moves no cell).
#[test]
fn w1_maps_the_stores_scans_to_its_pinned_counts_and_the_cells_of_the_texts_readings() {
    use occgrid::bench::intel::{build_intel_map, intel_geometry, intel_model, intel_settings};
    let bytes = dataset(INTEL.name);
    let (grid, c) = build_intel_map(&read_scans(&bytes[..]).unwrap());
    assert_eq!((c.beams, c.cell_updates), (163_800, 8_181_340), "{c:?}");
    assert_eq!(
        (c.occupied, c.free, c.unknown),
        (20_585, 417_317, 310_160),
        "{c:?}"
    );
    let mut text = occgrid::grid::LogOddsGrid::new(intel_geometry(), intel_settings()).unwrap();
    let mut mapper = occgrid::mapping::traversal::RayMapper::new();
    for r in LogReader::new(&bytes[..]) {
        mapper.integrate(&mut text, &intel_model(), &r.unwrap().to_scan().unwrap());
    }
    assert!(grid.log_odds() == text.log_odds(), "bit-identical cells");
}

#[test]
fn garbage_files_fail_on_line_one_without_panicking() {
    let png = dataset("intel-corrected.png");
    let (line, reason) = parse_error(&png);
    assert_eq!(line, 1, "{reason}");
    assert!(reason.contains("neither gzip nor a text log"), "{reason}");
    assert_words_only(&reason);

    let (line, reason) = parse_error(b"This is a shopping list.\nMilk\n");
    assert_eq!(line, 1);
    assert!(reason.contains("\"This\""), "{reason}");

    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    for _ in 0..50 {
        let n = rng.random_range(1..4000);
        let noise: Vec<u8> = (0..n).map(|_| rng.random::<u8>()).collect();
        // Random bytes are never a log: refused on line 1, in words.
        match read_all(&noise) {
            Err(OccError::Parse { line: 1, reason }) => assert_words_only(&reason),
            other => panic!("noise of {n} bytes: {other:?}"),
        }
    }
    // A gzip header over garbage.
    let (line, reason) = parse_error(&[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 0xff, 0xff, 0xff]);
    assert_eq!(line, 1);
    assert!(reason.contains("compressed"), "{reason}");
}

#[test]
fn a_gzip_log_cut_short_keeps_the_scans_before_the_cut_and_warns_with_the_line() {
    let bytes = dataset(INTEL.name);
    let (full, p) = read_all(&bytes).unwrap();
    assert_eq!(p.warning, None);
    for fraction in [0.02, 0.25, 0.3, 0.5, 0.9, 0.999] {
        let cut = (bytes.len() as f64 * fraction) as usize;
        let (scans, p) = read_all(&bytes[..cut]).unwrap();
        let warning = p.warning.expect("a cut log warns");
        let line: usize = warning
            .strip_prefix("line ")
            .and_then(|w| w.split(':').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{warning}"));
        assert!(warning.contains("ends early"), "{warning}");
        // Roughly where the cut is: the text is compressed about evenly.
        let expected = fraction * INTEL.lines as f64;
        assert!(
            (line as f64 - expected).abs() < 0.15 * INTEL.lines as f64,
            "cut at {fraction}: line {line}, expected near {expected}"
        );
        // Every scan before the cut, exactly as in the whole log.
        assert!(!scans.is_empty() && scans.len() < full.len());
        assert!(is_prefix(&scans, &full));
        assert!(
            warning.contains(&format!("the {} complete scans", scans.len())),
            "{warning}"
        );
    }
}

/// The byte offsets of each line's start, and the line number (from 1) and
/// start of the `k`-th FLASER line (from 0).
fn nth_flaser(text: &[u8], k: usize) -> (usize, usize, usize) {
    let starts: Vec<usize> = std::iter::once(0)
        .chain(
            text.iter()
                .enumerate()
                .filter(|(_, &b)| b == b'\n')
                .map(|(i, _)| i + 1),
        )
        .collect();
    let (number, start) = starts
        .iter()
        .enumerate()
        .filter(|(_, &s)| text[s..].starts_with(b"FLASER"))
        .map(|(k, &s)| (k + 1, s))
        .nth(k)
        .unwrap();
    let end = start + text[start..].iter().position(|&b| b == b'\n').unwrap();
    (number, start, end)
}

#[test]
fn a_plain_log_cut_inside_a_scan_keeps_the_scans_before_it_and_names_that_line() {
    let text = gunzip(&dataset(INTEL.name));
    // The fifth FLASER line.
    let (number, start, end) = nth_flaser(&text, 4);
    let line = std::str::from_utf8(&text[start..end]).unwrap();
    // Cut in the middle of the ranges, right after the pose, and inside
    // the odometry: the four scans before are kept, with a warning.
    let after_pose = line
        .split(' ')
        .take(185)
        .collect::<Vec<_>>()
        .join(" ")
        .len();
    for cut in [start + 400, start + after_pose, start + after_pose + 3] {
        let (scans, p) = read_all(&text[..cut]).unwrap();
        assert_eq!(
            (scans.len(), p.records),
            (4, number),
            "cut at byte {}",
            cut - start
        );
        let w = p.warning.unwrap();
        assert!(
            w.starts_with(&format!("line {number}: the file ends inside this line")),
            "{w}"
        );
        assert!(
            w.contains("FLASER line ends before") && w.contains("the 4 complete scans"),
            "{w}"
        );
    }
    // Cut after the odometry, inside the trailing timestamps: nothing the
    // map uses is lost, so the line counts.
    let after_odom = line
        .split(' ')
        .take(188)
        .collect::<Vec<_>>()
        .join(" ")
        .len();
    for cut in [start + after_odom, end - 2] {
        let (scans, p) = read_all(&text[..cut]).unwrap();
        assert_eq!((scans.len(), p.records, p.warning), (5, number, None));
    }
    // The Intel log cut at 30 %, mid-line, as a reader would have it: a map
    // of the scans before the cut, through the session the page drives.
    let cut = (text.len() as f64 * 0.3) as usize;
    let cut = cut + text[cut..].iter().position(|&b| b == b' ').unwrap();
    let mut session = occgrid::apps::real_log::RealLogSession::new(text[..cut].to_vec());
    let report = loop {
        let r = session.read(usize::MAX).unwrap();
        if r.progress.finished {
            break r;
        }
    };
    let w = report.progress.warning.expect("warned");
    let complete = read_scans(&text[..cut]).unwrap().len();
    assert!(complete > 200, "{complete}");
    assert_eq!(report.progress.scans, complete);
    assert!(
        w.contains(&format!("line {}:", report.progress.records)),
        "{w}"
    );
    while !session.build_chunk(usize::MAX).unwrap().finished {}
    assert_eq!(session.pane(0).unwrap().progress().scans_done, complete);
}

#[test]
fn cutting_a_mixed_log_at_every_byte_never_panics() {
    let text = mixed_log();
    let (full, p) = read_all(text.as_bytes()).unwrap();
    for cut in 0..text.len() {
        match read_all(&text.as_bytes()[..cut]) {
            Ok((scans, _)) => assert!(is_prefix(&scans, &full)),
            Err(OccError::Parse { line, .. }) => assert!(line >= 1 && line <= p.records),
            Err(e) => panic!("unexpected error kind {e}"),
        }
    }
}

const ROBOTLASER: &str = "ROBOTLASER1 0 -2.0943951 4.1887902 1.0471976 5.6 0.01 0 \
     5 1.0 2.0 5.6 3.5 0.5 2 100 200 \
     1.5 -2.0 0.3 1.4 -2.1 0.3 0.1 0.0 0.5 0.3 0.0 1234.5 host 1234.6";

fn mixed_log() -> String {
    let flaser_181 = format!(
        "FLASER 181 {} 0 0 0.5 0 0 0 3.0 host 3.0",
        vec!["1.25"; 181].join(" ")
    );
    [
        "# a mixed log",
        "PARAM robot_frontlaser_offset 0.0 nohost 0",
        "",
        "ODOM 0 0 0 0 0 0 1.0 host 1.0",
        "FLASER 4 1.0 1.5 2.0 2.5 0.1 0.2 0.3 0 0 0 1.5 host 1.5",
        "RAWLASER1 0 -1.57 3.14 0.0175 8.1 0.01 0 2 1.0 1.0 0 2.0 host 2.0",
        ROBOTLASER,
        "NEFF 12.5",
        &flaser_181,
    ]
    .join("\n")
        + "\n"
}

#[test]
fn a_mixed_log_keeps_file_order_line_numbers_and_each_message_kind() {
    let records: Vec<_> = LogReader::new(mixed_log().as_bytes())
        .map(|r| r.unwrap())
        .collect();
    let kinds: Vec<_> = records.iter().map(|r| (r.line, r.message)).collect();
    assert_eq!(
        kinds,
        [
            (5, LaserMessage::Flaser),
            (7, LaserMessage::RobotLaser1),
            (9, LaserMessage::Flaser)
        ]
    );
    // 181 FLASER beams include both ends of the half circle.
    let last = records[2].to_scan().unwrap();
    assert!((last.bearings()[180] - FRAC_PI_2).abs() < 1e-12);
    assert_eq!(records[2].timestamp, Some(3.0));
}

#[test]
fn a_malformed_line_in_a_mixed_log_is_reported_by_number_and_reason() {
    // (what to change in the ROBOTLASER1 line, to what, words of the reason)
    let robot_pose = " 1.4 -2.1 0.3 0.1 0.0 0.5 0.3 0.0 1234.5 host 1234.6";
    let edits = [
        (
            " 5 1.0 2.0",
            " 2.5 1.0 2.0",
            "beam count must be a whole number",
        ),
        ("1.0471976 5.6", "1.0471976 -5.6", "maximum_range"),
        ("1.0471976", "0", "angular_resolution"),
        ("-2.0943951 4.1887902", "-2.0943951 9.0", "field_of_view"),
        (
            " 2 100 200",
            " 2 100 x",
            "remission 2 is not a number: \"x\"",
        ),
        ("1.5 -2.0 0.3", "1.5 -2.0 inf", "laser_theta is not finite"),
        (robot_pose, " 1.4", "ends before robot_y"),
        ("1.0471976 5.6", "1e308 5.6", "puts the last beam at inf"),
        (
            ROBOTLASER,
            "FLASER 0",
            "beam count must be a whole number from 1",
        ),
        (ROBOTLASER, "FLASER 20000", "from 1 to 10000"),
        (ROBOTLASER, "flaser 1 1.0 0 0 0 0 0 0", "not a CARMEN log"),
        // A reading or a maximum range past f32 (what the store keeps).
        (
            ROBOTLASER,
            "FLASER 2 1e39 1 0 0 0 0 0 0",
            "FLASER range 1 = 1e39 is beyond 3.4e38 m",
        ),
        (
            "1.0471976 5.6",
            "1.0471976 1e39",
            "maximum_range = 1e39 is beyond 3.4e38 m",
        ),
        // A pose farther than 1,000 km from the origin.
        (
            ROBOTLASER,
            "FLASER 2 1 1 1e300 1e300 0 0 0 0",
            "FLASER x = 1e300 m is beyond 1e6 m",
        ),
        (
            ROBOTLASER,
            "FLASER 2 1 1 0 -2e6 0 0 0 0",
            "FLASER y = -2e6 m is beyond",
        ),
        (
            ROBOTLASER,
            "FLASER 2 1 1 0 0 0 1000000.5 0 0",
            "odom_x = 1000000.5 m is",
        ),
        (
            "1.5 -2.0 0.3",
            "1.5 -3e7 0.3",
            "ROBOTLASER1 laser_y = -3e7 m is beyond",
        ),
    ];
    for (from, to, why) in edits {
        let text = mixed_log().replace(ROBOTLASER, &ROBOTLASER.replace(from, to));
        let (line, reason) = parse_error(text.as_bytes());
        assert_eq!(line, 7, "{reason}");
        assert!(reason.contains(why), "expected {why:?} in {reason:?}");
    }
}

/// Reads `text` the way the page does, through the session, to the end of
/// the read or its error.
fn session_read(text: &str) -> (occgrid::apps::real_log::RealLogSession, occgrid::Result<()>) {
    let mut session = occgrid::apps::real_log::RealLogSession::new(text.as_bytes().to_vec());
    let outcome = loop {
        match session.read(usize::MAX) {
            Ok(r) if r.progress.finished => break Ok(()),
            Ok(_) => {}
            Err(e) => break Err(e),
        }
    };
    (session, outcome)
}

#[test]
fn a_reading_past_f32_is_refused_by_the_page_and_every_reading_kept_is_mapped() {
    // 1e39 is finite as f64 but infinite in the store's f32: the scan used
    // to be kept, counted in the beams read, and left out of the map.
    let text = "FLASER 3 1 1 1 0 0 0 0 0 0\nFLASER 3 1e39 1 1 0.1 0 0 0 0 0 0\n";
    let (session, outcome) = session_read(text);
    let e = outcome.unwrap_err().to_string();
    assert!(
        e.starts_with("line 2: FLASER range 1 = 1e39 is beyond"),
        "{e}"
    );
    assert!(!session.awaiting_settings());
    // Just inside f32: kept, and every beam read is a beam mapped.
    let scans = read_scans(text.replace("1e39", "3e38").as_bytes()).unwrap();
    assert_eq!(scans.beams(), 6);
    let mut b = LogPane::new(scans, LogMapSettings::default()).unwrap();
    let p = b.advance(usize::MAX);
    assert_eq!((p.scans_done, p.beams), (2, 6));
}

#[test]
fn a_pose_past_a_thousand_kilometres_is_refused_by_the_page_at_read_time() {
    // It used to be read, then refused at map time as a grid of 0 x 0 cells
    // with a session waiting for settings that could never fit.
    let (session, outcome) = session_read("FLASER 3 1 1 1 1e300 1e300 0 0 0 0\n");
    let e = outcome.unwrap_err().to_string();
    assert!(
        e.starts_with("line 1: FLASER x = 1e300 m is beyond 1e6 m"),
        "{e}"
    );
    assert!(!session.awaiting_settings());
    // At the bound, a pose is a pose.
    let edge = read_scans(&b"FLASER 3 1 1 1 1e6 -1e6 0 0 0 0\n"[..]).unwrap();
    assert_eq!(edge.pose(0).map(|p| (p.x, p.y)), Some((1e6, -1e6)));
}

#[test]
fn a_robotlaser1_line_parses_with_its_own_angles_range_and_poses() {
    let r = LogReader::new(ROBOTLASER.as_bytes())
        .next()
        .unwrap()
        .unwrap();
    assert_eq!(r.message, LaserMessage::RobotLaser1);
    let scan = r.to_scan().unwrap();
    assert_eq!(scan.ranges(), &[1.0, 2.0, 5.6, 3.5, 0.5]);
    // The log's own start angle and increment (not pi/3, though close).
    #[allow(clippy::approx_constant)]
    let expected: Vec<f64> = (0..5).map(|i| -2.0943951 + i as f64 * 1.0471976).collect();
    for (b, e) in scan.bearings().iter().zip(&expected) {
        assert!((b - e).abs() < 1e-12, "{b} vs {e}");
    }
    assert!(
        (scan.bearings()[4] - 2.0943951).abs() < 1e-6,
        "the last beam ends the 240 degree field"
    );
    assert_eq!(r.max_range, Some(5.6));
    let p = scan.pose();
    assert_eq!(
        (p.x, p.y, p.theta),
        (1.5, -2.0, 0.3),
        "the laser pose, not the robot's"
    );
    let rp = r.robot_pose.unwrap();
    assert_eq!((rp.x, rp.y), (1.4, -2.1));
    assert_eq!(r.timestamp, Some(1234.5));
    // No remissions at all is fine too.
    let none = ROBOTLASER.replace(" 2 100 200", " 0");
    let r = LogReader::new(none.as_bytes()).next().unwrap().unwrap();
    assert_eq!(r.ranges.len(), 5);
}

#[test]
fn a_robotlaser1_reading_at_its_maximum_range_carves_free_space_and_marks_nothing() {
    // Beam 0 straight ahead reads 4 m, the laser's own maximum; beam 1, at
    // 0.1 rad, reads 2 m. The cap (30 m) is longer than the laser's range.
    let text = "ROBOTLASER1 0 0 0.1 0.1 4.0 0.01 0 2 4.0 2.0 0 \
                0.0 0.0 0.0 0.0 0.0 0.0 0 0 0 0 0 1 h 1\n";
    let scans = read_scans(text.as_bytes()).unwrap();
    // Table 9.2's walls: every no-return carves out to its reach. (Under
    // the default incidence walls a no-return clears only what returns on
    // both its sides saw free, `mapping::neighbour_support`; this one has
    // a return on one side only, and clears nothing, as checked last.)
    let settings = LogMapSettings {
        resolution: 0.1,
        margin: 3.0,
        walls: WallModel::Table92,
        ..Default::default()
    };
    let mut defaults = LogPane::new(
        scans.clone(),
        LogMapSettings {
            walls: WallModel::Incidence,
            ..settings
        },
    )
    .unwrap();
    let mut b = LogPane::new(scans, settings).unwrap();
    b.advance(1);
    let g = b.grid().to_dense().unwrap();
    let geo = g.geometry();
    let at = |x: f64, y: f64| {
        let (ix, iy) = geo.world_to_cell(x, y).unwrap();
        g.log_odds()[geo.index(ix, iy)]
    };
    assert!(
        at(1.0, 0.01) < 0.0 && at(3.9, 0.01) < 0.0,
        "free out to 4 m"
    );
    assert_eq!(at(4.2, 0.01), 0.0, "nothing beyond the maximum");
    // Every occupied cell lies at the 2 m return, none at 4 m.
    let end = (2.0 * 0.1f64.cos(), 2.0 * 0.1f64.sin());
    let occupied: Vec<(f64, f64)> = (0..geo.len())
        .filter(|&i| g.log_odds()[i] > 0.0)
        .map(|i| {
            let (ix, iy) = geo.cell_of_index(i);
            geo.cell_center(ix, iy)
        })
        .collect();
    assert!(!occupied.is_empty(), "the 2 m reading marks its cell");
    for (x, y) in occupied {
        assert!((x - end.0).hypot(y - end.1) < 0.1, "occupied at ({x}, {y})");
    }
    defaults.advance(1);
    let d = defaults.grid().to_dense().unwrap();
    let at = |x: f64, y: f64| {
        let (ix, iy) = geo.world_to_cell(x, y).unwrap();
        d.log_odds()[geo.index(ix, iy)]
    };
    assert_eq!(
        (at(3.0, 0.01), at(4.2, 0.01)),
        (0.0, 0.0),
        "no-return: nothing"
    );
    assert!(at(end.0, end.1) > 0.0, "the 2 m reading marks its cell");
}

#[test]
fn the_grid_extent_holds_every_pose_and_endpoint_within_the_cap_plus_margin() {
    let scans = read_scans(&dataset(INTEL.name)[..]).unwrap();
    let settings = LogMapSettings::default();
    let b = LogPane::new(scans.clone(), settings).unwrap();
    let geo = *b.grid().to_dense().unwrap().geometry();
    let [ox, oy] = geo.origin();
    let r = geo.resolution();
    assert!(
        ((ox / r) - (ox / r).round()).abs() < 1e-9,
        "origin on the resolution's grid"
    );
    let inner = |x: f64, y: f64| {
        let m = settings.margin - 1e-9;
        geo.world_to_cell(x - m, y - m).is_some() && geo.world_to_cell(x + m, y + m).is_some()
    };
    let mut endpoints = 0;
    for k in 0..scans.len() {
        let s = scans.scan(k).unwrap();
        let p = s.pose();
        assert!(inner(p.x, p.y));
        for (&z, &bearing) in s.ranges().iter().zip(s.bearings()) {
            if z < settings.range_cap {
                let (x, y) = p.point_at(z, bearing);
                assert!(inner(x, y), "scan {k}: endpoint ({x}, {y}) outside");
                endpoints += 1;
            }
        }
    }
    assert_eq!(endpoints, 163_800 - INTEL.beyond_30m);
    // Tight: beyond the endpoints the box holds what the beams carved (a
    // no-return's clearing, a return's α/2) plus a cell and the margin.
    let [x0, y0, x1, y1] = scans.endpoint_bounds(settings.range_cap).unwrap();
    let carved = settings.no_return_reach.max(settings.alpha / 2.0);
    let slack = settings.margin + r + carved;
    assert!(x0 - ox <= slack && y0 - oy <= slack);
    let far_x = ox + geo.width() as f64 * r;
    let far_y = oy + geo.height() as f64 * r;
    assert!(far_x - x1 <= slack && far_y - y1 <= slack);
}

#[test]
fn the_intel_map_built_in_chunks_equals_the_one_call_build_and_the_w1_occupied_count() {
    let scans = read_scans(&dataset(INTEL.name)[..]).unwrap();
    let mut whole = LogPane::new(scans.clone(), LogMapSettings::chapter()).unwrap();
    let p = whole.advance(usize::MAX);
    assert!(p.finished && p.scans_done == 910 && p.beams == 163_800);
    let mut chunked = LogPane::new(scans, LogMapSettings::chapter()).unwrap();
    let mut calls = 0;
    while !chunked.advance(37).finished {
        calls += 1;
    }
    assert_eq!(calls, 910 / 37);
    assert_eq!(
        chunked.grid().to_dense().unwrap(),
        whole.grid().to_dense().unwrap(),
        "bit-identical"
    );
    assert_eq!(chunked.progress().cell_updates, p.cell_updates);
    // Every occupied cell of W1 lies inside the log's extent, so the count
    // agrees with docs/BENCHMARKS.md's reference (20,483 for a JavaScript port).
    let c = whole.counts();
    assert!(
        (c.occupied as f64 - 20_483.0).abs() < 0.01 * 20_483.0,
        "{c:?}"
    );
    assert!(c.occupied + c.free + c.unknown <= c.cells);
    assert_eq!(c.cells, whole.grid().to_dense().unwrap().geometry().len());
    let by_hand = whole
        .grid()
        .to_dense()
        .unwrap()
        .log_odds()
        .iter()
        .filter(|&&l| occgrid::grid::probability(l as f64) > 0.65)
        .count();
    assert_eq!(c.occupied, by_hand);
    // The path in image pixels puts the first pose back where it was.
    let path = whole.path_in_pixels();
    assert_eq!(path.len(), 2 * 910);
    let geo = *whole.grid().to_dense().unwrap().geometry();
    let first = whole.scans().pose(0).unwrap();
    let (u, v) = geo.world_to_grid(first.x, first.y);
    assert!((path[0] as f64 - u).abs() < 1e-3);
    assert!((path[1] as f64 - (geo.height() as f64 - v)).abs() < 1e-3);
    // A path grown a piece at a time is the whole one, bit for bit; a
    // piece past the scans is cut at the last.
    let pieces: Vec<f32> = [(0, 300), (300, 301), (301, 910), (910, 5000)]
        .iter()
        .flat_map(|&(a, b)| whole.path_in_pixels_between(a, b))
        .collect();
    assert_eq!(
        pieces.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        path.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert!(whole.path_in_pixels_between(700, 600).is_empty());
    assert!(whole.path_in_pixels_between(2000, 3000).is_empty());
}

#[test]
fn bad_settings_are_rejected_by_name_and_leave_the_map_as_it_was() {
    let scans = read_scans(mixed_log().as_bytes()).unwrap();
    let mut b = LogPane::new(scans, LogMapSettings::default()).unwrap();
    b.advance(2);
    let state = |b: &LogPane| {
        (
            b.grid().to_dense().unwrap().clone(),
            b.progress(),
            *b.settings(),
        )
    };
    let before = state(&b);
    let with = |change: fn(&mut LogMapSettings)| {
        let mut s = LogMapSettings::default();
        change(&mut s);
        s
    };
    let bad = [
        ("resolution", with(|s| s.resolution = 0.0)),
        ("resolution", with(|s| s.resolution = f64::NAN)),
        ("width x height", with(|s| s.resolution = 1e-4)),
        ("alpha", with(|s| s.alpha = -0.1)),
        ("rangeCap", with(|s| s.range_cap = 0.0)),
        ("clamp", with(|s| s.clamp = 0.0)),
        ("lOcc", with(|s| s.l_occ = f64::INFINITY)),
        ("margin", with(|s| s.margin = -1.0)),
    ];
    for (field, s) in bad {
        let e = b.configure(s).unwrap_err().to_string();
        assert!(e.contains(field), "{field}: {e}");
        assert_eq!(state(&b), before);
    }
    // The same verdicts without building: `check` plans the grid only.
    let huge = with(|s| s.resolution = 1e-4);
    let e = LogPane::check(b.scans(), &huge).unwrap_err().to_string();
    assert!(
        e.contains("width x height") && e.contains("coarser resolution"),
        "{e}"
    );
    assert_eq!(
        LogPane::check(b.scans(), b.settings()).unwrap(),
        *b.grid().geometry()
    );
    assert!(b.seek(4).is_err(), "only 3 scans");
    assert_eq!(b.progress(), before.1);
    let empty = read_scans(&b"ODOM 0 0 0\n"[..]).unwrap();
    let e = LogPane::new(empty, LogMapSettings::default())
        .err()
        .unwrap();
    // (A pane holds format-neutral scans: the words are the core's; the
    // CARMEN reader's own refusal names FLASER and ROBOTLASER1.)
    assert!(e.to_string().contains("no laser scans"), "{e}");
}

#[test]
fn the_hover_readout_reads_the_cell_under_an_image_pixel() {
    let scans = read_scans(mixed_log().as_bytes()).unwrap();
    let mut b = LogPane::new(scans, LogMapSettings::default()).unwrap();
    b.advance(3);
    let geo = *b.grid().to_dense().unwrap().geometry();
    let top_left = b.readout_at_pixel(0, 0).unwrap();
    assert_eq!(
        (top_left.ix, top_left.iy),
        (0, geo.height() - 1),
        "north up"
    );
    assert!(b.readout_at_pixel(geo.width(), 0).is_none());
    assert!(b.readout_at_pixel(0, geo.height()).is_none());
    // The most-updated cell reads back its own log odds and count.
    let (i, &n) = b
        .grid()
        .to_dense()
        .unwrap()
        .update_counts()
        .iter()
        .enumerate()
        .max_by_key(|(_, &n)| n)
        .unwrap();
    let (ix, iy) = geo.cell_of_index(i);
    let r = b.readout_at_pixel(ix, geo.height() - 1 - iy).unwrap();
    assert_eq!((r.ix, r.iy, r.updates), (ix, iy, n));
    assert_eq!(r.l, b.grid().to_dense().unwrap().log_odds()[i] as f64);
    assert!((r.p - occgrid::grid::probability(r.l)).abs() < 1e-15);
    assert_eq!((r.x, r.y), geo.cell_center(ix, iy));
}
