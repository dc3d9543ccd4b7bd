#![cfg(not(target_arch = "wasm32"))]
//! Map Weaver's run made in calls of bounded work (`WeaverBuild`): each
//! call stops within one piece of its budget of cells, and the run is the
//! one made in one call, bit for bit.

use occgrid::apps::map_weaver::{
    MapperKind, ModelKind, Weaver, WeaverBuild, WeaverSettings, WeaverStart,
};
use occgrid::geometry::GridGeometry;
use occgrid::inverse::training::{self, TrainingConfig};
use occgrid::inverse::LearnedInverse;
use occgrid::world::{Rect, World};
use std::sync::OnceLock;

fn learned() -> LearnedInverse {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    LEARNED
        .get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0)
        .clone()
}

/// Two different panes: the sweep at the scene's resolution, and the
/// traversal of the learned model at the coarser one.
fn settings() -> WeaverSettings {
    let mut s = WeaverSettings {
        seed: 11,
        ..WeaverSettings::default()
    };
    s.panes[0].mapper = MapperKind::Sweep;
    s.panes[0].model = ModelKind::HandCrafted;
    s.panes[1].model = ModelKind::Learned;
    s.panes[1].resolution = Some(0.05);
    s
}

/// Everything a run holds, as text: floats print exactly, so two runs
/// with the same text hold the same bits.
fn state(w: &Weaver) -> String {
    format!("{w:?}")
}

#[test]
fn a_run_built_in_small_calls_is_the_one_call_run_bit_for_bit() {
    let one = Weaver::with_learned(settings(), learned()).unwrap();
    let mut build = WeaverBuild::new(settings(), learned()).unwrap();
    let mut calls = 0;
    // A budget that is no whole number of rows.
    while !build.work(997).unwrap().done {
        calls += 1;
    }
    assert!(calls > 10, "the maps took {calls} calls");
    let mut built = build.finish().unwrap();
    assert_eq!(state(&built), state(&one));
    // And they stay the same run as they map (untimed: a scan's time is
    // the clock's, not the run's).
    let mut one = one;
    one.set_clock(None);
    built.set_clock(None);
    one.advance(20).unwrap();
    built.advance(20).unwrap();
    assert_eq!(state(&built), state(&one));
}

#[test]
fn a_call_stops_within_one_piece_of_its_budget() {
    // The apartment at 256 x 256 cells (Map Weaver's largest scene is
    // 1024 x 1024: the same pieces, four times the rows).
    let mut s = settings();
    s.panes[1].resolution = None;
    s.scene.width = 256;
    s.scene.height = 256;
    s.scene.resolution = 12.0 / 256.0;
    let (w, n) = (256u64, 256 * 256u64);
    // The units: a cell of a view synced; of a truth drawn, an eighth; of
    // a view made, a quarter.
    let (truth_row, view) = (w / 8, n / 4);
    let budget = 3 * w + 17;
    let mut build = WeaverBuild::new(s.clone(), learned()).unwrap();
    let (mut calls, mut views, mut total) = (0, 0, 0);
    loop {
        let r = build.work(budget).unwrap();
        calls += 1;
        total += r.cells;
        assert!(r.cells > 0, "call {calls} did nothing");
        // A band of rows passes the budget by less than a row; a pane's
        // view made counts its cells, once per pane.
        if r.cells >= budget + w {
            views += 1;
            assert!(r.cells < budget + view, "call {calls}: {} units", r.cells);
        }
        if r.done {
            break;
        }
    }
    assert!(views <= 2, "{views} calls made a view");
    // Three truths drawn, two views made and synced.
    assert_eq!(total, 3 * truth_row * 256 + 2 * view + 2 * n);
    // The bands took as many calls as a budget each allows.
    assert!(
        calls as u64 >= (total - 2 * view) / (budget + w),
        "{calls} calls"
    );
    let one = Weaver::with_learned(s, learned()).unwrap();
    assert_eq!(state(&build.finish().unwrap()), state(&one));
    // Nothing left: one more call does no work.
    let mut done = WeaverBuild::new(settings(), learned()).unwrap();
    done.work(u64::MAX).unwrap();
    assert_eq!(done.work(1).unwrap().cells, 0);
}

#[test]
fn a_refused_setting_is_refused_when_the_build_starts() {
    let mut s = settings();
    s.panes[1].clamp = f64::NAN;
    let e = WeaverBuild::new(s, learned()).unwrap_err().to_string();
    assert!(e.contains("panes[1].clamp"), "{e}");
    let mut s = settings();
    s.scene.width = 4096;
    let e = WeaverBuild::new(s, learned()).unwrap_err().to_string();
    assert!(e.contains("width"), "{e}");
}

#[test]
fn a_run_started_in_calls_is_the_run_of_its_model_and_the_model_is_kept() {
    // A quickly trained model of its own, so that no other test's run
    // has left it kept.
    let mut s = settings();
    s.training = TrainingConfig {
        triplets: 400,
        epochs: 1,
        ..TrainingConfig::default()
    };
    let (model, _, _) = training::train(&s.training).unwrap();
    let mut start = WeaverStart::new(s.clone()).unwrap();
    assert!(!start.trained());
    let mut calls = 0;
    while !start.train(97).unwrap() {
        calls += 1;
    }
    assert!(calls > 1, "the training took {calls} calls");
    assert!(start.trained());
    while !start.build(997).unwrap().done {}
    let one = Weaver::with_learned(s.clone(), model.clone()).unwrap();
    assert_eq!(state(&start.finish().unwrap()), state(&one));

    // Another run of the same training takes the kept model: nothing to
    // train, and the run of that model.
    let other = WeaverSettings {
        seed: 12,
        ..s.clone()
    };
    assert!(WeaverStart::new(other.clone()).unwrap().trained());
    let one = Weaver::with_learned(other.clone(), model).unwrap();
    assert_eq!(state(&WeaverStart::run(other).unwrap()), state(&one));

    // Refused settings are refused before any training, naming the field.
    let mut bad = s;
    bad.laps = 0;
    let e = WeaverStart::new(bad).unwrap_err().to_string();
    assert!(e.contains("laps"), "{e}");
}

#[test]
fn a_world_filled_in_bands_is_the_world_filled_cell_by_cell() {
    let g = GridGeometry::new(37, 29, 0.1, -0.3, 0.2).unwrap();
    let boxes = [
        Rect::new(0.0, 0.5, 1.05, 0.95),
        Rect::new(-1.0, -1.0, 0.25, 9.0),
        Rect::new(2.0, 2.0, 1.0, 1.0),
        Rect::new(f64::NAN, 0.0, 1.0, 1.0),
        Rect::new(1.5, f64::NEG_INFINITY, f64::INFINITY, 1.3),
        Rect::new(3.33, 2.07, 3.4500001, 3.15),
    ];
    // Every cell asked, as the chapter defines a box's cells.
    let mut reference = vec![false; g.len()];
    for b in &boxes {
        for iy in 0..g.height() {
            for ix in 0..g.width() {
                let (x, y) = g.cell_center(ix, iy);
                if b.contains(x, y) {
                    reference[g.index(ix, iy)] = true;
                }
            }
        }
    }
    assert_eq!(World::from_boxes(g, &boxes).occupied(), &reference[..]);
    let mut banded = World::empty(g);
    for rows in [0..4, 4..5, 5..20, 20..40] {
        for b in &boxes {
            banded.fill_rows(b, true, rows.clone());
        }
    }
    assert_eq!(banded.occupied(), &reference[..]);
}
