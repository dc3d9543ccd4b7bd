#![cfg(not(target_arch = "wasm32"))]
//! Table 9.3's search set up in calls of bounded work (`MapSearchSetup`,
//! and the doorway trap's `DoorwayTrapStart` around it): a call passes its
//! budget by at most one piece, and the search is the one `MapSearch::new`
//! builds in one call, bit for bit, before and after its climb.

use occgrid::apps::doorway_trap::{search_settings, DoorwayTrapSession, DoorwayTrapStart};
use occgrid::mapping::map_search::{MapSearch, MapSearchSetup};
use occgrid::scenes::doorway::DoorwayScene;

/// The doorway at `resolution` metres per cell.
fn scene(resolution: f64) -> DoorwayScene {
    DoorwayScene {
        resolution,
        ..DoorwayScene::standard()
    }
}

fn setup(scene: &DoorwayScene) -> MapSearchSetup {
    MapSearchSetup::new(
        scene.geometry().unwrap(),
        scene.beams().unwrap(),
        search_settings(scene),
    )
    .unwrap()
}

/// Everything a search holds, as text: floats print exactly, so equal
/// text means equal bits.
fn state(s: &MapSearch) -> String {
    format!("{s:?}")
}

#[test]
fn a_call_passes_its_budget_by_at_most_one_piece() {
    let scene = scene(0.02);
    // A budget of one unit: every call is one piece, the largest of which
    // bounds what a call may pass its budget by.
    let mut one = setup(&scene);
    let (mut pieces, mut largest, mut total) = (0u64, 0u64, 0u64);
    while !one.done() {
        let units = one.work(1);
        assert!(units > 0, "piece {pieces} did nothing");
        pieces += 1;
        largest = largest.max(units);
        total += units;
    }
    // A beam at a time, the transpose, the arrays, then bands of cells.
    let beams = scene.beams().unwrap().len() as u64;
    assert!(pieces > beams + 2, "{pieces} pieces");
    for budget in [1_000, 7_777, 60_000] {
        let mut s = setup(&scene);
        let (mut calls, mut spent) = (0, 0);
        while !s.done() {
            let units = s.work(budget);
            calls += 1;
            spent += units;
            assert!(
                units < budget + largest,
                "budget {budget}, call {calls}: {units}"
            );
            assert!(
                units >= budget || s.done(),
                "budget {budget}, call {calls} stopped at {units}"
            );
        }
        // The same pieces but the bands of gains, whose units are rounded up
        // per band: no more in all than one piece per call counted.
        assert!(
            spent <= total,
            "budget {budget}: {spent} units, {total} piece by piece"
        );
        assert!(calls > 1);
    }
}

#[test]
fn a_search_set_up_in_small_calls_is_the_one_call_search_bit_for_bit() {
    let scene = scene(0.025);
    let mut whole = MapSearch::new(
        scene.geometry().unwrap(),
        scene.beams().unwrap(),
        search_settings(&scene),
    )
    .unwrap();
    let mut s = setup(&scene);
    while !s.done() {
        s.work(333);
    }
    let mut staged = s.finish().unwrap();
    assert_eq!(state(&staged), state(&whole));
    whole.run(usize::MAX);
    staged.run(usize::MAX);
    assert!(staged.flips().len() > 3);
    assert_eq!(state(&staged), state(&whole));
}

#[test]
fn the_doorway_trap_started_in_calls_is_the_session_new_makes() {
    let scene = scene(0.05);
    let whole = DoorwayTrapSession::new(scene.clone()).unwrap();
    let mut start = DoorwayTrapStart::new(scene).unwrap();
    let mut calls = 0;
    while !start.done() {
        start.work(500);
        calls += 1;
    }
    assert!(calls > 3, "{calls} calls");
    let staged = start.finish().unwrap();
    assert_eq!(state(staged.search()), state(whole.search()));
    assert_eq!(staged.unreached_cells(), whole.unreached_cells());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    staged.map_render(&mut a).unwrap();
    whole.map_render(&mut b).unwrap();
    assert_eq!(a, b);
    assert_eq!(
        format!("{:?}", staged.sweep().grid()),
        format!("{:?}", whole.sweep().grid())
    );
}

#[test]
fn a_refused_scene_is_refused_before_any_work() {
    let mut bad = scene(0.1);
    bad.prior = f64::NAN;
    let e = DoorwayTrapStart::new(bad).err().unwrap().to_string();
    assert!(e.contains("prior"), "{e}");
    let e = MapSearchSetup::new(
        scene(0.1).geometry().unwrap(),
        Vec::new(),
        search_settings(&scene(0.1)),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("beams"), "{e}");
}
