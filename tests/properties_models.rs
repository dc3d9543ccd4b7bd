#![cfg(not(target_arch = "wasm32"))]
//! docs/ARCHITECTURE.md, "Bad input" as properties over the models: the forward beam model of
//! Table 6.1 and its ray casting, the exact joint posterior of a few cells,
//! the MAP search of Table 9.3, the learned inverse model of §9.3 and its
//! training, and the fusion rule of eq. 9.9.
//!
//! Arbitrary input must give a result that keeps the function's promises
//! (probabilities in [0, 1] that add up, finite densities and objectives,
//! an objective that only climbs) or an error naming the field; state is
//! left exactly as it was on error.

mod properties_support;

use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::inverse::learned::{FeatureFrame, FEATURES};
use occgrid::inverse::probes::{
    axis_log_odds, evidence_field, mean_free_evidence, side_by_side, BeamLattice,
};
use occgrid::inverse::training::{self, seed_from_number, TrainingConfig};
use occgrid::inverse::{HandCrafted, HandCraftedParams, InverseModel, LearnedInverse};
use occgrid::mapping::drift::prior_drift;
use occgrid::mapping::fusion::{
    max_fuse_into, max_fused_probabilities, mean_over, mean_probability,
};
use occgrid::mapping::joint::{ConeCell, JointPosterior, JointQuery};
use occgrid::mapping::map_search::{MapSearch, MapSearchSettings, MIN_GAIN};
use occgrid::sensors::beam_model::{
    erf, expected_range, normal_cdf, BeamModel, BeamModelParams, BeamShape,
};
use occgrid::sensors::scan::ConeBeam;
use occgrid::world::{Rect, World};
use properties_support::*;
use proptest::prelude::*;
use rand::rngs::StdRng;
use rand::SeedableRng;

const MODEL_FIELDS: [&str; 8] = [
    "z_hit",
    "z_short",
    "z_maxw",
    "z_rand",
    "z_hit + z_short + z_maxw + z_rand",
    "sigma_hit",
    "lambda_short",
    "z_max",
];

/// Forward-model parameters from valid to absurd: the weights are a
/// random split of 1 most of the time, anything otherwise.
fn wild_beam_params() -> impl Strategy<Value = BeamModelParams> {
    let weights = prop_oneof![
        3 => (0.0..1.0f64, 0.0..1.0f64, 0.0..1.0f64).prop_map(|(a, b, c)| {
            let (lo, mid, hi) = sort3(a, b, c);
            [lo, mid - lo, hi - mid, 1.0 - hi]
        }),
        1 => prop::array::uniform4(wild_f64()),
    ];
    (weights, wild_positive(), wild_positive(), wild_positive()).prop_map(
        |([z_hit, z_short, z_maxw, z_rand], sigma_hit, lambda_short, z_max)| BeamModelParams {
            z_hit,
            sigma_hit,
            z_short,
            lambda_short,
            z_maxw,
            z_rand,
            z_max,
        },
    )
}

fn sort3(a: f64, b: f64, c: f64) -> (f64, f64, f64) {
    let mut v = [a, b, c];
    v.sort_by(f64::total_cmp);
    (v[0], v[1], v[2])
}

/// A room with a few boxes, 6 m x 5 m at 0.1 m.
fn room() -> World {
    let g = GridGeometry::new(60, 50, 0.1, 0.0, 0.0).unwrap();
    World::from_boxes(
        g,
        &[
            Rect::new(0.0, 0.0, 6.0, 0.1),
            Rect::new(0.0, 4.9, 6.0, 5.0),
            Rect::new(0.0, 0.0, 0.1, 5.0),
            Rect::new(5.9, 0.0, 6.0, 5.0),
            Rect::new(2.0, 2.0, 2.6, 2.3),
        ],
    )
}

fn valid_model() -> impl Strategy<Value = BeamModel> {
    wild_beam_params().prop_filter_map("a valid model", |p| BeamModel::new(p).ok())
}

fn valid_frame() -> impl Strategy<Value = FeatureFrame> {
    (0.5..30.0f64, 0.001..1.0f64).prop_map(|(z_max, half_width)| FeatureFrame { z_max, half_width })
}

fn lattice() -> impl Strategy<Value = BeamLattice> {
    (
        wild_f64(),
        wild_f64(),
        prop_oneof![3 => 2usize..40, 1 => wild_size()],
        wild_f64(),
        prop_oneof![3 => 2usize..40, 1 => wild_size()],
    )
        .prop_map(
            |(min_range, max_range, ranges, max_bearing, bearings)| BeamLattice {
                min_range,
                max_range,
                ranges,
                max_bearing,
                bearings,
            },
        )
}

fn grid_with(w: usize, h: usize, evidence: &[f32]) -> LogOddsGrid {
    let g = GridGeometry::new(w, h, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    for i in 0..g.len() {
        let e = evidence[i % evidence.len()];
        if e != 0.0 {
            m.apply(i, e);
        }
    }
    m
}

proptest! {
    #![proptest_config(config(1024))]

    #[test]
    fn beam_model_accepts_valid_mixtures_and_its_density_is_a_finite_non_negative_number(
        p in wild_beam_params(), z in wild_f64(), z_star in wild_f64(),
    ) {
        match BeamModel::new(p) {
            Ok(m) => {
                let d = m.density(z, z_star);
                if z_star.is_finite() {
                    prop_assert!(d.is_finite() && d >= 0.0, "p(z = {z} | z* = {z_star}) = {d} under {p:?}");
                }
                // The chapter's two reference readings, for any model.
                for (a, b) in [(0.5 * p.z_max, 0.5 * p.z_max), (0.0, p.z_max), (p.z_max, 0.0)] {
                    let d = m.density(a, b);
                    prop_assert!(d.is_finite() && d >= 0.0, "p({a} | {b}) = {d} under {p:?}");
                }
            }
            Err(e) => assert_names_one_of(&e, &MODEL_FIELDS),
        }
    }

    #[test]
    fn sampled_readings_lie_in_0_to_z_max_for_any_expected_range(
        m in valid_model(), z_star in wild_f64(), seed in any::<u64>(),
    ) {
        let mut rng = StdRng::seed_from_u64(seed);
        let z_max = m.params().z_max;
        for _ in 0..8 {
            let z = m.sample(z_star, &mut rng);
            prop_assert!((0.0..=z_max).contains(&z), "{z} outside [0, {z_max}]");
        }
    }

    #[test]
    fn cone_shapes_are_checked_and_name_their_field(h in wild_f64(), n in wild_size()) {
        match BeamShape::cone(h, n) {
            Ok(s) => prop_assert!(s.sub_rays() >= 1 && s.half_width() <= std::f64::consts::FRAC_PI_2),
            Err(e) => assert_names_one_of(&e, &["half_width", "sub_rays"]),
        }
    }

    #[test]
    fn expected_range_is_within_z_max_and_a_thin_beam_agrees_with_the_ray_caster(
        x in prop_oneof![3 => -1.0..7.0f64, 1 => wild_f64()],
        y in prop_oneof![3 => -1.0..6.0f64, 1 => wild_f64()],
        theta in wild_f64(), bearing in wild_f64(),
        z_max in prop_oneof![3 => 0.1..12.0f64, 1 => wild_f64()],
        half in 0.0..1.5f64, rays in 1usize..12,
    ) {
        let world = room();
        let pose = Pose { x, y, theta };
        let shape = BeamShape::cone(half, rays).unwrap();
        match expected_range(&world, &pose, bearing, shape, z_max) {
            Ok(z) => {
                prop_assert!((0.0..=z_max).contains(&z), "{z} outside [0, {z_max}]");
                let thin = expected_range(&world, &pose, bearing, BeamShape::THIN, z_max).unwrap();
                let cast = world.cast(x, y, theta + bearing, z_max);
                prop_assert!((thin - cast).abs() <= 1e-9 * z_max.max(1.0), "{thin} vs cast {cast}");
            }
            Err(e) => assert_names_one_of(&e, &["pose.x", "pose.y", "pose.theta", "bearing", "z_max"]),
        }
    }

    #[test]
    fn likelihoods_and_generated_scans_name_a_bad_reading_or_bearing(
        m in valid_model(), z in wild_f64(),
        bearings in prop::collection::vec(prop_oneof![3 => -3.0..3.0f64, 1 => wild_f64()], 0..5),
        seed in any::<u64>(),
    ) {
        let world = room();
        let pose = Pose::new(3.0, 1.0, 0.3).unwrap();
        match m.likelihood(&world, &pose, 0.2, BeamShape::THIN, z) {
            Ok(l) => prop_assert!(l.is_finite() && l >= 0.0),
            Err(e) => assert_names(&e, "z"),
        }
        let mut rng = StdRng::seed_from_u64(seed);
        match m.sample_scan(&world, &pose, &bearings, BeamShape::THIN, &mut rng) {
            Ok(scan) => {
                prop_assert_eq!(scan.len(), bearings.len());
                prop_assert!(scan.ranges().iter().all(|&r| (0.0..=m.params().z_max).contains(&r)));
            }
            Err(e) => assert_names_one_of(&e, &["bearings", "ranges"]),
        }
    }

    #[test]
    fn erf_and_the_normal_cdf_stay_in_range(x in wild_f64()) {
        if !x.is_nan() {
            prop_assert!((-1.0..=1.0).contains(&erf(x)), "erf({x}) = {}", erf(x));
            prop_assert!((0.0..=1.0).contains(&normal_cdf(x)), "Phi({x}) = {}", normal_cdf(x));
        }
    }

    #[test]
    fn joint_posterior_is_a_distribution_or_names_the_bad_part_of_the_query(
        prior in wild_probability(),
        beta_deg in prop_oneof![3 => 1.0..90.0f64, 1 => wild_f64()],
        cells in prop::collection::vec(
            (prop_oneof![3 => 0.0..4.0f64, 1 => wild_f64()], prop_oneof![3 => -5.0..5.0f64, 1 => wild_f64()]),
            0..8,
        ),
        readings in prop::collection::vec(prop_oneof![3 => 0.0..4.0f64, 1 => wild_f64()], 0..5),
        model in prop_oneof![3 => Just(BeamModelParams::CHAPTER), 1 => wild_beam_params()],
        pattern_len in 0usize..10,
        config_index in wild_size(),
        pair in (0usize..10, 0usize..10),
    ) {
        let q = JointQuery {
            prior,
            beta_deg,
            cells: cells.iter().map(|&(range, bearing_deg)| ConeCell { range, bearing_deg }).collect(),
            readings,
            model,
        };
        match JointPosterior::compute(&q) {
            Ok(post) => {
                let total: f64 = post.joint.iter().sum();
                prop_assert!((total - 1.0).abs() < 1e-9, "joint sums to {total}");
                prop_assert!(post.joint.iter().all(|p| p.is_finite() && *p >= 0.0));
                prop_assert!(post.marginals.iter().all(|m| (0.0..=1.0 + 1e-12).contains(m)));
                let report = post.report();
                prop_assert!(report.mutual_information_bits.is_finite());
                let pattern = vec![None; pattern_len];
                match post.event(&pattern) {
                    Ok((t, f)) => prop_assert!((t - 1.0).abs() < 1e-9 && (f - 1.0).abs() < 1e-12),
                    Err(e) => assert_names(&e, "pattern"),
                }
                match post.configuration(config_index) {
                    Ok((t, f)) => prop_assert!((0.0..=1.0 + 1e-9).contains(&t) && (0.0..=1.0 + 1e-9).contains(&f)),
                    Err(e) => assert_names(&e, "configuration"),
                }
                match post.pair_mutual_information_bits(pair.0, pair.1) {
                    Ok(mi) => prop_assert!(mi.is_finite() && mi >= 0.0),
                    Err(e) => assert_names_one_of(&e, &["a", "b"]),
                }
            }
            Err(e) => {
                let mut fields = vec!["prior", "beta_deg", "cells", "readings"];
                fields.extend(MODEL_FIELDS);
                assert_names_one_of(&e, &fields);
            }
        }
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn map_search_climbs_monotonically_and_its_bookkeeping_matches_a_recount(
        w in 4usize..24, h in 4usize..24,
        prior in prop_oneof![3 => 0.05..0.95f64, 1 => wild_probability()],
        half_width in prop_oneof![3 => 0.0..0.5f64, 1 => wild_f64()],
        sub_rays in prop_oneof![3 => 1usize..9, 1 => wild_size()],
        model in prop_oneof![2 => Just(BeamModelParams::CHAPTER), 1 => wild_beam_params()],
        beams in prop::collection::vec(
            (0.0..2.4f64, 0.0..2.4f64, -4.0..4.0f64, prop_oneof![3 => 0.0..3.0f64, 1 => wild_f64()]),
            0..6,
        ),
        bad_bearing in prop::option::of(wild_f64()),
        clamp in wild_f64(),
        probe in wild_size(),
    ) {
        let g = GridGeometry::new(w, h, 0.1, 0.0, 0.0).unwrap();
        let mut beams: Vec<ConeBeam> = beams
            .into_iter()
            .map(|(x, y, b, range)| ConeBeam { pose: Pose { x, y, theta: 0.0 }, bearing: b, range })
            .collect();
        if let (Some(b), Some(first)) = (bad_bearing, beams.first_mut()) {
            first.bearing = b;
        }
        let settings = MapSearchSettings { prior, half_width, sub_rays, model };
        let mut search = match MapSearch::new(g, beams, settings) {
            Ok(s) => s,
            Err(e) => {
                let mut fields = vec!["prior", "half_width", "sub_rays", "beams"];
                fields.extend(MODEL_FIELDS);
                assert_names_one_of(&e, &fields);
                return Ok(());
            }
        };
        search.run(40);
        let history = search.history();
        prop_assert!(history.windows(2).all(|p| p[1] > p[0] + MIN_GAIN * 0.5), "{history:?}");
        let recount = search.evaluate(search.occupied()).unwrap();
        prop_assert!((recount - search.objective()).abs() <= 1e-6 * recount.abs().max(1.0),
            "{recount} vs {}", search.objective());
        prop_assert!(search.evaluate(&[true]).is_err() || g.len() == 1);
        let _ = (search.beams_through(probe), search.beam_cells(probe), search.expected_range(probe));
        match search.to_grid(clamp) {
            Ok(grid) => prop_assert!(grid.log_odds().iter().all(|l| l.is_finite())),
            Err(e) => assert_names(&e, "clamp"),
        }
        let mut px = vec![1u8; 4 * g.len() + 1];
        let reached = vec![true; g.len()];
        let e = occgrid::render::gray::render_binary_rgba(search.geometry(), search.occupied(), &reached, &mut px).unwrap_err();
        assert_names(&e, "pixel buffer");
        prop_assert!(px.iter().all(|&b| b == 1));
    }

    #[test]
    fn learned_model_evidence_is_finite_everywhere_for_moderate_weights(
        frame in valid_frame(),
        weights in prop::array::uniform15(-50.0..50.0f64),
        r in wild_f64(), phi in wild_f64(),
        z in prop_oneof![3 => 0.0..40.0f64, 1 => prop::sample::select(vec![0.0, 5e-324, 1e300, f64::MAX])],
        l0 in prop_oneof![3 => -30.0..30.0f64, 1 => wild_f64()],
    ) {
        let m = LearnedInverse::new(frame, weights).unwrap().with_l0(l0);
        prop_assert!(m.l0().is_finite());
        if r.is_finite() && phi.is_finite() {
            let phi_features = frame.features(r, phi, z);
            prop_assert!(phi_features.iter().all(|f| f.is_finite() && (0.0..=1.0).contains(f)), "{phi_features:?}");
        }
        let e = m.evidence(r, phi, z);
        prop_assert!(e.is_finite(), "evidence({r}, {phi}, {z}) = {e}");
        prop_assert!(m.reach(z) >= 0.0);
    }

    #[test]
    fn feature_frames_and_weights_are_checked_and_named(
        z_max in wild_f64(), half_width in wild_f64(), bad in 0usize..FEATURES, w in wild_f64(),
    ) {
        let mut weights = [0.1; FEATURES];
        weights[bad] = w;
        match LearnedInverse::new(FeatureFrame { z_max, half_width }, weights) {
            Ok(_) => prop_assert!(w.is_finite() && z_max.is_finite() && half_width.is_finite()),
            Err(e) => assert_names_one_of(&e, &["z_max", "half_width", "weights["]),
        }
    }

    #[test]
    fn lattices_are_checked_and_every_evidence_image_has_its_size(
        lat in lattice(), z in wild_f64(), frame in valid_frame(),
    ) {
        let learned = LearnedInverse::new(frame, [0.3; FEATURES]).unwrap();
        let hand = HandCrafted::new(HandCraftedParams {
            alpha: 0.2, beta: 0.1, ..HandCraftedParams::laser(frame.z_max)
        }).unwrap();
        match side_by_side(&hand, &learned, z, &lat) {
            Ok(v) => {
                prop_assert_eq!(v.fields[0].len(), lat.ranges * lat.bearings);
                prop_assert_eq!(v.axes[1].len(), lat.ranges);
                prop_assert!(v.scale.is_finite());
                prop_assert!(v.fields.iter().flatten().all(|e| e.is_finite()));
            }
            Err(e) => assert_names_one_of(
                &e,
                &["z", "min_range", "max_range", "max_bearing", "ranges", "bearings"],
            ),
        }
        let a = evidence_field(&hand, z, &lat).is_ok();
        let b = axis_log_odds(&learned, z, &lat).is_ok();
        prop_assert_eq!(a, b, "both checks agree");
    }

    #[test]
    fn training_configs_are_checked_field_by_field(
        triplets in wild_size(), epochs in wild_size(), learning_rate in wild_f64(),
        sensor in wild_beam_params(), half_width in wild_f64(), sub_rays in wild_size(),
        resolution in wild_f64(), seed in wild_f64(), density in wild_f64(),
    ) {
        let c = TrainingConfig {
            seed: 1, triplets, epochs, learning_rate, sensor, half_width, sub_rays, resolution, density,
        };
        if let Err(e) = c.validate() {
            let mut fields = vec!["triplets", "epochs", "learning_rate", "half_width", "sub_rays", "resolution", "density"];
            fields.extend(MODEL_FIELDS);
            assert_names_one_of(&e, &fields);
        }
        match seed_from_number(seed) {
            Ok(s) => prop_assert_eq!(s as f64, seed),
            Err(e) => assert_names(&e, "seed"),
        }
    }

    #[test]
    fn fusion_takes_the_larger_probability_or_names_the_odd_map_and_leaves_out_untouched(
        shapes in prop::collection::vec((1usize..5, 1usize..5), 0..4),
        evidence in prop::collection::vec(-8.0..8.0f32, 1..6),
        cells in prop::collection::vec(prop_oneof![3 => 0usize..30, 1 => wild_size()], 0..5),
        out_shape in (1usize..5, 1usize..5),
    ) {
        let maps: Vec<LogOddsGrid> = shapes.iter().map(|&(w, h)| grid_with(w, h, &evidence)).collect();
        let refs: Vec<&LogOddsGrid> = maps.iter().collect();
        match max_fused_probabilities(&refs) {
            Ok(p) => {
                prop_assert_eq!(p.len(), maps[0].geometry().len());
                for (i, &pi) in p.iter().enumerate() {
                    let best = maps.iter().map(|m| m.probability_at(i)).fold(0.0, f64::max);
                    prop_assert!((pi - best).abs() < 1e-12);
                }
                match mean_over(&p, &cells) {
                    Ok(mean) => prop_assert!((0.0..=1.0).contains(&mean)),
                    Err(e) => assert_names(&e, "cells"),
                }
            }
            Err(e) => assert_names(&e, "maps"),
        }
        let mut out = grid_with(out_shape.0, out_shape.1, &[1.5]);
        let before = out.clone();
        match max_fuse_into(&mut out, &refs) {
            Ok(()) => prop_assert!(out.log_odds().iter().all(|l| l.is_finite())),
            Err(e) => {
                assert_names_one_of(&e, &["maps", "fused map", "clamp"]);
                prop_assert_eq!(&out, &before);
            }
        }
        match mean_probability(&out, &cells) {
            Ok(mean) => prop_assert!((0.0..=1.0).contains(&mean)),
            Err(e) => assert_names(&e, "cells"),
        }
    }
}

proptest! {
    // Each case sweeps a grid up to twice per scan: fewer cases.
    #![proptest_config(config(64))]

    #[test]
    fn mean_free_evidence_and_prior_drift_name_a_bad_reading(
        z in prop_oneof![3 => 0.0..10.0f64, 1 => wild_f64()],
        margin in prop_oneof![3 => 0.0..1.0f64, 1 => wild_f64()],
        scans in prop_oneof![3 => 1usize..3, 1 => wild_size()],
    ) {
        let frame = FeatureFrame { z_max: 8.0, half_width: 0.04 };
        let learned = LearnedInverse::new(frame, [0.2; FEATURES]).unwrap();
        match mean_free_evidence(&learned, z, margin) {
            Ok(m) => prop_assert!(m.is_finite()),
            Err(e) => assert_names_one_of(&e, &["z", "margin"]),
        }
        match prior_drift(&learned, z, scans) {
            Ok(r) => prop_assert!(r.own_l0.is_finite() && r.zero_l0.is_finite() && r.cells > 0),
            Err(e) => assert_names_one_of(&e, &["z", "scans"]),
        }
    }
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn a_small_training_run_on_any_valid_sensor_gives_a_finite_model(
        seed in any::<u64>(), triplets in 1usize..60, epochs in 1usize..3,
        z_max in 0.5..12.0f64, half_width in 0.005..0.5f64, sub_rays in 1usize..6,
        resolution in 0.05..0.3f64, learning_rate in 0.01..10.0f64,
    ) {
        let c = TrainingConfig {
            seed, triplets, epochs, learning_rate,
            sensor: BeamModelParams { z_max, ..BeamModelParams::CHAPTER },
            half_width, sub_rays, resolution, density: 0.0,
        };
        let Ok(()) = c.validate() else { return Ok(()) };
        let (model, set, _) = training::train(&c).unwrap();
        prop_assert_eq!(set.triplets.len(), triplets);
        prop_assert!(model.weights().iter().all(|w| w.is_finite()));
        // The chapter's summary quotes free space in front of a reading of
        // z_max / 4; a sensor shorter than 1.2 m has none to quote.
        match training::summarize(&model) {
            Ok(summary) => prop_assert!(summary.l0.is_finite() && summary.free_evidence_short.is_finite()),
            Err(e) => {
                assert_names(&e, "z");
                prop_assert!(z_max < 4.0 * training::FREE_MARGIN + 1e-9);
            }
        }
    }
}

/// Finite weights whose sum would overflow, and a map prior past f32's
/// range, are refused or held in range: no cell may receive NaN or an
/// infinity from the learned model.
#[test]
fn learned_model_with_finite_but_huge_weights_is_rejected_or_finite() {
    let frame = FeatureFrame {
        z_max: 8.0,
        half_width: 0.04,
    };
    for big in [1e308, f64::MAX, -f64::MAX, 1e300] {
        match LearnedInverse::new(frame, [big; FEATURES]) {
            Ok(m) => {
                for (r, z) in [(1.0, 2.0), (2.0, 2.0), (7.0, 8.0), (3.0, 2.0)] {
                    let e = m.evidence(r, 0.0, z);
                    assert!(e.is_finite(), "weights {big}: evidence({r}, 0, {z}) = {e}");
                }
                assert!(m.l0().is_finite(), "weights {big}: l0 = {}", m.l0());
            }
            Err(e) => assert_names(&e, "weights"),
        }
    }
    // A map prior past f32's range: `with_l0` keeps it (it is finite as
    // f64), and every evidence of the model becomes infinite as f32.
    let m = LearnedInverse::new(frame, [0.1; FEATURES])
        .unwrap()
        .with_l0(1e39);
    assert!(m.l0().is_finite(), "l0 = {}", m.l0());
    let e = m.evidence(1.0, 0.0, 2.0);
    assert!(e.is_finite(), "evidence = {e}");
}
