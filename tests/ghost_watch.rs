#![cfg(not(target_arch = "wasm32"))]
//! Exercise 5 in Map Weaver's ghost watch: the robot parked in the
//! corridor, the person standing by the kitchen door until the cells their
//! outline marks reach the clamp, then leaving. From then on every scan
//! takes `|l_free|` off a ghost cell (Table 9.1), so its fade lasts
//! `l_max / |l_free|` scans: linear in the clamp, inversely proportional to
//! the free evidence.
//!
//! Tolerance: the slowest fade is within one scan (1/12 s) of
//! `l_max / |l_free|`. The last free reading may leave a cell exactly at
//! p = 0.5 in f32 (12 - 60 x 0.2), and a fade ends only below it; the
//! person leaves over a few scans, and the cell they leave last fades
//! last.

use occgrid::apps::map_weaver::{
    GhostReadout, ModelKind, PaneSettings, Situation, Weaver, WeaverSettings, WATCH_GHOST_CELL,
    WATCH_PAUSE,
};
use occgrid::inverse::training::{self, TrainingConfig};
use occgrid::inverse::LearnedInverse;
use std::sync::OnceLock;

fn weaver(settings: WeaverSettings) -> Weaver {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    let learned = LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
    Weaver::with_learned(settings, learned.clone()).unwrap()
}

/// The ghost watch with the hand-crafted model in both panes, after the
/// person's first departure (300 scans: 8 s standing, the slowest fade
/// below 14 s, before they come back at 24.7 s).
fn first_departure(clamps: [f64; 2], strengths: [f64; 2]) -> [GhostReadout; 2] {
    let mut s = WeaverSettings {
        situation: Situation::GhostWatch,
        laps: 1,
        ..WeaverSettings::default()
    };
    for k in 0..2 {
        s.panes[k] = PaneSettings {
            model: ModelKind::HandCrafted,
            clamp: clamps[k],
            strength: strengths[k],
            ..PaneSettings::default()
        };
    }
    let mut w = weaver(s);
    assert_eq!(w.advance(300).unwrap(), 300);
    w.readout().panes.map(|p| p.ghost)
}

/// The slowest fade in scans, checked against the recursion's
/// `l_max / |l_free|` within one scan.
fn slowest(g: &GhostReadout, clamp: f64, strength: f64) -> f64 {
    let l_free = 0.40 * strength; // Table 9.2's laser l_free, scaled
    let expected = clamp / l_free;
    let recursion = g.recursion_scans.unwrap();
    assert!(
        (recursion - expected).abs() < 1e-4,
        "{recursion} vs {expected}"
    );
    let n = g.longest_scans.expect("a ghost faded") as f64;
    assert!(
        (n - expected).abs() <= 1.0,
        "clamp {clamp}, strength {strength}: slowest fade {n} scans, l_max / |l_free| = {expected}"
    );
    assert_eq!(g.lingering, 0, "every ghost cell faded");
    assert!(
        g.faded >= 4,
        "the person's outline leaves several ghost cells"
    );
    assert_eq!(g.longest_seconds, Some(n / 12.0));
    n
}

#[test]
fn the_fade_is_linear_in_the_clamp() {
    let [a, b] = first_departure([4.0, 8.0], [0.5, 0.5]);
    let [c, d] = first_departure([12.0, 16.0], [0.5, 0.5]);
    let n: Vec<f64> = [(&a, 4.0), (&b, 8.0), (&c, 12.0), (&d, 16.0)]
        .iter()
        .map(|(g, clamp)| slowest(g, *clamp, 0.5))
        .collect();
    // 20, 40, 60, 80 scans: equal steps, and each time over the clamp the
    // same 5 scans per log odds (to one scan in 20).
    for (i, clamp) in [4.0, 8.0, 12.0, 16.0].iter().enumerate() {
        assert!((n[i] / clamp - 5.0).abs() <= 1.0 / clamp + 1e-9, "{n:?}");
    }
    // Exercise 5's answer at strength 0.5: clamp 12 fades in about 5 s
    // (60 scans), 16 in well over.
    let seconds = c.longest_seconds.unwrap();
    assert!((seconds - 5.0).abs() <= 1.0 / 12.0, "{seconds}");
    assert!(d.longest_seconds.unwrap() > 6.5);
}

#[test]
fn the_fade_is_inversely_proportional_to_the_free_evidence() {
    let [a, b] = first_departure([8.0, 8.0], [0.25, 1.0]);
    let [c, _] = first_departure([8.0, 8.0], [0.5, 3.0]);
    let n: Vec<f64> = [(&a, 0.25), (&c, 0.5), (&b, 1.0)]
        .iter()
        .map(|(g, strength)| slowest(g, 8.0, *strength))
        .collect();
    // 80, 40, 20 scans: fade x |l_free| is the clamp, to one scan's worth.
    for (i, strength) in [0.25, 0.5, 1.0].iter().enumerate() {
        let product = n[i] * 0.40 * strength;
        assert!((product - 8.0).abs() <= 0.40 * strength + 1e-9, "{n:?}");
    }
}

/// The person stands long enough for the weakest evidence to reach the
/// largest clamp: 8 s x 12 scans x 0.25 x 0.85 = 20.4 > 16.
#[test]
fn the_watch_saturates_every_clamp_before_the_person_leaves() {
    let per_scan = 0.85 * 0.25;
    assert!(WATCH_PAUSE * 12.0 * per_scan > 16.0);
    let [g, _] = first_departure([16.0, 16.0], [0.25, 0.25]);
    slowest(&g, 16.0, 0.25);
}

/// The learned model's free evidence depends on the range: no single
/// `l_max / |l_free|` to predict from, so none is shown.
#[test]
fn the_learned_model_has_no_single_recursion_time() {
    let mut s = WeaverSettings {
        situation: Situation::GhostWatch,
        ..WeaverSettings::default()
    };
    s.panes[1].model = ModelKind::Learned;
    let mut w = weaver(s);
    w.advance(1).unwrap();
    let r = w.readout();
    assert_eq!(r.panes[1].ghost.recursion_scans, None);
    assert_eq!(r.panes[0].ghost.recursion_scans, Some(12.0 / 0.4f32 as f64));
}

/// The chart's "ghost cell" climbs to the clamp while the person stands
/// on it and falls by |l_free| a scan once they have gone: a straight line
/// from the clamp to p = 0.5 in l_max / |l_free| scans.
#[test]
fn the_charted_ghost_cell_rises_to_the_clamp_and_falls_in_a_straight_line() {
    let mut s = WeaverSettings {
        situation: Situation::GhostWatch,
        laps: 1,
        ..WeaverSettings::default()
    };
    s.panes[0].strength = 0.5;
    let mut w = weaver(s);
    w.advance(300).unwrap();
    let names: Vec<String> = w
        .tracked_readout(0)
        .unwrap()
        .iter()
        .map(|t| t.name.clone())
        .collect();
    assert_eq!(names, ["corridor wall", "ghost cell", "closet"]);
    let t = &w.tracked_readout(0).unwrap()[1];
    assert_eq!(t.at, WATCH_GHOST_CELL);
    let l: Vec<f32> = w.tracked_history(0).unwrap().iter().map(|c| c[1]).collect();
    let top = l
        .iter()
        .rposition(|&v| v == 12.0)
        .expect("the ghost cell reaches the clamp");
    let faded = top + l[top..].iter().position(|&v| v < 0.0).expect("and fades");
    assert_eq!(
        faded - top,
        61,
        "12 / 0.2 = 60 steps of -0.2 from the clamp, the last to just below 0"
    );
    for i in top + 1..=faded {
        assert!(
            (l[i - 1] - l[i] - 0.2).abs() < 1e-5,
            "scan {i}: {} -> {}",
            l[i - 1],
            l[i]
        );
    }
    assert!(
        WATCH_PAUSE * 12.0 > top as f64 - 12.0,
        "it stood there until about scan 96: {top}"
    );
    let wall = w.tracked_history(0).unwrap().last().unwrap()[0];
    assert_eq!(wall, 12.0, "the robot sees the corridor's north wall");
}
