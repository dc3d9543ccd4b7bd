#![cfg(not(target_arch = "wasm32"))]
//! The forward beam model of Table 6.1 (Table 6.1): the chapter's numbers, the
//! density's normalisation, the generative mode against the density, and
//! the expected range `z*` in a ground-truth world.

use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::sensors::beam_model::{expected_range, BeamModel, BeamModelParams, BeamShape};
use occgrid::world::{Rect, World};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// Midpoint rule over `[a, b)` with `n` panels.
fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    (0..n).map(|i| f(a + (i as f64 + 0.5) * h)).sum::<f64>() * h
}

#[test]
fn chapter_reference_values_to_a_thousandth() {
    let m = BeamModel::chapter();
    let at_2 = m.density(2.0, 2.0);
    let at_3 = m.density(2.0, 3.0);
    println!("p(z=2 | z*=2) = {at_2:.4}, p(z=2 | z*=3) = {at_3:.4}");
    assert!((at_2 - 2.160).abs() < 1e-3, "{at_2}");
    assert!((at_3 - 0.0309).abs() < 1e-3, "{at_3}");
}

#[test]
fn density_integrates_to_one_with_the_point_mass() {
    let m = BeamModel::chapter();
    let p = *m.params();
    for z_star in [0.3, 1.0, 2.0, 2.9, 3.0] {
        // The continuous part lives on [0, z_max); the point mass z_maxw
        // sits at z_max. 300,000 panels of 10 micrometres resolve the hit
        // Gaussian (sigma 0.15 m) and the short component's step at z*.
        let continuous = integrate(|z| m.density(z, z_star), 0.0, p.z_max, 300_000);
        let total = continuous + p.z_maxw;
        assert!(
            (total - 1.0).abs() < 1e-3,
            "z* = {z_star}: integral {continuous} + point mass {} = {total}",
            p.z_maxw
        );
    }
    // Another setting: heavy short and random parts, a long range.
    let m = BeamModel::new(BeamModelParams {
        z_hit: 0.5,
        sigma_hit: 0.4,
        z_short: 0.3,
        lambda_short: 0.5,
        z_maxw: 0.1,
        z_rand: 0.1,
        z_max: 8.0,
    })
    .unwrap();
    for z_star in [0.5, 4.0, 8.0] {
        let total = integrate(|z| m.density(z, z_star), 0.0, 8.0, 400_000) + 0.1;
        assert!((total - 1.0).abs() < 1e-3, "z* = {z_star}: {total}");
    }
}

/// Probability mass of the density on `[a, b)` below `z_max`.
fn bin_mass(m: &BeamModel, z_star: f64, a: f64, b: f64) -> f64 {
    integrate(|z| m.density(z, z_star), a, b, 2_000)
}

#[test]
fn samples_follow_the_density_bin_by_bin() {
    let m = BeamModel::chapter();
    let z_max = m.params().z_max;
    let n = 200_000;
    let bins = 30; // 0.1 m wide
    for (seed, z_star) in [(7u64, 2.0), (8, 0.6), (9, 3.0)] {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut counts = vec![0usize; bins + 1]; // the last bin is z >= z_max
        for _ in 0..n {
            let z = m.sample(z_star, &mut rng);
            assert!((0.0..=z_max).contains(&z), "{z}");
            let k = if z >= z_max {
                bins
            } else {
                ((z / z_max * bins as f64) as usize).min(bins - 1)
            };
            counts[k] += 1;
        }
        let mut worst: f64 = 0.0;
        for (k, &c) in counts.iter().enumerate() {
            let expected = if k == bins {
                m.params().z_maxw
            } else {
                let w = z_max / bins as f64;
                bin_mass(&m, z_star, k as f64 * w, (k + 1) as f64 * w)
            };
            let observed = c as f64 / n as f64;
            // Five binomial standard deviations, plus the quadrature's error.
            let sd = (expected * (1.0 - expected) / n as f64).sqrt();
            let z_score = (observed - expected).abs() / (sd + 1e-9);
            worst = worst.max(z_score);
            assert!(
                (observed - expected).abs() <= 5.0 * sd + 2e-4,
                "z* = {z_star}, bin {k}: observed {observed:.5}, density says {expected:.5}"
            );
        }
        println!("z* = {z_star}: worst bin off by {worst:.2} standard deviations");
    }
}

#[test]
fn sampling_is_deterministic_for_a_seed() {
    let m = BeamModel::chapter();
    let draw = |seed| {
        let mut rng = StdRng::seed_from_u64(seed);
        (0..1000)
            .map(|i| m.sample(0.5 + (i % 5) as f64 * 0.6, &mut rng).to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(draw(42), draw(42));
    assert_ne!(draw(42), draw(43));
}

#[test]
fn a_very_wide_hit_gaussian_still_samples_its_truncated_shape() {
    // sigma_hit far above z_max: the sampler switches to uniform proposals.
    let m = BeamModel::new(BeamModelParams {
        z_hit: 1.0,
        sigma_hit: 10.0,
        z_short: 0.0,
        lambda_short: 1.0,
        z_maxw: 0.0,
        z_rand: 0.0,
        z_max: 3.0,
    })
    .unwrap();
    let mut rng = StdRng::seed_from_u64(1);
    let n = 100_000;
    let below_1 = (0..n).filter(|_| m.sample(0.0, &mut rng) < 1.0).count() as f64 / n as f64;
    let expected = bin_mass(&m, 0.0, 0.0, 1.0);
    assert!((below_1 - expected).abs() < 0.01, "{below_1} vs {expected}");
}

fn room() -> World {
    let g = GridGeometry::new(60, 40, 0.1, 0.0, 0.0).unwrap();
    World::from_boxes(
        g,
        &[
            Rect::new(0.0, 0.0, 6.0, 0.1),
            Rect::new(0.0, 3.9, 6.0, 4.0),
            Rect::new(0.0, 0.0, 0.1, 4.0),
            Rect::new(5.9, 0.0, 6.0, 4.0),
            Rect::new(2.0, 1.5, 2.6, 2.2),
            Rect::new(4.1, 2.8, 4.3, 3.0),
        ],
    )
}

#[test]
fn thin_expected_range_agrees_with_the_world_caster() {
    let w = room();
    let mut rng = StdRng::seed_from_u64(3);
    for _ in 0..2000 {
        let (x, y) = (rng.random_range(0.1..5.9), rng.random_range(0.1..3.9));
        let theta = rng.random_range(-3.2..3.2);
        let z_max = rng.random_range(0.5..8.0);
        let pose = Pose::new(x, y, theta).unwrap();
        let ours = expected_range(&w, &pose, 0.0, BeamShape::THIN, z_max).unwrap();
        let world = w.cast(x, y, theta, z_max);
        assert!(
            (ours - world).abs() < 1e-9,
            "from ({x}, {y}) at {theta}: {ours} vs {world}"
        );
    }
    // From outside the map the ray is clipped by the world caster.
    let pose = Pose::new(-1.0, 1.05, 0.0).unwrap();
    let z = expected_range(&w, &pose, 0.0, BeamShape::THIN, 8.0).unwrap();
    assert!((z - 1.0).abs() < 1e-9, "{z}");
}

#[test]
fn cone_expected_range_is_the_nearest_of_its_sub_rays() {
    let w = room();
    let mut rng = StdRng::seed_from_u64(4);
    for _ in 0..500 {
        let (x, y) = (rng.random_range(0.1..5.9), rng.random_range(0.1..3.9));
        let theta = rng.random_range(-3.2..3.2);
        let half = rng.random_range(0.0..0.4);
        let rays = rng.random_range(1..9);
        let pose = Pose::new(x, y, theta).unwrap();
        let shape = BeamShape::cone(half, rays).unwrap();
        let ours = expected_range(&w, &pose, 0.0, shape, 8.0).unwrap();
        let world = w.cast_cone(x, y, theta, half, rays, 8.0).unwrap();
        // Sub-ray directions are built by rotation, not by angle: they
        // agree with the world's to rounding.
        assert!((ours - world).abs() < 1e-6, "{ours} vs {world}");
    }
    // The post at (4.1..4.3, 2.8..3.0) is off the axis of a beam from
    // (1, 2.9) heading east-north-east, but inside a 0.2 rad cone.
    let pose = Pose::new(1.0, 2.5, 0.0).unwrap();
    let axis = expected_range(&w, &pose, 0.0, BeamShape::THIN, 8.0).unwrap();
    let cone = expected_range(&w, &pose, 0.0, BeamShape::cone(0.2, 9).unwrap(), 8.0).unwrap();
    assert!(cone < axis, "{cone} vs {axis}");
}

#[test]
fn generated_scans_cluster_around_the_expected_ranges() {
    let w = room();
    let m = BeamModel::new(BeamModelParams {
        z_max: 8.0,
        ..BeamModelParams::CHAPTER
    })
    .unwrap();
    let pose = Pose::new(1.0, 1.0, 0.3).unwrap();
    let bearings: Vec<f64> = (0..360).map(|i| (i as f64).to_radians()).collect();
    let mut rng = StdRng::seed_from_u64(5);
    let scan = m
        .sample_scan(&w, &pose, &bearings, BeamShape::THIN, &mut rng)
        .unwrap();
    let near = scan
        .ranges()
        .iter()
        .zip(&bearings)
        .filter(|(&z, &b)| {
            let z_star = expected_range(&w, &pose, b, BeamShape::THIN, 8.0).unwrap();
            (z - z_star).abs() < 3.0 * 0.15
        })
        .count();
    // z_hit = 0.8 of the readings come from the hit Gaussian, 99.7% of which
    // fall within three sigma; a few short or random ones land there too.
    assert!((270..=330).contains(&near), "{near} of 360");
}

#[test]
fn bad_beams_are_errors_that_name_the_field() {
    let w = room();
    let bad = Pose {
        x: f64::NAN,
        y: 1.0,
        theta: 0.0,
    };
    let e = expected_range(&w, &bad, 0.0, BeamShape::THIN, 8.0).unwrap_err();
    assert!(e.to_string().contains("pose.x"), "{e}");
    let p = Pose::new(1.0, 1.0, 0.0).unwrap();
    let e = expected_range(&w, &p, f64::INFINITY, BeamShape::THIN, 8.0).unwrap_err();
    assert!(e.to_string().contains("bearing"), "{e}");
    let e = expected_range(&w, &p, 0.0, BeamShape::THIN, 0.0).unwrap_err();
    assert!(e.to_string().contains("z_max"), "{e}");
    assert!(BeamShape::cone(-0.1, 3)
        .unwrap_err()
        .to_string()
        .contains("half_width"));
    assert!(BeamShape::cone(0.1, 0)
        .unwrap_err()
        .to_string()
        .contains("sub_rays"));
    assert!(BeamShape::cone(2.0, 3).is_err());
    let m = BeamModel::chapter();
    assert!(m
        .likelihood(&w, &p, 0.0, BeamShape::THIN, -1.0)
        .unwrap_err()
        .to_string()
        .contains("-1"));
    let e = m
        .sample_scan(
            &w,
            &p,
            &[0.0, f64::NAN],
            BeamShape::THIN,
            &mut StdRng::seed_from_u64(0),
        )
        .unwrap_err();
    assert!(e.to_string().contains("bearings[1]"), "{e}");
}
