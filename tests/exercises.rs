#![cfg(not(target_arch = "wasm32"))]
//! The chapter's exercises as Map Weaver runs them, each doable in the
//! page: the two mappers of Table 9.1 side by side, the
//! ghost's fade, and the learned model with its `l0` forgotten.

use occgrid::apps::map_weaver::{
    MapperKind, ModelKind, PaneSettings, SensorKind, Weaver, WeaverSettings,
};
use occgrid::inverse::training::{self, TrainingConfig};
use occgrid::inverse::LearnedInverse;
use occgrid::io::map_server::map_server_pair;
use occgrid::scenes::apartment::ApartmentScene;
use occgrid::world::Rect;
use std::sync::OnceLock;

fn weaver(settings: WeaverSettings) -> Weaver {
    static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
    let learned = LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
    Weaver::with_learned(settings, learned.clone()).unwrap()
}

fn hand(mapper: MapperKind, sensor: SensorKind, resolution: f64) -> PaneSettings {
    PaneSettings {
        model: ModelKind::HandCrafted,
        mapper,
        sensor,
        beta_deg: 22.0,
        resolution: Some(resolution),
        ..PaneSettings::default()
    }
}

/// What one lap of the apartment looks like to the two mappers of Table
/// 9.1 (pane 0 by ray traversal, pane 1 by the literal sweep), both with
/// Table 9.2 and the same sensor.
struct Comparison {
    cells: usize,
    /// Cells whose verdict (p above, below or at 0.5) differs.
    verdicts_differ: usize,
    /// Cells the sweep updated and the traversal never did.
    only_sweep: usize,
    visited: [usize; 2],
}

fn compare(sensor: SensorKind, resolution: f64) -> Comparison {
    let s = WeaverSettings {
        laps: 1,
        panes: [
            hand(MapperKind::Traversal, sensor, resolution),
            hand(MapperKind::Sweep, sensor, resolution),
        ],
        ..Default::default()
    };
    let mut w = weaver(s);
    let n = w.scans_per_lap();
    assert_eq!(w.advance(n).unwrap(), n);
    let (t, sw) = (w.grid(0).unwrap(), w.grid(1).unwrap());
    let verdict = |l: f32| l.partial_cmp(&0.0).unwrap();
    let cells = t.geometry().len();
    let r = w.readout();
    Comparison {
        cells,
        verdicts_differ: (0..cells)
            .filter(|&i| verdict(t.log_odds()[i]) != verdict(sw.log_odds()[i]))
            .count(),
        only_sweep: (0..cells)
            .filter(|&i| t.update_counts()[i] == 0 && sw.update_counts()[i] > 0)
            .count(),
        visited: [r.panes[0].cells_visited, r.panes[1].cells_visited],
    }
}

/// Exercise 6. The bound: for the thin LiDAR (Table 9.2's one-degree
/// beta), after a lap at 0.10 m and at 0.05 m, fewer than 5% of the
/// map's cells get a different verdict from the two mappers and fewer
/// than 1% are reached by the sweep alone (measured: 3.4% and 0 cells at
/// 0.10 m, 1.2% and 0.1% at 0.05 m). The sweep visits every cell, the
/// traversal a fraction. A 22-degree cone parts them: the sweep paints the
/// cone between beams, which no beam's raster crosses (measured: 628
/// cells, 5.8% of the map, only the sweep reaches).
#[test]
fn sweep_and_traversal_agree_for_the_thin_lidar_and_part_for_a_22_degree_cone() {
    for res in [0.10, 0.05] {
        let c = compare(SensorKind::Lidar, res);
        assert!(
            c.verdicts_differ * 20 < c.cells,
            "{res} m: {} of {} verdicts differ",
            c.verdicts_differ,
            c.cells
        );
        assert!(
            c.only_sweep * 100 < c.cells,
            "{res} m: {} cells",
            c.only_sweep
        );
        assert_eq!(c.visited[1], c.cells, "the sweep visits every cell");
        assert!(c.visited[0] * 4 < c.cells, "{:?}", c.visited);
    }
    let thin = compare(SensorKind::Lidar, 0.10);
    let cone = compare(SensorKind::Cone, 0.10);
    assert!(
        cone.only_sweep * 25 > cone.cells && cone.only_sweep > 10 * (thin.only_sweep + 1),
        "cone: {} cells only the sweep reaches (thin: {})",
        cone.only_sweep,
        thin.only_sweep
    );
    assert!(cone.verdicts_differ > 2 * thin.verdicts_differ);
}

/// Exercise 5. The fade readout against a count made here from the log
/// odds of every cell the person stood on, scan by scan (seed 1, strength
/// 3, clamp 4): a ghost cell is one above p = 0.5 after the last scan in
/// which the person stood on it or next to it (their outline marks the
/// cells within a cell of their footprint; walls excluded); its fade is the number of scans from that
/// scan until the first scan after which it is below p = 0.5.
#[test]
fn the_ghost_fade_readout_matches_a_count_by_hand() {
    let mut s = WeaverSettings::default();
    s.panes[0].strength = 3.0;
    s.panes[0].clamp = 4.0;
    let mut w = weaver(s);
    let scene = ApartmentScene::default();
    let g = *w.pane_geometry(0).unwrap();
    // cell -> (scan that last saw the person on it, a ghost then?)
    let mut left: std::collections::BTreeMap<usize, usize> = Default::default();
    let mut under_before: Vec<(usize, bool)> = Vec::new();
    let mut fades = Vec::new();
    for scan in 1..=700 {
        assert_eq!(w.advance(1).unwrap(), 1);
        let l = w.grid(0).unwrap().log_odds().to_vec();
        // The cells the person's outline may have marked: the footprint
        // grown by a cell, less the walls.
        let now: Vec<usize> = match w.history().last().unwrap().person {
            Some(r) => scene
                .cells_in(
                    &g,
                    &[Rect::new(
                        r.min_x - 0.1,
                        r.min_y - 0.1,
                        r.max_x + 0.1,
                        r.max_y + 0.1,
                    )],
                )
                .into_iter()
                .filter(|&c| !w.ground_truth()[c])
                .collect(),
            None => Vec::new(),
        };
        for &(c, ghost) in &under_before {
            if ghost && !now.contains(&c) {
                left.insert(c, scan - 1);
            }
        }
        let done: Vec<usize> = left
            .iter()
            .filter(|(c, _)| now.contains(c) || l[**c] < 0.0)
            .map(|(c, _)| *c)
            .collect();
        // Completed fades in the order the readout records them: by the
        // scan the person left, then by cell.
        let mut finished: Vec<(usize, usize, usize)> = done
            .iter()
            .filter(|c| !now.contains(c))
            .map(|&c| (left[&c], c, scan - left[&c]))
            .collect();
        finished.sort();
        for c in &done {
            left.remove(c);
        }
        let mut ours: Vec<usize> = finished.iter().map(|f| f.2).collect();
        fades.append(&mut ours);
        under_before = now.iter().map(|&c| (c, l[c] > 0.0)).collect();
    }
    let mut theirs = w.ghost_fades(0).unwrap().to_vec();
    let mut sorted = fades.clone();
    sorted.sort();
    theirs.sort();
    assert!(
        fades.len() > 50,
        "the person leaves ghosts: {}",
        fades.len()
    );
    assert_eq!(theirs, sorted, "the same fades");
    let r = w.readout().panes[0].ghost.clone();
    assert_eq!(r.faded, fades.len());
    assert_eq!(r.lingering, left.len());
    assert_eq!(r.longest_scans, fades.iter().copied().max());
    let longest = r.longest_scans.unwrap();
    assert_eq!(r.longest_seconds, Some(longest as f64 / 12.0));
}

/// Exercise 8. With `l0` forgotten every update of the learned model adds
/// its own prior: after a few scans by the sweep, each cell has drifted
/// from the correct map by exactly `l0` per update it received (to f32
/// rounding; cells at the clamp excluded). Over a lap the drift shows in
/// the Brier score and the entropy curve.
#[test]
fn forgetting_l0_drifts_each_cell_by_l0_per_update() {
    let mut s = WeaverSettings {
        laps: 1,
        ..Default::default()
    };
    for p in &mut s.panes {
        p.model = ModelKind::Learned;
        p.mapper = MapperKind::Sweep;
        p.clamp = 16.0;
    }
    s.panes[1].forget_l0 = true;
    let mut w = weaver(s);
    w.advance(4).unwrap();
    let r = w.readout();
    let l0 = r.panes[0].model_l0;
    assert!(l0 < -0.2, "the learned model's own prior is negative: {l0}");
    assert_eq!(r.panes[1].model_l0, 0.0, "forgotten");
    let (a, b) = (w.grid(0).unwrap(), w.grid(1).unwrap());
    let mut checked = 0;
    for i in 0..a.geometry().len() {
        let u = b.update_counts()[i];
        let (la, lb) = (a.log_odds()[i], b.log_odds()[i]);
        if u == 0 || la.abs() >= 15.99 || lb.abs() >= 15.99 {
            continue;
        }
        let per_update = (lb - la) / u as f32;
        assert!(
            (per_update - l0).abs() < 1e-5,
            "cell {i}: {per_update} per update, l0 {l0}"
        );
        checked += 1;
    }
    assert!(checked > 1000, "{checked}");
    w.advance(usize::MAX).unwrap();
    let r = w.readout();
    assert!(
        r.panes[1].brier > 2.0 * r.panes[0].brier,
        "{} vs {}",
        r.panes[1].brier,
        r.panes[0].brier
    );
    let (e0, e1) = (w.entropy_curve(0).unwrap(), w.entropy_curve(1).unwrap());
    assert_eq!(e0.len(), e1.len());
    assert!(e1.last() != e0.last());

    // The same run with the traversal: the switch is per pane and does
    // not touch the other pane.
    let mut t = WeaverSettings::default();
    t.panes[0].model = ModelKind::Learned;
    t.panes[1].model = ModelKind::Learned;
    let mut plain = weaver(t.clone());
    plain.advance(30).unwrap();
    let mut w = weaver(t);
    w.advance(30).unwrap();
    let mut s1 = w.settings().panes[1];
    s1.forget_l0 = true;
    w.set_pane(1, s1).unwrap();
    assert_eq!(w.grid(0).unwrap(), plain.grid(0).unwrap());
    assert_ne!(w.grid(1).unwrap(), plain.grid(1).unwrap());
    assert_eq!(
        w.entropy_curve(1).unwrap().len(),
        31,
        "rebuilt over the 30 scans"
    );
}

/// Every new pane knob is checked, naming the field and the value, and a
/// refused change leaves the pane as it was. The sliders' knobs keep to
/// their steps (a strength of 3.25 or 1.1 is no slider position).
#[test]
fn pane_settings_are_checked_field_by_field() {
    let mut w = weaver(WeaverSettings::default());
    w.advance(10).unwrap();
    let before = w.grid(1).unwrap().clone();
    let ok = w.settings().panes[1];
    let cases: [(PaneSettings, &str, &str); 9] = [
        (
            PaneSettings {
                strength: 3.25,
                ..ok
            },
            "panes[1].strength",
            "3.25",
        ),
        (
            PaneSettings {
                strength: 1.1,
                ..ok
            },
            "panes[1].strength",
            "1.1",
        ),
        (
            PaneSettings { clamp: 12.25, ..ok },
            "panes[1].clamp",
            "12.25",
        ),
        (
            PaneSettings {
                beta_deg: 22.5,
                ..ok
            },
            "panes[1].betaDeg",
            "22.5",
        ),
        (
            PaneSettings {
                beta_deg: 0.5,
                ..ok
            },
            "panes[1].betaDeg",
            "0.5",
        ),
        (
            PaneSettings {
                beta_deg: f64::NAN,
                ..ok
            },
            "panes[1].betaDeg",
            "NaN",
        ),
        (
            PaneSettings {
                resolution: Some(0.2),
                ..ok
            },
            "panes[1].resolution",
            "0.2",
        ),
        (
            PaneSettings {
                beams: Some(7),
                ..ok
            },
            "panes[1].beams",
            "7",
        ),
        (
            PaneSettings {
                beams: Some(0),
                ..ok
            },
            "panes[1].beams",
            "0",
        ),
    ];
    for (bad, field, value) in cases {
        let e = w.set_pane(1, bad).unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(value), "{e}");
        assert_eq!(w.grid(1).unwrap(), &before);
        assert_eq!(w.settings().panes[1], ok);
        let mut s = WeaverSettings::default();
        s.panes[1] = bad;
        assert!(Weaver::new(s).unwrap_err().to_string().contains(field));
    }
}

/// A pane at 0.05 m, a thinned LiDAR and a rebuilt pane: the rebuilt pane
/// is the pane that had the settings from the start, and its readout says
/// so.
#[test]
fn changing_resolution_mapper_or_beams_rebuilds_the_pane_as_if_set_from_the_start() {
    let target = PaneSettings {
        resolution: Some(0.05),
        mapper: MapperKind::Sweep,
        beams: Some(20),
        ..PaneSettings::default()
    };
    let mut s = WeaverSettings::default();
    s.panes[1] = target;
    let mut reference = weaver(s);
    reference.advance(40).unwrap();
    let mut w = weaver(WeaverSettings::default());
    w.advance(40).unwrap();
    w.set_pane(1, target).unwrap();
    assert_eq!(w.grid(1).unwrap(), reference.grid(1).unwrap());
    assert_eq!(
        w.entropy_curve(1).unwrap(),
        reference.entropy_curve(1).unwrap()
    );
    let r = w.readout().panes[1].clone();
    assert_eq!((r.width, r.height, r.beams), (240, 180, 20));
    assert_eq!(r.cells_visited, 43_200);
    assert_eq!(w.overlay(1).unwrap().hits.len(), 20);
    assert!(r.scan_ms.is_some(), "timed natively");
    // The fast-forward budget counts what each pane does: 60 beams x 80
    // cells for the traversal, the whole 0.05 m map for the sweep.
    assert_eq!(w.work_per_scan(), 60 * 80 + 43_200);
    // The other pane is untouched.
    assert_eq!(w.readout().panes[0].width, 120);
}

/// Exercise 6 live: the readout's count of cells the two maps' exports
/// disagree on is the count of differing bytes of the two exported PGM
/// images. The thin LiDAR's maps differ too (Table 9.2's line 1: the sweep
/// tests each cell centre against the beam's half-opening beta/2 of half a
/// degree, the traversal updates every cell the beam's raster crosses), a
/// 22-degree cone far more; no count for panes of different resolutions.
#[test]
fn the_readout_counts_the_cells_where_the_two_exported_maps_differ() {
    let counts = |sensor: SensorKind| {
        let s = WeaverSettings {
            panes: [
                hand(MapperKind::Traversal, sensor, 0.10),
                hand(MapperKind::Sweep, sensor, 0.10),
            ],
            person: false,
            ..Default::default()
        };
        let mut w = weaver(s);
        w.advance(653).unwrap();
        let r = w.readout();
        let d = r.difference.expect("same resolution");
        if sensor == SensorKind::Lidar {
            // The corridor wall cell the chart follows: the traversal
            // updates it whenever a beam's raster crosses it and takes it
            // to the clamp; the sweep only when its centre lies within
            // half a degree of a beam's axis.
            let [by_traversal, by_sweep] = r.panes.map(|p| p.tracked[0]);
            assert_eq!(by_traversal, 12.0);
            assert!(by_sweep < 6.0, "{by_sweep}");
        }
        let image = |k: usize| {
            let pair = map_server_pair(w.grid(k).unwrap(), "x.pgm");
            let header = pair.pgm.len() - 10_800;
            pair.pgm[header..].to_vec()
        };
        let (a, b) = (image(0), image(1));
        let by_bytes = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!((d.cells, d.of), (by_bytes, 10_800));
        assert!(d.updated_by_one <= d.cells);
        (d, w)
    };
    let (thin, mut w) = counts(SensorKind::Lidar);
    let (cone, _) = counts(SensorKind::Cone);
    assert!(thin.cells > 100, "the thin LiDAR's maps differ: {thin:?}");
    // Measured at scan 653: 485 cells (52 updated by one mapper only) for
    // the thin LiDAR, 838 (434) for the cone, whose sweep paints the cone
    // between the beams.
    assert!(
        cone.cells > thin.cells && cone.updated_by_one > 4 * thin.updated_by_one,
        "{cone:?} vs {thin:?}"
    );
    let p = w.settings().panes[1];
    w.set_pane(
        1,
        PaneSettings {
            resolution: Some(0.05),
            ..p
        },
    )
    .unwrap();
    assert_eq!(w.readout().difference, None);
}

/// Exercise 8 live: with the learned model in both panes and only the
/// right one forgetting `l0`, the readout's measured drift per update is
/// the model's own `l0`, over the cells inside the clamp; no drift is
/// shown when the panes differ in any other knob too.
#[test]
fn the_readout_measures_the_drift_of_a_pane_that_forgets_l0() {
    let mut s = WeaverSettings::default();
    for p in &mut s.panes {
        p.model = ModelKind::Learned;
    }
    s.panes[1].forget_l0 = true;
    let mut w = weaver(s);
    w.advance(120).unwrap();
    let d = w
        .readout()
        .l0_drift
        .expect("the panes differ in forget-l0 alone");
    assert_eq!(d.pane, 1);
    assert!(d.model_l0 < -0.2, "{d:?}");
    assert!(d.cells > 100, "{d:?}");
    let per_update = d.per_update.unwrap();
    assert!((per_update - f64::from(d.model_l0)).abs() < 1e-4, "{d:?}");
    let p = w.settings().panes[0];
    w.set_pane(0, PaneSettings { clamp: 8.0, ..p }).unwrap();
    assert_eq!(w.readout().l0_drift, None);
    let mut s = WeaverSettings::default();
    s.panes[1].model = ModelKind::HandCrafted;
    assert_eq!(weaver(s).readout().l0_drift, None, "nobody forgets");
}
