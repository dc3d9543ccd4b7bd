#![cfg(not(target_arch = "wasm32"))]
//! docs/ARCHITECTURE.md, "Bad input" as properties over the simulated scenes and the widgets' cores:
//! the ground-truth world and its ray caster, the robot (lap, LiDAR,
//! odometry, walker), the apartment, the doorway, the table, the fusion
//! experiment and the Map Weaver session.
//!
//! Scenes are data an instructor's attributes can set field by field, so
//! the main properties change *one* field of the chapter's scene to an
//! arbitrary value: the scene must then either run (and every map it
//! builds stays finite and inside its clamp) or be refused with an error
//! naming that very field. The widgets' setters must refuse bad values
//! without touching the run.

mod properties_support;

use occgrid::apps::doorway_trap::DoorwaySweep;
use occgrid::apps::map_weaver::{ModelKind, PoseSource, Weaver, WeaverSettings};
use occgrid::apps::sensor_fusion::{FusionModels, TableFusion};
use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::LogOddsGrid;
use occgrid::inverse::learned::{FeatureFrame, FEATURES};
use occgrid::inverse::LearnedInverse;
use occgrid::scenes::apartment::{ApartmentScene, ApartmentSim};
use occgrid::scenes::doorway::DoorwayScene;
use occgrid::scenes::paths::{LapPath, WalkerParams};
use occgrid::scenes::table::TableScene;
use occgrid::sensors::lidar::Lidar;
use occgrid::sensors::odometry::OdometryParams;
use occgrid::world::{Rect, World};
use properties_support::*;
use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::sync::OnceLock;

/// One arbitrary value for whichever field a mutation sets.
#[derive(Debug, Clone, Copy)]
struct Value {
    real: f64,
    count: usize,
}

fn value() -> impl Strategy<Value = Value> {
    (wild_f64(), wild_size()).prop_map(|(real, count)| Value { real, count })
}

/// A change of one field, and the names an error about it may use (the
/// field itself, or the derived quantity it broke).
struct Mutation<S> {
    names: &'static [&'static str],
    apply: fn(&mut S, Value),
}

macro_rules! mutation {
    ($names:expr, |$s:ident, $v:ident| $body:expr) => {
        Mutation {
            names: $names,
            apply: |$s, $v| {
                $body;
            },
        }
    };
}

#[track_caller]
fn assert_sane(grid: &LogOddsGrid) {
    let c = grid.clamp();
    for (i, &l) in grid.log_odds().iter().enumerate() {
        assert!(
            l.is_finite() && l.abs() <= c,
            "cell {i} holds {l} (clamp {c})"
        );
    }
}

fn doorway_mutations() -> Vec<Mutation<DoorwayScene>> {
    vec![
        mutation!(&["min_x", "max_x", "width x height", "origin"], |s, v| s
            .min_x =
            v.real),
        mutation!(&["max_y", "min_y", "width x height", "origin"], |s, v| s
            .max_y =
            v.real),
        mutation!(
            &["resolution", "width x height", "beams x sub_rays"],
            |s, v| s.resolution = v.real
        ),
        mutation!(&["prior"], |s, v| s.prior = v.real),
        mutation!(&["sonar.beta_deg"], |s, v| s.sonar.beta_deg = v.real),
        mutation!(&["sonar.z_max", "beams x sub_rays"], |s, v| s.sonar.z_max =
            v.real),
        mutation!(&["sonar.sigma"], |s, v| s.sonar.sigma = v.real),
        mutation!(&["sonar.count"], |s, v| s.sonar.count = v.count),
        mutation!(&["sonar.sub_rays", "beams x sub_rays"], |s, v| s
            .sonar
            .sub_rays =
            v.count),
        mutation!(&["pose.x"], |s, v| s.poses[1].x = v.real),
        mutation!(&["pose.theta"], |s, v| s.poses[0].theta = v.real),
        mutation!(&["poses"], |s, v| s.poses.truncate(v.count % 3)),
        mutation!(&["bearings_deg"], |s, v| s.bearings_deg[2] = v.real),
        mutation!(&["bearings_deg", "poses x bearings_deg"], |s, v| s
            .bearings_deg
            .resize(v.count.min(5000), 1.0)),
        mutation!(&["walls"], |s, v| s.walls[0].max_y = v.real),
        mutation!(&["walls"], |s, v| s.door.min_x = v.real),
        mutation!(&[], |s, v| s.seed = v.count as u64),
    ]
}

fn table_mutations() -> Vec<Mutation<TableScene>> {
    vec![
        mutation!(
            &[
                "room[0]",
                "resolution",
                "width x height",
                "wall",
                "table.center",
                "path"
            ],
            |s, v| s.room[0] = v.real
        ),
        mutation!(&["wall", "path"], |s, v| s.wall = v.real),
        mutation!(&["resolution", "width x height"], |s, v| s.resolution =
            v.real),
        mutation!(&["table.center"], |s, v| s.table.center[0] = v.real),
        mutation!(
            &["table.size[1]", "table.leg_inset", "table.center", "path"],
            |s, v| s.table.size[1] = v.real
        ),
        mutation!(&["table.leg", "table.leg_inset", "resolution"], |s, v| s
            .table
            .leg =
            v.real),
        mutation!(&["table.leg_inset"], |s, v| s.table.leg_inset = v.real),
        mutation!(&["path"], |s, v| s.path[3][0] = v.real),
        mutation!(&["path"], |s, v| s.path.truncate(v.count % 3)),
        mutation!(&["step"], |s, v| s.step = v.real),
        mutation!(&["laps", "step"], |s, v| s.laps = v.count),
        mutation!(&["sonar.count"], |s, v| s.sonar.count = v.count),
        mutation!(&["sonar.beta_deg"], |s, v| s.sonar.beta_deg = v.real),
        mutation!(&["sonar.z_max"], |s, v| s.sonar.z_max = v.real),
        mutation!(&["sonar.sigma"], |s, v| s.sonar.sigma = v.real),
        mutation!(&["sonar.sub_rays"], |s, v| s.sonar.sub_rays = v.count),
        mutation!(&["lidar.beams"], |s, v| s.lidar.beams = v.count),
        mutation!(&["lidar.z_max"], |s, v| s.lidar.z_max = v.real),
        mutation!(&["lidar.sigma"], |s, v| s.lidar.sigma = v.real),
        mutation!(&["lidar.first_bearing"], |s, v| s.lidar.first_bearing =
            v.real),
        mutation!(&[], |s, v| s.seed = v.count as u64),
    ]
}

fn model_mutations() -> Vec<Mutation<FusionModels>> {
    vec![
        mutation!(&["sonar_p_occ"], |m, v| m.sonar_p_occ = v.real),
        mutation!(&["sonar_p_free"], |m, v| m.sonar_p_free = v.real),
        mutation!(&["alpha"], |m, v| m.sonar_alpha = v.real),
        mutation!(&["lidar_p_occ"], |m, v| m.lidar_p_occ = v.real),
        mutation!(&["lidar_p_free"], |m, v| m.lidar_p_free = v.real),
        mutation!(&["alpha"], |m, v| m.lidar_alpha = v.real),
        mutation!(&["prior", "clamp"], |m, v| m.prior = v.real),
        mutation!(&["clamp"], |m, v| m.clamp = v.real),
    ]
}

fn weaver_mutations() -> Vec<Mutation<WeaverSettings>> {
    vec![
        mutation!(&["laps"], |s, v| s.laps = v.count),
        mutation!(&["panes[0].clamp"], |s, v| s.panes[0].clamp = v.real),
        mutation!(&["panes[1].strength"], |s, v| s.panes[1].strength = v.real),
        mutation!(&["alpha"], |s, v| s.hand_crafted.alpha = v.real),
        mutation!(&["beta"], |s, v| s.hand_crafted.beta = v.real),
        mutation!(&["z_max"], |s, v| s.hand_crafted.z_max = v.real),
        mutation!(&["l_occ"], |s, v| s.hand_crafted.l_occ = v.real),
        mutation!(&["l_free"], |s, v| s.hand_crafted.l_free = v.real),
        mutation!(&["l0", "l_occ", "l_free"], |s, v| s.hand_crafted.l0 =
            v.real),
        mutation!(&["triplets"], |s, v| s.training.triplets = v.count),
        mutation!(&["epochs"], |s, v| s.training.epochs = v.count),
        mutation!(&["learning_rate"], |s, v| s.training.learning_rate = v.real),
        mutation!(&["half_width"], |s, v| s.training.half_width = v.real),
        mutation!(&["sub_rays"], |s, v| s.training.sub_rays = v.count),
        mutation!(&["resolution"], |s, v| s.training.resolution = v.real),
        mutation!(&["z_max", "resolution"], |s, v| s.training.sensor.z_max =
            v.real),
        mutation!(
            &["width", "tracked", "path.waypoints", "surveyed"],
            |s, v| s.scene.width = v.count
        ),
        mutation!(
            &["height", "tracked", "path.waypoints", "surveyed"],
            |s, v| s.scene.height = v.count
        ),
        mutation!(
            &[
                "resolution",
                "tracked",
                "path.waypoints",
                "surveyed",
                "width"
            ],
            |s, v| s.scene.resolution = v.real
        ),
        mutation!(&["scan_rate", "laps", "path"], |s, v| s.scene.scan_rate =
            v.real),
        mutation!(&["lidar.beams", "laps"], |s, v| s.scene.lidar.beams =
            v.count),
        mutation!(&["lidar.z_max"], |s, v| s.scene.lidar.z_max = v.real),
        mutation!(&["lidar.sigma"], |s, v| s.scene.lidar.sigma = v.real),
        mutation!(&["lidar.first_bearing"], |s, v| s
            .scene
            .lidar
            .first_bearing = v.real),
        mutation!(&["odometry.alpha[2]"], |s, v| s.scene.odometry.alpha[2] =
            v.real),
        mutation!(&["odometry.heading_drift"], |s, v| s
            .scene
            .odometry
            .heading_drift =
            v.real),
        mutation!(&["odometry.turn_scale"], |s, v| s
            .scene
            .odometry
            .turn_scale = v.real),
        mutation!(&["person.size"], |s, v| s.scene.person.size = v.real),
        mutation!(&["person.to.x"], |s, v| s.scene.person.to[0] = v.real),
        mutation!(&["person.speed"], |s, v| s.scene.person.speed = v.real),
        mutation!(&["person.pause"], |s, v| s.scene.person.pause = v.real),
        mutation!(&["person.phase"], |s, v| s.scene.person.phase = v.real),
        mutation!(&["path.speed", "path"], |s, v| s.scene.path.speed = v.real),
        mutation!(&["path.turn_rate", "path"], |s, v| s.scene.path.turn_rate =
            v.real),
        mutation!(
            &["path.waypoints[1]", "path.waypoints[2]", "path"],
            |s, v| s.scene.path.waypoints[1][0] = v.real
        ),
        mutation!(&["path.waypoints"], |s, v| s
            .scene
            .path
            .waypoints
            .truncate(v.count % 2)),
        mutation!(&["tracked[1].at"], |s, v| s.scene.tracked[1].at[0] = v.real),
        mutation!(&["obstacles[4].min_x"], |s, v| s.scene.obstacles[4].min_x =
            v.real),
        mutation!(&["surveyed"], |s, v| s.scene.surveyed.max_x = v.real),
        mutation!(&["hidden[0].max_y"], |s, v| s.scene.hidden[0].max_y =
            v.real),
        mutation!(&["rooms[2].area.min_y"], |s, v| s.scene.rooms[2]
            .area
            .min_y = v.real),
        mutation!(&["closet.min_x"], |s, v| s.scene.closet.min_x = v.real),
        mutation!(&[], |s, v| s.seed = v.count as u64),
    ]
}

/// A learned model for the Weaver runs, built directly (training is not
/// what these properties are about).
fn learned() -> &'static LearnedInverse {
    static L: OnceLock<LearnedInverse> = OnceLock::new();
    L.get_or_init(|| {
        let mut w = [0.0; FEATURES];
        w[0] = -0.4;
        w[3] = 1.5;
        w[9] = -0.8;
        LearnedInverse::new(
            FeatureFrame {
                z_max: 8.0,
                half_width: 2.5f64.to_radians(),
            },
            w,
        )
        .unwrap()
    })
}

/// The chapter's Map Weaver run, a few scans in.
fn weaver() -> Weaver {
    static W: OnceLock<Weaver> = OnceLock::new();
    W.get_or_init(|| {
        let mut w = Weaver::with_learned(WeaverSettings::default(), learned().clone()).unwrap();
        w.advance(30).unwrap();
        w
    })
    .clone()
}

/// Everything a page reads from a run: equal before and after a refused
/// call means the call changed nothing visible.
fn weaver_state(w: &Weaver) -> String {
    format!(
        "{:?}|{:?}|{:?}|{:?}|{:?}",
        w.readout(),
        w.settings(),
        w.grid(0).unwrap(),
        w.grid(1).unwrap(),
        w.view(1).unwrap().rgba()
    )
}

fn fusion_state(f: &TableFusion) -> String {
    format!(
        "{:?}|{:?}|{:?}|{:?}|{:?}|{:?}",
        f.readout(),
        f.sonar(),
        f.lidar(),
        f.summed(),
        f.fused(),
        f.run().lidar()
    )
}

proptest! {
    #![proptest_config(config(512))]

    #[test]
    fn the_world_from_any_boxes_casts_ranges_within_z_max(
        boxes in prop::collection::vec(prop::array::uniform4(wild_f64()), 0..4),
        x in wild_f64(), y in wild_f64(), angle in wild_f64(),
        z_max in prop_oneof![3 => 0.1..20.0f64, 1 => wild_f64()],
        half in wild_f64(), rays in wild_size(),
    ) {
        let g = GridGeometry::new(30, 20, 0.1, -0.5, 0.2).unwrap();
        let rects: Vec<Rect> = boxes.iter().map(|b| Rect::new(b[0], b[1], b[2], b[3])).collect();
        let mut world = World::from_boxes(g, &rects);
        world.fill(&Rect::new(0.0, 0.0, 1.0, 1.0), true);
        let z = world.cast(x, y, angle, z_max);
        if z_max.is_finite() && z_max > 0.0 {
            prop_assert!((0.0..=z_max).contains(&z), "cast {z} outside [0, {z_max}]");
        }
        match world.cast_cone(x, y, angle, half, rays.min(64), z_max) {
            Ok(c) => if z_max.is_finite() && z_max > 0.0 {
                prop_assert!((0.0..=z_max).contains(&c) && c <= z, "cone {c} vs ray {z}");
            },
            Err(e) => assert_names_one_of(&e, &["half_width", "sub_rays"]),
        }
    }

    #[test]
    fn robot_parts_are_checked_and_give_finite_poses_and_ranges(
        speed in wild_positive(), turn_rate in wild_positive(), t in wild_f64(),
        corner in wild_f64(),
        beams in prop_oneof![3 => 1usize..100, 1 => wild_size()],
        z_max in wild_positive(), sigma in wild_positive(), first in wild_f64(),
        alpha in prop::array::uniform4(prop_oneof![3 => 0.0..0.2f64, 1 => wild_f64()]),
        drift in wild_f64(), turn_scale in prop_oneof![3 => -0.5..0.5f64, 1 => wild_f64()],
        size in wild_positive(), phase in wild_probability(), pause in wild_positive(),
        seed in any::<u64>(),
    ) {
        let lap = LapPath { waypoints: vec![[0.5, 0.5], [2.5, 0.5], [corner, 1.5]], speed, turn_rate };
        match lap.validate() {
            Ok(()) => {
                let p = lap.pose_at(t);
                if t.is_finite() && lap.lap_seconds().is_finite() {
                    prop_assert!(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite(), "{p:?} at {t}");
                }
            }
            Err(e) => assert_names_one_of(&e, &["path.waypoints", "path.speed", "path.turn_rate"]),
        }
        let lidar = Lidar { beams, z_max, sigma, first_bearing: first };
        let mut rng = StdRng::seed_from_u64(seed);
        match lidar.validate() {
            Ok(()) => {
                let g = GridGeometry::new(30, 20, 0.1, 0.0, 0.0).unwrap();
                let world = World::from_boxes(g, &[Rect::new(2.0, 0.0, 2.2, 2.0)]);
                let mut ranges = Vec::new();
                lidar.scan_into(&world, &Pose::new(1.0, 1.0, 0.3).unwrap(), &mut rng, &mut ranges);
                prop_assert_eq!(ranges.len(), beams);
                prop_assert!(ranges.iter().all(|r| (0.0..=z_max).contains(r)), "{ranges:?}");
            }
            Err(e) => assert_names(&e, "lidar."),
        }
        let odo = OdometryParams { alpha, heading_drift: drift, turn_scale };
        match odo.validate() {
            Ok(()) => {
                let a = Pose::new(1.0, 1.0, 0.2).unwrap();
                let b = Pose::new(1.3, 1.1, 0.5).unwrap();
                let p = odo.dead_reckon(&a, &a, &b, &mut rng);
                prop_assert!(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite(), "{p:?}");
            }
            Err(e) => assert_names(&e, "odometry."),
        }
        let walker = WalkerParams { size, from: [1.0, 1.0], to: [corner, 2.0], speed, pause, phase };
        match walker.validate() {
            Ok(()) => {
                let [cx, cy] = walker.center_at(t);
                prop_assert!(!t.is_finite() || (cx.is_finite() && cy.is_finite()), "({cx}, {cy}) at {t}");
            }
            Err(e) => assert_names(&e, "person."),
        }
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn a_doorway_scene_with_one_field_changed_runs_sanely_or_names_that_field(
        k in 0usize..16, v in value(),
    ) {
        let mutations = doorway_mutations();
        let m = &mutations[k % mutations.len()];
        let mut scene = DoorwayScene::standard();
        (m.apply)(&mut scene, v);
        let built = DoorwaySweep::new(&scene).and_then(|sweep| Ok((sweep, occgrid::apps::doorway_trap::map_search(&scene)?)));
        match built {
            Ok((mut sweep, mut search)) => {
                while sweep.step().is_some() {}
                search.run(20);
                assert_sane(sweep.grid());
                prop_assert!(search.objective().is_finite());
                let report = occgrid::apps::doorway_trap::door_report(&scene, sweep.grid(), search.occupied()).unwrap();
                prop_assert!(report.sweep_closed <= report.door_cells);
                let view = occgrid::apps::doorway_trap::view(&scene).unwrap();
                prop_assert_eq!(view.beams.len(), scene.poses.len() * scene.bearings_deg.len());
                let wrong = vec![true; search.occupied().len() + 1];
                let e = occgrid::apps::doorway_trap::door_report(&scene, sweep.grid(), &wrong).unwrap_err();
                assert_names(&e, "map");
            }
            Err(e) => {
                prop_assert!(!m.names.is_empty(), "a valid change was refused: {e}");
                assert_names_one_of(&e, m.names);
            }
        }
    }

    #[test]
    fn map_weaver_settings_with_one_field_changed_run_sanely_or_name_that_field(
        k in 0usize..64, v in value(),
    ) {
        let mutations = weaver_mutations();
        let m = &mutations[k % mutations.len()];
        let mut settings = WeaverSettings::default();
        (m.apply)(&mut settings, v);
        match Weaver::with_learned(settings, learned().clone()) {
            Ok(mut w) => {
                w.advance(3).unwrap();
                for pane in 0..2 {
                    assert_sane(w.grid(pane).unwrap());
                    let o = w.overlay(pane).unwrap();
                    prop_assert!(o.beams.iter().all(|b| !b.is_nan()));
                }
                let r = w.readout();
                for p in &r.panes {
                    prop_assert!(p.entropy_bits.is_finite() && (0.0..=1.0).contains(&p.brier));
                }
            }
            Err(e) => {
                prop_assert!(!m.names.is_empty(), "a valid change was refused: {e}");
                assert_names_one_of(&e, m.names);
            }
        }
    }

    #[test]
    fn map_weaver_setters_refuse_bad_values_and_leave_the_run_as_it_was(
        op in 0usize..8, pane in prop_oneof![3 => 0usize..2, 1 => wild_size()],
        x in wild_f64(), col in wild_size(), row in wild_size(), model in any::<bool>(),
    ) {
        let mut w = weaver();
        let before = weaver_state(&w);
        let result = match op {
            0 => w.set_clamp(pane, x),
            1 => w.set_strength(pane, x),
            2 => w.set_model(pane, if model { ModelKind::Learned } else { ModelKind::HandCrafted }),
            3 => w.set_pose_source(pane, if model { PoseSource::DeadReckoning } else { PoseSource::Oracle }),
            4 => w.cell_info(pane, col, row).map(|c| {
                if let Some(c) = c { assert!(c.cell.p.is_finite() && c.cell.l.is_finite()); }
            }),
            5 => w.overlay(pane).map(drop),
            6 => w.entropy_curve(pane).and(w.brier_curve(pane)).and(w.tracked_history(pane)).map(drop),
            _ => { w.record_frame_ms(x); Ok(()) }
        };
        match result {
            Ok(()) => {
                for k in 0..2 { assert_sane(w.grid(k).unwrap()); }
                w.advance(2).unwrap();
                for k in 0..2 { assert_sane(w.grid(k).unwrap()); }
                if let Some(ms) = w.readout().frame_ms { prop_assert!(ms.is_finite() && ms >= 0.0); }
            }
            Err(e) => {
                assert_names_one_of(&e, &["pane", "panes["]);
                prop_assert_eq!(weaver_state(&w), before, "a refused call changed the run");
            }
        }
    }

    #[test]
    fn an_apartment_scene_with_one_field_changed_simulates_ranges_within_z_max(
        k in 0usize..64, v in value(), seed in any::<u64>(), person in any::<bool>(),
    ) {
        let mutations = weaver_mutations();
        let m = &mutations[k % mutations.len()];
        let mut settings = WeaverSettings::default();
        (m.apply)(&mut settings, v);
        let scene: ApartmentScene = settings.scene;
        match ApartmentSim::new(scene.clone(), seed, person) {
            Ok(mut sim) => {
                let z_max = scene.lidar.z_max;
                for _ in 0..3 {
                    let s = sim.next_scan();
                    prop_assert_eq!(s.ranges.len(), scene.lidar.beams);
                    prop_assert!(s.ranges.iter().all(|r| (0.0..=z_max).contains(r)));
                    prop_assert!(Pose::new(s.odometry.x, s.odometry.y, s.odometry.theta).is_ok());
                }
                let cells = scene.tracked_cells().unwrap();
                prop_assert!(cells.iter().all(|&i| i < scene.geometry().unwrap().len()));
            }
            Err(e) => assert_names_one_of(&e, m.names),
        }
    }
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn a_table_scene_or_model_with_one_field_changed_runs_sanely_or_names_that_field(
        k in 0usize..28, v in value(), beams in prop_oneof![3 => 1.0..400.0f64, 1 => wild_f64()],
    ) {
        let (scenes, models) = (table_mutations(), model_mutations());
        let mut scene = TableScene::default();
        let mut models_v = FusionModels::default();
        let names = if k < scenes.len() {
            (scenes[k].apply)(&mut scene, v);
            scenes[k].names
        } else {
            let m = &models[(k - scenes.len()) % models.len()];
            (m.apply)(&mut models_v, v);
            m.names
        };
        if let Err(e) = scene.validate().and_then(|()| models_v.validate(&scene)) {
            prop_assert!(!names.is_empty(), "a valid change was refused: {e}");
            assert_names_one_of(&e, names);
            return Ok(());
        }
        // Valid: build it if the run is small enough for a debug test.
        let per_step = scene.sonar.count * scene.sonar.sub_rays + scene.lidar.beams;
        if per_step * 100 * scene.laps > 200_000 {
            return Ok(());
        }
        let mut f = TableFusion::with_models(&scene, models_v).unwrap();
        f.step();
        f.step();
        for g in [f.sonar(), f.lidar(), f.summed(), f.fused()] {
            assert_sane(g);
        }
        let r = f.readout();
        for m in [r.footprint.sonar, r.footprint.lidar, r.footprint.max, r.footprint.sum] {
            prop_assert!((0.0..=1.0).contains(&m));
        }
        // A bad beam count from the slider is refused without a trace.
        let before = fusion_state(&f);
        let whole = beams.is_finite() && beams >= 0.0 && beams.fract() == 0.0 && beams <= 1e9;
        if whole {
            match f.set_lidar_beams(beams as usize) {
                Ok(()) => {
                    assert_sane(f.lidar());
                    prop_assert_eq!(f.run().lidar()[0].len(), beams as usize);
                }
                Err(e) => {
                    assert_names(&e, "lidar.beams");
                    prop_assert_eq!(fusion_state(&f), before);
                }
            }
        }
    }
}
