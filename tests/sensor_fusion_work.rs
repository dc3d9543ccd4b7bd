#![cfg(not(target_arch = "wasm32"))]
//! Sensor fusion in bounded calls (eq. 9.9 on the table scene): a page
//! playing the lap asks the core for a frame's work with a budget of cell
//! visits, and the maps it ends with are those of the same steps taken one
//! at a time (docs/ARCHITECTURE.md, "Sessions and panes").

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
fn a_small_budget_takes_one_step_per_call_and_ends_with_the_stepped_maps() {
    let scene = TableScene::default();
    let mut worked = TableFusion::new(&scene).unwrap();
    let mut stepped = TableFusion::new(&scene).unwrap();
    // A step sweeps every cell for the sonar twice (its own map and the
    // summed one): a budget of one sweep is spent by the first step.
    let one_sweep = worked.sonar().geometry().len() as u64;
    let mut calls = 0;
    loop {
        let before = worked.steps_done();
        let r = worked.work(4, one_sweep);
        if r.steps == 0 {
            assert!(r.done);
            break;
        }
        calls += 1;
        assert_eq!(r.steps, 1, "call {calls}: the budget holds one step");
        assert_eq!(r.step, before + 1);
        assert!(r.cell_visits >= 2 * one_sweep, "call {calls}: {r:?}");
        stepped.step();
        same_maps(&worked, &stepped);
    }
    assert_eq!(calls, 81, "one lap of the default path");
    assert!(!stepped.step(), "the stepped run is over too");
}

#[test]
fn a_call_goes_past_its_budget_by_at_most_one_step() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    let mut probe = TableFusion::new(&TableScene::default()).unwrap();
    let one_step = probe.work(1, u64::MAX).cell_visits;
    // Three and a half steps' worth: the fourth step starts under budget
    // and is finished, and no fifth starts.
    let budget = one_step * 7 / 2;
    let r = f.work(100, budget);
    assert_eq!(r.steps, 4, "{r:?}");
    assert!(
        r.cell_visits >= budget && r.cell_visits < budget + 2 * one_step,
        "{r:?}"
    );
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
    assert_eq!(f.work(10, 0).steps, 1, "a budget of 0 counts as 1");
    while !f.work(usize::MAX, u64::MAX).done {}
    let end = f.clone();
    let r = f.work(5, u64::MAX);
    assert_eq!((r.steps, r.cell_visits, r.done), (0, 0, true));
    same_maps(&f, &end);
}
