#![cfg(target_arch = "wasm32")]
//! The bindings as wasm under Node (`wasm-pack test --node`): numbers cross
//! the boundary intact, and core errors arrive in JavaScript as `Error`
//! objects whose message names the field and the value.

use js_sys::{Error, Reflect};
use occgrid::bindings::cell_filter::{run_cell_filter, worked_example};
use occgrid::bindings::real_log::LaserLog;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

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
    let p: Vec<f64> = steps.iter().map(|s| get(&s, "p").as_f64().unwrap()).collect();
    for (got, want) in p.iter().zip([0.7, 0.8448, 0.7]) {
        assert!((got - want).abs() < 1e-4, "{got} vs {want}");
    }
}

#[wasm_bindgen_test]
fn bad_probabilities_arrive_as_errors_naming_field_and_value() {
    let msg = js_error_message(run_cell_filter(0.7, 0.3, 1.0, 12.0, &[1], true).unwrap_err());
    assert!(msg.contains("prior") && msg.contains('1'), "{msg}");
    let msg = js_error_message(run_cell_filter(f64::NAN, 0.3, 0.5, 12.0, &[1], true).unwrap_err());
    assert!(msg.contains("p_occ") && msg.contains("NaN"), "{msg}");
    let msg = js_error_message(run_cell_filter(0.7, 0.3, 0.5, 0.0, &[1], true).unwrap_err());
    assert!(msg.contains("clamp"), "{msg}");
    let msg = js_error_message(run_cell_filter(0.7, 0.3, 0.5, 12.0, &[1, 7], true).unwrap_err());
    assert!(msg.contains("readings[1]") && msg.contains('7'), "{msg}");
}

#[wasm_bindgen_test]
fn garbage_logs_arrive_as_line_numbered_errors() {
    let msg = js_error_message(LaserLog::from_bytes(b"PARAM x\nFLASER 3 1.0 oops\n").err().unwrap());
    assert!(msg.starts_with("line 2:"), "{msg}");
    let msg = js_error_message(LaserLog::from_bytes(&[0x1f, 0x8b, 0, 0, 0]).err().unwrap());
    assert!(msg.contains("line"), "{msg}");
    let ok = LaserLog::from_bytes(b"FLASER 2 1.0 2.0 0 0 0 0 0 0 1 h 1\n").unwrap();
    assert_eq!(ok.scan_count(), 1);
}
