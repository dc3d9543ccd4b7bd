//! Bindings of `<occgrid-cell-filter>`: one cell's filter.

use super::{number_from_js, to_js};
use crate::mapping::cell_filter::{self, CellFilterParams, CellFilterPreset};
use wasm_bindgen::prelude::*;

/// Runs one cell's filter over `readings` (a `Uint8Array` or an array of
/// numbers, 1 = occupied, 0 = free) and returns `{ lOcc, lFree, l0, steps:
/// [{ step, occupied, l, p }], clamp, firstAtClamp, freeIsEvidenceForOccupied }`:
/// `firstAtClamp` the first step whose `l` sits at `±clamp` (null if none),
/// `freeIsEvidenceForOccupied` whether `p_free >= p_occ`, so that a "free"
/// reading raises the cell at least as much as an occupied one.
#[wasm_bindgen(js_name = runCellFilter)]
pub fn run_cell_filter_js(
    p_occ: JsValue,
    p_free: JsValue,
    prior: JsValue,
    clamp: JsValue,
    readings: JsValue,
    subtract_prior: bool,
) -> Result<JsValue, JsError> {
    let p_occ = number_from_js("p_occ", &p_occ)?;
    let p_free = number_from_js("p_free", &p_free)?;
    let prior = number_from_js("prior", &prior)?;
    let clamp = number_from_js("clamp", &clamp)?;
    // The length first: a 100-million-byte array is refused before it is
    // copied into wasm memory.
    let len = if let Some(array) = readings.dyn_ref::<js_sys::Array>() {
        Some(array.length() as usize)
    } else if let Some(bytes) = readings.dyn_ref::<js_sys::Uint8Array>() {
        Some(bytes.length() as usize)
    } else {
        readings
            .dyn_ref::<js_sys::ArrayBuffer>()
            .map(|b| b.byte_length() as usize)
    };
    if let Some(len) = len {
        cell_filter::check_readings(len)?;
    }
    let readings = if let Some(array) = readings.dyn_ref::<js_sys::Array>() {
        // Each element as JavaScript holds it: the glue's copy into bytes
        // would wrap 256 to 0 and -1 to 255.
        array
            .iter()
            .enumerate()
            .map(|(i, r)| match r.as_f64() {
                Some(v) if v == 0.0 || v == 1.0 => Ok(v as u8),
                _ => Err(JsError::new(&format!(
                    "invalid readings[{i}]: {} (expected 1 for occupied or 0 for free)",
                    super::describe(&r)
                ))),
            })
            .collect::<Result<Vec<u8>, JsError>>()?
    } else {
        super::bytes_from_js(
            "readings",
            &readings,
            "a Uint8Array or an array of 1 (occupied) and 0 (free)",
        )?
    };
    run_cell_filter(p_occ, p_free, prior, clamp, &readings, subtract_prior)
}

/// [`run_cell_filter_js`] for Rust callers, the readings already bytes.
pub fn run_cell_filter(
    p_occ: f64,
    p_free: f64,
    prior: f64,
    clamp: f64,
    readings: &[u8],
    subtract_prior: bool,
) -> Result<JsValue, JsError> {
    let params = CellFilterParams {
        p_occ,
        p_free,
        prior,
        clamp,
    };
    if let Some((i, &bad)) = readings.iter().enumerate().find(|(_, &r)| r > 1) {
        return Err(JsError::new(&format!(
            "invalid readings[{i}]: {bad} (expected 1 for occupied or 0 for free)"
        )));
    }
    let flags: Vec<bool> = readings.iter().map(|&r| r == 1).collect();
    let steps = cell_filter::run(&params, &flags, subtract_prior)?;
    let lo = cell_filter::log_odds_of(&params)?;
    #[derive(serde::Serialize)]
    #[serde(rename_all = "camelCase")]
    struct Table {
        l_occ: f64,
        l_free: f64,
        l0: f64,
        steps: Vec<cell_filter::CellStep>,
        clamp: f64,
        first_at_clamp: Option<usize>,
        free_is_evidence_for_occupied: bool,
    }
    let first_at_clamp = steps.iter().find(|s| s.l.abs() >= clamp).map(|s| s.step);
    to_js(&Table {
        l_occ: lo.l_occ,
        l_free: lo.l_free,
        l0: lo.l0,
        first_at_clamp,
        free_is_evidence_for_occupied: p_free >= p_occ,
        clamp,
        steps,
    })
}

/// The chapter's worked example: readings occupied, occupied, free with an
/// inverse model of 0.7 / 0.3 and a prior of 0.5.
#[wasm_bindgen(js_name = workedExample)]
pub fn worked_example() -> Result<JsValue, JsError> {
    let p = CellFilterPreset::WORKED_EXAMPLE;
    run_cell_filter(
        p.p_occ,
        p.p_free,
        p.prior,
        p.clamp,
        p.readings,
        p.subtract_prior,
    )
}
