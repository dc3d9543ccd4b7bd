#![cfg(not(target_arch = "wasm32"))]
//! Sensor fusion on the table scene (docs/ARCHITECTURE.md, "Two sensors", Probabilistic Robotics
//! eq. 9.9): the required regression, the beam-count experiment, and the
//! max rule's defining property.

use occgrid::apps::sensor_fusion::{FusionModels, TableFusion};
use occgrid::grid::LogOddsGrid;
use occgrid::mapping::fusion::max_fused_probabilities;
use occgrid::scenes::table::TableScene;

/// The default scene (seed 7, 360-beam LiDAR, 16-sonar ring), one full lap.
fn finished(scene: &TableScene) -> TableFusion {
    let mut f = TableFusion::new(scene).unwrap();
    assert_eq!(f.run_to_end(), 81, "one lap of the default path");
    f
}

#[test]
fn max_fusion_keeps_the_table_while_summation_erases_it() {
    // docs/ARCHITECTURE.md, "Two sensors" regression, fixed seed.
    let scene = TableScene::default();
    assert_eq!(scene.seed, 7);
    let f = finished(&scene);
    let m = f.footprint_means();
    assert!(m.max > 0.55, "max fusion footprint mean {}", m.max);
    assert!(m.sum < 0.10, "summation footprint mean {}", m.sum);
    // Pinned to the run as built (tolerance covers float noise across
    // platforms, not a change of behaviour).
    assert!((m.max - 0.714).abs() < 0.01, "{}", m.max);
    assert!((m.sum - 0.069).abs() < 0.01, "{}", m.sum);
    // Each modality alone answers its own question: the sonar reports the
    // top (its map is the max map's source here), the LiDAR free floor.
    assert!(m.sonar > 0.55 && m.lidar < 0.10, "{m:?}");
    assert!(m.max >= m.sonar && m.max >= m.lidar);
}

#[test]
fn summation_tracks_the_lidar_beam_count_while_max_fusion_does_not() {
    // Only the LiDAR's beam count changes: same seed, path, table, sonar
    // readings and inverse models.
    //
    // Why the summed map *should* flip here: the summed grid adds every
    // reading of both sensors to the same cells as if they were independent
    // looks at one fact. Under the table they are not — the sonar answers
    // "is there something at table height?" (yes), the LiDAR "is there
    // something at shin height?" (no, between the legs). The sum then
    // settles where the ratio of the two evidence rates puts it: with 6
    // beams, few LiDAR rays cross the footprint per scan and the sonar's
    // echoes outvote them; with 360, a ray crosses every footprint cell in
    // every scan and the LiDAR's free evidence outvotes the sonar. The
    // table has not changed, only a property of one sensor, so the summed
    // verdict is about beam counts, not about the table. Max fusion keeps
    // one map per question and does not move.
    let sparse = TableScene::default().with_lidar_beams(6).unwrap();
    let dense = TableScene::default().with_lidar_beams(360).unwrap();
    let a = finished(&sparse);
    let b = finished(&dense);
    assert_eq!(a.sonar(), b.sonar(), "the sonar's map is bit-identical");
    let (ma, mb) = (a.footprint_means(), b.footprint_means());
    assert!(
        ma.sum > 0.5,
        "6 beams: the summed table is occupied ({})",
        ma.sum
    );
    assert!(
        mb.sum < 0.10,
        "360 beams: the summed table is gone ({})",
        mb.sum
    );
    assert!((ma.max - mb.max).abs() < 0.01, "{} vs {}", ma.max, mb.max);
    assert!(ma.max > 0.55 && mb.max > 0.55);

    // And in between, more beams only push the sum further toward free.
    let sums: Vec<f64> = [6, 16, 45, 360]
        .iter()
        .map(|&n| {
            let s = TableScene::default().with_lidar_beams(n).unwrap();
            finished(&s).footprint_means().sum
        })
        .collect();
    assert!(sums.windows(2).all(|w| w[1] < w[0]), "{sums:?}");
}

/// Checks eq. 9.9 cell by cell: never less occupied than either modality,
/// and equal to one of them.
fn assert_max_dominates(f: &TableFusion) {
    let (s, l) = (f.sonar(), f.lidar());
    let p = f.fused_probabilities();
    assert_eq!(p.len(), s.geometry().len());
    let fused = f.fused();
    for (i, &pi) in p.iter().enumerate() {
        let (ps, pl) = (s.probability_at(i), l.probability_at(i));
        assert!(pi >= ps && pi >= pl, "cell {i}: {} < {ps} or {pl}", p[i]);
        assert!(p[i] == ps || p[i] == pl, "cell {i}");
        // The drawn map says the same thing.
        let lf = fused.log_odds()[i];
        assert!(lf >= s.log_odds()[i] && lf >= l.log_odds()[i], "cell {i}");
    }
}

#[test]
fn max_fusion_never_reports_a_cell_less_occupied_than_either_modality() {
    for beams in [6, 360] {
        let scene = TableScene::default().with_lidar_beams(beams).unwrap();
        let mut f = TableFusion::new(&scene).unwrap();
        assert_max_dominates(&f);
        let mut k = 0;
        while f.step() {
            k += 1;
            if k % 10 == 0 {
                assert_max_dominates(&f);
            }
        }
        assert_max_dominates(&f);
    }
    // Also on maps the fusion module never built itself.
    let g = *TableScene::default().build().unwrap().geometry();
    let mut a = LogOddsGrid::new(g, Default::default()).unwrap();
    let mut b = LogOddsGrid::new(g, Default::default()).unwrap();
    for i in 0..g.len() {
        a.apply(i, ((i * 7919) % 23) as f32 - 11.0);
        b.apply(i, ((i * 104_729) % 19) as f32 - 9.0);
    }
    let p = max_fused_probabilities(&[&a, &b]).unwrap();
    for (i, &pi) in p.iter().enumerate() {
        assert!(pi >= a.probability_at(i) && pi >= b.probability_at(i));
    }
}

#[test]
fn the_sonar_map_holds_the_top_and_the_lidar_map_holds_the_legs() {
    let f = finished(&TableScene::default());
    let run = f.run();
    let shins = run.shins().occupied();
    let legs: Vec<usize> = run
        .footprint()
        .iter()
        .copied()
        .filter(|&i| shins[i])
        .collect();
    assert_eq!(legs.len(), 4, "one 5 cm cell per 6 cm leg here");
    for &i in &legs {
        assert!(f.lidar().probability_at(i) > 0.9, "leg cell {i}");
        assert!(f.fused_probabilities()[i] > 0.9, "a leg survives fusion");
    }
    // The LiDAR calls most of the floor under the table free.
    let free = run
        .footprint()
        .iter()
        .filter(|&&i| f.lidar().probability_at(i) < 0.1)
        .count();
    assert!(free * 10 > run.footprint().len() * 8, "{free}");
    // The sonar never sees past the top's edge: it marks a rim, never a
    // footprint cell free, and leaves the middle unknown.
    let sonar = f.sonar();
    let (occupied, freed, unknown) = run.footprint().iter().fold((0, 0, 0), |(o, fr, u), &i| {
        let p = sonar.probability_at(i);
        (
            o + (p > 0.9) as usize,
            fr + (p < 0.4) as usize,
            u + sonar.is_unknown(i) as usize,
        )
    });
    assert!(
        occupied >= 120,
        "{occupied} rim cells, {freed} freed, {unknown} unknown"
    );
    assert_eq!(freed, 0);
    assert!(unknown >= 150, "{unknown} cells the sonar cannot see");
}

#[test]
fn same_seed_gives_bit_identical_maps() {
    let a = finished(&TableScene::default());
    let b = finished(&TableScene::default());
    assert_eq!(a.summed(), b.summed());
    assert_eq!(a.fused(), b.fused());
    assert_eq!(a.fused_probabilities(), b.fused_probabilities());
    let other = TableScene {
        seed: 8,
        ..TableScene::default()
    };
    let c = finished(&other);
    assert_ne!(a.summed(), c.summed());
    // Another seed, the same story.
    let m = c.footprint_means();
    assert!(m.max > 0.55 && m.sum < 0.10, "{m:?}");
}

#[test]
fn changing_the_beam_count_mid_run_replays_to_the_same_step() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    for _ in 0..30 {
        f.step();
    }
    f.set_lidar_beams(12).unwrap();
    assert_eq!(f.steps_done(), 30);
    let mut fresh = TableFusion::new(&TableScene::default().with_lidar_beams(12).unwrap()).unwrap();
    for _ in 0..30 {
        fresh.step();
    }
    assert_eq!(f.summed(), fresh.summed());
    assert_eq!(f.fused_probabilities(), fresh.fused_probabilities());
    assert_eq!(f.readout(), fresh.readout());
    assert_eq!(f.readout().lidar_beams, 12);
}

#[test]
fn bad_input_is_an_error_naming_the_field_and_leaves_the_maps_alone() {
    let mut f = TableFusion::new(&TableScene::default()).unwrap();
    for _ in 0..10 {
        f.step();
    }
    let before = (f.summed().clone(), f.readout());
    for beams in [0, 1_000_000] {
        let e = f.set_lidar_beams(beams).unwrap_err().to_string();
        assert!(
            e.contains("lidar.beams") && e.contains(&beams.to_string()),
            "{e}"
        );
    }
    assert_eq!((f.summed().clone(), f.readout()), before);

    let scene = TableScene::default();
    for (models, field) in [
        (
            FusionModels {
                sonar_p_occ: 1.0,
                ..Default::default()
            },
            "sonar_p_occ",
        ),
        (
            FusionModels {
                lidar_alpha: -0.1,
                ..Default::default()
            },
            "alpha",
        ),
        (
            FusionModels {
                clamp: 0.0,
                ..Default::default()
            },
            "clamp",
        ),
        (
            FusionModels {
                prior: f64::NAN,
                ..Default::default()
            },
            "prior",
        ),
    ] {
        let e = TableFusion::with_models(&scene, models)
            .unwrap_err()
            .to_string();
        assert!(e.contains(field), "{e}");
    }
    let e = TableFusion::new(&TableScene {
        resolution: 0.0,
        ..TableScene::default()
    })
    .unwrap_err()
    .to_string();
    assert!(e.contains("resolution") && e.contains('0'), "{e}");
}

#[test]
fn stepping_past_the_end_changes_nothing() {
    let mut f = finished(&TableScene::default());
    let before = f.summed().clone();
    assert!(!f.step());
    assert_eq!(f.summed(), &before);
    f.reset();
    assert_eq!(f.steps_done(), 0);
    assert!(f.summed().log_odds().iter().all(|&l| l == 0.0));
    assert_eq!(f.footprint_means().max, 0.5);
}
