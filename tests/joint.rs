#![cfg(not(target_arch = "wasm32"))]
//! The independence trap (docs/ARCHITECTURE.md, "The independence trap"): exact joint posteriors over a few cells
//! in one sonar cone against what a factored map believes.

use occgrid::mapping::joint::{ConeCell, JointPosterior, JointQuery};
use occgrid::sensors::beam_model::BeamModelParams;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

fn cells(spec: &[(f64, f64)]) -> Vec<ConeCell> {
    spec.iter()
        .map(|&(range, bearing_deg)| ConeCell { range, bearing_deg })
        .collect()
}

#[test]
fn chapter_two_cell_joint_table_and_marginals() {
    let post = JointPosterior::compute(&JointQuery::chapter_two_cells()).unwrap();
    // (mA mB) = 00, 10, 01, 11, first cell the lowest bit.
    let chapter = [0.0047, 0.3318, 0.3318, 0.3318];
    for (k, (&p, &want)) in post.joint.iter().zip(&chapter).enumerate() {
        assert!((p - want).abs() < 1e-3, "configuration {k}: {p} vs {want}");
    }
    for &m in &post.marginals {
        assert!((m - 0.6635).abs() < 1e-3, "marginal {m}");
    }
    // The expected ranges behind the table: all free reads to z_max.
    assert_eq!(post.expected_ranges, vec![3.0, 2.0, 2.0, 2.0]);
}

#[test]
fn chapter_both_free_is_0_0047_truly_and_0_1132_factored_a_factor_of_24() {
    let post = JointPosterior::compute(&JointQuery::chapter_two_cells()).unwrap();
    let (truth, factored) = post.all_free();
    assert!((truth - 0.0047).abs() < 1e-3, "{truth}");
    assert!((factored - 0.1132).abs() < 1e-3, "{factored}");
    assert!(
        (factored - (1.0 - post.marginals[0]).powi(2)).abs() < 1e-12,
        "factored is the product of marginals"
    );
    let factor = factored / truth;
    assert_eq!(factor.round(), 24.0, "factor {factor}");
    let answer = post.answer();
    assert_eq!(answer.all_free_true, truth);
    assert_eq!(answer.all_free_factored, factored);
    // The same through the general event query.
    let (t, f) = post.event(&[Some(false), Some(false)]).unwrap();
    assert_eq!((t, f), (truth, factored));
}

/// A query of one to eight cells anywhere in a cone of 1 to 40 degrees, with
/// one to five readings.
fn random_query(rng: &mut StdRng) -> JointQuery {
    let beta_deg = rng.random_range(1.0..40.0);
    let k = rng.random_range(1..9);
    JointQuery {
        prior: rng.random_range(0.01..0.99),
        beta_deg,
        cells: (0..k)
            .map(|_| ConeCell {
                range: rng.random_range(0.0..3.5),
                bearing_deg: rng.random_range(-0.5..0.5) * beta_deg,
            })
            .collect(),
        readings: (0..rng.random_range(1..6))
            .map(|_| rng.random_range(0.0..3.2))
            .collect(),
        model: BeamModelParams::CHAPTER,
    }
}

#[test]
fn joint_tables_sum_to_one_and_marginals_are_their_sums() {
    let mut rng = StdRng::seed_from_u64(11);
    for case in 0..200 {
        let q = random_query(&mut rng);
        let k = q.cells.len();
        let post = JointPosterior::compute(&q).unwrap();
        assert_eq!(post.joint.len(), 1 << k);
        let total: f64 = post.joint.iter().sum();
        assert!((total - 1.0).abs() < 1e-12, "case {case}: sum {total}");
        assert!(post.joint.iter().all(|&p| (0.0..=1.0).contains(&p)));
        for j in 0..k {
            let (truth, factored) = post
                .event(&(0..k).map(|i| (i == j).then_some(true)).collect::<Vec<_>>())
                .unwrap();
            assert!((truth - post.marginals[j]).abs() < 1e-12);
            assert!((factored - post.marginals[j]).abs() < 1e-12);
        }
        let table = post.table();
        let factored_total: f64 = table.iter().map(|r| r.factored).sum();
        assert!(
            (factored_total - 1.0).abs() < 1e-12,
            "the product of marginals is a distribution too"
        );
    }
}

/// Binary entropy in bits, written out here so that the report's figures
/// are checked against an independent sum.
fn h_b(p: f64) -> f64 {
    [p, 1.0 - p]
        .iter()
        .filter(|&&q| q > 0.0)
        .map(|&q| -q * q.log2())
        .sum()
}

/// The chapter's exercise on entropy: a factored map states the sum of its
/// cells' own entropies, which bounds the entropy of the true joint
/// posterior from above; the gap is the information the cells share (with
/// two cells, their mutual information), never negative. The two-cell
/// table shows all three for its presets.
#[test]
fn the_sum_of_marginal_entropies_exceeds_the_joint_entropy_by_the_shared_information() {
    let mut gaps = Vec::new();
    for name in ["side", "collinear", "apart"] {
        let q = occgrid::apps::two_cell_table::preset(name).unwrap();
        let post = JointPosterior::compute(&q).unwrap();
        let r = post.report();
        let joint: f64 = r
            .table
            .iter()
            .filter(|row| row.joint > 0.0)
            .map(|row| -row.joint * row.joint.log2())
            .sum();
        let factored: f64 = post.marginals.iter().map(|&m| h_b(m)).sum();
        assert!((r.joint_entropy_bits - joint).abs() < 1e-12, "{name}");
        assert!(
            (r.marginal_entropy_sum_bits - factored).abs() < 1e-12,
            "{name}"
        );
        assert!(
            (r.shared_information_bits - (factored - joint)).abs() < 1e-9,
            "{name}: gap {} vs {} - {joint}",
            r.shared_information_bits,
            factored
        );
        // With two cells the gap is their mutual information.
        assert!(
            (r.shared_information_bits - r.mutual_information_bits).abs() < 1e-9,
            "{name}"
        );
        gaps.push(r.shared_information_bits);
    }
    // Side by side, either cell alone explains the echo: 0.222 bits shared.
    assert!((gaps[0] - 0.222).abs() < 2e-3, "{gaps:?}");
    // Collinear, the reading all but settles both cells: little is left
    // to share.
    assert!(gaps[1] > 0.0 && gaps[1] < gaps[0] / 5.0, "{gaps:?}");

    // Never negative, for any cells and readings; one cell shares nothing.
    let mut rng = StdRng::seed_from_u64(23);
    for case in 0..200 {
        let q = random_query(&mut rng);
        let k = q.cells.len();
        let r = JointPosterior::compute(&q).unwrap().report();
        assert!(r.shared_information_bits >= 0.0, "case {case}");
        assert!(
            r.marginal_entropy_sum_bits >= r.joint_entropy_bits - 1e-9,
            "case {case}: {} < {}",
            r.marginal_entropy_sum_bits,
            r.joint_entropy_bits
        );
        assert!(
            (r.marginal_entropy_sum_bits - r.joint_entropy_bits - r.shared_information_bits).abs()
                < 1e-9,
            "case {case}"
        );
        if k == 1 {
            assert_eq!(r.shared_information_bits, 0.0, "case {case}");
        }
    }
}

#[test]
fn sixteen_cells_enumerate_65536_configurations() {
    let q = JointQuery {
        cells: (0..16)
            .map(|i| ConeCell {
                range: 1.0 + 0.1 * i as f64,
                bearing_deg: -10.0 + 1.25 * i as f64,
            })
            .collect(),
        ..JointQuery::chapter_two_cells()
    };
    let post = JointPosterior::compute(&q).unwrap();
    assert_eq!(post.joint.len(), 65_536);
    assert!((post.joint.iter().sum::<f64>() - 1.0).abs() < 1e-9);
    // The cell at the reading's range is the likeliest echo.
    let top = (0..16)
        .max_by(|&a, &b| post.marginals[a].total_cmp(&post.marginals[b]))
        .unwrap();
    assert_eq!(top, 10, "{:?}", post.marginals);
    let seventeen = JointQuery {
        cells: cells(&[(1.0, 0.0); 17]),
        ..q
    };
    let e = JointPosterior::compute(&seventeen).unwrap_err().to_string();
    assert!(e.contains("cells") && e.contains("17"), "{e}");
}

#[test]
fn collinear_cell_behind_the_echo_stays_near_its_prior() {
    // B hides behind A on the same bearing: once A explains the echo,
    // nothing the sonar says reaches B.
    let q = JointQuery {
        cells: cells(&[(2.0, 0.0), (2.5, 0.0)]),
        ..JointQuery::chapter_two_cells()
    };
    let post = JointPosterior::compute(&q).unwrap();
    assert!(post.marginals[0] > 0.95, "{:?}", post.marginals);
    assert!(
        (post.marginals[1] - 0.5).abs() < 0.02,
        "{:?}",
        post.marginals
    );
}

#[test]
fn a_cell_in_front_of_the_echo_is_free_and_nearly_independent() {
    let q = JointQuery {
        cells: cells(&[(2.0, -5.0), (1.0, 5.0)]),
        ..JointQuery::chapter_two_cells()
    };
    let post = JointPosterior::compute(&q).unwrap();
    assert!(post.marginals[1] < 0.05, "{:?}", post.marginals);
    // Apart, the two cells share far less information than side by side,
    // where either one alone explains the echo.
    let side_by_side = JointPosterior::compute(&JointQuery::chapter_two_cells()).unwrap();
    let (near, far) = (
        side_by_side.pair_mutual_information_bits(0, 1).unwrap(),
        post.pair_mutual_information_bits(0, 1).unwrap(),
    );
    assert!((near - 0.222).abs() < 2e-3, "side by side: {near} bits");
    assert!(far < near / 3.0, "apart: {far} bits vs {near}");
}

#[test]
fn repeated_readings_sharpen_the_trap() {
    let once = JointPosterior::compute(&JointQuery::chapter_two_cells()).unwrap();
    let thrice = JointPosterior::compute(&JointQuery {
        readings: vec![2.0, 2.02, 1.98],
        ..JointQuery::chapter_two_cells()
    })
    .unwrap();
    assert!(thrice.all_free().0 < once.all_free().0 / 100.0);
    // Three readings agree about "something is there", not about which cell.
    assert!((thrice.marginals[0] - 2.0 / 3.0).abs() < 1e-3);
    // Hundreds of readings neither underflow nor overflow.
    let many = JointPosterior::compute(&JointQuery {
        readings: vec![2.0; 1000],
        ..JointQuery::chapter_two_cells()
    })
    .unwrap();
    assert!(many.joint.iter().all(|p| p.is_finite()));
    assert!((many.joint.iter().sum::<f64>() - 1.0).abs() < 1e-12);
}

#[test]
fn rejects_bad_queries_naming_the_field_and_value() {
    let base = JointQuery::chapter_two_cells();
    let check = |q: JointQuery, field: &str, value: &str| {
        let e = JointPosterior::compute(&q).unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(value), "{e}");
    };
    check(
        JointQuery {
            prior: 1.0,
            ..base.clone()
        },
        "prior",
        "1",
    );
    check(
        JointQuery {
            prior: f64::NAN,
            ..base.clone()
        },
        "prior",
        "NaN",
    );
    check(
        JointQuery {
            beta_deg: -22.0,
            ..base.clone()
        },
        "beta_deg",
        "-22",
    );
    check(
        JointQuery {
            cells: vec![],
            ..base.clone()
        },
        "cells",
        "0",
    );
    check(
        JointQuery {
            cells: cells(&[(2.0, 0.0), (-1.0, 0.0)]),
            ..base.clone()
        },
        "cells[1].range",
        "-1",
    );
    check(
        JointQuery {
            cells: cells(&[(f64::INFINITY, 0.0)]),
            ..base.clone()
        },
        "cells[0].range",
        "inf",
    );
    check(
        JointQuery {
            cells: cells(&[(2.0, 12.0)]),
            ..base.clone()
        },
        "cells[0].bearing_deg",
        "12",
    );
    check(
        JointQuery {
            readings: vec![],
            ..base.clone()
        },
        "readings",
        "0",
    );
    check(
        JointQuery {
            readings: vec![2.0, f64::NAN],
            ..base.clone()
        },
        "readings[1]",
        "NaN",
    );
    check(
        JointQuery {
            model: BeamModelParams {
                z_rand: 0.5,
                ..BeamModelParams::CHAPTER
            },
            ..base.clone()
        },
        "z_hit + z_short + z_maxw + z_rand",
        "1.45",
    );
    // A model that calls every configuration impossible has nothing to
    // normalise.
    let hit_only = BeamModelParams {
        z_hit: 1.0,
        z_short: 0.0,
        z_maxw: 0.0,
        z_rand: 0.0,
        sigma_hit: 0.01,
        ..BeamModelParams::CHAPTER
    };
    check(
        JointQuery {
            model: hit_only,
            readings: vec![0.2],
            ..base
        },
        "readings",
        "0.2",
    );
}
