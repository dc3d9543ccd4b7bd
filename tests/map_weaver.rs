#![cfg(not(target_arch = "wasm32"))]
//! Map Weaver's claims about the simulated apartment, checked on whole
//! laps with fixed seeds, and the limits and choices its session offers.

use occgrid::apps::map_weaver::{Leaning, PaneSettings, PoseSource, Weaver, WeaverSettings};
use occgrid::geometry::Pose;
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::inverse::training::{self, TrainingConfig};
use occgrid::inverse::{HandCrafted, LearnedInverse};
use occgrid::mapping::traversal::RayMapper;
use occgrid::scenes::apartment::ApartmentScene;
use occgrid::sensors::Scan;
use occgrid::world::Rect;
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::sync::OnceLock;

/// A run with the learned model trained once for all the tests here.
fn weaver(settings: WeaverSettings) -> Weaver {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    let learned = LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
    Weaver::with_learned(settings, learned.clone()).unwrap()
}

/// A run with both panes on the hand-crafted model and the oracle.
fn settings(seed: u64, person: bool) -> WeaverSettings {
    let mut s = WeaverSettings {
        seed,
        person,
        ..Default::default()
    };
    for p in &mut s.panes {
        p.model = occgrid::apps::map_weaver::ModelKind::HandCrafted;
        p.pose = PoseSource::Oracle;
    }
    s
}

fn one_lap(s: WeaverSettings) -> Weaver {
    let mut w = weaver(s);
    let n = w.scans_per_lap();
    assert_eq!(w.advance(n).unwrap(), n);
    w
}

/// True when cell `i` or one of its eight neighbours is occupied in truth.
fn near_truth_wall(w: &Weaver, i: usize) -> bool {
    let g = w.geometry();
    let (ix, iy) = g.cell_of_index(i);
    let truth = w.ground_truth();
    (-1i64..=1).any(|dy| {
        (-1i64..=1).any(|dx| {
            let (x, y) = (ix as i64 + dx, iy as i64 + dy);
            x >= 0
                && y >= 0
                && (x as usize) < g.width()
                && (y as usize) < g.height()
                && truth[g.index(x as usize, y as usize)]
        })
    })
}

#[test]
fn full_lap_with_the_oracle_puts_walls_where_the_ground_truth_has_walls() {
    let w = one_lap(settings(1, false));
    let grid = w.grid(0).unwrap();
    let scene = ApartmentScene::default();
    let g = *w.geometry();

    // Brier score over the surveyed rooms and their walls. An empty map
    // scores 0.25; a perfect one 0. What remains after one lap is mostly
    // cells no beam can reach (the far row of the 0.2 m outer walls, the
    // inside of the sofa and the counters), at 0.25 each, and the jagged
    // edges of walls seen at a slant.
    let surveyed = scene.cells_in(&g, &[scene.surveyed]);
    let brier = grid.brier_score(w.ground_truth(), Some(&surveyed)).unwrap();
    assert!(brier < 0.085, "Brier over the surveyed rooms: {brier}");
    // The widget's readout (scored from a table, src/render/map_view.rs) agrees.
    assert!((w.view(0).unwrap().brier_region() - brier).abs() < 1e-6);

    // Precision: every cell the map calls occupied (p > 0.65) lies on a
    // true wall or right next to one.
    let occupied: Vec<usize> = (0..g.len())
        .filter(|&i| grid.probability_at(i) > 0.65)
        .collect();
    assert!(occupied.len() > 500, "{}", occupied.len());
    let near = occupied.iter().filter(|&&i| near_truth_wall(&w, i)).count();
    assert_eq!(near, occupied.len(), "occupied cells away from any wall");
    let exact = occupied.iter().filter(|&&i| w.ground_truth()[i]).count();
    assert!(
        exact as f64 > 0.55 * occupied.len() as f64,
        "{exact} of {} on the wall itself",
        occupied.len()
    );

    // Recall: the faces of the walls the robot drives along (occupied
    // cells with a free neighbour inside a room it enters) mostly come out
    // occupied.
    let entered: Vec<Rect> = scene
        .rooms
        .iter()
        .filter(|r| r.entered)
        .map(|r| r.area)
        .collect();
    let in_entered = scene.cells_in(&g, &entered);
    let mut is_entered = vec![false; g.len()];
    for &i in &in_entered {
        is_entered[i] = true;
    }
    let faces: Vec<usize> = (0..g.len())
        .filter(|&i| {
            let (ix, iy) = g.cell_of_index(i);
            w.ground_truth()[i]
                && [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)]
                    .iter()
                    .any(|&(dx, dy)| {
                        let (x, y) = (ix as i64 + dx, iy as i64 + dy);
                        x >= 0
                            && y >= 0
                            && (x as usize) < g.width()
                            && (y as usize) < g.height()
                            && is_entered[g.index(x as usize, y as usize)]
                            && !w.ground_truth()[g.index(x as usize, y as usize)]
                    })
        })
        .collect();
    let seen = faces
        .iter()
        .filter(|&&i| grid.probability_at(i) > 0.5)
        .count();
    assert!(
        seen as f64 > 0.75 * faces.len() as f64,
        "{seen} of {} wall faces occupied",
        faces.len()
    );
}

#[test]
fn never_entered_rooms_keep_their_far_interiors_at_l0() {
    let w = one_lap(settings(1, true));
    let scene = ApartmentScene::default();
    let g = *w.geometry();
    let hidden = scene.cells_in(&g, &scene.hidden);
    let rooms: Vec<Rect> = scene
        .rooms
        .iter()
        .filter(|r| !r.entered)
        .map(|r| r.area)
        .collect();
    let interior = scene.cells_in(&g, &rooms);
    // "Far interior" is most of the two rooms, not a corner.
    assert!(
        hidden.len() as f64 > 0.55 * interior.len() as f64,
        "{} of {}",
        hidden.len(),
        interior.len()
    );
    for pane in 0..2 {
        let grid = w.grid(pane).unwrap();
        let moved: Vec<usize> = hidden
            .iter()
            .copied()
            .filter(|&i| !grid.is_unknown(i) || grid.update_counts()[i] != 0)
            .collect();
        assert!(moved.is_empty(), "pane {pane}: cells {moved:?} left l0");
        // The near ends, by the doors, were seen.
        let seen = interior.iter().filter(|&&i| !grid.is_unknown(i)).count();
        assert!(seen > 150, "{seen}");
    }
}

#[test]
fn closet_cell_never_moves_from_l0() {
    for pose in [PoseSource::Oracle, PoseSource::DeadReckoning] {
        let mut s = settings(2, true);
        s.panes[1].pose = pose;
        let mut w = weaver(s);
        let n = 2 * w.scans_per_lap();
        w.advance(n).unwrap();
        let [_, _, closet] = w.tracked_cells();
        let l0 = w.grid(1).unwrap().l0();
        let history = w.tracked_history(1).unwrap();
        assert_eq!(history.len(), n + 1);
        assert!(history.iter().all(|t| t[2] == l0), "{pose:?}");
        assert_eq!(w.grid(1).unwrap().update_counts()[closet], 0);
        let scene = ApartmentScene::default();
        let closet_cells = scene.cells_in(w.geometry(), &[scene.closet]);
        assert!(closet_cells.contains(&closet));
        if pose == PoseSource::Oracle {
            let grid = w.grid(1).unwrap();
            assert!(closet_cells.iter().all(|&i| grid.is_unknown(i)));
        }
    }
}

#[test]
fn entropy_falls_over_the_lap() {
    let w = one_lap(settings(3, true));
    let curve = w.entropy_curve(0).unwrap();
    // A fresh map with p0 = 0.5 holds one bit per cell.
    assert_eq!(curve[0], 10_800.0);
    let end = *curve.last().unwrap();
    assert!(end < 0.45 * curve[0], "{end}");
    // Falling all along, not just overall: every 5 s of driving ends lower
    // than it began (a ghost may add a little entropy for a few scans, a
    // new stretch of wall always takes more away).
    let window = 60;
    for k in (window..curve.len()).step_by(window) {
        assert!(
            curve[k] < curve[k - window],
            "scan {k}: {} -> {}",
            curve[k - window],
            curve[k]
        );
    }
}

#[test]
fn dead_reckoning_makes_the_brier_score_clearly_worse() {
    for seed in [1, 2, 3] {
        let mut s = settings(seed, false);
        s.panes[1].pose = PoseSource::DeadReckoning;
        let w = one_lap(s);
        let oracle = w.view(0).unwrap().brier_region();
        let dead = w.view(1).unwrap().brier_region();
        assert!(
            dead > 1.3 * oracle && dead - oracle > 0.02,
            "seed {seed}: oracle {oracle}, dead reckoning {dead}"
        );
        // Dead reckoning drifts: by the end of the lap the estimate is
        // tens of centimetres off.
        let last = w.history().last().unwrap();
        let err = (last.truth.x - last.odometry.x).hypot(last.truth.y - last.odometry.y);
        assert!(err > 0.15, "seed {seed}: {err} m");
    }
}

/// The ghost experiment: the robot stands still in the corridor looking
/// down it; a person stands 2 m ahead for `stay` scans and walks off.
/// Returns the ghost's peak log odds and how many scans after the person
/// left it took for every ghost cell to drop back below the prior (p < 0.5).
///
/// After the person leaves, every ghost cell lies on the raster of a beam
/// that now runs on to the far wall, so each scan takes exactly `l_free`
/// off it: a ghost at the clamp needs `clamp / |l_free|` scans.
fn ghost_fade_scans(clamp: f64, strength: f64) -> (f32, usize) {
    let scene = ApartmentScene::default();
    let truth = scene.ground_truth().unwrap();
    let mut with_person = truth.clone();
    with_person.fill(&Rect::new(4.85, 4.55, 5.25, 4.95), true);
    let model =
        HandCrafted::with_strength(WeaverSettings::default().hand_crafted, strength).unwrap();
    let mut grid =
        LogOddsGrid::new(*truth.geometry(), FilterSettings { prior: 0.5, clamp }).unwrap();
    let mut mapper = RayMapper::new();
    let pose = Pose::new(3.05, 4.75, 0.0).unwrap();
    let bearings = scene.lidar.bearings();
    let mut rng = StdRng::seed_from_u64(11);
    let mut ranges = Vec::new();
    let mut scan = |world: &occgrid::world::World, grid: &mut LogOddsGrid| {
        scene.lidar.scan_into(world, &pose, &mut rng, &mut ranges);
        let s = Scan::new(pose, ranges.clone(), bearings.clone()).unwrap();
        mapper.integrate(grid, &model, &s);
    };
    for _ in 0..200 {
        scan(&with_person, &mut grid);
    }
    // The ghost: cells around the person's footprint that the map now
    // calls occupied.
    let near_person = scene.cells_in(truth.geometry(), &[Rect::new(4.7, 4.4, 5.4, 5.1)]);
    let ghost: Vec<usize> = near_person
        .into_iter()
        .filter(|&i| !truth.occupied()[i] && grid.log_odds()[i] > 0.0)
        .collect();
    assert!(!ghost.is_empty());
    let peak = ghost
        .iter()
        .map(|&i| grid.log_odds()[i])
        .fold(f32::MIN, f32::max);
    for n in 1..1000 {
        scan(&truth, &mut grid);
        if ghost.iter().all(|&i| grid.log_odds()[i] < 0.0) {
            return (peak, n);
        }
    }
    panic!("the ghost never faded");
}

#[test]
fn ghost_fades_in_scans_linear_in_the_clamp_and_inverse_in_l_free() {
    let l_free = WeaverSettings::default().hand_crafted.l_free.abs();
    let (peak4, n4) = ghost_fade_scans(4.0, 1.0);
    let (peak8, n8) = ghost_fade_scans(8.0, 1.0);
    // The person stood long enough to saturate the ghost at the clamp.
    assert_eq!((peak4, peak8), (4.0, 8.0));
    // clamp / |l_free| = 10 and 20 scans (one more where rounding leaves
    // the log odds a hair above zero).
    for (clamp, n) in [(4.0, n4), (8.0, n8)] {
        let expected = clamp / l_free;
        assert!(
            (n as f64 - expected).abs() <= 1.0,
            "clamp {clamp}: {n} scans, expected {expected}"
        );
    }
    // Linear: doubling the clamp doubles the time.
    assert!((n8 as f64 / n4 as f64 - 2.0).abs() < 0.25, "{n4} -> {n8}");
    // Twice the evidence strength (|l_free| = 0.8): half the scans.
    let (_, n8_strong) = ghost_fade_scans(8.0, 2.0);
    assert!(n8_strong < n8, "{n8_strong} vs {n8}");
    assert!(
        (n8_strong as f64 - 8.0 / (2.0 * l_free)).abs() <= 1.0,
        "{n8_strong}"
    );
}

#[test]
fn the_walking_person_leaves_ghosts_only_when_present() {
    // Along the corridor leg, every 10 scans: ghosts are cells the map
    // calls occupied (p > 0.65) on the person's walk, where the truth is
    // free floor.
    let scene = ApartmentScene::default();
    let walk = Rect::new(2.6, 4.15, 9.4, 4.65);
    let cells = scene.cells_in(&scene.geometry().unwrap(), &[walk]);
    let most_ghosts = |person: bool| {
        let mut w = weaver(settings(4, person));
        (0..20)
            .map(|_| {
                w.advance(10).unwrap();
                let grid = w.grid(0).unwrap();
                cells
                    .iter()
                    .filter(|&&i| !w.ground_truth()[i] && grid.probability_at(i) > 0.65)
                    .count()
            })
            .max()
            .unwrap()
    };
    assert_eq!(most_ghosts(false), 0);
    let ghosts = most_ghosts(true);
    assert!(ghosts >= 12, "{ghosts}");
}

#[test]
fn same_seed_gives_a_bit_identical_map() {
    let run = |seed: u64| {
        let mut s = WeaverSettings {
            seed,
            ..Default::default()
        };
        s.panes[1].pose = PoseSource::DeadReckoning;
        let mut w = weaver(s);
        w.advance(300).unwrap();
        w.set_person(false);
        w.advance(100).unwrap();
        let bits = |k: usize| -> Vec<u32> {
            w.grid(k)
                .unwrap()
                .log_odds()
                .iter()
                .map(|l| l.to_bits())
                .collect()
        };
        (bits(0), bits(1), w.view(1).unwrap().rgba().to_vec())
    };
    let a = run(5);
    assert!(a == run(5), "same seed, different maps");
    let b = run(6);
    assert!(a.0 != b.0 && a.1 != b.1, "another seed gives another map");
}

/// A scene whose LiDAR has 48 beams: the session offers exactly the
/// divisors of 48, accepts each, and refuses any other count with a
/// message that lists the 48's divisors (it said "60: 1, 2, 3, 4, 5, 6, 10,
/// 12, 15, 20, 30 or 60" whatever the scene), leaving the pane as it was.
#[test]
fn a_48_beam_lidar_offers_and_accepts_exactly_the_divisors_of_48() {
    let mut s = settings(1, false);
    s.scene.lidar.beams = 48;
    let mut w = weaver(s);
    w.advance(5).unwrap();
    let choices = w.choices();
    let offered: Vec<usize> = choices.beams.iter().map(|c| c.value).collect();
    assert_eq!(offered, [48, 24, 16, 12, 8, 6, 4, 3, 2, 1]);
    assert_eq!(
        (choices.beams[0].setting, choices.beams[1].setting),
        (None, Some(24))
    );
    assert_eq!(w.readout().choices, choices);
    for c in &choices.beams {
        let pane = PaneSettings {
            beams: c.setting,
            ..w.settings().panes[1]
        };
        w.set_pane(1, pane).unwrap();
        let r = w.readout();
        assert_eq!(r.panes[1].beams, c.value);
        assert_eq!(w.overlay(1).unwrap().hits.len(), c.value);
    }
    let before = w.grid(1).unwrap().clone();
    let kept = w.settings().panes[1];
    for beams in (0..=60).filter(|b| !offered.contains(b)) {
        let e = w
            .set_pane(
                1,
                PaneSettings {
                    beams: Some(beams),
                    ..kept
                },
            )
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "invalid panes[1].beams: {beams} (expected a divisor of the LiDAR's beam count \
                 (48: 1, 2, 3, 4, 6, 8, 12, 16, 24 or 48))"
            )
        );
        assert_eq!(w.grid(1).unwrap(), &before);
        assert_eq!(w.settings().panes[1], kept);
    }
}

/// The status line's "scan n of N" and the hover line's verdict are the
/// core's: N is the run's laps times its scans per lap, and each cell
/// leans the way its log odds point (the panes' prior is 0.5).
#[test]
fn the_readout_counts_the_run_and_says_which_way_each_cell_leans() {
    let mut s = settings(2, true);
    s.laps = 2;
    let mut w = weaver(s);
    assert_eq!(w.readout().total_scans, 2 * w.scans_per_lap());
    w.advance(60).unwrap();
    let g = *w.pane_geometry(0).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for row in 0..g.height() {
        for col in 0..g.width() {
            let info = w.cell_info(0, col, row).unwrap().unwrap();
            let expected = if info.cell.unknown {
                Leaning::Unknown
            } else if info.cell.p > 0.5 {
                Leaning::Occupied
            } else if info.cell.p < 0.5 {
                Leaning::Free
            } else {
                Leaning::Even
            };
            assert_eq!(info.leaning, expected, "({col}, {row})");
            seen.insert(format!("{expected:?}"));
        }
    }
    assert!(seen.len() >= 3, "{seen:?}");
}
