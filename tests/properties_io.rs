#![cfg(not(target_arch = "wasm32"))]
//! Properties over what files bring in and take out: the CARMEN
//! log reader (random bytes, gzip-looking garbage, real log lines mutated
//! field by field, real gzip logs cut short), the chunked map build it
//! feeds, and the ROS `map_server` export.
//!
//! A damaged file must end in an [`OccError::Parse`] that names the line
//! that broke (and, for a laser line, the message and its field); a good
//! prefix must never yield a scan with a NaN in it; a refused setting must
//! leave the build exactly where it was.

mod properties_support;

use occgrid::apps::real_log::{LogMapSettings, LogPane};
use occgrid::geometry::GridGeometry;
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::io::carmen::{flaser_angle_increment, read_scans, LogLoader, LogReader};
use occgrid::io::map_server::{file_stem, map_server_pair, read_pgm, trinary_gray, zip_pair};
use occgrid::sensors::ScanLog;
use occgrid::OccError;
use properties_support::*;
use proptest::prelude::*;
use std::io::{Cursor, Read};
use std::path::PathBuf;
use std::sync::OnceLock;

fn datasets() -> PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into())
}

/// The compressed Intel log, as shipped.
fn intel_gz() -> &'static [u8] {
    static B: OnceLock<Vec<u8>> = OnceLock::new();
    B.get_or_init(|| {
        let path = datasets().join("intel-corrected.log.gz");
        std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
    })
}

/// The Intel log's first 1,000 lines (comments, parameters, odometry,
/// `NEFF` and about 70 laser lines), each with its newline.
fn intel_lines() -> &'static [String] {
    static L: OnceLock<Vec<String>> = OnceLock::new();
    L.get_or_init(|| {
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(intel_gz())
            .take(600_000)
            .read_to_string(&mut text)
            .unwrap();
        let lines: Vec<String> = text
            .split_inclusive('\n')
            .take(1000)
            .map(String::from)
            .collect();
        assert!(lines.iter().filter(|l| l.starts_with("FLASER")).count() > 40);
        lines
    })
}

fn laser_lines() -> Vec<&'static String> {
    intel_lines()
        .iter()
        .filter(|l| l.starts_with("FLASER"))
        .collect()
}

/// Ways to damage one line of a log.
#[derive(Debug, Clone)]
enum Damage {
    /// Replace whitespace-separated token `k` (mod the token count).
    Token(usize, String),
    /// Cut the line after this many bytes (mod its length).
    Cut(usize),
    /// Insert bytes at a position (mod its length).
    Insert(usize, Vec<u8>),
    /// Drop token `k`.
    Drop(usize),
}

fn token_text() -> impl Strategy<Value = String> {
    prop_oneof![
        wild_f64().prop_map(|v| format!("{v}")),
        prop::sample::select(vec![
            "nan",
            "NaN",
            "inf",
            "-inf",
            "infinity",
            "1e999",
            "-1",
            "-0",
            "0x10",
            "1,5",
            "",
            "ÿ",
            "3.",
            ".5",
            "+2",
            "1e-400",
            "9999999999",
            "10001",
            "181",
            "0.5e",
            "--1",
            "1_0",
        ])
        .prop_map(String::from),
        "[ -~]{0,12}",
    ]
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        4 => (any::<usize>(), token_text()).prop_map(|(k, t)| Damage::Token(k, t)),
        2 => any::<usize>().prop_map(Damage::Cut),
        2 => (any::<usize>(), prop::collection::vec(any::<u8>().prop_filter("one line", |b| *b != b'\n'), 1..6))
            .prop_map(|(k, b)| Damage::Insert(k, b)),
        1 => any::<usize>().prop_map(Damage::Drop),
    ]
}

fn apply(line: &str, d: &Damage) -> Vec<u8> {
    let body = line.trim_end_matches('\n');
    let mut tokens: Vec<&str> = body.split(' ').collect();
    let mut out: Vec<u8> = match d {
        Damage::Token(k, t) => {
            let k = k % tokens.len();
            tokens[k] = t;
            tokens.join(" ").into_bytes()
        }
        Damage::Drop(k) => {
            tokens.remove(k % tokens.len());
            tokens.join(" ").into_bytes()
        }
        Damage::Cut(k) => body.as_bytes()[..k % (body.len() + 1)].to_vec(),
        Damage::Insert(k, b) => {
            let mut v = body.as_bytes().to_vec();
            let at = k % (v.len() + 1);
            v.splice(at..at, b.iter().copied());
            v
        }
    };
    out.push(b'\n');
    out
}

/// A scan the reader let through must be kept whole and finite throughout.
#[track_caller]
fn assert_finite_scans(scans: &ScanLog) {
    for k in 0..scans.len() {
        let s = scans.scan(k).expect("every kept scan can be mapped");
        let p = s.pose();
        assert!(
            p.x.is_finite() && p.y.is_finite() && p.theta.is_finite(),
            "{p:?}"
        );
        assert!(s.ranges().iter().all(|r| r.is_finite() && *r >= 0.0));
        assert!(s.bearings().iter().all(|b| b.is_finite()));
    }
}

/// The map-build settings as the page sends them, each field anything.
fn wild_log_settings() -> impl Strategy<Value = LogMapSettings> {
    let d = LogMapSettings::default();
    (0usize..8, wild_f64()).prop_map(move |(k, v)| {
        let mut s = d;
        match k {
            0 => s.resolution = v,
            1 => s.range_cap = v,
            2 => s.alpha = v,
            3 => s.l_occ = v,
            4 => s.l_free = v,
            5 => s.clamp = v,
            6 => s.margin = v,
            _ => {}
        }
        s
    })
}

/// The names a refused map-build setting may carry: the page's own (the
/// serde names), and "width x height" for a grid too large to hold.
fn setting_names() -> Vec<&'static str> {
    let mut names = LogMapSettings::FIELDS.to_vec();
    names.push("width x height");
    names
}

proptest! {
    #![proptest_config(config(1024))]

    #[test]
    fn random_bytes_are_read_or_refused_with_a_line_number(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
        match read_scans(&bytes[..]) {
            Ok(log) => assert_finite_scans(&log),
            Err(OccError::Parse { line, reason }) => {
                let lines = bytes.iter().filter(|&&b| b == b'\n').count() + 1;
                prop_assert!((1..=lines).contains(&line), "line {line} of {lines}");
                prop_assert!(!reason.is_empty());
            }
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
        }
    }

    #[test]
    fn text_made_of_log_words_is_read_or_refused_naming_the_message(
        words in prop::collection::vec(
            prop_oneof![
                3 => prop::sample::select(vec!["FLASER", "ROBOTLASER1", "ODOM", "#", "PARAM", "\n", "\r\n", " "]).prop_map(String::from),
                4 => token_text(),
            ],
            0..60,
        ),
    ) {
        let text = words.join(" ");
        match read_scans(text.as_bytes()) {
            Ok(log) => assert_finite_scans(&log),
            Err(OccError::Parse { line, reason }) => {
                prop_assert!(line >= 1);
                prop_assert!(
                    ["FLASER", "ROBOTLASER1", "not a CARMEN log"].iter().any(|w| reason.contains(w)),
                    "{reason}"
                );
            }
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
        }
    }

    #[test]
    fn gzip_magic_followed_by_garbage_is_refused_as_a_damaged_file(
        tail in prop::collection::vec(any::<u8>(), 0..400),
    ) {
        let mut bytes = vec![0x1f, 0x8b];
        bytes.extend(tail);
        match read_scans(&bytes[..]) {
            Err(OccError::Parse { line, .. }) => prop_assert!(line >= 1),
            Ok(log) => assert_finite_scans(&log),
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
        }
    }

    #[test]
    fn a_damaged_real_laser_line_fails_on_its_own_line_or_reads_finite(
        before in 0usize..300, which in any::<prop::sample::Index>(), d in damage(),
    ) {
        let lines = intel_lines();
        let lasers = laser_lines();
        let target = which.get(&lasers);
        let mut file: Vec<u8> = lines[..before].concat().into_bytes();
        let bad_line = lines[..before].len() + 1;
        file.extend(apply(target, &d));
        file.extend(lines[before..before + 3].concat().into_bytes());
        match read_scans(&file[..]) {
            Ok(log) => {
                assert_finite_scans(&log);
                let most = lines[..before + 3].iter().filter(|l| l.starts_with("FLASER")).count() + 1;
                prop_assert!(log.len() <= most);
            }
            Err(OccError::Parse { line, reason }) => {
                prop_assert_eq!(line, bad_line, "{}", reason);
                prop_assert!(
                    ["FLASER", "not a CARMEN log", "ROBOTLASER1"].iter().any(|w| reason.contains(w)),
                    "{reason}"
                );
            }
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
        }
    }

    #[test]
    fn robot_laser_lines_with_any_numbers_are_read_finite_or_refused_by_field(
        fields in prop::collection::vec(prop_oneof![3 => -5.0..5.0f64, 1 => wild_f64()], 7),
        n in prop_oneof![3 => 1usize..6, 1 => wild_size()],
        ranges in prop::collection::vec(prop_oneof![3 => 0.0..10.0f64, 1 => wild_f64()], 0..6),
        m in 0usize..3,
        pose in prop::collection::vec(prop_oneof![3 => -5.0..5.0f64, 1 => wild_f64()], 6),
        tail in prop::option::of(Just(" 1.5 host 1.6")),
    ) {
        let num = |v: &f64| format!("{v}");
        let mut line = String::from("ROBOTLASER1 ");
        line += &fields.iter().map(num).collect::<Vec<_>>().join(" ");
        line += &format!(" {n} ");
        line += &ranges.iter().map(num).collect::<Vec<_>>().join(" ");
        line += &format!(" {m} ");
        line += &vec!["0.5"; m].join(" ");
        line += " ";
        line += &pose.iter().map(num).collect::<Vec<_>>().join(" ");
        line += &format!(" 0 0 0 0 0{}\n", tail.unwrap_or(""));
        match read_scans(line.as_bytes()) {
            Ok(log) => assert_finite_scans(&log),
            Err(OccError::Parse { line, reason }) => {
                prop_assert_eq!(line, 1);
                prop_assert!(reason.contains("ROBOTLASER1"), "{}", reason);
            }
            Err(other) => prop_assert!(false, "not a parse error: {other}"),
        }
    }

    #[test]
    fn laser_scan_accessors_answer_none_past_the_end_and_extents_stay_finite(
        scans in 0usize..6, k in wild_size(), cap in wild_f64(),
    ) {
        let lasers = laser_lines();
        let text: String = lasers[..scans].iter().map(|s| s.as_str()).collect();
        let read = read_scans(text.as_bytes()).unwrap();
        prop_assert_eq!(read.len(), scans);
        let inside = k < scans;
        prop_assert_eq!(read.scan(k).is_some(), inside);
        prop_assert_eq!(read.pose(k).is_some(), inside);
        prop_assert_eq!(read.origin(k).is_some(), inside);
        prop_assert_eq!(read.max_range(k).is_some(), inside);
        match read.endpoint_bounds(cap) {
            Some(b) => {
                prop_assert!(scans > 0);
                prop_assert!(b.iter().all(|v| v.is_finite()) && b[0] <= b[2] && b[1] <= b[3], "{b:?}");
            }
            None => prop_assert_eq!(scans, 0),
        }
    }

    #[test]
    fn flaser_angle_increments_are_finite_and_positive_for_any_count(n in wild_size()) {
        let a = flaser_angle_increment(n);
        prop_assert!(n == 0 || (a.is_finite() && a > 0.0), "{n}: {a}");
    }

    #[test]
    fn map_server_pairs_are_well_formed_for_any_image_name_and_read_back(
        w in 1usize..12, h in 1usize..12,
        evidence in prop::collection::vec(-6.0..6.0f32, 1..8),
        name in prop_oneof!["\\PC{0,20}", ".*", Just(String::new()), Just("../../etc/passwd".into())],
    ) {
        let g = GridGeometry::new(w, h, 0.05, -1.25, 3.5).unwrap();
        let mut grid = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        for i in 0..g.len() {
            let e = evidence[i % evidence.len()];
            if e.abs() > 0.5 { grid.apply(i, e); }
        }
        let pair = map_server_pair(&grid, &name);
        prop_assert!(pair.yaml.starts_with("image: "));
        prop_assert_eq!(pair.yaml.lines().count(), 7, "{}", pair.yaml);
        let pgm = read_pgm(&pair.pgm).unwrap();
        prop_assert_eq!((pgm.width, pgm.height), (w, h));
        for row in 0..h {
            for col in 0..w {
                let i = g.index(col, h - 1 - row);
                prop_assert_eq!(pgm.at(col, row), Some(trinary_gray(grid.model(), grid.log_odds()[i])));
            }
        }
        let stem = file_stem(&name);
        prop_assert!(!stem.is_empty() && !stem.starts_with('.') && stem.chars().count() <= 100);
        prop_assert!(stem.chars().all(|c| c.is_ascii_alphanumeric() || "._-".contains(c)), "{stem}");
        let (file, zip) = zip_pair(&pair, &name);
        prop_assert!(file.ends_with(".zip"));
        prop_assert_eq!(&zip[..4], b"PK\x03\x04");
        prop_assert_eq!(&zip[zip.len() - 22..zip.len() - 18], b"PK\x05\x06");
    }

    #[test]
    fn pgm_reading_refuses_damaged_files_by_line_without_panicking(
        cut in any::<usize>(), flips in prop::collection::vec((any::<usize>(), any::<u8>()), 0..4),
        garbage in prop::collection::vec(any::<u8>(), 0..80),
    ) {
        let g = GridGeometry::new(5, 4, 0.1, 0.0, 0.0).unwrap();
        let grid = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        let mut bytes = map_server_pair(&grid, "m.pgm").pgm;
        for (at, b) in &flips {
            let n = bytes.len();
            bytes[at % n] = *b;
        }
        bytes.truncate(cut % (bytes.len() + 1));
        for input in [&bytes[..], &garbage[..]] {
            match read_pgm(input) {
                Ok(p) => prop_assert_eq!(p.pixels.len(), p.width * p.height),
                Err(e) => prop_assert!(matches!(e, OccError::Parse { line, .. } if line >= 1), "{e}"),
            }
        }
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn the_map_build_refuses_bad_settings_and_scrubs_without_a_trace(
        scans in 1usize..25, chunk in wild_size(),
        first in wild_log_settings(), second in wild_log_settings(), seek in wild_size(),
    ) {
        let lasers = laser_lines();
        let text: String = lasers[..scans.min(lasers.len())].iter().map(|s| s.as_str()).collect();
        let mut loader = LogLoader::new(Cursor::new(text.into_bytes()));
        let mut last = 0;
        while !loader.is_finished() {
            let p = loader.read(chunk.min(7)).unwrap();
            prop_assert!(p.scans >= last);
            last = p.scans;
        }
        let scans_read = loader.into_scans();
        let mut build = match LogPane::new(scans_read, first) {
            Ok(b) => b,
            Err(e) => {
                assert_names_one_of(&e, &setting_names());
                return Ok(());
            }
        };
        let p = build.advance(chunk);
        prop_assert!(p.scans_done <= p.scans_total);
        let c = build.grid().to_dense().unwrap().clamp();
        prop_assert!(build.grid().to_dense().unwrap().log_odds().iter().all(|l| l.is_finite() && l.abs() <= c));
        let state = |b: &LogPane| (b.grid().to_dense().unwrap().clone(), b.progress(), *b.settings());
        let before = state(&build);
        match build.seek(seek) {
            Ok(()) => prop_assert!(seek <= build.scans().len()),
            Err(e) => {
                assert_names(&e, "scan");
                prop_assert!(state(&build) == before, "a refused seek changed the build");
            }
        }
        let before = state(&build);
        match build.configure(second) {
            Ok(()) => {
                build.advance(usize::MAX);
                let c = build.grid().to_dense().unwrap().clamp();
                prop_assert!(build.grid().to_dense().unwrap().log_odds().iter().all(|l| l.is_finite() && l.abs() <= c));
            }
            Err(e) => {
                assert_names_one_of(&e, &setting_names());
                prop_assert!(state(&build) == before, "a refused configure changed the build");
            }
        }
        let g = *build.grid().to_dense().unwrap().geometry();
        prop_assert!(build.readout_at_pixel(g.width(), 0).is_none());
        prop_assert!(build.readout_at_pixel(usize::MAX, usize::MAX).is_none());
        prop_assert!(build.path_in_pixels().iter().all(|v| v.is_finite()));
    }
}

proptest! {
    #![proptest_config(config(16))]

    #[test]
    fn a_real_gzip_log_cut_short_keeps_its_scans_or_fails_as_a_compressed_file_that_ends_early(
        cut in prop_oneof![3 => 0usize..60_000, 1 => 0usize..448_366],
    ) {
        let gz = intel_gz();
        let cut = cut.min(gz.len() - 1);
        let mut reader = LogReader::new(&gz[..cut]);
        let mut scans = 0usize;
        let err = loop {
            match reader.next_record() {
                Ok(Some(r)) => {
                    prop_assert!(r.to_scan().is_ok());
                    scans += 1;
                }
                Ok(None) => break None,
                Err(e) => break Some(e),
            }
        };
        match err {
            Some(OccError::Parse { line, reason }) => {
                prop_assert!(line >= 1);
                prop_assert!(reason.contains("compressed"), "line {line}: {reason}");
                // The reader stays failed: no clean end over half a log.
                prop_assert!(reader.next_record().is_err());
            }
            // Cut after a complete scan: the scans before the cut are kept,
            // with a warning naming the line.
            None if scans > 0 => {
                let w = reader.warning().unwrap_or_default().to_string();
                prop_assert!(w.starts_with("line ") && w.contains("ends early"), "{w}");
                prop_assert!(w.contains(&format!("the {scans} complete scan")), "{w}");
            }
            other => prop_assert!(cut < 2 && other.is_none() && scans == 0, "{other:?} after {scans} scans"),
        }
    }
}

/// A resolution of `f64::MAX` metres per cell puts the map's corners past
/// f64: the page sent a resolution, and the message says so.
#[test]
fn an_absurd_map_resolution_is_refused_under_its_own_name() {
    let lasers = laser_lines();
    let text: String = lasers[..3].iter().map(|s| s.as_str()).collect();
    let scans = read_scans(text.as_bytes()).unwrap();
    for resolution in [f64::MAX, 1e300] {
        let settings = LogMapSettings {
            resolution,
            ..LogMapSettings::default()
        };
        let e = LogPane::check(&scans, &settings).unwrap_err();
        assert!(
            matches!(&e, OccError::InvalidParameter { field, .. } if field == "resolution"),
            "{e}"
        );
        assert!(e.to_string().contains(&format!("{resolution:e}")), "{e}");
    }
    // Cells so small that both edges of the extent overflow: too many cells,
    // not a map of zero width.
    let settings = LogMapSettings {
        resolution: 1e-320,
        ..LogMapSettings::default()
    };
    let e = LogPane::check(&scans, &settings).unwrap_err();
    assert_names(&e, "width x height");
}

/// Evidence past f32 is refused under the names the page sent (`lOcc`,
/// `lFree`), not under the Table 9.2 model's own (`l_occ`, `l_free`).
#[test]
fn map_build_model_errors_carry_the_pages_field_names() {
    let lasers = laser_lines();
    let text: String = lasers[..3].iter().map(|s| s.as_str()).collect();
    let scans = read_scans(text.as_bytes()).unwrap();
    let cases = [
        (
            LogMapSettings {
                l_occ: 1e39,
                ..LogMapSettings::default()
            },
            "lOcc",
        ),
        (
            LogMapSettings {
                l_free: -1e39,
                ..LogMapSettings::default()
            },
            "lFree",
        ),
    ];
    for (settings, name) in cases {
        let e = LogPane::check(&scans, &settings).unwrap_err();
        assert!(
            matches!(&e, OccError::InvalidParameter { field, .. } if field == name),
            "{e} should be under {name}"
        );
    }
}
