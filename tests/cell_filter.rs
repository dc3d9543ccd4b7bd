#![cfg(not(target_arch = "wasm32"))]
//! The chapter's single-cell numbers and the bookkeeping of the prior.

use approx::assert_abs_diff_eq;
use occgrid::geometry::GridGeometry;
use occgrid::grid::{binary_entropy_bits, logit, FilterSettings, LogOddsGrid};
use occgrid::mapping::cell_filter::{self, CellFilterParams};

#[test]
fn worked_example_matches_the_chapter_to_four_decimals() {
    let lo = cell_filter::log_odds_of(&CellFilterParams::WORKED_EXAMPLE).unwrap();
    assert_abs_diff_eq!(lo.l_occ, 0.8473, epsilon = 1e-4);
    assert_abs_diff_eq!(lo.l_free, -0.8473, epsilon = 1e-4);
    let steps = cell_filter::run(
        &CellFilterParams::WORKED_EXAMPLE,
        &[true, true, false],
        true,
    )
    .unwrap();
    let expected = [(0.8473, 0.7000), (1.6946, 0.8448), (0.8473, 0.7000)];
    for (s, (l, p)) in steps.iter().zip(expected) {
        assert_abs_diff_eq!(s.l, l, epsilon = 1e-4);
        assert_abs_diff_eq!(s.p, p, epsilon = 1e-4);
    }
}

#[test]
fn any_order_of_the_same_readings_ends_at_the_same_log_odds() {
    let orders = [
        [true, true, false],
        [true, false, true],
        [false, true, true],
    ];
    let params = CellFilterParams {
        prior: 0.3,
        ..CellFilterParams::WORKED_EXAMPLE
    };
    let ends: Vec<f64> = orders
        .iter()
        .map(|o| {
            cell_filter::run(&params, o, true)
                .unwrap()
                .last()
                .unwrap()
                .l
        })
        .collect();
    for e in &ends {
        assert_abs_diff_eq!(*e, ends[0], epsilon = 1e-12);
    }
    // The same holds for a grid cell updated through `apply`.
    let g = GridGeometry::new(1, 1, 0.1, 0.0, 0.0).unwrap();
    let mut a = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let mut b = a.clone();
    for e in [0.85f32, -0.4, 0.85, 0.85, -0.4] {
        a.apply(0, e);
    }
    for e in [-0.4f32, -0.4, 0.85, 0.85, 0.85] {
        b.apply(0, e);
    }
    assert_abs_diff_eq!(a.log_odds()[0], b.log_odds()[0], epsilon = 1e-6);
}

#[test]
fn forgetting_to_subtract_l0_with_prior_0_2_drifts_by_l0_per_reading() {
    let params = CellFilterParams {
        p_occ: 0.37,
        p_free: 0.1,
        prior: 0.2,
        clamp: 100.0,
    };
    let readings: Vec<bool> = (0..10).map(|i| i % 2 == 0).collect();
    let kept = cell_filter::run(&params, &readings, true).unwrap();
    let forgot = cell_filter::run(&params, &readings, false).unwrap();
    let l0 = logit(0.2);
    for (i, (k, f)) in kept.iter().zip(&forgot).enumerate() {
        // Each reading counts the prior once more: after n readings the gap is n * l0.
        assert_abs_diff_eq!(f.l - k.l, (i + 1) as f64 * l0, epsilon = 1e-9);
    }
    // With the subtraction, readings symmetric around the prior stay near it;
    // without it the cell ends far on the free side.
    assert!((kept.last().unwrap().l - l0).abs() < 0.3);
    assert!(forgot.last().unwrap().p < 1e-5);
}

#[test]
fn clamp_saturates_and_keeps_the_cell_revisable() {
    let params = CellFilterParams {
        clamp: 3.5,
        ..CellFilterParams::WORKED_EXAMPLE
    };
    let mut readings = vec![true; 40];
    let steps = cell_filter::run(&params, &readings, true).unwrap();
    assert_eq!(steps.last().unwrap().l, 3.5, "saturates at the clamp");
    // From the clamp, ceil(3.5 / 0.8473) = 5 free readings bring it below 0.5.
    readings.extend([false; 5]);
    let steps = cell_filter::run(&params, &readings, true).unwrap();
    assert!(steps.last().unwrap().p < 0.5);
    assert!(steps[steps.len() - 2].p > 0.5);
    // Without a clamp (a huge one), the same 5 free readings barely dent it.
    let unclamped = CellFilterParams {
        clamp: 1e6,
        ..params
    };
    let steps = cell_filter::run(&unclamped, &readings, true).unwrap();
    assert!(steps.last().unwrap().p > 0.99);
}

/// The chapter's first exercise: a prior of 0.2 (l0 = -1.3863) and ten
/// readings whose inverse model answers exactly the prior. With the
/// correction the cell stays at l0; without it each reading adds l0 once
/// more, to l_10 = 11 l0 = -15.25, p = 2.4e-7. The widget's clamp of 12
/// would stop the drift at reading 8, so the exercise runs without one.
#[test]
fn exercise_1_ten_readings_of_the_prior_drift_to_eleven_l0_without_a_clamp() {
    let params = CellFilterParams {
        p_occ: 0.2,
        p_free: 0.2,
        prior: 0.2,
        clamp: f64::INFINITY,
    };
    let l0 = logit(0.2);
    assert_abs_diff_eq!(l0, -1.3863, epsilon = 1e-4);
    let readings = [true; 10];
    let kept = cell_filter::run(&params, &readings, true).unwrap();
    assert!(kept.iter().all(|s| (s.l - l0).abs() < 1e-12), "{kept:?}");
    let forgot = cell_filter::run(&params, &readings, false).unwrap();
    let last = forgot.last().unwrap();
    assert_abs_diff_eq!(last.l, 11.0 * l0, epsilon = 1e-9);
    assert_abs_diff_eq!(last.l, -15.25, epsilon = 0.01);
    assert!((last.p - 2.4e-7).abs() < 0.05e-7, "p = {}", last.p);
    // The drift is l0 per reading, every reading.
    for pair in forgot.windows(2) {
        assert_abs_diff_eq!(pair[1].l - pair[0].l, l0, epsilon = 1e-9);
    }

    // At the widget's default clamp of 12 the same run stops at reading 8.
    let clamped = CellFilterParams {
        clamp: CellFilterParams::CLAMP,
        ..params
    };
    let stopped = cell_filter::run(&clamped, &readings, false).unwrap();
    let first = stopped.iter().position(|s| s.l == -12.0).unwrap();
    assert_eq!(first + 1, 8);
    assert_eq!(stopped.last().unwrap().l, -12.0);
}

#[test]
fn the_clamp_is_positive_or_none_and_a_bad_one_is_refused_by_name() {
    for bad in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
        let params = CellFilterParams {
            clamp: bad,
            ..CellFilterParams::WORKED_EXAMPLE
        };
        let e = cell_filter::run(&params, &[true], true)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("clamp") && e.contains(&occgrid::error::show(bad)) && e.contains("infinity"),
            "{e}"
        );
    }
    let none = CellFilterParams {
        clamp: f64::INFINITY,
        ..CellFilterParams::WORKED_EXAMPLE
    };
    let steps = cell_filter::run(&none, &[true; 20], true).unwrap();
    assert_abs_diff_eq!(steps.last().unwrap().l, 20.0 * 0.8473, epsilon = 1e-2);
}

#[test]
fn a_fresh_map_holds_exactly_one_bit_per_cell() {
    let g = GridGeometry::new(120, 90, 0.1, 0.0, 0.0).unwrap();
    let m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    assert_eq!(m.entropy_bits(), 10_800.0);
    let biased = LogOddsGrid::new(
        g,
        FilterSettings {
            prior: 0.2,
            clamp: 12.0,
        },
    )
    .unwrap();
    // l0 is stored as f32, so the prior comes back to about 1e-8.
    assert_abs_diff_eq!(
        biased.entropy_bits(),
        10_800.0 * binary_entropy_bits(0.2),
        epsilon = 1e-3
    );
}

#[test]
fn brier_score_of_a_certain_map_is_zero_and_of_a_fresh_one_a_quarter() {
    let g = GridGeometry::new(4, 1, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(
        g,
        FilterSettings {
            prior: 0.5,
            clamp: 40.0,
        },
    )
    .unwrap();
    let truth = [true, false, true, false];
    assert_abs_diff_eq!(m.brier_score(&truth, None).unwrap(), 0.25, epsilon = 1e-12);
    for (i, &t) in truth.iter().enumerate() {
        m.apply(i, if t { 40.0 } else { -40.0 });
    }
    assert!(m.brier_score(&truth, None).unwrap() < 1e-12);
    assert!(m.brier_score(&truth, Some(&[0, 1])).unwrap() < 1e-12);
}
