//! The session's own tests: views against the renderer, refusals, rebuilds,
//! hover and overlay, the fast-forward budget and the clock of the curves.

use super::*;
use crate::inverse::TrainingConfig;
use std::sync::OnceLock;

/// A run with a model trained once for all the tests here.
fn weaver(settings: WeaverSettings) -> Weaver {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    let learned = LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
    Weaver::with_learned(settings, learned.clone()).unwrap()
}

#[test]
fn view_pixels_match_the_grid_renderer_after_scans_and_a_clamp_change() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(40).unwrap();
    w.set_clamp(0, 1.5).unwrap();
    w.advance(5).unwrap();
    for k in 0..2 {
        let grid = w.grid(k).unwrap();
        let mut px = vec![0u8; grid.geometry().len() * 4];
        crate::render::viewport::render_grid_rgba(grid, &mut px).unwrap();
        assert_eq!(w.view(k).unwrap().rgba(), &px[..], "pane {k}");
        // The view scores from a table (view.rs): within 1e-6 bits per
        // cell of the exact sum.
        let h = grid.entropy_bits();
        assert!((w.view(k).unwrap().entropy_bits() - h).abs() < 1e-6 * 10_800.0);
        let b = grid.brier_score(w.ground_truth(), None).unwrap();
        assert!((w.view(k).unwrap().brier_all() - b).abs() < 1e-6);
    }
}

#[test]
fn training_past_the_update_limit_is_refused_before_it_starts() {
    let mut s = WeaverSettings::default();
    s.training.triplets = 1_000_000;
    s.training.epochs = 200;
    let e = Weaver::new(s.clone()).err().unwrap().to_string();
    assert!(
        e.contains("training.triplets x training.epochs")
            && e.contains("200000000")
            && e.contains("5000000"),
        "{e}"
    );
    // Each alone, at its own maximum, is fine.
    s.training.epochs = 5;
    s.validate().unwrap();
    s.training = TrainingConfig {
        epochs: 200,
        ..TrainingConfig::default()
    };
    s.validate().unwrap();
}

#[test]
fn bad_knobs_are_rejected_naming_the_pane_and_leave_the_map_alone() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(10).unwrap();
    let before = w.grid(1).unwrap().clone();
    let e = w.set_clamp(1, 0.0).unwrap_err().to_string();
    assert!(e.contains("panes[1].clamp") && e.contains('0'), "{e}");
    let e = w.set_strength(1, f64::NAN).unwrap_err().to_string();
    assert!(e.contains("panes[1].strength") && e.contains("NaN"), "{e}");
    assert!(w.set_strength(1, 11.0).is_err());
    assert!(w
        .set_clamp(2, 3.0)
        .unwrap_err()
        .to_string()
        .contains("pane"));
    assert!(w.cell_info(5, 0, 0).is_err());
    assert_eq!(w.cell_info(0, 120, 0).unwrap(), None);
    assert_eq!(w.grid(1).unwrap(), &before);
    let s = WeaverSettings {
        laps: 0,
        ..WeaverSettings::default()
    };
    assert!(Weaver::new(s).unwrap_err().to_string().contains("laps"));
    let mut s = WeaverSettings::default();
    s.panes[0].clamp = -1.0;
    assert!(Weaver::new(s)
        .unwrap_err()
        .to_string()
        .contains("panes[0].clamp"));
}

#[test]
fn switching_the_pose_source_rebuilds_the_pane_over_the_same_scans() {
    let mut s = WeaverSettings::default();
    s.panes[1].pose = PoseSource::DeadReckoning;
    let mut reference = weaver(s);
    reference.advance(120).unwrap();
    let mut w = weaver(WeaverSettings::default());
    w.advance(120).unwrap();
    w.set_pose_source(1, PoseSource::DeadReckoning).unwrap();
    assert_eq!(w.grid(1).unwrap(), reference.grid(1).unwrap());
    assert_eq!(
        w.entropy_curve(1).unwrap(),
        reference.entropy_curve(1).unwrap()
    );
    assert_eq!(w.entropy_curve(1).unwrap().len(), 121);
}

#[test]
fn hover_reads_the_cell_under_the_pointer_north_up() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(30).unwrap();
    // Image row 0 is the map's northernmost row.
    let info = w.cell_info(0, 30, 0).unwrap().unwrap();
    assert_eq!((info.cell.ix, info.cell.iy), (30, 89));
    assert!(info.occupied, "the north outer wall");
    let [wall, _, _] = w.tracked_cells();
    let (ix, iy) = w.geometry().cell_of_index(wall);
    let info = w.cell_info(0, ix, 89 - iy).unwrap().unwrap();
    assert_eq!(info.cell.l, w.grid(0).unwrap().log_odds()[wall] as f64);
    assert_eq!(info.cell.updates, w.grid(0).unwrap().update_counts()[wall]);
}

#[test]
fn overlay_puts_the_robot_on_its_cell_with_one_end_point_per_beam() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(1).unwrap();
    let o = w.overlay(0).unwrap();
    // The lap starts at (1.2 m, 4.95 m): column 12, 49.5 rows from the
    // bottom of 90, so 40.5 rows from the top.
    assert!((o.robot.x - 12.0).abs() < 1e-9 && (o.robot.y - 40.5).abs() < 1e-9);
    assert!(o.robot.heading.cos() > 0.99, "facing east");
    assert_eq!((o.beams.len(), o.hits.len()), (120, 60));
    assert!(o.person.is_some());
}

/// A link asking for more scans than the work budget is refused by
/// name before any work; the run's end bounds what is asked for.
#[test]
fn fast_forward_is_bounded_by_the_work_budget_and_the_run() {
    let w = weaver(WeaverSettings::default());
    // 60 beams x 80 cells (8 m at 0.1 m) x 2 panes.
    assert_eq!(w.work_per_scan(), 9600);
    let total = 3 * w.scans_per_lap();
    assert_eq!(w.check_fast_forward(10).unwrap(), 10);
    assert_eq!(w.check_fast_forward(1_000_000).unwrap(), total);
    let mut s = WeaverSettings {
        laps: 20,
        ..WeaverSettings::default()
    };
    s.scene.width = 960;
    s.scene.height = 720;
    s.scene.resolution = 0.0125;
    s.scene.scan_rate = 60.0;
    let fine = weaver(s);
    assert_eq!(fine.work_per_scan(), 2 * 60 * 640);
    let limit = (MAX_FAST_FORWARD_WORK / fine.work_per_scan()) as usize;
    assert_eq!(fine.check_fast_forward(limit).unwrap(), limit);
    let e = fine.check_fast_forward(1_000_000).unwrap_err().to_string();
    assert!(e.starts_with("invalid scans: 1000000 ("), "{e}");
    assert!(e.contains("250000000 cell visits"), "{e}");
    assert!(fine.check_fast_forward(limit + 1).is_err());
}

/// The readout's "s of driving" and the charts' time axis come from the
/// scene's scan rate (a chart that assumed 12 scans per second put the
/// 12th scan of a 6 Hz scene at 1 s, the readout at 2 s).
#[test]
fn readout_time_and_curve_times_follow_the_scene_scan_rate() {
    let mut s = WeaverSettings::default();
    s.scene.scan_rate = 6.0;
    let mut w = weaver(s);
    w.advance(12).unwrap();
    let times = w.curve_times();
    assert_eq!(times.len(), w.entropy_curve(0).unwrap().len());
    assert_eq!(times[0], 0.0);
    assert_eq!(*times.last().unwrap(), 2.0);
    assert_eq!(w.readout().time, 2.0);
}
