#![cfg(target_arch = "wasm32")]
//! `SensorFusion.work(steps, budget)` through the JavaScript surface
//! (`wasm-pack test --node`): the report a page reads each animation frame,
//! and every bad argument refused with an `Error` naming it, the maps left
//! as they were.

use occgrid::bindings::sensor_fusion::SensorFusion;
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

mod wasm_support;
use wasm_support::*;

#[wasm_bindgen_test]
fn work_reports_its_steps_visits_and_the_end_of_the_lap() {
    let mut f = SensorFusion::new(JsValue::UNDEFINED, JsValue::UNDEFINED).unwrap();
    let r = f.work(num(3.0), num(1.0)).unwrap();
    assert_eq!(
        get(&r, "steps").as_f64(),
        Some(0.0),
        "a budget of 1 does one piece of a step"
    );
    assert!(get(&r, "cellVisits").as_f64().unwrap() > 1.0);
    assert_eq!(get(&r, "step").as_f64(), Some(0.0));
    assert_eq!(get(&r, "underWay").as_bool(), Some(true));
    assert_eq!(get(&r, "done").as_bool(), Some(false));
    // The step under way is the next call's first.
    let r = f.work(num(1.0), num(f64::INFINITY)).unwrap();
    assert_eq!(get(&r, "steps").as_f64(), Some(1.0));
    assert_eq!(get(&r, "step").as_f64(), Some(1.0));
    assert_eq!(get(&r, "underWay").as_bool(), Some(false));
    let r = f.work(num(f64::INFINITY), num(f64::INFINITY)).unwrap();
    assert_eq!(get(&r, "step").as_f64(), Some(81.0), "the rest of the lap");
    assert_eq!(get(&r, "done").as_bool(), Some(true));
}

#[wasm_bindgen_test]
fn bad_steps_or_budget_are_refused_by_name_and_change_nothing() {
    let mut f = SensorFusion::new(JsValue::UNDEFINED, JsValue::UNDEFINED).unwrap();
    assert!(f.step());
    let before = stringify(&f.readout().unwrap());
    refused(f.work(num(-1.0), num(1000.0)), &["steps", "-1"]);
    refused(f.work(num(1.5), num(1000.0)), &["steps", "1.5"]);
    refused(f.work(JsValue::from_str("4"), num(1000.0)), &["steps"]);
    refused(f.work(num(4.0), num(f64::NAN)), &["budget", "NaN"]);
    refused(f.work(num(4.0), JsValue::UNDEFINED), &["budget"]);
    assert_eq!(stringify(&f.readout().unwrap()), before);
}
