#![cfg(not(target_arch = "wasm32"))]
//! MAP occupancy mapping (Table 9.3) on the doorway scene and on random
//! small scenes: the climb ends at a true local maximum, its incremental
//! gains are the gains a brute-force search would compute, and it keeps the
//! door open where the literal Table 9.1 sweep closes it.

use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::{logit, FilterSettings, LogOddsGrid};
use occgrid::mapping::map_search::{MapSearch, MapSearchSettings, MIN_GAIN};
use occgrid::mapping::sweep::sweep_scan;
use occgrid::scenes::doorway::DoorwayScene;
use occgrid::sensors::beam_model::{BeamModel, BeamModelParams};
use occgrid::sensors::scan::ConeBeam;
use occgrid::world::{Rect, World};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

fn doorway_search() -> (DoorwayScene, MapSearch) {
    let scene = DoorwayScene::standard();
    let search = MapSearch::new(
        scene.geometry().unwrap(),
        scene.beams().unwrap(),
        occgrid::apps::doorway_trap::search_settings(&scene),
    )
    .unwrap();
    (scene, search)
}

/// `J(m)` computed without the search's caches: each beam's expected range
/// from the ground-truth cone caster on a world holding `occupied`.
fn objective_by_cone_casts(search: &MapSearch, occupied: &[bool]) -> f64 {
    let mut world = World::empty(*search.geometry());
    world.occupied_mut().copy_from_slice(occupied);
    let st = search.settings();
    let model = BeamModel::new(st.model).unwrap();
    let log_lik: f64 = search
        .beams()
        .iter()
        .map(|b| {
            let z_star = world
                .cast_cone(
                    b.pose.x,
                    b.pose.y,
                    b.pose.theta + b.bearing,
                    st.half_width,
                    st.sub_rays,
                    st.model.z_max,
                )
                .unwrap();
            model.density(b.range, z_star).max(1e-300).ln()
        })
        .sum();
    let count = occupied.iter().filter(|&&o| o).count() as f64;
    log_lik + logit(st.prior) * count
}

#[test]
fn map_result_on_the_doorway_is_a_local_maximum_by_brute_force() {
    let (_, mut search) = doorway_search();
    let flips = search.run(10_000);
    assert!(search.is_converged(), "stopped after {flips} flips");
    assert!(search.step().is_none());

    // Try every single flip from scratch: none may raise the objective.
    let base = search.evaluate(search.occupied()).unwrap();
    let mut map = search.occupied().to_vec();
    let mut best = f64::NEG_INFINITY;
    for i in 0..map.len() {
        map[i] = !map[i];
        best = best.max(search.evaluate(&map).unwrap() - base);
        map[i] = !map[i];
    }
    assert!(best <= MIN_GAIN, "a single flip still gains {best} nats");

    // The objective the climb reports is the objective of its map.
    assert!((search.objective() - base).abs() < 1e-9);
    let cast = objective_by_cone_casts(&search, search.occupied());
    assert!(
        (search.objective() - cast).abs() < 1e-9,
        "cached {} vs cone casts {cast}",
        search.objective()
    );
}

#[test]
fn incremental_gains_equal_gains_recomputed_from_scratch_after_every_flip() {
    let mut rng = StdRng::seed_from_u64(2024);
    let mut flips_checked = 0;
    for scene in 0..40 {
        let (w, h) = (rng.random_range(5..16), rng.random_range(5..16));
        let res = 0.1;
        let g = GridGeometry::new(w, h, res, 0.0, 0.0).unwrap();
        let (wm, hm) = (w as f64 * res, h as f64 * res);
        let mut world = World::empty(g);
        for _ in 0..rng.random_range(0..4) {
            let (x, y) = (rng.random_range(0.0..wm), rng.random_range(0.0..hm));
            let (dx, dy) = (rng.random_range(0.05..0.5), rng.random_range(0.05..0.5));
            world.fill(&Rect::new(x, y, x + dx, y + dy), true);
        }
        let settings = MapSearchSettings {
            prior: rng.random_range(0.15..0.7),
            half_width: rng.random_range(0.0..0.35),
            sub_rays: rng.random_range(1..8),
            model: BeamModelParams {
                z_max: rng.random_range(0.6..1.8),
                ..BeamModelParams::CHAPTER
            },
        };
        let z_max = settings.model.z_max;
        let beams: Vec<ConeBeam> = (0..rng.random_range(1..12))
            .map(|_| {
                let pose =
                    Pose::new(rng.random_range(0.0..wm), rng.random_range(0.0..hm), 0.0).unwrap();
                let bearing = rng.random_range(-3.2..3.2);
                // Readings of every kind: the truth, noise, no return.
                let range = match rng.random_range(0..3) {
                    0 => world
                        .cast_cone(
                            pose.x,
                            pose.y,
                            bearing,
                            settings.half_width,
                            settings.sub_rays,
                            z_max,
                        )
                        .unwrap(),
                    1 => rng.random_range(0.0..z_max),
                    _ => z_max,
                };
                ConeBeam {
                    pose,
                    bearing,
                    range,
                }
            })
            .collect();
        let mut search = MapSearch::new(g, beams, settings).unwrap();
        loop {
            let scratch = search.gains_from_scratch();
            for (i, (a, b)) in search.sensitivity().iter().zip(&scratch).enumerate() {
                assert!(
                    (a - b).abs() < 1e-9,
                    "scene {scene}, after {} flips, cell {i}: incremental {a} vs scratch {b}",
                    search.flips().len()
                );
            }
            let cast = objective_by_cone_casts(&search, search.occupied());
            assert!(
                (search.objective() - cast).abs() < 1e-9,
                "scene {scene}: objective {} vs cone casts {cast}",
                search.objective()
            );
            if search.step().is_none() {
                break;
            }
            flips_checked += 1;
        }
    }
    assert!(
        flips_checked > 100,
        "only {flips_checked} flips exercised the incremental path"
    );
}

#[test]
fn literal_sweep_closes_the_doorway_while_map_leaves_it_open_and_marks_the_far_wall() {
    let (scene, mut search) = doorway_search();
    let g = scene.geometry().unwrap();

    // Left half of the widget: Table 9.1 swept over every cell, scan by scan.
    let mut grid = LogOddsGrid::new(
        g,
        FilterSettings {
            prior: scene.prior,
            clamp: 12.0,
        },
    )
    .unwrap();
    let model = occgrid::apps::doorway_trap::inverse_model(&scene).unwrap();
    for scan in scene.scans().unwrap() {
        sweep_scan(&mut grid, &model, &scan);
    }
    let door: Vec<usize> = scene
        .cells_in(&scene.door)
        .unwrap()
        .into_iter()
        .flatten()
        .collect();
    assert_eq!(door.len(), 7, "a 0.7 m door is seven cells wide");
    for &i in &door {
        assert!(
            grid.probability_at(i) > 0.5,
            "door cell {:?} is not closed: p = {}",
            g.cell_of_index(i),
            grid.probability_at(i)
        );
    }

    // Right half: the MAP climb keeps the whole passage, door to far wall,
    // free and explains the readings through it with the far wall.
    search.run(10_000);
    let passage = Rect::new(
        scene.door.min_x,
        scene.door.min_y,
        scene.door.max_x,
        scene.far_wall.min_y,
    );
    let blocked: Vec<_> = scene
        .cells_in(&passage)
        .unwrap()
        .into_iter()
        .flatten()
        .filter(|&i| search.occupied()[i])
        .map(|i| g.cell_of_index(i))
        .collect();
    assert!(
        blocked.is_empty(),
        "MAP put cells in the doorway: {blocked:?}"
    );
    let far_wall = scene.cells_in(&scene.far_wall).unwrap();
    let truth = scene.world().unwrap();
    let on_far_wall = far_wall
        .iter()
        .flatten()
        .filter(|&&i| search.occupied()[i] && truth.occupied()[i])
        .count();
    assert!(
        on_far_wall >= 1,
        "no MAP cell on the far wall behind the door"
    );
    // And it is sparse: a handful of cells explain 63 readings.
    assert!(
        search.occupied_count() < 40,
        "{} cells",
        search.occupied_count()
    );
}

#[test]
fn every_flip_raises_the_objective_and_its_annotation_adds_up() {
    let (_, mut search) = doorway_search();
    let mut before = search.beam_log_likelihoods().to_vec();
    while let Some(flip) = search.step().cloned() {
        let after = search.beam_log_likelihoods().to_vec();
        // The annotated beams are exactly those whose likelihood moved.
        let moved: Vec<usize> = (0..after.len())
            .filter(|&b| after[b] != before[b])
            .collect();
        let listed: Vec<usize> = flip.beams.iter().map(|c| c.beam).collect();
        assert_eq!(listed, moved, "flip {}", flip.number);
        for c in &flip.beams {
            assert_eq!(c.before, before[c.beam]);
            assert_eq!(c.after, after[c.beam]);
        }
        let sum: f64 = flip.beams.iter().map(|c| c.delta).sum::<f64>() + flip.prior_term;
        assert!((sum - flip.gain).abs() < 1e-9, "flip {}", flip.number);
        assert!(flip.gain > MIN_GAIN);
        let h = search.history();
        assert_eq!(h.len(), flip.number + 1);
        assert_eq!(h[flip.number], flip.objective);
        assert!((h[flip.number] - h[flip.number - 1] - flip.gain).abs() < 1e-9);
        before = after;
    }
    assert!(search.flips().len() >= 5);
}

#[test]
fn climb_removes_a_cell_once_better_cells_explain_its_beams() {
    // Steepest ascent on the doorway first drops a cell just behind the
    // door to explain the cones that straddle a jamb, and clears it again
    // once the jamb cells explain them: single flips run both ways.
    let (_, mut search) = doorway_search();
    search.run(10_000);
    let cleared: Vec<_> = search.flips().iter().filter(|f| !f.to_occupied).collect();
    assert!(!cleared.is_empty(), "no flip ever cleared a cell");
    for f in cleared {
        assert!(f.prior_term == -search.l0());
        assert!(f.gain > MIN_GAIN);
    }
}

#[test]
fn sensitivity_at_convergence_prices_every_occupied_cell() {
    let (_, mut search) = doorway_search();
    search.run(10_000);
    let s = search.sensitivity();
    for (i, &o) in search.occupied().iter().enumerate() {
        assert!(s[i] <= MIN_GAIN, "cell {i} could still gain {}", s[i]);
        if o {
            // Removing a cell the climb chose costs something (or it would
            // never have been worth a flip).
            assert!(s[i] < 0.0, "occupied cell {i} has sensitivity {}", s[i]);
        }
    }
}

#[test]
fn same_scene_gives_the_same_climb_and_reset_starts_over() {
    let (_, mut a) = doorway_search();
    let (_, mut b) = doorway_search();
    a.run(10_000);
    b.run(10_000);
    assert_eq!(a.flips(), b.flips());
    assert_eq!(a.objective().to_bits(), b.objective().to_bits());
    let start = a.history()[0];
    a.reset();
    assert_eq!(a.occupied_count(), 0);
    assert_eq!(a.history(), &[start]);
    assert!(!a.is_converged());
    a.run(10_000);
    assert_eq!(a.flips(), b.flips());
}
