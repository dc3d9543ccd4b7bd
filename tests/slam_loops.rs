#![cfg(not(target_arch = "wasm32"))]
//! SLAM on a built world: a ring corridor driven once round and on past
//! the start, from dead reckoning that drifts, closes its loop (the path
//! ends far nearer the truth than dead reckoning); the same seed gives the
//! same poses bit for bit. (Run in release: `cargo test --release --test
//! slam_loops`.)

use occgrid::geometry::{GridGeometry, Pose};
use occgrid::mapping::scan_match::MatchSettings;
use occgrid::sensors::lidar::Lidar;
use occgrid::sensors::odometry::OdometryParams;
use occgrid::sensors::Scan;
use occgrid::slam::SlamBuilder;
use occgrid::world::{Rect, World};
use rand::rngs::StdRng;
use rand::SeedableRng;

/// A 3 m wide corridor round a 18 x 8 m block, with doorway posts and
/// cupboards along its outer wall at uneven spacing (a corridor without
/// them pins nothing along its length).
fn ring_world() -> World {
    let g = GridGeometry::new(540, 340, 0.05, 0.0, 0.0).unwrap();
    let mut boxes = vec![
        Rect::new(0.5, 0.5, 26.5, 1.0),
        Rect::new(0.5, 16.0, 26.5, 16.5),
        Rect::new(0.5, 0.5, 1.0, 16.5),
        Rect::new(26.0, 0.5, 26.5, 16.5),
        Rect::new(4.0, 4.0, 22.5, 12.5),
    ];
    let posts = [2.3, 5.1, 6.0, 9.7, 13.2, 14.0, 17.9, 20.4, 24.1];
    for (i, &x) in posts.iter().enumerate() {
        let depth = 0.3 + 0.15 * (i % 3) as f64;
        boxes.push(Rect::new(x, 1.0, x + 0.4, 1.0 + depth));
        boxes.push(Rect::new(x + 0.7, 16.0 - depth, x + 1.1, 16.0));
    }
    for (i, &y) in [3.1, 6.4, 8.0, 11.5, 13.9].iter().enumerate() {
        let depth = 0.3 + 0.2 * (i % 2) as f64;
        boxes.push(Rect::new(1.0, y, 1.0 + depth, y + 0.5));
        boxes.push(Rect::new(26.0 - depth, y + 0.6, 26.0, y + 1.0));
    }
    World::from_boxes(g, &boxes)
}

/// Round the corridor's middle line once, anticlockwise, and on along the
/// first side again: a step of 0.3 m, corners turned in place.
fn route() -> Vec<Pose> {
    let corners: [(f64, f64); 6] = [
        (2.5, 2.5),
        (24.5, 2.5),
        (24.5, 14.2),
        (2.5, 14.2),
        (2.5, 2.5),
        (12.0, 2.5),
    ];
    let mut out = Vec::new();
    let mut heading = 0.0;
    for w in corners.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        let to = (y1 - y0).atan2(x1 - x0);
        let turn = occgrid::geometry::wrap_angle(to - heading);
        for i in 1..=4 {
            out.push(Pose {
                x: x0,
                y: y0,
                theta: heading + turn * i as f64 / 4.0,
            });
        }
        heading = to;
        let length = (x1 - x0).hypot(y1 - y0);
        let steps = (length / 0.3).round() as usize;
        for i in 1..=steps {
            let t = i as f64 / steps as f64;
            out.push(Pose {
                x: x0 + t * (x1 - x0),
                y: y0 + t * (y1 - y0),
                theta: heading,
            });
        }
    }
    out
}

/// Dead reckoning that drifts as worn wheels do: a tenth of a degree of
/// heading a metre on top of the usual noise.
const DRIFTING: OdometryParams = OdometryParams {
    heading_drift: 0.0035,
    ..OdometryParams::WHEELS
};

fn scans(world: &World, truth: &[Pose]) -> Vec<Scan> {
    let lidar = Lidar {
        beams: 360,
        z_max: 20.0,
        sigma: 0.01,
        first_bearing: 0.0,
    };
    let mut rng = StdRng::seed_from_u64(7);
    let mut ranges = Vec::new();
    truth
        .iter()
        .map(|p| {
            lidar.scan_into(world, p, &mut rng, &mut ranges);
            Scan::new(*p, ranges.clone(), lidar.bearings()).unwrap()
        })
        .collect()
}

fn slam(odometry: &[Pose], scans: &[Scan]) -> SlamBuilder {
    let mut b =
        SlamBuilder::new(odometry.to_vec(), DRIFTING, MatchSettings::default(), 0.05).unwrap();
    for s in scans {
        b.add_scan(s, 20.0).unwrap();
    }
    b
}

/// Every coordinate's bits: poses compared bit for bit.
fn bits(poses: &[Pose]) -> Vec<u64> {
    poses
        .iter()
        .flat_map(|q| [q.x.to_bits(), q.y.to_bits(), q.theta.to_bits()])
        .collect()
}

fn rms(a: &[Pose], b: &[Pose]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p.x - q.x).powi(2) + (p.y - q.y).powi(2))
        .sum();
    (sum / a.len() as f64).sqrt()
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped twice: minutes unoptimised, run with --release"
)]
fn a_corridor_loop_with_drift_closes_and_one_seed_gives_one_path() {
    let world = ring_world();
    let truth = route();
    let scans = scans(&world, &truth);
    let odometry = DRIFTING.dead_reckon_path(&truth, 3);
    let before = rms(&odometry, &truth);
    let b = slam(&odometry, &scans);
    let after = rms(b.poses(), &truth);
    eprintln!(
        "{} scans: dead reckoning {before:.3} m, slam {after:.3} m, {} closures",
        truth.len(),
        b.closures()
    );
    assert!(before > 0.5, "the dead reckoning drifts: {before}");
    assert!(b.closures() > 0 && b.revision() > 0, "the loop is closed");
    assert!(
        after < 0.2 * before && after < 0.15,
        "before {before}, after {after}"
    );
    // Same seed, same poses, bit for bit.
    let again = slam(&odometry, &scans);
    assert_eq!(bits(b.poses()), bits(again.poses()));
}

/// The ring's scans as a log: the true poses as its reference, no
/// odometry of its own (so the sources dead-reckon from the seed).
fn ring_log(scans: &[Scan]) -> occgrid::sensors::ScanLog {
    let mut log = occgrid::sensors::ScanLog::new("scan");
    for (k, s) in scans.iter().enumerate() {
        let record = occgrid::sensors::ScanRecord {
            origin: k + 1,
            stamp: None,
            pose: s.pose(),
            odometry: None,
            ranges: s.ranges(),
            first_bearing: s.bearings()[0],
            bearing_step: s.bearings()[1] - s.bearings()[0],
            max_range: Some(20.0),
        };
        log.push(&record, usize::MAX).unwrap();
    }
    log
}

/// The ring driven along [`route`], its log, and a real-log pane's
/// settings at SLAM poses (log odds).
fn ring_slam_log() -> (
    Vec<Pose>,
    occgrid::sensors::ScanLog,
    occgrid::apps::real_log::LogMapSettings,
) {
    use occgrid::apps::real_log::{LogCellModel, LogMapSettings};
    let truth = route();
    let log = ring_log(&scans(&ring_world(), &truth));
    let settings = LogMapSettings {
        poses: occgrid::poses::PoseSourceKind::Slam,
        model: LogCellModel::LogOdds,
        ..LogMapSettings::default()
    };
    (truth, log, settings)
}

/// SLAM as a pane at `settings` runs it over the ring (from the same
/// seeded dead reckoning, with the same matcher), fed scan by scan.
fn one_call_slam(
    truth: &[Pose],
    settings: &occgrid::apps::real_log::LogMapSettings,
) -> SlamBuilder {
    let odometry = OdometryParams::WHEELS.dead_reckon_path(truth, settings.seed);
    SlamBuilder::new(
        odometry,
        OdometryParams::WHEELS,
        occgrid::poses::match_settings(settings.range_cap),
        settings.resolution,
    )
    .unwrap()
}

/// A real-log pane at SLAM poses ends with the map of every scan at the
/// final, optimised poses: bit for bit the map inserted afresh at them
/// (its map was rebuilt after each optimisation, not left at the poses
/// each scan was first put at).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped with SLAM: minutes unoptimised, run with --release"
)]
fn a_slam_pane_ends_with_the_map_at_the_optimised_poses() {
    use occgrid::apps::real_log::LogPane;
    use occgrid::mapping::insertion::ScanInserter;
    let (truth, log, settings) = ring_slam_log();
    let mut pane = LogPane::new(log.clone(), settings).unwrap();
    let progress = pane.advance(usize::MAX);
    assert!(progress.finished && pane.failure().is_none());
    let optimised = pane.poses().to_vec();
    let mut fresh = pane.grid().to_dense().unwrap();
    fresh.reset();
    let mut inserter = ScanInserter::new(settings.scan_insertion()).unwrap();
    for (k, pose) in optimised.iter().enumerate() {
        let scan = log.scan(k).unwrap().with_pose(*pose).unwrap();
        inserter.insert(&mut fresh, &scan, 20.0);
    }
    let built = pane.grid().to_dense().unwrap();
    assert_eq!(built.log_odds(), fresh.log_odds());
    // And the poses moved after they were first found: dead reckoning
    // wandered, and the loop pulled them back.
    let odometry = OdometryParams::WHEELS.dead_reckon_path(&truth, settings.seed);
    assert!(rms(&optimised, &truth) < 0.5 * rms(&odometry, &truth));
}

/// A SLAM pane built in calls of a bounded budget, as the page builds it:
/// few calls pass the budget, and none by more than one step's (a scan
/// located and inserted, a slice of a grid of maxima or one heading of a submap's
/// loop search, a slice of an optimiser iteration, or a scan inserted
/// again at revised poses), though the loop's optimisations each move every
/// scan; and the result is the one-call build's: the poses bit for bit
/// those of SLAM run scan by scan with each optimisation in one call, the
/// map the map of every scan at them.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped with SLAM: minutes unoptimised, run with --release"
)]
fn a_slam_pane_built_in_budgeted_calls_keeps_every_call_within_its_budget() {
    use occgrid::apps::real_log::LogPane;
    use occgrid::mapping::insertion::ScanInserter;
    /// About 25 ms of work natively (10 to 16 ns a unit: budget.rs), above
    /// the most one step of this log costs (a scan of 360 beams matched
    /// and inserted into two submaps, one of them finished: some 1.3
    /// million units; a step of a loop search or of an optimiser
    /// iteration).
    const BUDGET: u64 = 2_000_000;
    let (truth, log, settings) = ring_slam_log();
    // Built again at half the budget: below a whole submap's loop
    // search or optimiser iteration, which are cut into smaller steps.
    let build = |budget: u64| {
        let mut pane = LogPane::new(log.clone(), settings).unwrap();
        let (mut calls, mut longest, mut rebuilds) = (0usize, 0u64, 0usize);
        let (mut last_done, mut past) = (0, 0usize);
        loop {
            let before = pane.progress().work;
            let p = pane.advance_within(usize::MAX, budget);
            assert!(pane.failure().is_none());
            calls += 1;
            longest = longest.max(p.work - before);
            past += usize::from(p.work - before > budget);
            rebuilds += usize::from(p.scans_done < last_done);
            last_done = p.scans_done;
            if p.finished {
                break;
            }
        }
        eprintln!(
            "{calls} calls, {past} past their budget, the longest {longest} units of a budget \
             of {budget}, {rebuilds} rebuilds"
        );
        assert!(rebuilds > 0, "the map was built again at revised poses");
        assert!(
            longest < 2 * budget,
            "a call did {longest} units of work, its budget {budget}"
        );
        // A step that would take a call past its budget waits for the
        // next call (a scan located is some 1.3 million units here, a
        // settling slice or a scan inserted again a few thousand): before,
        // the locating step came after the budget was nearly spent, and
        // 178 of 179 calls passed it.
        assert!(
            past * 10 <= calls,
            "{past} of {calls} calls passed their budget of {budget}"
        );
        (pane, rebuilds)
    };
    build(BUDGET / 2);
    let (pane, rebuilds) = build(BUDGET);
    // The poses of SLAM run with every optimisation in one call.
    let mut one_call = one_call_slam(&truth, &settings);
    for k in 0..log.len() {
        one_call.add_scan(&log.scan(k).unwrap(), 20.0).unwrap();
    }
    assert!(one_call.revision() > 1, "optimised more than once");
    // Not a rebuild at every revision: each integrates every scan so far
    // again, so they are spaced by the scans located since the last one.
    assert!(
        rebuilds * 2 <= one_call.revision() as usize,
        "{rebuilds} rebuilds for {} revisions",
        one_call.revision()
    );
    // The pane says how many loop closures were found.
    assert!(one_call.closures() > 0);
    assert_eq!(pane.progress().loop_closures, Some(one_call.closures()));
    assert_eq!(bits(pane.poses()), bits(one_call.poses()));
    let mut fresh = pane.grid().to_dense().unwrap();
    fresh.reset();
    let mut inserter = ScanInserter::new(settings.scan_insertion()).unwrap();
    for (k, pose) in pane.poses().iter().enumerate() {
        let scan = log.scan(k).unwrap().with_pose(*pose).unwrap();
        inserter.insert(&mut fresh, &scan, 20.0);
    }
    assert_eq!(pane.grid().to_dense().unwrap().log_odds(), fresh.log_odds());
}

/// SLAM as a pose source asked for each scan in turn, with no settling
/// between them (`PoseSource::locate`, as a caller that wants only the
/// poses drives it): the optimisations then run when the next scan is
/// begun, inside a match of several stages, and after every scan the
/// poses it hands out are the graph's, bit for bit; at the end they are
/// those of the same SLAM run with a scan added at a time. Before, a
/// revision raised as a scan was begun was seen by no stage of its match:
/// the poses handed out stayed where each scan was first put (on the ACES
/// log natively 2 m apart from the graph's, 0.66 m aligned ATE against
/// the graph's 0.08).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped with SLAM: minutes unoptimised, run with --release"
)]
fn slam_located_scan_by_scan_hands_out_the_optimised_poses() {
    use occgrid::poses::{PoseSourceKind, SourceSettings};
    let (truth, log, settings) = ring_slam_log();
    let source_settings = SourceSettings {
        seed: settings.seed,
        noise: OdometryParams::WHEELS,
        matching: occgrid::poses::match_settings(settings.range_cap),
        resolution: settings.resolution,
    };
    let mut source = PoseSourceKind::Slam.start(&log, &source_settings).unwrap();
    let unread = occgrid::grid::TiledGrid::new(
        GridGeometry::new(8, 8, settings.resolution, 0.0, 0.0).unwrap(),
        occgrid::grid::FilterSettings {
            prior: 0.5,
            clamp: settings.clamp,
        },
        64,
    )
    .unwrap();
    // After every scan, the poses so far are the graph's.
    let mut revised = 0;
    for k in 0..log.len() {
        let revision = source.revision();
        source
            .locate(k, &log.scan(k).unwrap(), 20.0, &unread)
            .unwrap();
        revised += usize::from(source.revision() != revision);
        let graph = source.pose_graph().expect("SLAM has a pose graph");
        assert_eq!(
            bits(&source.poses()[..=k]),
            bits(&graph.nodes),
            "scan {k}, revision {}",
            source.revision()
        );
    }
    assert!(revised > 1, "optimised as scans were begun, more than once");
    while source.settling() {
        source.settle_within(u64::MAX);
    }
    let mut one_call = one_call_slam(&truth, &settings);
    for k in 0..log.len() {
        one_call.add_scan(&log.scan(k).unwrap(), 20.0).unwrap();
    }
    assert_eq!(bits(source.poses()), bits(one_call.poses()));
}

/// A scan SLAM locates is matched against its submap over several of a
/// pane's steps (the coarse copy, the search, each hypothesis's
/// refinement, each refinement on the submap itself) and inserted into
/// the pane's map in a step after them, so that no step holds a whole
/// match: on the Freiburg campus a whole one took up to 16 ms natively,
/// and a page's call that held one over 50 ms. Here the largest match
/// counts 670,000 units ([`local_match_work`]) and the largest step
/// 389,000 (the second scan's search, in the widest window); before, the
/// largest step was a whole match and the scan's insertion.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped with SLAM: minutes unoptimised, run with --release"
)]
fn a_slam_pane_step_holds_a_stage_of_a_scan_s_match_not_the_whole_match() {
    use occgrid::apps::real_log::LogPane;
    use occgrid::poses::local_match_work;
    let (truth, log, settings) = ring_slam_log();
    let mut one_call = one_call_slam(&truth, &settings);
    let mut largest_match = 0;
    for k in 0..log.len() {
        one_call.add_scan(&log.scan(k).unwrap(), 20.0).unwrap();
        largest_match = largest_match.max(local_match_work(one_call.last_match()));
    }
    let mut pane = LogPane::new(log, settings).unwrap();
    let (mut largest_step, mut steps) = (0, 0usize);
    loop {
        let before = pane.progress().work;
        let p = pane.advance_within(1, u64::MAX);
        assert!(pane.failure().is_none());
        largest_step = largest_step.max(p.work - before);
        steps += 1;
        if p.finished {
            break;
        }
    }
    eprintln!("largest step {largest_step} units of {steps}, largest match {largest_match}");
    assert!(
        largest_step * 5 < largest_match * 3,
        "a step of {largest_step} units, the largest match {largest_match}"
    );
    // The same poses as SLAM located scan by scan.
    assert_eq!(pane.poses(), one_call.poses());
}

/// The ring as a park: its walls hedges a metre deep, trunks along both
/// sides. A beam reaching a hedge returns from anywhere in its first
/// `depth` metres (leaves), or with chance `pass` goes through to the next
/// thing in its way; the trunks return every beam. The hedges' cells are
/// as often crossed as returned from, so a place seen again scores lower
/// than an office wall.
fn park_scans(truth: &[Pose], pass: f64, depth: f64) -> Vec<Scan> {
    use rand::Rng;
    let g = GridGeometry::new(540, 340, 0.05, 0.0, 0.0).unwrap();
    let hedges = [
        Rect::new(0.0, 0.0, 27.0, 1.0),
        Rect::new(0.0, 16.0, 27.0, 17.0),
        Rect::new(0.0, 0.0, 1.0, 17.0),
        Rect::new(26.0, 0.0, 27.0, 17.0),
        Rect::new(4.0, 4.0, 22.5, 12.5),
    ];
    let mut trunks = Vec::new();
    for (i, &x) in [2.3, 5.1, 9.7, 13.2, 17.9, 20.4, 24.1].iter().enumerate() {
        let off = 0.2 * (i % 3) as f64;
        trunks.push(Rect::new(x, 1.2 + off, x + 0.3, 1.5 + off));
        trunks.push(Rect::new(x + 0.9, 15.5 - off, x + 1.2, 15.8 - off));
    }
    for (i, &y) in [3.1, 6.4, 11.5, 13.9].iter().enumerate() {
        let off = 0.25 * (i % 2) as f64;
        trunks.push(Rect::new(1.2 + off, y, 1.5 + off, y + 0.3));
        trunks.push(Rect::new(25.5 - off, y + 0.6, 25.8 - off, y + 0.9));
    }
    let bare = World::from_boxes(g, &trunks);
    let mut all = trunks.clone();
    all.extend_from_slice(&hedges);
    let leafy = World::from_boxes(g, &all);
    let lidar = Lidar {
        beams: 360,
        z_max: 20.0,
        sigma: 0.01,
        first_bearing: 0.0,
    };
    let mut rng = StdRng::seed_from_u64(11);
    let (mut through, mut stopped) = (Vec::new(), Vec::new());
    truth
        .iter()
        .map(|p| {
            lidar.scan_into(&bare, p, &mut rng, &mut through);
            lidar.scan_into(&leafy, p, &mut rng, &mut stopped);
            let ranges = through
                .iter()
                .zip(&stopped)
                .map(|(&beyond, &hedge)| {
                    let leaves = depth * rng.random::<f64>();
                    if rng.random::<f64>() < pass || hedge >= beyond {
                        beyond
                    } else {
                        (hedge + leaves).min(beyond)
                    }
                })
                .collect();
            Scan::new(*p, ranges, lidar.bearings()).unwrap()
        })
        .collect()
}

/// Round a park of hedges that return from within their leaves or let a
/// beam through: the place seen again scores less than walls would, the
/// loop still closes, and every closure puts its scan where the truth has
/// it. (With the least loop score at 0.62 no closure is made.)
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "276 scans mapped: minutes unoptimised, run with --release"
)]
fn a_loop_round_hedges_that_return_from_their_leaves_closes() {
    let truth = route();
    let scans = park_scans(&truth, 0.6, 0.5);
    let odometry = DRIFTING.dead_reckon_path(&truth, 3);
    let before = rms(&odometry, &truth);
    let b = slam(&odometry, &scans);
    let after = rms(b.poses(), &truth);
    eprintln!(
        "{} scans round the park: dead reckoning {before:.3} m, slam {after:.3} m, {} closures",
        truth.len(),
        b.closures()
    );
    assert!(b.closures() > 0 && b.revision() > 0, "the loop is closed");
    assert!(
        after < 0.1 * before && after < 0.1,
        "before {before}, after {after}"
    );
    for e in b.graph.edges.iter().filter(|e| e.robust) {
        let t = occgrid::mapping::scan_match::relative_motion(&truth[e.from], &truth[e.to]);
        let off = (t[0] - e.measurement[0]).hypot(t[1] - e.measurement[1]);
        assert!(
            off < 0.15 && occgrid::geometry::wrap_angle(t[2] - e.measurement[2]).abs() < 0.02,
            "closure {} -> {} is {off:.3} m off",
            e.from,
            e.to
        );
    }
}

/// A corridor 60 m long and 4 m wide, posts 0.3 m thick along its walls
/// at uneven spacing, and a wall at each end.
fn posts_corridor() -> World {
    use rand::Rng;
    let length = 60.0;
    let g = GridGeometry::new(((length + 6.0) / 0.05) as usize, 120, 0.05, 0.0, 0.0).unwrap();
    let mut boxes = vec![
        Rect::new(0.5, 0.5, length + 5.5, 1.0),
        Rect::new(0.5, 4.5, length + 5.5, 5.0),
        Rect::new(0.5, 0.5, 1.0, 5.0),
        Rect::new(length + 5.0, 0.5, length + 5.5, 5.0),
    ];
    let mut rng = StdRng::seed_from_u64(3);
    let mut x = 1.5;
    while x < length + 4.0 {
        let depth = rng.random_range(0.2..0.6);
        if rng.random_bool(0.5) {
            boxes.push(Rect::new(x, 1.0, x + 0.3, 1.0 + depth));
        } else {
            boxes.push(Rect::new(x, 4.5 - depth, x + 0.3, 4.5));
        }
        x += rng.random_range(1.0..4.0);
    }
    World::from_boxes(g, &boxes)
}

/// Scans of a laser that sees only ahead, as a real log's does: the half
/// of the ring's beams within a quarter turn of the heading, in order.
fn forward_scans(world: &World, truth: &[Pose]) -> Vec<Scan> {
    let lidar = Lidar {
        beams: 360,
        z_max: 40.0,
        sigma: 0.01,
        first_bearing: -std::f64::consts::FRAC_PI_2,
    };
    let mut rng = StdRng::seed_from_u64(5);
    let mut ranges = Vec::new();
    truth
        .iter()
        .map(|p| {
            lidar.scan_into(world, p, &mut rng, &mut ranges);
            let ahead = lidar.beams / 2 + 1;
            let bearings = lidar.bearings()[..ahead].to_vec();
            Scan::new(*p, ranges[..ahead].to_vec(), bearings).unwrap()
        })
        .collect()
}

/// Down a corridor of posts and back, the laser looking ahead: on the way
/// back it sees the posts' other faces, each a post's width from the faces
/// the submaps of the way out hold. A closure that lays the one face on
/// the other is 0.3 m off along the corridor, and closures so laid made
/// the way out 0.6 % short (0.99406 of its length, 0.36 m in 60 m). With
/// each cell's surface normal kept, it keeps its length to 0.2 % (1.00117)
/// and no closure is off by a post's width.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "400 scans mapped: minutes unoptimised, run with --release"
)]
fn a_corridor_driven_out_and_back_keeps_its_length() {
    let world = posts_corridor();
    let step = 0.3;
    let out = 200;
    let mut truth: Vec<Pose> = (0..=out)
        .map(|i| Pose {
            x: 3.0 + i as f64 * step,
            y: 2.75,
            theta: 0.0,
        })
        .collect();
    let end = truth[out].x;
    for i in 1..=8 {
        truth.push(Pose {
            x: end,
            y: 2.75,
            theta: std::f64::consts::PI * i as f64 / 8.0,
        });
    }
    for i in 1..=out {
        truth.push(Pose {
            x: end - i as f64 * step,
            y: 2.75,
            theta: std::f64::consts::PI,
        });
    }
    let scans = forward_scans(&world, &truth);
    let mut b = SlamBuilder::new(
        truth.clone(),
        OdometryParams::EXACT,
        MatchSettings::default(),
        0.05,
    )
    .unwrap();
    for s in &scans {
        b.add_scan(s, 40.0).unwrap();
    }
    assert!(b.closures() > 20, "{} closures", b.closures());
    let p = b.poses();
    let length = (p[out].x - p[0].x).hypot(p[out].y - p[0].y);
    let ratio = length / (truth[out].x - truth[0].x);
    eprintln!("out and back: the way out {ratio:.5} of its length");
    assert!(
        (ratio - 1.0).abs() < 0.002,
        "the way out is {ratio:.5} of its length"
    );
    for e in b.graph.edges.iter().filter(|e| e.robust && e.active) {
        let t = occgrid::mapping::scan_match::relative_motion(&truth[e.from], &truth[e.to]);
        let off = (t[0] - e.measurement[0]).hypot(t[1] - e.measurement[1]);
        assert!(
            off < 0.2,
            "closure {} -> {} is {off:.3} m off",
            e.from,
            e.to
        );
    }
}
