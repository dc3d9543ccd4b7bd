//! The work in bounded calls: each call keeps to its budget, a pane built
//! in slices is the pane built in one go, and every knob rebuilds its pane
//! over the scans so far.

use super::super::*;
use crate::inverse::TrainingConfig;
use std::sync::OnceLock;

/// A run with a model trained once for all the tests here.
fn weaver(settings: WeaverSettings) -> Weaver {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    let learned = LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
    Weaver::with_learned(settings, learned.clone()).unwrap()
}

/// The chapter's run with the left pane on the literal sweep.
fn sweep_left() -> WeaverSettings {
    let mut s = WeaverSettings::default();
    s.panes[0].mapper = MapperKind::Sweep;
    s
}

/// Everything the widget shows of pane `k`, compared bit for bit.
fn assert_same_pane(a: &Weaver, b: &Weaver, k: usize) {
    // Compared without printing them: a grid is thousands of numbers.
    assert!(
        a.grid(k).unwrap() == b.grid(k).unwrap(),
        "pane {k}: the grids differ"
    );
    assert!(
        a.view(k).unwrap().rgba() == b.view(k).unwrap().rgba(),
        "pane {k}: the pixels differ"
    );
    let bits = |w: &Weaver| {
        let e = w.entropy_curve(k).unwrap().iter().map(|x| x.to_bits());
        let b = w.brier_curve(k).unwrap().iter().map(|x| x.to_bits());
        e.chain(b).collect::<Vec<_>>()
    };
    assert_eq!(bits(a), bits(b), "pane {k}: entropy and Brier curves");
    assert_eq!(a.tracked_history(k).unwrap(), b.tracked_history(k).unwrap());
    assert_eq!(a.ghost_fades(k).unwrap(), b.ghost_fades(k).unwrap());
}

/// The most cell visits of one traversal scan of the chapter's run: 60
/// beams of at most 80 cells (8 m at 0.1 m), more than a row of the sweep
/// (120 cells).
const TRAVERSAL_SCAN: u64 = 60 * 80;

/// Calls `work(scans, budget)` until nothing is left, checking that no
/// call spends more than `budget` plus `overshoot` (one row of a sweep, or
/// one traversal scan); returns how many calls it took.
fn work_in_calls(w: &mut Weaver, scans: usize, budget: u64, overshoot: u64) -> usize {
    let mut calls = 0;
    let mut taken = 0;
    loop {
        let r = w.work(scans - taken, budget).unwrap();
        calls += 1;
        taken += r.scans;
        assert!(
            r.cell_visits <= budget + overshoot,
            "call {calls} spent {} cell visits on a budget of {budget}",
            r.cell_visits
        );
        if r.behind == [0, 0] && (taken == scans || r.done) {
            return calls;
        }
        assert!(r.cell_visits > 0, "call {calls} made no progress");
    }
}

/// A sweep over 120 x 90 cells in bands of 1,000 cells: each scan takes
/// several calls, none spends more than its budget and one traversal scan of
/// the right pane, and the maps,
/// views and curves are those of the same scans taken whole.
#[test]
fn a_sweep_spread_over_calls_keeps_each_to_its_budget_and_maps_the_same() {
    let mut whole = weaver(sweep_left());
    whole.advance(25).unwrap();
    let mut sliced = weaver(sweep_left());
    let calls = work_in_calls(&mut sliced, 25, 1_000, TRAVERSAL_SCAN);
    // 10,800 cells a scan on the left at about 1,000 a call.
    assert!(calls >= 25 * 10, "{calls} calls");
    assert_eq!(sliced.scans(), 25);
    for k in 0..2 {
        assert_same_pane(&whole, &sliced, k);
    }
}

/// By ray traversal a scan cannot be cut: a budget smaller than one scan
/// still takes one scan of one pane a call, never more.
#[test]
fn traversal_takes_one_pane_scan_a_call_on_a_small_budget() {
    let mut w = weaver(WeaverSettings::default());
    let mut calls = 0;
    while w.scans() < 10 || w.progress().behind != [0, 0] {
        let before = [
            w.entropy_curve(0).unwrap().len(),
            w.entropy_curve(1).unwrap().len(),
        ];
        w.work(10 - w.scans(), 1).unwrap();
        let after = [
            w.entropy_curve(0).unwrap().len(),
            w.entropy_curve(1).unwrap().len(),
        ];
        assert_eq!(
            after[0] + after[1],
            before[0] + before[1] + 1,
            "one pane scan a call"
        );
        calls += 1;
    }
    assert_eq!(calls, 20);
    let mut whole = weaver(WeaverSettings::default());
    whole.advance(10).unwrap();
    assert_same_pane(&whole, &w, 0);
    assert_same_pane(&whole, &w, 1);
}

/// A knob staged mid-run empties its pane, and budgeted calls rebuild it
/// over the scans so far before any new scan: in many calls, to the pane
/// that had the setting all along.
#[test]
fn a_staged_knob_rebuilds_its_pane_in_budgeted_calls_before_new_scans() {
    let mut w = weaver(sweep_left());
    w.advance(30).unwrap();
    let mut s = w.settings().panes[0];
    s.clamp = 1.0;
    assert!(w.stage_pane(0, s).unwrap());
    assert!(
        !w.stage_pane(0, s).unwrap(),
        "the same settings again: nothing to do"
    );
    assert_eq!(w.progress().behind, [30, 0]);
    assert_eq!(w.entropy_curve(0).unwrap().len(), 1, "emptied at once");
    // New scans wait for the rebuild.
    let r = w.work(5, 2_000).unwrap();
    assert_eq!((r.scans, w.scans()), (0, 30));
    let calls = work_in_calls(&mut w, 5, 2_000, TRAVERSAL_SCAN);
    assert!(calls > 30 * 5, "{calls} calls");
    assert_eq!(w.scans(), 35);
    let mut all_along = sweep_left();
    all_along.panes[0].clamp = 1.0;
    let mut reference = weaver(all_along);
    reference.advance(35).unwrap();
    assert_same_pane(&reference, &w, 0);
    assert_same_pane(&reference, &w, 1);
}

/// `advance` keeps its meaning with a rebuild under way: it finishes the
/// rebuild, then takes its scans.
#[test]
fn advance_finishes_a_staged_rebuild_first() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(20).unwrap();
    let mut s = w.settings().panes[1];
    s.pose = PoseSource::DeadReckoning;
    w.stage_pane(1, s).unwrap();
    w.work(0, 1).unwrap();
    assert_eq!(w.progress().behind, [0, 19]);
    assert_eq!(w.advance(4).unwrap(), 4);
    assert_eq!(w.progress().behind, [0, 0]);
    let mut reference = WeaverSettings::default();
    reference.panes[1].pose = PoseSource::DeadReckoning;
    let mut reference = weaver(reference);
    reference.advance(24).unwrap();
    assert_same_pane(&reference, &w, 1);
}

/// A staged setting that is refused changes nothing, rebuild or not.
#[test]
fn a_refused_staged_knob_leaves_the_run_alone() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(12).unwrap();
    let before = w.grid(0).unwrap().clone();
    let mut s = w.settings().panes[0];
    s.clamp = 0.0;
    let e = w.stage_pane(0, s).unwrap_err().to_string();
    assert!(e.contains("panes[0].clamp"), "{e}");
    s.clamp = 3.0;
    s.beams = Some(7);
    let e = w.stage_pane(0, s).unwrap_err().to_string();
    assert!(e.contains("panes[0].beams"), "{e}");
    assert!(w.stage_pane(2, s).unwrap_err().to_string().contains("pane"));
    assert_eq!(w.grid(0).unwrap(), &before);
    assert_eq!(w.progress().behind, [0, 0]);
    assert_eq!(w.settings().panes[0], WeaverSettings::default().panes[0]);
}

/// The run done and both panes caught up: a call does nothing and says so.
#[test]
fn the_end_of_the_run_is_done_and_work_stops() {
    let s = WeaverSettings {
        laps: 1,
        ..WeaverSettings::default()
    };
    let mut w = weaver(s);
    let total = w.total_scans();
    assert_eq!(w.advance(usize::MAX).unwrap(), total);
    let r = w.work(10, 1_000).unwrap();
    assert_eq!(
        (r.scans, r.cell_visits, r.behind, r.done),
        (0, 0, [0, 0], true)
    );
}

/// A clamp dragged to 1 and back used to leave the map pulled in. Each knob
/// now gives, over the scans so far, the map of a run that had its value
/// all along, and a knob turned and turned back the map it had.
#[test]
fn every_knob_turned_and_turned_back_leaves_the_map_as_it_was() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(200).unwrap();
    let mut untouched = weaver(WeaverSettings::default());
    untouched.advance(200).unwrap();
    let default = w.settings().panes[0];
    w.set_clamp(0, 1.0).unwrap();
    w.set_clamp(0, default.clamp).unwrap();
    w.set_strength(0, 3.0).unwrap();
    w.set_strength(0, default.strength).unwrap();
    assert_same_pane(&untouched, &w, 0);
    let e = |w: &Weaver| w.readout().panes[0].entropy_bits;
    assert_eq!(e(&w), e(&untouched));
}

/// Clamp, strength and the cone's β each give the run that had that value
/// all along (the β of the hand-crafted model's cone, Table 9.2).
#[test]
fn clamp_strength_and_beta_rebuild_over_the_scans_so_far() {
    let mut base = WeaverSettings::default();
    base.panes[0].sensor = SensorKind::Cone;
    type Knob = fn(&mut PaneSettings);
    let knobs: [(&str, Knob); 3] = [
        ("clamp", |p| p.clamp = 1.5),
        ("strength", |p| p.strength = 2.5),
        ("beta", |p| p.beta_deg = 30.0),
    ];
    for (name, turn) in knobs {
        let mut w = weaver(base.clone());
        w.advance(60).unwrap();
        let mut s = w.settings().panes[0];
        turn(&mut s);
        w.set_pane(0, s).unwrap();
        let mut all_along = base.clone();
        turn(&mut all_along.panes[0]);
        let mut reference = weaver(all_along);
        reference.advance(60).unwrap();
        assert!(
            w.grid(0).unwrap() == reference.grid(0).unwrap(),
            "{name}: the grids differ"
        );
        assert_same_pane(&reference, &w, 0);
    }
}
