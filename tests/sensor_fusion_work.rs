#![cfg(not(target_arch = "wasm32"))]
//! Sensor fusion in bounded calls (eq. 9.9 on the table scene): a page
//! playing the lap asks the core for a frame's work with a budget of cell
//! visits, a call stops within a step once its budget is spent (past it by
//! at most one piece), what it shows changes a whole step at a time, and
//! the maps it ends with are those of the same steps taken one at a time
//! (docs/ARCHITECTURE.md, "Sessions and panes").

use occgrid::apps::sensor_fusion::TableFusion;
use occgrid::scenes::table::TableScene;

/// The four maps and the readout, for comparing two runs.
fn same_maps(a: &TableFusion, b: &TableFusion) {
    assert_eq!(a.sonar(), b.sonar());
    assert_eq!(a.lidar(), b.lidar());
    assert_eq!(a.summed(), b.summed());
    assert_eq!(a.fused(), b.fused());
    assert_eq!(a.fused_probabilities(), b.fused_probabilities());
    assert_eq!(a.readout(), b.readout());
}

#[test]
fn a_small_budget_stops_within_a_step_and_shows_only_whole_steps() {
    let scene = TableScene::default();
    let mut worked = TableFusion::new(&scene).unwrap();
    let mut stepped = TableFusion::new(&scene).unwrap();
    // A step sweeps every cell for the sonar twice (its own map and the
    // summed one): a budget of a third of a sweep stops within a step.
    let cells = worked.sonar().geometry().len() as u64;
    let budget = cells / 3;
    // The largest piece: a budget of one visit does one piece a call.
    let (mut probe, mut largest) = (worked.clone(), 0);
    loop {
        let r = probe.work(1, 1);
        if r.done {
            break;
        }
        largest = largest.max(r.cell_visits);
    }
    let (mut calls, mut within) = (0, 0);
    loop {
        let before = (worked.readout(), worked.fused_probabilities().to_vec());
        let r = worked.work(4, budget);
        if r.cell_visits == 0 {
            assert!(r.done);
            break;
        }
        calls += 1;
        assert!(r.steps <= 1, "call {calls}: {r:?}");
        assert!(r.cell_visits > 0, "call {calls} did nothing");
        if r.steps == 1 {
            stepped.step();
            same_maps(&worked, &stepped);
        } else {
            within += 1;
            assert!(r.under_way, "call {calls}: {r:?}");
            // Nothing shown moved: the maps are those of the whole steps.
            same_maps(&worked, &stepped);
            assert_eq!(worked.readout(), before.0, "call {calls}");
            assert_eq!(worked.fused_probabilities(), &before.1[..]);
        }
        // Past the budget by less than one piece: a band of rows of a sweep
        // (at most the rows the budget holds, at least one), a scan's
        // simulation, the LiDAR's raster.
        assert!(r.cell_visits < budget + largest, "call {calls}: {r:?}");
    }
    assert_eq!(worked.steps_done(), 81, "one lap of the default path");
    assert!(
        within >= 81,
        "{within} calls ended within a step, of {calls}"
    );
    assert!(!stepped.step(), "the stepped run is over too");
}

#[test]
fn a_call_goes_past_its_budget_by_at_most_one_piece() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    let mut probe = TableFusion::new(&TableScene::default()).unwrap();
    let one_step = probe.work(1, u64::MAX).cell_visits;
    // The largest piece: a budget of one visit does one piece a call.
    let mut largest = 0;
    while probe.steps_done() < 4 {
        largest = largest.max(probe.work(1, 1).cell_visits);
    }
    assert!(largest < one_step, "a piece {largest}, a step {one_step}");
    // Three and a half steps' worth: three steps whole, the fourth under
    // way when the budget is spent.
    let budget = one_step * 7 / 2;
    let r = f.work(100, budget);
    assert_eq!((r.steps, r.under_way), (3, true), "{r:?}");
    assert!(
        r.cell_visits >= budget && r.cell_visits < budget + largest,
        "{r:?}"
    );
    // The next call finishes the step under way first: the maps are those
    // of four steps.
    let r = f.work(1, u64::MAX);
    assert_eq!((r.steps, r.step, r.under_way), (1, 4, false));
    let mut g = TableFusion::new(&TableScene::default()).unwrap();
    for _ in 0..4 {
        g.step();
    }
    same_maps(&f, &g);
}

#[test]
fn a_step_under_way_is_the_next_step_and_is_dropped_by_reset_and_a_new_beam_count() {
    let scene = TableScene::default();
    let mut f = TableFusion::new(&scene).unwrap();
    f.work(5, u64::MAX);
    let r = f.work(1, 10);
    assert!(r.under_way && r.steps == 0, "{r:?}");
    // step() finishes it: one step more, no other.
    let mut stepped = f.clone();
    assert!(stepped.step());
    let mut g = TableFusion::new(&scene).unwrap();
    g.work(6, u64::MAX);
    same_maps(&stepped, &g);
    // run_to_end() counts it among the steps it took.
    let mut ran = f.clone();
    assert_eq!(ran.run_to_end(), 81 - 5);
    // A new beam count starts it again over the new LiDAR's maps.
    let mut restaged = f.clone();
    restaged.stage_lidar_beams(24).unwrap();
    restaged.run_to_end();
    let mut fresh = TableFusion::new(&scene.with_lidar_beams(24).unwrap()).unwrap();
    fresh.run_to_end();
    same_maps(&restaged, &fresh);
    // Reset drops it.
    f.reset();
    let r = f.work(1, u64::MAX);
    assert_eq!((r.steps, r.step), (1, 1));
    let mut one = TableFusion::new(&scene).unwrap();
    one.step();
    same_maps(&f, &one);
}

#[test]
fn the_steps_asked_for_bound_a_call_with_budget_to_spare() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    let r = f.work(3, u64::MAX);
    assert_eq!((r.steps, r.step, r.done), (3, 3, false));
    let mut g = TableFusion::new(&TableScene::default()).unwrap();
    for _ in 0..3 {
        g.step();
    }
    same_maps(&f, &g);
    // Asked for none: nothing moves.
    let r = f.work(0, u64::MAX);
    assert_eq!((r.steps, r.cell_visits, r.step), (0, 0, 3));
    same_maps(&f, &g);
}

#[test]
fn a_budget_of_zero_still_moves_and_the_end_of_the_lap_changes_nothing() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    let r = f.work(10, 0);
    assert!(
        r.cell_visits > 0 && r.under_way,
        "a budget of 0 counts as 1: {r:?}"
    );
    while !f.work(usize::MAX, u64::MAX).done {}
    let end = f.clone();
    let r = f.work(5, u64::MAX);
    assert_eq!((r.steps, r.cell_visits, r.done), (0, 0, true));
    same_maps(&f, &end);
}
