#![cfg(target_arch = "wasm32")]
//! What a page can send that is not what it seems, through the JavaScript
//! surface (`wasm-pack test --node`): a revoked Proxy (every question put
//! to it throws), an own `"__proto__"` field, a Proxy or a look-alike of a
//! `Uint8Array`, a typed array whose `length` lies or throws, an array
//! whose items throw, and work past a widget's budgets. Each is refused
//! with an `Error` naming the parameter; nothing JavaScript throws unwinds
//! through the core, and every object stays usable.

use js_sys::{Array, Function, Object, Reflect, Uint8Array};
use occgrid::bindings::bench::LaserLog;
use occgrid::bindings::cell_filter::run_cell_filter;
use occgrid::bindings::doorway_trap::DoorwayTrap;
use occgrid::bindings::map_files::zip_map_pair;
use occgrid::bindings::map_weaver::MapWeaver;
use occgrid::bindings::real_log::RealLogSession;
use occgrid::bindings::sensor_fusion::SensorFusion;
use occgrid::bindings::two_cell_table::{chapter_two_cell_query, joint_answer, joint_posterior};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

mod wasm_support;
use wasm_support::*;

/// A fresh run small enough to build in milliseconds.
fn small_weaver() -> MapWeaver {
    MapWeaver::new(json(
        r#"{"laps": 1, "training": {"triplets": 400, "epochs": 1}}"#,
    ))
    .unwrap()
}

/// `Array.isArray` threw through the core on a revoked Proxy while the
/// session was borrowed (the session said "recursive use of an object" to
/// every later call), and each such exception kept the stack its frames had
/// taken: call 1,559 wrote past it ("memory access out of bounds").
#[wasm_bindgen_test]
fn a_revoked_proxy_is_an_invalid_settings_object_and_leaves_everything_usable() {
    let mut s = log_session(FLASER.repeat(4).into_bytes());
    s.read(num(2.0)).unwrap();
    refused(s.configure(revoked()), &["invalid settings", "revoked"]);
    refused(
        s.configure(object_with("resolution", &revoked())),
        &["invalid settings.resolution", "revoked"],
    );
    refused(
        s.configure(object_with("clamp", &Array::of1(&revoked()).into())),
        &["invalid settings.clamp[0]", "revoked"],
    );
    assert_eq!(
        get(&s.read(num(10.0)).unwrap(), "scans").as_f64(),
        Some(4.0)
    );
    assert!(s.configure(json(r#"{"clamp": 3}"#)).is_ok());

    let mut w = small_weaver();
    refused(
        w.stage_pane(num(0.0), revoked()),
        &["invalid panes[0]", "revoked"],
    );
    refused(
        w.stage_pane(num(1.0), object_with("clamp", &revoked())),
        &["invalid panes[1].clamp", "revoked"],
    );
    refused(MapWeaver::new(revoked()), &["invalid settings", "revoked"]);
    refused(
        DoorwayTrap::new(object_with("sonar", &revoked())),
        &["invalid scene.sonar", "revoked"],
    );
    refused(
        SensorFusion::new(JsValue::UNDEFINED, revoked()),
        &["invalid models", "revoked"],
    );
    assert_eq!(w.advance(num(2.0)).unwrap(), 2);

    for _ in 0..3000 {
        refused(joint_posterior(revoked()), &["invalid joint query"]);
    }
    let answer = joint_answer(chapter_two_cell_query().unwrap()).unwrap();
    assert_eq!(Array::from(&get(&answer, "joint")).length(), 4);
    assert_eq!(small_weaver().advance(num(1.0)).unwrap(), 1);
}

/// `JSON.parse` makes `"__proto__"` an own field (a page's `scene`
/// attribute goes through it); the copy assigned it and so made it the
/// copy's prototype, and the field vanished unread.
#[wasm_bindgen_test]
fn an_own_proto_field_is_refused_by_name_at_any_depth() {
    refused(
        MapWeaver::new(json(
            r#"{"laps": 1, "scene": {"__proto__": {"scan_rate": 1}}}"#,
        )),
        &["invalid settings.scene", "unknown field \"__proto__\""],
    );
    refused(
        DoorwayTrap::new(json(r#"{"__proto__": {"seed": 3}}"#)),
        &["invalid scene", "\"__proto__\""],
    );
    refused(
        joint_posterior(json(r#"{"__proto__": {"prior": 0.5}}"#)),
        &["invalid joint query", "\"__proto__\""],
    );
    let mut w = small_weaver();
    let clamp = |w: &MapWeaver| {
        get(
            &Array::from(&get(&w.readout().unwrap(), "panes")).get(0),
            "clamp",
        )
    };
    let before = clamp(&w);
    refused(
        w.stage_pane(num(0.0), json(r#"{"__proto__": {"clamp": 2}}"#)),
        &["invalid panes[0]", "\"__proto__\""],
    );
    assert_eq!(clamp(&w), before);
}

/// A Proxy of a `Uint8Array` passed `instanceof`; its `length`, or a real
/// one's own `length` property, was then trusted for the copy: a throwing
/// getter threw through the core, a shrinking one made the copy's
/// assertion panic. Bytes are now told by their internal slots.
#[wasm_bindgen_test]
fn bytes_are_read_by_their_internal_slots_never_by_their_own_code() {
    let text = FLASER.repeat(3);
    let throwing = Uint8Array::from(text.as_bytes());
    let getter = Function::new_no_args("throw new Error('no length')");
    Reflect::define_property(
        &throwing,
        &JsValue::from_str("length"),
        &object_with("get", &getter).unchecked_into(),
    )
    .unwrap();
    let mut s = RealLogSession::new(throwing.into(), JsValue::UNDEFINED).unwrap();
    assert_eq!(
        get(&s.read(num(100.0)).unwrap(), "scans").as_f64(),
        Some(3.0)
    );

    let proxy: JsValue =
        js_sys::Proxy::new(&Uint8Array::from(text.as_bytes()), &Object::new()).into();
    let look_alike = Object::new();
    Reflect::set_prototype_of(
        &look_alike,
        &Reflect::get_prototype_of(&Uint8Array::new_with_length(0)).unwrap(),
    )
    .unwrap();
    for fake in [proxy, look_alike.into(), revoked()] {
        refused(
            RealLogSession::new(fake.clone(), JsValue::UNDEFINED),
            &["invalid bytes", "Uint8Array"],
        );
        refused(
            LaserLog::from_bytes(fake.clone()),
            &["invalid bytes", "Uint8Array"],
        );
        refused(
            zip_map_pair("m".into(), fake.clone(), "image: m.pgm\n".into()),
            &["invalid pgm"],
        );
        refused(
            run_cell_filter(num(0.7), num(0.3), num(0.5), num(12.0), fake, JsValue::TRUE),
            &["invalid readings"],
        );
    }
    // An array of readings whose item throws is refused at that item.
    let trap = object_with(
        "get",
        &Function::new_with_args(
            "t, k",
            "if (k === '1') throw new Error('trap'); return t[k];",
        ),
    );
    let readings: JsValue = js_sys::Proxy::new(&json("[1, 0, 1]"), &trap.unchecked_into()).into();
    refused(
        run_cell_filter(
            num(0.7),
            num(0.3),
            num(0.5),
            num(12.0),
            readings,
            JsValue::TRUE,
        ),
        &["invalid readings[1]", "trap"],
    );
    // True or false is a boolean, nothing the glue would have to convert.
    for bad in [
        num(1.0),
        JsValue::from_str("yes"),
        JsValue::UNDEFINED,
        Object::new().into(),
    ] {
        refused(
            run_cell_filter(num(0.7), num(0.3), num(0.5), num(12.0), json("[1]"), bad),
            &["invalid subtract_prior", "expected true or false"],
        );
    }
}

/// The readings have a budget, checked on the length JavaScript reports
/// before a byte is copied: a hundred million readings made the core panic
/// (its table of rows would have taken 3.2 GB).
#[wasm_bindgen_test]
fn the_cell_filter_refuses_more_readings_than_its_budget_before_copying_them() {
    let run = |readings: JsValue| {
        run_cell_filter(
            num(0.7),
            num(0.3),
            num(0.5),
            num(12.0),
            readings,
            JsValue::TRUE,
        )
    };
    let huge = js_sys::Uint8Array::new_with_length(100_000_000);
    refused(
        run(huge.clone().into()),
        &["invalid readings", "100000000 readings", "at most 10000"],
    );
    refused(
        run(huge.buffer().into()),
        &["readings", "100000000 readings"],
    );
    let many = Array::new_with_length(10_001);
    many.fill(&num(1.0), 0, 10_001);
    refused(run(many.into()), &["invalid readings", "10001 readings"]);
    refused(
        cell_filter(0.7, 0.3, 0.5, 12.0, &vec![0; 10_001], true),
        &["readings", "10001 readings"],
    );
    // At the budget it runs, and the module is alive after the refusals.
    let t = run(js_sys::Uint8Array::new_with_length(10_000).into()).unwrap();
    assert_eq!(Array::from(&get(&t, "steps")).length(), 10_000);
}

/// Bytes and readings come as typed arrays (or, for readings, arrays of
/// numbers): a string, a number or `undefined` is refused by name, where the
/// glue's own copy read a string's characters as bytes and a number as none.
#[wasm_bindgen_test]
fn byte_parameters_refuse_what_is_not_bytes_by_name() {
    let run = |readings: JsValue| {
        run_cell_filter(
            num(0.7),
            num(0.3),
            num(0.5),
            num(12.0),
            readings,
            JsValue::TRUE,
        )
    };
    let t = run(json("[1, 1, 0]")).unwrap();
    assert_eq!(Array::from(&get(&t, "steps")).length(), 3);
    let t = run(js_sys::Uint8Array::from(&[1u8, 0][..]).into()).unwrap();
    assert_eq!(Array::from(&get(&t, "steps")).length(), 2);
    refused(run(json("[1, 256]")), &["readings[1]", "256"]);
    refused(run(json("[1, -1]")), &["readings[1]", "-1"]);
    refused(run(json(r#"[1, "1"]"#)), &["readings[1]", "\"1\""]);
    refused(run(json("[0.5]")), &["readings[0]", "0.5"]);
    for bad in [
        JsValue::from_str("101"),
        JsValue::from_f64(5.0),
        JsValue::UNDEFINED,
        JsValue::NULL,
        Object::new().into(),
    ] {
        refused(run(bad), &["invalid readings", "Uint8Array"]);
    }

    let text = FLASER.as_bytes();
    let buffer = js_sys::Uint8Array::from(text).buffer();
    assert_eq!(
        LaserLog::from_bytes(buffer.clone().into())
            .unwrap()
            .scan_count(),
        1
    );
    assert_eq!(
        LaserLog::from_bytes(js_sys::Uint8Array::from(text).into())
            .unwrap()
            .scan_count(),
        1
    );
    for bad in [
        JsValue::from_str(FLASER),
        JsValue::from_f64(42.0),
        JsValue::UNDEFINED,
        json("[70, 76]"),
    ] {
        refused(
            LaserLog::from_bytes(bad.clone()),
            &["invalid bytes", "Uint8Array"],
        );
        refused(
            RealLogSession::new(bad, JsValue::UNDEFINED),
            &["invalid bytes", "Uint8Array"],
        );
    }
    let mut s = RealLogSession::new(buffer.into(), JsValue::UNDEFINED).unwrap();
    assert_eq!(
        get(&s.read(num(f64::INFINITY)).unwrap(), "finished").as_bool(),
        Some(true)
    );
}

/// Inputs each within its own bound whose product would hold a widget for
/// minutes are refused before any work, naming the factors and the limit.
#[wasm_bindgen_test]
fn work_past_the_widget_limits_is_refused_naming_the_fields_and_the_limit() {
    refused(
        DoorwayTrap::new(json(r#"{"resolution": 0.0015}"#)),
        &["width x height", "3334 x 2667", "250000"],
    );
    refused(
        DoorwayTrap::new(json(r#"{"sonar": {"sub_rays": 1024, "z_max": 1000}}"#)),
        &["poses x bearings_deg x sonar.sub_rays", "5e7"],
    );
    assert!(DoorwayTrap::new(json(r#"{"resolution": 0.01}"#)).is_ok());
    refused(
        SensorFusion::new(
            json(
                r#"{"step": 0.00041, "sonar": {"count": 256, "sub_rays": 256}, "lidar": {"beams": 2048}}"#,
            ),
            JsValue::UNDEFINED,
        ),
        &["steps x sonar.count x sonar.sub_rays", "2000000"],
    );
    refused(
        SensorFusion::new(json(r#"{"resolution": 0.01}"#), JsValue::UNDEFINED),
        &["width x height", "250000"],
    );
    // 13 laps of one thin sonar: 1,053 steps, within every bound until the
    // LiDAR asks for 2,048 beams on each.
    let mut f = SensorFusion::new(
        json(r#"{"laps": 13, "sonar": {"count": 1, "sub_rays": 1}}"#),
        JsValue::UNDEFINED,
    )
    .unwrap();
    let before = stringify(&f.readout().unwrap());
    refused(
        f.set_lidar_beams(num(2048.0)),
        &["steps x lidar.beams", "2000000"],
    );
    assert_eq!(stringify(&f.readout().unwrap()), before);
    assert!(f.step(), "still steps");
    refused(
        MapWeaver::new(json(
            r#"{"laps": 1, "training": {"triplets": 1000000, "epochs": 200}}"#,
        )),
        &["training.triplets x training.epochs", "5000000"],
    );
}
