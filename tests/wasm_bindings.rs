#![cfg(target_arch = "wasm32")]
//! The bindings as wasm under Node (`wasm-pack test --node`): numbers cross
//! the boundary intact, and core errors arrive in JavaScript as `Error`
//! objects whose message names the field and the value.

use js_sys::{Error, Reflect};
use occgrid::bindings::cell_filter::worked_example;
use occgrid::bindings::doorway_trap::DoorwayTrap;
use occgrid::bindings::two_cell_table::{chapter_two_cell_query, joint_answer};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

mod wasm_support;
use wasm_support::{cell_filter, laser_log, log_session};

fn get(v: &JsValue, key: &str) -> JsValue {
    Reflect::get(v, &JsValue::from_str(key)).unwrap()
}

/// The JavaScript `Error` a failed binding call throws, and its message.
fn js_error_message(e: wasm_bindgen::JsError) -> String {
    let value: JsValue = e.into();
    let error = value.dyn_into::<Error>().expect("a JavaScript Error");
    String::from(error.message())
}

#[wasm_bindgen_test]
fn worked_example_crosses_the_boundary() {
    let t = worked_example().unwrap();
    let l_occ = get(&t, "lOcc").as_f64().unwrap();
    assert!((l_occ - 0.8473).abs() < 1e-4);
    let steps = js_sys::Array::from(&get(&t, "steps"));
    assert_eq!(steps.length(), 3);
    let p: Vec<f64> = steps
        .iter()
        .map(|s| get(&s, "p").as_f64().unwrap())
        .collect();
    for (got, want) in p.iter().zip([0.7, 0.8448, 0.7]) {
        assert!((got - want).abs() < 1e-4, "{got} vs {want}");
    }
}

#[wasm_bindgen_test]
fn bad_probabilities_arrive_as_errors_naming_field_and_value() {
    let msg = js_error_message(cell_filter(0.7, 0.3, 1.0, 12.0, &[1], true).unwrap_err());
    assert!(msg.contains("prior") && msg.contains('1'), "{msg}");
    let msg = js_error_message(cell_filter(f64::NAN, 0.3, 0.5, 12.0, &[1], true).unwrap_err());
    assert!(msg.contains("p_occ") && msg.contains("NaN"), "{msg}");
    let msg = js_error_message(cell_filter(0.7, 0.3, 0.5, 0.0, &[1], true).unwrap_err());
    assert!(msg.contains("clamp"), "{msg}");
    let msg = js_error_message(cell_filter(0.7, 0.3, 0.5, 12.0, &[1, 7], true).unwrap_err());
    assert!(msg.contains("readings[1]") && msg.contains('7'), "{msg}");
}

#[wasm_bindgen_test]
fn garbage_logs_arrive_as_line_numbered_errors() {
    let msg = js_error_message(laser_log(b"PARAM x\nFLASER 3 1.0 oops\n").err().unwrap());
    assert!(msg.starts_with("line 2:"), "{msg}");
    let msg = js_error_message(laser_log(&[0x1f, 0x8b, 0, 0, 0]).err().unwrap());
    assert!(msg.contains("line"), "{msg}");
    let ok = laser_log(b"FLASER 2 1.0 2.0 0 0 0 0 0 0 1 h 1\n").unwrap();
    assert_eq!(ok.scan_count(), 1);
}

#[wasm_bindgen_test]
fn chapter_two_cell_case_crosses_the_boundary() {
    let a = joint_answer(chapter_two_cell_query().unwrap()).unwrap();
    let joint = js_sys::Array::from(&get(&a, "joint"));
    for (k, w) in [0.0047, 0.3318, 0.3318, 0.3318].iter().enumerate() {
        assert!((joint.get(k as u32).as_f64().unwrap() - w).abs() < 1e-3);
    }
    let msg = js_error_message(joint_answer(JsValue::from_str("nope")).unwrap_err());
    assert!(msg.contains("joint query"), "{msg}");
    assert!(!msg.contains("Error:"), "no doubled prefix: {msg}");
}

#[wasm_bindgen_test]
fn doorway_climb_reaches_a_local_maximum() {
    // The binding runs the session's climb: as many flips as the native
    // session makes on the chapter's scene, then none.
    let mut native = occgrid::apps::doorway_trap::DoorwayTrapSession::new(
        occgrid::scenes::doorway::DoorwayScene::standard(),
    )
    .unwrap();
    let flips = native.map_run(10_000);
    assert!(flips > 0 && flips < 10_000, "{flips}");
    assert!(native.map_step().is_none());
    let mut t = DoorwayTrap::new(JsValue::UNDEFINED).unwrap();
    assert_eq!(
        t.map_run(JsValue::from_f64(10_000.0)).unwrap() as usize,
        flips
    );
    assert!(t.map_step().unwrap().is_null());
}

#[wasm_bindgen_test]
fn a_log_session_reads_maps_exports_and_reports_errors_by_line() {
    let text = b"# log\nFLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 1 h 1\nFLASER 3 1.0 2.0 3.0 0.1 0 0 0 0 0 2 h 2\n";
    let mut s = log_session(text);
    let p = s.read(JsValue::from_f64(100.0)).unwrap();
    assert_eq!(get(&p, "finished").as_bool(), Some(true));
    assert_eq!(get(&p, "scans").as_f64(), Some(2.0));
    let b = s
        .build_slice(JsValue::from_f64(f64::INFINITY), JsValue::UNDEFINED)
        .unwrap();
    assert_eq!(get(&b, "scansDone").as_f64(), Some(2.0));
    let pair = s
        .export_map(JsValue::from_f64(0.0), "lab".into(), JsValue::UNDEFINED)
        .unwrap();
    assert!(get(&pair, "yaml")
        .as_string()
        .unwrap()
        .starts_with("image: lab.pgm\nmode: trinary\n"));
    let msg = js_error_message(
        s.configure(js_sys::JSON::parse(r#"{"resolution": -1}"#).unwrap())
            .unwrap_err(),
    );
    assert!(msg.contains("resolution") && msg.contains("-1"), "{msg}");
    let msg = js_error_message(
        s.configure(js_sys::JSON::parse(r#"{"resoluton": 0.1}"#).unwrap())
            .unwrap_err(),
    );
    assert!(msg.contains("resoluton"), "{msg}");
    let mut broken = log_session(b"ODOM 0 0 0\nFLASER 2 1.0 -2 0 0 0 0 0 0\n");
    let msg = js_error_message(broken.read(JsValue::from_f64(10.0)).unwrap_err());
    assert!(
        msg.starts_with("line 2:") && msg.contains("negative"),
        "{msg}"
    );
}

/// A misspelt field of a scene or settings object is an error naming it,
/// at any depth, for every widget (a scene that silently dropped it would
/// run with the default the reader tried to change).
#[wasm_bindgen_test]
fn misspelt_scene_and_settings_fields_are_errors_naming_them() {
    use occgrid::bindings::map_weaver::MapWeaver;
    use occgrid::bindings::sensor_fusion::SensorFusion;
    let parse = |json: &str| js_sys::JSON::parse(json).unwrap();
    let msg = js_error_message(
        DoorwayTrap::new(parse(r#"{"prior": 0.5, "sonr": {}}"#))
            .err()
            .unwrap(),
    );
    assert!(msg.contains("sonr"), "{msg}");
    let msg = js_error_message(
        SensorFusion::new(
            parse(r#"{"lidar": {"beams": 60, "beems": 2}}"#),
            JsValue::UNDEFINED,
        )
        .err()
        .unwrap(),
    );
    assert!(msg.contains("beems") && msg.contains("lidar"), "{msg}");
    // The table's sonar spoke of `beta` in radians; the one sonar type
    // speaks of `beta_deg`, and the old name is refused, not misread.
    let msg = js_error_message(
        SensorFusion::new(parse(r#"{"sonar": {"beta": 0.44}}"#), JsValue::UNDEFINED)
            .err()
            .unwrap(),
    );
    assert!(
        msg.contains("sonar") && msg.contains("\"beta\"") && msg.contains("beta_deg"),
        "{msg}"
    );
    let msg = js_error_message(
        MapWeaver::new(parse(r#"{"scene": {"scan_rat": 6}}"#))
            .err()
            .unwrap(),
    );
    assert!(msg.contains("scan_rat") && msg.contains("scene"), "{msg}");
    let mut session = log_session(Vec::new());
    let msg = js_error_message(
        session
            .configure(parse(r#"{"resolutoin": 0.1}"#))
            .unwrap_err(),
    );
    assert!(msg.contains("resolutoin"), "{msg}");
}
