#![cfg(not(target_arch = "wasm32"))]
//! ROS 2 bags written by the tests themselves: each compression, either
//! byte order, a tf chain, a yawed mount, other topic names, a summary or
//! none map each scan at the odometry interpolated at its stamp, moved by
//! the mount; topic choice, REP 117 ranges and scans without odometry.

mod bag_support;

use bag_support::{robot_bag, BagSpec, Compression};
use occgrid::geometry::wrap_angle;
use occgrid::io::{open_log, read_log, LogBudget, LogFormat};
use occgrid::poses::{PoseSourceKind, SourceSettings};
use occgrid::sensors::ScanLog;

fn read_all(
    bytes: Vec<u8>,
    scan: Option<&str>,
    odom: Option<&str>,
) -> occgrid::Result<(ScanLog, Option<String>)> {
    let mut source = open_log(bytes, LogBudget::default())?;
    assert_eq!(source.format(), LogFormat::Mcap);
    source.choose_topics(scan.map(Into::into), odom.map(Into::into))?;
    loop {
        let p = source.read(usize::MAX)?;
        if p.finished {
            return Ok((source.into_scans(), p.warning));
        }
    }
}

fn assert_at_truth(scans: &ScanLog, truth: &[[f64; 3]]) {
    assert_eq!(scans.len(), truth.len());
    for (k, (p, t)) in scans.poses().iter().zip(truth).enumerate() {
        let d = (p.x - t[0]).hypot(p.y - t[1]) + wrap_angle(p.theta - t[2]).abs();
        assert!(d < 1e-6, "scan {k}: {p:?} against {t:?}");
    }
    assert_eq!(scans.odometry().unwrap(), scans.poses());
    assert!(!scans.pose_kinds().reference);
}

#[test]
fn every_storage_and_byte_order_places_the_scans_at_the_truth() {
    for compression in [
        Compression::Unchunked,
        Compression::None,
        Compression::Zstd,
        Compression::Lz4,
    ] {
        for big_endian in [false, true] {
            for summary in [false, true] {
                let spec = BagSpec {
                    compression,
                    big_endian,
                    summary,
                    ..BagSpec::default()
                };
                let (bag, truth) = robot_bag(&spec);
                let (scans, warning) = read_all(bag, None, None).unwrap();
                assert_eq!(warning, None, "{spec:?}");
                assert_at_truth(&scans, &truth);
                assert_eq!(scans.beams(), spec.scans * spec.beams);
            }
        }
    }
}

#[test]
fn a_chain_and_a_yawed_mount_move_the_laser_off_the_odometry() {
    let spec = BagSpec {
        chain: true,
        mount: [0.3, 0.1, 0.7],
        ..BagSpec::default()
    };
    let (bag, truth) = robot_bag(&spec);
    let (scans, _) = read_all(bag, None, None).unwrap();
    assert_at_truth(&scans, &truth);
    let m = scans.mount();
    // base_footprint → base_link (0.05 m ahead) → laser.
    assert!(
        (m.x - 0.35).abs() < 1e-9 && (m.y - 0.1).abs() < 1e-9 && (m.theta - 0.7).abs() < 1e-9,
        "{m:?}"
    );
}

#[test]
fn a_mount_given_only_on_tf_is_read_there_with_a_warning() {
    let spec = BagSpec {
        chain: true,
        mount_on_tf: true,
        ..BagSpec::default()
    };
    let (bag, truth) = robot_bag(&spec);
    let (scans, warning) = read_all(bag, None, None).unwrap();
    assert_at_truth(&scans, &truth);
    let w = warning.unwrap();
    assert!(w.contains("mount is read from /tf"), "{w}");
}

#[test]
fn other_topic_names_map_and_several_topics_need_a_choice() {
    let spec = BagSpec {
        scan_topics: vec!["/front/scan", "/rear/scan"],
        odom_topics: vec!["/wheel/odom"],
        ..BagSpec::default()
    };
    let (bag, truth) = robot_bag(&spec);
    let e = read_all(bag.clone(), None, None).unwrap_err().to_string();
    assert!(
        e.contains("\"/front/scan\" (\"sensor_msgs/msg/LaserScan\", 12 messages)")
            && e.contains("\"/rear/scan\"")
            && e.contains("scan_topic"),
        "{e}"
    );
    let (scans, _) = read_all(bag.clone(), Some("/rear/scan"), None).unwrap();
    assert_at_truth(&scans, &truth);
    let e = read_all(bag, Some("/nope"), None).unwrap_err().to_string();
    assert!(
        e.contains("\"/nope\"") && e.contains("\"/wheel/odom\" (\"nav_msgs/msg/Odometry\""),
        "{e}"
    );
    // Without a summary the choice is refused once the messages are read.
    let (bag, _) = robot_bag(&BagSpec {
        summary: false,
        ..spec
    });
    let e = read_all(bag, None, None).unwrap_err().to_string();
    assert!(e.contains("2 sensor_msgs/msg/LaserScan topics"), "{e}");
}

#[test]
fn a_bag_without_laser_scans_is_refused_with_its_topics() {
    let (bag, _) = robot_bag(&BagSpec {
        scan_topics: vec![],
        ..BagSpec::default()
    });
    let e = read_all(bag, None, None).unwrap_err().to_string();
    assert!(
        e.contains("no sensor_msgs/msg/LaserScan topic")
            && e.contains("\"/odom\" (\"nav_msgs/msg/Odometry\"")
            && e.contains("\"/tf_static\""),
        "{e}"
    );
}

#[test]
fn rep_117_no_returns_clear_at_range_max_and_too_close_or_invalid_readings_are_dropped() {
    let spec = BagSpec {
        range: |k, i| match (k, i % 6) {
            // Scan 0 measures nothing: skipped.
            (0, _) => f32::NEG_INFINITY,
            (_, 0) => f32::INFINITY,
            (_, 1) => f32::NAN,
            (_, 2) => 9.5,
            (_, 3) => 0.01,
            (_, 4) => f32::NEG_INFINITY,
            _ => 2.0,
        },
        step: -0.01,
        ..BagSpec::default()
    };
    let (bag, _) = robot_bag(&spec);
    let (scans, warning) = read_all(bag, None, None).unwrap();
    assert_eq!(scans.len(), 11);
    let scan = scans.scan(0).unwrap();
    assert_eq!(scans.max_range(0), Some(8.0));
    // +inf and 9.5 m (past range_max 8 m) are no-returns at range_max;
    // NaN, 0.01 m (below range_min 0.05 m) and -inf leave no beam.
    assert_eq!(scan.len(), 3 * 15);
    assert_eq!(&scan.ranges()[..3], &[8.0, 8.0, 2.0]);
    let first = scan.bearings()[0];
    for (j, i) in [0usize, 2, 5, 6].into_iter().enumerate() {
        let expected = first + i as f64 * f64::from(-0.01f32);
        assert!((scan.bearings()[j] - expected).abs() < 1e-9, "beam {i}");
    }
    // Too close: two of each six beams of 11 scans, and all 90 of scan 0.
    let w = warning.unwrap();
    assert!(
        w.contains(&format!(
            "by REP 117, {} readings too close to measure (-inf or below range_min) and {} invalid ones (NaN) are dropped, and 1 scans left with none skipped",
            2 * 15 * 11 + 90,
            15 * 11
        )),
        "{w}"
    );
}

#[test]
fn scans_without_odometry_around_them_are_skipped_by_name_or_refused() {
    let (bag, truth) = robot_bag(&BagSpec {
        odom_from: 3,
        ..BagSpec::default()
    });
    let (scans, warning) = read_all(bag, None, None).unwrap();
    assert_at_truth(&scans, &truth);
    let w = warning.unwrap();
    // Messages: the static transforms, then scan 0.
    assert!(
        w.contains(
            "3 scans with no odometry around their stamps are skipped (the first is message 2)"
        ),
        "{w}"
    );
    let (bag, _) = robot_bag(&BagSpec {
        odom_from: 12,
        ..BagSpec::default()
    });
    let e = read_all(bag, None, None).unwrap_err().to_string();
    assert!(e.contains("\"/odom\" has no messages"), "{e}");
}

#[test]
fn a_bag_maps_at_odometry_and_scan_matched_but_not_corrected_or_dead_reckoning() {
    let (bag, _) = robot_bag(&BagSpec::default());
    let scans = read_log(bag).unwrap();
    let settings = SourceSettings {
        seed: 1,
        noise: occgrid::sensors::odometry::OdometryParams::WHEELS,
        matching: Default::default(),
        resolution: 0.05,
    };
    let odometry = PoseSourceKind::Odometry.start(&scans, &settings).unwrap();
    assert_eq!(odometry.poses(), scans.poses());
    assert!(PoseSourceKind::ScanMatched.start(&scans, &settings).is_ok());
    for kind in [PoseSourceKind::Corrected, PoseSourceKind::DeadReckoning] {
        let e = kind.start(&scans, &settings).err().unwrap().to_string();
        assert!(e.contains("does not apply"), "{kind:?}: {e}");
        assert!(!kind.applies(&scans));
    }
}

#[test]
fn a_scan_frame_no_transform_reaches_is_refused_naming_both_frames() {
    use bag_support::{laser_scan, laser_scan_def, odometry, odometry_def, Writer};
    let mut w = Writer::new(Compression::Lz4);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    w.schema(2, "nav_msgs/msg/Odometry", &odometry_def());
    w.channel(1, 1, "/scan");
    w.channel(2, 2, "/odom");
    for k in 0..3 {
        let t = 10.0 + k as f64;
        w.message(2, t - 0.5, &odometry(false, t - 0.5, "base_link", [0.0; 3]));
        w.message(
            1,
            t,
            &laser_scan(false, t, "lidar\u{7}", 0.0, 0.1, 8.0, &[1.0; 5]),
        );
        w.message(2, t + 0.5, &odometry(false, t + 0.5, "base_link", [0.0; 3]));
    }
    let e = read_all(w.finish(true), None, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no frame \"base_link\"")
            && e.contains("frame \"lidar?\"")
            && e.contains("static transforms: none"),
        "{e}"
    );
}
