#![cfg(not(target_arch = "wasm32"))]
//! A ROS 2 bag in the real-log session: read, planned and mapped at its
//! odometry, or scan-matched from it with no corrected or dead-reckoned
//! map beside (neither applies to a bag); at the default corrected poses
//! it is refused by name.

mod bag_support;

use bag_support::{robot_bag, BagSpec};
use occgrid::apps::real_log::{LogMapSettings, RealLogSession};
use occgrid::poses::PoseSourceKind;

fn session(poses: PoseSourceKind) -> RealLogSession {
    let (bag, _) = robot_bag(&BagSpec {
        scans: 20,
        ..BagSpec::default()
    });
    let mut s = RealLogSession::new(bag);
    s.configure(LogMapSettings {
        poses,
        ..LogMapSettings::default()
    })
    .unwrap();
    s
}

fn read_and_build(s: &mut RealLogSession) -> occgrid::Result<()> {
    while !s.read(3)?.progress.finished {}
    while !s.build_slice(20_000)?.finished {}
    Ok(())
}

#[test]
fn a_bag_maps_at_its_odometry_and_scan_matched_alone() {
    for poses in [PoseSourceKind::Odometry, PoseSourceKind::ScanMatched] {
        let mut s = session(poses);
        read_and_build(&mut s).unwrap();
        assert_eq!(s.panes().len(), 1, "{poses:?}: only the chosen map");
        let state = s.state();
        assert_eq!(state.panes[0].poses, poses);
        assert_eq!((state.scans_done, state.scans_total), (20, 20), "{poses:?}");
    }
}

#[test]
fn a_bag_at_corrected_poses_is_refused_by_name() {
    let mut s = session(PoseSourceKind::Corrected);
    let e = read_and_build(&mut s).unwrap_err().to_string();
    assert!(
        e.contains("the pose source corrected does not apply"),
        "{e}"
    );
}

/// A bag of two LaserScan topics and one Odometry topic, `scans` each.
fn two_scan_topics(summary: bool) -> Vec<u8> {
    robot_bag(&BagSpec {
        scans: 6,
        scan_topics: vec!["/front_scan", "/rear_scan"],
        summary,
        ..BagSpec::default()
    })
    .0
}

#[test]
fn a_bag_with_two_scan_topics_offers_them_and_maps_the_one_chosen() {
    for summary in [true, false] {
        let bag = two_scan_topics(summary);
        let mut s = RealLogSession::new(bag.clone());
        s.configure(LogMapSettings {
            poses: PoseSourceKind::Odometry,
            ..LogMapSettings::default()
        })
        .unwrap();
        assert!(read_and_build(&mut s).is_err(), "summary {summary}");
        let state = s.state();
        let topics = state.topics.expect("the read wants a topic choice");
        let scans: Vec<(&str, &str, u64)> = topics
            .scan_topics
            .iter()
            .map(|t| (t.topic.as_str(), t.type_name.as_str(), t.messages))
            .collect();
        assert_eq!(
            scans,
            [
                ("/front_scan", "sensor_msgs/msg/LaserScan", 6),
                ("/rear_scan", "sensor_msgs/msg/LaserScan", 6)
            ],
            "summary {summary}"
        );
        assert_eq!(topics.odom_topics.len(), 1);
        assert_eq!(topics.odom_topics[0].topic, "/odom");
        assert_eq!(topics.odom_topics[0].type_name, "nav_msgs/msg/Odometry");
        assert!(topics.odom_topics[0].messages > 0);

        // Opened again with a topic named: no choice wanted, and it maps.
        s.open(bag, "two.mcap");
        assert_eq!(s.state().topics, None);
        s.choose_topics(Some("/rear_scan".into()), None).unwrap();
        read_and_build(&mut s).unwrap();
        let state = s.state();
        assert_eq!(state.topics, None);
        assert_eq!(state.scans_done, 6, "summary {summary}");
    }
}

#[test]
fn a_refusal_other_than_a_topic_choice_offers_no_topics() {
    let mut s = session(PoseSourceKind::Corrected);
    assert!(read_and_build(&mut s).is_err());
    assert_eq!(s.state().topics, None);
    let mut s = RealLogSession::new(b"\x89MCAP0\r\nnot a bag at all".to_vec());
    assert!(s.read(10).is_err());
    assert_eq!(s.state().topics, None);
}

#[test]
fn a_bag_is_mapped_at_its_own_odometry_and_a_carmen_log_at_its_corrected_poses() {
    let (bag, _) = robot_bag(&BagSpec::default());
    let mut s = RealLogSession::new(bag);
    assert_eq!(s.own_poses(), Some(PoseSourceKind::Odometry));
    // What a page does for a reader who named no poses: the log's own.
    s.configure(LogMapSettings {
        poses: s.own_poses().unwrap(),
        ..LogMapSettings::default()
    })
    .unwrap();
    read_and_build(&mut s).unwrap();
    assert_eq!(s.state().panes[0].poses, PoseSourceKind::Odometry);
    assert_eq!(
        s.own_poses(),
        Some(PoseSourceKind::Odometry),
        "read: the read bag's own, odometry without a map \u{2192} odom transform"
    );
    let carmen = b"FLASER 3 1.0 1.0 1.0 0 0 0 0 0 0 1 host 0\n".to_vec();
    let s = RealLogSession::new(carmen);
    assert_eq!(s.own_poses(), Some(PoseSourceKind::Corrected));
}

/// A page sizes each read call from the work the last one reports, in
/// scans. A bag keeps no scan until every message is read (its scans are
/// placed at the odometry after): its read calls report the scans they
/// decoded, then those they placed, each at most the call's budget,
/// never nothing while the reading goes on (before, every call of the
/// reading reported 0, and the page's calls were sized at random).
#[test]
fn a_bags_read_calls_report_the_scans_they_decoded_and_placed() {
    let (bag, _) = robot_bag(&BagSpec {
        scans: 40,
        ..BagSpec::default()
    });
    let mut s = RealLogSession::new(bag);
    s.configure(LogMapSettings {
        poses: PoseSourceKind::Odometry,
        ..LogMapSettings::default()
    })
    .unwrap();
    let mut works = Vec::new();
    loop {
        let report = s.read(4).unwrap();
        works.push(report.work);
        if report.progress.finished {
            break;
        }
    }
    assert!(works.iter().all(|&w| w <= 4), "{works:?}");
    // Each scan decoded once and placed once; a call that only passed
    // over other messages (the summary, the last odometry) may count none.
    let total: usize = works.iter().sum();
    assert!(total >= 80, "total {total}: {works:?}");
    let idle = works.iter().filter(|&&w| w == 0).count();
    assert!(
        idle <= 2,
        "{idle} calls of {} reported no work: {works:?}",
        works.len()
    );
}
