#![cfg(target_arch = "wasm32")]
//! Garbage through the JavaScript surface (`wasm-pack test --node`): the
//! garbage a page, an instructor's attributes or a dropped file can send —
//! NaN, infinities, negative and absurd numbers, settings objects of the
//! wrong type or with wrong-typed fields, empty arrays, huge counts, broken
//! logs — must reach JavaScript as an `Error` whose message names the field,
//! and every widget object must stay usable afterwards, unchanged by the
//! call it refused.

use js_sys::{Array, Object};
use occgrid::bindings::doorway_trap::DoorwayTrap;
use occgrid::bindings::inverse_workbench::{forward_density, InverseWorkbench};
use occgrid::bindings::map_files::zip_map_pair;
use occgrid::bindings::map_weaver::MapWeaver;
use occgrid::bindings::sensor_fusion::SensorFusion;
use occgrid::bindings::two_cell_table::{chapter_two_cell_query, joint_posterior};
use wasm_bindgen::{JsError, JsValue};
use wasm_bindgen_test::*;

mod wasm_support;
use wasm_support::*;

/// The Intel log as shipped (read at build time from the shared datasets,
/// not copied into the repository).
const INTEL_GZ: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/datasets/intel-corrected.log.gz"
));

const BAD_NUMBERS: [f64; 6] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 0.0, 1e39];

#[wasm_bindgen_test]
fn the_cell_filter_refuses_every_bad_number_by_name() {
    for v in BAD_NUMBERS {
        refused(cell_filter(v, 0.3, 0.5, 12.0, &[1], true), &["p_occ"]);
        refused(cell_filter(0.7, v, 0.5, 12.0, &[1], true), &["p_free"]);
        refused(cell_filter(0.7, 0.3, v, 12.0, &[1], true), &["prior"]);
        // Infinity is the cell filter's "no clamp".
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN is refused too
        if !(v > 0.0) {
            refused(cell_filter(0.7, 0.3, 0.5, v, &[1], true), &["clamp"]);
        }
    }
    let unclamped = cell_filter(0.7, 0.3, 0.5, f64::INFINITY, &[1; 20], true).unwrap();
    assert!(
        get(&unclamped, "firstAtClamp").is_null(),
        "never at a clamp"
    );
    refused(
        cell_filter(0.7, 0.3, 1.0, 12.0, &[1], true),
        &["prior", "1"],
    );
    refused(
        cell_filter(0.7, 0.3, 0.5, 12.0, &[0, 1, 2], false),
        &["readings[2]", "2"],
    );
    // An empty run is a table with no rows, not an error.
    let t = cell_filter(0.7, 0.3, 0.5, 12.0, &[], true).unwrap();
    assert_eq!(Array::from(&get(&t, "steps")).length(), 0);
    let long = vec![1u8; occgrid::mapping::cell_filter::MAX_FILTER_READINGS];
    let t = cell_filter(0.7, 0.3, 0.5, 12.0, &long, true).unwrap();
    let steps = Array::from(&get(&t, "steps"));
    let last = steps.get(steps.length() - 1);
    assert_eq!(
        get(&last, "l").as_f64(),
        Some(12.0),
        "saturates at the clamp"
    );
}

#[wasm_bindgen_test]
fn the_forward_density_refuses_bad_readings_and_bad_models_by_name() {
    refused(
        forward_density(num(f64::NAN), num(2.0), JsValue::UNDEFINED),
        &["z", "NaN"],
    );
    refused(
        forward_density(num(-1.0), num(2.0), JsValue::UNDEFINED),
        &["z", "-1"],
    );
    refused(
        forward_density(num(1.0), num(f64::INFINITY), JsValue::UNDEFINED),
        &["z_star", "inf"],
    );
    refused(
        forward_density(num(1.0), num(2.0), JsValue::from_str("wide")),
        &["params"],
    );
    refused(
        forward_density(num(1.0), num(2.0), json(r#"{"sigma_hit": -1}"#)),
        &["sigma_hit", "-1"],
    );
    refused(
        forward_density(num(1.0), num(2.0), json(r#"{"z_rand": 0.5}"#)),
        &["add up to 1"],
    );
    let nan_rate = with(&json("{}"), "lambda_short", JsValue::from_f64(f64::NAN));
    refused(
        forward_density(num(1.0), num(2.0), nan_rate),
        &["lambda_short", "NaN"],
    );
    refused(
        forward_density(num(1.0), num(2.0), json(r#"{"z_max": "far"}"#)),
        &["params"],
    );
    // Degenerate but valid models still give a number.
    let flat = json(r#"{"sigma_hit": 1e300, "lambda_short": 1e-300}"#);
    let d = forward_density(num(1.0), num(2.0), flat).unwrap();
    assert!(d.is_finite() && d >= 0.0, "{d}");
}

#[wasm_bindgen_test]
fn joint_queries_with_garbage_are_refused_by_field() {
    let q = || chapter_two_cell_query().unwrap();
    refused(joint_posterior(JsValue::from_str("nope")), &["joint query"]);
    refused(joint_posterior(JsValue::NULL), &["joint query"]);
    refused(
        joint_posterior(with(&q(), "prior", JsValue::from_f64(1.0))),
        &["prior"],
    );
    refused(
        joint_posterior(with(&q(), "prior", JsValue::from_f64(f64::NAN))),
        &["prior", "NaN"],
    );
    refused(
        joint_posterior(with(&q(), "beta_deg", JsValue::from_f64(f64::INFINITY))),
        &["beta_deg", "inf"],
    );
    refused(
        joint_posterior(with(&q(), "cells", Array::new().into())),
        &["cells"],
    );
    refused(
        joint_posterior(with(&q(), "readings", Array::new().into())),
        &["readings"],
    );
    refused(
        joint_posterior(with(&q(), "readings", json("[2.0, -3]"))),
        &["readings[1]", "-3"],
    );
    let many: Array = (0..5000).map(|_| JsValue::from_f64(2.0)).collect();
    refused(
        joint_posterior(with(&q(), "readings", many.into())),
        &["readings", "5000"],
    );
    let cells: Array = (0..17)
        .map(|_| json(r#"{"range": 2, "bearing_deg": 0}"#))
        .collect();
    refused(
        joint_posterior(with(&q(), "cells", cells.into())),
        &["cells", "17"],
    );
    refused(
        joint_posterior(with(&q(), "model.sigma_hit", JsValue::from_f64(0.0))),
        &["sigma_hit"],
    );
    refused(
        joint_posterior(with(&q(), "cells", JsValue::from_f64(3.0))),
        &["joint query"],
    );
    // The query still works after all that.
    let a = joint_posterior(q()).unwrap();
    assert!((get(&a, "allFreeRatio").as_f64().unwrap() - 24.0).abs() < 1.0);
}

#[wasm_bindgen_test]
fn the_doorway_trap_refuses_bad_scenes_by_field_and_stays_usable() {
    let scene = |text: &str| json(text);
    refused(DoorwayTrap::new(JsValue::from_str("door")), &["scene"]);
    refused(
        DoorwayTrap::new(with(&json("{}"), "prior", JsValue::from_f64(f64::NAN))),
        &["prior", "NaN"],
    );
    refused(DoorwayTrap::new(scene(r#"{"prior": 1e-9}"#)), &["prior"]);
    refused(
        DoorwayTrap::new(scene(r#"{"resolution": 0}"#)),
        &["resolution", "0"],
    );
    refused(
        DoorwayTrap::new(scene(r#"{"resolution": 1e-4}"#)),
        &["width x height"],
    );
    refused(DoorwayTrap::new(scene(r#"{"max_x": -1}"#)), &["max_x"]);
    refused(DoorwayTrap::new(scene(r#"{"poses": []}"#)), &["poses"]);
    refused(
        DoorwayTrap::new(scene(r#"{"bearings_deg": []}"#)),
        &["bearings_deg"],
    );
    refused(
        DoorwayTrap::new(scene(r#"{"sonar": {"sub_rays": 0}}"#)),
        &["sonar.sub_rays"],
    );
    refused(
        DoorwayTrap::new(scene(r#"{"sonar": {"beta_deg": 200}}"#)),
        &["sonar.beta_deg"],
    );
    refused(
        DoorwayTrap::new(scene(r#"{"sonar": {"z_max": 1e300}}"#)),
        &["z_max"],
    );
    // The old spelling `noise_sigma` still reads; the error names the one
    // field both spellings set.
    refused(
        DoorwayTrap::new(with(
            &json("{}"),
            "sonar.noise_sigma",
            JsValue::from_f64(f64::NEG_INFINITY),
        )),
        &["sonar.sigma"],
    );
    let bearings: Array = [0.0, f64::NAN]
        .iter()
        .map(|&b| JsValue::from_f64(b))
        .collect();
    refused(
        DoorwayTrap::new(with(&json("{}"), "bearings_deg", bearings.into())),
        &["bearings_deg[1]"],
    );
    refused(DoorwayTrap::new(scene(r#"{"seed": "seven"}"#)), &["scene"]);

    let mut t = DoorwayTrap::new(scene(r#"{"seed": 3}"#)).unwrap();
    let state = stringify(&t.map_state().unwrap());
    refused(t.cell_info(num(-1.0), num(0.0)), &["cell", "-1"]);
    refused(t.cell_info(num(0.0), num(t.height() as f64)), &["cell"]);
    refused(t.cell_info(num(0.5), num(0.0)), &["cell", "0.5"]);
    refused(t.cell_info(num(f64::NAN), num(0.0)), &["cell", "NaN"]);
    refused(t.cell_info(num(4_294_967_296.0), num(0.0)), &["cell"]);
    refused(t.export_map("both".into()), &["map", "both"]);
    for bad in [
        JsValue::from_f64(0.0),
        JsValue::UNDEFINED,
        Object::new().into(),
    ] {
        refused(t.export_map(bad), &["map", "expected \"sweep\" or \"map\""]);
    }
    for bad in [f64::NAN, -1.0, 2.5, f64::NEG_INFINITY] {
        refused(t.map_run(num(bad)), &["maxFlips"]);
    }
    assert_eq!(
        stringify(&t.map_state().unwrap()),
        state,
        "refusals changed nothing"
    );
    assert!(!t.sweep_step().unwrap().is_null());
    assert!(t.map_run(num(f64::INFINITY)).unwrap() > 0);
    assert!(t.map_step().unwrap().is_null(), "converged");
    assert!(t.map_render().unwrap() != 0 && t.sweep_render() != 0);
    let report = t.report().unwrap();
    assert!(get(&report, "doorCells").as_f64().unwrap() > 0.0);
    t.export_map("map".into()).unwrap();
    assert!(t.cell_info(num(0.0), num(0.0)).is_ok());
}

#[wasm_bindgen_test]
fn sensor_fusion_refuses_bad_scenes_models_and_beam_counts_without_a_trace() {
    refused(
        SensorFusion::new(JsValue::from_f64(3.0), JsValue::UNDEFINED),
        &["scene"],
    );
    refused(
        SensorFusion::new(json(r#"{"resolution": "fine"}"#), JsValue::UNDEFINED),
        &["scene"],
    );
    refused(
        SensorFusion::new(json(r#"{"resolution": 0.2}"#), JsValue::UNDEFINED),
        &["resolution"],
    );
    refused(
        SensorFusion::new(json(r#"{"lidar": {"beams": 0}}"#), JsValue::UNDEFINED),
        &["lidar.beams"],
    );
    refused(
        SensorFusion::new(
            json(r#"{"sonar": {"sub_rays": 100000}}"#),
            JsValue::UNDEFINED,
        ),
        &["sonar.sub_rays"],
    );
    refused(
        SensorFusion::new(json(r#"{"path": []}"#), JsValue::UNDEFINED),
        &["path"],
    );
    refused(
        SensorFusion::new(json(r#"{"step": 1e-12}"#), JsValue::UNDEFINED),
        &["step"],
    );
    refused(
        SensorFusion::new(
            with(&json("{}"), "room", json("[1e999, 5]")),
            JsValue::UNDEFINED,
        ),
        &["room[0]"],
    );
    refused(
        SensorFusion::new(JsValue::UNDEFINED, json(r#"{"clamp": 0}"#)),
        &["clamp"],
    );
    refused(
        SensorFusion::new(JsValue::UNDEFINED, json(r#"{"prior": 1}"#)),
        &["prior"],
    );
    refused(
        SensorFusion::new(JsValue::UNDEFINED, json(r#"{"sonar_p_occ": -0.5}"#)),
        &["sonar_p_occ"],
    );
    refused(
        SensorFusion::new(JsValue::UNDEFINED, JsValue::from_str("strong")),
        &["models"],
    );

    let mut f = SensorFusion::new(JsValue::UNDEFINED, JsValue::UNDEFINED).unwrap();
    assert!(f.step());
    let before = stringify(&f.readout().unwrap());
    for beams in [f64::NAN, f64::INFINITY, -1.0, 1.5, 0.0, 4096.0, 1e300] {
        refused(f.set_lidar_beams(num(beams)), &["lidar.beams"]);
        assert_eq!(
            stringify(&f.readout().unwrap()),
            before,
            "refusing {beams} changed the run"
        );
    }
    refused(f.render("sonar ".into()), &["map"]);
    refused(f.export_map("".into()), &["map"]);
    for bad in [JsValue::from_f64(2.0), JsValue::NULL, Array::new().into()] {
        refused(f.render(bad.clone()), &["map", "\"sonar\""]);
        refused(f.export_map(bad), &["map", "\"sonar\""]);
    }
    assert!(f.step(), "still steps");
    f.set_lidar_beams(num(90.0)).unwrap();
    assert!(f.render("max".into()).unwrap() != 0);
    assert!(f.export_map("sum".into()).is_ok());
}

/// A short Map Weaver run: one lap, a quickly trained learned model.
fn weaver_settings() -> JsValue {
    json(r#"{"laps": 1, "training": {"triplets": 400, "epochs": 1}}"#)
}

/// Builds a Map Weaver and drops it at once, in a frame of its own: a
/// session is tens of kilobytes (the learned model's tables are inline),
/// and a test that kept every attempt's result in one frame would overrun
/// the wasm stack of a debug build.
#[inline(never)]
fn weaver_from(settings: JsValue) -> Result<(), JsError> {
    MapWeaver::new(settings).map(drop)
}

#[wasm_bindgen_test]
fn map_weaver_refuses_bad_settings_by_field() {
    let s = weaver_settings;
    refused(weaver_from(JsValue::from_str("weave")), &["settings"]);
    refused(
        weaver_from(with(&s(), "laps", JsValue::from_f64(0.0))),
        &["laps"],
    );
    refused(
        weaver_from(with(&s(), "laps", JsValue::from_f64(-1.0))),
        &["settings"],
    );
    refused(
        weaver_from(with(&s(), "seed", JsValue::from_str("x"))),
        &["settings"],
    );
    refused(
        weaver_from(with(&s(), "panes", json(r#"[{"clamp": 0}, {}]"#))),
        &["panes[0].clamp"],
    );
    let nan_pane = with(&json("{}"), "strength", JsValue::from_f64(f64::NAN));
    let panes: Array = [JsValue::from(Object::new()), nan_pane]
        .into_iter()
        .collect();
    refused(
        weaver_from(with(&s(), "panes", panes.into())),
        &["panes[1].strength", "NaN"],
    );
    refused(
        weaver_from(with(&s(), "panes", json(r#"[{"model": "oracle"}, {}]"#))),
        &["settings", "oracle"],
    );
    refused(
        weaver_from(with(&s(), "training.triplets", JsValue::from_f64(0.0))),
        &["triplets"],
    );
    refused(
        weaver_from(with(&s(), "scene.width", JsValue::from_f64(100_000.0))),
        &["width"],
    );
    refused(
        weaver_from(with(&s(), "scene.resolution", JsValue::from_f64(-0.1))),
        &["resolution"],
    );
    refused(
        weaver_from(with(
            &s(),
            "scene.scan_rate",
            JsValue::from_f64(f64::INFINITY),
        )),
        &["scan_rate"],
    );
    refused(
        weaver_from(with(
            &s(),
            "scene.lidar",
            json(r#"{"beams": 0, "z_max": 8, "sigma": 0, "first_bearing": 0}"#),
        )),
        &["lidar.beams"],
    );
    refused(
        weaver_from(with(
            &s(),
            "handCrafted",
            json(
                r#"{"alpha": 0.1, "beta": 0.02, "z_max": 8, "l_occ": 1e39, "l_free": -0.4, "l0": 0}"#,
            ),
        )),
        &["l_occ"],
    );
    refused(
        weaver_from(with(&s(), "handCrafted", json(r#"{"alpha": 0.1}"#))),
        &["settings", "beta"],
    );
    refused(
        weaver_from(with(&s(), "person", JsValue::from_str("yes"))),
        &["settings"],
    );
}

#[wasm_bindgen_test]
fn map_weaver_refuses_bad_knobs_and_keeps_mapping() {
    let mut w = MapWeaver::new(weaver_settings()).unwrap();
    assert_eq!(w.advance(num(5.0)).unwrap(), 5);
    let before = stringify(&w.readout().unwrap());
    // stagePane is the one way to turn a knob: a patch of the pane's settings.
    let patch = |field: &str, v: JsValue| with(&Object::new().into(), field, v);
    for clamp in BAD_NUMBERS {
        refused(
            w.stage_pane(num(0.0), patch("clamp", num(clamp))),
            &["panes[0].clamp"],
        );
    }
    refused(
        w.stage_pane(num(7.0), patch("clamp", num(3.0))),
        &["pane", "7"],
    );
    for s in [f64::NAN, -1.0, 11.0, f64::INFINITY] {
        refused(
            w.stage_pane(num(1.0), patch("strength", num(s))),
            &["panes[1].strength"],
        );
    }
    refused(
        w.stage_pane(num(1e300), patch("strength", num(1.0))),
        &["pane", "1e300"],
    );
    refused(
        w.stage_pane(num(0.0), patch("model", "magic".into())),
        &["panes[0].model", "magic"],
    );
    refused(
        w.stage_pane(num(2.0), patch("model", "learned".into())),
        &["pane"],
    );
    refused(
        w.stage_pane(num(1.0), patch("pose", "gps".into())),
        &["panes[1].pose", "gps"],
    );
    // A pane index that the glue would once have wrapped or truncated to a
    // valid pane (2^32 to 0, 1.5 to 1, -0.5 to 0) is refused by name.
    for pane in [4_294_967_296.0, 1.5, -0.5, -1.0, f64::NAN, f64::INFINITY] {
        refused(w.pixels(num(pane)), &["pane"]);
        refused(w.stage_pane(num(pane), patch("clamp", num(3.0))), &["pane"]);
        refused(w.overlay(num(pane)), &["pane"]);
    }
    refused(w.pixels(num(2.0)), &["pane"]);
    refused(w.entropy_curve(num(9.0)), &["pane"]);
    refused(w.brier_curve(num(9.0)), &["pane"]);
    refused(w.tracked_history(num(9.0)), &["pane"]);
    refused(w.cell_info(num(5.0), num(0.0), num(0.0)), &["pane"]);
    refused(w.cell_info(num(0.0), num(0.5), num(0.0)), &["col", "0.5"]);
    refused(
        w.cell_info(num(0.0), num(0.0), num(f64::NAN)),
        &["row", "NaN"],
    );
    refused(w.overlay(num(3.0)), &["pane"]);
    refused(w.export_map(num(4.0)), &["pane"]);
    // Names where names belong, and nothing else.
    for bad in [
        JsValue::from_f64(42.0),
        JsValue::NULL,
        json(r#"["learned"]"#),
        JsValue::TRUE,
    ] {
        refused(
            w.stage_pane(num(0.0), patch("model", bad.clone())),
            &["panes[0].model", "\"learned\""],
        );
        refused(
            w.stage_pane(num(1.0), patch("pose", bad)),
            &["panes[1].pose", "\"oracle\""],
        );
    }
    // And a patch is an object of named settings.
    for bad in [JsValue::UNDEFINED, JsValue::NULL, num(3.0), json("[]")] {
        refused(
            w.stage_pane(num(0.0), bad),
            &["panes[0]", "expected an object of named settings"],
        );
    }
    for bad in [f64::NAN, -1.0, 0.5, f64::NEG_INFINITY] {
        refused(w.advance(num(bad)), &["scans"]);
    }
    // A frame time that is no duration is refused by name.
    for (bad, shown) in [(f64::NAN, "NaN"), (-5.0, "-5"), (f64::INFINITY, "inf")] {
        refused(w.record_frame_ms(num(bad)), &["invalid ms", shown]);
    }
    assert_eq!(
        stringify(&w.readout().unwrap()),
        before,
        "refusals changed nothing"
    );
    assert!(w
        .cell_info(num(0.0), num(1e12), num(0.0))
        .unwrap()
        .is_null());
    assert!(w
        .cell_info(num(1.0), num(0.0), num(-1.0))
        .unwrap()
        .is_null());
    assert!(w
        .cell_info(num(1.0), num(0.0), num(4_294_967_296.0))
        .unwrap()
        .is_null());

    // Still maps, and a huge request stops at the end of the run.
    assert_eq!(w.advance(num(3.0)).unwrap(), 3);
    w.stage_pane(num(1.0), patch("pose", "dead-reckoning".into()))
        .unwrap();
    w.stage_pane(num(0.0), patch("model", "learned".into()))
        .unwrap();
    let taken = w.advance(num(f64::INFINITY)).unwrap();
    let r = w.readout().unwrap();
    assert_eq!(get(&r, "done").as_bool(), Some(true));
    assert_eq!(get(&r, "scans").as_f64().unwrap() as usize, 8 + taken);
    assert_eq!(w.advance(num(1e300)).unwrap(), 0);
    assert!(w.pixels(num(1.0)).unwrap() != 0);
    w.reset().unwrap();
    assert_eq!(w.advance(num(2.0)).unwrap(), 2);
}

#[wasm_bindgen_test]
fn garbage_log_files_are_refused_by_line_and_sessions_stay_usable() {
    // Random-looking bytes, a picture, gzip magic with garbage behind it,
    // and the real log cut short.
    let mut noise = Vec::new();
    let mut x: u32 = 0x2545_f491;
    for _ in 0..4096 {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        noise.push(x as u8);
    }
    refused(laser_log(&noise), &["line"]);
    refused(laser_log(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR"), &["line 1"]);
    refused(
        laser_log(&[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 0xff, 0xff]),
        &["line"],
    );
    // A gzip cut short keeps the complete scans before the cut.
    let cut = laser_log(&INTEL_GZ[..20_000]).expect("a cut log keeps its scans");
    assert!(
        cut.scan_count() > 0 && cut.scan_count() < 910,
        "{}",
        cut.scan_count()
    );
    refused(laser_log(b"FLASER 3 1 2\n"), &["line 1", "FLASER"]);
    refused(
        laser_log(b"ODOM 0 0 0\nFLASER 2 1 nan 0 0 0 0 0 0\n"),
        &["line 2", "range 2"],
    );
    assert_eq!(laser_log(&[]).unwrap().scan_count(), 0);

    // A session over garbage: the read fails by line, every later call
    // fails cleanly too.
    let mut bad = log_session(noise.clone());
    refused(bad.read(num(10.0)), &["line"]);
    refused(bad.read(num(10.0)), &["line"]);
    refused(bad.render_view(num(0.0)), &["not been read"]);
    refused(bad.seek(num(3.0)), &["not been read"]);
    refused(
        bad.build_slice(num(f64::INFINITY), JsValue::UNDEFINED),
        &["not been read"],
    );
    refused(bad.geometry(num(0.0)), &["not been read"]);

    // A log without laser lines.
    let mut empty = log_session(b"ODOM 0 0 0\n");
    refused(
        empty.read(num(f64::INFINITY)),
        &["no FLASER or ROBOTLASER1 lines"],
    );

    // A good session and bad settings.
    let text = FLASER.repeat(6);
    let mut s = log_session(text.into_bytes());
    for bad in [f64::NAN, -1.0, 0.5] {
        refused(s.read(num(bad)), &["maxScans"]);
    }
    let p = s.read(num(f64::INFINITY)).unwrap();
    assert_eq!(get(&p, "finished").as_bool(), Some(true));
    let geometry = stringify(&s.geometry(num(0.0)).unwrap());
    refused(s.configure(JsValue::from_str("fine")), &["settings"]);
    refused(
        s.configure(json(r#"{"resolution": -1}"#)),
        &["resolution", "-1"],
    );
    refused(
        s.configure(json(r#"{"resolution": 1e-5}"#)),
        &["width x height"],
    );
    refused(s.configure(json(r#"{"rangeCap": 0}"#)), &["rangeCap"]);
    refused(s.configure(json(r#"{"clamp": 0}"#)), &["clamp"]);
    refused(s.configure(json(r#"{"bogus": 1}"#)), &["settings", "bogus"]);
    refused(
        s.configure(with(&json("{}"), "lOcc", JsValue::from_f64(f64::NAN))),
        &["lOcc"],
    );
    assert_eq!(
        stringify(&s.geometry(num(0.0)).unwrap()),
        geometry,
        "refused settings changed the map"
    );
    refused(
        s.build_slice(num(f64::NAN), JsValue::UNDEFINED),
        &["maxCells"],
    );
    refused(s.build_slice(num(f64::INFINITY), num(0.0)), &["withinMs"]);
    s.build_slice(num(f64::INFINITY), num(1e9)).unwrap();
    refused(s.seek(num(1e6)), &["scan"]);
    refused(s.seek(num(-1.0)), &["scan", "-1"]);
    refused(s.seek(num(2.5)), &["scan", "2.5"]);
    refused(s.robot_at(num(0.0), num(1e9)), &["scan"]);
    refused(s.robot_at(num(0.0), num(-1.0)), &["scan", "-1"]);
    refused(s.robot_at(num(0.0), num(f64::NAN)), &["scan", "NaN"]);
    assert!(s.cell_at(num(0.0), num(1e12), num(0.0)).unwrap().is_null());
    assert!(s.cell_at(num(0.0), num(-1.0), num(0.0)).unwrap().is_null());
    refused(s.cell_at(num(0.0), num(0.5), num(0.0)), &["col"]);
    refused(s.cell_at(num(0.0), num(0.0), num(f64::INFINITY)), &["row"]);
    assert!(s.render_view(num(0.0)).unwrap() != 0);
    let c = s.counts(num(0.0)).unwrap();
    assert!(get(&c, "occupied").as_f64().unwrap() > 0.0);
    s.export_map(num(0.0), "../../etc/passwd\n".into(), JsValue::UNDEFINED)
        .unwrap();
    s.export_map(num(0.0), JsValue::NULL, JsValue::UNDEFINED)
        .unwrap();
    s.export_map(num(0.0), JsValue::UNDEFINED, JsValue::UNDEFINED)
        .unwrap();
    s.export_map(num(0.0), "lab".into(), JsValue::UNDEFINED)
        .unwrap();
    refused(
        s.export_map(num(0.0), JsValue::from_f64(7.0), JsValue::UNDEFINED),
        &["name", "7"],
    );
    refused(
        s.export_map(num(0.0), Object::new().into(), JsValue::UNDEFINED),
        &["name"],
    );
    refused(
        s.export_map(num(1.0), JsValue::NULL, JsValue::UNDEFINED),
        &["pane", "1"],
    );
    // The log's name is a string or nothing; a hostile one is quoted in
    // the YAML's comments, never a line of its own.
    let pair = s
        .export_map(num(0.0), "lab".into(), "x.log\nimage: /etc/passwd".into())
        .unwrap();
    let yaml = get(&pair, "yaml").as_string().unwrap();
    assert!(
        !yaml.lines().any(|l| l.starts_with("image: /etc")),
        "{yaml}"
    );
    s.export_map(num(0.0), "lab".into(), JsValue::NULL).unwrap();
    refused(
        s.export_map(num(0.0), "lab".into(), JsValue::from_f64(7.0)),
        &["logFile", "7"],
    );
    let bytes = |b: &[u8]| JsValue::from(js_sys::Uint8Array::from(b));
    zip_map_pair("".into(), bytes(&[]), "".into()).unwrap();
    zip_map_pair("\u{0}\n..".into(), bytes(&[1, 2, 3]), "image: x\n".into()).unwrap();
    refused(
        zip_map_pair(JsValue::UNDEFINED, bytes(&[1]), "".into()),
        &["name", "undefined"],
    );
    refused(
        zip_map_pair("m".into(), json("[1, 2]"), "".into()),
        &["pgm", "[1,2]"],
    );
    refused(
        zip_map_pair("m".into(), bytes(&[1]), JsValue::from_f64(3.0)),
        &["yaml", "3"],
    );
}

#[wasm_bindgen_test]
fn the_inverse_workbench_refuses_bad_seeds_and_lattices_and_keeps_its_model() {
    for seed in [f64::NAN, f64::INFINITY, -1.0, 1.5, 1e300] {
        refused(InverseWorkbench::new(num(seed)), &["seed"]);
    }
    let mut w = InverseWorkbench::new(JsValue::UNDEFINED).unwrap();
    let lattice = || {
        json(r#"{"minRange": 0, "maxRange": 8, "ranges": 50, "maxBearing": 0.1, "bearings": 9}"#)
    };
    let before = stringify(&w.readout().unwrap());
    for seed in [f64::NAN, -3.0, 0.5, f64::INFINITY] {
        refused(w.retrain(num(seed)), &["seed"]);
    }
    assert_eq!(
        stringify(&w.readout().unwrap()),
        before,
        "a refused retrain changed the model"
    );
    refused(w.view(num(f64::NAN), lattice()), &["z", "NaN"]);
    refused(w.view(num(-2.0), lattice()), &["z", "-2"]);
    refused(w.view(num(3.0), JsValue::from_str("grid")), &["lattice"]);
    refused(
        w.view(num(3.0), with(&lattice(), "ranges", JsValue::from_f64(1e9))),
        &["ranges"],
    );
    refused(
        w.view(
            num(3.0),
            with(&lattice(), "ranges", JsValue::from_f64(-1.0)),
        ),
        &["lattice"],
    );
    refused(
        w.view(
            num(3.0),
            with(&lattice(), "ranges", JsValue::from_f64(100_000.0)),
        ),
        &["ranges"],
    );
    refused(
        w.view(
            num(3.0),
            with(&lattice(), "bearings", JsValue::from_f64(1.0)),
        ),
        &["bearings"],
    );
    refused(
        w.view(
            num(3.0),
            with(&lattice(), "maxRange", JsValue::from_f64(f64::NAN)),
        ),
        &["max_range"],
    );
    refused(
        w.view(
            num(3.0),
            with(&lattice(), "maxBearing", JsValue::from_f64(4.0)),
        ),
        &["max_bearing"],
    );
    refused(w.view(num(3.0), json("{}")), &["lattice"]);
    let v = w.view(num(3.0), lattice()).unwrap();
    assert!(get(&v, "scale").as_f64().unwrap().is_finite());
    // A reading too short to have free space in front: null, not NaN.
    let v = w.view(num(0.1), lattice()).unwrap();
    assert!(get(&v, "handFree").is_null());
}

/// Wrong-typed fields and arrays in place of settings objects: an array
/// would otherwise be read as a settings struct with every field absent
/// (so `[]` would silently mean "the chapter's scene"), and a wrong-typed
/// field is reported under its path (`scene.seed`), not only as a type
/// mismatch.
#[wasm_bindgen_test]
fn wrong_typed_fields_and_arrays_are_refused_naming_the_field() {
    refused(
        forward_density(num(1.0), num(2.0), json("[1, 2]")),
        &["params"],
    );
    refused(DoorwayTrap::new(json("[]")), &["scene"]);
    refused(MapWeaver::new(json("[1]")), &["settings"]);
    refused(DoorwayTrap::new(json(r#"{"seed": "seven"}"#)), &["seed"]);
    refused(
        SensorFusion::new(json(r#"{"resolution": "fine"}"#), JsValue::UNDEFINED),
        &["resolution"],
    );
    refused(
        forward_density(num(1.0), num(2.0), json(r#"{"z_max": "far"}"#)),
        &["z_max"],
    );
    let q = chapter_two_cell_query().unwrap();
    refused(
        joint_posterior(with(&q, "cells", JsValue::from_f64(3.0))),
        &["cells"],
    );
    refused(
        MapWeaver::new(with(&weaver_settings(), "seed", JsValue::from_str("x"))),
        &["seed"],
    );
    refused(
        MapWeaver::new(with(&weaver_settings(), "laps", JsValue::from_f64(-1.0))),
        &["laps"],
    );
    // The message reads "invalid WHAT.PATH: reason", once, without a
    // doubled "Error:" prefix.
    let text = refused(
        DoorwayTrap::new(json(r#"{"sonar": {"sub_rays": "many"}}"#)),
        &["invalid scene.sonar.sub_rays: "],
    );
    assert!(!text.contains("Error:"), "{text}");
    let text = refused(
        MapWeaver::new(with(
            &weaver_settings(),
            "panes",
            json(r#"[{}, {"clamp": "high"}]"#),
        )),
        &["settings.panes[1].clamp"],
    );
    assert!(!text.contains("Error:"), "{text}");
    let text = refused(
        DoorwayTrap::new(json("[]")),
        &["invalid scene: [] (expected an object of named settings)"],
    );
    assert!(!text.contains("Error:"), "{text}");
    refused(
        SensorFusion::new(JsValue::UNDEFINED, json("[0.7, 0.4]")),
        &["models", "[0.7,0.4]"],
    );
    refused(
        SensorFusion::new(json("[]"), JsValue::UNDEFINED),
        &["scene", "[]"],
    );
    refused(joint_posterior(json("[]")), &["joint query", "[]"]);
    refused(joint_posterior(JsValue::TRUE), &["joint query", "true"]);
    refused(
        forward_density(num(1.0), num(2.0), JsValue::from_f64(f64::NAN)),
        &["params", "NaN"],
    );
    let long: Array = (0..500).map(|_| JsValue::from_f64(1.0)).collect();
    let text = refused(DoorwayTrap::new(long.into()), &["scene", "..."]);
    assert!(text.len() < 200, "a long value is cut short: {text}");
    let mut session = log_session(FLASER.repeat(2).into_bytes());
    session.read(num(f64::INFINITY)).unwrap();
    refused(session.configure(json("[]")), &["settings"]);
    refused(session.configure(JsValue::NULL), &["settings", "null"]);
    refused(
        session.configure(json(r#"{"clamp": "tight"}"#)),
        &["settings.clamp"],
    );
    let mut w = InverseWorkbench::new(JsValue::UNDEFINED).unwrap();
    refused(
        w.view(num(3.0), json("[0, 8, 50, 0.1, 9]")),
        &["lattice", "[0,8"],
    );
    refused(
        w.view(num(3.0), json(r#"{"minRange": 0, "maxRange": "far", "ranges": 50, "maxBearing": 0.1, "bearings": 9}"#)),
        &["lattice.maxRange"],
    );
    // Enum-like values stay strings: a settings object may still name a
    // model inside it.
    let ok = MapWeaver::new(with(
        &weaver_settings(),
        "panes",
        json(r#"[{"model": "learned"}, {"pose": "dead-reckoning"}]"#),
    ));
    assert!(ok.is_ok());
    w.retrain(num(3.0)).unwrap();
}
