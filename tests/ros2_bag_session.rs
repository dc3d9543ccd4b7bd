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
