//! Shared pieces of the property tests (`tests/properties_*.rs`): input
//! strategies that reach the corners a page, an attribute or a file can
//! send (NaN, infinities, signed zeros, subnormals, values past `f32`'s
//! range, sizes of 0, 1 and `usize::MAX`), the runner configuration, and the
//! check that an error names its field.
//!
//! Every property runs from a fixed seed, so a failure reproduces; set
//! `OCCGRID_PROPTEST_SEED` to explore other inputs and `PROPTEST_CASES` to
//! multiply the case counts for a longer hunt.

#![allow(dead_code)]

use occgrid::OccError;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// The runner configuration for a property with `cases` cases: a fixed
/// seed, no regression files written into the source tree.
pub fn config(cases: u32) -> Config {
    let seed = std::env::var("OCCGRID_PROPTEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x0CC_6A1D);
    let scale = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
        .map_or(1, |n| n.max(1));
    Config {
        cases: cases.saturating_mul(scale),
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(seed),
        max_shrink_iters: 2_000,
        ..Config::default()
    }
}

/// Floats a caller could send, weighted towards the ones that break code:
/// special values, any bit pattern, and ordinary magnitudes.
pub fn wild_f64() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![
        3 => prop::sample::select(SPECIAL.to_vec()),
        2 => proptest::num::f64::ANY,
        3 => -50.0..50.0f64,
    ]
}

/// Values that each break some naive check.
pub const SPECIAL: [f64; 22] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    5e-324,
    -5e-324,
    f64::MIN_POSITIVE,
    f64::MIN_POSITIVE / 2.0,
    f64::MAX,
    f64::MIN,
    1e300,
    -1e300,
    1e-300,
    1e39, // finite in f64, infinite as f32
    -1e39,
    1.0,
    -1.0,
    0.5,
    1.0 - f64::EPSILON / 2.0,
    1e9,
    -1e9,
];

/// A probability-like value: mostly inside `[0, 1]`, often exactly at its
/// ends, sometimes anything at all.
pub fn wild_probability() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![
        3 => 0.0..=1.0f64,
        2 => prop::sample::select(vec![0.0, 1.0, 0.5, 1e-300, 1.0 - 1e-16, -0.0, 5e-324]),
        1 => wild_f64(),
    ]
}

/// A plausible positive quantity (a length, a rate): mostly ordinary, some
/// extreme.
pub fn wild_positive() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![
        4 => 0.01..20.0f64,
        1 => wild_f64(),
    ]
}

/// Sizes and counts: 0, 1, the small numbers code is written for, the
/// limits the core declares, and the ones no allocation survives.
pub fn wild_size() -> impl Strategy<Value = usize> + Clone {
    prop_oneof![
        3 => 0usize..40,
        1 => prop::sample::select(vec![
            0,
            1,
            2,
            4095,
            4096,
            4097,
            1 << 20,
            1 << 24,
            (1 << 24) + 1,
            u32::MAX as usize,
            usize::MAX / 2,
            usize::MAX,
        ]),
    ]
}

/// Asserts that `e` names `field` (and so tells the reader what to fix).
#[track_caller]
pub fn assert_names(e: &OccError, field: &str) {
    let text = e.to_string();
    assert!(
        text.contains(field),
        "the error {text:?} should name the field {field:?}"
    );
}

/// Asserts that `e` names one of `fields`.
#[track_caller]
pub fn assert_names_one_of(e: &OccError, fields: &[&str]) {
    let text = e.to_string();
    assert!(
        fields.iter().any(|f| text.contains(f)),
        "the error {text:?} should name one of {fields:?}"
    );
}

/// The text the core prints for a value in an error (`Display` of `f64`).
pub fn shown(v: f64) -> String {
    format!("{v}")
}
