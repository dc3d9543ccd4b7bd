#![cfg(not(target_arch = "wasm32"))]
//! Sensor fusion without a long first call (eq. 9.9 on the table scene;
//! docs/ARCHITECTURE.md, "Sessions and panes"): the run simulates each scan
//! when a step first needs it, and a changed LiDAR beam count is rebuilt in
//! the bounded `work` calls rather than at once. Both give the scans and the
//! maps of the eager run, bit for bit.

use occgrid::apps::sensor_fusion::{FusionModels, TableFusion};
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::mapping::sweep::sweep_scan;
use occgrid::mapping::traversal::RayMapper;
use occgrid::scenes::table::{TableRun, TableScene};
use occgrid::sensors::Scan;

/// Two scans are the same reading for reading, bit for bit.
fn same_scan(a: &Scan, b: &Scan, what: &str) {
    assert_eq!(a.pose(), b.pose(), "{what}: pose");
    let bits = |s: &Scan| -> Vec<(u64, u64)> {
        s.ranges()
            .iter()
            .zip(s.bearings())
            .map(|(z, b)| (z.to_bits(), b.to_bits()))
            .collect()
    };
    assert_eq!(bits(a), bits(b), "{what}: ranges and bearings");
}

/// The scenes compared: the chapter's, and one with two laps, another seed
/// and a coarse LiDAR.
fn scenes() -> Vec<TableScene> {
    let mut other = TableScene {
        laps: 2,
        seed: 3,
        ..TableScene::default()
    };
    other.lidar.beams = 90;
    vec![TableScene::default(), other]
}

#[test]
fn a_lazily_built_run_simulates_the_eager_scans_one_by_one() {
    for scene in scenes() {
        let eager = scene.build().unwrap();
        let mut lazy = scene.start().unwrap();
        assert_eq!(lazy.len(), eager.len());
        assert_eq!(lazy.simulated(), 0, "no scan before a step asks for it");
        assert_eq!(lazy.poses(), eager.poses());
        assert_eq!(lazy.footprint(), eager.footprint());
        for k in 0..eager.len() {
            let cost = lazy.simulate_through(k + 1).unwrap();
            assert!(cost > 0, "scan {k} was simulated");
            assert_eq!(lazy.simulated(), k + 1);
            same_scan(&lazy.sonar()[k], &eager.sonar()[k], &format!("sonar {k}"));
            same_scan(&lazy.lidar()[k], &eager.lidar()[k], &format!("lidar {k}"));
            // Asking again simulates nothing more.
            assert_eq!(lazy.simulate_through(k + 1).unwrap(), 0);
        }
        assert_eq!(lazy, eager, "the whole run, noise streams included");
    }
}

#[test]
fn a_restarted_lidar_is_simulated_again_as_a_run_that_had_it_all_along() {
    let scene = TableScene::default();
    let mut run = scene.start().unwrap();
    run.simulate_through(30).unwrap();
    run.restart_lidar(45).unwrap();
    assert_eq!((run.sonar().len(), run.lidar().len()), (30, 0));
    run.simulate_through(run.len()).unwrap();
    let fresh = scene.with_lidar_beams(45).unwrap().build().unwrap();
    assert_eq!(run, fresh);
    // A refused beam count leaves the run as it was.
    let before = run.clone();
    assert!(run
        .restart_lidar(0)
        .unwrap_err()
        .to_string()
        .contains("lidar.beams"));
    assert_eq!(run, before);
}

/// The three maps of an eager run integrated step by step with the
/// fusion's mappers and models: the maps the session must show.
fn replayed(run: &TableRun, steps: usize) -> [LogOddsGrid; 3] {
    let models = FusionModels::default();
    let scene = run.scene();
    let (sonar_model, lidar_model) = (
        models.sonar_model(scene).unwrap(),
        models.lidar_model(scene).unwrap(),
    );
    let settings = FilterSettings {
        prior: models.prior,
        clamp: models.clamp,
    };
    let fresh = LogOddsGrid::new(*run.geometry(), settings).unwrap();
    let [mut sonar, mut lidar, mut summed] = [fresh.clone(), fresh.clone(), fresh];
    let (mut ray, mut summed_ray) = (RayMapper::new(), RayMapper::new());
    for k in 0..steps {
        let (s, l) = (&run.sonar()[k], &run.lidar()[k]);
        sweep_scan(&mut sonar, &sonar_model, s);
        ray.integrate(&mut lidar, &lidar_model, l);
        sweep_scan(&mut summed, &sonar_model, s);
        summed_ray.integrate(&mut summed, &lidar_model, l);
    }
    [sonar, lidar, summed]
}

fn shows(f: &TableFusion, maps: &[LogOddsGrid; 3]) {
    assert_eq!(f.sonar(), &maps[0]);
    assert_eq!(f.lidar(), &maps[1]);
    assert_eq!(f.summed(), &maps[2]);
}

#[test]
fn the_session_simulates_a_scan_only_when_a_step_reaches_it_and_maps_the_eager_scans() {
    for scene in scenes() {
        let eager = scene.build().unwrap();
        let mut f = TableFusion::new(&scene).unwrap();
        assert_eq!(
            f.readout().scans_simulated,
            0,
            "a new session simulated no scan"
        );
        let one_step = f.work(1, u64::MAX);
        assert_eq!(f.readout().scans_simulated, 1);
        // The first call's budget is spent on its own step's scans and
        // maps, not on the rest of the lap.
        let mut calls = 1;
        loop {
            let r = f.work(3, one_step.cell_visits);
            if r.steps == 0 && !r.under_way {
                break;
            }
            calls += 1;
            assert_eq!(f.readout().scans_simulated, r.step, "call {calls}");
        }
        assert!(calls > eager.len() / 3, "{calls} calls");
        shows(&f, &replayed(&eager, eager.len()));
    }
}

#[test]
fn a_staged_beam_count_does_no_work_and_the_budgeted_calls_rebuild_it_first() {
    let scene = TableScene::default();
    let mut f = TableFusion::new(&scene).unwrap();
    let step_cost = f.work(1, u64::MAX).cell_visits;
    f.work(59, u64::MAX);
    assert_eq!(f.steps_done(), 60);

    f.stage_lidar_beams(12).unwrap();
    let r = f.readout();
    assert_eq!((r.step, r.rebuilding, r.lidar_beams), (60, 60, 12));
    // Staged, the LiDAR's maps are at the prior: the call integrated nothing.
    let m = FusionModels::default();
    let settings = FilterSettings {
        prior: m.prior,
        clamp: m.clamp,
    };
    let empty = LogOddsGrid::new(*f.run().geometry(), settings).unwrap();
    assert_eq!((f.lidar(), f.summed()), (&empty, &empty));

    // Each call rebuilds within its budget (and one piece of a step), and
    // asks for new steps in vain until the rebuild is done.
    // A budget of 1 does one piece of a rebuilt step (its LiDAR scan
    // simulated, the LiDAR's raster, a band of the sonar's sweep of the
    // summed map, the LiDAR's raster into it), and nothing shown changes
    // until the step is whole.
    let shown = (f.lidar().clone(), f.summed().clone(), f.readout());
    let (mut first, mut pieces) = (0, 0);
    loop {
        let w = f.work(4, 1);
        pieces += 1;
        first += w.cell_visits;
        assert_eq!(w.steps, 0);
        if w.rebuilt == 1 {
            assert_eq!((w.rebuilding, w.under_way), (59, false));
            break;
        }
        assert_eq!((w.rebuilt, w.rebuilding, w.under_way), (0, 60, true));
        assert_eq!(
            (f.lidar(), f.summed(), f.readout()),
            (&shown.0, &shown.1, shown.2)
        );
    }
    assert!(pieces > 3, "a rebuilt step in {pieces} pieces");
    // Then two such steps' work per call.
    let budget = 2 * first;
    let (mut calls, mut rebuilt) = (pieces, 1);
    while f.rebuilding() > 0 {
        let before = f.rebuilding();
        let w = f.work(4, budget);
        calls += 1;
        rebuilt += w.rebuilt;
        assert!(
            (w.rebuilt >= 1 || w.under_way) && w.cell_visits < budget + step_cost,
            "{w:?}"
        );
        assert_eq!(w.rebuilding, before - w.rebuilt);
        if w.rebuilding > 0 {
            assert_eq!(
                (w.steps, w.step),
                (0, 60),
                "no new step before the rebuild ends"
            );
        }
    }
    assert_eq!(rebuilt, 60);
    assert!(calls >= 20, "the rebuild of 60 steps took {calls} calls");
    let fresh = scene.with_lidar_beams(12).unwrap().build().unwrap();
    let now = f.steps_done();
    shows(&f, &replayed(&fresh, now));
    let mut all_along = TableFusion::new(&scene.with_lidar_beams(12).unwrap()).unwrap();
    all_along.work(now, u64::MAX);
    assert_eq!(f.readout(), all_along.readout());
    assert_eq!(f.fused_probabilities(), all_along.fused_probabilities());
    while !f.work(usize::MAX, budget).done {}
    shows(&f, &replayed(&fresh, fresh.len()));
}

#[test]
fn a_rebuild_under_way_is_finished_by_the_unbounded_calls_and_undone_by_reset() {
    let scene = TableScene::default();
    let mut stepped = TableFusion::new(&scene).unwrap();
    stepped.work(20, u64::MAX);
    let mut reset = stepped.clone();
    let mut ran = stepped.clone();
    stepped.stage_lidar_beams(24).unwrap();
    assert!(stepped.step());
    assert_eq!((stepped.steps_done(), stepped.rebuilding()), (21, 0));
    let fresh = scene.with_lidar_beams(24).unwrap().build().unwrap();
    shows(&stepped, &replayed(&fresh, 21));

    ran.stage_lidar_beams(24).unwrap();
    ran.run_to_end();
    shows(&ran, &replayed(&fresh, fresh.len()));

    reset.stage_lidar_beams(24).unwrap();
    reset.reset();
    assert_eq!((reset.steps_done(), reset.rebuilding()), (0, 0));
    reset.run_to_end();
    shows(&reset, &replayed(&fresh, fresh.len()));
}

#[test]
fn a_refused_beam_count_stages_nothing() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    f.work(10, u64::MAX);
    let before = f.clone();
    for beams in [0, 4097, usize::MAX] {
        let e = f.stage_lidar_beams(beams).unwrap_err().to_string();
        assert!(e.contains("lidar.beams"), "{e}");
        assert_eq!(f.readout(), before.readout());
        assert_eq!(f.lidar(), before.lidar());
        assert_eq!(f.run(), before.run());
    }
}
