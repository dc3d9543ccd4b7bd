#![cfg(not(target_arch = "wasm32"))]
//! Scan matching on real and built logs: a known offset of an Intel scan
//! recovered against the map of the other scans, the matched path of a
//! real log against its dead reckoning, one seed one path bit for bit,
//! bad parameters refused by name, a featureless corridor that only
//! the odometry can place along its length, and the panel's scan-matched
//! pane (built in slices, deterministic, from a raw log's own odometry).

use occgrid::apps::real_log::{LogCellModel, LogMapSettings, RealLogSession};
use occgrid::geometry::{wrap_angle, GridGeometry, Pose};
use occgrid::grid::TiledGrid;
use occgrid::inverse::HandCraftedParams;
use occgrid::io::carmen::read_scans;
use occgrid::mapping::insertion::{ScanInserter, ScanInsertion};
use occgrid::mapping::reach::covering_grid;
use occgrid::mapping::scan_match::{
    compose, relative_motion, MatchSettings, Prediction, ScanMatcher,
};
use occgrid::poses::MatchedPath;
use occgrid::poses::PoseSourceKind;
use occgrid::sensors::odometry::OdometryParams;
use occgrid::sensors::Scan;
use occgrid::sensors::ScanLog;
use occgrid::OccError;
use std::path::PathBuf;

mod scan_match_support;
use scan_match_support::{distance, grid, scans, turn};

/// The real-log map's recipe at the real-log defaults, beam by beam (the
/// space between beams left to the beams).
fn insertion() -> ScanInsertion {
    ScanInsertion {
        between_beams: false,
        ..LogMapSettings::default().scan_insertion()
    }
}

/// A map wide enough for the log at its corrected poses and at `extra`
/// (a dead-reckoned path), plus a few metres of drift.
fn grid_for(log: &ScanLog, extra: &[Pose]) -> TiledGrid {
    let s = LogMapSettings::default();
    let mut placed = log.clone();
    placed.set_poses(extra).unwrap();
    let [a, b] = [
        log.endpoint_bounds(s.range_cap).unwrap(),
        placed.endpoint_bounds(s.range_cap).unwrap(),
    ];
    let extent = [
        a[0].min(b[0]) - 5.0,
        a[1].min(b[1]) - 5.0,
        a[2].max(b[2]) + 5.0,
        a[3].max(b[3]) + 5.0,
    ];
    grid(covering_grid(extent, s.resolution, s.margin).unwrap())
}

/// Three Intel scans, each moved 0.15 m and 0.1 m and turned 3° one way
/// and then the other, come back when matched against the map of all the
/// other scans at their corrected poses: to within a centimetre and a
/// tenth of a degree of where the same match started at the corrected
/// pose puts them, and within 5 cm and 0.6° of the corrected pose
/// (the corrected poses themselves are that far from the best fit of one
/// scan to the others).
#[test]
fn a_known_offset_of_an_intel_scan_is_recovered_against_the_other_scans() {
    let log = scans("intel-corrected.log.gz");
    let picked = [150, 450, 750];
    let mut map = grid_for(&log, log.poses());
    let mut inserter = ScanInserter::new(insertion()).unwrap();
    for k in (0..log.len()).filter(|k| !picked.contains(k)) {
        inserter.insert(&mut map, &log.scan(k).unwrap(), log.max_range(k).unwrap());
    }
    let mut matcher = ScanMatcher::new(MatchSettings::default()).unwrap();
    for k in picked {
        let truth = log.pose(k).unwrap();
        let scan = log.scan(k).unwrap();
        let laser_max = log.max_range(k).unwrap();
        let mut from = |pose: Pose| {
            // A prediction known only to a metre and 20°: the pose kept is
            // the fit's (to a fraction of a millimetre).
            let prediction = Prediction {
                pose,
                position_spread: 1.0,
                heading_spread: 20f64.to_radians(),
            };
            matcher
                .match_scan(&map, &scan, laser_max, &prediction)
                .unwrap()
        };
        // Where the fit itself puts the scan: the corrected poses are a
        // few centimetres from the best fit of each scan to the others.
        let own = from(truth);
        for sign in [1.0, -1.0] {
            let offset = Pose {
                x: truth.x + sign * 0.15,
                y: truth.y + sign * 0.10,
                theta: truth.theta + sign * 3f64.to_radians(),
            };
            let r = from(offset);
            assert!(r.accepted, "scan {k}: {r:?}");
            assert!(r.score > r.predicted_score);
            let (d, t) = (distance(&r.pose, &own.pose), turn(&r.pose, &own.pose));
            assert!(
                d < 0.01 && t < 0.1f64.to_radians(),
                "scan {k} from {sign:+} offset: {d:.4} m, {:.3} deg from the fit's own pose",
                t.to_degrees()
            );
            let (d, t) = (distance(&r.pose, &truth), turn(&r.pose, &truth));
            assert!(
                d < 0.05 && t < 0.6f64.to_radians(),
                "scan {k} from {sign:+} offset: {d:.4} m, {:.3} deg from the corrected pose",
                t.to_degrees()
            );
        }
    }
}

/// The first 300 scans of the Intel log (184 m of driving): seeded dead reckoning wanders 30 m away, the
/// matched path stays within half a metre of the corrected poses all
/// along (12 cm on average; its start is the log's, and nothing closes
/// its loops), and its heading error between consecutive scans is less
/// than half the odometry's.
#[test]
fn the_matched_path_of_a_real_log_stays_near_the_corrected_poses() {
    let log = scans("intel-corrected.log.gz");
    let n = 300;
    let truth = log.poses()[..n].to_vec();
    let dr = OdometryParams::WHEELS.dead_reckon_path(&truth, 1);
    let mut whole = OdometryParams::WHEELS.dead_reckon_path(log.poses(), 1);
    whole[..n].copy_from_slice(&dr);
    let mut path = MatchedPath::new(
        grid_for(&log, &whole),
        dr.clone(),
        OdometryParams::WHEELS,
        MatchSettings::default(),
        insertion(),
    )
    .unwrap();
    for k in 0..n {
        path.step(&log.scan(k).unwrap(), log.max_range(k).unwrap())
            .unwrap();
    }
    assert!(path.is_finished());
    let matched = path.poses();
    let worst = |poses: &[Pose]| {
        poses
            .iter()
            .zip(&truth)
            .map(|(a, b)| distance(a, b))
            .fold(0.0, f64::max)
    };
    let step_error = |poses: &[Pose]| {
        (1..n)
            .map(|k| {
                let (a, b) = (
                    relative_motion(&poses[k - 1], &poses[k]),
                    relative_motion(&truth[k - 1], &truth[k]),
                );
                wrap_angle(a[2] - b[2]).abs()
            })
            .sum::<f64>()
            / (n - 1) as f64
    };
    let mean = |poses: &[Pose]| {
        poses
            .iter()
            .zip(&truth)
            .map(|(a, b)| distance(a, b))
            .sum::<f64>()
            / n as f64
    };
    assert!(worst(&dr) > 10.0, "dead reckoning {:.2} m off", worst(&dr));
    assert!(worst(matched) < 0.5, "matched {:.3} m off", worst(matched));
    assert!(mean(matched) < 0.2, "matched {:.3} m off", mean(matched));
    assert!(
        step_error(matched) < 0.5 * step_error(&dr),
        "heading error per step: matched {:.3} deg, dead reckoning {:.3} deg",
        step_error(matched).to_degrees(),
        step_error(&dr).to_degrees()
    );
}

/// Two paths from the same seed give the same poses and the same map,
/// bit for bit; another seed, another path.
#[test]
fn one_seed_one_matched_path_bit_for_bit() {
    let log = scans("aces-corrected.log.gz");
    let n = 120;
    let run = |seed: u64| {
        let truth = log.poses().to_vec();
        let dr = OdometryParams::WHEELS.dead_reckon_path(&truth, seed);
        let mut path = MatchedPath::new(
            grid_for(&log, &dr),
            dr,
            OdometryParams::WHEELS,
            MatchSettings::default(),
            insertion(),
        )
        .unwrap();
        for k in 0..n {
            path.step(&log.scan(k).unwrap(), log.max_range(k).unwrap())
                .unwrap();
        }
        path
    };
    let bits = |p: &MatchedPath| -> Vec<[u64; 3]> {
        p.poses()
            .iter()
            .map(|q| [q.x.to_bits(), q.y.to_bits(), q.theta.to_bits()])
            .collect()
    };
    let (a, b) = (run(7), run(7));
    assert_eq!(bits(&a), bits(&b));
    assert!(a.grid() == b.grid(), "the same map, cell for cell");
    assert_ne!(bits(&a), bits(&run(8)));
}

fn expect_invalid(e: OccError, field: &str, value: &str) {
    let text = e.to_string();
    assert!(
        text.starts_with(&format!("invalid {field}: {value}")),
        "{field}: {text}"
    );
}

/// Every field of the settings is checked and named as a page spells
/// it, with the value it was given; a misspelt field is refused by name.
#[test]
fn bad_settings_are_refused_naming_the_field_and_the_value() {
    let d = MatchSettings::default();
    let cases: Vec<(MatchSettings, &str, &str)> = vec![
        (
            MatchSettings {
                linear_window: -0.1,
                ..d
            },
            "linearWindow",
            "-0.1",
        ),
        (
            MatchSettings {
                angular_window: 4.0,
                ..d
            },
            "angularWindow",
            "4",
        ),
        (
            MatchSettings {
                window_spreads: f64::NAN,
                ..d
            },
            "windowSpreads",
            "NaN",
        ),
        (
            MatchSettings {
                max_linear_window: 0.2,
                ..d
            },
            "maxLinearWindow",
            "0.2",
        ),
        (
            MatchSettings {
                max_angular_window: 3.5,
                ..d
            },
            "maxAngularWindow",
            "3.5",
        ),
        (
            MatchSettings {
                max_angular_window: 0.1,
                ..d
            },
            "maxAngularWindow",
            "0.1",
        ),
        (
            MatchSettings {
                angular_step: 0.0,
                ..d
            },
            "angularStep",
            "0",
        ),
        (MatchSettings { hypotheses: 0, ..d }, "hypotheses", "0"),
        (
            MatchSettings {
                coarse_factor: 3,
                ..d
            },
            "coarseFactor",
            "3",
        ),
        (
            MatchSettings {
                coarse_factor: 1,
                ..d
            },
            "coarseFactor",
            "1",
        ),
        (
            MatchSettings {
                max_iterations: 1000,
                ..d
            },
            "maxIterations",
            "1000",
        ),
        (
            MatchSettings {
                min_range: f64::NAN,
                ..d
            },
            "minRange",
            "NaN",
        ),
        (
            MatchSettings {
                max_range: 0.05,
                ..d
            },
            "maxRange",
            "0.05",
        ),
        (MatchSettings { max_points: 0, ..d }, "maxPoints", "0"),
        (
            MatchSettings {
                max_points: 5000,
                ..d
            },
            "maxPoints",
            "5000",
        ),
        (
            MatchSettings {
                min_position_spread: 0.0,
                ..d
            },
            "minPositionSpread",
            "0",
        ),
        (
            MatchSettings {
                min_heading_spread: f64::INFINITY,
                ..d
            },
            "minHeadingSpread",
            "inf",
        ),
        (
            MatchSettings {
                refine_translation_weight: -1.0,
                ..d
            },
            "refineTranslationWeight",
            "-1",
        ),
        (
            MatchSettings {
                refine_rotation_weight: f64::NAN,
                ..d
            },
            "refineRotationWeight",
            "NaN",
        ),
        (
            MatchSettings {
                min_overlap: 1.5,
                ..d
            },
            "minOverlap",
            "1.5",
        ),
        (
            MatchSettings {
                min_score: -0.5,
                ..d
            },
            "minScore",
            "-0.5",
        ),
        (
            MatchSettings {
                fit_position_spread: -1.0,
                ..d
            },
            "fitPositionSpread",
            "-1",
        ),
        (
            MatchSettings {
                fit_heading_spread: 0.0,
                ..d
            },
            "fitHeadingSpread",
            "0",
        ),
    ];
    for (settings, field, value) in cases {
        expect_invalid(settings.validate().unwrap_err(), field, value);
        expect_invalid(ScanMatcher::new(settings).unwrap_err(), field, value);
    }
    // The search's size depends on the map's cells: bounded before work.
    let fine = MatchSettings {
        angular_step: 1e-4,
        ..d
    };
    assert!(fine.validate().is_ok());
    expect_invalid(
        fine.validate_for(0.05).unwrap_err(),
        "angularStep",
        "0.0001",
    );
    expect_invalid(d.validate_for(0.001).unwrap_err(), "maxRange", "30");
    expect_invalid(d.validate_for(-1.0).unwrap_err(), "resolution", "-1");
    let e = serde_json::from_str::<MatchSettings>(r#"{"linearWindw": 0.2}"#).unwrap_err();
    assert!(e.to_string().contains("linearWindw"), "{e}");
    let parsed: MatchSettings = serde_json::from_str(r#"{"hypotheses": 5}"#).unwrap();
    assert_eq!(parsed, MatchSettings { hypotheses: 5, ..d });
}

/// A path refuses a bad odometry pose, bad odometry noise, an insertion
/// model and a laser range by name; a step past the last scan is an error
/// that leaves the path as it was.
#[test]
fn a_path_refuses_bad_inputs_and_stays_as_it_was() {
    let g = || grid(GridGeometry::sparse(200, 200, 0.05, -5.0, -5.0).unwrap());
    let start = Pose::default();
    let mut odometry = vec![start; 4];
    odometry[2].theta = f64::NAN;
    let d = MatchSettings::default();
    let w = OdometryParams::WHEELS;
    let e = MatchedPath::new(g(), odometry, w, d, insertion()).unwrap_err();
    expect_invalid(e, "odometry[2]", "(0, 0, NaN)");
    let noisy = OdometryParams {
        turn_scale: 2.0,
        ..w
    };
    let e = MatchedPath::new(g(), vec![start; 2], noisy, d, insertion()).unwrap_err();
    expect_invalid(e, "odometry.turn_scale", "2");
    let bad_model = ScanInsertion {
        no_return_reach: 0.0,
        ..insertion()
    };
    let e = MatchedPath::new(g(), vec![start; 2], w, d, bad_model).unwrap_err();
    expect_invalid(e, "no_return_reach", "0");
    let wide = ScanInsertion {
        model: HandCraftedParams {
            z_max: 500.0,
            ..insertion().model
        },
        ..insertion()
    };
    let e = MatchedPath::new(g(), vec![start; 2], w, d, wide).unwrap_err();
    expect_invalid(e, "z_max", "500");

    let scan = Scan::uniform(start, vec![2.0; 90], -1.5, 3f64.to_radians()).unwrap();
    let mut path = MatchedPath::new(g(), vec![start; 2], w, d, insertion()).unwrap();
    expect_invalid(path.step(&scan, f64::NAN).unwrap_err(), "laser_max", "NaN");
    assert_eq!(path.next_scan(), 0);
    path.step(&scan, f64::INFINITY).unwrap();
    path.step(&scan, f64::INFINITY).unwrap();
    let (poses, map) = (path.poses().to_vec(), path.grid().clone());
    let e = path.step(&scan, f64::INFINITY).unwrap_err();
    assert_eq!(e.to_string(), "all 2 scans of the path are matched");
    assert_eq!(path.poses(), &poses[..]);
    assert!(path.grid() == &map);
    path.reset();
    assert_eq!((path.next_scan(), path.grid().tiles_allocated()), (0, 0));
}

/// The ranges a 180-beam laser at `pose` reads in a straight corridor
/// between the walls `y = -1` and `y = 1`, open at both ends (beams that
/// meet no wall within 30 m are no-returns, read at 81.9 m as in the
/// corpus).
fn corridor_scan(pose: Pose) -> Scan {
    let step = std::f64::consts::PI / 180.0;
    let ranges = (0..180)
        .map(|i| {
            let a = pose.theta - std::f64::consts::FRAC_PI_2 + i as f64 * step;
            let s = a.sin();
            let wall = if s > 0.0 { 1.0 } else { -1.0 };
            let r = (wall - pose.y) / s;
            if r.is_finite() && r > 0.0 && r < 30.0 {
                r
            } else {
                81.9
            }
        })
        .collect();
    Scan::uniform(pose, ranges, -std::f64::consts::FRAC_PI_2, step).unwrap()
}

/// Down a straight, featureless corridor the map pins the heading and the
/// distance to the walls but says nothing about how far along the robot
/// is: the matched path keeps the first two to half a degree and a few
/// centimetres at every scan (dead reckoning ends a metre off to the
/// side), and along the corridor stays with the odometry's increments
/// (their errors summed) instead of sliding.
#[test]
fn a_featureless_corridor_keeps_heading_and_walls_and_follows_the_odometry_along_it() {
    let truth: Vec<Pose> = (0..40)
        .map(|k| Pose {
            x: k as f64,
            y: 0.2 * (k as f64 * 0.3).sin(),
            theta: 0.05 * (k as f64 * 0.5).cos(),
        })
        .collect();
    let dr = OdometryParams::WHEELS.dead_reckon_path(&truth, 3);
    let map = grid(GridGeometry::sparse(1400, 200, 0.05, -10.0, -5.0).unwrap());
    let mut path = MatchedPath::new(
        map,
        dr.clone(),
        OdometryParams::WHEELS,
        MatchSettings::default(),
        insertion(),
    )
    .unwrap();
    let laser_max = 81.9;
    for p in &truth {
        path.step(&corridor_scan(*p), laser_max).unwrap();
    }
    let (mut along, mut across) = (0f64, 0f64);
    for (k, (m, t)) in path.poses().iter().zip(&truth).enumerate() {
        assert!(m.x.is_finite() && m.y.is_finite() && m.theta.is_finite());
        assert!((m.y - t.y).abs() < 0.06, "scan {k}: {m:?} against {t:?}");
        assert!(turn(m, t) < 0.5f64.to_radians(), "scan {k}: {m:?}");
        along = along.max((m.x - t.x).abs());
        across += (m.y - t.y).abs() / truth.len() as f64;
    }
    eprintln!("along {along} across {across}");
    // The odometry's own lateral error, for scale: the path keeps half of
    // each step's (the pose kept weighs fit and prediction alike).
    let dr_across = dr
        .iter()
        .zip(&truth)
        .map(|(m, t)| (m.y - t.y).abs())
        .sum::<f64>()
        / truth.len() as f64;
    eprintln!("dr across {dr_across}");
    // The odometry's own distance error over the corridor, for scale.
    let odometry_error = (1..truth.len())
        .map(|k| {
            let (a, b) = (
                relative_motion(&dr[k - 1], &dr[k]),
                relative_motion(&truth[k - 1], &truth[k]),
            );
            (a[0] - b[0]).abs()
        })
        .sum::<f64>();
    assert!(
        along <= odometry_error + 0.1,
        "{along:.3} m along the corridor, odometry {odometry_error:.3} m"
    );
    // A scan that sees nothing at all is put where it was predicted.
    let blind = Scan::uniform(truth[5], vec![81.9; 180], -1.5, 0.01).unwrap();
    let mut matcher = ScanMatcher::new(MatchSettings::default()).unwrap();
    let at = compose(&truth[5], [0.1, 0.0, 0.0]);
    let r = matcher
        .match_scan(
            path.grid(),
            &blind,
            laser_max,
            &Prediction::at(at, &MatchSettings::default()),
        )
        .unwrap();
    assert!(!r.accepted && r.pose == at && r.points == 0, "{r:?}");
    // Nor is a scan predicted absurdly far from the map moved (and its
    // cells are not looked for).
    let far = Pose {
        x: 1e300,
        y: -1e300,
        theta: 0.3,
    };
    let r = matcher
        .match_scan(
            path.grid(),
            &corridor_scan(truth[5]),
            laser_max,
            &Prediction::at(far, &MatchSettings::default()),
        )
        .unwrap();
    assert!(!r.accepted && r.pose == far && r.points > 0, "{r:?}");
}

/// The first `n` laser lines of a log of the datasets folder, as text.
fn first_scans(name: &str, n: usize) -> Vec<u8> {
    use std::io::Read;
    let dir: PathBuf = std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/datasets").into());
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(dir.join(name)).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("FLASER"))
        .take(n)
        .collect();
    (lines.join("\n") + "\n").into_bytes()
}

/// A session over `bytes` at `settings`, read to the end.
fn session_of(bytes: Vec<u8>, settings: LogMapSettings) -> RealLogSession {
    let mut s = RealLogSession::new(bytes);
    s.configure(settings).unwrap();
    while !s.read(1 << 20).unwrap().progress.finished {}
    s
}

fn pose_bits(poses: &[Pose]) -> Vec<[u64; 3]> {
    poses
        .iter()
        .map(|q| [q.x.to_bits(), q.y.to_bits(), q.theta.to_bits()])
        .collect()
}

/// Scan-matched settings whose map is the one the core's matched path
/// keeps (Table 9.2's log odds, no floor between beams), so that the two
/// can be compared cell for cell.
fn scan_matched(seed: u64) -> LogMapSettings {
    LogMapSettings {
        poses: PoseSourceKind::ScanMatched,
        seed,
        model: LogCellModel::LogOdds,
        between_beams: false,
        ..LogMapSettings::default()
    }
}

/// The panel's scan-matched pane: beside it the corrected and the
/// dead-reckoned maps (the same seed); built in slices whose budget counts
/// the matching too, it finds the poses the core's matched path finds on
/// the same grid, bit for bit, maps there, and says so in its export and
/// its `poses.tsv`.
#[test]
fn a_session_s_scan_matched_pane_is_the_matched_path_built_in_slices() {
    let n = 150;
    let bytes = first_scans("intel-corrected.log.gz", n);
    let mut session = session_of(bytes.clone(), scan_matched(3));
    let sources: Vec<PoseSourceKind> = session.panes().iter().map(|p| p.source()).collect();
    assert_eq!(
        sources,
        [
            PoseSourceKind::ScanMatched,
            PoseSourceKind::Corrected,
            PoseSourceKind::DeadReckoning
        ]
    );
    assert_eq!(
        session.state().panes[0].caption,
        "Scan-matched (from dead reckoning, seed 3)"
    );
    let budget = 200_000;
    let mut slices = 0;
    let mut last = session.state();
    let mut most_per_scan = 0u64;
    while !last.finished {
        let next = session.build_slice(budget).unwrap();
        let did = next.work - last.work;
        let scans = (next.scans_done - last.scans_done).max(1) as u64;
        most_per_scan = most_per_scan.max(did / scans);
        // A slice stops at the scan that reaches its budget: it does less
        // than the budget plus one scan of each pane.
        assert!(did < budget + 3 * 2_000_000, "slice {slices}: {did}");
        assert!(next.work >= next.cell_updates);
        slices += 1;
        last = next;
        assert!(slices < 10 * n, "the build ends");
    }
    assert!(slices > 3, "{slices} slices");
    let pane = &session.panes()[0];
    assert!(
        pane.progress().work > pane.progress().cell_updates,
        "matching counted"
    );
    // The same matcher on the same grid outside the session.
    let log = read_scans(&bytes[..]).unwrap();
    let odometry = pane.matched_odometry().unwrap().to_vec();
    assert_eq!(
        odometry,
        OdometryParams::WHEELS.dead_reckon_path(log.poses(), 3),
        "a corrected log's odometry fields repeat its poses: dead reckoning is the start"
    );
    let settings = scan_matched(3);
    let mut path = MatchedPath::new(
        grid(*pane.grid().geometry()),
        odometry,
        OdometryParams::WHEELS,
        occgrid::poses::match_settings(settings.range_cap),
        settings.scan_insertion(),
    )
    .unwrap();
    for k in 0..n {
        path.step(&log.scan(k).unwrap(), log.max_range(k).unwrap())
            .unwrap();
    }
    assert_eq!(pose_bits(pane.poses()), pose_bits(path.poses()));
    assert!(
        pane.grid().to_dense().unwrap() == path.grid().to_dense().unwrap(),
        "the same map, cell for cell"
    );
    // Its poses as a file, every number read back bit for bit.
    let tsv = pane.poses_tsv();
    let read: Vec<Pose> = tsv
        .lines()
        .enumerate()
        .map(|(k, line)| {
            let t: Vec<&str> = line.split(' ').collect();
            assert_eq!(t[0], k.to_string());
            Pose {
                x: t[1].parse().unwrap(),
                y: t[2].parse().unwrap(),
                theta: t[3].parse().unwrap(),
            }
        })
        .collect();
    assert_eq!(pose_bits(&read), pose_bits(path.poses()));
    let yaml = pane.export_map(Some("m")).yaml;
    assert!(yaml.contains("\n# poses: scan-matched (seed 3)"), "{yaml}");
    assert_eq!(pane.export_stem("intel.log.gz"), "intel-scan-matched-map");
    // The last match is there to draw: its scan's points at its pose.
    let view = pane.match_view().unwrap();
    assert_eq!(view.scan, n - 1);
    assert!(view.points.len() > 100 && view.points.len().is_multiple_of(2));
    assert!(session.panes()[1].match_view().is_none());
}

/// One seed, one scan-matched map, bit for bit (also after scrubbing back
/// and building again); another seed, other poses.
#[test]
fn one_seed_one_scan_matched_pane_bit_for_bit_and_after_a_scrub() {
    let bytes = first_scans("aces-corrected.log.gz", 100);
    let build = |seed: u64| {
        let mut s = session_of(bytes.clone(), scan_matched(seed));
        while !s.build_slice(500_000).unwrap().finished {}
        s
    };
    let (mut a, b) = (build(5), build(5));
    let (pa, pb) = (&a.panes()[0], &b.panes()[0]);
    assert_eq!(pose_bits(pa.poses()), pose_bits(pb.poses()));
    assert!(pa.grid().to_dense().unwrap() == pb.grid().to_dense().unwrap());
    assert_eq!(pa.poses_tsv(), pb.poses_tsv());
    let (poses, map) = (pa.poses().to_vec(), pa.grid().to_dense().unwrap());
    a.seek(40).unwrap();
    assert_eq!(a.panes()[0].progress().work, 0, "going back starts again");
    while !a.build_slice(500_000).unwrap().finished {}
    assert_eq!(a.panes()[0].poses_tsv().lines().count(), 40);
    a.seek(100).unwrap();
    while !a.build_slice(500_000).unwrap().finished {}
    assert_eq!(pose_bits(a.panes()[0].poses()), pose_bits(&poses));
    assert!(a.panes()[0].grid().to_dense().unwrap() == map);
    assert_ne!(pose_bits(build(6).panes()[0].poses()), pose_bits(&poses));
}

/// A raw log, whose odometry fields differ from its laser poses, is
/// matched from its own odometry, not from dead reckoning made up; an
/// unknown pose source is refused by name and changes nothing.
#[test]
fn a_raw_log_is_matched_from_its_own_odometry_and_a_bad_source_is_refused() {
    let mut text = String::new();
    for k in 0..8 {
        let (x, odom) = (k as f64 * 0.2, k as f64 * 0.21 + 10.0);
        text.push_str(&format!(
            "FLASER 4 1.0 1.5 2.0 2.5 {x} 0.0 0.1 {odom} -1.0 0.2 0 h 0\n"
        ));
    }
    let mut s = session_of(text.clone().into_bytes(), scan_matched(1));
    while !s.build_slice(u64::MAX).unwrap().finished {}
    let odometry = s.panes()[0].matched_odometry().unwrap();
    assert_eq!(odometry.len(), 8);
    assert_eq!(
        odometry[3],
        Pose {
            x: 3.0 * 0.21 + 10.0,
            y: -1.0,
            theta: 0.2
        }
    );
    // The path starts where the odometry does.
    assert_eq!(s.panes()[0].poses()[0], odometry[0]);
    let bad: Result<LogMapSettings, _> = serde_json::from_str(r#"{"poses": "scan-match"}"#);
    let e = bad.unwrap_err().to_string();
    assert!(
        e.contains("scan-match") && e.contains("scan-matched"),
        "{e}"
    );
    let before = s.state();
    let e = s
        .configure(LogMapSettings {
            resolution: -1.0,
            ..scan_matched(1)
        })
        .unwrap_err();
    expect_invalid(e, "resolution", "-1");
    assert_eq!(s.state(), before);
}
