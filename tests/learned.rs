#![cfg(not(target_arch = "wasm32"))]
//! The learned inverse model of §9.3 (§9.3): training is deterministic
//! and reaches the regression's optimum; the model learns its own negative
//! prior and its skepticism of max-range readings; trained on buildings
//! with thin walls, its occupied band ends a few decimetres past the
//! reading, and its reach, read off the model, ends with it; removing its
//! own `l0` keeps unknown cells put while `l0 = 0` makes them drift; it
//! works in both mappers; and its map of the apartment is scored against
//! the ground truth beside the hand-crafted model's, in Map Weaver too,
//! without the band behind every wall a prior of deep blocks paints.

use occgrid::apps::map_weaver::WeaverSettings;
use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::{logit, FilterSettings, LogOddsGrid};
use occgrid::inverse::learned::{
    LearnedInverse, BEHIND_BAND, BEYOND, BIAS, FEATURES, NEGLIGIBLE, SPLINE_END,
};
use occgrid::inverse::probes::{axis_log_odds, BeamLattice};
use occgrid::inverse::training::{
    cross_entropy, fit, sample_triplets, seed_from_number, summarize, train, FitReport,
    TrainingConfig, TrainingSet,
};
use occgrid::inverse::{HandCrafted, InverseModel};
use occgrid::mapping::drift::prior_drift;
use occgrid::mapping::sweep::sweep_scan;
use occgrid::mapping::traversal::RayMapper;
use occgrid::scenes::apartment::{ApartmentScene, ApartmentSim};
use occgrid::sensors::beam_model::{BeamModel, BeamShape};
use occgrid::sensors::Scan;
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::sync::OnceLock;

/// The default training run (seed 9, 24,000 triplets), shared by the tests.
fn trained() -> &'static (LearnedInverse, TrainingSet, FitReport) {
    static RUN: OnceLock<(LearnedInverse, TrainingSet, FitReport)> = OnceLock::new();
    RUN.get_or_init(|| train(&TrainingConfig::default()).unwrap())
}

fn model() -> &'static LearnedInverse {
    &trained().0
}

#[test]
fn training_is_deterministic_for_a_seed() {
    let (again, set, _) = train(&TrainingConfig::default()).unwrap();
    let bits = |m: &LearnedInverse| m.weights().map(f64::to_bits);
    assert_eq!(bits(&again), bits(model()), "same seed, same weights");
    assert_eq!(set.triplets, trained().1.triplets, "same seed, same data");
    let other = TrainingConfig {
        seed: 10,
        ..TrainingConfig::default()
    };
    let (different, _, _) = train(&other).unwrap();
    assert_ne!(bits(&different), bits(model()));
}

#[test]
fn learned_l0_is_negative_and_near_the_prior_of_the_sampled_maps() {
    let (m, set, _) = trained();
    let l0 = m.own_l0();
    // Read off the model: the score far beyond a short reading, the same at
    // any bearing inside the field.
    let w = m.weights();
    assert!((l0 - (w[BIAS] + w[BEYOND])).abs() < 1e-12);
    assert!((m.score(2.0 + SPLINE_END + 1.0, 0.05, 2.0) - l0).abs() < 1e-12);
    // What the maps say: the occupied share of the target cells far beyond
    // a real return, and of all cells of the sampled maps.
    let beyond: Vec<_> = set
        .triplets
        .iter()
        .filter(|t| t.z < 8.0 && (t.r - t.z) as f64 >= SPLINE_END)
        .collect();
    let share = beyond.iter().filter(|t| t.occupied).count() as f64 / beyond.len() as f64;
    println!(
        "l0 = {l0:.3}; occupied share far beyond a reading {share:.3} (logit {:.3}, {} cells); \
         sampled maps {:.3} occupied (logit {:.3}) over {} maps",
        logit(share),
        beyond.len(),
        set.map_occupancy,
        logit(set.map_occupancy),
        set.maps
    );
    assert!(l0 < 0.0, "{l0}");
    // The sampled buildings are about a sixth occupied, so the prior is
    // well below the -0.3 of a map of deep blocks (about two fifths
    // occupied): the price of thin walls.
    assert!((0.12..0.22).contains(&set.map_occupancy), "{set:?}");
    assert!((-2.4..=-1.5).contains(&l0), "{l0}");
    assert!((l0 - logit(share)).abs() < 0.2, "{l0} vs {}", logit(share));
    // Cells past a reading's band are room behind a wall or a piece of
    // furniture, a little emptier than the maps as a whole (whose count
    // includes the outer wall and the inside of every obstacle, which no
    // target past a reading lands in).
    let prior = logit(set.map_occupancy);
    assert!(l0 < prior && prior - l0 < 0.5, "{l0} vs {prior}");
}

#[test]
fn free_evidence_along_a_max_range_reading_is_less_than_half_of_a_short_ones() {
    let s = summarize(model()).unwrap();
    println!(
        "mean free evidence: {:.3} in front of a {} m reading, {:.3} along a max-range reading",
        s.free_evidence_short, s.short_reading, s.free_evidence_max_range
    );
    assert!(s.free_evidence_short < -1.5, "{s:?}");
    assert!(
        s.free_evidence_max_range.abs() < 0.5 * s.free_evidence_short.abs(),
        "{s:?}"
    );
    // Still free, only weakly.
    assert!(s.free_evidence_max_range < 0.0, "{s:?}");
}

#[test]
fn mapping_with_l0_forced_to_zero_drifts_and_with_its_own_l0_does_not() {
    let m = model();
    // Few enough scans that the drift stays inside the grid's clamp.
    let scans = 5;
    let r = prior_drift(m, 2.0, scans).unwrap();
    println!("{r:?}, l0 = {:.4}", m.own_l0());
    assert!(r.cells > 10);
    assert!(r.own_l0.abs() < 1e-6, "{r:?}");
    let expected = scans as f64 * m.own_l0();
    assert!((r.zero_l0 - expected).abs() < 1e-3, "{r:?} vs {expected}");
    assert!(r.zero_l0 < -2.0, "{r:?}");

    // The same with the ray-traversal mapper along one thin beam: a cell
    // just past the band, which the traversal reaches only when the prior
    // is not the model's own (with its own, the cell would get exactly
    // nothing, so the field ends with the band).
    let g = GridGeometry::new(60, 5, 0.1, 0.0, 0.0).unwrap();
    let scan = Scan::new(Pose::new(0.05, 0.25, 0.0).unwrap(), vec![2.0], vec![0.0]).unwrap();
    let i = ((2.0 + m.band_end()) / 0.1).floor() as usize + 1;
    let d = i as f64 * 0.1 - 2.0;
    assert!(d > m.band_end() && d <= m.band_end() + BEHIND_BAND, "{d}");
    assert!(m.reach(2.0) < 2.0 + d && m.with_l0(0.0).reach(2.0) >= 2.0 + d);
    let behind = g.index(i, 2);
    let run = |model: &LearnedInverse| {
        let mut grid = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        let mut mapper = RayMapper::new();
        for _ in 0..scans {
            mapper.integrate(&mut grid, model, &scan);
        }
        grid.log_odds()[behind] as f64
    };
    assert_eq!(run(m), 0.0, "own l0: the cell stays at the prior");
    let drifted = run(&m.with_l0(0.0));
    assert!((drifted - expected).abs() < 1e-3, "{drifted} vs {expected}");
}

/// Newton's method on the same cross-entropy: the exact optimum SGD should
/// reach.
fn newton(config: &TrainingConfig, set: &TrainingSet) -> [f64; FEATURES] {
    use nalgebra::{SMatrix, SVector};
    let frame = config.frame();
    let rows: Vec<([f64; FEATURES], f64)> = set
        .triplets
        .iter()
        .map(|t| {
            let phi = frame.features(t.r as f64, t.psi as f64, t.z as f64);
            (phi, if t.occupied { 1.0 } else { 0.0 })
        })
        .collect();
    let mut w = SVector::<f64, FEATURES>::zeros();
    for _ in 0..12 {
        let mut h = SMatrix::<f64, FEATURES, FEATURES>::identity() * 1e-9;
        let mut g = SVector::<f64, FEATURES>::zeros();
        for (phi, y) in &rows {
            let x = SVector::<f64, FEATURES>::from_row_slice(phi);
            let p = 1.0 / (1.0 + (-x.dot(&w)).exp());
            g += x * (p - y);
            h += x * x.transpose() * (p * (1.0 - p));
        }
        w -= h
            .cholesky()
            .expect("the Hessian is positive definite")
            .solve(&g);
    }
    let mut out = [0.0; FEATURES];
    out.copy_from_slice(w.as_slice());
    out
}

#[test]
fn sgd_reaches_the_minimum_of_the_cross_entropy() {
    let config = TrainingConfig::default();
    let (m, set, _) = trained();
    let exact = LearnedInverse::new(config.frame(), newton(&config, set)).unwrap();
    let (sgd, best) = (cross_entropy(m, set), cross_entropy(&exact, set));
    println!(
        "cross-entropy: SGD {sgd:.5} nats, Newton {best:.5}; l0 {:.3} vs {:.3}",
        m.own_l0(),
        exact.own_l0()
    );
    assert!(sgd >= best - 1e-9, "Newton's optimum is the minimum");
    assert!(sgd - best < 2e-3, "{sgd} vs {best}");
    assert!((m.own_l0() - exact.own_l0()).abs() < 0.05);
    // And SGD did learn: clearly better than the best constant guess (most
    // target cells lie where a reading says little, so the gain is modest
    // on average and large near the reading).
    let p = trained().2.occupied_fraction;
    let constant = -(p * p.ln() + (1.0 - p) * (1.0 - p).ln());
    println!("best constant: {constant:.5} nats");
    assert!(sgd < 0.95 * constant, "{sgd} vs {constant}");
}

#[test]
fn the_learned_model_has_the_shape_the_chapter_describes() {
    let m = model();
    let z = 2.0;
    let lattice = BeamLattice {
        min_range: 0.0,
        max_range: 4.0,
        ranges: 401,
        max_bearing: 0.0,
        bearings: 2,
    };
    let axis = axis_log_odds(m, z, &lattice).unwrap();
    let l0 = m.own_l0() as f32;
    let at = |r: f64| axis[(r / 0.01).round() as usize] - l0;
    // Free in front, strongly.
    assert!(at(1.0) < -1.5, "{}", at(1.0));
    // The occupied band peaks slightly past the reading.
    let (peak_i, peak) =
        axis.iter()
            .enumerate()
            .fold((0, f32::MIN), |b, (i, &v)| if v > b.1 { (i, v) } else { b });
    let peak_r = peak_i as f64 * 0.01;
    println!(
        "peak {:.2} log odds at {peak_r:.2} m for a 2 m reading",
        peak - l0
    );
    assert!(peak_r > z && peak_r < z + 0.4, "{peak_r}");
    assert!(peak - l0 > 0.5);
    // A ramp, not a step (a step would cross in one 1 cm sample): from the
    // free plateau to the prior over a few centimetres, as wide as the
    // reading's noise (sigma_hit 5 cm) and no wider than half of the
    // counterpart's alpha (two cells, 0.2 m), ending at the reading.
    let plateau = at(1.0);
    let first = |test: &dyn Fn(f32) -> bool| {
        (100..axis.len()).find(|&i| test(axis[i] - l0)).unwrap() as f64 * 0.01
    };
    let start = first(&|e| e > 0.9 * plateau);
    let end = first(&|e| e > 0.0);
    println!("ramp: from 90% of the free evidence at {start:.2} m to the prior at {end:.2} m");
    assert!(end - start > 0.02 && end - start <= 0.1, "{start} {end}");
    assert!((end - z).abs() < 0.05, "{end}");
    // Evidence concentrated near the axis: at the cone's edge (half of
    // beta) the occupied evidence is less than half of the axis's.
    let h = TrainingConfig::default().half_width;
    assert!(m.evidence(peak_r, h, z) < 0.5 * m.evidence(peak_r, 0.0, z));
    // Past the band, and outside the field: nothing at all.
    assert_eq!(m.evidence(z + m.band_end() + 0.01, 0.0, z), 0.0);
    assert_eq!(m.evidence(z + m.band_end() + 0.01, 0.8 * h, z), 0.0);
    assert_eq!(m.evidence(z + SPLINE_END + 0.05, 0.0, z), 0.0);
    assert_eq!(m.evidence(1.0, m.half_width() * 1.01, z), 0.0);
    assert_eq!(m.evidence(m.reach(z) + 0.01, 0.0, z), 0.0);
}

#[test]
fn the_learned_model_maps_a_wall_in_both_mappers() {
    let m = model();
    // A wall 3 m east of the sensor seen by a fan of beams 1 degree apart.
    let g = GridGeometry::new(50, 40, 0.1, 0.0, -2.0).unwrap();
    let pose = Pose::new(0.05, 0.05, 0.0).unwrap();
    let bearings: Vec<f64> = (-10..=10).map(|k| (k as f64).to_radians()).collect();
    let ranges: Vec<f64> = bearings.iter().map(|b| 2.95 / b.cos()).collect();
    let scan = Scan::new(pose, ranges, bearings).unwrap();
    let cell = |x: f64, y: f64| {
        let (ix, iy) = g.world_to_cell(x, y).unwrap();
        g.index(ix, iy)
    };
    let mut by_ray = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    RayMapper::new().integrate(&mut by_ray, m, &scan);
    let mut by_sweep = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    sweep_scan(&mut by_sweep, m, &scan);
    for (name, grid) in [("ray traversal", &by_ray), ("sweep", &by_sweep)] {
        let l = |x, y| grid.log_odds()[cell(x, y)];
        assert!(l(1.5, 0.05) < -1.5, "{name}: free in front");
        assert!(l(2.85, 0.05) < 0.0, "{name}: free in front of the face");
        assert!(l(3.05, 0.05) > 1.5, "{name}: most occupied at the face");
        assert!(l(3.25, 0.05) > 0.0, "{name}: still occupied just past it");
        assert!(
            l(3.05, 0.05) > 2.0 * l(3.25, 0.05),
            "{name}: the band falls off behind the face"
        );
        assert_eq!(l(3.55, 0.05), 0.0, "{name}: nothing 0.6 m behind");
        assert_eq!(l(4.5, 0.05), 0.0, "{name}: nothing far behind");
        assert_eq!(l(1.5, 1.5), 0.0, "{name}: nothing outside the fan");
    }
}

/// Brier scores of one lap of the apartment, mapped by both models with
/// the ray-traversal mapper, over the surveyed region and over the map.
fn lap_brier(forward_readings: bool) -> [(f64, f64); 2] {
    let scene = ApartmentScene::default();
    let mut sim = ApartmentSim::new(scene.clone(), 1, false).unwrap();
    let truth = sim.ground_truth().clone();
    let g = *truth.geometry();
    let region = scene.cells_in(&g, &[scene.surveyed]);
    let bearings = sim.bearings().to_vec();
    // Map Weaver's hand-crafted model for this LiDAR.
    let hand = HandCrafted::new(WeaverSettings::default().hand_crafted).unwrap();
    let config = TrainingConfig::default();
    let sensor = BeamModel::new(config.sensor).unwrap();
    let shape = BeamShape::cone(config.half_width, config.sub_rays).unwrap();
    let mut rng = StdRng::seed_from_u64(5);
    let mut grids = [0, 1].map(|_| LogOddsGrid::new(g, FilterSettings::default()).unwrap());
    let mut mappers = [RayMapper::new(), RayMapper::new()];
    for _ in 0..scene.scans_per_lap() {
        let s = sim.next_scan();
        let scan = if forward_readings {
            sensor
                .sample_scan(&truth, &s.truth, &bearings, shape, &mut rng)
                .unwrap()
        } else {
            Scan::new(s.truth, s.ranges, bearings.clone()).unwrap()
        };
        mappers[0].integrate(&mut grids[0], &hand, &scan);
        mappers[1].integrate(&mut grids[1], model(), &scan);
    }
    grids.map(|grid| {
        (
            grid.brier_score(truth.occupied(), Some(&region)).unwrap(),
            grid.brier_score(truth.occupied(), None).unwrap(),
        )
    })
}

#[test]
fn brier_scores_of_both_models_against_the_apartments_ground_truth() {
    // An untouched map (p = 0.5 everywhere) scores 0.25; a perfect one 0.
    let [hand, learned] = lap_brier(false);
    println!(
        "one lap, the apartment's LiDAR readings: Brier surveyed / whole map: \
         hand-crafted {:.4} / {:.4}, learned {:.4} / {:.4}",
        hand.0, hand.1, learned.0, learned.1
    );
    assert!(hand.0 < 0.08 && hand.1 < 0.14, "{hand:?}");
    // The learned model maps the apartment at least as well as Table 9.2,
    // over the surveyed rooms and over the whole map (where a band behind
    // every wall of the rooms the lap never enters would show).
    assert!(learned.0 < hand.0 + 0.01, "{hand:?} {learned:?}");
    assert!(learned.1 < hand.1 + 0.01, "{hand:?} {learned:?}");

    // Readings from the forward model it was trained on (short readings,
    // random ones, dropouts): there it knows better than to trust them.
    let [hand, learned] = lap_brier(true);
    println!(
        "one lap, forward-model readings (5 degree cone, chapter mixture): Brier surveyed / \
         whole map: hand-crafted {:.4} / {:.4}, learned {:.4} / {:.4}",
        hand.0, hand.1, learned.0, learned.1
    );
    assert!(hand.0 < 0.2 && hand.1 < 0.25, "{hand:?}");
    assert!(
        learned.0 < hand.0 && learned.1 < hand.1,
        "{hand:?} {learned:?}"
    );
}

#[test]
fn the_occupied_band_ends_a_few_decimetres_past_the_reading() {
    let m = model();
    let l0 = m.own_l0();
    println!(
        "band ends {:.3} m past the reading; reach of a 2 m reading {:.3} m",
        m.band_end(),
        m.reach(2.0)
    );
    // Read off the model: a few decimetres, well short of the features'
    // ceiling, and the reach of a real return ends with the band.
    assert!(
        (0.2..=0.45).contains(&m.band_end()) && m.band_end() < SPLINE_END - 0.05,
        "{}",
        m.band_end()
    );
    for z in [1.0, 2.0, 4.0, 6.0] {
        assert_eq!(m.reach(z), z + m.band_end());
        let e = |d: f64| m.evidence(z + d, 0.0, z);
        let peak = (0..50).map(|i| e(i as f64 * 0.01)).fold(f32::MIN, f32::max);
        println!(
            "z = {z}: peak {peak:.2}, at +0.2 m {:.2}, +0.3 m {:.2}, +0.4 m {:.2}",
            e(0.2),
            e(0.3),
            e(0.4)
        );
        assert!(peak > 1.5, "{z}: {peak}");
        // Past its half-height by 0.3 m, and nothing past the band's end
        // (at most 0.45 m, above), at any bearing: the fitted score
        // itself, before anything is dropped, is negligible there.
        assert!(e(0.3) < 0.5 * peak, "{z}: {}", e(0.3));
        for psi in [0.0, 0.02, -0.04, 0.06] {
            assert_eq!(m.evidence(z + m.band_end() + 0.005, psi, z), 0.0);
            assert_eq!(m.evidence(z + 0.5, psi, z), 0.0);
            for k in 0..=20 {
                let d = m.band_end() + k as f64 * (SPLINE_END - m.band_end()) / 20.0;
                let fitted = m.score(z + d, psi, z) - l0;
                assert!(fitted.abs() < NEGLIGIBLE, "{z} {psi} {d}: {fitted}");
            }
        }
    }
}

/// Map Weaver as shipped (the apartment, seed 1, the person walking, the
/// hand-crafted pane beside the learned one) with the default training.
fn weaver_after(laps: usize) -> occgrid::apps::map_weaver::Weaver {
    use occgrid::apps::map_weaver::{ModelKind, Weaver, WeaverSettings};
    let settings = WeaverSettings::default();
    assert_eq!(settings.training, TrainingConfig::default());
    assert_eq!(settings.panes[0].model, ModelKind::HandCrafted);
    assert_eq!(settings.panes[1].model, ModelKind::Learned);
    let mut w = Weaver::with_learned(settings, model().clone()).unwrap();
    let n = w.scans_per_lap();
    assert_eq!(w.advance(laps * n).unwrap(), laps * n);
    w
}

#[test]
fn map_weavers_learned_pane_scores_within_a_hundredth_of_the_hand_crafted_one() {
    for laps in [1, 3] {
        let w = weaver_after(laps);
        let r = w.readout();
        let (hand, learned) = (&r.panes[0], &r.panes[1]);
        println!(
            "Map Weaver after {laps} lap(s): Brier surveyed / whole map: hand-crafted {:.4} / {:.4}, \
             learned {:.4} / {:.4}; cells visited per scan {} / {}",
            hand.brier, hand.brier_all, learned.brier, learned.brier_all,
            hand.cells_visited, learned.cells_visited
        );
        assert!(hand.brier < 0.09, "{hand:?}");
        assert!(learned.brier < hand.brier + 0.01, "{hand:?} {learned:?}");
        assert!(
            learned.brier_all < hand.brier_all + 0.01,
            "{hand:?} {learned:?}"
        );
    }
}

#[test]
fn no_band_is_painted_behind_the_walls_of_the_rooms_the_lap_never_enters() {
    // The corridor's north wall (y 5.5 to 5.6 m) between the two doors:
    // the lap sees it only from the corridor, so whatever its beams paint
    // behind it, in the study and the bedroom, stays.
    let w = weaver_after(3);
    let g = *w.geometry();
    let grid = w.grid(1).unwrap();
    let truth = w.ground_truth();
    // Cells of row y (metres) between the doors whose truth is `wall`, and
    // how many of them the learned pane calls occupied.
    let row = |y: f64, wall: bool| -> (usize, usize) {
        let (mut occupied, mut cells) = (0, 0);
        for k in 0..85 {
            let x = 1.55 + 0.1 * k as f64;
            let (ix, iy) = g.world_to_cell(x, y).unwrap();
            let i = g.index(ix, iy);
            // (The study | bedroom wall at x = 5.0 m crosses the rows
            // behind the corridor's.)
            if truth[i] == wall {
                cells += 1;
                occupied += (grid.probability_at(i) > 0.5) as usize;
            }
        }
        (occupied, cells)
    };
    let wall = row(5.55, true);
    println!("the wall: {wall:?} cells occupied");
    assert!(wall.1 == 85 && wall.0 >= 80, "{wall:?}");
    // The band the model learned runs a few decimetres past a reading (at
    // most 0.45 m, `the_occupied_band_ends_a_few_decimetres_past_the_
    // reading`): a beam cannot tell a wall met head-on (free room behind
    // it) from one met at a slant (more wall behind the face), so the
    // cells behind the wall that the band reaches fill in. Past it,
    // nothing: a prior of deep blocks painted 0.7 m.
    let band = model().band_end();
    assert!(band <= 0.45, "{band}");
    let face = 5.5;
    for (k, y) in [5.65, 5.75, 5.85, 5.95, 6.05, 6.15].into_iter().enumerate() {
        let (occupied, cells) = row(y, false);
        // How far past the face the row's nearest edge lies.
        let depth = y - 0.05 - face;
        println!(
            "{:.2} m behind the wall ({depth:.2} m past its face, band {band:.3} m): \
             {occupied} of {cells} cells occupied",
            0.1 * k as f64 + 0.05
        );
        // A row the band reaches only through a long reading's noise
        // (the apartment LiDAR's sigma is 2 cm: within half a cell) keeps under a tenth.
        if depth > band {
            assert!(occupied * 10 < cells, "{y}: {occupied} of {cells}");
        }
        if depth > band + 0.05 {
            assert_eq!(occupied, 0, "{y}");
        }
        // The rows closest behind the wall are always reached.
        if k < 2 {
            assert!(occupied * 10 > 9 * cells, "{y}: {occupied} of {cells}");
        }
    }
}

#[test]
fn bad_configurations_are_errors_that_name_the_field() {
    let d = TrainingConfig::default();
    let cases: [(TrainingConfig, &str); 7] = [
        (TrainingConfig { triplets: 0, ..d }, "triplets"),
        (TrainingConfig { epochs: 0, ..d }, "epochs"),
        (
            TrainingConfig {
                learning_rate: f64::NAN,
                ..d
            },
            "learning_rate",
        ),
        (
            TrainingConfig {
                half_width: 0.0,
                ..d
            },
            "half_width",
        ),
        (TrainingConfig { sub_rays: 0, ..d }, "sub_rays"),
        (
            TrainingConfig {
                resolution: 1e-4,
                ..d
            },
            "resolution",
        ),
        (
            TrainingConfig {
                sensor: occgrid::sensors::beam_model::BeamModelParams {
                    z_hit: 0.5,
                    ..d.sensor
                },
                ..d
            },
            "add up to 1",
        ),
    ];
    for (config, field) in cases {
        let e = sample_triplets(&config).unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
    let empty = TrainingSet {
        triplets: vec![],
        maps: 0,
        map_occupancy: 0.0,
        no_returns: 0.0,
        readings: 0,
    };
    assert!(fit(&d, &empty)
        .unwrap_err()
        .to_string()
        .contains("triplets"));
    assert_eq!(seed_from_number(42.0).unwrap(), 42);
    for bad in [-1.0, 1.5, f64::NAN, f64::INFINITY, 1e300] {
        assert!(seed_from_number(bad)
            .unwrap_err()
            .to_string()
            .contains("seed"));
    }
    let mut w = *model().weights();
    w[3] = f64::NAN;
    let e = LearnedInverse::new(d.frame(), w).unwrap_err().to_string();
    assert!(e.contains("weights[3]"), "{e}");
}

#[test]
fn evidence_of_non_numbers_is_no_information() {
    let m = model();
    for (r, phi, z) in [
        (f64::NAN, 0.0, 2.0),
        (1.0, f64::NAN, 2.0),
        (1.0, 0.0, f64::NAN),
        (f64::INFINITY, 0.0, 2.0),
        (1.0, f64::INFINITY, 2.0),
    ] {
        assert_eq!(m.evidence(r, phi, z), 0.0, "({r}, {phi}, {z})");
    }
    assert!(
        m.evidence(-0.05, 0.0, 2.0) < 0.0,
        "the sensor's own cell is free"
    );
}
