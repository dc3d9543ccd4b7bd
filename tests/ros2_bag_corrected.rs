#![cfg(not(target_arch = "wasm32"))]
//! A ROS 2 bag that carries a map-frame pose (a `map → odom` transform on
//! `/tf`, directly or through a static link to the odometry's frame) has
//! corrected poses: each scan's odometry pose composed after the
//! transform interpolated at its stamp (the nearest outside their stamps,
//! named). Such a bag maps at `corrected`, its own poses once read, and
//! at dead reckoning of them; a bag without one still refuses `corrected`
//! by name.

mod bag_support;

use bag_support::{compose, map_odom_at, robot_bag, BagSpec};
use occgrid::apps::real_log::{LogMapSettings, RealLogSession};
use occgrid::geometry::{wrap_angle, Pose};
use occgrid::io::{open_log, LogBudget};
use occgrid::poses::{PoseSourceKind, SourceSettings};
use occgrid::sensors::{LogPoseKinds, ScanLog};

const T0: f64 = 1_700_000_000.0;

fn read_all(bytes: Vec<u8>) -> occgrid::Result<(ScanLog, Option<String>)> {
    let mut source = open_log(bytes, LogBudget::default())?;
    loop {
        let p = source.read(5)?;
        if p.finished {
            return Ok((source.into_scans(), p.warning));
        }
    }
}

fn assert_near(found: &[Pose], expected: &[[f64; 3]], what: &str) {
    assert_eq!(found.len(), expected.len(), "{what}");
    for (k, (p, t)) in found.iter().zip(expected).enumerate() {
        let d = (p.x - t[0]).hypot(p.y - t[1]) + wrap_angle(p.theta - t[2]).abs();
        assert!(d < 1e-6, "{what}, scan {k}: {p:?} against {t:?}");
    }
}

/// `map → odom` every 1.3 s, from before the first scan to after the last
/// (scans every 0.5 s: most fall between two transforms).
fn around_every_scan() -> Vec<f64> {
    (0..6).map(|i| T0 - 0.4 + 1.3 * i as f64).collect()
}

fn settings() -> SourceSettings {
    SourceSettings {
        seed: 1,
        noise: occgrid::sensors::odometry::OdometryParams::WHEELS,
        matching: Default::default(),
        resolution: 0.05,
    }
}

#[test]
fn map_to_odom_on_tf_gives_each_scan_a_corrected_pose_at_its_stamp() {
    let spec = BagSpec {
        map_stamps: around_every_scan(),
        ..BagSpec::default()
    };
    let (bag, truth) = robot_bag(&spec);
    let (scans, warning) = read_all(bag).unwrap();
    assert_eq!(warning, None);
    assert_eq!(
        scans.pose_kinds(),
        LogPoseKinds {
            reference: true,
            odometry: true
        }
    );
    let corrected: Vec<[f64; 3]> = truth
        .iter()
        .enumerate()
        .map(|(k, odom)| compose(map_odom_at((spec.stamp)(k)), *odom))
        .collect();
    assert_near(scans.poses(), &corrected, "corrected");
    assert_near(scans.odometry().unwrap(), &truth, "odometry");
    assert_eq!(PoseSourceKind::own_of(&scans), PoseSourceKind::Corrected);

    let source = PoseSourceKind::Corrected
        .start(&scans, &settings())
        .unwrap();
    assert_eq!(source.poses(), scans.poses());
    let odometry = PoseSourceKind::Odometry.start(&scans, &settings()).unwrap();
    assert_eq!(odometry.poses(), scans.odometry().unwrap());
    // As a CARMEN log with corrected poses and raw odometry: dead reckoning
    // adds its noise to the corrected path's motion.
    assert!(PoseSourceKind::DeadReckoning.applies(&scans));
}

#[test]
fn map_to_a_frame_linked_statically_to_odom_is_followed() {
    let via = [0.3, -0.2, 0.4];
    let spec = BagSpec {
        map_stamps: around_every_scan(),
        map_child: "odom_root",
        map_via: Some(via),
        chain: true,
        ..BagSpec::default()
    };
    let (bag, truth) = robot_bag(&spec);
    let (scans, _) = read_all(bag).unwrap();
    assert!(scans.pose_kinds().reference);
    let corrected: Vec<[f64; 3]> = truth
        .iter()
        .enumerate()
        .map(|(k, odom)| compose(compose(map_odom_at((spec.stamp)(k)), via), *odom))
        .collect();
    assert_near(scans.poses(), &corrected, "through odom_root");
}

#[test]
fn scans_outside_the_map_transforms_take_the_nearest_by_name() {
    // One transform, at scan 2's stamp: the ten other scans hold it.
    let at = T0 + 1.0;
    let (bag, truth) = robot_bag(&BagSpec {
        map_stamps: vec![at],
        ..BagSpec::default()
    });
    let (scans, warning) = read_all(bag).unwrap();
    let corrected: Vec<[f64; 3]> = truth.iter().map(|o| compose(map_odom_at(at), *o)).collect();
    assert_near(scans.poses(), &corrected, "held");
    let w = warning.unwrap();
    assert!(
        w.contains("11 scans lie outside the stamps of the map \u{2192} odometry transforms and take the nearest"),
        "{w}"
    );
}

#[test]
fn a_map_link_that_reaches_no_odometry_frame_leaves_the_bag_without_corrected_poses() {
    let (bag, truth) = robot_bag(&BagSpec {
        map_stamps: around_every_scan(),
        map_child: "elsewhere",
        ..BagSpec::default()
    });
    let (scans, warning) = read_all(bag).unwrap();
    assert!(!scans.pose_kinds().reference);
    assert_near(scans.poses(), &truth, "odometry");
    let w = warning.unwrap();
    assert!(
        w.contains("(map \u{2192} \"elsewhere\") lead to no odometry frame"),
        "{w}"
    );
    assert_eq!(PoseSourceKind::own_of(&scans), PoseSourceKind::Odometry);
    let e = PoseSourceKind::Corrected
        .start(&scans, &settings())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("the pose source corrected does not apply"),
        "{e}"
    );
}

fn read_and_build(s: &mut RealLogSession) -> occgrid::Result<()> {
    while !s.read(4)?.progress.finished {}
    while !s.build_slice(20_000)?.finished {}
    Ok(())
}

#[test]
fn a_session_maps_such_a_bag_at_corrected_its_own_poses_once_read() {
    let spec = BagSpec {
        map_stamps: around_every_scan(),
        ..BagSpec::default()
    };
    let (bag, _) = robot_bag(&spec);
    let mut s = RealLogSession::new(bag.clone());
    // Before the read, only the format is known: a bag's odometry.
    assert_eq!(s.own_poses(), Some(PoseSourceKind::Odometry));
    s.configure(LogMapSettings {
        poses: PoseSourceKind::Odometry,
        ..LogMapSettings::default()
    })
    .unwrap();
    read_and_build(&mut s).unwrap();
    assert_eq!(s.own_poses(), Some(PoseSourceKind::Corrected));

    let mut s = RealLogSession::new(bag);
    s.configure(LogMapSettings {
        poses: PoseSourceKind::Corrected,
        ..LogMapSettings::default()
    })
    .unwrap();
    read_and_build(&mut s).unwrap();
    let state = s.state();
    assert_eq!(state.panes[0].poses, PoseSourceKind::Corrected);
    assert_eq!(state.scans_done, 12);

    // Without the transform the read bag's own poses stay its odometry.
    let (plain, _) = robot_bag(&BagSpec::default());
    let mut s = RealLogSession::new(plain);
    s.configure(LogMapSettings {
        poses: PoseSourceKind::Odometry,
        ..LogMapSettings::default()
    })
    .unwrap();
    read_and_build(&mut s).unwrap();
    assert_eq!(s.own_poses(), Some(PoseSourceKind::Odometry));
}
