#![cfg(not(target_arch = "wasm32"))]
//! docs/ARCHITECTURE.md, "Bad input" as properties over the map's foundation: the grid and its
//! geometry, poses and scans, the supercover raster, both Table 9.1 mappers,
//! the single-cell filter, the Table 9.2 model and the view that draws and
//! scores a map.
//!
//! For every public function that takes input, arbitrary values (NaN,
//! infinities, subnormals, values past `f32`'s range, sizes 0, 1 and
//! `usize::MAX`) must give either a result that keeps the function's
//! promises or an error that names the offending field, and a rejected
//! update must leave the map exactly as it was. No property catches a
//! panic: the functions must simply return.

mod properties_support;

use occgrid::geometry::raster::supercover;
use occgrid::geometry::{wrap_angle, Pose};
use occgrid::geometry::{GridGeometry, MAX_CELLS};
use occgrid::grid::{binary_entropy_bits, logit, probability, FilterSettings, LogOddsGrid};
use occgrid::inverse::{HandCrafted, HandCraftedParams, InverseModel};
use occgrid::mapping::cell_filter::{self, CellFilterParams};
use occgrid::mapping::sweep::sweep_scan;
use occgrid::mapping::traversal::RayMapper;
use occgrid::render::gray::gray_level;
use occgrid::render::map_view::{cell_look, MapView};
use occgrid::sensors::Scan;
use properties_support::*;
use proptest::prelude::*;

/// The field `GridGeometry::new` must blame, in the order it checks them,
/// or `None` when the input is valid.
fn geometry_fault(w: usize, h: usize, res: f64, ox: f64, oy: f64) -> Option<&'static str> {
    if w == 0 {
        return Some("width");
    }
    if h == 0 {
        return Some("height");
    }
    if w.checked_mul(h).is_none_or(|n| n > MAX_CELLS) {
        return Some("width x height");
    }
    if !(res.is_finite() && res > 0.0) {
        return Some("resolution");
    }
    if !ox.is_finite() {
        return Some("origin_x");
    }
    if !oy.is_finite() {
        return Some("origin_y");
    }
    if !(ox + w as f64 * res).is_finite() {
        return Some("origin_x + width * resolution");
    }
    if !(oy + h as f64 * res).is_finite() {
        return Some("origin_y + height * resolution");
    }
    None
}

/// A small valid geometry with an arbitrary (finite) placement.
fn small_geometry() -> impl Strategy<Value = GridGeometry> {
    (
        1usize..30,
        1usize..30,
        0.02..1.0f64,
        -50.0..50.0f64,
        -50.0..50.0f64,
    )
        .prop_map(|(w, h, r, x, y)| GridGeometry::new(w, h, r, x, y).unwrap())
}

/// Valid filter settings: any open prior whose log odds fit a clamp of up
/// to 30.
fn settings() -> impl Strategy<Value = FilterSettings> {
    (0.001..0.999f64, 0.0..30.0f64).prop_map(|(prior, extra)| FilterSettings {
        prior,
        clamp: logit(prior).abs() + extra + 1e-3,
    })
}

/// Hand-crafted parameters as an attribute might spell them: every field
/// anything from ordinary to absurd.
fn wild_hand_crafted() -> impl Strategy<Value = HandCraftedParams> {
    (
        wild_positive(),
        wild_positive(),
        wild_positive(),
        wild_f64(),
        wild_f64(),
        prop_oneof![3 => Just(0.0), 1 => wild_f64()],
    )
        .prop_map(
            |(alpha, beta, z_max, l_occ, l_free, l0)| HandCraftedParams {
                alpha,
                beta,
                z_max,
                l_occ,
                l_free,
                l0,
            },
        )
}

/// The field `HandCraftedParams::validate` must blame, or `None`.
fn hand_crafted_fault(p: &HandCraftedParams) -> Option<&'static str> {
    let pos = |v: f64| v.is_finite() && v > 0.0;
    if !pos(p.alpha) {
        return Some("alpha");
    }
    if !pos(p.beta) || p.beta > std::f64::consts::TAU {
        return Some("beta");
    }
    if !pos(p.z_max) {
        return Some("z_max");
    }
    for (f, v) in [("l_occ", p.l_occ), ("l_free", p.l_free), ("l0", p.l0)] {
        if !v.is_finite() {
            return Some(f);
        }
    }
    None
}

/// A scan a mapper may legally receive: finite pose (possibly far away),
/// finite non-negative ranges from zero through subnormal to huge, finite
/// bearings of any size.
fn valid_scan() -> impl Strategy<Value = Scan> {
    let coordinate = prop_oneof![4 => -60.0..60.0f64, 1 => prop::sample::select(vec![1e300, -1e300, 1e-300, 0.0])];
    let range = prop_oneof![
        6 => 0.0..12.0f64,
        1 => prop::sample::select(vec![0.0, 5e-324, 1e-300, 1e300, f64::MAX, 1e39]),
    ];
    let bearing =
        prop_oneof![4 => -7.0..7.0f64, 1 => prop::sample::select(vec![1e300, -1e18, 0.0])];
    (
        coordinate.clone(),
        coordinate,
        -10.0..10.0f64,
        prop::collection::vec((range, bearing), 1..24),
    )
        .prop_map(|(x, y, theta, beams)| {
            let (r, b) = beams.into_iter().unzip();
            Scan::new(Pose::new(x, y, theta).unwrap(), r, b).unwrap()
        })
}

/// Every cell finite and inside the clamp: what a map must stay whatever
/// it was fed.
#[track_caller]
fn assert_sane(grid: &LogOddsGrid) {
    let c = grid.clamp();
    for (i, &l) in grid.log_odds().iter().enumerate() {
        assert!(
            l.is_finite() && l.abs() <= c,
            "cell {i} holds {l} (clamp {c})"
        );
    }
}

proptest! {
    #![proptest_config(config(1024))]

    #[test]
    fn geometry_new_accepts_exactly_the_valid_limits_and_names_what_it_rejects(
        w in wild_size(), h in wild_size(),
        res in wild_f64(), ox in wild_f64(), oy in wild_f64(),
    ) {
        match (GridGeometry::new(w, h, res, ox, oy), geometry_fault(w, h, res, ox, oy)) {
            (Ok(g), None) => {
                prop_assert_eq!((g.width(), g.height()), (w, h));
                prop_assert!(g.len() <= MAX_CELLS);
            }
            (Err(e), Some(field)) => assert_names(&e, field),
            (got, want) => prop_assert!(false, "{got:?}, but the fault is {want:?}"),
        }
    }

    #[test]
    fn covering_gives_a_map_holding_the_box_or_names_the_bad_bound(
        min_x in wild_f64(), min_y in wild_f64(),
        dx in wild_f64(), dy in wild_f64(), res in wild_f64(),
    ) {
        let (max_x, max_y) = (min_x + dx, min_y + dy);
        match GridGeometry::covering(min_x, min_y, max_x, max_y, res) {
            Ok(g) => {
                let [ox, oy] = g.origin();
                prop_assert_eq!((ox, oy), (min_x, min_y));
                prop_assert!(ox + g.width() as f64 * g.resolution() >= max_x);
                prop_assert!(oy + g.height() as f64 * g.resolution() >= max_y);
                prop_assert!(g.len() <= MAX_CELLS);
            }
            Err(e) => assert_names_one_of(
                &e,
                &["resolution", "min_x", "min_y", "max_x", "max_y", "width x height", "width", "height", "origin"],
            ),
        }
    }

    #[test]
    fn world_to_cell_answers_a_cell_inside_the_map_or_none(
        g in small_geometry(), x in wild_f64(), y in wild_f64(),
    ) {
        if let Some((ix, iy)) = g.world_to_cell(x, y) {
            prop_assert!(ix < g.width() && iy < g.height());
            prop_assert!(x.is_finite() && y.is_finite());
        }
        // A cell's centre is in that cell.
        let (ix, iy) = (g.width() / 2, g.height() / 2);
        let (cx, cy) = g.cell_center(ix, iy);
        prop_assert_eq!(g.world_to_cell(cx, cy), Some((ix, iy)));
        prop_assert_eq!(g.cell_of_index(g.index(ix, iy)), (ix, iy));
    }

    #[test]
    fn log_odds_grid_new_accepts_exactly_open_priors_within_a_finite_clamp(
        prior in wild_probability(), clamp in wild_f64(),
    ) {
        let g = GridGeometry::new(3, 2, 0.1, 0.0, 0.0).unwrap();
        match LogOddsGrid::new(g, FilterSettings { prior, clamp }) {
            Ok(m) => {
                prop_assert!(prior > 0.0 && prior < 1.0);
                prop_assert!(m.clamp().is_finite() && m.clamp() > 0.0);
                prop_assert!(m.l0().abs() <= m.clamp());
                prop_assert!((0..6).all(|i| m.is_unknown(i)));
                assert_sane(&m);
            }
            Err(e) => {
                if !(prior > 0.0 && prior < 1.0) {
                    assert_names(&e, "prior");
                    let names_value = names_number(&e.to_string(), prior);
                    prop_assert!(names_value);
                } else {
                    assert_names(&e, "clamp");
                    let names_value = names_number(&e.to_string(), clamp);
                    prop_assert!(names_value);
                }
            }
        }
    }

    #[test]
    fn set_clamp_pulls_every_cell_in_or_leaves_the_map_exactly_as_it_was(
        g in small_geometry(), s in settings(), scan in valid_scan(), clamp in wild_f64(),
    ) {
        let mut m = LogOddsGrid::new(g, s).unwrap();
        let model = HandCrafted::new(HandCraftedParams {
            alpha: 0.2, beta: 0.05, z_max: 8.0, l_occ: 2.0, l_free: -1.5, l0: 0.0,
        }).unwrap();
        for _ in 0..4 {
            RayMapper::new().integrate(&mut m, &model, &scan);
        }
        let before = m.clone();
        match m.set_clamp(clamp) {
            Ok(()) => {
                prop_assert_eq!(m.clamp(), clamp as f32);
                assert_sane(&m);
            }
            Err(e) => {
                assert_names(&e, "clamp");
                prop_assert_eq!(&m, &before);
            }
        }
    }

    #[test]
    fn brier_score_is_a_mean_square_in_0_1_or_names_truth_or_region(
        g in small_geometry(),
        truth_len_delta in prop_oneof![3 => Just(0isize), 1 => -3isize..3],
        region in prop::option::of(prop::collection::vec(wild_size(), 0..6)),
    ) {
        let m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        let n = (g.len() as isize + truth_len_delta).max(0) as usize;
        let truth: Vec<bool> = (0..n).map(|i| i % 3 == 0).collect();
        match m.brier_score(&truth, region.as_deref()) {
            Ok(b) => prop_assert!((0.0..=1.0).contains(&b), "{b}"),
            Err(e) => assert_names_one_of(&e, &["truth", "region"]),
        }
    }

    #[test]
    fn render_rgba_fills_a_buffer_of_the_right_size_or_touches_nothing(
        g in small_geometry(), delta in prop_oneof![2 => Just(0isize), 1 => -5isize..5],
    ) {
        let m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        let n = (g.len() as isize * 4 + delta).max(0) as usize;
        let mut px = vec![7u8; n];
        match occgrid::render::viewport::render_grid_rgba(&m, &mut px) {
            Ok(()) => prop_assert!(px.chunks_exact(4).all(|p| p == [128, 128, 128, 255])),
            Err(e) => {
                assert_names(&e, "pixel buffer");
                prop_assert!(px.iter().all(|&b| b == 7));
            }
        }
    }

    #[test]
    fn logit_probability_and_entropy_stay_in_their_ranges(l in wild_f64(), p in wild_probability()) {
        let q = probability(l);
        if !l.is_nan() {
            prop_assert!((0.0..=1.0).contains(&q), "probability({l}) = {q}");
        }
        if (0.0..=1.0).contains(&p) {
            let h = binary_entropy_bits(p);
            prop_assert!((0.0..=1.0 + 1e-12).contains(&h), "H({p}) = {h}");
            if p > 1e-12 && p < 1.0 - 1e-12 {
                prop_assert!((probability(logit(p)) - p).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn pose_new_names_the_first_coordinate_that_is_not_finite(
        x in wild_f64(), y in wild_f64(), t in wild_f64(),
    ) {
        match Pose::new(x, y, t) {
            Ok(p) => prop_assert!(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite()),
            Err(e) => {
                let field = if !x.is_finite() { "pose.x" } else if !y.is_finite() { "pose.y" } else { "pose.theta" };
                assert_names(&e, field);
            }
        }
    }

    #[test]
    fn scan_new_accepts_exactly_finite_non_negative_beams_and_names_the_bad_one(
        x in wild_f64(), y in wild_f64(), t in wild_f64(),
        ranges in prop::collection::vec(wild_f64(), 0..8),
        extra_bearings in prop_oneof![4 => Just(0isize), 1 => -2isize..3],
        bearing_seed in prop::collection::vec(wild_f64(), 10),
    ) {
        let n = (ranges.len() as isize + extra_bearings).max(0) as usize;
        let bearings: Vec<f64> = bearing_seed.iter().cycle().take(n).copied().collect();
        let pose = Pose { x, y, theta: t };
        match Scan::new(pose, ranges.clone(), bearings.clone()) {
            Ok(s) => {
                prop_assert!(s.ranges().iter().all(|r| r.is_finite() && *r >= 0.0));
                prop_assert!(s.bearings().iter().all(|b| b.is_finite()));
                prop_assert_eq!(s.len(), s.bearings().len());
                prop_assert!(!s.is_empty());
            }
            Err(e) => {
                let field = if Pose::new(x, y, t).is_err() {
                    "pose."
                } else if ranges.is_empty() {
                    "ranges"
                } else if bearings.len() != ranges.len() {
                    "bearings"
                } else if let Some(i) = ranges.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
                    return { assert_names(&e, &format!("ranges[{i}]")); Ok(()) };
                } else {
                    let i = bearings.iter().position(|b| !b.is_finite()).unwrap();
                    return { assert_names(&e, &format!("bearings[{i}]")); Ok(()) };
                };
                assert_names(&e, field);
            }
        }
    }

    #[test]
    fn scan_uniform_and_with_pose_validate_like_scan_new(
        ranges in prop::collection::vec(prop_oneof![3 => 0.0..10.0f64, 1 => wild_f64()], 0..6),
        first in wild_f64(), step in wild_f64(), x in wild_f64(),
    ) {
        match Scan::uniform(Pose::default(), ranges.clone(), first, step) {
            Ok(s) => {
                prop_assert!(s.bearings().iter().all(|b| b.is_finite()));
                match s.with_pose(Pose { x, y: 0.0, theta: 0.0 }) {
                    Ok(moved) => prop_assert_eq!(moved.ranges(), s.ranges()),
                    Err(e) => assert_names(&e, "pose.x"),
                }
            }
            Err(e) => assert_names_one_of(&e, &["first_bearing", "bearing_step", "ranges", "bearings["]),
        }
    }

    #[test]
    fn wrap_angle_lands_in_the_half_open_interval_for_every_finite_angle(a in wild_f64()) {
        let w = wrap_angle(a);
        if a.is_finite() {
            prop_assert!(w > -std::f64::consts::PI && w <= std::f64::consts::PI, "{a} -> {w}");
        }
    }

    #[test]
    fn supercover_visits_only_cells_of_the_grid_and_says_how_many(
        w in 1usize..40, h in 1usize..40,
        ax in wild_f64(), ay in wild_f64(), bx in wild_f64(), by in wild_f64(),
    ) {
        let mut visited = 0usize;
        let n = supercover(w, h, (ax, ay), (bx, by), |ix, iy| {
            assert!(ix < w && iy < h, "visited ({ix}, {iy}) of a {w} x {h} grid");
            visited += 1;
        });
        prop_assert_eq!(n, visited);
    }

    #[test]
    fn hand_crafted_accepts_exactly_valid_parameters_and_names_the_bad_one(p in wild_hand_crafted()) {
        match (HandCrafted::new(p), hand_crafted_fault(&p)) {
            (Ok(m), None) => {
                // Evidence crosses into f32: it must still be a number.
                for (r, z) in [(0.0, 1.0), (1.0, 1.0), (0.5 * p.z_max, p.z_max)] {
                    prop_assert!(m.evidence(r, 0.0, z).is_finite());
                }
            }
            (Err(e), Some(field)) => assert_names(&e, field),
            (Err(e), None) => {
                // Valid as f64, but its evidence overflows f32: named too.
                assert_names_one_of(&e, &["l_occ", "l_free", "l0"]);
            }
            (Ok(_), Some(field)) => prop_assert!(false, "accepted a bad {field}"),
        }
    }

    #[test]
    fn from_probabilities_and_with_strength_name_what_they_reject(
        p_occ in wild_probability(), p_free in wild_probability(), prior in wild_probability(),
        alpha in wild_positive(), beta in wild_positive(), z_max in wild_positive(),
        strength in prop_oneof![3 => 0.0..10.0f64, 1 => wild_f64()],
    ) {
        match HandCraftedParams::from_probabilities(p_occ, p_free, prior, alpha, beta, z_max) {
            Ok(p) => match HandCrafted::with_strength(p, strength) {
                Ok(m) => {
                    prop_assert!(m.evidence(0.0, 0.0, 1.0).is_finite());
                    prop_assert!(m.evidence(1.0, 0.0, 1.0).is_finite());
                }
                Err(e) => assert_names_one_of(&e, &["strength", "l_occ", "l_free"]),
            },
            Err(e) => assert_names_one_of(&e, &["p_occ", "p_free", "prior", "alpha", "beta", "z_max"]),
        }
    }

    #[test]
    fn table_9_2_axis_profile_equals_the_model_at_every_range(
        alpha in prop_oneof![3 => 0.01..1.0f64, 1 => wild_positive()],
        z_max in prop_oneof![3 => 1.0..30.0f64, 1 => wild_positive()],
        z in prop_oneof![3 => 0.0..30.0f64, 1 => prop::sample::select(vec![0.0, 5e-324, 1e300, f64::MAX])],
        offsets in prop::collection::vec(-3i64..3, 8),
    ) {
        let params = HandCraftedParams { alpha, beta: 0.1, ..HandCraftedParams::laser(z_max) };
        let Ok(m) = HandCrafted::new(params) else { return Ok(()) };
        let Some(profile) = m.axis_profile(z) else { return Ok(()) };
        // Probe the band's edges to the ulp, where the two could disagree.
        let edges = [z - 0.5 * alpha, z + 0.5 * alpha, z, m.reach(z), 0.0, 0.5 * z];
        for (k, &edge) in edges.iter().enumerate() {
            let mut r = edge;
            let steps = offsets[k % offsets.len()];
            for _ in 0..steps.abs() {
                r = if steps > 0 { r.next_up() } else { r.next_down() };
            }
            if r.is_finite() && r >= 0.0 {
                prop_assert_eq!(profile.at(r), m.evidence(r, 0.0, z), "r = {}", r);
            }
        }
    }

    #[test]
    fn both_mappers_keep_every_cell_finite_and_inside_the_clamp(
        g in small_geometry(), p in wild_hand_crafted(),
        clamp in prop_oneof![3 => 0.5..30.0f64, 1 => prop::sample::select(vec![1e39, 1e300, f64::MAX, 3.4e38])],
        scans in prop::collection::vec(valid_scan(), 1..4),
    ) {
        let Ok(model) = HandCrafted::new(p) else { return Ok(()) };
        let settings = FilterSettings { prior: 0.5, clamp };
        let Ok(mut traversed) = LogOddsGrid::new(g, settings) else { return Ok(()) };
        let mut swept = traversed.clone();
        let mut mapper = RayMapper::new();
        for scan in &scans {
            let t = mapper.integrate(&mut traversed, &model, scan);
            let s = sweep_scan(&mut swept, &model, scan);
            prop_assert!(t.cells_updated <= g.len());
            prop_assert_eq!(s.cells_visited, g.len());
            // Twice: the second pass meets cells already at the clamp.
            mapper.integrate(&mut traversed, &model, scan);
            sweep_scan(&mut swept, &model, scan);
        }
        assert_sane(&traversed);
        assert_sane(&swept);
        let most = 2 * scans.len() as u32;
        prop_assert!(traversed.update_counts().iter().all(|&c| c <= most));
        prop_assert!(swept.update_counts().iter().all(|&c| c <= most));
    }

    #[test]
    fn cell_filter_runs_only_on_valid_parameters_and_stays_finite(
        p_occ in wild_probability(), p_free in wild_probability(), prior in wild_probability(),
        clamp in wild_f64(),
        readings in prop::collection::vec(any::<bool>(), 0..40),
        subtract in any::<bool>(),
    ) {
        let params = CellFilterParams { p_occ, p_free, prior, clamp };
        match cell_filter::run(&params, &readings, subtract) {
            Ok(steps) => {
                prop_assert_eq!(steps.len(), readings.len());
                for s in &steps {
                    prop_assert!(s.l.is_finite() && s.l.abs() <= clamp);
                    prop_assert!((0.0..=1.0).contains(&s.p));
                }
            }
            Err(e) => {
                let open = |v: f64| v > 0.0 && v < 1.0;
                let field = if !open(p_occ) { "p_occ" } else if !open(p_free) { "p_free" } else if !open(prior) { "prior" } else { "clamp" };
                assert_names(&e, field);
            }
        }
    }

    #[test]
    fn the_view_draws_exactly_the_grid_renderers_gray_and_scores_in_range(l in wild_f64()) {
        let l = l as f32;
        let gray = gray_level(l);
        let (look, p, h) = cell_look(l);
        if l.is_finite() {
            let exact = (255.0 * (1.0 - probability(l as f64)) + 0.5) as u8;
            prop_assert_eq!(gray, exact, "l = {}", l);
            prop_assert_eq!(look, exact, "l = {}", l);
            prop_assert!((0.0..=1.0).contains(&p) && (0.0..=1.0 + 1e-6).contains(&h), "{} {}", p, h);
        }
    }

    #[test]
    fn map_view_new_names_a_bad_truth_or_region_and_sync_survives_any_grid(
        g in small_geometry(), other in small_geometry(),
        truth_delta in prop_oneof![3 => Just(0isize), 1 => -2isize..2],
        region in prop::collection::vec(prop_oneof![3 => 0usize..50, 1 => wild_size()], 0..5),
    ) {
        let n = (g.len() as isize + truth_delta).max(0) as usize;
        let truth: Vec<bool> = (0..n).map(|i| i % 2 == 0).collect();
        match MapView::new(&g, &truth, &region) {
            Ok(mut view) => {
                let grid = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
                view.sync(&grid);
                prop_assert_eq!(view.rgba().len(), 4 * g.len());
                prop_assert!((view.entropy_bits() - g.len() as f64).abs() < 1e-3);
                // A grid of other limits is a caller's mistake, not a crash.
                let stranger = LogOddsGrid::new(other, FilterSettings::default()).unwrap();
                view.sync(&stranger);
            }
            Err(e) => assert_names_one_of(&e, &["truth", "region"]),
        }
    }
}

/// A grid without cells has nothing to visit. `supercover` is public and
/// takes raw sizes; today a segment touching the line `x = 0` of a
/// `0 x h` grid reports cell (0, 0), which a caller indexing its own cells
/// would read out of bounds.
#[test]
fn supercover_on_a_grid_without_cells_visits_nothing() {
    for (w, h) in [(0, 25), (25, 0), (0, 0), (0, 1)] {
        for (a, b) in [
            ((0.0, 0.0), (0.0, 5.0)),
            ((-1.0, 0.5), (3.0, 0.5)),
            ((0.0, 0.0), (0.0, 0.0)),
        ] {
            let n = supercover(w, h, a, b, |ix, iy| {
                panic!("visited ({ix}, {iy}) of a {w} x {h} grid");
            });
            assert_eq!(n, 0, "{w} x {h}, {a:?} -> {b:?}");
        }
    }
}

/// A message names a number either as Rust prints it or in the core's short
/// form for extreme magnitudes (`error::show`).
fn names_number(message: &str, x: f64) -> bool {
    message.contains(&shown(x)) || message.contains(&occgrid::error::show(x))
}
