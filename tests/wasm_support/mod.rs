//! What the wasm tests share: reading a refusal's message, building
//! JavaScript values (numbers, JSON, objects with a field set, a revoked
//! Proxy) and reading them back.
#![allow(dead_code)]

use js_sys::{Error, Function, Object, Reflect, JSON};
use occgrid::bindings::bench::LaserLog;
use occgrid::bindings::cell_filter::run_cell_filter;
use occgrid::bindings::real_log::RealLogSession;
use wasm_bindgen::{JsCast, JsError, JsValue};

pub const FLASER: &str = "FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

/// The message of the JavaScript `Error` a refused call throws.
pub fn message(e: JsError) -> String {
    let value: JsValue = e.into();
    let error = value
        .dyn_into::<Error>()
        .expect("a refused call throws a JavaScript Error");
    String::from(error.message())
}

/// Asserts that `result` is a refusal whose message names every word.
#[track_caller]
pub fn refused<T>(result: Result<T, JsError>, words: &[&str]) -> String {
    let Err(e) = result else {
        panic!("expected an error naming {words:?}, the call succeeded");
    };
    let text = message(e);
    for w in words {
        assert!(text.contains(w), "{text:?} should name {w:?}");
    }
    text
}

/// A JavaScript number: every number parameter of the bindings takes a
/// `JsValue` and reads it without coercion.
pub fn num(v: f64) -> JsValue {
    JsValue::from_f64(v)
}

/// A JavaScript `Uint8Array` of `b`: what a page sends as a file's bytes.
pub fn bytes(b: &[u8]) -> JsValue {
    js_sys::Uint8Array::from(b).into()
}

/// `runCellFilter` with numbers, a `Uint8Array` of readings and a bool.
pub fn cell_filter(
    p_occ: f64,
    p_free: f64,
    prior: f64,
    clamp: f64,
    readings: &[u8],
    subtract_prior: bool,
) -> Result<JsValue, JsError> {
    run_cell_filter(
        num(p_occ),
        num(p_free),
        num(prior),
        num(clamp),
        bytes(readings),
        JsValue::from_bool(subtract_prior),
    )
}

/// A log parsed through `LaserLog.fromBytes`.
pub fn laser_log(b: &[u8]) -> Result<LaserLog, JsError> {
    LaserLog::from_bytes(bytes(b))
}

/// A real-log session about to read `b`, made as a page makes one.
pub fn log_session(b: impl AsRef<[u8]>) -> RealLogSession {
    RealLogSession::new(bytes(b.as_ref()), JsValue::UNDEFINED).expect("bytes are accepted")
}

pub fn json(text: &str) -> JsValue {
    JSON::parse(text).expect("valid JSON in the test")
}

pub fn stringify(v: &JsValue) -> String {
    JSON::stringify(v).unwrap().as_string().unwrap()
}

pub fn get(v: &JsValue, key: &str) -> JsValue {
    Reflect::get(v, &JsValue::from_str(key)).unwrap()
}

/// `{ key: value }`.
pub fn object_with(key: &str, value: &JsValue) -> JsValue {
    let o = Object::new();
    Reflect::set(&o, &JsValue::from_str(key), value).unwrap();
    o.into()
}

/// `value` with `path` (dot-separated keys) set to `v`, creating objects
/// on the way: how a NaN or an infinity gets into a settings object (JSON
/// has neither).
pub fn with(value: &JsValue, path: &str, v: JsValue) -> JsValue {
    let keys: Vec<&str> = path.split('.').collect();
    let mut node = value.clone();
    for (k, key) in keys.iter().enumerate() {
        let key = JsValue::from_str(key);
        if k + 1 == keys.len() {
            Reflect::set(&node, &key, &v).unwrap();
        } else {
            let mut next = Reflect::get(&node, &key).unwrap();
            if !next.is_object() {
                next = Object::new().into();
                Reflect::set(&node, &key, &next).unwrap();
            }
            node = next;
        }
    }
    value.clone()
}

/// A Proxy that has been revoked: `Array.isArray`, `typeof` aside, and
/// every other question put to it throw a `TypeError`.
pub fn revoked() -> JsValue {
    let pair = js_sys::Proxy::revocable(&Object::new(), &Object::new());
    get(&pair, "revoke")
        .unchecked_into::<Function>()
        .call0(&JsValue::UNDEFINED)
        .unwrap();
    get(&pair, "proxy")
}
