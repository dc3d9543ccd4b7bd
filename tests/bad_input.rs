#![cfg(not(target_arch = "wasm32"))]
//! docs/ARCHITECTURE.md, "Bad input" for the foundation: every bad input is an error that names the
//! field and the value, and the map is left exactly as it was.

use occgrid::geometry::GridGeometry;
use occgrid::geometry::Pose;
use occgrid::grid::{FilterSettings, LogOddsGrid};
use occgrid::inverse::HandCrafted;
use occgrid::inverse::HandCraftedParams;
use occgrid::mapping::traversal::RayMapper;
use occgrid::sensors::Scan;

fn says(result: Result<impl std::fmt::Debug, occgrid::OccError>, words: &[&str]) {
    let text = result.expect_err("must be rejected").to_string();
    for w in words {
        assert!(text.contains(w), "{text:?} should mention {w:?}");
    }
}

#[test]
fn grid_sizes_and_resolutions() {
    says(GridGeometry::new(0, 10, 0.1, 0.0, 0.0), &["width", "0"]);
    says(GridGeometry::new(10, 0, 0.1, 0.0, 0.0), &["height", "0"]);
    says(
        GridGeometry::new(100_000, 100_000, 0.1, 0.0, 0.0),
        &["100000 x 100000"],
    );
    says(
        GridGeometry::new(usize::MAX, 2, 0.1, 0.0, 0.0),
        &["width x height"],
    );
    says(
        GridGeometry::new(10, 10, 0.0, 0.0, 0.0),
        &["resolution", "0"],
    );
    says(
        GridGeometry::new(10, 10, -0.1, 0.0, 0.0),
        &["resolution", "-0.1"],
    );
    says(
        GridGeometry::new(10, 10, f64::NAN, 0.0, 0.0),
        &["resolution", "NaN"],
    );
    says(
        GridGeometry::new(10, 10, f64::INFINITY, 0.0, 0.0),
        &["resolution", "inf"],
    );
    says(
        GridGeometry::new(10, 10, 0.1, f64::NAN, 0.0),
        &["origin_x", "NaN"],
    );
    says(
        GridGeometry::new(10, 10, 1e308, 1e308, 0.0),
        &["origin_x + width"],
    );
    says(
        GridGeometry::covering(0.0, 0.0, -1.0, 1.0, 0.1),
        &["max_x", "-1"],
    );
    says(
        GridGeometry::covering(0.0, 0.0, 1e6, 1e6, 0.001),
        &["width x height"],
    );
}

#[test]
fn priors_and_clamps() {
    let g = GridGeometry::new(4, 4, 0.1, 0.0, 0.0).unwrap();
    for p in [0.0, 1.0, -0.5, 1.5, f64::NAN] {
        says(
            LogOddsGrid::new(
                g,
                FilterSettings {
                    prior: p,
                    clamp: 12.0,
                },
            ),
            &["prior"],
        );
    }
    says(
        LogOddsGrid::new(
            g,
            FilterSettings {
                prior: 0.5,
                clamp: 0.0,
            },
        ),
        &["clamp", "0"],
    );
    says(
        LogOddsGrid::new(
            g,
            FilterSettings {
                prior: 0.5,
                clamp: -3.0,
            },
        ),
        &["clamp", "-3"],
    );
    says(
        LogOddsGrid::new(
            g,
            FilterSettings {
                prior: 0.01,
                clamp: 2.0,
            },
        ),
        &["clamp", "l0"],
    );
}

#[test]
fn scans_with_bad_ranges_bearings_or_poses() {
    let p = Pose::default();
    says(
        Scan::new(p, vec![1.0, f64::NAN], vec![0.0, 0.1]),
        &["ranges[1]", "NaN"],
    );
    says(Scan::new(p, vec![-0.5], vec![0.0]), &["ranges[0]", "-0.5"]);
    says(
        Scan::new(p, vec![f64::INFINITY], vec![0.0]),
        &["ranges[0]", "inf"],
    );
    says(
        Scan::new(p, vec![1.0, 2.0], vec![0.0]),
        &["bearings", "1", "2"],
    );
    says(
        Scan::new(p, vec![], vec![]),
        &["ranges", "at least one beam"],
    );
    says(
        Scan::new(p, vec![1.0], vec![f64::NEG_INFINITY]),
        &["bearings[0]"],
    );
    says(
        Scan::uniform(p, vec![1.0], 0.0, f64::NAN),
        &["bearing_step", "NaN"],
    );
    says(Pose::new(0.0, f64::NAN, 0.0), &["pose.y", "NaN"]);
    let bad = Pose {
        x: 0.0,
        y: 0.0,
        theta: f64::INFINITY,
    };
    says(Scan::new(bad, vec![1.0], vec![0.0]), &["pose.theta", "inf"]);
}

#[test]
fn inverse_model_parameters() {
    says(
        HandCraftedParams::from_probabilities(0.0, 0.3, 0.5, 0.1, 0.1, 5.0),
        &["p_occ", "0"],
    );
    says(
        HandCraftedParams::from_probabilities(0.7, 1.0, 0.5, 0.1, 0.1, 5.0),
        &["p_free", "1"],
    );
    says(
        HandCraftedParams::from_probabilities(0.7, 0.3, 0.5, 0.1, -1.0, 5.0),
        &["beta", "-1"],
    );
    says(
        HandCraftedParams::from_probabilities(0.7, 0.3, 0.5, 0.1, 0.1, f64::NAN),
        &["z_max", "NaN"],
    );
    says(
        HandCraftedParams::from_probabilities(0.7, 0.3, 0.5, 0.1, 7.0, 5.0),
        &["beta", "7"],
    );
}

#[test]
fn a_rejected_update_leaves_the_map_exactly_as_it_was() {
    let g = GridGeometry::new(20, 20, 0.1, 0.0, 0.0).unwrap();
    let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
    let model = HandCrafted::new(
        HandCraftedParams::from_probabilities(0.7, 0.4, 0.5, 0.1, 0.02, 5.0).unwrap(),
    )
    .unwrap();
    let scan = Scan::uniform(Pose::new(1.0, 1.0, 0.0).unwrap(), vec![0.5; 36], 0.0, 0.17).unwrap();
    RayMapper::new().integrate(&mut m, &model, &scan);
    let before = m.clone();
    says(m.set_clamp(0.0), &["clamp"]);
    says(m.set_clamp(f64::NAN), &["clamp", "NaN"]);
    says(m.brier_score(&[true; 3], None), &["truth", "3", "400"]);
    says(
        m.brier_score(&[true; 400], Some(&[400])),
        &["region", "400"],
    );
    says(
        occgrid::render::viewport::render_grid_rgba(&m, &mut [0u8; 7]),
        &["pixel buffer"],
    );
    assert_eq!(m, before, "the map is untouched by every rejected call");
}
